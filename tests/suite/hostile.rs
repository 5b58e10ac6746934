//! Issue 28, a hostile tester's findings: each case as the tester ran it (the real binary),
//! with what it must do now. Numbered as in the issue.

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use shadeballs::environment::{save, EnvMap};

use crate::bad_input::fails_with_one_line;
use crate::cli::temp_dir;
use crate::cli_render::scene_file;

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_shadeballs")
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs `shadeballs args` with `envs`: the output.
fn run(args: &[&str], envs: &[(&str, &str)]) -> Output {
    let out = Command::new(bin())
        .args(args)
        .envs(envs.iter().copied())
        .output()
        .unwrap();
    println!(
        "{args:?} -> {:?}\n{}",
        out.status.code(),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Runs `script` under `bash -c` (a `ulimit` for the binary, `$BIN`): the output.
fn bash(script: &str) -> Output {
    let out = Command::new("bash")
        .arg("-c")
        .arg(script)
        .env("BIN", bin())
        .output()
        .unwrap();
    println!(
        "{script} -> {:?}\n{}",
        out.status.code(),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// The files in `dir`, sorted.
fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

fn exr_values(path: &Path) -> Vec<f32> {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .into_rgba32f()
        .into_raw()
}

/// The mean of the RGB channels of an RGBA image.
fn rgb_mean(rgba: &[f32]) -> f64 {
    let n = rgba.len() / 4;
    rgba.chunks(4)
        .map(|p| f64::from(p[0] + p[1] + p[2]) / 3.0)
        .sum::<f64>()
        / n as f64
}

/// Finding 1: GL cannot hold the truth's f32 sums: with the default 64 frames (`accumulate_truth`)
/// it refused only with `--spp 1`; with more, the error scopes' drop order panicked.
#[test]
fn gl_truth_balls_refuse_in_one_line_at_any_spp() {
    let dir = temp_dir("hostile-gl-truth");
    let png = dir.join("x.png");
    for spp in [None, Some("2"), Some("1")] {
        let mut args = vec![
            "render",
            "--scene",
            "",
            "--width",
            "64",
            "--height",
            "36",
            "--out",
            s(&png),
        ];
        let scene = scene_file("truth.toml");
        args[2] = &scene;
        if let Some(n) = spp {
            args.extend(["--spp", n]);
        }
        let out = run(&args, &[("WGPU_BACKEND", "gl")]);
        let err = stderr(&out);
        assert!(!err.contains("panicked"), "{spp:?}: {err}");
        // Where GL can render to Rgba32Float the render succeeds; lavapipe's GL cannot.
        if out.status.success() {
            assert!(png.exists());
        } else {
            assert_eq!(out.status.code(), Some(1), "{spp:?}: {err}");
            assert!(err.contains("cannot render to Rgba32Float"), "{err}");
            assert_eq!(err.trim().lines().count(), 1, "{err}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A 256x128 map of 0.5 with a 4x4 sun of `sun` behind the camera, 30 degrees up (what
/// the balls' fronts reflect), as f32 EXR.
fn sun_map(path: &Path, sun: f32) {
    let (w, h) = (256u32, 128u32);
    let mut texels = vec![[0.5f32; 3]; (w * h) as usize];
    // Direction +z (behind the camera) is u = 0 (and 1); 30 degrees up is v = 1/3.
    for j in 41..45 {
        for i in [254, 255, 0, 1] {
            texels[(j * w + i) as usize] = [sun; 3];
        }
    }
    save(&EnvMap::new(w, h, texels).unwrap(), path).unwrap();
}

/// Finding 2: Radiance above f16's 65504 kept its energy nowhere but in `--backend montecarlo`:
/// GPU and CPU clipped the sun. Now the map's textures hold it divided by a power of two.
#[test]
fn bright_suns_keep_their_energy_on_the_gpu_and_the_cpu() {
    let dir = temp_dir("hostile-sun");
    let mut means = Vec::new();
    for sun in [2e5f32, 2e6] {
        let map = dir.join(format!("sun-{sun}.exr"));
        sun_map(&map, sun);
        let mean = |backend: &str| {
            let out = dir.join(format!("{backend}-{sun}.exr"));
            let o = run(
                &[
                    "render",
                    "--environment",
                    s(&map),
                    "--background",
                    "black",
                    "--no-labels",
                    "--backend",
                    backend,
                    "--width",
                    "96",
                    "--height",
                    "54",
                    "--spp",
                    "64",
                    "--out",
                    s(&out),
                ],
                &[],
            );
            assert!(o.status.success(), "{}", stderr(&o));
            let v = exr_values(&out);
            assert!(v.iter().all(|c| c.is_finite()), "{backend} {sun}");
            (rgb_mean(&v), v)
        };
        let (mc, _) = mean("montecarlo");
        let (gpu, gpu_v) = mean("vulkan");
        let (cpu, cpu_v) = mean("cpu");
        println!("sun {sun}: montecarlo {mc:.4}, vulkan {gpu:.4}, cpu {cpu:.4}");
        means.push((mc, gpu, cpu));
        // The split sum against the Monte Carlo integral of the same model: clipped at
        // 65504 the GPU was 3x under at 2e5 and 30x under at 2e6. Measured at df0c8fe:
        // 6.938 against 7.099 (-2.3 %), 69.20 against 70.80; with the prefilter's bright
        // texels apart (its layers within 0.2 % of their converged selves about a sun,
        // gpu::tests::ibl::the_sampled_layers_under_a_sun_converge): 6.888 (-3.0 %) and
        // 68.70 (-3.0 %), the split sum's own approximation of a sun's highlight on these
        // 12-pixel balls. 3 %, for the clipping this test is about, is now at the edge.
        for (name, m) in [("vulkan", gpu), ("cpu", cpu)] {
            assert!((m / mc - 1.0).abs() < 0.03, "{name} {m} vs montecarlo {mc}");
        }
        // The CPU twin reads the same f16 textures with the same scale: measured 4.6e-4
        // relative of the GPU's mean at both suns (f64 against f32, the antialiased edge).
        assert!((cpu / gpu - 1.0).abs() < 2e-3, "cpu {cpu} vs gpu {gpu}");
        assert_eq!(gpu_v.len(), cpu_v.len());
    }
    // Ten times the sun: the image's energy follows (nearly all of it is the sun's).
    let ratio = means[1].1 / means[0].1;
    let mc_ratio = means[1].0 / means[0].0;
    assert!(
        (ratio / mc_ratio - 1.0).abs() < 0.05,
        "{ratio} vs {mc_ratio}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Finding 2: What f16 still cannot hold once scaled (values 1e-12 of the peak) is said in one
/// warning; the scale alone is no warning.
#[test]
fn a_map_beyond_f16s_range_warns_once() {
    let dir = temp_dir("hostile-range");
    let map = dir.join("range.exr");
    let (w, h) = (64u32, 32u32);
    let mut texels = vec![[1e-9f32; 3]; (w * h) as usize];
    texels[0] = [1e4; 3];
    save(&EnvMap::new(w, h, texels.clone()).unwrap(), &map).unwrap();
    let out = dir.join("x.png");
    let args = [
        "render",
        "--environment",
        s(&map),
        "--backend",
        "cpu",
        "--width",
        "32",
        "--height",
        "18",
        "--out",
        s(&out),
    ];
    let o = run(&args, &[]);
    assert!(o.status.success());
    let warnings = |o: &Output| {
        stderr(o)
            .lines()
            .filter(|l| l.contains("became 0 in its half-float textures"))
            .count()
    };
    assert_eq!(warnings(&o), 1, "{}", stderr(&o));
    // A bright sun over a sky f16 holds: scaled, no warning.
    sun_map(&map, 2e6);
    let o = run(&args, &[]);
    assert!(o.status.success());
    assert_eq!(warnings(&o), 0, "{}", stderr(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Finding 3: An 8192x4096 map under a 3 GB address space aborted in `MipChain::new`; now its
/// memory is estimated before the chain is built.
#[test]
fn maps_beyond_memory_fail_in_one_line_before_allocating() {
    let dir = temp_dir("hostile-map-memory");
    let sky = dir.join("sky.hdr");
    let o = run(
        &[
            "environment",
            "--name",
            "sky",
            "--width",
            "8192",
            "--out",
            s(&sky),
        ],
        &[],
    );
    assert!(o.status.success());
    let png = dir.join("x.png");
    // Measured before the fix (the tester saw 134 under 3 GB on their machine): Vulkan
    // aborted (134) under 2.6 GB and rendered under 3 GB; the CPU aborted under 1.3 GB and
    // rendered under 1.5 GB. Now the aborts are one line, and what rendered still renders
    // with room to spare (4 GB, 2 GB).
    for (backend, limit, fits) in [
        ("vulkan", 2600000, false),
        ("vulkan", 4000000, true),
        ("cpu", 1300000, false),
        ("cpu", 2000000, true),
    ] {
        let o = bash(&format!(
            "ulimit -v {limit}; exec \"$BIN\" render --backend {backend} --environment '{}' \
             --width 320 --height 180 --out '{}'",
            sky.display(),
            png.display()
        ));
        let err = stderr(&o);
        if fits {
            assert!(o.status.success(), "{backend} under {limit} kB: {err}");
            std::fs::remove_file(&png).unwrap();
            continue;
        }
        assert_eq!(
            o.status.code(),
            Some(1),
            "{backend} under {limit} kB: {err}"
        );
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(
            err.contains("environment map") && err.contains("needs about"),
            "{err}"
        );
        assert!(!png.exists());
    }
    // The viewer prepares the same chain on the GPU at its first frame (the library's
    // check, after the device opened, as `render`'s): refused in one line, not an abort.
    let x = crate::viewer::Xvfb::start();
    let script = format!(
        "ulimit -v 2600000; exec \"$BIN\" view --environment '{}' --frames 2",
        sky.display()
    );
    let child = x
        .command("bash")
        .args(["-c", &script])
        .env("BIN", bin())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let o = crate::viewer::wait(child, Duration::from_secs(120));
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    let errors: Vec<&str> = err.lines().filter(|l| l.starts_with("error")).collect();
    assert_eq!(errors.len(), 1, "{err}");
    assert!(
        errors[0].contains("mip chain") && errors[0].contains("needs about"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Finding 4 (a): The sidecar's path is checked with the image's, before the walk.
#[test]
fn truth_sidecar_paths_are_checked_before_rendering() {
    let dir = temp_dir("hostile-sidecar");
    std::fs::create_dir(dir.join("t1.stderr.exr")).unwrap();
    let exr = dir.join("t1.exr");
    let start = Instant::now();
    let err = fails_with_one_line(
        &[
            "render",
            "--backend",
            "truth",
            "--spp",
            "4",
            "--out",
            s(&exr),
        ],
        &[],
        "t1.stderr.exr",
    );
    assert!(err.contains("not a regular file"), "{err}");
    // Refused at once: the walk at 1280x720 takes minutes on two cores.
    assert!(start.elapsed() < Duration::from_secs(10));
    assert_eq!(entries(&dir), ["t1.stderr.exr"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Findings 4 (b) and 11: A write that fails for want of room (a file size limit, as a full disk)
/// leaves the old pair as it was, no temporary file, and says why in the writer's words.
#[test]
fn truth_pairs_commit_together_and_a_full_disk_is_named() {
    let dir = temp_dir("hostile-pair");
    let exr = dir.join("t.exr");
    let side = dir.join("t.stderr.exr");
    // A map behind the balls makes the image much larger than its sidecar (zeros there).
    let truth = |limit: Option<u64>, seed: u32| {
        bash(&format!(
            "trap '' XFSZ; {} exec \"$BIN\" render --backend truth --spp 2 --environment \
             studio --width 48 --height 27 --seed {seed} --out '{}'",
            limit.map_or(String::new(), |k| format!("ulimit -f {k};")),
            exr.display()
        ))
    };
    let o = truth(None, 1);
    assert!(o.status.success(), "{}", stderr(&o));
    let (old_image, old_side) = (std::fs::read(&exr).unwrap(), std::fs::read(&side).unwrap());
    println!(
        "image {} bytes, sidecar {}",
        old_image.len(),
        old_side.len()
    );
    // Room for the sidecar, not for the image (bash's ulimit -f counts 1024-byte blocks).
    let k = (old_side.len() as u64).div_ceil(1024) + 1;
    assert!(
        k * 1024 < old_image.len() as u64,
        "the image must be larger than the sidecar: {} and {}",
        old_image.len(),
        old_side.len()
    );
    // Another seed: a new sidecar would differ from the old one, which must be left.
    let o = truth(Some(k), 2);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("File too large"), "{err}");
    assert!(!err.contains("decoding"), "{err}");
    assert_eq!(std::fs::read(&exr).unwrap(), old_image);
    assert_eq!(std::fs::read(&side).unwrap(), old_side);
    assert_eq!(entries(&dir), ["t.exr", "t.stderr.exr"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Finding 5: One estimate has no standard error, and a target missed at the cap is said.
#[test]
fn truth_statistics_say_what_they_cannot_know() {
    let dir = temp_dir("hostile-stats");
    let small = ["--backend", "truth", "--width", "32", "--height", "18"];
    let exr = dir.join("t.exr");
    let err = fails_with_one_line(
        &[&["render", "--spp", "1", "--out", s(&exr)][..], &small].concat(),
        &[],
        "no standard error",
    );
    assert!(err.contains("--spp 2"), "{err}");
    assert!(entries(&dir).is_empty());
    let png = dir.join("t.png");
    let o = run(
        &[&["render", "--spp", "1", "--out", s(&png)][..], &small].concat(),
        &[],
    );
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(!err.contains("+- 0.000 %"), "{err}");
    assert!(err.contains("no standard error from one estimate"), "{err}");
    let o = run(
        &[
            &[
                "render",
                "--stderr",
                "0.0001",
                "--spp",
                "4",
                "--out",
                s(&png),
            ][..],
            &small,
        ]
        .concat(),
        &[],
    );
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("warning: the target standard error 0.010 % was not reached"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Finding 7: A 250-byte name renders (its temporary name is short); a 256-byte one is refused
/// before rendering.
#[test]
fn long_output_names_render_or_fail_first() {
    let dir = temp_dir("hostile-long");
    let small = ["--backend", "cpu", "--width", "16", "--height", "9"];
    let name = format!("{}.png", "n".repeat(246));
    assert_eq!(name.len(), 250);
    let out = dir.join(&name);
    let o = run(&[&["render", "--out", s(&out)][..], &small].concat(), &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(image::open(&out).is_ok());
    assert_eq!(entries(&dir), [name]);
    // Two long names with one prefix: their temporary names differ (the sidecar and its
    // image are written at once).
    let exr = dir.join(format!("{}.exr", "t".repeat(240)));
    let o = run(
        &[
            "render",
            "--backend",
            "truth",
            "--spp",
            "2",
            "--width",
            "16",
            "--height",
            "9",
            "--out",
            s(&exr),
        ],
        &[],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(entries(&dir).len(), 3, "{:?}", entries(&dir));
    let long = dir.join(format!("{}.png", "n".repeat(252)));
    let start = Instant::now();
    fails_with_one_line(
        &[&["render", "--out", s(&long)][..], &small].concat(),
        &[],
        "more than the 255",
    );
    assert!(start.elapsed() < Duration::from_secs(10));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Finding 8: A FIFO named as a map was opened twice and waited forever; now it is refused (the
/// test gives it 20 s, then kills it and fails).
#[test]
fn a_fifo_map_is_refused_without_waiting() {
    let dir = temp_dir("hostile-fifo");
    let fifo = dir.join("m.hdr");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let mut child = Command::new(bin())
        .args([
            "render",
            "--backend",
            "cpu",
            "--width",
            "8",
            "--height",
            "8",
        ])
        .args(["--environment", s(&fifo), "--out", s(&dir.join("x.png"))])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > Duration::from_secs(20) {
            child.kill().unwrap();
            child.wait().unwrap();
            panic!("a FIFO map still waits after 20 s");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    println!("{err}");
    assert_eq!(status.code(), Some(1), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("not a regular file"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

const BALL: &str = "[[ball]]\ngrid = [0, 0]\nradius = 35\nroughness = 0.5\nmaterial = { kind = \"metal\", f0 = [1, 1, 1] }\n";

/// Finding 10: Black balls from a black map, an ignored `--stderr` and `--labels` that draw
/// nothing each get a warning.
#[test]
fn silent_cases_get_a_warning() {
    let dir = temp_dir("hostile-silence");
    let png = dir.join("x.png");
    let black = dir.join("black.exr");
    save(&EnvMap::new(8, 4, vec![[0.0; 3]; 32]).unwrap(), &black).unwrap();
    let white = dir.join("white.exr");
    save(&EnvMap::new(8, 4, vec![[1.0; 3]; 32]).unwrap(), &white).unwrap();
    let zero = dir.join("zero.toml");
    std::fs::write(
        &zero,
        format!(
            "{BALL}[environment]\nmap = '{}'\nintensity = 0\n",
            white.display()
        ),
    )
    .unwrap();
    let black_scene = dir.join("black.toml");
    std::fs::write(
        &black_scene,
        format!("{BALL}[environment]\nmap = '{}'\n", black.display()),
    )
    .unwrap();
    let warned = |extra: &[&str], needle: &str| {
        let small = if extra.contains(&"--width") {
            &["--backend", "cpu"][..]
        } else {
            &["--backend", "cpu", "--width", "32", "--height", "18"][..]
        };
        let o = run(
            &[&["render", "--out", s(&png)][..], small, extra].concat(),
            &[],
        );
        let err = stderr(&o);
        assert!(o.status.success(), "{extra:?}: {err}");
        assert!(err.contains(needle), "{extra:?}: {err}");
    };
    warned(&["--scene", s(&zero)], "the map's intensity is 0");
    warned(&["--scene", s(&black_scene)], "the map is black");
    warned(&["--stderr", "0.01"], "--stderr is ignored");
    warned(&["--labels"], "--labels drew nothing");
    for size in [["480", "270"], ["320", "180"]] {
        warned(
            &["--labels", "--width", size[0], "--height", size[1]],
            "--labels drew nothing",
        );
    }
    // A map that lights the balls: no black-ball warning.
    let o = run(
        &[
            &["render", "--out", s(&png), "--environment", s(&white)][..],
            &["--backend", "cpu", "--width", "32", "--height", "18"],
        ]
        .concat(),
        &[],
    );
    assert!(!stderr(&o).contains("black"), "{}", stderr(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Finding 9: The KTX2 reader accepted what the writer never writes. Byte offsets: the descriptor
/// starts at 104 (its basic block at 108: primaries at 117, samples at 132, 16 bytes each,
/// sampleLower at +8 and sampleUpper at +12).
#[test]
fn ktx2_reader_accepts_only_what_the_writer_writes() {
    use shadeballs::lut::ktx2::{encode_tables, parse_tables};
    use shadeballs::lut::{bake, BakeConfig, Layout, LayoutKind, Storage};
    let file = |storage| {
        let layout = Layout::of_kind(LayoutKind::Warped)
            .with_storage(storage)
            .with_size(4, 3);
        encode_tables(&bake(&BakeConfig {
            layout,
            ..BakeConfig::default()
        }))
        .unwrap()
    };
    let refused = |bytes: &[u8], needle: &str| {
        let e = parse_tables(bytes).expect_err("read back").to_string();
        println!("{e}");
        assert!(!e.contains('\n') && e.contains(needle), "{e}");
    };
    let set = |bytes: &[u8], at: usize, v: &[u8]| {
        let mut b = bytes.to_vec();
        b[at..at + v.len()].copy_from_slice(v);
        b
    };
    let unorm = file(Storage::Unorm8);
    parse_tables(&unorm).unwrap();
    // Both samples' sampleUpper 255 -> 127: a conforming reader would rescale.
    let mut upper = unorm.clone();
    for k in 0..2 {
        upper = set(&upper, 132 + 16 * k + 12, &127u32.to_le_bytes());
    }
    refused(&upper, "sampleUpper");
    let float = file(Storage::F32);
    parse_tables(&float).unwrap();
    refused(
        &set(&float, 132 + 8, &f32::NAN.to_bits().to_le_bytes()),
        "sampleLower",
    );
    refused(
        &set(&float, 132 + 12, &7.5f32.to_bits().to_le_bytes()),
        "sampleUpper",
    );
    refused(&set(&float, 117, &[10]), "primaries");
    let mut trailing = float.clone();
    trailing.extend_from_slice(&[0; 4]);
    refused(&trailing, "bytes after the texel data");
    // The fuzz: 4000 files of each storage with 1 to 4 bytes changed at random (a fixed
    // generator, so a failure repeats). Never a panic or a second line; a file read back
    // re-encodes to exactly its bytes but for the `KTXwriter` value, which any version may
    // write (so only that value and texel values may differ from the writer's file, the
    // texels only to values the writer would store as they are).
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let mut counts = [0usize; 2];
    for good in [unorm, float, file(Storage::F16)] {
        let writer = good.windows(10).position(|w| w == b"KTXwriter\0").unwrap() + 10;
        let value = writer + good[writer..].iter().position(|&c| c == 0).unwrap();
        let outside = |b: &[u8]| [b[..writer].to_vec(), b[value..].to_vec()].concat();
        for _ in 0..4000 {
            let mut bad = good.clone();
            for _ in 0..1 + next() % 4 {
                let at = (next() % bad.len() as u64) as usize;
                bad[at] = next() as u8;
            }
            match parse_tables(&bad) {
                Ok(t) => {
                    counts[0] += 1;
                    let again = encode_tables(&t).unwrap();
                    assert_eq!(again.len(), bad.len());
                    assert_eq!(outside(&again), outside(&bad), "a changed file read back");
                }
                Err(e) => {
                    counts[1] += 1;
                    assert!(!e.to_string().contains('\n'), "{e}");
                }
            }
        }
    }
    println!(
        "ktx2 fuzz: {} read back (texel changes), {} refused",
        counts[0], counts[1]
    );
}

/// Finding 11: The viewer's window destroyed from outside: winit's size query panicked (exit 101);
/// now the viewer quits. And GL's refusal of the truth balls is said once, not every frame.
#[test]
fn the_viewer_survives_its_window_and_says_things_once() {
    use crate::viewer::{wait, Xvfb};
    let x = Xvfb::start();
    let child = x
        .command(bin())
        .arg("view")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let id = x.xdotool(&["search", "--sync", "--name", "^shadeballs$"]);
    let id = id.lines().next().unwrap().to_string();
    // A frame or two first, as a user's window has.
    std::thread::sleep(Duration::from_millis(1500));
    x.xdotool(&["windowclose", &id]);
    let out = wait(child, Duration::from_secs(60));
    let err = stderr(&out);
    println!("{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(out.status.code(), Some(0), "{err}");
    let out = x
        .command(bin())
        .args(["view", "--backend", "gl", "--frames", "5", "--scene"])
        .arg(scene_file("truth.toml"))
        .output()
        .unwrap();
    let err = stderr(&out);
    println!("{err}");
    assert!(out.status.success(), "{err}");
    // lavapipe's GL cannot render to Rgba32Float: the line once, not five times.
    let said = err.matches("cannot render to Rgba32Float").count();
    assert!(said <= 1, "{err}");
}

/// Finding 2: An `.hdr` of maximum-exponent texels (1.7e38, f32's range) rendered a flat 65504;
/// now its radiance, finite, on every renderer. Since issue 38 (finding 1) a map's brightest
/// texel times its intensity is held to the scene's 1e12: the map at an intensity that
/// brings it to 8.5e11 renders that, unclipped; at intensity 1 it is refused in one line.
#[test]
fn a_maximum_exponent_hdr_renders_finite_and_unclipped() {
    let dir = temp_dir("hostile-max-hdr");
    let map = dir.join("max.hdr");
    let (w, h) = (16usize, 8usize);
    let mut bytes = format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n").into_bytes();
    bytes.extend(std::iter::repeat_n(255u8, 4 * w * h));
    std::fs::write(&map, bytes).unwrap();
    let scene = dir.join("max.toml");
    std::fs::write(
        &scene,
        "[environment]\nmap = \"max.hdr\"\nintensity = 5e-27\n[[ball]]\ngrid = [0, 0]\n\
         radius = 35\nroughness = 0.5\nmaterial = { kind = \"metal\", f0 = [1, 1, 1] }\n",
    )
    .unwrap();
    for backend in ["vulkan", "gl", "cpu"] {
        let out = dir.join(format!("{backend}.exr"));
        let o = run(
            &[
                "render",
                "--scene",
                s(&scene),
                "--backend",
                backend,
                "--width",
                "32",
                "--height",
                "18",
                "--out",
                s(&out),
            ],
            &[],
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let v = exr_values(&out);
        let bad = v.iter().filter(|c| !c.is_finite()).count();
        let max = v.iter().copied().fold(0.0f32, f32::max);
        println!("{backend}: {bad} non-finite channels, max {max:e}");
        assert_eq!(bad, 0, "{backend}");
        // RGBE (255, 255, 255, exponent 255) is 255/256 2^127 = 1.69e38, times 5e-27.
        assert!(max > 8e11 && max <= 1e12, "{backend}: {max}");
    }
    let out = dir.join("refused.exr");
    let o = run(&["render", "--environment", s(&map), "--out", s(&out)], &[]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("beyond the 1e12"), "{}", stderr(&o));
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Finding 6: Where balls are smaller than a pixel (1x1, 3x1, 16384x1 images) the GPU and the
/// CPU disagreed by up to 31/255: the antialiased silhouette linearised over a pixel wider than
/// the ball shaded a knife edge (n.v = 0) that f32 and f64 resolve differently. Now such a
/// ball is shaded along the pixel's centre ray on both, which agree within 1/255 (the
/// README's promise). The homework's scene (the tester's default then) and the showcase.
#[test]
fn gpu_and_cpu_agree_on_tiny_and_extreme_images() {
    let dir = temp_dir("hostile-tiny");
    for scene in ["homework.toml", "default.toml"] {
        for (w, h) in [(1, 1), (3, 1), (16384, 1), (1, 9)] {
            let mut images = Vec::new();
            for backend in ["vulkan", "cpu"] {
                let out = dir.join(format!("{scene}-{w}x{h}-{backend}.png"));
                let (ws, hs) = (w.to_string(), h.to_string());
                let args = [
                    "render",
                    "--scene",
                    &scene_file(scene),
                    "--no-labels",
                    "--backend",
                    backend,
                    "--width",
                    &ws,
                    "--height",
                    &hs,
                    "--out",
                    s(&out),
                ];
                assert!(run(&args, &[]).status.success());
                images.push(image::open(&out).unwrap().to_rgba8().into_raw());
            }
            let worst = images[0]
                .iter()
                .zip(&images[1])
                .map(|(a, b)| a.abs_diff(*b))
                .max()
                .unwrap();
            assert!(
                worst <= 1,
                "{scene} at {w}x{h}: GPU and CPU differ by {worst}/255"
            );
        }
    }
}
