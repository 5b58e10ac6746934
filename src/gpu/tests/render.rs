//! GPU against the CPU reference renderer (docs/design/testing.md), and the white furnace.

use glam::DVec3;

use crate::cpu;

use crate::gpu::Renderer;

use crate::lut::TableSet;

use crate::scene::{Preset, Scene};

use crate::pixels::{assert_close, both, compare, mixed_scene, renderer, vulkan};

const W: u32 = 1280;

const H: u32 = 720;

fn gpu_matches_cpu(r: &mut Renderer, backend: &str) {
    for preset in Preset::ALL {
        let scene = Scene {
            preset,
            ..Scene::reference()
        };
        let (gpu, cpu) = both(r, &scene, W, H);
        assert_close(
            &compare(&gpu, &cpu, W),
            &format!("{backend} vs CPU, default scene, {preset}"),
        );
    }
    let (gpu, cpu) = both(r, &Scene::furnace(), W, H);
    assert_close(
        &compare(&gpu, &cpu, W),
        &format!("{backend} vs CPU, furnace"),
    );
}

/// Every G variant, a dielectric, two lights and an environment at once.
#[test]
fn every_geometry_and_material_matches_cpu() {
    use crate::brdf::Geometry;
    let mut r = vulkan();
    let mut scene = mixed_scene();
    scene.environment = DVec3::new(0.1, 0.12, 0.15);
    for geometry in Geometry::ALL {
        scene.geometry = geometry;
        let (w, h) = (640, 360);
        let (gpu, cpu) = both(&mut r, &scene, w, h);
        assert_close(
            &compare(&gpu, &cpu, w),
            &format!("Vulkan vs CPU, mixed scene, {geometry} G"),
        );
    }
}

#[test]
fn vulkan_matches_cpu_reference() {
    gpu_matches_cpu(&mut vulkan(), "Vulkan");
}

#[test]
fn gl_matches_cpu_reference() {
    gpu_matches_cpu(&mut renderer(wgpu::Backends::GL), "GL");
}

#[test]
fn hdr_output_is_linear_radiance() {
    let mut r = vulkan();
    let scene = Scene::reference();
    let (w, h) = (160, 90);
    let hdr = r.render_hdr(&scene, w, h).unwrap();
    let tables = TableSet::full(r.tables_for(scene.effective_geometry()));
    let cpu = cpu::to_rgba_f32(&cpu::render_radiance(
        &scene,
        &crate::prepared::Prepared::new(&scene, &tables),
        w,
        h,
    ));
    let close = hdr
        .rgba
        .iter()
        .zip(&cpu)
        .filter(|(a, b)| (*a - *b).abs() <= 1e-3 * b.abs().max(1.0))
        .count();
    println!(
        "HDR: {close} of {} channels within 1e-3 relative",
        cpu.len()
    );
    assert!(close as f64 >= 0.999 * cpu.len() as f64);
}

/// GL renders to no 32-bit float format: `render_hdr` draws the f32 bits into `Rgba32Uint`
/// (`fs_ball_bits`) and gets Vulkan's f32 values (`cli_render.rs` holds the `.exr` of both
/// against the CPU's), the clear's bits included: the furnace's background is the
/// environment (here with 1e5 in green, above f16's range). Measured, 160x90, relative to
/// max(|Vulkan's|, 1e-3): the default scene at most 3.2e-4 (GLSL and SPIR-V compile the
/// WGSL apart), the furnace 8.6e-6; with f16 storage the furnace differed by 0.35.
#[test]
fn gl_hdr_is_f32() {
    let (w, h) = (160, 90);
    let mut gl = renderer(wgpu::Backends::GL);
    let mut vk = vulkan();
    let mut environment = Scene::furnace();
    environment.environment = DVec3::new(0.3, 1e5, 7.0);
    for scene in [Scene::reference(), environment] {
        let a = gl.render_hdr(&scene, w, h).unwrap().rgba;
        let b = vk.render_hdr(&scene, w, h).unwrap().rgba;
        let max = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (x - y).abs() / y.abs().max(1e-3))
            .fold(0.0, f32::max);
        println!("GL vs Vulkan HDR: at most {max:.2e} relative");
        assert!(max <= 1e-3, "{max:e}");
        // The corner pixel is background (the clear): exact.
        assert_eq!(a[..4], b[..4]);
        assert_eq!(a[1], scene.environment.y as f32);
    }
}

#[test]
fn no_adapter_error_names_the_package() {
    let e = crate::Error::NoAdapter {
        backends: "VULKAN".into(),
        message: "none".into(),
    };
    assert!(e.to_string().contains("mesa-vulkan-drivers"), "{e}");
}

#[test]
fn bad_sizes_are_errors() {
    let mut r = vulkan();
    for (w, h) in [(0, 10), (10, 0), (100_000, 10)] {
        let e = r
            .render_ldr(&Scene::reference(), w, h)
            .err()
            .expect("size should be rejected");
        assert!(e.to_string().contains("image size"), "{e}");
    }
}

/// Pixels whose ray hits ball `k` and whose 4 neighbours hit it too (no silhouette).
fn interior(scene: &Scene, k: usize, w: u32, h: u32) -> Vec<usize> {
    let basis = scene.camera.basis(w, h);
    let hit = |x: u32, y: u32| -> Option<usize> {
        let d = basis.ray(x, y, w, h);
        let mut best: Option<(f64, usize)> = None;
        for (i, b) in scene.balls.iter().enumerate() {
            let t = cpu::intersect_sphere(basis.origin, d, b.center, b.radius);
            if t > 0.0 && best.is_none_or(|(bt, _)| t < bt) {
                best = Some((t, i));
            }
        }
        best.map(|(_, i)| i)
    };
    let mut out = Vec::new();
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            if [(x, y), (x - 1, y), (x + 1, y), (x, y - 1), (x, y + 1)]
                .iter()
                .all(|&(a, b)| hit(a, b) == Some(k))
            {
                out.push((y * w + x) as usize);
            }
        }
    }
    out
}

#[test]
fn furnace_balls_vanish_with_the_term_and_darken_without() {
    let (w, h) = (640, 360);
    let scene = Scene::furnace();
    let image = &vulkan().render_ldr(&scene, w, h).unwrap().rgba;
    let bg = crate::display::to_unorm8(crate::display::tone_map(1.0, scene.exposure));
    assert_eq!(&image[..3], &[bg, bg, bg], "corner pixel is background");
    for (k, ball) in scene.balls.iter().enumerate() {
        let px = interior(&scene, k, w, h);
        assert!(
            px.len() > 500,
            "ball {k} covers {} interior pixels",
            px.len()
        );
        let worst = px
            .iter()
            .flat_map(|&p| (0..3).map(move |c| image[4 * p + c].abs_diff(bg)))
            .max()
            .unwrap();
        let mean = px.iter().map(|&p| image[4 * p] as f64).sum::<f64>() / px.len() as f64;
        println!(
            "furnace ball r={:.2} term={}: mean {mean:.1} vs background {bg}, max |diff| {worst}",
            ball.roughness,
            ball.model.has_term()
        );
        if ball.model.has_term() {
            assert!(
                worst <= 2,
                "ball {k} (r={}) differs from the background by {worst}/255",
                ball.roughness
            );
        } else if ball.roughness >= 0.5 {
            // Height-correlated Smith (the default G) misses less energy than Schlick's G:
            // at roughness 0.55 the ball is about 7/255 darker (schlick: 10/255).
            assert!(
                bg as f64 - mean >= 5.0,
                "ball {k} (r={}) is not visibly darker: mean {mean}",
                ball.roughness
            );
        }
    }
}

#[test]
fn furnace_radiance_is_one_on_the_cpu_with_the_term() {
    let scene = Scene::furnace();
    let tables = TableSet::from(crate::lut::bake(&Default::default()));
    let radiance = cpu::render_radiance(
        &scene,
        &crate::prepared::Prepared::new(&scene, &tables),
        320,
        180,
    );
    let worst = radiance
        .iter()
        .map(|c| (*c - DVec3::ONE).abs().max_element())
        .fold(0.0, f64::max);
    println!("CPU furnace: max |Lo - 1| over the image (bottom row excluded below) = {worst:.2e}");
    let top: Vec<usize> = (0..5).flat_map(|k| interior(&scene, k, 320, 180)).collect();
    let worst_top = top
        .iter()
        .map(|&p| (radiance[p] - DVec3::ONE).abs().max_element())
        .fold(0.0, f64::max);
    println!("CPU furnace, top row interiors: max |Lo - 1| = {worst_top:.2e}");
    assert!(worst_top < 1e-5, "{worst_top}");
}

/// A host's device (no adapter of ours) answers which formats it renders to by trying a
/// 1x1 target: the same answers as the adapter's on Vulkan and GL, for the truth's sums,
/// the readback's fallback and an 8-bit target (WebGPU's guarantees said yes to
/// `Rgba32Float` on a GL window's device that refuses it).
#[test]
fn a_hosts_device_knows_its_render_targets() {
    use wgpu::TextureFormat as F;
    for backends in [wgpu::Backends::VULKAN, wgpu::Backends::GL] {
        let ours = renderer(backends);
        let gpu = ours.gpu();
        let host = crate::Gpu::from_device(&gpu.device, &gpu.queue);
        for format in [F::Rgba32Float, F::Rgba32Uint, F::Rgba8Unorm] {
            assert_eq!(
                host.renderable(format),
                gpu.renderable(format),
                "{backends:?} {format:?}"
            );
        }
    }
}
