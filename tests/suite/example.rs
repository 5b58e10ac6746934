//! `examples/bake_at_startup.rs`, run as a user runs it: a wgpu program of its own that
//! bakes, uploads through the facade and shades one ball with the crate's WGSL library,
//! held against `shadeballs render` of the same scene file.
use std::path::PathBuf;
use std::process::Command;

use crate::cli::{shadeballs, temp_dir};
use crate::pixels::compare;

/// The example's binary beside this test binary (`cargo test` builds the examples).
fn example_exe() -> PathBuf {
    let exe = std::env::current_exe().expect("test binary path");
    let dir = exe
        .parent()
        .and_then(|d| d.parent())
        .expect("target folder");
    let path = dir.join("examples").join("bake_at_startup");
    assert!(
        path.exists(),
        "{} is missing: build it with `cargo build --release --example bake_at_startup` \
         (`cargo test --release` builds it)",
        path.display()
    );
    path
}

fn read_rgba(path: &std::path::Path) -> (Vec<u8>, u32, u32) {
    let img = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8();
    let (w, h) = img.dimensions();
    (img.into_raw(), w, h)
}

#[test]
fn the_example_shades_the_ball_as_shadeballs_renders_it() {
    let dir = temp_dir("example");
    let scene = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/one_ball.toml");
    let ours = dir.join("example.png");
    let out = Command::new(example_exe())
        .args(["--out", ours.to_str().unwrap(), "--scene"])
        .arg(&scene)
        .output()
        .expect("run the example");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "example failed: {stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // It reports its startup cost: bake and upload.
    assert!(
        stdout.contains("baked the tables") && stdout.contains("uploaded in"),
        "{stdout}"
    );
    println!("{}", stdout.trim());

    let reference = dir.join("render.png");
    let (ok, stderr) = shadeballs(&[
        "render",
        "--backend",
        "vulkan",
        "--scene",
        scene.to_str().unwrap(),
        "--width",
        "256",
        "--height",
        "256",
        "--out",
        reference.to_str().unwrap(),
        // The example's own shader takes one ray per pixel: compare without antialiasing.
        "--aa",
        "off",
    ]);
    assert!(ok, "{stderr}");
    let (a, w, h) = read_rgba(&ours);
    let (b, w2, h2) = read_rgba(&reference);
    assert_eq!((w, h), (w2, h2));
    let d = compare(&a, &b, w);
    let report = d.report("example against shadeballs render");
    println!("{report}");
    // The bound: every pixel within 1/255. The two differ in how they read E (the
    // example bilinearly between the 2-D table's rows, the renderer one exact row per
    // roughness) and in f_add (f32 in WGSL against f64 per ball): both far below 1/255.
    assert!(d.max <= 1, "{report}");
    // The ball is there: a picture of black would pass the bound trivially.
    let lit = a.chunks_exact(4).filter(|p| p[0] > 40).count();
    assert!(lit > 5_000, "only {lit} lit pixels");
}
