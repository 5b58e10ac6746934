//! The truth on the GPU (`walk.wgsl`, src/gpu/truth.rs) against the CPU truth
//! (`cpu::render_truth`): per ball, the mean radiance over the ball's inner pixels within 4
//! combined standard errors, on a scene with two lights, a uniform environment, metal,
//! dielectric (IOR 1.33, 1.5, 2.0) and partly metal truth balls; the white furnace equal to
//! its environment within 4 standard errors, for metals and for coatings over a white
//! base; the progressive sums (restart on a change, count per draw); GL either agrees or
//! refuses.
//!
//! The GPU's standard error comes from its own frames by batch means: the sums are read
//! back every `BATCH` frames, and each batch's mean is the difference of two read-backs.

use glam::DVec3;

use crate::cpu::{self, intersect_sphere, TruthSettings};

use crate::gpu::Renderer;

use crate::lut::TableSet;

use crate::lut::{self, BakeConfig};

use crate::scene::{Model, Scene};

use crate::pixels::{renderer, vulkan};

const W: u32 = 320;

const H: u32 = 180;

/// The image of the clear coat's and the anisotropic surface's tests: a quarter of the
/// pixels (each ball's mean over a few hundred inner pixels), to keep each test to seconds.
const SMALL: (u32, u32) = (160, 90);

/// Frames a batch, and batches: 32 batch means give the standard error with 31 degrees of
/// freedom, so 4 of them is a two-sided tail of about 4e-4 of Student's t.
const BATCH: u32 = 4;

const BATCHES: u32 = 32;

/// The agreement bound: 4 combined standard errors (the brief's).
const Z_MAX: f64 = 4.0;

/// A floor on each comparison's standard error, relative to the CPU's mean: the exact
/// part (the lights' single scattering) is evaluated in f32 on the GPU and f64 on the
/// CPU, where a ball whose walk adds almost nothing has a standard error far below the
/// f32 rounding of its mean (1e-4 is about 800 f32 ulps, and the order of what the f32
/// normal of a hit point moves the lights' term by).
const F32_FLOOR: f64 = 1e-4;

fn all_truth(mut scene: Scene) -> Scene {
    for b in &mut scene.balls {
        b.model = Model::Truth;
    }
    scene
}

/// Per pixel, the ball whose pixel it is and whose eight neighbours are its too (the
/// silhouettes, where the f32 and f64 rays may pick different balls, are left out).
fn inner_pixels(scene: &Scene) -> Vec<Option<usize>> {
    inner_pixels_at(scene, (W, H))
}

/// [`inner_pixels`] of a `w x h` image.
fn inner_pixels_at(scene: &Scene, (w, h): (u32, u32)) -> Vec<Option<usize>> {
    let basis = scene.camera.basis(w, h);
    let nearest: Vec<Option<usize>> = (0..w * h)
        .map(|i| {
            let d = basis.ray(i % w, i / w, w, h);
            let mut best: Option<(f64, usize)> = None;
            for (k, b) in scene.balls.iter().enumerate() {
                let t = intersect_sphere(basis.origin, d, b.center, b.radius);
                if t > 0.0 && best.is_none_or(|(bt, _)| t < bt) {
                    best = Some((t, k));
                }
            }
            best.map(|(_, k)| k)
        })
        .collect();
    (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as i64, (i / w) as i64);
            let k = nearest[i as usize]?;
            let inner = (-1..=1).all(|dy| {
                (-1..=1).all(|dx| {
                    let (nx, ny) = (x + dx, y + dy);
                    (0..w as i64).contains(&nx)
                        && (0..h as i64).contains(&ny)
                        && nearest[(ny * w as i64 + nx) as usize] == Some(k)
                })
            });
            inner.then_some(k)
        })
        .collect()
}

/// A ball's mean radiance and its standard error, per channel.
#[derive(Clone, Copy, Debug)]
struct Estimate {
    mean: DVec3,
    std_error: DVec3,
}

/// Mean over each ball's inner pixels of an RGBA f32 image.
fn ball_means(rgba: &[f32], owner: &[Option<usize>], balls: usize) -> Vec<DVec3> {
    let mut sums = vec![(DVec3::ZERO, 0u32); balls];
    for (i, k) in owner.iter().enumerate() {
        if let Some(k) = *k {
            let p = &rgba[4 * i..4 * i + 3];
            sums[k].0 += DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64);
            sums[k].1 += 1;
        }
    }
    sums.into_iter()
        .map(|(s, n)| s / f64::from(n.max(1)))
        .collect()
}

/// The GPU truth per ball by batch means over `BATCHES` batches of `BATCH` frames.
fn gpu_truth(r: &mut Renderer, scene: &Scene, owner: &[Option<usize>]) -> Vec<Estimate> {
    gpu_truth_at(r, scene, owner, (W, H))
}

/// [`gpu_truth`] of a `w x h` image.
fn gpu_truth_at(
    r: &mut Renderer,
    scene: &Scene,
    owner: &[Option<usize>],
    (w, h): (u32, u32),
) -> Vec<Estimate> {
    let n = scene.balls.len();
    r.reset_truth();
    let mut previous = vec![DVec3::ZERO; n];
    let mut batch_means: Vec<Vec<DVec3>> = Vec::new();
    for b in 1..=BATCHES {
        for _ in 1..BATCH {
            r.accumulate_truth(scene, w, h).unwrap();
        }
        // The draw adds the batch's last frame.
        let image = r.render_hdr(scene, w, h).unwrap();
        assert_eq!(r.truth_samples(), Some(b * BATCH));
        let means = ball_means(&image.rgba, owner, n);
        let frames = f64::from(b * BATCH);
        let batch: Vec<DVec3> = (0..n)
            .map(|k| {
                (means[k] * frames - previous[k] * (frames - f64::from(BATCH))) / f64::from(BATCH)
            })
            .collect();
        previous = means;
        batch_means.push(batch);
    }
    let m = f64::from(BATCHES);
    (0..n)
        .map(|k| {
            let mean = batch_means.iter().map(|b| b[k]).sum::<DVec3>() / m;
            let var = batch_means
                .iter()
                .map(|b| (b[k] - mean) * (b[k] - mean))
                .sum::<DVec3>()
                / (m - 1.0);
            Estimate {
                mean,
                std_error: (var / m).powf(0.5),
            }
        })
        .collect()
}

/// The CPU truth per ball over the same inner pixels (the standard error of that mean
/// from its pixels' own).
fn cpu_truth(scene: &Scene, owner: &[Option<usize>], spp: u32) -> Vec<Estimate> {
    cpu_truth_at(scene, owner, spp, (W, H))
}

/// [`cpu_truth`] of a `w x h` image.
fn cpu_truth_at(
    scene: &Scene,
    owner: &[Option<usize>],
    spp: u32,
    (w, h): (u32, u32),
) -> Vec<Estimate> {
    let tables = lut::bake(&BakeConfig {
        geometry: scene.effective_geometry(),
        ..Default::default()
    });
    let settings = TruthSettings {
        spp,
        seed: 3,
        ..Default::default()
    };
    let image = cpu::render_truth(
        scene,
        &crate::prepared::Prepared::new(scene, &TableSet::full(tables.clone())),
        w,
        h,
        settings,
        |_| true,
    )
    .unwrap()
    .image;
    let n = scene.balls.len();
    let mut sums = vec![(DVec3::ZERO, DVec3::ZERO, 0u32); n];
    for (i, k) in owner.iter().enumerate() {
        if let Some(k) = *k {
            let s = image.std_error[i];
            sums[k].0 += image.mean[i];
            sums[k].1 += s * s;
            sums[k].2 += 1;
        }
    }
    sums.into_iter()
        .map(|(mean, var, count)| {
            let c = f64::from(count.max(1));
            Estimate {
                mean: mean / c,
                std_error: var.powf(0.5) / c,
            }
        })
        .collect()
}

/// Per ball and channel, |GPU - expected| in combined standard errors (with the f32 floor
/// relative to the expected value); the largest, and the report of every ball.
fn z_scores(gpu: &[Estimate], expected: &[Estimate]) -> (f64, String) {
    let mut worst = 0.0f64;
    let mut report = String::new();
    for (k, (g, c)) in gpu.iter().zip(expected).enumerate() {
        let floor = c.mean.abs() * F32_FLOOR;
        let se = (g.std_error * g.std_error + c.std_error * c.std_error + floor * floor)
            .powf(0.5)
            .max(DVec3::splat(1e-30));
        let z = (g.mean - c.mean).abs() / se;
        worst = worst.max(z.max_element());
        report += &format!(
            "\n  ball {k}: gpu {} +- {}, expected {} +- {}, z {}",
            show(g.mean, "{:.5}"),
            show(g.std_error, "{:.1e}"),
            show(c.mean, "{:.5}"),
            show(c.std_error, "{:.1e}"),
            show(z, "{:.2}")
        );
    }
    (worst, report)
}

/// A vector's channels, each formatted like `{:.5}` (`fmt`) or in exponent form (`{:.1e}`).
fn show(v: DVec3, fmt: &str) -> String {
    let one = |x: f64| match fmt {
        "{:.1e}" => format!("{x:.1e}"),
        "{:.2}" => format!("{x:.2}"),
        _ => format!("{x:.5}"),
    };
    format!("[{}, {}, {}]", one(v.x), one(v.y), one(v.z))
}

/// Two lights, a uniform environment, every ball the truth: the metals and dielectrics of
/// the mixed scene at five roughnesses, the dielectrics at IOR 1.33, 1.5 and 2.0, and a
/// half metal. Every part of the GPU truth: the metal's exact single scattering, the
/// walks' next-event estimates, the coating's gathering at its base, the escapes into the
/// environment, and the mix by metallic.
fn agreement_scene() -> Scene {
    let mut scene = all_truth(crate::pixels::mixed_scene());
    // Balls 0, 2, 4, 6, 8 are the dielectrics (IOR 1.5); 4 is the roughest of the top row,
    // 6 the second roughness of the bottom row.
    scene.balls[4].material.ior = 1.33;
    scene.balls[6].material.ior = 2.0;
    // A metallic-roughness half metal: its F0 the metal's, a coloured base beneath.
    let half = &mut scene.balls[1].material;
    half.metallic = 0.5;
    half.diffuse = DVec3::new(0.6, 0.3, 0.15);
    scene.environment = DVec3::new(0.3, 0.25, 0.2);
    scene
}

fn agrees_with_cpu(r: &mut Renderer, what: &str) {
    let scene = agreement_scene();
    let owner = inner_pixels(&scene);
    let gpu = gpu_truth(r, &scene, &owner);
    let cpu = cpu_truth(&scene, &owner, 64);
    assert_eq!(gpu.len(), 10, "every ball is the truth");
    let (worst, report) = z_scores(&gpu, &cpu);
    eprintln!("{what} truth vs CPU truth (worst {worst:.2} standard errors):{report}");
    assert!(
        worst < Z_MAX,
        "{what} truth differs from the CPU truth by {worst:.2} standard errors:{report}"
    );
}

#[test]
fn gpu_truth_agrees_with_the_cpu_truth_per_ball() {
    agrees_with_cpu(&mut vulkan(), "Vulkan");
}

#[test]
fn gpu_truth_white_furnace_is_the_environment() {
    let mut r = vulkan();
    let scene = all_truth(Scene::furnace());
    let owner = inner_pixels(&scene);
    let gpu = gpu_truth(&mut r, &scene, &owner);
    // F0 = 1 loses nothing: every ball's radiance is the environment's, exactly.
    let exact: Vec<Estimate> = gpu
        .iter()
        .map(|_| Estimate {
            mean: scene.environment,
            std_error: DVec3::ZERO,
        })
        .collect();
    let (worst, report) = z_scores(&gpu, &exact);
    eprintln!("GPU truth furnace (worst {worst:.2} standard errors):{report}");
    assert!(
        worst < Z_MAX,
        "the GPU truth's furnace is not its environment ({worst:.2} standard errors):{report}"
    );
}

/// The white furnace of coated truth balls: a lossless coating over a white base reflects
/// everything, so every ball is its environment (Heitz et al. 2016's walk conserves
/// energy; only Russian roulette, which a white base never plays, or the guard could end a
/// path early), at five roughnesses and the IORs 1.1 to 2.5 (a lower IOR traps less light
/// by total internal reflection, a higher one more, so longer paths).
#[test]
fn gpu_truth_white_furnace_of_coatings_is_the_environment() {
    use crate::scene::Material;
    let mut r = vulkan();
    let mut scene = all_truth(Scene::furnace());
    let iors = [1.1, 1.33, 1.5, 2.0, 2.5];
    for (k, b) in scene.balls.iter_mut().enumerate() {
        // Top row: IOR rising with roughness; bottom row shifted by two.
        b.material = Material::dielectric(DVec3::ONE, iors[(k + 2 * (k / 5)) % 5]);
    }
    let owner = inner_pixels(&scene);
    let gpu = gpu_truth(&mut r, &scene, &owner);
    let exact: Vec<Estimate> = gpu
        .iter()
        .map(|_| Estimate {
            mean: scene.environment,
            std_error: DVec3::ZERO,
        })
        .collect();
    let (worst, report) = z_scores(&gpu, &exact);
    eprintln!("GPU truth furnace of coatings (worst {worst:.2} standard errors):{report}");
    assert!(
        worst < Z_MAX,
        "the GPU truth's coated furnace is not its environment ({worst:.2} standard errors):{report}"
    );
}

#[test]
fn gpu_truth_on_gl_agrees_or_refuses() {
    let mut r = renderer(wgpu::Backends::GL);
    if r.truth_supported() {
        agrees_with_cpu(&mut r, "GL");
    } else {
        let scene = agreement_scene();
        let err = r.render_hdr(&scene, W, H).err().expect("GL must refuse");
        assert!(err.to_string().contains("Rgba32Float"), "{err}");
    }
}

#[test]
fn truth_sums_count_draws_and_restart_on_a_change() {
    let mut r = vulkan();
    let mut scene = all_truth(Scene::reference());
    for k in 1..=3 {
        r.render_ldr(&scene, 64, 36).unwrap();
        assert_eq!(r.truth_samples(), Some(k));
    }
    // The exposure is the resolve's: the sums go on.
    scene.exposure = 2.0;
    r.render_ldr(&scene, 64, 36).unwrap();
    assert_eq!(r.truth_samples(), Some(4));
    // A change of the scene or of the size starts again.
    scene.balls[0].roughness = 0.5;
    r.render_ldr(&scene, 64, 36).unwrap();
    assert_eq!(r.truth_samples(), Some(1));
    r.render_ldr(&scene, 48, 36).unwrap();
    assert_eq!(r.truth_samples(), Some(1));
    let image = r.render_truth_ldr(&scene, 64, 36, 5).unwrap();
    assert_eq!(r.truth_samples(), Some(5));
    assert_eq!(image.rgba.len(), 64 * 36 * 4);
}

#[test]
fn a_truth_ball_is_not_drawn_as_none() {
    // Before the GPU truth, a truth ball was drawn with the `none` model: the walk's
    // multiple scattering adds light at high roughness, so the truth ball is brighter.
    let mut r = vulkan();
    let mut scene = Scene::reference();
    for b in &mut scene.balls {
        b.model = Model::None;
    }
    let owner = inner_pixels(&scene);
    let none = ball_means(&r.render_hdr(&scene, W, H).unwrap().rgba, &owner, 10);
    let truth_scene = all_truth(scene);
    let truth = ball_means(
        &r.render_truth_hdr(&truth_scene, W, H, 16).unwrap().rgba,
        &owner,
        10,
    );
    // The roughest balls (roughness 0.95, the fifth of each row) gain most.
    for k in [4, 9] {
        assert!(
            truth[k].x > none[k].x * 1.02,
            "ball {k}: truth {:?} vs none {:?}",
            truth[k],
            none[k]
        );
    }
}

#[test]
fn truth_spp_is_checked() {
    let mut r = vulkan();
    let scene = all_truth(Scene::reference());
    assert!(r.render_truth_ldr(&scene, 32, 18, 0).is_err());
    assert!(r
        .render_truth_ldr(&scene, 32, 18, crate::gpu::MAX_TRUTH_SPP + 1)
        .is_err());
}

/// A clear-coated truth ball under lights is refused in one line by every way the GPU
/// draws (its coat's walk has no next-event estimation: drawn, it would lose its lights),
/// as the CPU's truth refuses it; without the lights, or with the coat on a ball of
/// another model, the same scene renders.
#[test]
fn a_clear_coated_truth_ball_under_lights_is_refused() {
    let mut r = vulkan();
    let mut scene = Scene::reference();
    assert!(!scene.lights.is_empty());
    scene.balls[0].material.clearcoat.weight = 1.0;
    scene.balls[1].model = Model::Truth;
    // The coat on a ball the model shades, a truth ball without a coat: drawn.
    r.render_hdr(&scene, 32, 18).unwrap();
    scene.balls[0].model = Model::Truth;
    let refused = |r: &mut Renderer, scene: &Scene| {
        let errors = [
            r.render_hdr(scene, 32, 18).err(),
            r.render_ldr(scene, 32, 18).err(),
            r.render_truth_hdr(scene, 32, 18, 2).err(),
        ];
        for e in errors {
            let e = e.expect("refused").to_string();
            assert!(e.contains("clear-coated") && !e.contains('\n'), "{e}");
        }
        let tables = TableSet::full(lut::bake(&BakeConfig::default()));
        let prepared = crate::prepared::Prepared::new(scene, &tables);
        let settings = TruthSettings::default();
        let cpu = cpu::render_truth(scene, &prepared, 32, 18, settings, |_| true);
        assert!(cpu.is_err(), "the CPU's truth refuses it too");
    };
    refused(&mut r, &scene);
    scene.lights.clear();
    r.render_hdr(&scene, 32, 18).unwrap();
}

/// A smooth map (a warm horizon fading into a blue zenith, brighter towards +u), every
/// texel a multiple of 1/64 so that the GPU's 16-bit float texture holds it exactly: the
/// exits' directions matter, not only their weights, and the bilinear reads of f32 and f64
/// agree far below the noise.
fn smooth_map() -> crate::environment::Environment {
    use crate::environment::{Builtin, EnvMap, Environment, Source};
    let (w, h) = (32u32, 16u32);
    let mut texels = Vec::new();
    for j in 0..h {
        for i in 0..w {
            let across = i.min(w - i) as f32 / 64.0;
            let up = j as f32 / 16.0;
            texels.push([0.25 + 2.0 * up + across, 0.5 + up + across, 1.5 - up]);
        }
    }
    Environment {
        source: Source::Builtin(Builtin::White),
        map: std::sync::Arc::new(EnvMap::new(w, h, texels).unwrap()),
        rotation_deg: 30.0,
        intensity: 1.0,
    }
}

/// The reference chart under the smooth map and a uniform environment, no lights, every
/// ball the truth with a clear coat of weight 1 or 0.5, roughness 0.05 to 0.8 and index 1.3
/// to 2.0 over metals (a coloured F0), plastics and half metals; ball 9's metal is
/// anisotropic under its coat.
fn coated_scene() -> Scene {
    use crate::scene::{ClearCoat, Material};
    let mut scene = all_truth(Scene::reference());
    scene.lights.clear();
    scene.environment = DVec3::new(0.1, 0.08, 0.06);
    scene.environment_map = Some(smooth_map());
    let bases = [
        Material::metal(DVec3::new(0.95, 0.64, 0.54)),
        Material::dielectric(DVec3::new(0.6, 0.08, 0.05), 1.5),
        Material::metallic_roughness(DVec3::new(0.8, 0.5, 0.2), 0.5, 1.5),
    ];
    let coats = [
        (1.0, 0.05, 1.5),
        (1.0, 0.3, 1.3),
        (0.5, 0.2, 1.5),
        (1.0, 0.6, 2.0),
        (1.0, 0.8, 1.5),
    ];
    for (k, b) in scene.balls.iter_mut().enumerate() {
        let (weight, roughness, ior) = coats[k % 5];
        b.material = bases[k % 3].with_clearcoat(ClearCoat {
            weight,
            roughness,
            ior,
        });
    }
    let last = &mut scene.balls[9];
    last.material = Material::metal(DVec3::new(0.9, 0.9, 0.92))
        .with_anisotropy(0.8, 0.5)
        .with_clearcoat(ClearCoat {
            weight: 1.0,
            roughness: 0.1,
            ior: 1.5,
        });
    scene
}

/// The GPU truth through a clear coat (walk.wgsl clearcoat_walk) equals the CPU truth
/// (src/walk/clearcoat.rs) per ball within [`Z_MAX`] combined standard errors.
#[test]
fn gpu_truth_through_a_clear_coat_agrees_with_the_cpu_truth() {
    let mut r = vulkan();
    let scene = coated_scene();
    let owner = inner_pixels_at(&scene, SMALL);
    let gpu = gpu_truth_at(&mut r, &scene, &owner, SMALL);
    let cpu = cpu_truth_at(&scene, &owner, 64, SMALL);
    let (worst, report) = z_scores(&gpu, &cpu);
    eprintln!("GPU truth through a coat vs CPU truth (worst {worst:.2} standard errors):{report}");
    assert!(
        worst < Z_MAX,
        "the GPU truth through a coat differs from the CPU's by {worst:.2} standard errors:{report}"
    );
}

/// The white furnace through a clear coat and on anisotropic surfaces: coats of every
/// weight, roughness and index over a white metal (F0 = 1), a white plastic and a white
/// half metal, and anisotropic white metals bare and coated, lose nothing, so every ball is
/// its environment. A negative control: the same chart with a grey F0 is darker by far
/// more than the noise.
#[test]
fn gpu_truth_white_furnace_through_coats_and_anisotropy() {
    use crate::scene::{ClearCoat, Material};
    let mut r = vulkan();
    let mut scene = all_truth(Scene::furnace());
    let white = [
        Material::metal(DVec3::ONE),
        Material::dielectric(DVec3::ONE, 1.5),
        Material::metallic_roughness(DVec3::ONE, 0.5, 1.5),
    ];
    let coats = [
        (1.0, 0.05, 1.5),
        (0.5, 0.3, 1.3),
        (1.0, 0.6, 2.0),
        (1.0, 0.9, 1.5),
    ];
    for (k, b) in scene.balls.iter_mut().enumerate() {
        let (weight, roughness, ior) = coats[k % 4];
        let coat = ClearCoat {
            weight,
            roughness,
            ior,
        };
        b.material = match k {
            // Anisotropic white metals: bare, rotated, and under a coat.
            7 => Material::metal(DVec3::ONE).with_anisotropy(0.9, 0.0),
            8 => Material::metal(DVec3::ONE).with_anisotropy(0.6, 1.2),
            9 => Material::metal(DVec3::ONE)
                .with_anisotropy(0.9, 0.3)
                .with_clearcoat(coat),
            _ => white[k % 3].with_clearcoat(coat),
        };
    }
    let owner = inner_pixels_at(&scene, SMALL);
    let gpu = gpu_truth_at(&mut r, &scene, &owner, SMALL);
    let exact: Vec<Estimate> = gpu
        .iter()
        .map(|_| Estimate {
            mean: scene.environment,
            std_error: DVec3::ZERO,
        })
        .collect();
    let (worst, report) = z_scores(&gpu, &exact);
    eprintln!("GPU truth furnace through coats (worst {worst:.2} standard errors):{report}");
    assert!(
        worst < Z_MAX,
        "the GPU truth's furnace through coats is not its environment ({worst:.2} standard errors):{report}"
    );
    // The negative control: metals of F0 0.5 lose light at every bounce.
    for b in &mut scene.balls {
        b.material.f0 = DVec3::splat(0.5);
    }
    let grey = gpu_truth_at(&mut r, &scene, &owner, SMALL);
    let (lost, report) = z_scores(&grey, &exact);
    assert!(
        lost > 10.0 * Z_MAX,
        "a grey F0 should fail the furnace ({lost:.2} standard errors):{report}"
    );
}

/// Anisotropic truth balls on the GPU (walk.wgsl on the stretched surface, in the ball's
/// tangent frame) equal the CPU truth per ball within [`Z_MAX`] combined standard errors,
/// under two lights and a uniform environment: anisotropy 0.3 to 1, rotations 0 to pi,
/// the chart's five roughnesses, metals and a half metal (whose coating stays isotropic);
/// ball 0, a plastic, is isotropic.
#[test]
fn gpu_truth_anisotropic_agrees_with_the_cpu_truth() {
    let mut r = vulkan();
    let mut scene = agreement_scene();
    let turns = [0.0, 0.4, 1.0, 1.9, std::f64::consts::PI];
    for (k, b) in scene.balls.iter_mut().enumerate().skip(1) {
        if k % 2 == 0 {
            // The dielectrics become coloured metals (the lobe the stretch is for); the
            // metals and the half metal keep their materials.
            b.material = crate::scene::Material::metal(DVec3::new(0.9, 0.6, 0.3));
        }
        b.material = b
            .material
            .with_anisotropy(0.3 + 0.7 * (k as f64 / 9.0), turns[k % 5]);
    }
    let owner = inner_pixels_at(&scene, SMALL);
    let gpu = gpu_truth_at(&mut r, &scene, &owner, SMALL);
    let cpu = cpu_truth_at(&scene, &owner, 64, SMALL);
    let (worst, report) = z_scores(&gpu, &cpu);
    eprintln!("GPU anisotropic truth vs CPU truth (worst {worst:.2} standard errors):{report}");
    assert!(
        worst < Z_MAX,
        "the GPU's anisotropic truth differs from the CPU's by {worst:.2} standard errors:{report}"
    );
}
