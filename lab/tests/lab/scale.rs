//! Scale (issue 18): the planned renderer settles occlusion with a depth test (one
//! intersection a fragment), the CPU renderer shades each pixel against the balls whose
//! bounds cover it, and scenes hold up to MAX_BALLS = 4,096 balls. Overlapping, touching
//! and coincident balls must come out as the CPU's nearest hit (ties: lowest index).
use glam::DVec3;
use shadeballs::cpu;
use shadeballs::gpu::Renderer;
use shadeballs::lut::TableSet;
use shadeballs::scene::{self, Ball, Material, Model, Scene, MAX_BALLS};
use shadeballs_lab::bench::scale::chart;

use crate::pixels::both;
use crate::pixels::{assert_close, compare, renderer, vulkan};

/// Balls that interpenetrate (centres closer than the sum of radii, one deep inside
/// another's silhouette), touch (centres exactly the sum of radii apart, side by side and
/// one behind the other), and coincide (same centre and radius, different materials: the
/// lower index must win everywhere).
fn overlapping() -> Scene {
    let mut scene = Scene::reference();
    let metal = |rgb: [f64; 3]| Material::metal_srgb(rgb);
    let dielectric = Material::dielectric(DVec3::new(0.2, 0.5, 0.7), 1.5);
    let ball = |c: [f64; 3], r: f64, roughness: f64, material: Material, ms: bool| Ball {
        center: DVec3::from_array(c),
        radius: r,
        roughness,
        material,
        model: if ms { Model::KullaConty } else { Model::None },
        label: None,
    };
    scene.balls = vec![
        // Interpenetrating pair and a small ball half sunk into the big one.
        ball([-150.0, 40.0, 0.0], 60.0, 0.3, metal([0.9, 0.6, 0.2]), true),
        ball(
            [-90.0, 40.0, 30.0],
            45.0,
            0.7,
            metal([0.6, 0.6, 0.9]),
            false,
        ),
        ball([-150.0, 40.0, 60.0], 20.0, 0.1, dielectric, true),
        // Touching side by side (distance 40 + 30 = 70) and front to back.
        ball([20.0, 60.0, 0.0], 40.0, 0.5, metal([0.9, 0.9, 0.9]), true),
        ball([90.0, 60.0, 0.0], 30.0, 0.2, dielectric, false),
        ball([20.0, 60.0, 70.0], 30.0, 0.9, metal([0.3, 0.9, 0.3]), true),
        // Coincident: three identical spheres, the first must show.
        ball(
            [150.0, -70.0, 0.0],
            45.0,
            0.25,
            metal([0.95, 0.3, 0.3]),
            false,
        ),
        ball(
            [150.0, -70.0, 0.0],
            45.0,
            0.85,
            metal([0.3, 0.3, 0.95]),
            true,
        ),
        ball([150.0, -70.0, 0.0], 45.0, 0.55, dielectric, true),
        // A chain of interpenetrating balls receding from the camera.
        ball([-40.0, -80.0, 0.0], 35.0, 0.4, metal([0.8, 0.5, 0.3]), true),
        ball([-10.0, -80.0, -40.0], 35.0, 0.6, dielectric, false),
        ball(
            [20.0, -80.0, -80.0],
            35.0,
            0.8,
            metal([0.5, 0.8, 0.3]),
            true,
        ),
    ];
    scene.environment = DVec3::new(0.05, 0.06, 0.08);
    scene
}

fn overlapping_matches_cpu(r: &mut Renderer, backend: &str) {
    let scene = overlapping();
    for (w, h) in [(1280, 720), (333, 199)] {
        let (gpu, cpu) = both(r, &scene, w, h);
        assert_close(
            &compare(&gpu, &cpu, w),
            &format!("{backend} vs CPU, overlapping balls, {w}x{h}"),
        );
    }
}

#[test]
fn overlapping_balls_match_cpu_vulkan() {
    overlapping_matches_cpu(&mut vulkan(), "Vulkan");
}

#[test]
fn overlapping_balls_match_cpu_gl() {
    overlapping_matches_cpu(&mut renderer(wgpu::Backends::GL), "GL");
}

/// The float target (EXR's) gets the same occlusion: linear radiance against the CPU's.
#[test]
fn overlapping_balls_hdr_match_cpu() {
    let mut r = vulkan();
    let scene = overlapping();
    let (w, h) = (320, 180);
    let hdr = r.render_hdr(&scene, w, h).unwrap();
    let radiance = match r.bound_tables() {
        rows @ TableSet::Rows(_) => cpu::render_radiance(
            &scene,
            &shadeballs::prepared::Prepared::new(&scene, &rows),
            w,
            h,
        ),
        _ => {
            let tables = TableSet::full(r.tables_for(scene.effective_geometry()));
            cpu::render_radiance(
                &scene,
                &shadeballs::prepared::Prepared::new(&scene, &tables),
                w,
                h,
            )
        }
    };
    let cpu = cpu::to_rgba_f32(&radiance);
    let close = hdr
        .rgba
        .iter()
        .zip(&cpu)
        .filter(|(a, b)| (*a - *b).abs() <= 1e-3 * b.abs().max(1.0))
        .count();
    println!("HDR overlapping: {close} of {} channels", cpu.len());
    assert!(close as f64 >= 0.999 * cpu.len() as f64);
}

/// Coincident balls: the lowest index shows, on the GPU as on the CPU, whichever pipeline
/// (shader variant) each is drawn by.
#[test]
fn coincident_balls_show_the_lowest_index() {
    let mut r = vulkan();
    let mut scene = overlapping();
    scene
        .balls
        .retain(|b| b.center == DVec3::new(150.0, -70.0, 0.0));
    let (w, h) = (320, 180);
    let (gpu, cpu) = both(&mut r, &scene, w, h);
    let d = compare(&gpu, &cpu, w);
    assert_close(&d, "coincident balls");
    // And the image is the first ball's alone.
    let first = Scene {
        balls: vec![scene.balls[0]],
        ..scene.clone()
    };
    let alone = r.render_ldr(&first, w, h).unwrap().rgba;
    assert_eq!(gpu, alone, "a later coincident ball showed through");
}

/// The renderer's depth target follows the colour target's size: sizes in turn, each equal
/// to a fresh renderer's image.
#[test]
fn depth_target_follows_the_target_size() {
    let _turn = crate::quick_bench_turn();
    let mut r = vulkan();
    let scene = overlapping();
    for (w, h) in [(320, 180), (640, 360), (200, 300), (320, 180)] {
        let image = r.render_ldr(&scene, w, h).unwrap().rgba;
        let fresh = vulkan().render_ldr(&scene, w, h).unwrap().rgba;
        assert_eq!(image, fresh, "{w}x{h}");
    }
}

/// The CPU renderer's bins change nothing: bit-identical to a loop over every ball.
#[test]
fn cpu_bins_equal_the_loop_over_every_ball() {
    let _turn = crate::quick_bench_turn();
    use shadeballs::lut::{bake, BakeConfig};
    for scene in [overlapping(), chart(16, 2, None), Scene::reference()] {
        // The loop below is one centre ray per pixel: the renderer without antialiasing
        // (`antialias.rs` holds the antialiased edges).
        let scene = Scene {
            antialias: false,
            ..scene
        };
        let (w, h) = (301, 173);
        let tables = bake(&BakeConfig {
            geometry: scene.effective_geometry(),
            ..BakeConfig::default()
        });
        let tables = TableSet::from(tables);
        let binned = cpu::render_radiance(
            &scene,
            &shadeballs::prepared::Prepared::new(&scene, &tables),
            w,
            h,
        );
        let basis = scene.camera.basis(w, h);
        let read = &tables;
        let mut k = 0;
        for py in 0..h {
            for px in 0..w {
                let d = basis.ray(px, py, w, h);
                let o = basis.origin;
                let mut best: Option<(f64, usize)> = None;
                for (i, b) in scene.balls.iter().enumerate() {
                    let t = cpu::intersect_sphere(o, d, b.center, b.radius);
                    if t > 0.0 && best.is_none_or(|(bt, _)| t < bt) {
                        best = Some((t, i));
                    }
                }
                let expected = match best {
                    None => scene.environment,
                    Some((t, i)) => {
                        let b = &scene.balls[i];
                        let n = cpu::surface_normal(o + t * d - b.center, d);
                        cpu::shade(
                            &scene,
                            b,
                            n,
                            -d,
                            read,
                            scene.preset.f_avg_form(),
                            scene.effective_geometry(),
                        )
                    }
                };
                assert_eq!(binned[k], expected, "pixel ({px}, {py})");
                k += 1;
            }
        }
    }
}

/// A 64 x 64 chart (MAX_BALLS balls) renders and matches the CPU.
#[test]
fn a_chart_of_max_balls_matches_cpu() {
    let _turn = crate::quick_bench_turn();
    const { assert!(MAX_BALLS >= 4096) };
    let scene = chart(64, 1, None);
    assert_eq!(scene.balls.len(), 4096);
    let mut r = vulkan();
    let (w, h) = (1280, 720);
    let (gpu, cpu) = both(&mut r, &scene, w, h);
    assert_close(&compare(&gpu, &cpu, w), "Vulkan vs CPU, 64 x 64 chart");
}

/// Scene files take MAX_BALLS balls and refuse one more, naming the limit.
#[test]
fn scene_files_hold_max_balls() {
    let one = "[[ball]]\ngrid = [0, 0]\nradius = 1\nroughness = 0.5\nmaterial = { kind = \"metal\", f0 = [1, 1, 1] }\n";
    let scene = scene::parse(&one.repeat(MAX_BALLS), std::path::Path::new("chart.toml"))
        .expect("MAX_BALLS balls parse");
    assert_eq!(scene.balls.len(), MAX_BALLS);
    let e = scene::parse(
        &one.repeat(MAX_BALLS + 1),
        std::path::Path::new("chart.toml"),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains(&format!("more than {MAX_BALLS} balls")), "{e}");
}

/// The block model of `bench --only scale` (4 x 4 blocks shaded per primitive): a large
/// ball's quad shades about its bounds' area (4 / pi of its disc, plus the blocks its edges
/// and diagonal cut), its floor about its disc; both grow as the balls shrink, and the
/// quads never shade less than the floor.
#[test]
fn block_model_counts_what_a_block_rasteriser_shades() {
    use shadeballs_lab::bench::scale::{
        block_shades, covered_pixels, GPU_QUAD_PX, LAVAPIPE_BLOCK_PX,
    };
    let (w, h) = (1280, 720);
    // Shades per covered pixel, on blocks of `block` pixels a side.
    let per_covered = |scene: &Scene, block| {
        let covered = covered_pixels(scene, w, h) as f64;
        let (quad, floor) = block_shades(scene, w, h, block);
        (quad / covered, floor / covered)
    };
    let (quad, floor) = per_covered(&chart(1, 1, None), LAVAPIPE_BLOCK_PX);
    assert!(
        (4.0 / std::f64::consts::PI..1.45).contains(&quad),
        "one ball: quads {quad}"
    );
    assert!((1.0..1.06).contains(&floor), "one ball: floor {floor}");
    let mut last = (0.0, 0.0);
    for n in [1, 4, 16, 64] {
        let scene = chart(n, 1, None);
        let (quad, floor) = per_covered(&scene, LAVAPIPE_BLOCK_PX);
        // Smaller blocks shade less: 2 x 2 quads never more than 4 x 4 blocks.
        let (small, _) = per_covered(&scene, GPU_QUAD_PX);
        assert!(small <= quad, "{n} x {n}: 2 x 2 {small} over 4 x 4 {quad}");
        assert!(
            quad >= floor,
            "{n} x {n}: quads {quad} under the floor {floor}"
        );
        assert!(
            quad > last.0 && floor > last.1,
            "{n} x {n}: {quad}, {floor} after {last:?}"
        );
        last = (quad, floor);
    }
}
