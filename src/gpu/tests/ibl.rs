//! Image-based lighting: the split-sum table, the prefiltered environment (CPU and GPU),
//! and the shading under a map against its CPU twin.

use crate::brdf::Geometry;
use crate::lut::{self, e_reference, split_sum, SplitSum};

/// A + B = E. Against E by the same `theta_i` nodes with the azimuth in closed form the
/// sum checks the split sum's azimuthal quadrature, and against the precise adaptive
/// reference the whole 2-D rule: within 1e-6 and 2e-6 (the tables' own accuracy goal) for
/// every G, over mu and roughness including grazing, but for the grazing near-mirror
/// (mu <= 1e-3 at roughness <= 0.05), where both are off by up to 3.1e-3 (measured,
/// height-correlated G at mu = 0, roughness 0; 1.9e-6 at roughness 0.05): the azimuth there has three scales (the peak,
/// a 1/phi^2 shoulder 1/alpha wider, a floor) that 2 x 32 nodes do not resolve.
#[test]
fn split_sum_adds_up_to_e() {
    let mut worst_same: (f64, f64, f64, &str) = (0.0, 0.0, 0.0, "");
    let mut worst_ref: (f64, f64, f64, &str) = (0.0, 0.0, 0.0, "");
    for g in Geometry::ALL {
        for &mu in &[0.0, 1e-3, 0.02, 0.1, 0.3, 0.5, 0.77, 0.99, 1.0] {
            for &r in &[0.0, 0.05, 0.15, 0.3, 0.5, 0.75, 1.0] {
                let (a, b) = split_sum(mu, r, g);
                assert!(a >= -1e-12 && b >= 0.0, "{mu} {r} {a} {b}");
                let same = (a + b - lut::e_same_nodes(mu, r, g)).abs();
                let reference = (a + b - e_reference(mu, r, g)).abs();
                if mu <= 1e-3 && r <= 0.05 {
                    assert!(
                        same < 5e-3 && reference < 5e-3,
                        "{mu} {r} {same} {reference}"
                    );
                    continue;
                }
                if same > worst_same.0 {
                    worst_same = (same, mu, r, g.name());
                }
                if reference > worst_ref.0 {
                    worst_ref = (reference, mu, r, g.name());
                }
            }
        }
    }
    assert!(
        worst_same.0 < 1e-6,
        "A + B - E (same nodes) worst {worst_same:?}"
    );
    assert!(
        worst_ref.0 < 2e-6,
        "A + B - E (reference) worst {worst_ref:?}"
    );
}

/// B is the Fresnel-weighted part: at normal incidence and low roughness v.h = 1 nearly
/// everywhere, so B is tiny; at grazing it is a large share of E.
#[test]
fn split_sum_bias_grows_towards_grazing() {
    let (_, b_normal) = split_sum(1.0, 0.1, Geometry::SmithCorrelated);
    let (a_grazing, b_grazing) = split_sum(0.05, 0.1, Geometry::SmithCorrelated);
    assert!(b_normal < 1e-3, "{b_normal}");
    assert!(
        b_grazing > 0.3 * (a_grazing + b_grazing),
        "{b_grazing} {a_grazing}"
    );
    let table = SplitSum::bake(Geometry::SmithCorrelated);
    let direct = split_sum(0.5, 0.5, Geometry::SmithCorrelated).1 as f32;
    assert!((table.bias_at(0.5, 0.5) - direct).abs() < 2e-3);
}

/// The table is baked with fewer nodes than `split_sum` (a startup cost of a few
/// milliseconds): every texel within 5e-5 of the 1e-6 quadrature, every G, but at mu = 0,
/// roughness <= 1/31 (the 32 x 32
/// bilinear read itself is good to about 1e-3).
#[test]
fn split_sum_table_is_baked_close_to_the_precise_quadrature() {
    for g in Geometry::ALL {
        let table = SplitSum::bake(g);
        let n = lut::SPLIT_SUM_SIZE;
        let mut worst = (0.0f64, 0, 0);
        for j in (0..n).step_by(3) {
            for i in 0..n {
                if i == 0 && j <= 1 {
                    // The grazing near-mirror, where split_sum itself is off by up to 3e-3
                    // (split_sum_adds_up_to_e).
                    continue;
                }
                let mu = i as f64 / (n - 1) as f64;
                let r = j as f64 / (n - 1) as f64;
                let precise = split_sum(mu, r, g).1;
                let err = (table.bias[j * n + i] as f64 - precise).abs();
                if err > worst.0 {
                    worst = (err, i, j);
                }
            }
        }
        assert!(worst.0 < 5e-5, "{g}: worst {worst:?}");
    }
}

// ---------------------------------------------------------------------------------------
// The prefiltered environment and the shading under a map.

use std::sync::Arc;

use crate::cpu;
use crate::environment::prefilter::{MipChain, Prefiltered};
use crate::environment::{self, Builtin, EnvMap, Environment, IblTerm, Source};
use crate::lut::TableSet;
use crate::scene::{Material, Model, Scene};
use glam::{DVec2, DVec3};

use crate::pixels::both;
use crate::pixels::{assert_close, compare, vulkan};

/// `scene` lit by `map` alone (no lights, no uniform environment), with `term`.
fn under(scene: Scene, environment: Environment, term: IblTerm) -> Scene {
    Scene {
        lights: Vec::new(),
        environment: DVec3::ZERO,
        environment_map: Some(environment),
        ..scene
    }
    .with_term(term)
}

fn map_environment(map: EnvMap, rotation_deg: f64) -> Environment {
    Environment {
        source: Source::Builtin(Builtin::White),
        map: Arc::new(map),
        rotation_deg,
        intensity: 1.0,
    }
}

/// The white furnace through the whole map path (`white` is a map of 1, prefiltered,
/// convolved and read like any other), F0 = 1: with the term every ball pixel is within
/// 1/255 of the background for every method, on the GPU and on the CPU; without it the
/// rough balls are visibly dark (the bottom row, roughness 0.75 and 0.95: more than 10/255
/// below). Every method is exact for F0 = 1 by construction (docs/design/environment.md,
/// "Per pixel"), so what is left is f16 and f32 rounding.
#[test]
fn furnace_through_the_map_path_holds_for_every_term() {
    let mut r = vulkan();
    let (w, h) = (320, 180);
    for term in IblTerm::ALL {
        let scene = under(Scene::furnace(), Environment::builtin(Builtin::White), term);
        let gpu = r.render_ldr(&scene, w, h).unwrap().rgba;
        let cpu = cpu::to_rgba8(
            &cpu::render_radiance(
                &scene,
                &crate::prepared::Prepared::new(
                    &scene,
                    &TableSet::full(r.tables_for(scene.effective_geometry())),
                ),
                w,
                h,
            ),
            scene.exposure,
        );
        for (what, image) in [("GPU", &gpu), ("CPU", &cpu)] {
            let background = image[0];
            let mut worst_top = 0u8;
            let mut darkest_bottom = 255u8;
            let basis = scene.camera.basis(w, h);
            for (k, px) in image.chunks_exact(4).enumerate() {
                let (x, y) = ((k as u32) % w, (k as u32) / w);
                let d = basis.ray(x, y, w, h);
                for b in &scene.balls {
                    if cpu::intersect_sphere(basis.origin, d, b.center, b.radius) > 0.0 {
                        if b.model.has_term() {
                            worst_top = worst_top.max(px[0].abs_diff(background));
                        } else if b.roughness >= 0.75 {
                            darkest_bottom = darkest_bottom.min(px[0]);
                        }
                    }
                }
            }
            assert!(
                worst_top <= 1,
                "{what} {term}: a ball with the term is {worst_top}/255 off the background"
            );
            assert!(
                darkest_bottom + 10 < background,
                "{what} {term}: rough balls without the term not dark ({darkest_bottom} vs {background})"
            );
        }
    }
}

/// The GPU against its CPU twin under the built-in maps (the CPU prefilters the same mip
/// chain with the same samples and reads the same split-sum table): the render issue's
/// bound, every method, the reference balls plus a dielectric row.
#[test]
fn gpu_matches_its_cpu_twin_under_maps() {
    let mut r = vulkan();
    // 320x180 (it was 640x360, for CI's time): every ball keeps its interior and its
    // silhouette, and the bound is per pixel.
    let (w, h) = (320, 180);
    let mut balls = Scene::reference().balls;
    for b in balls.iter_mut().skip(5) {
        b.material = Material::dielectric(DVec3::new(0.6, 0.1, 0.1), 1.5);
        b.model = Model::KullaConty;
    }
    let base = Scene {
        balls,
        ..Scene::reference()
    };
    for builtin in [Builtin::Studio, Builtin::Sky] {
        let environment = Environment::builtin(builtin);
        for term in IblTerm::ALL {
            let scene = under(base.clone(), environment.clone(), term);
            let (gpu, cpu) = both(&mut r, &scene, w, h);
            assert_close(&compare(&gpu, &cpu, w), &format!("{builtin}, {term}"));
        }
    }
}

/// Prefiltering a constant map gives the constant in every layer (each layer is a
/// normalised weighted average), on the CPU exactly up to f16 rounding; and on the GPU the
/// furnace balls (F0 = 1, the term on) return that constant in linear radiance.
#[test]
fn prefiltering_a_constant_map_gives_the_constant() {
    let c = DVec3::new(0.3, 2.0, 7.0);
    let map = EnvMap::uniform(c, 128, 64);
    let chain = MipChain::new(&map);
    let tables = crate::lut::bake(&Default::default());
    let pre = Prefiltered::new(
        &chain,
        &environment::prefilter::kernels(&tables),
        Geometry::SmithCorrelated,
    );
    for level in pre.specular.iter().chain(&pre.convolved) {
        for t in &level.texels {
            for k in 0..3 {
                let rel = (t[k] as f64 - c[k]).abs() / c[k];
                assert!(rel < 1e-3, "{t:?} vs {c}");
            }
        }
    }
    let mut r = vulkan();
    let scene = under(
        Scene::furnace(),
        map_environment(map, 0.0),
        IblTerm::KullaConty,
    );
    let (w, h) = (160, 90);
    let hdr = r.render_hdr(&scene, w, h).unwrap();
    let basis = scene.camera.basis(w, h);
    let mut checked = 0;
    for (k, px) in hdr.rgba.chunks_exact(4).enumerate() {
        let d = basis.ray(k as u32 % w, k as u32 / w, w, h);
        let top = scene.balls.iter().filter(|b| b.model.has_term());
        if top
            .into_iter()
            .any(|b| cpu::intersect_sphere(basis.origin, d, b.center, b.radius) > 0.0)
        {
            for ch in 0..3 {
                let rel = (px[ch] as f64 - c[ch]).abs() / c[ch];
                assert!(rel < 2e-3, "pixel {k}: {px:?} vs {c}");
            }
            checked += 1;
        }
    }
    assert!(checked > 100, "{checked} ball pixels");
}

/// Turning the environment by 90 degrees is the same as turning the map's texels by a
/// quarter of its width (each texel centre resampled through `Environment::to_map`, exact
/// for a quarter turn): the highlights move with it. Not bit-exact, as the prefilter's
/// sample pattern about each direction is not turned with it, which shows the prefilter's
/// own sampling noise: measured 99.07 % of pixels within 3/255, 98.3 % within 1/255, the
/// worst 23/255 (a few pixels on the rough balls); the bound is 98.5 % within 3/255. The
/// turned image is far from the unturned one.
#[test]
fn rotating_the_environment_rotates_the_highlights() {
    let studio = Builtin::Studio.generate(512);
    let turned_env = map_environment(studio.clone(), 90.0);
    let (w0, h0) = (studio.width(), studio.height());
    let mut texels = Vec::with_capacity((w0 * h0) as usize);
    for j in 0..h0 {
        for i in 0..w0 {
            let uv = DVec2::new((i as f64 + 0.5) / w0 as f64, (j as f64 + 0.5) / h0 as f64);
            let source =
                environment::direction_to_uv(turned_env.to_map(environment::uv_to_direction(uv)));
            let si = ((source.x * w0 as f64 - 0.5).round() as i64).rem_euclid(w0 as i64) as u32;
            let t = studio.texel(si, j);
            texels.push([t.x as f32, t.y as f32, t.z as f32]);
        }
    }
    let pre_turned = map_environment(EnvMap::new(w0, h0, texels).unwrap(), 0.0);
    let mut r = vulkan();
    let (w, h) = (320, 180);
    let render = |r: &mut crate::Renderer, e: Environment| {
        let scene = under(Scene::reference(), e, IblTerm::KullaConty);
        r.render_ldr(&scene, w, h).unwrap().rgba
    };
    let a = render(&mut r, turned_env);
    let b = render(&mut r, pre_turned);
    let unturned = render(&mut r, map_environment(studio, 0.0));
    let same = compare(&a, &b, w);
    assert!(
        same.frac_3() >= 0.985,
        "{}",
        same.report("turned vs pre-turned")
    );
    let moved = compare(&a, &unturned, w);
    // The studio's gradient does not change under a turn about +y, so most of the
    // background stays; the balls and the lights in view move (measured: 18.5 % of the
    // pixels more than 3/255 apart).
    assert!(
        moved.frac_3() < 0.9,
        "{}",
        moved.report("turned vs unturned")
    );
}

/// The map path on GL (llvmpipe through EGL: a fresh machine's `--backend auto`) against
/// the CPU twin, the same bound as Vulkan: the prefilter's compute passes, the array
/// textures and the background pass compile and agree there too.
#[test]
fn gl_matches_the_cpu_twin_under_a_map() {
    let mut r = crate::pixels::renderer(wgpu::Backends::GL);
    let (w, h) = (640, 360);
    for term in IblTerm::ALL {
        let scene = under(
            Scene::reference(),
            Environment::builtin(Builtin::Studio),
            term,
        );
        let (gpu, cpu) = both(&mut r, &scene, w, h);
        assert_close(&compare(&gpu, &cpu, w), &format!("GL, studio, {term}"));
    }
}

/// The renderer keeps up to MAX_PREFILTERED_MAPS prepared maps: drawing one of them again
/// prepares nothing (the latest preparation's time stays that of the map prepared last),
/// a further map is prepared, and a map dropped and made again (a new `Arc`, possibly at
/// the old address) is prepared again, never served stale textures.
#[test]
fn prepared_maps_are_kept_and_reused() {
    use crate::gpu::MAX_PREFILTERED_MAPS;
    let mut r = vulkan();
    let (w, h) = (64, 36);
    let maps: Vec<Environment> = (0..MAX_PREFILTERED_MAPS)
        .map(|k| map_environment(EnvMap::uniform(DVec3::splat(0.2 + k as f64), 32, 16), 0.0))
        .collect();
    let draw = |r: &mut crate::Renderer, e: &Environment| {
        let scene = under(Scene::furnace(), e.clone(), IblTerm::KullaConty);
        r.render_hdr(&scene, w, h).unwrap().rgba
    };
    let mut images = Vec::new();
    for e in &maps {
        images.push(draw(&mut r, e));
    }
    let last = r.last_prefilter_time().unwrap();
    for (e, image) in maps.iter().zip(&images) {
        assert_eq!(&draw(&mut r, e), image, "a kept map draws as before");
        assert_eq!(
            r.last_prefilter_time().unwrap(),
            last,
            "nothing prepared again"
        );
    }
    // A map of another radiance, made anew: prepared, and drawn with its own radiance.
    let fresh = map_environment(EnvMap::uniform(DVec3::splat(9.0), 32, 16), 0.0);
    let image = draw(&mut r, &fresh);
    assert_ne!(r.last_prefilter_time().unwrap(), last);
    let centre = ((h / 2 * w + w / 2) * 4) as usize;
    assert!((image[centre] - 9.0).abs() < 0.05, "{}", image[centre]);
}

/// The split-sum tables shipped in `assets/split_sum_bias.bin` are the bake's, bit for bit
/// (run with SHADEBALLS_UPDATE_GOLDENS=1 to write them again after a change to the bake).
#[test]
fn shipped_split_sum_tables_are_the_bake() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/split_sum_bias.bin");
    let baked = SplitSum::shipped_bytes();
    if std::env::var("SHADEBALLS_UPDATE_GOLDENS").is_ok_and(|v| v == "1") {
        std::fs::write(&path, &baked).unwrap();
    }
    let shipped = std::fs::read(&path).unwrap();
    assert!(
        shipped == baked,
        "assets/split_sum_bias.bin differs from the bake"
    );
    for g in Geometry::ALL {
        assert_eq!(SplitSum::shipped(g), SplitSum::bake(g));
    }
}

// ---------------------------------------------------------------------------------------
// Lighting that follows the lobe (`ibl_method = "lobe"`).

use crate::environment::IblMethod;

/// The lab's IBL balls (copper over a white metal row, every ball with the Kulla-Conty
/// term) under `builtin` alone, lit by `n` lobe samples a frame, no antialiasing (the Monte
/// Carlo's centre rays).
fn lobe_scene(builtin: Builtin, n: u32) -> Scene {
    let mut scene = under(
        Scene::reference(),
        Environment::builtin(builtin),
        IblTerm::KullaConty,
    );
    for b in scene.balls.iter_mut().skip(5) {
        b.material = Material::metal(DVec3::splat(0.95));
        b.model = Model::KullaConty;
    }
    scene.antialias = false;
    scene.ibl_method = IblMethod::Lobe;
    scene.ibl_samples = n;
    scene
}

/// The GPU's lobe samples against the CPU twin (the same sequence per pixel in integer
/// arithmetic, the same VNDF samples, levels and trilinear reads of the same f16 chain): the
/// GPU-vs-CPU bound of the split sum (`assert_close`, the render issue's), at frame 0 and
/// at a later frame, every term, under both maps, with antialiasing on.
#[test]
fn lobe_gpu_matches_its_cpu_twin() {
    assert_lobe_matches_its_cpu_twin("lobe", |builtin, term| {
        lobe_scene(builtin, 4).with_term(term)
    });
}

/// The GPU's lobe image of `scene_of(map, term)` (antialiasing on) against the CPU twin's,
/// at 320x180, under studio and sky, for every term, at frames 0 and 5, within
/// [`assert_close_sampled`]'s bound.
fn assert_lobe_matches_its_cpu_twin(what: &str, scene_of: impl Fn(Builtin, IblTerm) -> Scene) {
    let mut r = vulkan();
    // Not smaller: the bound is a share of the pixels, and the map's background differs
    // by 1/255 in a band whose share grows as the frame shrinks (at 192x108, 22 pixels:
    // 99.89 % within 1/255).
    let (w, h) = (320, 180);
    for builtin in [Builtin::Studio, Builtin::Sky] {
        for term in IblTerm::ALL {
            let mut scene = scene_of(builtin, term);
            scene.antialias = true;
            let frames = [0, 5];
            let tables = TableSet::full(r.tables_for(scene.effective_geometry()));
            let radiance = cpu::render_radiance_at_lobe_frames(
                &scene,
                &crate::prepared::Prepared::new(&scene, &tables),
                w,
                h,
                &frames,
            );
            for (frame, radiance) in frames.into_iter().zip(radiance) {
                r.set_lobe_frame(frame);
                let gpu = r.render_ldr(&scene, w, h).unwrap().rgba;
                r.set_lobe_frame(0);
                let cpu = cpu::to_display_rgba8(&radiance, scene.exposure, scene.display());
                assert_close_sampled(
                    &compare(&gpu, &cpu, w),
                    &format!("{what}, {builtin}, {term}, frame {frame}"),
                );
            }
        }
    }
}

/// The lobe mode's GPU-vs-CPU bound: 99.8 % of pixels within 1/255 and 99.98 % within 3/255
/// (the render issue's is 99.9 % within 1/255). The multiple importance sampling sums the
/// map's own samples of its brightest texels (studio's lights are 60 to 500 times the
/// gradient) with the visible normals' and the cosine's: a direction that rounds to a
/// neighbouring texel in f32 near a light's edge moves a pixel, by more where a pixel takes
/// few samples (these scenes take 4). A map sample carries its drawn texel's density
/// (`luminance_sample`), so only the other strategies' directions look one up. Measured
/// with the Owen-scrambled Sobol points (the same points on both sides, integer
/// arithmetic) and the compensated tables (9cac3d5): studio 99.911 to 99.913 % within 1/255
/// and 99.993 to 99.995 % within 3/255 (3 or 4 pixels of 57600), max 4/255; sky 100 %
/// within 1/255. Before, with the map sample's density looked up again: 99.901 to 99.906 %
/// and 99.990 to 99.993 %, one ball pixel at 18/255; with the net and the R2 points:
/// 99.899 % and 99.995 %, max 4/255, under a bound of 99.99 % within 3/255.
fn assert_close_sampled(d: &crate::pixels::Diff, what: &str) {
    let report = d.report(what);
    println!("{report}");
    assert!(d.frac_1() >= 0.998 && d.frac_3() >= 0.9998, "{report}");
}

/// The coating's lobe samples (plastics under `lobe`: the specular from its own lobe, the
/// base as under the split sum) against the CPU twin, at the same bound as the metals':
/// a dielectric row (IOR 1.5, and one ball of it half metal, the two parts mixed) over the
/// reference copper row, every term, both maps, frames 0 and 5, antialiasing on.
#[test]
fn lobe_coating_gpu_matches_its_cpu_twin() {
    assert_lobe_matches_its_cpu_twin("coating lobe", |builtin, term| {
        let mut scene = lobe_scene(builtin, 4);
        for (k, b) in scene.balls.iter_mut().enumerate().skip(5) {
            b.material = if k == 7 {
                Material::metallic_roughness(DVec3::new(0.9, 0.6, 0.3), 0.5, 1.5)
            } else {
                Material::dielectric(DVec3::new(0.6, 0.1, 0.1), 1.5)
            };
        }
        scene.with_term(term)
    });
}

/// Under `lobe` the coating's specular is its lobe's samples, not the prefiltered layers:
/// its image differs from the split sum's (a test that could not fail if the coating still
/// took the split sum), and the all-dielectric balls' images differ between frames.
#[test]
fn lobe_coating_takes_its_own_samples() {
    let mut r = vulkan();
    let (w, h) = (96, 54);
    let mut scene = lobe_scene(Builtin::Studio, 4);
    for b in scene.balls.iter_mut() {
        b.material = Material::dielectric(DVec3::new(0.6, 0.1, 0.1), 1.5);
    }
    let lobe = r.render_hdr(&scene, w, h).unwrap().rgba;
    r.set_lobe_frame(1);
    let next = r.render_hdr(&scene, w, h).unwrap().rgba;
    r.set_lobe_frame(0);
    let split = Scene {
        ibl_method: IblMethod::SplitSum,
        ..scene.clone()
    };
    let split = r.render_hdr(&split, w, h).unwrap().rgba;
    assert_ne!(lobe, split);
    assert_ne!(lobe, next);
}

/// Frames of the lobe's samples take new samples: frame 1 differs from frame 0, and the
/// mean of frames 0..4 is the mean of the four frames drawn one by one.
#[test]
fn lobe_frames_take_new_samples_and_average() {
    let mut r = vulkan();
    let (w, h) = (96, 54);
    let scene = lobe_scene(Builtin::Studio, 2);
    let frames: Vec<Vec<f32>> = (0..4)
        .map(|k| {
            r.set_lobe_frame(k);
            r.render_hdr(&scene, w, h).unwrap().rgba
        })
        .collect();
    assert_ne!(frames[0], frames[1]);
    let mean = r.render_lobe_hdr(&scene, w, h, 4).unwrap().rgba;
    assert_eq!(r.lobe_frame(), 0);
    for (i, m) in mean.iter().enumerate() {
        let expected = frames.iter().map(|f| f64::from(f[i])).sum::<f64>() / 4.0;
        assert!((f64::from(*m) - expected).abs() <= 1e-6 * expected.abs().max(1.0));
    }
    assert!(r.render_lobe_hdr(&scene, w, h, 0).is_err());
}

/// The worst over the balls of roughness >= 0.3 of the mean relative luminance error of
/// `image` against the Monte Carlo `mc` over each ball's pixels (the lab's measure).
fn worst_ball_error(
    scene: &Scene,
    w: u32,
    h: u32,
    image: &[f32],
    mc: &cpu::MonteCarloImage,
) -> f64 {
    let luminance = DVec3::new(0.2126, 0.7152, 0.0722);
    let basis = scene.camera.basis(w, h);
    let mut per_ball = vec![(0.0, 0usize); scene.balls.len()];
    for py in 0..h {
        for px in 0..w {
            let d = basis.ray(px, py, w, h);
            let Some((_, k)) = cpu::nearest_ball(scene, basis.origin, d) else {
                continue;
            };
            let i = (py * w + px) as usize;
            let y_ref = mc.mean[i].dot(luminance);
            if y_ref < 1e-4 {
                continue;
            }
            let p = &image[4 * i..4 * i + 3];
            let y = DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64).dot(luminance);
            per_ball[k].0 += (y - y_ref).abs() / y_ref;
            per_ball[k].1 += 1;
        }
    }
    scene
        .balls
        .iter()
        .zip(per_ball)
        .filter(|(b, (_, n))| b.roughness >= 0.3 && *n > 0)
        .map(|(_, (e, n))| e / n as f64)
        .fold(0.0, f64::max)
}

/// The lobe's progressive image against the CPU Monte Carlo of the same model (96x54,
/// 2048 spp, the metals of roughness >= 0.3): under sky, 16 frames of 16 samples within
/// 3 % (measured 1.09 % at 160x90 by lab/examples/lobe_sweep, docs/design/environment.md,
/// "Lighting that follows the lobe"; the split sum is 4.8 % there); under studio, 64 frames
/// of 16 within 4 % (measured 2.3 %; the split sum 25.6 %) and closer than the split sum.
/// (Here, at 96x54, at a88643d: sky 0.99 %, studio 1.69 %; the split sum 4.4 % and
/// 23.8 %.)
#[test]
fn lobe_converges_to_the_monte_carlo_of_the_model() {
    let mut r = vulkan();
    let (w, h) = (96, 54);
    for (builtin, frames, bound) in [(Builtin::Sky, 16, 0.03), (Builtin::Studio, 64, 0.04)] {
        let scene = lobe_scene(builtin, 16);
        let (e_lobe, e_split) = lobe_and_split_sum_errors(&mut r, &scene, (w, h), frames);
        println!("{builtin}: lobe {frames} x 16 {e_lobe:.4}, split sum {e_split:.4}");
        assert!(e_lobe < bound, "{builtin}: {e_lobe}");
        assert!(e_lobe < e_split, "{builtin}: {e_lobe} vs {e_split}");
    }
}

/// [`worst_ball_error`] of `scene`'s lobe mode (`frames` progressive frames) and of its
/// split sum, each against the CPU Monte Carlo of the same model (2048 spp, seed 7).
fn lobe_and_split_sum_errors(
    r: &mut crate::Renderer,
    scene: &Scene,
    (w, h): (u32, u32),
    frames: u32,
) -> (f64, f64) {
    let tables = TableSet::full(r.tables_for(scene.effective_geometry()));
    let prepared = crate::prepared::Prepared::new(scene, &tables);
    let mc = cpu::render_montecarlo(scene, &prepared, w, h, 2048, 7).unwrap();
    let lobe = r.render_lobe_hdr(scene, w, h, frames).unwrap().rgba;
    let split = Scene {
        ibl_method: IblMethod::SplitSum,
        ..scene.clone()
    };
    let split = r.render_hdr(&split, w, h).unwrap().rgba;
    (
        worst_ball_error(scene, w, h, &lobe, &mc),
        worst_ball_error(scene, w, h, &split, &mc),
    )
}

/// `scene` drawn by [`crate::Renderer::render_progressive`] into a `w x h`
/// `Rgba8Unorm` texture of the test's own, read back.
fn progressive_ldr(r: &mut crate::Renderer, scene: &Scene, (w, h): (u32, u32)) -> Vec<u8> {
    use crate::gpu::readback::Readback;
    let format = wgpu::TextureFormat::Rgba8Unorm;
    let device = r.gpu().device.clone();
    let texture = target_texture(
        &device,
        "progressive target",
        (w, h),
        format,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
    );
    let view = texture.create_view(&Default::default());
    let target = crate::Target {
        view: &view,
        format,
        width: w,
        height: h,
    };
    r.render_progressive(scene, target).unwrap();
    let readback = Readback::new(&device, format, (w, h)).unwrap();
    let mut encoder = device.create_command_encoder(&Default::default());
    readback.record(&mut encoder, &texture);
    r.gpu().queue.submit([encoder.finish()]);
    readback.read(&device).unwrap()
}

/// The lobe's frames summed on the GPU (`render_lobe_hdr`: `accumulate.wgsl`, one
/// read-back) against the mean of the same frames of the CPU twin
/// (`cpu::render_radiance_at_lobe_frames`), within the GPU-vs-CPU bound of one frame
/// (`assert_close`, the render issue's; `lobe_gpu_matches_its_cpu_twin` holds it per
/// frame), under both maps, 4 frames of 4 samples; on Vulkan and on GL (which renders the
/// same `Rgba32Uint` sums), under studio there.
#[test]
fn lobe_accumulated_on_the_gpu_matches_the_mean_of_its_cpu_frames() {
    // 192x108 and 4 frames (it was 320x180 and 6, for CI's time): the sum still spans
    // several frames, and the bound is per pixel.
    let (w, h, frames) = (192, 108, 4);
    let gl = || crate::pixels::renderer(wgpu::Backends::GL);
    for (mut r, builtin, backend) in [
        (vulkan(), Builtin::Studio, "Vulkan"),
        (vulkan(), Builtin::Sky, "Vulkan"),
        (gl(), Builtin::Studio, "GL"),
    ] {
        let mut scene = lobe_scene(builtin, 4);
        scene.antialias = true;
        let gpu = r.render_lobe_hdr(&scene, w, h, frames).unwrap().rgba;
        assert_eq!(r.lobe_samples(), Some(frames * 4));
        let gpu: Vec<DVec3> = gpu
            .chunks_exact(4)
            .map(|p| DVec3::new(p[0].into(), p[1].into(), p[2].into()))
            .collect();
        let tables = TableSet::full(r.tables_for(scene.effective_geometry()));
        let mut mean = vec![DVec3::ZERO; (w * h) as usize];
        let all: Vec<u32> = (0..frames).collect();
        let prepared = crate::prepared::Prepared::new(&scene, &tables);
        for frame in cpu::render_radiance_at_lobe_frames(&scene, &prepared, w, h, &all) {
            for (m, x) in mean.iter_mut().zip(frame) {
                *m += x / f64::from(frames);
            }
        }
        let display = |x: &[DVec3]| cpu::to_display_rgba8(x, scene.exposure, scene.display());
        assert_close(
            &compare(&display(&gpu), &display(&mean), w),
            &format!("lobe, {builtin}, {frames} frames summed on {backend}"),
        );
    }
}

/// The progressive draw (`render_progressive`, what the viewer calls each frame): its first
/// frame is the single frame's picture byte for byte; each draw of the unchanged scene adds
/// `ibl_samples` samples a pixel (a new exposure too: the sums are linear) and changes the
/// picture; a moved camera starts again at one frame; the cap stops the count; a scene
/// without the lobe holds none.
#[test]
fn lobe_progressive_counts_and_restarts_when_the_scene_changes() {
    let mut r = vulkan();
    let size = (96, 54);
    let scene = lobe_scene(Builtin::Studio, 4);
    let first = progressive_ldr(&mut r, &scene, size);
    assert_eq!(r.lobe_samples(), Some(4));
    r.set_lobe_frame(0);
    assert!(first == r.render_ldr(&scene, size.0, size.1).unwrap().rgba);
    let second = progressive_ldr(&mut r, &scene, size);
    assert_eq!(r.lobe_samples(), Some(8));
    assert_ne!(first, second);
    let brighter = Scene {
        exposure: 2.0,
        ..scene.clone()
    };
    progressive_ldr(&mut r, &brighter, size);
    assert_eq!(r.lobe_samples(), Some(12));
    let mut moved = scene.clone();
    moved.camera.position += DVec3::new(0.1, 0.0, 0.0);
    let restarted = progressive_ldr(&mut r, &moved, size);
    assert_eq!(r.lobe_samples(), Some(4));
    r.set_lobe_frame(0);
    assert!(restarted == r.render_ldr(&moved, size.0, size.1).unwrap().rgba);
    r.set_lobe_sample_cap(Some(8));
    for _ in 0..3 {
        progressive_ldr(&mut r, &moved, size);
    }
    assert_eq!(r.lobe_samples(), Some(8));
    let split = Scene {
        ibl_method: IblMethod::SplitSum,
        ..scene.clone()
    };
    let split_image = progressive_ldr(&mut r, &split, size);
    assert_eq!(r.lobe_samples(), None);
    assert!(split_image == r.render_ldr(&split, size.0, size.1).unwrap().rgba);
}

/// Times the lobe's progressive image at 1280x720, three ways interleaved (so that the
/// load of a shared machine falls on each alike), for the frame counts at which
/// docs/design/environment.md's sweep found it within 1 % (sky: 16 frames of 16) or
/// closest (studio: 256 frames of 16; `--ignored` with `LOBE_TIME_STUDIO=1`): summed on the
/// GPU (`render_lobe_hdr`: `accumulate.wgsl`, one read-back); the way before it (each frame
/// read back, `render_hdr`, and summed on the CPU in f64); and the frames alone drawn into
/// an `Rgba8Unorm` target and waited for, read back never (the floor: the shading). A
/// measurement, not a check: run it alone,
/// `cargo test --release -p shadeballs --test suite -- --ignored ibl::time_lobe_progressive_at_720p --nocapture`.
#[test]
#[ignore]
fn time_lobe_progressive_at_720p() {
    use std::time::Instant;
    let mut r = vulkan();
    let (w, h) = (1280, 720);
    let mut runs = vec![(Builtin::Sky, 16)];
    if std::env::var_os("LOBE_TIME_STUDIO").is_some() {
        runs.push((Builtin::Studio, 256));
    }
    let device = r.gpu().device.clone();
    let texture = target_texture(
        &device,
        "frame",
        (w, h),
        wgpu::TextureFormat::Rgba8Unorm,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    );
    let view = texture.create_view(&Default::default());
    let target = crate::Target {
        view: &view,
        format: wgpu::TextureFormat::Rgba8Unorm,
        width: w,
        height: h,
    };
    for (builtin, frames) in runs {
        let scene = lobe_scene(builtin, 16);
        // The first renders compile the pipelines and prefilter the map: not timed.
        r.render_lobe_hdr(&scene, w, h, 1).unwrap();
        r.render_hdr(&scene, w, h).unwrap();
        r.render(&scene, target).unwrap();
        let mut times = [Vec::new(), Vec::new(), Vec::new()];
        for _ in 0..3 {
            let start = Instant::now();
            r.render_lobe_hdr(&scene, w, h, frames).unwrap();
            times[0].push(start.elapsed().as_secs_f64());
            let start = Instant::now();
            let mut sum = vec![0.0f64; (4 * w * h) as usize];
            for k in 0..frames {
                r.set_lobe_frame(k);
                let image = r.render_hdr(&scene, w, h).unwrap();
                for (s, v) in sum.iter_mut().zip(&image.rgba) {
                    *s += f64::from(*v);
                }
            }
            r.set_lobe_frame(0);
            times[1].push(start.elapsed().as_secs_f64());
            let start = Instant::now();
            for k in 0..frames {
                r.set_lobe_frame(k);
                r.render(&scene, target).unwrap();
                let _ = device.poll(wgpu::PollType::wait_indefinitely());
            }
            r.set_lobe_frame(0);
            times[2].push(start.elapsed().as_secs_f64());
        }
        for (t, what) in times.iter_mut().zip([
            "summed on the GPU, one read-back",
            "each frame read back, summed on the CPU",
            "the frames alone, no read-back",
        ]) {
            t.sort_by(f64::total_cmp);
            println!(
                "{builtin}: {frames} frames of 16 at {w}x{h}, {what}: median {:.2} s of 3 ({:.1} ms a frame)",
                t[1],
                t[1] * 1e3 / f64::from(frames)
            );
        }
    }
}

/// `DrawOptions::dominant_direction` off (the light bench's split sum along the plain
/// mirror direction) reads the prefiltered layers along r: the studio's picture changes on
/// the balls, most on the rough ones (the dominant direction bends r towards n as the lobe
/// widens: nothing at roughness 0), and the plan says so; without a map nothing changes.
#[test]
fn the_split_sum_reads_along_the_mirror_direction_when_asked() {
    let mut r = vulkan();
    let (w, h) = (160, 90);
    let studio = under(
        Scene::reference(),
        Environment::builtin(Builtin::Studio),
        IblTerm::KullaConty,
    );
    let dominant = r.render_hdr(&studio, w, h).unwrap().rgba;
    let homework = r.render_hdr(&Scene::reference(), w, h).unwrap().rgba;
    let mirror = crate::gpu::DrawOptions {
        dominant_direction: false,
        ..Default::default()
    };
    r.set_draw_options(mirror);
    let along_r = r.render_hdr(&studio, w, h).unwrap().rgba;
    assert!(r.plan_for(&studio).to_string().contains("mirror direction"));
    assert_eq!(
        r.render_hdr(&Scene::reference(), w, h).unwrap().rgba,
        homework
    );
    let changed = dominant
        .chunks_exact(4)
        .zip(along_r.chunks_exact(4))
        .filter(|(a, b)| a != b)
        .count();
    // The ten balls cover about a fifth of the 160x90 image; most of their pixels move
    // (the roughest most), the background none.
    assert!(
        changed > w as usize * h as usize / 20,
        "{changed} pixels changed"
    );
}

/// The term's cost under a map, two ways (docs/benchmarks.md, "The term's cost under a
/// map"): the median of 11 frames with the term and 11 without, alternating and then each
/// in a row (Turquin's term, studio, 1280x720, Vulkan). Prints; a measurement, not a check:
/// `cargo test --release --test suite term_frame_cost -- --ignored --nocapture`.
#[test]
#[ignore]
fn term_frame_cost_alternating_and_in_a_row() {
    let mut scene = Scene::reference();
    for b in scene.balls.iter_mut() {
        b.model = Model::from_term(IblTerm::Turquin);
    }
    let scene = Scene {
        antialias: false,
        ..under(
            scene,
            Environment::builtin(Builtin::Studio),
            IblTerm::Turquin,
        )
    };
    let mut r = vulkan();
    let device = r.gpu().device.clone();
    let (w, h) = (1280, 720);
    let format = wgpu::TextureFormat::Rgba8Unorm;
    let texture = target_texture(
        &device,
        "term frame",
        (w, h),
        format,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    );
    let view = texture.create_view(&Default::default());
    let target = crate::gpu::Target {
        view: &view,
        format,
        width: w,
        height: h,
    };
    let frame = |r: &mut crate::Renderer, on: bool| {
        r.set_multiple_scattering_term(on);
        let t = std::time::Instant::now();
        r.render(&scene, target).unwrap();
        let _ = r.gpu().device.poll(wgpu::PollType::wait_indefinitely());
        t.elapsed().as_secs_f64() * 1e3
    };
    frame(&mut r, true);
    frame(&mut r, false);
    let median = |mut v: Vec<f64>| crate::stats::median(&mut v);
    let (mut on, mut off) = (Vec::new(), Vec::new());
    for _ in 0..11 {
        on.push(frame(&mut r, true));
        off.push(frame(&mut r, false));
    }
    println!(
        "alternating: with {:.2} ms, without {:.2} ms",
        median(on),
        median(off)
    );
    let on: Vec<f64> = (0..11).map(|_| frame(&mut r, true)).collect();
    let off: Vec<f64> = (0..11).map(|_| frame(&mut r, false)).collect();
    println!(
        "in a row: with {:.2} ms, without {:.2} ms",
        median(on),
        median(off)
    );
}

/// A `w x h` 2-D texture of `format` with `usage`, one level, for a test's frame target.
fn target_texture(
    device: &wgpu::Device,
    label: &str,
    (w, h): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

// ---------------------------------------------------------------------------------------
// The split sum under a small bright sun (issue 37, part 2: the prefilter's bright texels
// apart, `environment::prefilter::Bright`).

/// Radiance of [`sun_map`]'s sun.
const SUN_RADIANCE: f32 = 1e4;
/// The share of the sphere [`sun_map`]'s sun covers (issue 37's sun map).
const SUN_SHARE: f64 = 1e-3;

/// The direction of [`sun_map`]'s sun: up and left behind the camera of
/// `Scene::reference`, so the balls' lobes catch it on their visible faces.
fn sun_direction() -> DVec3 {
    DVec3::new(-0.45, 0.55, 0.7).normalize()
}

/// A 512 x 256 map: a dim sky (bluish, 0.2 at the nadir to 1 at the zenith) and a sun of
/// [`SUN_RADIANCE`] over the texels whose centres lie in a cap of [`SUN_SHARE`] of the
/// sphere (3.6 degrees in radius) about [`sun_direction`].
fn sun_map() -> EnvMap {
    let (w, h) = (512u32, 256u32);
    let cos_cap = 1.0 - 2.0 * SUN_SHARE;
    let texels = (0..w * h)
        .map(|k| {
            let uv = DVec2::new(
                ((k % w) as f64 + 0.5) / w as f64,
                ((k / w) as f64 + 0.5) / h as f64,
            );
            let d = environment::uv_to_direction(uv);
            if d.dot(sun_direction()) >= cos_cap {
                return [SUN_RADIANCE; 3];
            }
            let s = (0.6 + 0.4 * d.y) as f32;
            [0.8 * s, 0.9 * s, s]
        })
        .collect();
    EnvMap::new(w, h, texels).unwrap()
}

/// Issue 37, part 2, at its source: each sampled specular layer of [`sun_map`] (roughness
/// 1/6 to 1, 64 to 256 samples a texel) at 256 directions within 25 degrees of its sun,
/// against the same layer converged (16384 samples of the whole map, no texel apart): RMS
/// of the luminance error over the reference's mean. Measured with the bright texels apart,
/// layers 1 to 6: 1.91, 0.29, 0.25, 0.59, 0.67, 1.04 %; sampled as before (the samples
/// reading the whole map, the negative control, computed here too): 6.52, 5.06, 4.03, 7.10,
/// 6.62, 9.07 %, the blotches. Layer 1's 1.9 % is not noise: the bright texels' excess is
/// weighted at their centres (1.4-degree texels under a lobe about 4 degrees wide), a
/// smooth difference. The mean signed error (the energy the layer keeps about the sun):
/// -0.09, 0.16, -0.01, -0.01, 0.07, 0.02 % apart; -1.17, -0.38, 0.67, 0.27, -0.22, -0.50 %
/// sampled. Bounds: 3 % and a third of the sampled error; 0.5 % for the mean.
#[test]
fn the_sampled_layers_under_a_sun_converge() {
    use crate::environment::prefilter::{
        prefilter_specular, specular_roughness, specular_samples, Bright, SPECULAR_LEVELS,
    };
    let chain = MipChain::new(&sun_map());
    let bright = Bright::new(&chain).expect("the sun's texels are bright");
    let sun = sun_direction();
    let (t, b) = crate::sampling::duff_frame(sun).tangents();
    // 256 points of a golden-angle spiral over the cap.
    let cos_max = 25f64.to_radians().cos();
    let dirs: Vec<DVec3> = (0..256)
        .map(|i| {
            let c = 1.0 - (i as f64 + 0.5) / 256.0 * (1.0 - cos_max);
            let s = (1.0 - c * c).sqrt();
            let phi = i as f64 * 2.399_963_229_728_653;
            (t * (s * phi.cos()) + b * (s * phi.sin()) + sun * c).normalize()
        })
        .collect();
    let y = |v: DVec3| v.dot(environment::sampler::LUMINANCE);
    let g = Geometry::SmithCorrelated;
    for layer in 1..SPECULAR_LEVELS {
        let roughness = specular_roughness(layer);
        let samples = specular_samples(layer);
        let (mut apart, mut sampled, mut mean) = (0.0, 0.0, 0.0);
        let (mut apart_bias, mut sampled_bias) = (0.0, 0.0);
        for &d in &dirs {
            let reference = y(prefilter_specular(&chain, &[], d, roughness, g, 16384));
            let new = y(prefilter_specular(
                &bright.chain,
                &bright.texels,
                d,
                roughness,
                g,
                samples,
            ));
            let old = y(prefilter_specular(&chain, &[], d, roughness, g, samples));
            apart += (new - reference).powi(2);
            apart_bias += new - reference;
            sampled_bias += old - reference;
            sampled += (old - reference).powi(2);
            mean += reference;
        }
        let n = dirs.len() as f64;
        let rms = |e: f64| (e / n).sqrt() / (mean / n);
        let (apart, sampled) = (rms(apart), rms(sampled));
        let (apart_bias, sampled_bias) = (apart_bias / mean, sampled_bias / mean);
        println!(
            "layer {layer}: RMS relative error, bright texels apart {apart:.4}, sampled \
             {sampled:.4}; mean error {apart_bias:.4}, {sampled_bias:.4}"
        );
        assert!(apart < 0.03, "layer {layer}: {apart}");
        assert!(apart_bias.abs() < 0.005, "layer {layer}: {apart_bias}");
        assert!(
            apart < sampled / 3.0,
            "layer {layer}: {apart} against {sampled} sampled"
        );
    }
}

/// Luminance per pixel of an RGBA f32 image.
fn luminance_rgba(image: &[f32]) -> Vec<f64> {
    image
        .chunks_exact(4)
        .map(|p| {
            DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64).dot(environment::sampler::LUMINANCE)
        })
        .collect()
}

/// cos of the angle the sun keeps above the surface's horizon and the mirror direction's.
const HORIZON_MARGIN: f64 = 0.3;

/// Half the side of [`high_pass_rms`]'s box, pixels.
const HIGH_PASS_RADIUS: i64 = 2;

/// Per ball of `scene` of roughness >= `min_roughness`: the RMS over the ball's inner 80 %
/// (pixels within 0.8 of its radius on screen) of `d` minus its box-blurred self (a box of
/// `2 HIGH_PASS_RADIUS + 1` pixels a side), over the ball's mean `level`: the
/// high-frequency part of `d`, relative.
fn high_pass_rms(
    scene: &Scene,
    (w, h): (u32, u32),
    d: &[f64],
    level: &[f64],
    min_roughness: f64,
) -> Vec<f64> {
    let basis = scene.camera.basis(w, h);
    let owner = cpu::ball_index_map(scene, w, h);
    let side = 2 * HIGH_PASS_RADIUS + 1;
    let blur = |x: i64, y: i64| {
        let mut s = 0.0;
        for dy in -HIGH_PASS_RADIUS..=HIGH_PASS_RADIUS {
            for dx in -HIGH_PASS_RADIUS..=HIGH_PASS_RADIUS {
                s += d[((y + dy) * w as i64 + x + dx) as usize];
            }
        }
        s / (side * side) as f64
    };
    scene
        .balls
        .iter()
        .enumerate()
        .filter(|(_, b)| b.roughness >= min_roughness)
        .map(|(k, _)| {
            let pixels: Vec<u32> = (0..w * h)
                .filter(|&p| owner[p as usize] == Some(k))
                .collect();
            let n = pixels.len() as f64;
            let (cx, cy) = pixels.iter().fold((0.0, 0.0), |(x, y), &p| {
                (x + (p % w) as f64 / n, y + (p / w) as f64 / n)
            });
            let radius = (n / std::f64::consts::PI).sqrt();
            assert!(
                0.2 * radius >= HIGH_PASS_RADIUS as f64,
                "ball {k}: a radius of {radius} pixels is too small for the box"
            );
            let ball = &scene.balls[k];
            let inner: Vec<u32> = pixels
                .into_iter()
                .filter(|&p| ((p % w) as f64 - cx).hypot((p / w) as f64 - cy) <= 0.8 * radius)
                .filter(|&p| {
                    let ray = basis.ray(p % w, p / w, w, h);
                    let t = cpu::intersect_sphere(basis.origin, ray, ball.center, ball.radius);
                    let n = (basis.origin + ray * t - ball.center).normalize();
                    let r = ray - 2.0 * ray.dot(n) * n;
                    n.dot(sun_direction()) >= HORIZON_MARGIN
                        && r.dot(sun_direction()) >= HORIZON_MARGIN
                })
                .collect();
            let mean_level =
                inner.iter().map(|&p| level[p as usize]).sum::<f64>() / inner.len() as f64;
            let sum: f64 = inner
                .iter()
                .map(|&p| {
                    let (x, y) = ((p % w) as i64, (p / w) as i64);
                    (d[p as usize] - blur(x, y)).powi(2)
                })
                .sum();
            (sum / inner.len() as f64).sqrt() / mean_level
        })
        .collect()
}

/// The sun's lights (`Scene::sun_light`) under issue 37's sun map: four, their
/// irradiance the sun's, each `R / sqrt 2` from the disc's centre and a quarter turn from
/// the next, so that their mean is the centre and their mean squared angle from it `R^2 /
/// 2`, a uniform disc's.
#[test]
fn the_sun_is_four_points_on_its_disc() {
    let scene = under(
        Scene::reference(),
        map_environment(sun_map(), 30.0),
        IblTerm::KullaConty,
    );
    let environment = scene.environment_map.as_ref().unwrap();
    let sun = environment.map.sun().expect("the sun map has a sun");
    let centre = environment.from_map(sun.direction);
    let lights = scene.sun_light().expect("room for the sun").lights;
    let total: DVec3 = lights.iter().map(|l| l.radiance).sum();
    let irradiance = sun.irradiance * environment.intensity;
    assert!((total - irradiance).length() <= 1e-12 * irradiance.length());
    let spoke = |d: DVec3| (d - d.dot(centre) * centre).normalize();
    let mut squared = 0.0;
    for (k, l) in lights.iter().enumerate() {
        let angle = l.direction.dot(centre).clamp(-1.0, 1.0).acos();
        assert!(
            (angle - sun.radius / 2f64.sqrt()).abs() < 1e-9,
            "{angle} {}",
            sun.radius
        );
        let next = lights[(k + 1) % lights.len()].direction;
        assert!(spoke(l.direction).dot(spoke(next)).abs() < 1e-9);
        squared += angle * angle / lights.len() as f64;
    }
    assert!((squared - sun.radius * sun.radius / 2.0).abs() < 1e-9);
    let mean: DVec3 = lights.iter().map(|l| l.direction).sum();
    assert!(mean.normalize().dot(centre) > 1.0 - 1e-12);
}

/// Issue 37, part 2, on the picture: the high-frequency part of the split sum's difference
/// from the GPU Monte Carlo under [`sun_map`] ([`high_pass_rms`]: a box of 5 pixels on
/// balls about 40 across, over the pixels where the sun is above both the surface's and
/// the mirror direction's horizon by [`HORIZON_MARGIN`]), against the same measure of
/// the difference of two Monte Carlo images of other seeds over sqrt 2 (the Monte Carlo's
/// own noise). A ratio of at most sqrt 2 means no blotch above that noise (the split sum
/// minus the Monte Carlo holds its noise once).
///
/// The map's sun is four point lights on its disc for the balls it suits
/// (`Scene::sun_light`: here every ball from roughness 0.25), and they read the layers
/// without it. Measured at 320x180, 2048 spp, the balls of roughness 0.35, 0.55, 0.75, 0.95
/// with the term, then without: 0.73 1.14 1.09 0.98 1.32 0.75 0.97 1.04. The negative
/// control is the same scene with the lights' array full of black lights, so that the sun
/// stays in the layers (the split sum before): 3.88 2.89 1.63 1.05 4.70 2.02 1.77 1.29.
/// With the sun one light at the disc's centre (temporary switches): as a point 1.95 1.11
/// 1.09 0.98 3.36 0.77 0.97 1.04; the lobes widened by the disc (`alpha^2 + R^2 / 4`, the
/// shipped form before) 0.89 1.13 1.09 0.98 1.56 0.75 0.97 1.04; seven points (a degree-5
/// rule) 0.73 1.14 1.09 0.98 1.31 0.75 0.97 1.04. Bounds: sqrt 2 for every ball from
/// roughness 0.3; the control must exceed 2 somewhere. The balls' means against the Monte
/// Carlo's: -0.07 -0.11 -0.21 -0.09 -0.15 -0.26 -0.36 -0.06 % with the sun as lights, +1.2
/// -4.3 -5.2 +1.9 +1.3 -4.7 -9.0 +1.6 % in the layers (bounds 1 %, and the control beyond 3
/// % somewhere).
#[test]
fn the_split_sum_under_a_sun_has_no_blotches() {
    let mut r = vulkan();
    let (w, h, spp) = (320, 180, 2048);
    let mut scene = under(
        Scene::reference(),
        map_environment(sun_map(), 0.0),
        IblTerm::KullaConty,
    );
    scene.antialias = false;
    assert!(scene.sun_light().is_some(), "the sun map has a sun");
    let mut kept = scene.clone();
    kept.lights = vec![crate::scene::Light::new(DVec3::Y, DVec3::ZERO); crate::scene::MAX_LIGHTS];
    assert!(kept.sun_light().is_none(), "no room for the sun");
    let split = luminance_rgba(&r.render_hdr(&scene, w, h).unwrap().rgba);
    let split_kept = luminance_rgba(&r.render_hdr(&kept, w, h).unwrap().rgba);
    let mut mc = |seed| {
        let image = r.render_montecarlo(&scene, (w, h), spp, seed).unwrap();
        image
            .mean
            .iter()
            .map(|m| m.dot(environment::sampler::LUMINANCE))
            .collect::<Vec<f64>>()
    };
    let (a, b, c) = (mc(1), mc(2), mc(3));
    let noise: Vec<f64> = b
        .iter()
        .zip(&c)
        .map(|(x, y)| (x - y) / 2f64.sqrt())
        .collect();
    let noise = high_pass_rms(&scene, (w, h), &noise, &a, 0.3);
    let ratios = |split: &[f64]| {
        let blotches: Vec<f64> = split.iter().zip(&a).map(|(s, m)| s - m).collect();
        let blotches = high_pass_rms(&scene, (w, h), &blotches, &a, 0.3);
        println!("high-pass RMS over the ball's mean, split sum - MC: {blotches:.4?}");
        let ratios: Vec<f64> = blotches.iter().zip(&noise).map(|(b, n)| b / n).collect();
        let rough: Vec<(f64, f64)> = scene
            .balls
            .iter()
            .filter(|b| b.roughness >= 0.3)
            .zip(ratios)
            .map(|(b, ratio)| (b.roughness, ratio))
            .collect();
        assert_eq!(rough.len(), 8, "{rough:?}");
        rough
    };
    let (sun, control) = (ratios(&split), ratios(&split_kept));
    // The balls' means against the Monte Carlo's (the low frequencies the high pass leaves).
    let owner = cpu::ball_index_map(&scene, w, h);
    let mean_error = |image: &[f64]| -> Vec<f64> {
        (0..scene.balls.len())
            .filter(|&k| scene.balls[k].roughness >= 0.3)
            .map(|k| {
                let (mut s, mut m) = (0.0, 0.0);
                for (p, o) in owner.iter().enumerate() {
                    if *o == Some(k) {
                        s += image[p];
                        m += a[p];
                    }
                }
                s / m - 1.0
            })
            .collect()
    };
    let (means, means_kept) = (mean_error(&split), mean_error(&split_kept));
    println!(
        "ball means over the Monte Carlo's, less 1: the sun a light {means:.4?}, in the layers {means_kept:.4?}"
    );
    assert!(means.iter().all(|e| e.abs() < 0.01), "{means:.4?}");
    assert!(
        means_kept.iter().any(|e| e.abs() > 0.03),
        "{means_kept:.4?}"
    );
    println!("MC noise: {noise:.4?}; ratios, the sun a light: {sun:.3?}; the sun in the layers: {control:.3?}");
    for &(roughness, ratio) in &sun {
        assert!(ratio <= 2f64.sqrt(), "roughness {roughness}: {ratio:.3}");
    }
    assert!(
        control.iter().any(|&(_, ratio)| ratio > 2.0),
        "the control shows the blotches: {control:.3?}"
    );
}

/// Clear coats in the lobe mode (issue 37: nothing on the split sum's path): the coat's
/// lobe and its shares of the base's light are sampled with the whole model
/// (`shade_environment_mis` with the coat's visible normals a fourth strategy), so the
/// progressive image of `clearcoat.toml` (coat weight x coat roughness over a red plastic
/// and a copper-coloured metal, the studio) converges to the CPU Monte Carlo of the same
/// model (96x54, 2048 spp): 64 frames of 16 within 4 % on every ball (measured 2.09 %),
/// and closer than the split sum (15.8 % at worst; 187 % before the sampled model widened
/// the base's lobe as the split sum does, docs/design/coat.md, "The lobe mode"; a ball of
/// 16 pixels here). Before, the lobe mode
/// read the coat's lobe from the prefiltered layers and weighted its samples by the split
/// sum's shares: 5.18 %, and the test fails.
#[test]
fn lobe_of_clear_coats_converges_to_the_monte_carlo_of_the_model() {
    let mut r = vulkan();
    let (w, h) = (96, 54);
    let mut scene = super::montecarlo::scene_file("clearcoat.toml", str::to_string);
    scene.ibl_method = IblMethod::Lobe;
    scene.ibl_samples = 16;
    let (e_lobe, e_split) = lobe_and_split_sum_errors(&mut r, &scene, (w, h), 64);
    println!("clearcoat.toml: lobe 64 x 16 {e_lobe:.4}, split sum {e_split:.4}");
    assert!(e_lobe < 0.04, "{e_lobe}");
    assert!(e_lobe < e_split, "{e_lobe} vs {e_split}");
}
