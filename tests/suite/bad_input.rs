//! Bad input to the real binary (issue 6): each case exits non-zero with one clear line on
//! stderr, never a panic, and leaves no file behind. (GPU failures: `gpu_faults.rs`.)

use std::path::Path;
use std::process::Command;

use crate::cli::temp_dir;

/// Runs the binary with `envs` set: (success, stderr). As root (CI), with `as_nobody`, it
/// runs as uid/gid 65534 through util-linux `setpriv`, so that folder permissions apply;
/// from a copy in the temp folder, which that user can reach wherever the checkout is.
pub fn run(args: &[&str], envs: &[(&str, &str)], as_nobody: bool) -> (bool, String) {
    let bin = env!("CARGO_BIN_EXE_shadeballs");
    let mut cmd = if as_nobody && is_root() {
        use std::os::unix::fs::PermissionsExt;
        let dir = temp_dir("nobody-bin");
        let copy = dir.join("shadeballs");
        std::fs::copy(bin, &copy).expect("copy the binary");
        for p in [&dir, &copy] {
            std::fs::set_permissions(p, std::fs::Permissions::from_mode(0o755)).unwrap();
        }
        let mut c = Command::new("setpriv");
        c.args(["--reuid=65534", "--regid=65534", "--clear-groups"]);
        c.arg(copy);
        c
    } else {
        Command::new(bin)
    };
    let out = cmd
        .args(args)
        .envs(envs.iter().copied())
        .output()
        .expect("run shadeballs");
    if as_nobody && is_root() {
        std::fs::remove_dir_all(temp_dir("nobody-bin")).unwrap();
    }
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn is_root() -> bool {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata("/proc/self")
        .map(|m| m.uid() == 0)
        .unwrap_or(false)
}

/// Asserts a failure with one line on stderr that starts with `error:` and contains
/// `expect`.
pub fn fails_with_one_line(args: &[&str], envs: &[(&str, &str)], expect: &str) -> String {
    let (ok, stderr) = run(args, envs, false);
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    println!("{args:?} -> {stderr}");
    assert!(!ok, "{args:?} succeeded");
    assert!(
        lines.len() == 1 && lines[0].starts_with("error: ") && lines[0].contains(expect),
        "{args:?}: expected one line with {expect:?}, got {stderr:?}"
    );
    stderr
}

#[test]
fn bad_flags_and_sizes_are_one_line_errors() {
    let dir = temp_dir("bad-flags");
    let png = dir.join("x.png");
    let png = png.to_str().unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["render", "--bogus"], "unexpected argument '--bogus'"),
        (
            &["render", "--widht", "5"],
            "similar argument exists: '--width'",
        ),
        (&["rendr"], "unrecognized subcommand"),
        (&["render", "--out", png, "--width", "0"], "at least 1"),
        (&["render", "--out", png, "--width", "-5"], "at least 1"),
        (&["render", "--out", png, "--width=-5"], "at least 1"),
        (
            &["render", "--out", png, "--height", "NaN"],
            "not a whole number",
        ),
        (
            &["render", "--out", png, "--height", "1e3"],
            "not a whole number",
        ),
        (
            &["render", "--out", png, "--width", "99999999999"],
            "beyond any device",
        ),
        (
            &[
                "render",
                "--out",
                png,
                "--width",
                "16385",
                "--backend",
                "vulkan",
            ],
            "image size",
        ),
        (
            &[
                "render",
                "--out",
                png,
                "--width",
                "16385",
                "--backend",
                "cpu",
            ],
            "image size",
        ),
        (
            &["render", "--out", png, "--width", "5", "--width", "6"],
            "multiple times",
        ),
        (
            &["bake", "--out", "t.csv", "--size", "-1"],
            "not a whole number",
        ),
        (
            &["bake", "--out", "t.csv", "--size", "8193"],
            "outside 2..=8192",
        ),
        (&["bake", "--out", "t.csv", "--samples", "-3"], "--samples"),
        (&["bake"], "--out"),
        (&["probe", "--out", "p.csv", "--grid", "1025"], "probe grid"),
        (&["probe", "--out", "p.csv", "--grid", "-1"], "--grid"),
    ];
    for (args, expect) in cases {
        fails_with_one_line(args, &[], expect);
    }
    // A frame whose read-back buffer the device cannot hold fails at once, before any
    // allocation (it used to panic in wgpu's out-of-memory handler).
    let exr = dir.join("big.exr");
    let start = std::time::Instant::now();
    fails_with_one_line(
        &[
            "render",
            "--backend",
            "vulkan",
            "--width",
            "16384",
            "--height",
            "16384",
            "--out",
            exr.to_str().unwrap(),
        ],
        &[],
        "read-back buffer",
    );
    assert!(start.elapsed().as_secs() < 20, "took {:?}", start.elapsed());
    assert!(
        std::fs::read_dir(&dir).unwrap().next().is_none(),
        "files left behind"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_scene_files_are_one_line_errors_with_line_and_column() {
    let dir = temp_dir("bad-scenes");
    let ball = "[[ball]]\ngrid = [0, 0]\nradius = 35\nroughness = 0.5\nmaterial = { kind = \"metal\", f0 = [1, 1, 1] }\n";
    let cases = [
        ("empty", String::new(), "no balls"),
        ("truncated", ball[..40].to_string(), "line 4"),
        (
            "not TOML",
            "this is not toml\n".to_string(),
            "line 1, column",
        ),
        (
            "wrong type",
            ball.replace("radius = 35", "radius = \"big\""),
            "line 3, column 10: invalid type",
        ),
        (
            "unknown key",
            format!("{ball}colour = 3\n"),
            "unknown field `colour`",
        ),
        (
            "roughness above 1",
            ball.replace("0.5", "1.5"),
            "line 4, column 13: roughness 1.5 is outside [0, 1]",
        ),
        (
            "negative roughness",
            ball.replace("0.5", "-0.0001"),
            "outside [0, 1]",
        ),
        (
            "NaN roughness",
            ball.replace("0.5", "nan"),
            "outside [0, 1]",
        ),
        (
            "radiance beyond f32",
            format!("{ball}[environment]\nradiance = [1e300, 0, 0]\n"),
            "beyond 1e12",
        ),
        (
            "radius overflow",
            ball.replace("radius = 35", "radius = 1e39"),
            "at most 1e12",
        ),
    ];
    let png = dir.join("x.png");
    for (name, text, expect) in cases {
        let path = dir.join(format!("{}.toml", name.replace(' ', "-")));
        std::fs::write(&path, text).unwrap();
        let stderr = fails_with_one_line(
            &[
                "render",
                "--backend",
                "cpu",
                "--scene",
                path.to_str().unwrap(),
                "--out",
                png.to_str().unwrap(),
            ],
            &[],
            expect,
        );
        assert!(stderr.contains(path.to_str().unwrap()), "{name}: {stderr}");
    }
    assert!(!png.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

fn args(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}

/// Names of the entries of `dir`.
fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn unwritable_outputs_fail_cleanly_and_leave_the_old_file_whole() {
    use std::os::unix::fs::PermissionsExt;
    let dir = temp_dir("bad-out");
    let small = ["--backend", "cpu", "--width", "16", "--height", "9"];
    let with = |out: &Path| {
        let mut a = vec!["render", "--out", out.to_str().unwrap()];
        a.extend(small);
        a.into_iter().map(String::from).collect::<Vec<_>>()
    };
    // A missing folder, and a folder where the file should be: refused before rendering.
    let missing = with(&dir.join("no/such/folder/x.png"));
    fails_with_one_line(&args(&missing), &[], "No such file or directory");
    std::fs::create_dir(dir.join("taken.png")).unwrap();
    let taken = with(&dir.join("taken.png"));
    fails_with_one_line(&args(&taken), &[], "not a regular file");
    // A read-only folder holding an older image: the write fails, the old file is whole,
    // and no temporary file is left. (As root this runs as `nobody`: root ignores modes.)
    let ro = dir.join("read-only");
    std::fs::create_dir(&ro).unwrap();
    std::fs::write(ro.join("x.png"), b"old image").unwrap();
    std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o755)).unwrap();
    std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o555)).unwrap();
    let (ok, stderr) = run(&args(&with(&ro.join("x.png"))), &[], true);
    println!("read-only folder -> {stderr}");
    assert!(
        !ok && stderr.contains("Permission denied") && stderr.trim().lines().count() == 1,
        "{stderr}"
    );
    assert_eq!(std::fs::read(ro.join("x.png")).unwrap(), b"old image");
    assert_eq!(entries(&ro), ["x.png"]);
    std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o755)).unwrap();
    // A read-only file system (sysfs, even for root).
    fails_with_one_line(
        &args(&with(Path::new("/sys/x.png"))),
        &[],
        "cannot write '/sys/x.png'",
    );
    assert_eq!(entries(&dir), ["read-only", "taken.png"]);
    std::fs::remove_dir_all(&dir).unwrap();
}
