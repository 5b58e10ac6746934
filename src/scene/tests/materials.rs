//! Materials as engines have them (docs/design/materials.md): the coating's tables, the
//! scene's material keys, the furnace of every metallic value, the layering forms.

use crate::brdf::{DielectricFresnel, Geometry};

use crate::lut::{
    coating_albedo, coating_albedo_quadrature, coating_row, CoatingKey, CoatingRule,
    COATING_ROW_LEN,
};

use crate::walk::single::{single_albedo, Rules};

use crate::walk::{Dielectric, Schlick};

/// The coating's albedo against the precise quadrature of `walk::single_albedo` (48 x 48
/// nodes a segment, peak-mapped), at the nodes and as read between them.
#[test]
fn coating_rows_meet_the_precise_quadrature() {
    let rules = Rules::default();
    let rule = CoatingRule::default();
    let mut worst_node = 0.0f64;
    let mut worst_read = 0.0f64;
    let mut worst_read_above = 0.0f64;
    for geometry in Geometry::ALL {
        for r in [0.02, 0.05, 0.15, 0.35, 0.6, 1.0] {
            for eta in [1.1, 1.33, 1.5, 2.0, 2.5] {
                for fresnel in [DielectricFresnel::Exact, DielectricFresnel::Schlick] {
                    let key = CoatingKey::new(r, eta, fresnel, geometry);
                    let row = coating_row(&rule, &key);
                    for j in 0..=40 {
                        let mu = (j as f64 / 40.0).max(0.002);
                        let exact = match fresnel {
                            DielectricFresnel::Exact => single_albedo(
                                &rules,
                                mu,
                                key.roughness(),
                                &[Dielectric(key.eta())],
                                &[geometry],
                            )[0][0],
                            DielectricFresnel::Schlick => single_albedo(
                                &rules,
                                mu,
                                key.roughness(),
                                &[Schlick(crate::brdf::f0_from_ior(key.eta()))],
                                &[geometry],
                            )[0][0],
                        };
                        let node = (coating_albedo_quadrature(&rule, mu, &key) - exact).abs();
                        let read = (f64::from(coating_albedo(&row, mu as f32)) - exact).abs();
                        worst_node = worst_node.max(node);
                        worst_read = worst_read.max(read);
                        if mu >= 0.01 {
                            worst_read_above = worst_read_above.max(read);
                        }
                    }
                }
            }
        }
    }
    println!("worst node {worst_node:.2e} read {worst_read:.2e}, {worst_read_above:.2e} at mu >= 0.01 ({COATING_ROW_LEN} values a row)");
    // Thresholds: the measured worst with a little room: 1.3e-3 at the nodes (at mu =
    // 0.002 and roughness 0.02, where E_F changes over a span of mu of about alpha), 8.8e-4
    // as read from mu = 0.01 up, 4.8e-3 as read below.
    assert!(worst_node < 2e-3, "{worst_node}");
    assert!(worst_read_above < 1.2e-3, "{worst_read_above}");
    assert!(worst_read < 1e-2, "{worst_read}");
}

/// What the coating's rows cost at startup: the 15 of `plastic.toml` (3 indices x 5
/// roughness values), printed (docs/design/materials.md quotes it).
#[test]
fn coating_rows_bake_time() {
    let keys: Vec<CoatingKey> = [1.33, 1.5, 2.0]
        .iter()
        .flat_map(|&eta| {
            crate::scene::REFERENCE_ROUGHNESS.map(|r| {
                CoatingKey::new(r, eta, DielectricFresnel::Exact, Geometry::SmithCorrelated)
            })
        })
        .collect();
    let mut times = Vec::new();
    for _ in 0..5 {
        let start = std::time::Instant::now();
        let rows = crate::lut::CoatingRows::bake(keys.iter().copied(), &mut Default::default());
        times.push(start.elapsed().as_secs_f64() * 1e3);
        assert_eq!(rows.rows.len(), 15);
    }
    times.sort_by(f64::total_cmp);
    println!("15 coating rows: median {:.2} ms", times[2]);
}

use glam::DVec3;

use crate::environment::IblTerm;

use crate::scene::{Ball, Camera, Layering, Material, Model, Scene};

use crate::pixels::{assert_close, compare, renderer, vulkan};

use crate::scene::Preset;

/// Balls on a `rows x cols` grid (step 80 across, 90 down, radius 35, y up), looked at
/// head on through an 18 degree field of view from far enough to frame them at 16:9.
pub(crate) fn chart(
    rows: usize,
    cols: usize,
    ball: impl Fn(usize, usize) -> (f64, Material, Model),
) -> Scene {
    let mut balls = Vec::new();
    for r in 0..rows {
        for c in 0..cols {
            let (roughness, material, model) = ball(r, c);
            balls.push(Ball {
                center: DVec3::new(
                    80.0 * (c as f64 - (cols - 1) as f64 / 2.0),
                    90.0 * ((rows - 1) as f64 / 2.0 - r as f64),
                    0.0,
                ),
                radius: 35.0,
                roughness,
                material,
                model,
                label: None,
            });
        }
    }
    let height = (90.0 * rows as f64 + 60.0).max((80.0 * cols as f64 + 60.0) * 9.0 / 16.0);
    let z = height / (2.0 * 9f64.to_radians().tan());
    Scene {
        balls,
        lights: Vec::new(),
        camera: Camera {
            position: DVec3::new(0.0, 0.0, z),
            target: DVec3::ZERO,
            vfov_deg: 18.0,
            min_aspect: None,
        },
        labels: false,
        ..Scene::reference()
    }
}

/// Pixels whose centre ray and its 4 neighbours' hit ball `k` (no silhouette).
pub(crate) fn interior(scene: &Scene, k: usize, w: u32, h: u32) -> Vec<usize> {
    let basis = scene.camera.basis(w, h);
    let b = &scene.balls[k];
    let hit = |x: u32, y: u32| {
        crate::cpu::intersect_sphere(basis.origin, basis.ray(x, y, w, h), b.center, b.radius) > 0.0
    };
    let mut out = Vec::new();
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            if [(x, y), (x - 1, y), (x + 1, y), (x, y - 1), (x, y + 1)]
                .iter()
                .all(|&(a, b)| hit(a, b))
            {
                out.push((y * w + x) as usize);
            }
        }
    }
    out
}

/// The white furnace of the materials issue: white base (`base_color` 1), metallic 0 to 1
/// down the rows, roughness 0.05 to 1 across, the term on, for one IOR.
fn furnace_chart(ior: f64, term: IblTerm) -> Scene {
    const METALLIC: [f64; 5] = [0.0, 0.25, 0.5, 0.75, 1.0];
    const ROUGHNESS: [f64; 6] = [0.05, 0.2, 0.4, 0.6, 0.8, 1.0];
    let mut scene = chart(5, 6, |r, c| {
        (
            ROUGHNESS[c],
            Material::metallic_roughness(DVec3::ONE, METALLIC[r], ior),
            Model::from_term(term),
        )
    });
    scene.environment = DVec3::ONE;
    scene
}

/// The largest difference, in 1/255, of any interior pixel of any ball of `image` from
/// the background (the corner pixel, which no ball covers), and the ball it is on.
pub(crate) fn furnace_worst(scene: &Scene, image: &[u8], w: u32, h: u32) -> (u8, usize) {
    let bg = [image[0], image[1], image[2]];
    let mut worst = (0, 0);
    for k in 0..scene.balls.len() {
        let px = interior(scene, k, w, h);
        assert!(
            px.len() > 100,
            "ball {k} covers {} interior pixels",
            px.len()
        );
        for p in px {
            for c in 0..3 {
                let d = image[4 * p + c].abs_diff(bg[c]);
                if d > worst.0 {
                    worst = (d, k);
                }
            }
        }
    }
    worst
}

/// Every metallic value, IOR and roughness vanishes in the white furnace with the term,
/// under every energy-conserving layering form and every term, on the GPU and the CPU,
/// under the uniform environment and through the map path (`builtin = "white"`).
#[test]
fn white_furnace_every_metallic_ior_and_roughness() {
    // Half the size it was (640x360), for CI's time: a ball still covers hundreds of
    // pixels, and the check is each ball's worst pixel.
    let (w, h) = (320, 180);
    let mut gpu = vulkan();
    let white = crate::environment::Builtin::White;
    for ior in [1.1, 1.33, 1.5, 2.0, 2.5] {
        for term in IblTerm::ALL {
            for layering in [Layering::ViewOnly, Layering::Reciprocal, Layering::Physical] {
                let mut scene = furnace_chart(ior, term);
                scene.layering = layering;
                let what = format!("IOR {ior}, {term}, {layering}");
                let image = gpu.render_ldr(&scene, w, h).unwrap().rgba;
                let (worst, k) = furnace_worst(&scene, &image, w, h);
                println!("{what}: GPU {worst}/255 (ball {k})");
                // The goal: within 1/255 of the background.
                assert!(worst <= 1, "{what}: GPU ball {k} is {worst}/255 off");
                // The CPU twin and the map path for the default form, every term.
                if layering == Layering::Physical {
                    let cpu = crate::pixels::both(&mut gpu, &scene, w, h).1;
                    let (worst, k) = furnace_worst(&scene, &cpu, w, h);
                    assert!(worst <= 1, "{what}: CPU ball {k} is {worst}/255 off");
                    let mut map = scene.clone();
                    map.environment = DVec3::ZERO;
                    map.environment_map = Some(crate::environment::Environment::builtin(white));
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
    }
    // The check can fail: the design before (the constant form) and the balls without
    // the term show in the same furnace (the issue measured 0.949 at roughness 0.95).
    let mut constant = furnace_chart(1.5, IblTerm::KullaConty);
    constant.layering = Layering::Constant;
    let image = gpu.render_ldr(&constant, w, h).unwrap().rgba;
    let (worst, _) = furnace_worst(&constant, &image, w, h);
    println!("constant form: {worst}/255");
    assert!(
        worst >= 3,
        "the constant form passes the furnace ({worst}/255)"
    );
    let mut none = furnace_chart(1.5, IblTerm::KullaConty);
    none.balls.iter_mut().for_each(|b| b.model = Model::None);
    let image = gpu.render_ldr(&none, w, h).unwrap().rgba;
    let (worst, _) = furnace_worst(&none, &image, w, h);
    println!("without the term: {worst}/255");
    assert!(
        worst >= 3,
        "the balls without the term pass the furnace ({worst}/255)"
    );
}

/// Per ball, the mean of `image` over `pixels[k]`.
pub(crate) fn ball_means(image: &[DVec3], pixels: &[Vec<usize>]) -> Vec<DVec3> {
    pixels
        .iter()
        .map(|px| px.iter().map(|&p| image[p]).sum::<DVec3>() / px.len().max(1) as f64)
        .collect()
}

/// `plastic.toml` (antialiasing off: the truth traces pixel centres, like with like) under
/// its own studio map or the reference scene's light from the camera (no map).
fn plastic_scene(studio: bool) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/plastic.toml");
    let mut scene = crate::scene::load(&path).unwrap();
    scene.antialias = false;
    assert!(scene.environment_map.is_some() && scene.lights.is_empty());
    if !studio {
        scene.environment_map = None;
        scene.background = Scene::reference().background;
        scene.lights = Scene::reference().lights;
    }
    scene
}

/// Every layering form against the truth (the random walk through the coating over the
/// substrate, `cpu::render_truth`) on every ball of `plastic.toml`, under its light and
/// under the studio: the relative error of each ball's mean radiance over its inner
/// pixels (largest channel), with the truth's own standard error beside it. The goal: the
/// physical form within 5 % on every plastic ball with the term, beyond 3 of the truth's
/// standard errors (under the studio its walk only finds the map by its exits, so its
/// noise is several per cent at this budget; the rows without the term leave
/// out the coating's multiple scattering, as the metals' do: they are reported, not held
/// to it). `--nocapture` prints the table docs/design/materials.md quotes (the mean of the
/// channels' signed errors, per ball, rows of five).
#[test]
fn layering_forms_against_the_truth_on_plastic_toml() {
    let (w, h) = (320, 180);
    for studio in [false, true] {
        let scene = plastic_scene(studio);
        let light = if studio { "studio" } else { "reference light" };
        let tables = crate::lut::bake(&crate::lut::BakeConfig {
            geometry: scene.effective_geometry(),
            ..Default::default()
        });
        let e = crate::lut::TableSet::full(tables.clone());
        let settings = crate::cpu::TruthSettings {
            spp: if studio { 256 } else { 64 },
            seed: 11,
            ..Default::default()
        };
        let truth = crate::cpu::render_truth(
            &scene,
            &crate::prepared::Prepared::new(&scene, &e),
            w,
            h,
            settings,
            |_| true,
        )
        .unwrap();
        let pixels: Vec<Vec<usize>> = (0..scene.balls.len())
            .map(|k| interior(&scene, k, w, h))
            .collect();
        let t_means = ball_means(&truth.image.mean, &pixels);
        let t_err: Vec<DVec3> = pixels
            .iter()
            .map(|px| {
                let var: DVec3 = px.iter().map(|&p| truth.image.std_error[p].powf(2.0)).sum();
                var.powf(0.5) / px.len().max(1) as f64
            })
            .collect();
        let mut worst_physical = 0.0f64;
        for layering in Layering::ALL {
            let scene = Scene {
                layering,
                ..scene.clone()
            };
            let model = crate::cpu::render_radiance(
                &scene,
                &crate::prepared::Prepared::new(&scene, &e),
                w,
                h,
            );
            let m_means = ball_means(&model, &pixels);
            let mut line = format!("{light}, {layering:>10}:");
            let (mut worst, mut worst_term) = (0.0f64, 0.0f64);
            for k in 0..scene.balls.len() {
                let rel = ((m_means[k] - t_means[k]) / t_means[k]).abs().max_element();
                worst = worst.max(rel);
                // Held to the goal beyond the truth's own noise: 3 of its standard errors.
                let noise = (t_err[k] / t_means[k]).max_element();
                if scene.balls[k].model.has_term() {
                    worst_term = worst_term.max(rel - 3.0 * noise);
                }
                if k % 5 == 0 {
                    line += " |";
                }
                line += &format!(
                    " {:+.1}",
                    100.0 * ((m_means[k] - t_means[k]) / t_means[k]).element_sum() / 3.0
                );
            }
            println!(
                "{line} | worst {:.1} %, {:.1} % with the term beyond 3 standard errors",
                100.0 * worst,
                100.0 * worst_term
            );
            if layering == Layering::Physical {
                worst_physical = worst_term;
            }
        }
        let noise = t_err
            .iter()
            .zip(&t_means)
            .map(|(e, m)| (*e / *m).max_element())
            .fold(0.0, f64::max);
        println!(
            "{light}: the truth's largest relative standard error of a ball's mean {:.2} %",
            100.0 * noise
        );
        assert!(
            worst_physical <= 0.05,
            "{light}: the physical form is {:.1} % beyond the truth's noise on a ball with the term",
            100.0 * worst_physical
        );
    }
}

/// A scene file of `assets/scenes`.
fn asset_scene(name: &str) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/scenes")
        .join(name);
    crate::scene::load(&path).unwrap()
}

/// The GPU and its CPU twin within the house's bound (99.9 % of pixels within 1/255) on
/// the materials' scenes: `plastic.toml` under every layering form and `presets`, and
/// the metallic-roughness chart under the studio with every term, on `backends`.
fn materials_match_cpu(backends: wgpu::Backends, what: &str, presets: &[Preset]) {
    // 192x108 (it was 320x180, for CI's time): every ball keeps its interior and its
    // silhouette, and the bound is per pixel.
    let (w, h) = (192, 108);
    let mut r = renderer(backends);
    for &preset in presets {
        for layering in Layering::ALL {
            let scene = Scene {
                preset,
                layering,
                ..asset_scene("plastic.toml")
            };
            let (gpu, cpu) = crate::pixels::both(&mut r, &scene, w, h);
            assert_close(
                &compare(&gpu, &cpu, w),
                &format!("{what} vs CPU, plastic.toml, {preset}, {layering}"),
            );
        }
    }
    for term in IblTerm::ALL {
        let scene = asset_scene("metallic_roughness.toml").with_term(term);
        let (gpu, cpu) = crate::pixels::both(&mut r, &scene, w, h);
        assert_close(
            &compare(&gpu, &cpu, w),
            &format!("{what} vs CPU, metallic_roughness.toml, {term}"),
        );
    }
}

#[test]
fn materials_vulkan_matches_cpu() {
    materials_match_cpu(wgpu::Backends::VULKAN, "Vulkan", &Preset::ALL);
}

/// GL under the accurate preset only (for CI's time): the presets change the tables and
/// the geometry term, which Vulkan's twin covers; GL's own risk is the translated shader,
/// which every layering form and term still runs through here.
#[test]
fn materials_gl_matches_cpu() {
    materials_match_cpu(wgpu::Backends::GL, "GL", &[Preset::Accurate]);
}

/// The material keys of a scene file: `base_color` (sRGB curve), `metallic`, `ior`; the
/// shorthands as before; every bad combination or value a one-line error naming the line.
#[test]
fn material_keys_parse_and_refuse_in_one_line() {
    let ball = |material: &str| {
        format!("[[ball]]\ngrid = [0, 0]\nradius = 35\nroughness = 0.5\nmaterial = {material}\n")
    };
    let parse = |text: &str| crate::scene::parse(text, std::path::Path::new("m.toml"));
    let m = parse(&ball(
        "{ base_color = [0.5, 0.5, 0.5], metallic = 0.25, ior = 1.33 }",
    ))
    .unwrap()
    .balls[0]
        .material;
    // sRGB 0.5 is linear 0.21404 (IEC 61966-2-1).
    assert!((m.diffuse.x - 0.214_041).abs() < 1e-5, "{m:?}");
    assert_eq!((m.metallic, m.ior, m.f0), (0.25, 1.33, m.diffuse));
    let m = parse(&ball("{ base_color = [1, 1, 1] }")).unwrap().balls[0].material;
    assert_eq!(
        (m.metallic, m.ior),
        (0.0, 1.5),
        "the defaults: a dielectric of IOR 1.5"
    );
    let m = parse(&ball(
        "{ kind = \"dielectric\", albedo = [0.5, 0.5, 0.5], f0 = [0.04, 0.04, 0.04] }",
    ))
    .unwrap()
    .balls[0]
        .material;
    assert!((m.ior - 1.5).abs() < 1e-12 && m.metallic == 0.0, "{m:?}");
    let m = parse(&ball("{ kind = \"metal\", albedo = [0.7216, 0.451, 0.2] }"))
        .unwrap()
        .balls[0]
        .material;
    assert_eq!(m, Material::metal_gamma22([0.7216, 0.451, 0.2]));
    for (material, says) in [
        (
            "{ base_color = [0.5, 0.5, 0.5], metallic = 1.5 }",
            "metallic 1.5 is outside [0, 1]",
        ),
        (
            "{ base_color = [0.5, 0.5, 0.5], ior = 0.5 }",
            "ior 0.5 is outside [1, 4]",
        ),
        ("{ base_color = [2, 0.5, 0.5] }", "outside [0, 1]"),
        (
            "{ kind = \"metal\", base_color = [0.5, 0.5, 0.5] }",
            "`kind` or `base_color`, not both",
        ),
        (
            "{ kind = \"metal\", f0 = [1, 1, 1], metallic = 0.5 }",
            "`metallic` goes with `base_color`",
        ),
        (
            "{ kind = \"metal\", f0 = [1, 1, 1], ior = 1.5 }",
            "a metal takes no `ior`",
        ),
        (
            "{ kind = \"dielectric\", f0 = [0.04, 0.05, 0.04] }",
            "must be grey",
        ),
        (
            "{ kind = \"dielectric\", f0 = [0.04, 0.04, 0.04], ior = 1.5 }",
            "`ior` or `f0`, not both",
        ),
        ("{ albedo = [0.5, 0.5, 0.5] }", "needs `base_color`"),
    ] {
        let err = parse(&ball(material)).expect_err(material).to_string();
        assert!(
            err.contains(says) && err.contains("line 5") && !err.contains('\n'),
            "{material}: {err}"
        );
    }
    let layering = parse(&format!(
        "layering = \"view-only\"\n{}",
        ball("{ base_color = [1, 1, 1] }")
    ));
    assert_eq!(layering.unwrap().layering, Layering::ViewOnly);
    let err = parse(&format!(
        "layering = \"flat\"\n{}",
        ball("{ base_color = [1, 1, 1] }")
    ))
    .unwrap_err()
    .to_string();
    assert!(err.contains("physical") && err.contains("line 1"), "{err}");
}
