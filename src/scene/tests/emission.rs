//! Emission (docs/interop.md, "Emission"): a glTF material's `emissiveFactor` x
//! `KHR_materials_emissive_strength` becomes the material's `emission`, added to the light
//! the ball reflects where a ray first meets it, by every backend: the real-time renderer
//! (split sum and lobe mode), the Monte Carlo of the model and the truth, on the CPU and
//! the GPU. Each is drawn with and without the emission from the same samples: the
//! difference is the emission exactly, on the emissive ball's pixels only.

use crate::environment::{Builtin, IblMethod, Source};
use crate::lut::{bake, BakeConfig, TableSet};
use crate::prepared::Prepared;
use crate::scene::{Model, Scene};
use glam::DVec3;
use serde_json::json;

use crate::pixels::temp_dir;

/// The picture's size: small, the checks are per pixel.
const W: u32 = 96;
const H: u32 = 54;

/// The width of the studio map the test lights the balls with.
const STUDIO_WIDTH: u32 = 64;

/// The glowing material's `emissiveFactor` and `emissiveStrength`.
const FACTOR: [f64; 3] = [0.5, 0.25, 0.125];
const STRENGTH: f64 = 0.75;

/// A glTF file of two materials and no mesh (a chart of two balls): an orange plastic, and
/// the same plastic glowing.
fn glowing_file(dir: &std::path::Path) -> std::path::PathBuf {
    let pbr = json!({"baseColorFactor": [0.8, 0.3, 0.1, 1.0], "metallicFactor": 0.0,
                     "roughnessFactor": 0.35});
    let doc = json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_materials_emissive_strength"],
        "materials": [
            {"name": "plastic", "pbrMetallicRoughness": pbr},
            {"name": "glowing plastic", "pbrMetallicRoughness": pbr,
             "emissiveFactor": FACTOR,
             "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": STRENGTH}}}
        ]
    });
    let path = dir.join("glowing.gltf");
    std::fs::write(&path, serde_json::to_string_pretty(&doc).unwrap()).unwrap();
    path
}

/// The imported scene (antialiasing off: a pixel is the ball's or not, so the difference
/// is exact on every pixel; no labels), and the emission it carries.
fn imported() -> (Scene, DVec3) {
    let dir = temp_dir("glow");
    let file = glowing_file(&dir);
    let imported_file = crate::import::load(&file).unwrap();
    assert!(
        !imported_file.notices.join("\n").contains("emission"),
        "{:?}",
        imported_file.notices
    );
    let mut scene = imported_file.scene.clone();
    scene.antialias = false;
    scene.labels = false;
    // The import's studio map, generated small: the CPU prepares it per render, and a
    // test's budget is seconds.
    let studio = scene.environment_map.as_mut().unwrap();
    assert_eq!(studio.source, Source::Builtin(Builtin::Studio));
    studio.map = std::sync::Arc::new(Builtin::Studio.generate(STUDIO_WIDTH));
    let e = DVec3::from_array(FACTOR) * STRENGTH;
    assert_eq!(scene.balls[0].material.emission, DVec3::ZERO);
    assert_eq!(scene.balls[1].material.emission, e);
    // `import` writes the key (through its writer), which loads back to the same value.
    let out = dir.join("glowing.toml");
    let text = crate::cli::import::scene_text(&imported_file, &file).unwrap();
    std::fs::write(&out, &text).unwrap();
    assert!(
        text.contains("emission = [0.375, 0.1875, 0.09375]"),
        "{text}"
    );
    let back = crate::scene::load(&out).unwrap();
    assert_eq!(back.balls[1].material.emission, e);
    let _ = std::fs::remove_dir_all(&dir);
    (scene, e)
}

/// The scene without any emission.
fn dark(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    for b in &mut s.balls {
        b.material.emission = DVec3::ZERO;
    }
    s
}

fn tables(scene: &Scene) -> TableSet {
    TableSet::full(bake(&BakeConfig {
        geometry: scene.effective_geometry(),
        ..Default::default()
    }))
}

/// Which ball each pixel's centre ray meets first.
fn owners(scene: &Scene) -> Vec<Option<usize>> {
    crate::cpu::ball_index_map(scene, W, H)
}

/// Checks that `lit - unlit` is `e` on ball 1's pixels and 0 elsewhere, within `tolerance`
/// relative to the pixel's radiance (0: exactly, up to the last bits of one addition).
/// Pixels on a silhouette (a neighbour's centre ray meets another ball or none) are left
/// out: f32 and f64 may settle them differently.
fn brighter_by(
    what: &str,
    scene: &Scene,
    lit: &[DVec3],
    unlit: &[DVec3],
    e: DVec3,
    tolerance: f64,
) {
    let owner = owners(scene);
    let (w, h) = (W as usize, H as usize);
    let inner = |p: usize| {
        let (x, y) = (p % w, p / w);
        x > 0
            && y > 0
            && x + 1 < w
            && y + 1 < h
            && [p - 1, p + 1, p - w, p + w]
                .iter()
                .all(|&q| owner[q] == owner[p])
    };
    let mut glowing = 0;
    for (p, ((a, b), o)) in lit.iter().zip(unlit).zip(&owner).enumerate() {
        if !inner(p) {
            continue;
        }
        let want = if *o == Some(1) { e } else { DVec3::ZERO };
        glowing += usize::from(*o == Some(1));
        let allowed = (a.max_element() * tolerance).max(a.max_element() * f64::EPSILON * 4.0);
        let off = ((*a - *b) - want).abs().max_element();
        assert!(
            off <= allowed,
            "{what}: pixel {p} ({:?}): {a} - {b} is not {want} (off by {off:e})",
            o
        );
    }
    assert!(
        glowing > 100,
        "{what}: only {glowing} pixels on the glowing ball"
    );
}

fn rgb(rgba: &[f32]) -> Vec<DVec3> {
    rgba.chunks(4)
        .map(|p| DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64))
        .collect()
}

/// The imported emissive material is brighter by exactly its emission in every CPU
/// backend (linear), and the GPU's matches (f32), and the GPU's display values agree with
/// the CPU's within 1/255.
#[test]
fn an_imported_emissive_material_is_brighter_by_its_emission_in_every_backend() {
    let clock = std::time::Instant::now();
    let lap = |what: &str| println!("{what}: {:.2} s", clock.elapsed().as_secs_f64());
    let (scene, e) = imported();
    lap("import");
    let unlit = dark(&scene);
    let t = tables(&scene);
    let cpu = |s: &Scene| crate::cpu::render_radiance(s, &Prepared::new(s, &t), W, H);
    // The real-time renderer's CPU twin (split sum).
    brighter_by("CPU split sum", &scene, &cpu(&scene), &cpu(&unlit), e, 0.0);
    lap("CPU split sum");
    // The lobe mode (the map's part sampled; the same samples with and without).
    let lobe = |s: &Scene| {
        let mut s = s.clone();
        s.ibl_method = IblMethod::Lobe;
        s.ibl_samples = 8;
        s
    };
    brighter_by(
        "CPU lobe",
        &scene,
        &cpu(&lobe(&scene)),
        &cpu(&lobe(&unlit)),
        e,
        0.0,
    );
    // The model's Monte Carlo (the same seed: the same samples).
    let mc = |s: &Scene| {
        crate::cpu::render_montecarlo(s, &Prepared::new(s, &t), W, H, 4, 7)
            .unwrap()
            .mean
    };
    brighter_by("CPU Monte Carlo", &scene, &mc(&scene), &mc(&unlit), e, 0.0);
    lap("CPU Monte Carlo");
    // The truth (the walk; emission added at the first hit).
    let truth = |s: &Scene| {
        let settings = crate::cpu::TruthSettings {
            spp: 2,
            seed: 7,
            ..Default::default()
        };
        crate::cpu::render_truth(s, &Prepared::new(s, &t), W, H, settings, |_| true)
            .unwrap()
            .image
            .mean
    };
    brighter_by("CPU truth", &scene, &truth(&scene), &truth(&unlit), e, 0.0);
    lap("CPU truth");

    // The GPU: the same differences in f32.
    let mut gpu = crate::pixels::vulkan();
    let f32_tolerance = 1e-5;
    let hdr = |r: &mut crate::gpu::Renderer, s: &Scene| rgb(&r.render_hdr(s, W, H).unwrap().rgba);
    let (a, b) = (hdr(&mut gpu, &scene), hdr(&mut gpu, &unlit));
    brighter_by("GPU split sum", &scene, &a, &b, e, f32_tolerance);
    lap("GPU split sum");
    let lobe_hdr = |r: &mut crate::gpu::Renderer, s: &Scene| {
        rgb(&r.render_lobe_hdr(&lobe(s), W, H, 2).unwrap().rgba)
    };
    let (a, b) = (lobe_hdr(&mut gpu, &scene), lobe_hdr(&mut gpu, &unlit));
    brighter_by("GPU lobe", &scene, &a, &b, e, f32_tolerance);
    lap("GPU lobe");
    let gpu_mc = |r: &mut crate::gpu::Renderer, s: &Scene| {
        r.render_montecarlo(s, (W, H), 64, 7).unwrap().mean
    };
    let (a, b) = (gpu_mc(&mut gpu, &scene), gpu_mc(&mut gpu, &unlit));
    brighter_by("GPU Monte Carlo", &scene, &a, &b, e, f32_tolerance);
    lap("GPU Monte Carlo");
    let all_truth = |s: &Scene| {
        let mut s = s.clone();
        for b in &mut s.balls {
            b.model = Model::Truth;
        }
        s
    };
    let gpu_truth = |r: &mut crate::gpu::Renderer, s: &Scene| {
        rgb(&r.render_truth_hdr(&all_truth(s), W, H, 2).unwrap().rgba)
    };
    let (a, b) = (gpu_truth(&mut gpu, &scene), gpu_truth(&mut gpu, &unlit));
    brighter_by("GPU truth", &scene, &a, &b, e, f32_tolerance);
    lap("GPU truth");

    // After exposure and the tone map: the GPU's picture is the CPU's within 1/255, with
    // the emission and antialiasing on.
    let mut shown = scene.clone();
    shown.antialias = true;
    let (g, c) = crate::pixels::both(&mut gpu, &shown, W, H);
    let d = crate::pixels::compare(&g, &c, W);
    crate::pixels::assert_close(&d, "emissive scene, GPU vs CPU");
    let (g0, _) = crate::pixels::both(&mut gpu, &dark(&shown), W, H);
    let changed = crate::pixels::compare(&g, &g0, W);
    assert!(
        changed.pixels - changed.equal > 100,
        "the emission changes the picture: {}",
        changed.report("lit vs unlit")
    );
}

/// The key: 0 without it (so every scene before it, the white furnaces among them, draws
/// as before), its value with it, and the viewer's writer carries it.
#[test]
fn emission_key_defaults_to_zero_and_saves() {
    let parse = |text: &str| crate::scene::parse(text, std::path::Path::new("e.toml"));
    let ball = |material: &str| {
        format!("[[ball]]\ngrid = [0, 0]\nradius = 35\nroughness = 0.5\nmaterial = {material}\n")
    };
    let m = parse(&ball("{ base_color = [0.8, 0.3, 0.1] }"))
        .unwrap()
        .balls[0]
        .material;
    assert_eq!(m.emission, DVec3::ZERO);
    let m = parse(&ball(
        "{ base_color = [0.8, 0.3, 0.1], emission = [2, 0.5, 0] }",
    ))
    .unwrap()
    .balls[0]
        .material;
    assert_eq!(m.emission, DVec3::new(2.0, 0.5, 0.0));
    // The viewer's writer writes it, and it loads back.
    let scene = parse(&ball(
        "{ kind = \"metal\", f0 = [1, 1, 1], emission = [0.25, 0.5, 1] }",
    ))
    .unwrap();
    let text = crate::viewer::save::scene_toml(&scene, (64, 36)).unwrap();
    let back = parse(&text).unwrap();
    assert_eq!(back.balls, scene.balls);
}
