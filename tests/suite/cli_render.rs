//! `shadeballs render` and `shadeballs probe` as a user runs them: the real binary, its
//! files, exit codes and messages.
use std::path::PathBuf;

use crate::cli::{shadeballs, temp_dir};

fn scene_file(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("assets/scenes")
        .join(name)
        .to_string_lossy()
        .into_owned()
}

#[test]
fn render_writes_png_and_exr_on_every_backend() {
    let dir = temp_dir("render");
    for (backend, ext) in [
        ("vulkan", "png"),
        ("vulkan", "exr"),
        ("gl", "png"),
        ("cpu", "exr"),
    ] {
        let out = dir.join(format!("{backend}.{ext}"));
        let (ok, stderr) = shadeballs(&[
            "render",
            "--backend",
            backend,
            "--width",
            "64",
            "--height",
            "36",
            "--out",
            out.to_str().unwrap(),
            "--scene",
            &scene_file("furnace.toml"),
            "--preset",
            "games202",
        ]);
        assert!(ok, "{backend} {ext}: {stderr}");
        assert!(
            stderr.contains("rendered 64x36 (games202 preset"),
            "{stderr}"
        );
        let image = image::open(&out).unwrap_or_else(|e| panic!("{}: {e}", out.display()));
        assert_eq!((image.width(), image.height()), (64, 36));
    }
}

#[test]
fn render_rejects_bad_input_with_a_clear_message() {
    let dir = temp_dir("render-bad");
    let png = dir.join("x.png");
    let png = png.to_str().unwrap();
    for (args, expect) in [
        (vec!["--width", "0"], "in 1..=16384"),
        (vec!["--height", "tall"], "not a whole number"),
        (vec!["--width", "100000"], "image size"),
        (vec!["--backend", "metal"], "backend"),
        (vec!["--scene", "/nonexistent.toml"], "/nonexistent.toml"),
    ] {
        let mut all = vec!["render", "--out", png];
        all.extend(args.iter().copied());
        let (ok, stderr) = shadeballs(&all);
        assert!(!ok, "{args:?} should fail");
        assert!(stderr.contains(expect), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
    let (ok, stderr) = shadeballs(&["render", "--out", dir.join("x.jpg").to_str().unwrap()]);
    assert!(!ok && stderr.contains(".png or .exr"), "{stderr}");
}

#[test]
fn probe_writes_the_grid_as_csv() {
    let out = temp_dir("probe").join("probe.csv");
    let (ok, stderr) = shadeballs(&[
        "probe",
        "--out",
        out.to_str().unwrap(),
        "--grid",
        "9",
        "--geometry",
        "smith",
    ]);
    assert!(ok, "{stderr}");
    let csv = std::fs::read_to_string(&out).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("roughness,mu,E,E_avg"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 81);
    assert!(rows
        .iter()
        .all(|r| r.len() == 4 && r[2..].iter().all(|v| (0.0..=1.0).contains(v))));
    let (ok, stderr) = shadeballs(&["probe", "--out", out.to_str().unwrap(), "--grid", "1"]);
    assert!(!ok && stderr.contains("not in 2..=1024"), "{stderr}");
    // Along the default scene's own rows: 9 mu a row, its five roughness values.
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/reference.toml");
    let args = [
        "probe",
        "--out",
        out.to_str().unwrap(),
        "--grid",
        "9",
        "--scene",
        scene,
    ];
    let (ok, stderr) = shadeballs(&args);
    assert!(ok && stderr.contains("9x5 rows"), "{stderr}");
    let csv = std::fs::read_to_string(&out).unwrap();
    assert_eq!(csv.lines().count(), 1 + 45);
    assert!(csv.lines().nth(1).unwrap().starts_with("0.15,0,"), "{csv}");
}
