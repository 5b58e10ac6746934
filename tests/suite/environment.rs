//! Environment maps (issue 15, the map side): the direction convention, texel solid angles,
//! rotation, the `.hdr`/`.exr` loader and writer and their bad-input rules, the built-ins,
//! the scene file's `[environment]`, `background` and `ibl_term`, and the `environment`
//! subcommand.

use std::path::PathBuf;

use shadeballs::environment::{self, Builtin};

use shadeballs::scene;

use crate::cli::{shadeballs, temp_dir};

const BALL: &str = "[[ball]]\ngrid = [0, 0]\nradius = 35\nroughness = 0.5\nmaterial = { kind = \"metal\", f0 = [1, 1, 1] }\n";

#[test]
fn environment_command_writes_a_map_a_scene_can_use() {
    let dir = temp_dir("env-cli");
    let out: PathBuf = dir.join("sky.exr");
    let (ok, stderr) = shadeballs(&[
        "environment",
        "--name",
        "sky",
        "--out",
        out.to_str().unwrap(),
        "--width",
        "256",
    ]);
    assert!(ok, "{stderr}");
    assert!(stderr.contains("generated sky 256x128"), "{stderr}");
    let scene_path = dir.join("scene.toml");
    std::fs::write(
        &scene_path,
        format!("[environment]\nmap = \"sky.exr\"\n{BALL}"),
    )
    .unwrap();
    let s = scene::load(&scene_path).unwrap();
    let map = s.environment_map.unwrap().map;
    assert_eq!(*map, Builtin::Sky.generate(256));
    let hdr = dir.join("studio.hdr");
    let (ok, stderr) = shadeballs(&[
        "environment",
        "--name",
        "studio",
        "--out",
        hdr.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert_eq!(environment::load(&hdr).unwrap().0.width(), 1024);
    // A .png is a preview: every texel through the display transform.
    let png = dir.join("studio.png");
    let (ok, stderr) = shadeballs(&[
        "environment",
        "--name",
        "studio",
        "--out",
        png.to_str().unwrap(),
        "--width",
        "64",
    ]);
    assert!(ok, "{stderr}");
    assert!(stderr.contains("a preview"), "{stderr}");
    let preview = image::open(&png).unwrap().to_rgba8();
    let map = Builtin::Studio.generate(64);
    assert_eq!(preview.dimensions(), (64, 32));
    // The default (accurate) preset's display transform, as `render` shows the map.
    let preset = shadeballs::scene::Preset::default();
    let display = shadeballs::display::DisplayTransform {
        tone_map: preset.tone_map(),
        transfer: preset.transfer(),
    };
    for (t, p) in map.texels().iter().zip(preview.pixels()) {
        let c = glam::DVec3::new(f64::from(t[0]), f64::from(t[1]), f64::from(t[2]));
        assert_eq!(p.0, shadeballs::display::to_rgba8_pixel(c, 1.0, display));
    }
    let cases: [(&[&str], &str); 4] = [
        (
            &["environment", "--name", "forest", "--out", "x.exr"],
            "[possible values: studio, sky, white]",
        ),
        (
            &[
                "environment",
                "--name",
                "sky",
                "--out",
                "x.exr",
                "--width",
                "3",
            ],
            "even",
        ),
        (
            &[
                "environment",
                "--name",
                "sky",
                "--out",
                "x.exr",
                "--width",
                "16384",
            ],
            "2..=8192",
        ),
        (
            &["environment", "--name", "sky", "--out", "x.jpg"],
            "expected .exr, .hdr or .png",
        ),
    ];
    for (args, expected) in cases {
        let (ok, stderr) = shadeballs(args);
        assert!(!ok, "{args:?}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--ibl-method`, `--ibl-samples` and `--ibl-frames`: a bad value is one clear line from
/// the command line before any work.
#[test]
fn render_refuses_bad_ibl_flags_in_one_line() {
    let out = temp_dir("ibl-flags").join("x.png");
    let out = out.to_str().unwrap();
    for (flag, value, says) in [
        ("--ibl-method", "lobes", "split-sum"),
        ("--ibl-samples", "0", "1..=256"),
        ("--ibl-samples", "257", "1..=256"),
        ("--ibl-samples", "-1", "1..=256"),
        ("--ibl-frames", "0", "1..=4096"),
        ("--ibl-frames", "4097", "1..=4096"),
    ] {
        let (ok, stderr) = shadeballs(&["render", flag, value, "--out", out]);
        println!("{flag} {value}: {stderr}");
        assert!(!ok, "{flag} {value}");
        let first = stderr.lines().next().unwrap_or("");
        assert!(first.contains(flag) && first.contains(value), "{stderr}");
        assert!(stderr.contains(says), "{flag} {value}: {stderr}");
    }
}
