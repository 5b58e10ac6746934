//! The clear coat (docs/design/coat.md): its scene keys, the GPU against its CPU twin, the
//! white furnace with the engines' forms as negative controls, the walk's laws, and every
//! form against the truth.

use glam::DVec3;

use crate::environment::{Builtin, Environment};

use crate::scene::{ClearCoat, CoatForm, Light, Material, Model, Scene};

use crate::walk::clearcoat::Layered;

use crate::walk::coating::{smooth_coating_albedo, Coating};

use crate::walk::microsurface::Microsurface;

use crate::walk::{trace, Rng, Schlick};

use super::materials::{ball_means, chart, furnace_worst, interior};

use crate::pixels::{assert_close, compare, renderer, vulkan};

/// A scene file of `assets/scenes`.
fn asset_scene(name: &str) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/scenes")
        .join(name);
    crate::scene::load(&path).unwrap()
}

fn coat(weight: f64, roughness: f64) -> ClearCoat {
    ClearCoat {
        weight,
        roughness,
        ior: 1.5,
    }
}

/// The keys `clearcoat`, `clearcoat_roughness`, `clearcoat_ior` and `coat_form`, their
/// defaults, and a one-line error for each value out of range.
#[test]
fn clearcoat_keys_parse_and_refuse_in_one_line() {
    let ball = |material: &str| {
        format!("[[ball]]\ngrid = [0, 0]\nradius = 35\nroughness = 0.5\nmaterial = {material}\n")
    };
    let parse = |text: &str| crate::scene::parse(text, std::path::Path::new("c.toml"));
    let s = parse(&ball(
        "{ base_color = [0.5, 0.5, 0.5], metallic = 1, clearcoat = 0.5, clearcoat_roughness = 0.2, clearcoat_ior = 1.6 }",
    ))
    .unwrap();
    let c = s.balls[0].material.clearcoat;
    assert_eq!((c.weight, c.roughness, c.ior), (0.5, 0.2, 1.6));
    assert_eq!(s.coat_form, CoatForm::Physical, "the default form");
    let s = parse(&ball("{ kind = \"metal\", f0 = [1, 1, 1], clearcoat = 1 }")).unwrap();
    let c = s.balls[0].material.clearcoat;
    assert_eq!(
        (c.weight, c.roughness, c.ior),
        (1.0, 0.0, 1.5),
        "the defaults"
    );
    let s = parse(&format!(
        "coat_form = \"filament\"\n{}",
        ball("{ base_color = [1, 1, 1] }")
    ))
    .unwrap();
    assert_eq!(s.coat_form, CoatForm::Filament);
    assert!(!s.balls[0].material.clearcoat.is_on(), "no coat by default");
    for (text, says) in [
        (
            ball("{ base_color = [1, 1, 1], clearcoat = 1.5 }"),
            "clearcoat: 1.5 is outside [0, 1]",
        ),
        (
            ball("{ base_color = [1, 1, 1], clearcoat = -0.1 }"),
            "clearcoat: -0.1 is outside [0, 1]",
        ),
        (
            ball("{ base_color = [1, 1, 1], clearcoat_roughness = 2 }"),
            "clearcoat_roughness: roughness 2.0 is outside [0, 1]",
        ),
        (
            ball("{ base_color = [1, 1, 1], clearcoat_ior = 0.5 }"),
            "clearcoat_ior: ior 0.5 is outside [1, 4]",
        ),
        (
            format!(
                "coat_form = \"matte\"\n{}",
                ball("{ base_color = [1, 1, 1] }")
            ),
            "coat form",
        ),
    ] {
        let e = parse(&text).unwrap_err().to_string();
        assert!(e.contains(says), "{text}: {e}");
        assert!(!e.contains('\n'), "one line: {e}");
    }
}

/// The base's lobe leaves a physical coat wider and keeps its albedo at the view:
/// `clearcoat_base_lobe`'s energy factor times `E` at the widened roughness (read along the
/// packed row the ball carries) is `E` at the base's own, over base and coat roughness, at
/// half and full weight, for `mu` from 0 to 1, under the plan's rows and under the 2-D
/// table. Under the engines' forms the lobe is the bare one.
#[test]
fn a_coated_bases_wider_lobe_keeps_its_albedo() {
    use crate::cpu::clearcoat::{clearcoat_base_lobe, BaseLobe};
    use crate::lut::{CoatingRows, TableSet};
    use crate::prepared::ClearcoatConstants;
    let bake = crate::lut::BakeConfig::default();
    let full = TableSet::Full(std::sync::Arc::new(crate::lut::bake(&bake)));
    let mut worst = (0.0_f64, String::new());
    for base in [0.05, 0.2, 0.4, 0.7, 1.0] {
        for coat_roughness in [0.0, 0.3, 0.7, 1.0] {
            for weight in [0.5, 1.0] {
                let m = Material::metallic_roughness(DVec3::new(0.95, 0.64, 0.54), 1.0, 1.5)
                    .with_clearcoat(coat(weight, coat_roughness));
                let scene = chart(1, 1, |_, _| (base, m, Model::KullaConty));
                let plan = crate::gpu::Plan::new(&scene, bake, Default::default());
                let TableSet::Rows(keys) = &plan.tables else {
                    panic!("the plan's rows: {:?}", plan.tables);
                };
                let rows = crate::lut::bake_rows(keys)
                    .into_iter()
                    .map(std::sync::Arc::new);
                let planned =
                    TableSet::Rows(std::sync::Arc::new(crate::lut::RowSet::new(rows.collect())));
                for e in [&planned, &full] {
                    let b = &scene.balls[0];
                    let rows =
                        CoatingRows::bake(scene.ball_coating_keys(b), &mut Default::default());
                    let c = ClearcoatConstants::of_ball(&scene, b, e, &rows).unwrap();
                    let own_roughness = b.shading_roughness() as f32;
                    for k in 0..=50 {
                        let mu = k as f64 / 50.0;
                        let lobe = clearcoat_base_lobe(&c, b.shading_roughness(), mu, e);
                        let own = 1.0 - f64::from(e.lut_loss(mu as f32, own_roughness));
                        let wide = 1.0 - f64::from(e.lut_loss(mu as f32, lobe.roughness as f32));
                        let err = (lobe.energy * wide / own - 1.0).abs();
                        if err > worst.0 {
                            worst = (
                                err,
                                format!(
                                    "base {base}, coat {coat_roughness}, weight {weight}, mu {mu}"
                                ),
                            );
                        }
                    }
                }
            }
        }
    }
    println!("worst relative error of the widened lobe's albedo at the view: {worst:?}");
    assert!(worst.0 < 1e-4, "{worst:?}");
    let mut scene = chart(1, 1, |_, _| {
        (
            0.4,
            Material::metallic_roughness(DVec3::splat(0.9), 1.0, 1.5)
                .with_clearcoat(coat(1.0, 1.0)),
            Model::KullaConty,
        )
    });
    scene.coat_form = CoatForm::Filament;
    let b = &scene.balls[0];
    let rows = CoatingRows::bake(scene.ball_coating_keys(b), &mut Default::default());
    let c = ClearcoatConstants::of_ball(&scene, b, &full, &rows).unwrap();
    let lobe = clearcoat_base_lobe(&c, b.shading_roughness(), 0.5, &full);
    assert_eq!(lobe, BaseLobe::bare(b.shading_roughness()));
}

/// A scene of coated balls lit by one light and a uniform environment: white-ish plastic,
/// red plastic, copper and a half metal down the rows, coat roughness across.
fn lit_chart(weight: f64) -> Scene {
    const ROUGHNESS: [f64; 4] = [0.05, 0.3, 0.6, 1.0];
    let bases = [
        Material::metallic_roughness(DVec3::splat(0.8), 0.0, 1.5),
        Material::metallic_roughness(DVec3::new(0.6, 0.05, 0.03), 0.0, 1.33),
        Material::metallic_roughness(DVec3::new(0.95, 0.64, 0.54), 1.0, 1.5),
        Material::metallic_roughness(DVec3::new(0.5, 0.5, 0.2), 0.5, 1.5),
    ];
    let mut scene = chart(4, 4, |r, c| {
        (
            0.4,
            bases[r].with_clearcoat(coat(weight, ROUGHNESS[c])),
            Model::KullaConty,
        )
    });
    scene.environment = DVec3::splat(0.3);
    scene.lights = vec![Light::new(
        DVec3::new(0.3, 0.5, 1.0).normalize(),
        DVec3::splat(2.5),
    )];
    scene
}

/// The GPU and its CPU twin within the house's bound (99.9 % of pixels within 1/255) with
/// clear coats under every form: `clearcoat.toml` (the studio), a lit chart (one light and
/// a uniform environment) at two weights, and the chart under the lobe's method.
#[test]
fn clearcoat_vulkan_matches_cpu() {
    // 192x108 (it was 320x180, for CI's time): every ball keeps its interior and its
    // silhouette, and the bound is per pixel.
    let (w, h) = (192, 108);
    let mut r = vulkan();
    for form in CoatForm::ALL {
        let mut scenes = vec![
            ("clearcoat.toml", asset_scene("clearcoat.toml")),
            ("lit chart, weight 1", lit_chart(1.0)),
            ("lit chart, weight 0.5", lit_chart(0.5)),
        ];
        let mut lobe = asset_scene("clearcoat.toml");
        lobe.ibl_method = crate::environment::IblMethod::Lobe;
        scenes.push(("clearcoat.toml, lobe", lobe));
        for (name, mut scene) in scenes {
            scene.coat_form = form;
            let (gpu, cpu) = crate::pixels::both(&mut r, &scene, w, h);
            assert_close(&compare(&gpu, &cpu, w), &format!("{name}, {form} coat"));
        }
    }
}

/// A coat fading out reaches the bare ball: `clearcoat.toml` (the studio, glossy and rough
/// bases) with every coat at weight 1e-3 against the same balls bare, on the GPU, within
/// the house's bound. The base's prefiltered read under the physical coat is widened
/// (`clearcoat_base_roughness`) in proportion to the weight; at full width for any weight,
/// the glossy balls here differ by far more than 1/255.
#[test]
fn a_coat_fading_out_is_the_bare_ball() {
    let (w, h) = (192, 108);
    let mut r = vulkan();
    let with_weight = |weight: f64| {
        let mut scene = asset_scene("clearcoat.toml");
        for b in &mut scene.balls {
            b.material.clearcoat = coat(weight, b.material.clearcoat.roughness);
        }
        scene.labels = false;
        scene
    };
    let faint = r.render_ldr(&with_weight(1e-3), w, h).unwrap().rgba;
    let bare = r.render_ldr(&with_weight(0.0), w, h).unwrap().rgba;
    assert_close(&compare(&faint, &bare, w), "coat weight 1e-3 against none");
}

/// The same on GL (`--backend auto` may land there).
#[test]
fn clearcoat_gl_matches_cpu() {
    let (w, h) = (320, 180);
    let mut r = renderer(wgpu::Backends::GL);
    let (gpu, cpu) = crate::pixels::both(&mut r, &lit_chart(0.5), w, h);
    assert_close(&compare(&gpu, &cpu, w), "GL, lit chart, physical coat");
}

/// White bases (metallic 0, 0.5, 1 down the rows) under coats of every roughness (across),
/// for one weight and coat index, in the white furnace.
fn furnace_chart(weight: f64, ior: f64) -> Scene {
    const METALLIC: [f64; 3] = [0.0, 0.5, 1.0];
    const ROUGHNESS: [f64; 5] = [0.02, 0.2, 0.4, 0.7, 1.0];
    let mut scene = chart(3, 5, |r, c| {
        let c = ClearCoat {
            weight,
            roughness: ROUGHNESS[c],
            ior,
        };
        (
            0.5,
            Material::metallic_roughness(DVec3::ONE, METALLIC[r], 1.5).with_clearcoat(c),
            Model::KullaConty,
        )
    });
    scene.environment = DVec3::ONE;
    scene
}

/// White bases under the physical coat vanish in the white furnace within 1/255 on the GPU
/// (every weight, coat roughness and index, the uniform environment and the white map), on
/// the CPU twin too; the engines' forms are negative controls that must fail it.
#[test]
fn clearcoat_white_furnace() {
    let (w, h) = (480, 270);
    let mut gpu = vulkan();
    for weight in [0.25, 0.5, 1.0] {
        for ior in [1.2, 1.5, 2.0] {
            let scene = furnace_chart(weight, ior);
            let what = format!("weight {weight}, coat IOR {ior}");
            let image = gpu.render_ldr(&scene, w, h).unwrap().rgba;
            let (worst, k) = furnace_worst(&scene, &image, w, h);
            println!("{what}: GPU {worst}/255 (ball {k})");
            assert!(worst <= 1, "{what}: GPU ball {k} is {worst}/255 off");
            if ior == 1.5 {
                let cpu = crate::pixels::both(&mut gpu, &scene, w, h).1;
                let (worst, k) = furnace_worst(&scene, &cpu, w, h);
                assert!(worst <= 1, "{what}: CPU ball {k} is {worst}/255 off");
                let mut map = scene.clone();
                map.environment = DVec3::ZERO;
                map.environment_map = Some(Environment::builtin(Builtin::White));
                let image = gpu.render_ldr(&map, w, h).unwrap().rgba;
                let (worst, k) = furnace_worst(&map, &image, w, h);
                println!("{what}, white map: GPU {worst}/255 (ball {k})");
                assert!(
                    worst <= 1,
                    "{what}, white map: GPU ball {k} is {worst}/255 off"
                );
            }
        }
    }
    // The negative controls: the engines' forms lose energy under a rough coat.
    for form in [CoatForm::Filament, CoatForm::Gltf] {
        let mut scene = furnace_chart(1.0, 1.5);
        scene.coat_form = form;
        let image = gpu.render_ldr(&scene, w, h).unwrap().rgba;
        let (worst, k) = furnace_worst(&scene, &image, w, h);
        println!("{form} coat, weight 1: GPU {worst}/255 (ball {k})");
        assert!(
            worst >= 5,
            "{form} coat: expected to fail the furnace, worst {worst}/255"
        );
    }
}

/// The conductor's albedo at `mu` by the walk's own estimator (`walk::trace`, escaping mass
/// summed: independent of `Layered`'s drawn exits).
fn conductor_albedo(roughness: f64, f0: [f64; 3], mu: f64, paths: u32, seed: u64) -> [f64; 3] {
    let s = Microsurface::new(roughness);
    let channels = f0.map(Schlick);
    let mut rng = Rng::new(&[seed]);
    let mut sum = [0.0; 3];
    for _ in 0..paths {
        trace(
            &s,
            crate::walk::incident(mu),
            &channels,
            u32::MAX,
            &mut rng,
            |_, _, mass, w| {
                for k in 0..3 {
                    sum[k] += mass * w[k];
                }
            },
            |_, _, _, _, _| {},
        );
    }
    sum.map(|s| s / f64::from(paths))
}

fn layered(coat: ClearCoat, metallic: f64, roughness: f64, base: [f64; 3], ior: f64) -> Layered {
    Layered {
        coat: Coating::new(coat.roughness, coat.ior),
        weight: coat.weight,
        metallic,
        metal: Microsurface::new(roughness),
        f0: base,
        plastic: Coating::new(roughness, ior),
        rho: base,
    }
}

/// The walk's laws, each able to fail: the white furnace at every weight and coat
/// roughness over a white conductor and a white plastic; a coat of weight 0 is the bare
/// base (against the conductor's own estimator and the plastic's walk); a coat of index 1
/// is no interface; a smooth coat over a Lambertian base (a plastic of index 1) meets the
/// closed form.
#[test]
fn clearcoat_walk_laws() {
    let paths = 4000;
    let mut rng = Rng::new(&[36]);
    for metallic in [0.0, 1.0] {
        for weight in [0.3, 1.0] {
            for r in [0.02, 0.3, 0.7, 1.0] {
                let l = layered(coat(weight, r), metallic, 0.5, [1.0; 3], 1.5);
                for mu in [0.2, 0.7] {
                    let (mean, se) = l.albedo(mu, paths, &mut rng);
                    let what = format!("metallic {metallic}, weight {weight}, coat r {r}, mu {mu}");
                    // A lossless path weighs exactly 1: a lost or cut path shows.
                    assert!(
                        (mean[0] - 1.0).abs() <= 3.0 * se[0] + 1e-9,
                        "{what}: furnace {mean:?} +- {se:?}"
                    );
                }
            }
        }
    }
    let (base, mu) = ([0.9, 0.5, 0.1], 0.6);
    // Weight 0 against the bare bases' own walks.
    let bare = layered(coat(0.0, 0.3), 1.0, 0.4, base, 1.5);
    let (mean, se) = bare.albedo(mu, 20_000, &mut rng);
    let reference = conductor_albedo(0.4, base, mu, 20_000, 5);
    for k in 0..3 {
        assert!(
            (mean[k] - reference[k]).abs() <= 4.0 * se[k] + 2e-3,
            "conductor, weight 0: {mean:?} +- {se:?} against {reference:?}"
        );
    }
    let bare = layered(coat(0.0, 0.3), 0.0, 0.4, base, 1.5);
    let (mean, se) = bare.albedo(mu, 20_000, &mut rng);
    let (reference, rse) = Coating::new(0.4, 1.5).albedo(mu, &base, 20_000, &mut rng);
    for k in 0..3 {
        let tolerance = 4.0 * (se[k] * se[k] + rse[k] * rse[k]).sqrt();
        assert!(
            (mean[k] - reference[k]).abs() <= tolerance,
            "plastic, weight 0: {mean:?} +- {se:?} against {reference:?}"
        );
    }
    // Index 1: the coat is no interface at all.
    let invisible = layered(
        ClearCoat {
            ior: 1.0,
            ..coat(1.0, 0.3)
        },
        1.0,
        0.4,
        base,
        1.5,
    );
    let (mean, se) = invisible.albedo(mu, 20_000, &mut rng);
    for k in 0..3 {
        assert!(
            (mean[k] - reference_conductor(k)).abs() <= 4.0 * se[k] + 2e-3,
            "coat of index 1: {mean:?} +- {se:?}"
        );
    }
    fn reference_conductor(k: usize) -> f64 {
        conductor_albedo(0.4, [0.9, 0.5, 0.1], 0.6, 20_000, 5)[k]
    }
    // A smooth coat over a Lambertian base (a plastic of index 1).
    for rho in [0.2, 0.8] {
        let l = layered(coat(1.0, 0.0), 0.0, 0.5, [rho; 3], 1.0);
        let (mean, se) = l.albedo(mu, 20_000, &mut rng);
        let closed = smooth_coating_albedo(mu, 1.5, rho);
        assert!(
            (mean[0] - closed).abs() <= 3.0 * se[0] + 2e-3,
            "smooth coat over rho {rho}: {} +- {} against {closed}",
            mean[0],
            se[0]
        );
    }
    // The control: over a black plastic, the bare base reflects only its own interface
    // while a coat adds its reflection (the walk sees the coat).
    let dark = layered(coat(1.0, 0.3), 0.0, 0.4, [0.0; 3], 1.5);
    let bare = layered(coat(0.0, 0.3), 0.0, 0.4, [0.0; 3], 1.5);
    let (a, _) = dark.albedo(0.9, 20_000, &mut rng);
    let (b, _) = bare.albedo(0.9, 20_000, &mut rng);
    assert!(a[0] - b[0] > 0.02, "the coat changes nothing: {a:?} {b:?}");
}

/// The goal's chart: a red plastic, a grey plastic, copper and a half metal down the rows
/// under a full coat, (base roughness, coat roughness) of 0.3 and 0.7 across, under the
/// studio; antialiasing off (the truth traces pixel centres).
fn goal_chart() -> Scene {
    const PAIRS: [(f64, f64); 4] = [(0.3, 0.3), (0.3, 0.7), (0.7, 0.3), (0.7, 0.7)];
    let bases = [
        Material::metallic_roughness(DVec3::new(0.6, 0.05, 0.03), 0.0, 1.5),
        Material::metallic_roughness(DVec3::splat(0.5), 0.0, 1.5),
        Material::metallic_roughness(DVec3::new(0.95, 0.64, 0.54), 1.0, 1.5),
        Material::metallic_roughness(DVec3::new(0.7, 0.7, 0.3), 0.5, 1.5),
    ];
    let mut scene = chart(4, 4, |r, c| {
        let (base_r, coat_r) = PAIRS[c];
        (
            base_r,
            bases[r].with_clearcoat(coat(1.0, coat_r)),
            Model::KullaConty,
        )
    });
    if std::env::var_os("SHADEBALLS_COAT_UNIFORM").is_some() {
        scene.environment = DVec3::ONE;
    } else {
        scene.environment_map = Some(Environment::builtin(Builtin::Studio));
    }
    scene.antialias = false;
    scene
}

/// The full tables of `scene`'s geometry and each ball's inner pixels at `w` x `h`.
fn tables_and_interiors(
    scene: &Scene,
    (w, h): (u32, u32),
) -> (crate::lut::TableSet, Vec<Vec<usize>>) {
    let tables = crate::lut::bake(&crate::lut::BakeConfig {
        geometry: scene.effective_geometry(),
        ..Default::default()
    });
    let pixels = (0..scene.balls.len())
        .map(|k| interior(scene, k, w, h))
        .collect();
    (crate::lut::TableSet::full(tables), pixels)
}

/// The standard error of each ball's mean over `pixels`, from a Monte Carlo image's
/// per-pixel standard errors.
fn ball_errors(std_error: &[DVec3], pixels: &[Vec<usize>]) -> Vec<DVec3> {
    pixels
        .iter()
        .map(|px| {
            let var: DVec3 = px.iter().map(|&p| std_error[p].powf(2.0)).sum();
            var.powf(0.5) / px.len().max(1) as f64
        })
        .collect()
}

/// The truth's mean and standard error of each ball's mean over `pixels`. Where
/// `SHADEBALLS_COAT_TRUTH` names a file, they are read from it when it exists (written by an
/// earlier run at the same settings) and written to it otherwise: a model's figures can then
/// be measured again without walking the truth again.
fn truth_means(
    scene: &Scene,
    e: &crate::lut::TableSet,
    (w, h): (u32, u32),
    settings: crate::cpu::TruthSettings,
    pixels: &[Vec<usize>],
) -> (Vec<DVec3>, Vec<DVec3>) {
    let cache = std::env::var_os("SHADEBALLS_COAT_TRUTH").map(std::path::PathBuf::from);
    let key = format!("{w}x{h} spp {} seed {}", settings.spp, settings.seed);
    if let Some(text) = cache.as_ref().and_then(|p| std::fs::read_to_string(p).ok()) {
        let mut lines = text.lines();
        if lines.next() == Some(key.as_str()) {
            let values: Vec<f64> = lines.filter_map(|l| l.parse().ok()).collect();
            let at = |k: usize| DVec3::new(values[k], values[k + 1], values[k + 2]);
            let n = pixels.len();
            if values.len() == 6 * n {
                return (
                    (0..n).map(|k| at(3 * k)).collect(),
                    (0..n).map(|k| at(3 * (n + k))).collect(),
                );
            }
        }
    }
    let prepared = crate::prepared::Prepared::new(scene, e);
    let truth = crate::cpu::render_truth(scene, &prepared, w, h, settings, |_| true).unwrap();
    let means = ball_means(&truth.image.mean, pixels);
    let errors = ball_errors(&truth.image.std_error, pixels);
    if let Some(path) = cache {
        let mut text = key + "\n";
        for v in means.iter().chain(&errors) {
            text += &format!("{:e}\n{:e}\n{:e}\n", v.x, v.y, v.z);
        }
        std::fs::write(path, text).unwrap();
    }
    (means, errors)
}

/// Every coat form against the truth (the CPU walk through the coat over the ball's own
/// walk), ball by ball over the inner pixels of [`goal_chart`]: `--nocapture` prints each
/// ball's signed error (the channels' mean) and the worst beyond three of the truth's
/// standard errors. The goal: the physical form within 3 % per ball.
/// `SHADEBALLS_COAT_SPP` raises the truth's samples (the docs' figures: 1024).
#[test]
fn clearcoat_forms_against_the_truth() {
    let (w, h) = (320, 180);
    let spp = std::env::var("SHADEBALLS_COAT_SPP")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(96);
    let scene = goal_chart();
    let (e, pixels) = tables_and_interiors(&scene, (w, h));
    let settings = crate::cpu::TruthSettings {
        spp,
        seed: 36,
        ..Default::default()
    };
    let (t_means, t_err) = truth_means(&scene, &e, (w, h), settings, &pixels);
    let mut worst_physical = 0.0f64;
    let mut errors: Vec<Vec<f64>> = Vec::new();
    for form in CoatForm::ALL {
        let scene = Scene {
            coat_form: form,
            ..scene.clone()
        };
        let prepared = crate::prepared::Prepared::new(&scene, &e);
        let model = crate::cpu::render_radiance(&scene, &prepared, w, h);
        let m_means = ball_means(&model, &pixels);
        let (mut worst, mut beyond) = (0.0f64, 0.0f64);
        let mut line = format!("{form:>9}:");
        errors.push(Vec::new());
        for k in 0..scene.balls.len() {
            let signed = (m_means[k] - t_means[k]) / t_means[k];
            let rel = signed.abs().max_element();
            errors.last_mut().unwrap().push(rel);
            let noise = (t_err[k] / t_means[k]).max_element();
            worst = worst.max(rel);
            beyond = beyond.max(rel - 3.0 * noise);
            if k % 4 == 0 {
                line += " |";
            }
            line += &format!(" {:+.1}", 100.0 * signed.element_sum() / 3.0);
        }
        println!(
            "{line} | worst channel {:.1} %, {:.1} % beyond 3 standard errors",
            100.0 * worst,
            100.0 * beyond
        );
        if form == CoatForm::Physical {
            worst_physical = beyond;
        }
    }
    // The physical model integrated over the map by sampling (the Monte Carlo backend's
    // estimator of its BRDF: no split sum), at SHADEBALLS_COAT_MC samples per pixel: the
    // model's own error apart from the light integration's (docs/design/coat.md).
    let mc_spp = std::env::var("SHADEBALLS_COAT_MC")
        .ok()
        .and_then(|s| s.parse().ok());
    if let Some(mc_spp) = mc_spp {
        let scene = Scene {
            coat_form: CoatForm::Physical,
            ..scene.clone()
        };
        let prepared = crate::prepared::Prepared::new(&scene, &e);
        let mc = crate::cpu::render_montecarlo(&scene, &prepared, w, h, mc_spp, 37).unwrap();
        let m_means = ball_means(&mc.mean, &pixels);
        let mut line = "physical, sampled:".to_string();
        let mut worst = 0.0;
        for k in 0..scene.balls.len() {
            let signed = (m_means[k] - t_means[k]) / t_means[k];
            worst += signed.abs().max_element() / scene.balls.len() as f64;
            if k % 4 == 0 {
                line += " |";
            }
            line += &format!(" {:+.1}", 100.0 * signed.element_sum() / 3.0);
        }
        println!(
            "{line} | mean of the balls' worst channel {:.1} %",
            100.0 * worst
        );
    }
    let noise = t_err
        .iter()
        .zip(&t_means)
        .map(|(e, m)| (*e / *m).max_element())
        .fold(0.0, f64::max);
    println!(
        "the truth at {spp} spp: largest relative standard error of a ball's mean {:.2} %",
        100.0 * noise
    );
    // The 3 % goal is not met on every ball (docs/design/coat.md, "Against the truth").
    // Held here: the measured worst with room (6.8 % beyond the noise at 96 spp), and the
    // physical form closer to the truth than both engines' forms over the chart (the mean
    // of the balls' worst channel).
    let mean = |e: &[f64]| e.iter().sum::<f64>() / e.len() as f64;
    let means: Vec<f64> = errors.iter().map(|e| mean(e)).collect();
    println!(
        "mean of the balls' worst channel: physical {:.1} %, filament {:.1} %, gltf {:.1} %",
        100.0 * means[0],
        100.0 * means[1],
        100.0 * means[2]
    );
    assert!(
        worst_physical <= 0.15,
        "the physical coat is {:.1} % beyond the truth's noise",
        100.0 * worst_physical
    );
    assert!(
        means[0] < means[1] && means[0] < means[2],
        "the physical form is not the closest over the chart: {means:?}"
    );
}

/// A map black but for a sun: a radiance of 1e4 over the texels whose centres lie in a
/// cap of 1e-3 of the sphere about unit direction `sun` (issue 37's sun, without its sky);
/// and the directional light its texels add up to (their irradiance on a surface facing
/// the sun, from their solid-angle-weighted mean direction).
fn sun_and_its_light(sun: DVec3) -> (Environment, Light) {
    use crate::environment::{uv_to_direction, EnvMap, Source};
    const RADIANCE: f64 = 1e4;
    let (w, h) = (256u32, 128u32);
    let cos_cap = 1.0 - 2.0 * 1e-3;
    let mut texels = Vec::new();
    let mut sun_texels = Vec::new();
    for j in 0..h {
        for i in 0..w {
            let uv = glam::DVec2::new(
                (f64::from(i) + 0.5) / f64::from(w),
                (f64::from(j) + 0.5) / f64::from(h),
            );
            let d = uv_to_direction(uv);
            let lit = d.dot(sun) >= cos_cap;
            if lit {
                sun_texels.push((d, j));
            }
            texels.push([if lit { RADIANCE as f32 } else { 0.0 }; 3]);
        }
    }
    let map = EnvMap::new(w, h, texels).unwrap();
    let axis: DVec3 = sun_texels
        .iter()
        .map(|&(d, j)| d * map.texel_solid_angle(j))
        .sum();
    let direction = axis.normalize();
    let irradiance: f64 = sun_texels
        .iter()
        .map(|&(d, j)| RADIANCE * map.texel_solid_angle(j) * d.dot(direction).max(0.0))
        .sum();
    let environment = Environment {
        source: Source::File("sun".into()),
        map: std::sync::Arc::new(map),
        rotation_deg: 0.0,
        intensity: 1.0,
    };
    let light = Light::new(direction, DVec3::splat(irradiance));
    (environment, light)
}

/// Coated balls under a directional light against their truth. The truth walks no light
/// through a coat, so it walks under a map black but for a small sun
/// ([`sun_and_its_light`]), and the model (the CPU twin) is lit by the light the sun's
/// texels add up to. Copper and a red plastic of roughness 0.4 under a full coat of
/// roughness 1, the sun up and to the left in front of them: the base's lobe leaves the
/// coat wider under the lights too (`clearcoat_base_lobe`), and its Fresnel is read inside
/// the coat (`clearcoat_base_fresnel_cosine`). Held: each ball's worst channel within 3 %
/// beyond 3 of the truth's standard errors (measured: copper -0.7, -1.6, -2.2 %, the red
/// plastic +2.2, -2.9, -3.4 %, whose green and blue are mostly the coat's own light,
/// standard errors 2.9 and 3.2 %; -1.1, -4.8, -5.1 % with the plastic's Fresnel read at the
/// outside cosines). With the base's own lobe under the lights (before the widening)
/// copper is 30 % under and the test fails.
#[test]
fn coated_balls_under_a_light_meet_their_truth_under_a_sun() {
    let (w, h) = (240, 135);
    let spp = 1024;
    let bases = [
        Material::metallic_roughness(DVec3::new(0.95, 0.64, 0.54), 1.0, 1.5),
        Material::metallic_roughness(DVec3::new(0.8, 0.1, 0.08), 0.0, 1.5),
    ];
    let mut truth_scene = chart(1, 2, |_, c| {
        (
            0.4,
            bases[c].with_clearcoat(coat(1.0, 1.0)),
            Model::KullaConty,
        )
    });
    truth_scene.antialias = false;
    truth_scene.environment = DVec3::ZERO;
    let (map, light) = sun_and_its_light(DVec3::new(-0.45, 0.55, 0.7).normalize());
    truth_scene.environment_map = Some(map);
    let mut lit_scene = truth_scene.clone();
    lit_scene.environment_map = None;
    lit_scene.lights = vec![light];
    let (e, pixels) = tables_and_interiors(&truth_scene, (w, h));
    let settings = crate::cpu::TruthSettings {
        spp,
        seed: 36,
        ..Default::default()
    };
    let prepared = crate::prepared::Prepared::new(&truth_scene, &e);
    let truth =
        crate::cpu::render_truth(&truth_scene, &prepared, w, h, settings, |_| true).unwrap();
    let t_means = ball_means(&truth.image.mean, &pixels);
    let t_err = ball_errors(&truth.image.std_error, &pixels);
    let prepared = crate::prepared::Prepared::new(&lit_scene, &e);
    let model = crate::cpu::render_radiance(&lit_scene, &prepared, w, h);
    let m_means = ball_means(&model, &pixels);
    for (k, (name, bound)) in [("copper", 0.03), ("red plastic", 0.03)].iter().enumerate() {
        let noise = t_err[k] / t_means[k];
        let signed = (m_means[k] - t_means[k]) / t_means[k];
        let beyond = (signed.abs() - 3.0 * noise).max_element();
        println!(
            "{name}: truth {:.4} {:.4} {:.4} (relative standard error {:.2} {:.2} {:.2} %), \
             model under the light {:+.1} {:+.1} {:+.1} %",
            t_means[k].x,
            t_means[k].y,
            t_means[k].z,
            100.0 * noise.x,
            100.0 * noise.y,
            100.0 * noise.z,
            100.0 * signed.x,
            100.0 * signed.y,
            100.0 * signed.z
        );
        assert!(
            beyond <= *bound,
            "{name} under the light is {:.1} % beyond 3 of its truth's standard errors",
            100.0 * beyond
        );
    }
}

/// A glossy base's Fresnel under a coat is read inside it: a black metal (`F0 = 0`) under
/// a full coat of roughness 0.3 and 1, base roughness 0.4, under uniform light, the CPU
/// model against the truth (whose metal sees the refracted directions, all within the
/// coat's critical cone, where Schlick's `F` of `F0 = 0` is at most 1.1e-3 at index 1.5).
/// Held: each ball within 20 % of its walk (measured: -1.4 % and -11.9 %, the rough coat's
/// own shortfall, docs/design/coat.md "Under a sun"). With the Fresnel read at the outside
/// cosines, where it rises to 1 at grazing, the ball under the coat of roughness 0.3 is
/// 41.5 % over its walk and the test fails.
#[test]
fn a_black_metal_under_a_coat_is_as_dark_as_its_walk() {
    const COAT_ROUGHNESS: [f64; 2] = [0.3, 1.0];
    let (w, h) = (160, 90);
    let black = Material::metallic_roughness(DVec3::ZERO, 1.0, 1.5);
    let mut scene = chart(1, 2, |_, c| {
        (
            0.4,
            black.with_clearcoat(coat(1.0, COAT_ROUGHNESS[c])),
            Model::KullaConty,
        )
    });
    scene.antialias = false;
    scene.environment = DVec3::ONE;
    let (e, pixels) = tables_and_interiors(&scene, (w, h));
    let settings = crate::cpu::TruthSettings {
        spp: 256,
        seed: 36,
        ..Default::default()
    };
    let prepared = crate::prepared::Prepared::new(&scene, &e);
    let truth = crate::cpu::render_truth(&scene, &prepared, w, h, settings, |_| true).unwrap();
    let t_means = ball_means(&truth.image.mean, &pixels);
    let t_err = ball_errors(&truth.image.std_error, &pixels);
    let model = crate::cpu::render_radiance(&scene, &prepared, w, h);
    let m_means = ball_means(&model, &pixels);
    for (k, roughness) in COAT_ROUGHNESS.into_iter().enumerate() {
        let signed = (m_means[k].x - t_means[k].x) / t_means[k].x;
        println!(
            "coat roughness {roughness}: truth {:.4} (standard error {:.4}), model {:.4}, \
             {:+.1} %",
            t_means[k].x,
            t_err[k].x,
            m_means[k].x,
            100.0 * signed
        );
        assert!(
            signed.abs() <= 0.2,
            "a black metal under a coat of roughness {roughness} is {:+.1} % off its walk",
            100.0 * signed
        );
    }
}

/// The coat alone against its walk, order by order: the walk over a black base (so only
/// the interface sends light back), its exits split into the first-order reflection, the
/// paths that reflect between facets only, and those that went into the coat and came
/// back out without the base. The law that can fail: the first order is the model's
/// single scattering `E_F(mu)` (the coating row's quadrature, height-correlated G, exact
/// Fresnel) within 4 standard errors. `--nocapture` prints the model's term `f_add (1 -
/// E(mu))` beside the walk's two multiple parts (docs/design/coat.md, "Under a sun": the
/// term falls short of the first part near grazing and has nothing for the second).
/// Held too, as measured: the model's coat albedo is at most 0.03 under the walk's (0.026
/// at coat roughness 0.3 and mu 0.1, where the walk's light between facets is 28 times the
/// term's).
#[test]
fn a_coat_alone_against_its_walk_order_by_order() {
    use crate::brdf::{f_add_accurate, f_avg_dielectric, DielectricFresnel, Geometry};
    use crate::lut::{coating_albedo_quadrature, CoatingKey, CoatingRule};
    use crate::walk::coating::{Event, Visit};
    /// Each exit's weight by its kind: first order, between facets only, through the coat.
    struct ByOrder {
        went_in: bool,
        sums: [f64; 3],
        first_sq: f64,
    }
    impl Visit for ByOrder {
        fn event(&mut self, event: &Event<'_>, _: &[f64]) {
            self.went_in |= event.inside;
        }
        fn exit(&mut self, order: u32, _: DVec3, weights: &[f64]) {
            let kind = match (self.went_in, order) {
                (true, _) => 2,
                (false, 1) => 0,
                (false, _) => 1,
            };
            self.sums[kind] += weights[0];
            if kind == 0 {
                self.first_sq += weights[0] * weights[0];
            }
        }
    }
    const ETA: f64 = 1.5;
    const PATHS: u32 = 400_000;
    let tables = crate::lut::bake(&crate::lut::BakeConfig {
        geometry: Geometry::SmithCorrelated,
        ..Default::default()
    });
    let e = crate::lut::TableSet::full(tables);
    let rule = CoatingRule::default();
    let f_avg = f_avg_dielectric(ETA);
    let mut worst_short = 0.0f64;
    for roughness in [0.3, 0.7, 1.0] {
        let coating = Coating::new(roughness, ETA);
        let key = CoatingKey::new(
            roughness,
            ETA,
            DielectricFresnel::Exact,
            Geometry::SmithCorrelated,
        );
        let e_avg = 1.0 - f64::from(e.lut_loss_avg(roughness as f32));
        let f_add = f_add_accurate(f_avg, e_avg);
        for mu in [0.1, 0.3, 0.5, 0.7, 0.9] {
            let mut rng = Rng::new(&[36, (100.0 * mu) as u64]);
            let mut by = ByOrder {
                went_in: false,
                sums: [0.0; 3],
                first_sq: 0.0,
            };
            for _ in 0..PATHS {
                by.went_in = false;
                coating.walk(
                    crate::walk::incident(mu),
                    &[0.0],
                    u32::MAX,
                    &mut rng,
                    &mut by,
                );
            }
            let n = f64::from(PATHS);
            let [first, between, through] = by.sums.map(|x| x / n);
            let first_se = ((by.first_sq / n - first * first).max(0.0) / (n - 1.0)).sqrt();
            let e_f = coating_albedo_quadrature(&rule, mu, &key);
            let term = f_add * f64::from(e.lut_loss(mu as f32, roughness as f32));
            let short = first + between + through - (e_f + term);
            worst_short = worst_short.max(short);
            println!(
                "coat roughness {roughness}, mu {mu}: first order {first:.5} (E_F {e_f:.5}), \
                 between facets {between:.5}, through the coat {through:.5}; the model's \
                 term {term:.5}, short by {short:.5}"
            );
            assert!(
                (first - e_f).abs() <= 4.0 * first_se + 1e-4,
                "the walk's first order {first} is not E_F {e_f} (standard error {first_se})"
            );
        }
    }
    assert!(
        worst_short <= 0.03,
        "the model's coat is {worst_short} under its walk"
    );
}
