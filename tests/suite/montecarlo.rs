//! The Monte Carlo backend (`cpu::montecarlo`, `render --backend montecarlo`): the white
//! furnace under a uniform map, lights against the CPU reference renderer, a uniform
//! environment two ways, determinism, the noise's fall with the sample count, and an
//! unbiased estimate against a dense quadrature of one pixel's integral.

use crate::cli::{shadeballs, temp_dir};

#[test]
fn cli_renders_with_the_montecarlo_backend() {
    let dir = temp_dir("montecarlo");
    let scene =
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/furnace.toml");
    // `montecarlo` runs on lavapipe here, `montecarlo-cpu` on the CPU.
    for (ext, backend, device) in [
        ("png", "montecarlo-cpu", "CPU Monte Carlo reference"),
        ("exr", "montecarlo-cpu", "CPU Monte Carlo reference"),
        ("png", "montecarlo", "GPU Monte Carlo"),
        ("exr", "montecarlo", "GPU Monte Carlo"),
    ] {
        let out = dir.join(format!("x.{ext}"));
        let (ok, stderr) = shadeballs(&[
            "render",
            "--backend",
            backend,
            "--spp",
            "4",
            "--seed",
            "3",
            "--width",
            "64",
            "--height",
            "36",
            "--scene",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(ok, "{stderr}");
        assert!(stderr.contains("montecarlo: 4 spp, seed 3"), "{stderr}");
        assert!(stderr.contains(device), "{stderr}");
        let image = image::open(&out).unwrap();
        assert_eq!((image.width(), image.height()), (64, 36));
    }
    let out = dir.join("bad.png");
    let (ok, stderr) = shadeballs(&[
        "render",
        "--backend",
        "montecarlo",
        "--spp",
        "0",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(stderr.contains("--spp"), "{stderr}");
}
