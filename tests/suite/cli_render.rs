//! `shadeballs render` and `shadeballs probe` as a user runs them: the real binary, its
//! files, exit codes and messages.
use std::path::PathBuf;

use crate::cli::{shadeballs, temp_dir};

/// The path of the built-in scene file `name` (`assets/scenes/NAME`).
pub fn scene_file(name: &str) -> String {
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
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/homework.toml");
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

/// The RGBA f32 values of an `.exr`.
fn exr_values(path: &std::path::Path) -> Vec<f32> {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .into_rgba32f()
        .into_raw()
}

/// `shadeballs render --backend BACKEND` of `scene` (the default scene when `None`) to
/// `DIR/NAME-BACKEND.exr`, 320x180; its values.
fn render_exr(dir: &std::path::Path, name: &str, backend: &str, scene: Option<&str>) -> Vec<f32> {
    let out = dir.join(format!("{name}-{backend}.exr"));
    let mut args = vec![
        "render",
        "--backend",
        backend,
        "--width",
        "320",
        "--height",
        "180",
        "--out",
        out.to_str().unwrap(),
    ];
    if let Some(scene) = scene {
        args.extend(["--scene", scene]);
    }
    let (ok, stderr) = shadeballs(&args);
    assert!(ok, "{name} on {backend}: {stderr}");
    exr_values(&out)
}

/// The differences between `a` and `b` relative to `max(|b|, 1e-3)`, largest first (GL and
/// Vulkan differ by a factor per pixel, up to 1.2e-3 where radiance is near 3e-4, a light
/// near a horizon: 4e-7 absolute).
fn relative_diffs(a: &[f32], b: &[f32]) -> Vec<f32> {
    assert_eq!(a.len(), b.len());
    let mut r: Vec<f32> = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / y.abs().max(1e-3))
        .collect();
    r.sort_by(|p, q| q.total_cmp(p));
    r
}

/// GL's `.exr` against Vulkan's: both f32 (GL through an `Rgba32Uint` target holding the
/// bits, `render_hdr`) from the same WGSL, but compiled apart (GLSL and SPIR-V), so a few
/// pixels differ by more than one rounding. Measured, 320x180: the default scene at most
/// 1.3e-4 relative, the 1e6 light 2.7e-4; 99.9 % of channels within 2.8e-5 and 6e-6. f16
/// storage rounds by up to 4.9e-4, most channels well above 1e-5 (GL differed by 2.4 %).
fn assert_gl_matches_vulkan(gl: &[f32], vulkan: &[f32], what: &str) {
    let r = relative_diffs(gl, vulkan);
    let (max, p999) = (r[0], r[r.len() / 1000]);
    println!("{what}: GL vs Vulkan at most {max:.2e} relative, 99.9 % within {p999:.2e}");
    assert!(
        max <= 1e-3 && p999 <= 3e-5,
        "{what}: GL vs Vulkan {max:e}, {p999:e}"
    );
}

/// GPU `.exr` against the CPU's: the bound of `render.rs` `hdr_output_is_linear_radiance`
/// (1e-3 relative to the value or 1, for 99.9 % of channels).
fn assert_matches_cpu(gpu: &[f32], cpu: &[f32], what: &str) {
    let close = gpu
        .iter()
        .zip(cpu)
        .filter(|(a, b)| (*a - *b).abs() <= 1e-3 * b.abs().max(1.0))
        .count();
    println!(
        "{what}: {close} of {} channels within 1e-3 of the CPU's",
        cpu.len()
    );
    assert!(close as f64 >= 0.999 * cpu.len() as f64, "{what}");
}

#[test]
fn exr_is_f32_and_the_same_on_gl_vulkan_and_cpu() {
    let dir = temp_dir("render-exr");
    let vulkan = render_exr(&dir, "default", "vulkan", None);
    let gl = render_exr(&dir, "default", "gl", None);
    let cpu = render_exr(&dir, "default", "cpu", None);
    assert_gl_matches_vulkan(&gl, &vulkan, "default scene .exr");
    // f16 keeps 11 bits: a value that is not an f16 shows GL is f32.
    assert!(gl.iter().any(|&v| half::f16::from_f32(v).to_f32() != v));
    assert_matches_cpu(&vulkan, &cpu, "Vulkan .exr");
    assert_matches_cpu(&gl, &cpu, "GL .exr");
}

/// A light of radiance 1e6: radiance far above f16's largest value (65504), which GL's
/// `.exr` clipped to when it stored f16.
#[test]
fn exr_keeps_radiance_above_the_f16_range_on_gl() {
    let dir = temp_dir("render-exr-bright");
    // Without antialiasing: the f32 path is what this test holds; the antialiased edges
    // of the same scene are `gl_antialiased_edges_match_vulkan`'s.
    let scene = std::fs::read_to_string(scene_file("one_ball.toml"))
        .unwrap()
        .replace("radiance = [3, 3, 3]", "radiance = [1e6, 1e6, 1e6]");
    assert!(scene.contains("1e6"));
    let scene = format!("antialias = false\n{scene}");
    let path = dir.join("bright.toml");
    std::fs::write(&path, scene).unwrap();
    let path = path.to_str().unwrap();
    let gl = render_exr(&dir, "bright", "gl", Some(path));
    let vulkan = render_exr(&dir, "bright", "vulkan", Some(path));
    let cpu = render_exr(&dir, "bright", "cpu", Some(path));
    let max = gl.iter().copied().fold(0.0, f32::max);
    let above = gl.iter().filter(|&&v| v > 65504.0).count();
    println!("bright scene: GL .exr max {max:e}, {above} channels above 65504");
    assert!(gl.iter().all(|v| v.is_finite()));
    assert!(
        max > 1e5 && above > 1000,
        "GL .exr max {max}, {above} above 65504"
    );
    assert_gl_matches_vulkan(&gl, &vulkan, "bright scene .exr");
    assert_matches_cpu(&gl, &cpu, "GL .exr, bright scene");
}

/// The bright scene with antialiased edges (the default): GL's `.exr` against Vulkan's.
/// An edge pixel's coverage is a product of small differences where the ball covers a
/// sliver of it, so the two compiles' last-bit differences grow relatively there: measured
/// at most 3.95e-3 relative (one edge pixel; 99.9 % of channels within 2.5e-5, as without
/// antialiasing). Bound: 1e-2 at most, 3e-5 for 99.9 % (assert_gl_matches_vulkan's).
#[test]
fn gl_antialiased_edges_match_vulkan() {
    let dir = temp_dir("render-exr-bright-aa");
    let scene = std::fs::read_to_string(scene_file("one_ball.toml"))
        .unwrap()
        .replace("radiance = [3, 3, 3]", "radiance = [1e6, 1e6, 1e6]");
    let path = dir.join("bright.toml");
    std::fs::write(&path, scene).unwrap();
    let path = path.to_str().unwrap();
    let gl = render_exr(&dir, "bright", "gl", Some(path));
    let vulkan = render_exr(&dir, "bright", "vulkan", Some(path));
    let r = relative_diffs(&gl, &vulkan);
    let (max, p999) = (r[0], r[r.len() / 1000]);
    println!("antialiased bright scene: GL vs Vulkan at most {max:.2e} relative, 99.9 % within {p999:.2e}");
    assert!(max <= 1e-2 && p999 <= 3e-5, "{max:e}, {p999:e}");
}
