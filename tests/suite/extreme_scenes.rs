//! Extreme scenes rendered to `.exr` by the real binary on Vulkan (issue 6): zero and
//! very bright lights, a very bright environment and exposure, grazing views with lights at
//! and below every horizon, a camera inside a ball, roughness 0 and 1, F0 0 and 1, tiny and
//! huge balls. Every pixel must be finite and non-negative.

use crate::cli::{shadeballs, temp_dir};

/// (pixels, non-finite, negative, largest finite value) of an RGBA f32 `.exr`.
fn exr_stats(path: &std::path::Path) -> (usize, usize, usize, f32) {
    let img = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .into_rgba32f();
    let mut s = (img.width() as usize * img.height() as usize, 0, 0, 0.0f32);
    for (k, &v) in img.as_raw().iter().enumerate() {
        s.1 += !v.is_finite() as usize;
        s.2 += (v < 0.0) as usize;
        if v.is_finite() && k % 4 != 3 {
            s.3 = s.3.max(v);
        }
    }
    s
}

fn ball(position: [f64; 3], radius: f64, roughness: f64, material: &str, ms: bool) -> String {
    format!(
        "[[ball]]\nposition = {position:?}\nradius = {radius:e}\nroughness = {roughness:?}\n\
         multiple_scattering = {ms}\nmaterial = {material}\n"
    )
}

/// Balls at roughness 0, ROUGHNESS_MIN and 1 with F0 0 and 1, with and without the term,
/// dielectrics with black and white bases, seen from `camera` (TOML), under `lights`.
fn extreme_scene(header: &str, lights: &[([f64; 3], f64)], environment: f64) -> String {
    let mut s = format!(
        "{header}\n[environment]\nradiance = [{environment:e}, {environment:e}, {environment:e}]\n"
    );
    for (d, radiance) in lights {
        s += &format!(
            "[[light]]\ndirection = {d:?}\nradiance = [{radiance:e}, {radiance:e}, {radiance:e}]\n"
        );
    }
    let materials = [
        "{ kind = \"metal\", f0 = [1, 1, 1] }",
        "{ kind = \"metal\", f0 = [0, 0, 0] }",
        "{ kind = \"dielectric\", albedo = [1, 1, 1], f0 = [0, 0, 0] }",
        "{ kind = \"dielectric\", albedo = [0, 0, 0] }",
    ];
    for (i, roughness) in [0.0, 0.02, 0.5, 1.0].into_iter().enumerate() {
        for (j, m) in materials.iter().enumerate() {
            let p = [i as f64 * 3.0 - 4.5, j as f64 * 3.0 - 4.5, 0.0];
            s += &ball(p, 1.4, roughness, m, (i + j) % 2 == 0);
        }
    }
    // A tiny ball and a huge one far behind.
    s += &ball([0.0, 0.0, 5.0], 1e-4, 0.0, materials[0], true);
    s += &ball([0.0, 0.0, -1e5], 9e4, 1.0, materials[0], true);
    s
}

/// Lights along every axis, so that some surface points see each one exactly at the horizon
/// and others below it.
fn axis_lights(radiance: f64) -> Vec<([f64; 3], f64)> {
    [
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ]
    .into_iter()
    .map(|d| (d, radiance))
    .collect()
}

/// The brightest light and environment the tests use (the scene file's limit).
const BRIGHT: f64 = shadeballs::scene::MAX_MAGNITUDE;

#[test]
fn extreme_scenes_render_to_exr_with_every_pixel_finite_and_non_negative() {
    let front = "[camera]\nposition = [0, 0, 20]\ntarget = [0, 0, 0]\nvfov_deg = 60";
    // Grazing: the camera nearly in the plane of the balls' centres, looking along it.
    let grazing = "[camera]\nposition = [0, -30, 0.05]\ntarget = [0, 0, 0]\nvfov_deg = 30";
    let inside = "[camera]\nposition = [-4.5, -4.5, 0.5]\ntarget = [0, 0, 0]\nvfov_deg = 170";
    let scenes = [
        ("zero light", extreme_scene(front, &axis_lights(0.0), 0.0)),
        (
            "bright lights",
            extreme_scene(front, &axis_lights(BRIGHT), 0.0),
        ),
        ("bright environment", extreme_scene(front, &[], BRIGHT)),
        (
            "grazing view",
            extreme_scene(grazing, &axis_lights(BRIGHT), 1.0),
        ),
        (
            "camera inside a ball",
            extreme_scene(inside, &axis_lights(1.0), 1.0),
        ),
        (
            "exposure and games202",
            extreme_scene(
                &format!("preset = \"games202\"\nexposure = {BRIGHT:e}\n{front}"),
                &axis_lights(BRIGHT),
                BRIGHT,
            ),
        ),
    ];
    let dir = temp_dir("extreme");
    let mut pixels = 0;
    for (name, text) in &scenes {
        let scene_path = dir.join(format!("{}.toml", name.replace(' ', "-")));
        std::fs::write(&scene_path, text).unwrap();
        for geometry in ["schlick", "smith", "smith-correlated"] {
            let out = dir.join(format!("{}-{geometry}.exr", name.replace(' ', "-")));
            let (ok, stderr) = shadeballs(&[
                "render",
                "--backend",
                "vulkan",
                "--scene",
                scene_path.to_str().unwrap(),
                "--geometry",
                geometry,
                "--width",
                "192",
                "--height",
                "108",
                "--out",
                out.to_str().unwrap(),
            ]);
            assert!(ok, "{name}, {geometry}: {stderr}");
            let (n, non_finite, negative, max) = exr_stats(&out);
            println!("extreme scene '{name}', {geometry} G, Vulkan: {n} pixels, {non_finite} non-finite, {negative} negative channels, max {max:.3e}");
            assert!(
                non_finite == 0 && negative == 0,
                "{name}, {geometry}: see above"
            );
            pixels += n;
        }
        // The PNG path tone-maps with the scene's exposure: no NaN may reach it either.
        let png = dir.join("x.png");
        let (ok, stderr) = shadeballs(&[
            "render",
            "--backend",
            "vulkan",
            "--scene",
            scene_path.to_str().unwrap(),
            "--width",
            "64",
            "--height",
            "36",
            "--out",
            png.to_str().unwrap(),
        ]);
        assert!(ok, "{name} png: {stderr}");
    }
    println!("extreme scenes: {pixels} pixels rendered to .exr, all finite and non-negative");
    std::fs::remove_dir_all(&dir).unwrap();
}
