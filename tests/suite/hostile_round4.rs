//! Issue 38, the fourth hostile round: each finding as the tester ran it (the real binary),
//! with what it must do now. Numbered as in the issue; docs/reliability.md ("Issue 38")
//! lists them.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use shadeballs::environment::{save, EnvMap};

use crate::cli::temp_dir;

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_shadeballs")
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs `shadeballs args` in `cwd` (the test's own folder where `None`): the output.
fn run_in(cwd: Option<&Path>, args: &[&str]) -> Output {
    let mut c = Command::new(bin());
    c.args(args);
    if let Some(dir) = cwd {
        c.current_dir(dir);
    }
    let out = c.output().unwrap();
    println!(
        "{args:?} -> {:?}\n{}",
        out.status.code(),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn run(args: &[&str]) -> Output {
    run_in(None, args)
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Asserts a failure (exit 1) with one line, `error: ...`, containing each of `says`: the
/// line.
fn one_line_failure(out: &Output, says: &[&str]) -> String {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(lines[0].starts_with("error: "), "{err}");
    for s in says {
        assert!(lines[0].contains(s), "expected {s:?} in {err}");
    }
    lines[0].to_string()
}

/// A `w x h` map of `value` everywhere but texel 0, which is `peak`, written to `path`.
fn flat_map(path: &Path, (w, h): (u32, u32), value: f32, peak: f32) {
    let mut texels = vec![[value; 3]; (w * h) as usize];
    texels[0] = [peak; 3];
    save(&EnvMap::new(w, h, texels).unwrap(), path).unwrap();
}

/// A scene file in `dir` named `name`: the homework's ball row under `map` (a path as the
/// file says it) at `intensity`, with a light where `light`.
fn map_scene(dir: &Path, name: &str, map: &str, intensity: &str, light: bool) -> PathBuf {
    let light = if light {
        "[[light]]\ndirection = [0, 0, 1]\nradiance = [1, 1, 1]\n"
    } else {
        ""
    };
    let text = format!(
        "[camera]\nposition = [0, 0, 300]\ntarget = [0, 0, 0]\nvfov_deg = 40\n\
         [environment]\nmap = \"{map}\"\nintensity = {intensity}\n{light}\
         [[ball]]\nposition = [0, 0, 0]\nradius = 60\nroughness = 0.3\n\
         material = {{ kind = \"metal\", f0 = [0.9, 0.6, 0.4] }}\n"
    );
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn exr_values(path: &Path) -> Vec<f32> {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .into_rgba32f()
        .into_raw()
}

/// Finding 1: map texels were not held to the scene's bound on radiance: a 128x64 map of
/// 1e30 at `intensity = 1e9` wrote an EXR of inf on Vulkan, the CPU and Monte Carlo (GL:
/// NaN), exit 0; a 3.4e38 texel at intensity 100 with a light too. Now a map whose brightest
/// texel times its intensity passes 1e12 is refused in one line naming the largest
/// intensity it takes, and one within the bound renders finite on every backend.
#[test]
fn maps_beyond_the_radiance_bound_are_refused_and_within_it_render_finite() {
    let dir = temp_dir("round4-bright-map");
    flat_map(&dir.join("huge.exr"), (128, 64), 1e30, 1e30);
    flat_map(&dir.join("max.exr"), (128, 64), 1.0, 3.4e38);
    flat_map(&dir.join("edge.exr"), (32, 16), 1e12, 1e12);
    let out = dir.join("x.exr");
    for (map, intensity, light) in [
        ("huge.exr", "1e9", false),
        ("max.exr", "100", true),
        ("max.exr", "1", false),
    ] {
        let scene = map_scene(&dir, "bright.toml", map, intensity, light);
        for backend in ["vulkan", "cpu", "montecarlo-cpu"] {
            let o = run(&[
                "render",
                "--scene",
                s(&scene),
                "--backend",
                backend,
                "--width",
                "32",
                "--height",
                "18",
                "--spp",
                "2",
                "--out",
                s(&out),
            ]);
            one_line_failure(&o, &["beyond the 1e12", "use an intensity of at most"]);
            assert!(!out.exists(), "{map} {backend}: wrote a file");
        }
    }
    // --environment (intensity 1) of a map beyond the bound.
    let o = run(&[
        "render",
        "--environment",
        s(&dir.join("huge.exr")),
        "--width",
        "32",
        "--height",
        "18",
        "--out",
        s(&out),
    ]);
    one_line_failure(&o, &["huge.exr", "beyond the 1e12"]);
    // At the bound: finite on every backend, the background the map's 1e12.
    let scene = map_scene(&dir, "edge.toml", "edge.exr", "1", true);
    for backend in ["vulkan", "gl", "cpu", "montecarlo-cpu", "montecarlo"] {
        let o = run(&[
            "render",
            "--scene",
            s(&scene),
            "--backend",
            backend,
            "--width",
            "32",
            "--height",
            "18",
            "--spp",
            "4",
            "--out",
            s(&out),
        ]);
        assert!(o.status.success(), "{backend}: {}", stderr(&o));
        let v = exr_values(&out);
        let bad = v.iter().filter(|c| !c.is_finite()).count();
        let max = v.iter().copied().fold(0.0f32, f32::max);
        println!("{backend}: {bad} non-finite channels, max {max:e}");
        assert_eq!(bad, 0, "{backend}");
        assert!(max >= 0.99e12, "{backend}: {max}");
        std::fs::remove_file(&out).unwrap();
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Bytes of every file in `files`, to compare after a refused command.
fn snapshot(files: &[&Path]) -> Vec<Vec<u8>> {
    files.iter().map(|f| std::fs::read(f).unwrap()).collect()
}

/// Finding 2: outputs overwrote the program's own inputs. Each is now refused in one line
/// before any work, and every input is left byte for byte.
#[test]
fn outputs_over_inputs_are_refused_and_the_inputs_stay_whole() {
    let dir = temp_dir("round4-overwrite");
    let map = dir.join("map.exr");
    flat_map(&map, (16, 8), 0.5, 0.5);
    let scene = map_scene(&dir, "scene.toml", "map.exr", "1", true);
    // A scene file whose name says .png.
    let png_scene = dir.join("scene.png");
    std::fs::copy(&scene, &png_scene).unwrap();
    // The truth's sidecar of x.exr is x.stderr.exr: here a map.
    let sidecar_map = dir.join("x.stderr.exr");
    std::fs::copy(&map, &sidecar_map).unwrap();
    // A link to the map, and a hard link of it.
    let link = dir.join("link.exr");
    std::os::unix::fs::symlink("map.exr", &link).unwrap();
    let hard = dir.join("hard.exr");
    std::fs::hard_link(&map, &hard).unwrap();
    let inputs = [
        map.as_path(),
        scene.as_path(),
        png_scene.as_path(),
        sidecar_map.as_path(),
    ];
    let before = snapshot(&inputs);
    let small = ["--width", "16", "--height", "9"];
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["render", "--environment", "map.exr", "--out", "map.exr"],
            "--out",
        ),
        (
            vec!["render", "--scene", "scene.toml", "--out", "map.exr"],
            "environment map",
        ),
        (
            vec!["render", "--scene", "scene.png", "--out", "scene.png"],
            "--scene",
        ),
        (
            vec!["render", "--environment", "map.exr", "--out", "link.exr"],
            "link.exr",
        ),
        (
            vec!["render", "--environment", "map.exr", "--out", "hard.exr"],
            "hard.exr",
        ),
        (
            vec![
                "render",
                "--backend",
                "truth",
                "--spp",
                "2",
                "--environment",
                "x.stderr.exr",
                "--out",
                "x.exr",
            ],
            "sidecar",
        ),
        (
            vec![
                "view",
                "--environment",
                "map.exr",
                "--frames",
                "1",
                "--screenshot",
                "map.exr",
            ],
            "--screenshot",
        ),
        (
            vec![
                "view",
                "--scene",
                "scene.toml",
                "--frames",
                "1",
                "--save-scene",
                "scene.toml",
            ],
            "--save-scene",
        ),
        (
            vec![
                "view",
                "--scene",
                "scene.toml",
                "--frames",
                "1",
                "--screenshot",
                "map.exr",
            ],
            "environment map",
        ),
    ];
    for (args, names) in cases {
        let mut args = args;
        if args[0] == "render" {
            args.extend(small);
        }
        let started = Instant::now();
        let o = run_in(Some(&dir), &args);
        one_line_failure(&o, &[names, "choose another output path"]);
        // Before any work: no device opened, nothing rendered.
        assert!(started.elapsed() < Duration::from_secs(5), "{args:?}");
        assert_eq!(snapshot(&inputs), before, "{args:?} changed an input");
        assert!(!dir.join("x.exr").exists());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Finding 3: `view --save-scene` failed whenever the map's path was relative ("the scene
/// file written would load as another scene"): `--environment sky.hdr` in the map's folder,
/// and a relative `map =` in a relative `--scene`. Under Xvfb (tests/suite/viewer.rs).
#[test]
fn the_viewer_saves_scenes_with_relative_map_paths() {
    let x = crate::viewer::Xvfb::start();
    let dir = temp_dir("round4-save-relative");
    flat_map(&dir.join("sky.exr"), (16, 8), 0.5, 2.0);
    map_scene(&dir, "rel.toml", "sky.exr", "2", true);
    for (i, args) in [
        vec!["--environment", "sky.exr"],
        vec!["--scene", "rel.toml"],
    ]
    .into_iter()
    .enumerate()
    {
        let saved = format!("saved{i}.toml");
        let out = x
            .command(bin())
            .current_dir(&dir)
            .arg("view")
            .args(&args)
            .args([
                "--width",
                "480",
                "--height",
                "270",
                "--frames",
                "1",
                "--save-scene",
            ])
            .arg(&saved)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .output()
            .unwrap();
        let err = stderr(&out);
        println!("{args:?}: {err}");
        assert!(out.status.success(), "{args:?}: {err}");
        let text = std::fs::read_to_string(dir.join(&saved)).unwrap();
        // The map by its absolute path, and the file loads (from another folder too).
        let absolute = std::fs::canonicalize(dir.join("sky.exr")).unwrap();
        assert!(
            text.contains(&format!("map = \"{}\"", absolute.display())),
            "{text}"
        );
        let back = shadeballs::scene::load(&dir.join(&saved)).unwrap();
        assert!(back.environment_map.is_some());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A scene far from the origin: the camera `distance` from one ball, both offset by
/// `offset` along x, at `vfov` degrees, a light from the camera.
fn far_scene(dir: &Path, name: &str, offset: f64, distance: f64, vfov: f64) -> PathBuf {
    let text = format!(
        "[camera]\nposition = [{offset:e}, 0, {distance:e}]\ntarget = [{offset:e}, 0, 0]\n\
         vfov_deg = {vfov:e}\n\
         [[light]]\ndirection = [0.3, 0.5, 1]\nradiance = [3, 3, 3]\n\
         [environment]\nradiance = [0.1, 0.1, 0.1]\n\
         [[ball]]\nposition = [{offset:e}, 0, 0]\nradius = 40\nroughness = 0.3\n\
         material = {{ kind = \"metal\", f0 = [0.9, 0.6, 0.4] }}\n"
    );
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// Pixels of two same-sized PNGs more than 1/255 apart in any channel.
fn pixels_apart(a: &Path, b: &Path) -> usize {
    let a = image::open(a).unwrap().to_rgba8();
    let b = image::open(b).unwrap().to_rgba8();
    assert_eq!(a.dimensions(), b.dimensions());
    a.pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0).any(|(&x, y)| x.abs_diff(y) > 1))
        .count()
}

/// Finding 4: far from the origin the GPU's f32 coordinates banded (a ball 120 units from
/// the camera with the scene at x = 1e8: 3,038 pixels more than 1/255 off the CPU; nothing
/// drawn at 1e12). The GPU now works relative to the camera (centres less the eye in f64):
/// it agrees with the CPU within 1/255; a field of view whose pixels f32 rays cannot
/// resolve (6.875e-6 degrees from 1e9 away) is refused on the GPU in one line, and the CPU
/// draws it.
#[test]
fn the_gpu_agrees_with_the_cpu_far_from_the_origin() {
    let dir = temp_dir("round4-far");
    for offset in [0.0, 1e7, 1e8, 1e12] {
        let scene = far_scene(&dir, "far.toml", offset, 120.0, 60.0);
        let mut outs = Vec::new();
        for backend in ["vulkan", "gl", "cpu"] {
            let out = dir.join(format!("{backend}.png"));
            let o = run(&[
                "render",
                "--scene",
                s(&scene),
                "--backend",
                backend,
                "--width",
                "160",
                "--height",
                "90",
                "--out",
                s(&out),
            ]);
            assert!(
                o.status.success(),
                "{backend} at {offset:e}: {}",
                stderr(&o)
            );
            outs.push(out);
        }
        for gpu in &outs[..2] {
            let apart = pixels_apart(gpu, &outs[2]);
            println!(
                "x = {offset:e}: {} against the CPU: {apart} pixels over 1/255",
                gpu.display()
            );
            assert_eq!(apart, 0, "{} at {offset:e}", gpu.display());
        }
    }
    // The tester's narrow camera: 1e9 from the ball, 6.875e-6 degrees.
    let scene = far_scene(&dir, "narrow.toml", 0.0, 1e9, 6.875e-6);
    let out = dir.join("narrow.png");
    for backend in ["vulkan", "montecarlo"] {
        let o = run(&[
            "render",
            "--scene",
            s(&scene),
            "--backend",
            backend,
            "--width",
            "160",
            "--height",
            "90",
            "--out",
            s(&out),
        ]);
        one_line_failure(&o, &["invalid camera", "f32 rays", "--backend cpu"]);
        assert!(!out.exists());
    }
    let o = run(&[
        "render",
        "--scene",
        s(&scene),
        "--backend",
        "cpu",
        "--width",
        "160",
        "--height",
        "90",
        "--out",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Whether this process is root (CI): then the unprivileged runs go through `setpriv`.
fn is_root() -> bool {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata("/proc/self").is_ok_and(|m| m.uid() == 0)
}

/// `shadeballs args` as an unprivileged user (uid/gid 65534 through util-linux `setpriv`
/// when root; as this user otherwise), from `copy`, a copy of the binary that user can run:
/// the output and the command's own time.
fn run_unprivileged(copy: &Path, args: &[&str]) -> (Output, Duration) {
    let mut c = if is_root() {
        let mut c = Command::new("setpriv");
        c.args(["--reuid=65534", "--regid=65534", "--clear-groups"])
            .arg(copy);
        c
    } else {
        Command::new(copy)
    };
    c.args(args);
    let started = Instant::now();
    let out = c.output().expect("run setpriv (util-linux)");
    let took = started.elapsed();
    println!(
        "{args:?} -> {:?} in {took:?}\n{}",
        out.status.code(),
        stderr(&out)
    );
    (out, took)
}

/// Finding 5: an unwritable output folder was found after the work (a truth render of
/// 39.6 s, then "cannot write"). Now every output's folder takes a probe file first: as an
/// unprivileged user, the refusal comes in well under a second, names the folder, and
/// writes nothing.
#[test]
fn an_unwritable_output_folder_is_refused_before_the_work() {
    use std::os::unix::fs::PermissionsExt;
    let dir = temp_dir("round4-readonly");
    let copy = dir.join("shadeballs");
    std::fs::copy(bin(), &copy).unwrap();
    let ro = dir.join("ro");
    std::fs::create_dir_all(&ro).unwrap();
    for (p, mode) in [(&dir, 0o755), (&copy, 0o755), (&ro, 0o555)] {
        std::fs::set_permissions(p, std::fs::Permissions::from_mode(mode)).unwrap();
    }
    let x = ro.join("x.exr");
    let png = ro.join("x.png");
    let csv = ro.join("t.csv");
    let cases: [Vec<&str>; 6] = [
        vec![
            "render",
            "--backend",
            "truth",
            "--spp",
            "256",
            "--out",
            s(&x),
        ],
        vec!["render", "--backend", "montecarlo-cpu", "--out", s(&x)],
        vec!["render", "--backend", "cpu", "--out", s(&png)],
        vec!["view", "--frames", "1", "--screenshot", s(&png)],
        vec!["bake", "--samples", "1000000", "--out", s(&csv)],
        vec!["environment", "--name", "sky", "--out", s(&x)],
    ];
    for args in cases {
        let (out, took) = run_unprivileged(&copy, &args);
        let line = one_line_failure(&out, &["takes no new file", "Permission denied"]);
        assert!(line.contains(s(&ro)), "{line}");
        assert!(took < Duration::from_millis(500), "{args:?}: {took:?}");
        println!("refused in {:.1} ms", took.as_secs_f64() * 1e3);
        assert_eq!(std::fs::read_dir(&ro).unwrap().count(), 0, "{args:?}");
    }
    std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o755)).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Finding 6: with `X.stderr.exr -> X.exr`, a truth render failed after replacing `X.exr`.
/// Now the sidecar that is (or links to) the image is refused before the work; the image
/// and the link are left as they were.
#[test]
fn a_sidecar_linked_to_the_image_is_refused_first() {
    let dir = temp_dir("round4-sidecar-link");
    let image = dir.join("X.exr");
    flat_map(&image, (8, 4), 0.25, 0.25);
    let before = std::fs::read(&image).unwrap();
    std::os::unix::fs::symlink("X.exr", dir.join("X.stderr.exr")).unwrap();
    let started = Instant::now();
    let o = run(&[
        "render",
        "--backend",
        "truth",
        "--spp",
        "4",
        "--width",
        "32",
        "--height",
        "18",
        "--out",
        s(&image),
    ]);
    one_line_failure(&o, &["standard-error sidecar", "X.stderr.exr", "--out"]);
    assert!(started.elapsed() < Duration::from_secs(2));
    assert_eq!(std::fs::read(&image).unwrap(), before);
    assert!(std::fs::symlink_metadata(dir.join("X.stderr.exr"))
        .unwrap()
        .file_type()
        .is_symlink());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The `Comment` text of a PNG.
fn png_comment(path: &Path) -> String {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let reader = decoder.read_info().unwrap();
    let text = reader
        .info()
        .uncompressed_latin1_text
        .iter()
        .find(|t| t.keyword == "Comment")
        .map(|t| t.text.clone());
    text.unwrap_or_default()
}

/// The `comment` attribute of an EXR.
fn exr_comment(path: &Path) -> String {
    let meta = exr::meta::MetaData::read_from_file(path, false).unwrap();
    // The reader files an unknown attribute with the layer's.
    let header = &meta.headers[0];
    let comment = (header.shared_attributes.other.iter())
        .chain(&header.own_attributes.other)
        .find(|(k, _)| **k == *"comment")
        .map(|(_, v)| match v {
            exr::meta::attribute::AttributeValue::Text(t) => t.to_string(),
            v => format!("{v:?}"),
        });
    comment.unwrap_or_default()
}

/// Finding 7: a GPU Monte Carlo render stopped by Ctrl-C wrote a file with no word of its
/// samples. Now every render of a progressive backend (montecarlo on the GPU and the CPU,
/// montecarlo-cpu, truth) says its samples a pixel in the file, and an interrupted one the
/// signal.
#[test]
fn progressive_renders_record_their_samples_in_the_file() {
    let dir = temp_dir("round4-notes");
    for (backend, says) in [
        ("montecarlo", "shadeballs Monte Carlo on the GPU: 4 spp"),
        ("montecarlo-cpu", "shadeballs Monte Carlo on the CPU: 4 spp"),
        ("truth", "shadeballs truth (random walk): 4 spp"),
    ] {
        for ext in ["png", "exr"] {
            let out = dir.join(format!("{backend}.{ext}"));
            let o = run(&[
                "render",
                "--backend",
                backend,
                "--spp",
                "4",
                "--width",
                "32",
                "--height",
                "18",
                "--out",
                s(&out),
            ]);
            assert!(o.status.success(), "{}", stderr(&o));
            let note = if ext == "png" {
                png_comment(&out)
            } else {
                exr_comment(&out)
            };
            assert_eq!(note, says, "{backend} .{ext}");
        }
    }
    // Ctrl-C during the GPU's Monte Carlo: the samples done and the signal, in each file.
    for ext in ["exr", "png"] {
        let out = dir.join(format!("stopped.{ext}"));
        let child = Command::new(bin())
            .args([
                "render",
                "--backend",
                "montecarlo",
                "--spp",
                "65536",
                "--width",
                "320",
                "--height",
                "180",
                "--out",
                s(&out),
            ])
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(2500));
        let err = crate::cli::interrupt(child, "INT", 130);
        let spp = crate::truth_progress::interrupted_spp(&err);
        assert!(spp < 65536, "{err}");
        let note = if ext == "png" {
            png_comment(&out)
        } else {
            exr_comment(&out)
        };
        assert_eq!(
            note,
            format!("shadeballs Monte Carlo on the GPU: {spp} spp, interrupted by SIGINT")
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Runs `script` under `bash -c` with `$BIN` the binary: the output.
fn bash(script: &str) -> Output {
    let out = Command::new("bash")
        .arg("-c")
        .arg(script)
        .env("BIN", bin())
        .output()
        .unwrap();
    println!("{script} -> {:?}\n{}", out.status.code(), stderr(&out));
    out
}

/// Finding 8: under memory limits the messages misled: the CPU had the GPU's 256 MiB margin
/// (a 160x90 render refused as needing 0.3 GB), a driver that failed for want of memory was
/// advised a package to install, and the memory figure moved with what happened to be
/// mapped. Now the CPU has its own margin, the failure names the memory, and every refusal
/// says what bounds the figure.
#[test]
fn messages_under_memory_limits_name_the_memory() {
    let dir = temp_dir("round4-memory");
    let png = dir.join("x.png");
    // The CPU in 400 MB of address space: a small render fits.
    let o = bash(&format!(
        "ulimit -v 400000; \"$BIN\" render --backend cpu --width 160 --height 90 --out {}",
        s(&png)
    ));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(png.exists());
    // A size beyond it: the figure with what bounds it.
    let o = bash(&format!(
        "ulimit -v 400000; \"$BIN\" render --backend cpu --width 16384 --height 16384 --out {}",
        s(&dir.join("big.png"))
    ));
    one_line_failure(&o, &["needs about", "ulimit -v 0.41 GB less", "mapped"]);
    // Tighter still, the process itself runs short: the built-in map's 6 MiB allocation
    // aborted the process (SIGABRT, "memory allocation of 6291456 bytes failed") at 32 and
    // 35 MB, and the device's opening thread panicked at 30 MB; each is one line now
    // (cli::process::ExitsWhenShortOfMemory, cannot_start), exit status 1.
    for limit in [30000, 32000, 35000] {
        let o = bash(&format!(
            "ulimit -v {limit}; \"$BIN\" render --backend cpu --width 16 --height 16 --out {}",
            s(&dir.join("tiny.png"))
        ));
        if !o.status.success() {
            one_line_failure(&o, &["for want of memory"]);
        }
    }
    // Vulkan where the driver cannot start: no package to install. Under these limits the
    // worker threads, started by the first parallel loop after the driver had mapped its
    // libraries, sometimes could not start and rayon panicked (seen at 100 MB and 300 MB,
    // one run in several); they start with the process now (cli::process::init).
    for limit in [100000, 300000, 400000] {
        let o = bash(&format!(
            "ulimit -v {limit}; \"$BIN\" render --backend vulkan --width 160 --height 90 --out {}",
            s(&dir.join("v.png"))
        ));
        let err = stderr(&o);
        assert!(
            !err.contains("mesa-vulkan-drivers") && !err.contains("install"),
            "{err}"
        );
        // (The driver may log a line of its own before the error.)
        if !o.status.success() {
            let last = err.lines().last().unwrap_or_default();
            assert!(
                last.starts_with("error: ") && last.contains("for want of memory"),
                "{err}"
            );
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Finding 9, the smaller ones: negative flag values, a truth with no ball pixel, numbers
/// printed in 14 digits, a dielectric without `albedo`, an ignored `--ibl-frames`, "1
/// samples".
#[test]
fn the_smaller_findings_say_what_they_mean() {
    let dir = temp_dir("round4-smaller");
    let png = dir.join("x.png");
    // Negative values reach the flag's own check.
    for (args, says) in [
        (
            vec!["view", "--compare", "on,off", "--split", "-0.1"],
            "'-0.1' is not a split",
        ),
        (
            vec!["view", "--compare", "on,off", "--difference", "-2"],
            "not a difference scale",
        ),
        (
            vec!["render", "--backend", "truth", "--stderr", "-0.5"],
            "not a relative standard error",
        ),
    ] {
        let o = run(&args);
        let err = stderr(&o);
        assert!(!o.status.success() && err.contains(says), "{args:?}: {err}");
        assert!(!err.contains("unexpected argument"), "{err}");
    }
    // A truth with no ball pixel: no "0.000 %", no target met, a warning; two passes.
    let empty = dir.join("empty.toml");
    std::fs::write(
        &empty,
        "[camera]\nposition = [0, 0, 300]\ntarget = [0, 0, 0]\nvfov_deg = 40\n\
         [environment]\nradiance = [0.5, 0.5, 0.5]\n\
         [[ball]]\nposition = [0, 0, 900]\nradius = 10\nroughness = 0.3\n\
         material = { kind = \"metal\", f0 = [0.9, 0.6, 0.4] }\n",
    )
    .unwrap();
    let o = run(&[
        "render",
        "--scene",
        s(&empty),
        "--backend",
        "truth",
        "--stderr",
        "0.5%",
        "--width",
        "32",
        "--height",
        "18",
        "--out",
        s(&png),
    ]);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(!err.contains("0.000 %"), "{err}");
    assert!(err.contains("worst ball standard error n/a"), "{err}");
    assert!(err.contains("no ball covers a pixel"), "{err}");
    assert!(
        err.lines().filter(|l| l.starts_with("truth: ")).count() <= 3,
        "{err}"
    );
    // Numbers: 1e13, not 10000000000000.0; f0 = 1 is a mirror, not "ior 2000000000000".
    let bad = |name: &str, body: &str| {
        let path = dir.join(name);
        std::fs::write(&path, body).unwrap();
        let o = run(&["render", "--scene", s(&path), "--out", s(&png)]);
        one_line_failure(&o, &[])
    };
    let ball = |material: &str| {
        format!(
            "[[ball]]\nposition = [0, 0, 0]\nradius = 10\nroughness = 0.3\nmaterial = {material}\n"
        )
    };
    let metal = "{ kind = \"metal\", f0 = [0.9, 0.6, 0.4] }";
    let line = bad(
        "far.toml",
        &format!("[camera]\nposition = [1e13, 0, 0]\n{}", ball(metal)),
    );
    assert!(
        line.contains("[1e13, 0.0, 0.0]") && !line.contains("10000000000000"),
        "{line}"
    );
    let line = bad(
        "mirror.toml",
        &ball("{ kind = \"dielectric\", albedo = [0.5, 0.5, 0.5], f0 = [1, 1, 1] }"),
    );
    assert!(
        line.contains("perfect mirror") && !line.contains("2000000000000"),
        "{line}"
    );
    // A dielectric without albedo is refused, as a metal without f0 is.
    let line = bad("bare.toml", &ball("{ kind = \"dielectric\", ior = 1.5 }"));
    assert!(line.contains("a dielectric needs `albedo`"), "{line}");
    let line = bad("bare-metal.toml", &ball("{ kind = \"metal\" }"));
    assert!(line.contains("a metal needs exactly one of"), "{line}");
    // --ibl-frames where nothing accumulates frames: a notice, and no frames drawn.
    let homework = crate::cli_render::scene_file("homework.toml");
    for (args, says) in [
        (
            vec!["--environment", "studio"],
            "the split sum draws one exact frame",
        ),
        (
            vec!["--scene", &homework, "--ibl-method", "lobe"],
            "no environment map",
        ),
        (
            vec!["--environment", "studio", "--backend", "cpu"],
            "only a GPU backend",
        ),
    ] {
        let mut all = vec![
            "render",
            "--width",
            "32",
            "--height",
            "18",
            "--ibl-frames",
            "8",
        ];
        all.extend(args);
        all.extend(["--out", s(&png)]);
        let o = run(&all);
        let err = stderr(&o);
        assert!(o.status.success(), "{err}");
        assert!(
            err.contains("notice: --ibl-frames 8 is ignored") && err.contains(says),
            "{err}"
        );
        assert!(!err.contains("lobe: 8 frames"), "{err}");
    }
    // "1 sample", "1 frame".
    let o = run(&[
        "render",
        "--environment",
        "studio",
        "--ibl-method",
        "lobe",
        "--ibl-samples",
        "1",
        "--ibl-frames",
        "2",
        "--width",
        "32",
        "--height",
        "18",
        "--out",
        s(&png),
    ]);
    let err = stderr(&o);
    assert!(err.contains("lobe: 2 frames of 1 sample at"), "{err}");
    assert!(!err.contains("1 samples"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A glTF file `x.gltf` in `dir` with two materials, a buffer file `buf.bin` and an image
/// file `tex.png` it names (neither drawn): the three inputs.
fn gltf_with_files(dir: &Path) -> [PathBuf; 3] {
    let gltf = dir.join("x.gltf");
    let doc = serde_json::json!({
        "asset": {"version": "2.0"},
        "materials": [
            {"name": "gold", "pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.8, 0.3, 1.0],
                "metallicFactor": 1.0, "roughnessFactor": 0.3}},
            {"name": "clay", "pbrMetallicRoughness": {"metallicFactor": 0.0,
                "roughnessFactor": 0.8}}
        ],
        "buffers": [{"byteLength": 8, "uri": "buf.bin"}],
        "images": [{"uri": "tex.png"}]
    });
    std::fs::write(&gltf, serde_json::to_vec_pretty(&doc).unwrap()).unwrap();
    let bin = dir.join("buf.bin");
    std::fs::write(&bin, [7u8; 8]).unwrap();
    let tex = dir.join("tex.png");
    std::fs::write(&tex, b"not drawn, but the asset's").unwrap();
    [gltf, bin, tex]
}

/// The names in `dir`, sorted: a refused command leaves no temporary file.
fn names_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Finding 2 for the glTF commands of issue 35: `import FILE --out`, `render --scene
/// FILE.gltf` and `view --scene FILE.gltf` wrote through an output that is (or links to)
/// the glTF file, or the buffer or image file it names. Each is refused in one line before
/// any work; every input is left byte for byte and no file is added.
#[test]
fn gltf_outputs_over_their_inputs_are_refused() {
    let dir = temp_dir("round4-gltf-overwrite");
    let inputs = gltf_with_files(&dir);
    for (link, to) in [
        ("gltf.toml", "x.gltf"),
        ("bin.toml", "buf.bin"),
        ("tex.toml", "tex.png"),
        ("bin.png", "buf.bin"),
        ("bin.exr", "buf.bin"),
    ] {
        std::os::unix::fs::symlink(to, dir.join(link)).unwrap();
    }
    std::fs::hard_link(&inputs[0], dir.join("hard.toml")).unwrap();
    let files: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    let before = snapshot(&files);
    let names = names_in(&dir);
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["import", "x.gltf", "--out", "gltf.toml"],
            "the glTF file",
        ),
        (
            vec!["import", "x.gltf", "--out", "hard.toml"],
            "the glTF file",
        ),
        (
            vec!["import", "x.gltf", "--out", "bin.toml"],
            "the glTF file's buffer",
        ),
        (
            vec!["import", "x.gltf", "--out", "tex.toml"],
            "the glTF file's image",
        ),
        (
            vec!["render", "--scene", "x.gltf", "--out", "bin.png"],
            "the glTF file's buffer",
        ),
        (
            vec!["render", "--scene", "x.gltf", "--out", "tex.png"],
            "the glTF file's image",
        ),
        (
            vec![
                "render",
                "--scene",
                "x.gltf",
                "--backend",
                "truth",
                "--spp",
                "2",
                "--out",
                "bin.exr",
            ],
            "the glTF file's buffer",
        ),
        (
            vec![
                "view",
                "--scene",
                "x.gltf",
                "--frames",
                "1",
                "--screenshot",
                "bin.png",
            ],
            "the glTF file's buffer",
        ),
    ];
    for (args, names_it) in cases {
        let mut args = args;
        if args[0] == "render" {
            args.extend(["--width", "16", "--height", "9"]);
        }
        let started = Instant::now();
        let o = run_in(Some(&dir), &args);
        one_line_failure(&o, &[names_it, "choose another output path"]);
        assert!(started.elapsed() < Duration::from_secs(5), "{args:?}");
        assert_eq!(snapshot(&files), before, "{args:?} changed an input");
        assert_eq!(names_in(&dir), names, "{args:?} left a file");
    }
    // The same glTF imports and renders where the output is its own file.
    let o = run_in(Some(&dir), &["import", "x.gltf", "--out", "s.toml"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read_to_string(dir.join("s.toml"))
        .unwrap()
        .contains("gold"));
    assert_eq!(snapshot(&files), before);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Finding 5 for the commands of issue 35: `import` and `export-shader` found an
/// unwritable folder only when writing. Now their folder takes a probe file first: as an
/// unprivileged user the refusal names the folder and writes nothing (`bake` to a C or
/// GLSL header already probed: held here too).
#[test]
fn gltf_and_shader_outputs_probe_their_folder_first() {
    use std::os::unix::fs::PermissionsExt;
    let dir = temp_dir("round4-gltf-readonly");
    let copy = dir.join("shadeballs");
    std::fs::copy(bin(), &copy).unwrap();
    let [gltf, ..] = gltf_with_files(&dir);
    let ro = dir.join("ro");
    std::fs::create_dir_all(&ro).unwrap();
    for (p, mode) in [(&dir, 0o755), (&copy, 0o755), (&gltf, 0o644), (&ro, 0o555)] {
        std::fs::set_permissions(p, std::fs::Permissions::from_mode(mode)).unwrap();
    }
    let (toml, frag) = (ro.join("s.toml"), ro.join("ball.frag"));
    let (h, glsl) = (ro.join("t.h"), ro.join("t.glsl"));
    let cases: [Vec<&str>; 4] = [
        vec!["import", s(&gltf), "--out", s(&toml)],
        vec!["export-shader", "--lang", "glsl", "--out", s(&frag)],
        vec!["bake", "--samples", "1000", "--out", s(&h)],
        vec!["bake", "--samples", "1000", "--out", s(&glsl)],
    ];
    for args in cases {
        let (out, took) = run_unprivileged(&copy, &args);
        let line = one_line_failure(&out, &["takes no new file", "Permission denied"]);
        assert!(line.contains(s(&ro)), "{line}");
        assert!(took < Duration::from_millis(500), "{args:?}: {took:?}");
        assert_eq!(std::fs::read_dir(&ro).unwrap().count(), 0, "{args:?}");
    }
    std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o755)).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
}
