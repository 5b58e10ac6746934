//! Image-based lighting: each real-time method against the Monte Carlo integral of its own
//! model (`ibl.csv`), the cost of preparing a map (`prefilter.csv`) and of each method's
//! term in a frame (`ibl_frame.csv`).
//!
//! Accuracy: the reference balls (a copper row and a white row, F0 0.95, every ball with
//! the term) under `studio` and `sky`, rendered on the GPU in linear radiance and with
//! the Monte Carlo of the same model with the same tables (no split sum, no prefiltering:
//! `Renderer::render_montecarlo_part` on the GPU, `cpu::render_montecarlo_part` where the
//! device cannot render to `Rgba32Float`). Per ball pixel the relative error of luminance;
//! per roughness the mean and the 99th percentile over the pixels of the two balls of that
//! roughness. `part = whole`: the method's image; `part = ms`: what the term adds (the
//! image with the term minus the image without it) against the Monte Carlo integral of
//! the model's multiple-scattering lobe alone. The Monte Carlo noise is reported beside
//! (`mc_rel_std_err`, the mean relative standard error of the same pixels): an error
//! near it is noise, not the method.

use std::sync::Arc;

use glam::DVec3;

use super::table::{sci, Table};
use super::{device, median, Goal, Sweep};
use crate::plot::{Plot, Series, Style};
use shadeballs::cpu::{self, Part};
use shadeballs::environment::prefilter::SPECULAR_SAMPLES;
use shadeballs::environment::{Builtin, Environment, IblTerm};
use shadeballs::error::Result;
use shadeballs::gpu::{Renderer, Target};
use shadeballs::lut::BakeConfig;
use shadeballs::scene::{Material, Model, Scene, REFERENCE_ROUGHNESS};

/// Luminance weights (Rec. 709) of the relative errors.
const LUMINANCE: DVec3 = DVec3::new(0.2126, 0.7152, 0.0722);
/// Bands of `mu_o = n.v` the whole image's error is broken down by (grazing to facing).
const MU_BANDS: [(f64, f64); 4] = [(0.0, 0.25), (0.25, 0.5), (0.5, 0.75), (0.75, 1.01)];
/// Pixels whose reference luminance is below this are left out of relative errors.
const LUMINANCE_FLOOR: f64 = 1e-4;

/// The measured balls: the reference scene's copper row over a white metal row (F0 0.95),
/// every ball with the term, lit by `environment` alone with `term`.
pub fn ibl_scene(environment: Environment, term: IblTerm) -> Scene {
    let mut scene = Scene::reference();
    for b in scene.balls.iter_mut() {
        if !b.model.has_term() {
            b.material = Material::metal(DVec3::splat(0.95));
        }
        b.model = Model::from_term(term);
    }
    Scene {
        lights: Vec::new(),
        environment: DVec3::ZERO,
        environment_map: Some(environment),
        // One ray through each pixel's centre on both sides (the GPU's image and the
        // Monte Carlo reference's): the errors are the lighting's, not the silhouettes'.
        antialias: false,
        ..scene
    }
}

/// Per-pixel relative errors of `image` against `reference` (luminance), grouped by the
/// roughness of the ball each pixel sees: (roughness, mean, p99) per entry of
/// REFERENCE_ROUGHNESS with the reference's mean relative standard error over the same
/// pixels; only pixels whose `mu_o = n.v` lies in `mu_band`. `image` is `scene` rendered
/// under its pixel filter: errors unless `reference` has the same
/// ([`cpu::MonteCarloImage::compares_with`]).
pub fn errors_by_roughness(
    scene: &Scene,
    w: u32,
    h: u32,
    image: &[DVec3],
    reference: &cpu::MonteCarloImage,
    mu_band: (f64, f64),
) -> Result<Vec<(f64, f64, f64, f64)>> {
    reference.compares_with(scene.antialias)?;
    let basis = scene.camera.basis(w, h);
    let mut out = Vec::new();
    for &r in &REFERENCE_ROUGHNESS {
        let mut errs = Vec::new();
        let mut noise = Vec::new();
        for py in 0..h {
            for px in 0..w {
                let d = basis.ray(px, py, w, h);
                let hit =
                    cpu::nearest_ball(scene, basis.origin, d).map(|(t, k)| (t, &scene.balls[k]));
                let Some((t, b)) = hit else { continue };
                if b.roughness != r {
                    continue;
                }
                let n = (basis.origin + t * d - b.center).normalize();
                let mu_o = n.dot(-d);
                if mu_o < mu_band.0 || mu_o >= mu_band.1 {
                    continue;
                }
                let k = (py * w + px) as usize;
                let y_ref = reference.mean[k].dot(LUMINANCE);
                if y_ref < LUMINANCE_FLOOR {
                    continue;
                }
                errs.push((image[k].dot(LUMINANCE) - y_ref).abs() / y_ref);
                noise.push(reference.std_error[k].dot(LUMINANCE) / y_ref);
            }
        }
        let n = errs.len().max(1) as f64;
        let mean = errs.iter().sum::<f64>() / n;
        let mean_noise = noise.iter().sum::<f64>() / n;
        errs.sort_by(f64::total_cmp);
        let p99 = errs
            .get(((errs.len() as f64 * 0.99) as usize).min(errs.len().saturating_sub(1)))
            .copied()
            .unwrap_or(f64::NAN);
        out.push((r, mean, p99, mean_noise));
    }
    Ok(out)
}

/// The Monte Carlo of `part` of `scene`'s model: on the GPU where the renderer can
/// (`Renderer::render_montecarlo_part`, which equals the CPU's within 3 standard errors:
/// src/gpu/tests/montecarlo.rs), else on the CPU. Both trace pixel centres.
fn montecarlo(
    renderer: &mut Renderer,
    (scene, e): (&Scene, &shadeballs::lut::TableSet),
    (w, h): (u32, u32),
    (spp, seed): (u32, u64),
    part: Part,
) -> Result<cpu::MonteCarloImage> {
    if renderer.truth_supported() {
        renderer.render_montecarlo_part(scene, (w, h), (spp, seed), part)
    } else {
        cpu::render_montecarlo_part(
            scene,
            &shadeballs::prepared::Prepared::new(scene, e),
            w,
            h,
            spp,
            seed,
            part,
        )
    }
}

/// Linear RGB of an `Rgba32Float` image's pixels (alpha dropped).
pub(super) fn linear(rgba: &[f32]) -> Vec<DVec3> {
    rgba.chunks_exact(4)
        .map(|p| DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64))
        .collect()
}

fn series(label: &str) -> Series {
    Series {
        label: label.into(),
        style: Style::Marked,
        ..Default::default()
    }
}

/// The IBL sweep on `renderer`.
pub fn ibl_sweep(renderer: &mut Renderer, quick: bool) -> Result<Sweep> {
    renderer.set_draw_options(shadeballs::gpu::DrawOptions::default());
    renderer.set_bake_config(BakeConfig::default());
    renderer.set_multiple_scattering_term(true);
    let mut goals = Vec::new();
    let mut plots = Vec::new();
    // Monte Carlo noise sets the floor of the measured errors: 8192 samples keep its mean
    // relative standard error near 1 % (reported per row).
    let (w, h, spp) = if quick {
        (96, 54, 256)
    } else {
        (160, 90, 8192)
    };

    // Accuracy against Monte Carlo.
    let mut accuracy = Table::new(
        "ibl",
        &format!(
            "IBL: each method against the Monte Carlo integral of its own model ({w}x{h}, {spp} spp; relative error of luminance over the ball pixels of each roughness)"
        ),
        &[
            "environment",
            "method",
            "roughness",
            "part",
            "mean_rel_err",
            "p99_rel_err",
            "mc_rel_std_err",
        ],
    );
    let mut whereabouts = Table::new(
        "ibl_where",
        "IBL: where the whole image's error lies, by n.v of the pixel (mean relative error of luminance)",
        &["environment", "method", "roughness", "mu_o", "mean_rel_err", "mc_rel_std_err"],
    );
    let mut worst_ms = 0.0f64;
    let mut worst_whole = 0.0f64;
    for builtin in [Builtin::Studio, Builtin::Sky] {
        let environment = Environment::builtin(builtin);
        let mut whole_series = Vec::new();
        let mut ms_series = Vec::new();
        for term in IblTerm::ALL {
            let scene = ibl_scene(environment.clone(), term);
            let tables = shadeballs::lut::bake(&BakeConfig {
                geometry: scene.effective_geometry(),
                ..BakeConfig::default()
            });
            let e = shadeballs::lut::TableSet::full(tables);
            renderer.set_multiple_scattering_term(true);
            let with = linear(&renderer.render_hdr(&scene, w, h)?.rgba);
            renderer.set_multiple_scattering_term(false);
            let without = linear(&renderer.render_hdr(&scene, w, h)?.rgba);
            renderer.set_multiple_scattering_term(true);
            let term_only: Vec<DVec3> = with.iter().zip(&without).map(|(a, b)| *a - *b).collect();
            let seed = 7;
            let mc_whole = montecarlo(renderer, (&scene, &e), (w, h), (spp, seed), Part::Whole)?;
            let mc_ms = montecarlo(renderer, (&scene, &e), (w, h), (spp, seed), Part::Multiple)?;
            let mut sw = series(&format!("{term}, whole"));
            let mut sm = series(&format!("{term}, ms"));
            for (part, image, reference, s) in [
                ("whole", &with, &mc_whole, &mut sw),
                ("ms", &term_only, &mc_ms, &mut sm),
            ] {
                let all = (f64::NEG_INFINITY, f64::INFINITY);
                for (r, mean, p99, noise) in
                    errors_by_roughness(&scene, w, h, image, reference, all)?
                {
                    accuracy.push(vec![
                        builtin.to_string(),
                        term.to_string(),
                        format!("{r}"),
                        part.to_string(),
                        sci(mean),
                        sci(p99),
                        sci(noise),
                    ]);
                    s.points.push((r, mean.max(1e-6)));
                    if r >= 0.3 && mean.is_finite() {
                        if part == "whole" {
                            worst_whole = worst_whole.max(mean);
                        } else if term == IblTerm::KullaConty {
                            worst_ms = worst_ms.max(mean);
                        }
                    }
                }
            }
            whole_series.push(sw);
            ms_series.push(sm);
            // Where the whole image's error lies: by n.v.
            for band in MU_BANDS {
                for (r, mean, _, noise) in
                    errors_by_roughness(&scene, w, h, &with, &mc_whole, band)?
                {
                    whereabouts.push(vec![
                        builtin.to_string(),
                        term.to_string(),
                        format!("{r}"),
                        format!("{:.2}-{:.2}", band.0, band.1),
                        sci(mean),
                        sci(noise),
                    ]);
                }
            }
        }
        let mut all = whole_series;
        all.extend(ms_series);
        plots.push((
            format!("ibl_{builtin}"),
            Plot {
                title: format!("IBL under {builtin}: mean relative error against Monte Carlo"),
                x_label: "roughness".into(),
                y_label: "mean relative error".into(),
                series: all,
                goals: vec![
                    ("2 % (ms, kulla-conty)".into(), None, Some(0.02)),
                    ("3 % (whole)".into(), None, Some(0.03)),
                ],
            },
        ));
    }
    goals.push(Goal {
        what: "ibl: the kulla-conty term (ms part) within 2 % mean relative error of its Monte Carlo integral, roughness >= 0.3, studio and sky".into(),
        figure: format!("worst {:.2} % (ibl.csv)", 100.0 * worst_ms),
        met: worst_ms <= 0.02,
    });
    goals.push(Goal {
        what: "ibl: every method's whole image within 3 % mean relative error of its Monte Carlo, roughness >= 0.3".into(),
        figure: format!("worst {:.2} % (ibl.csv)", 100.0 * worst_whole),
        met: worst_whole <= 0.03,
    });

    // Furnace through the map path.
    let mut furnace_worst = 0u8;
    for term in IblTerm::ALL {
        let mut scene = Scene {
            lights: Vec::new(),
            environment: DVec3::ZERO,
            environment_map: Some(Environment::builtin(Builtin::White)),
            ..Scene::furnace()
        };
        scene.set_term(term);
        let (fw, fh) = (320, 180);
        let image = renderer.render_ldr(&scene, fw, fh)?.rgba;
        let basis = scene.camera.basis(fw, fh);
        let background = image[0];
        for (k, px) in image.chunks_exact(4).enumerate() {
            let d = basis.ray(k as u32 % fw, k as u32 / fw, fw, fh);
            let on_term_ball = scene.balls.iter().any(|b| {
                b.model.has_term()
                    && cpu::intersect_sphere(basis.origin, d, b.center, b.radius) > 0.0
            });
            if on_term_ball {
                furnace_worst = furnace_worst.max(px[0].abs_diff(background));
            }
        }
    }
    goals.push(Goal {
        what: "ibl: furnace through the map path (white, F0 = 1): every ball with the term within 1/255 of the background, every method".into(),
        figure: format!("worst {furnace_worst}/255"),
        met: furnace_worst <= 1,
    });

    // Preparing a map.
    let mut prefilter = Table::new(
        "prefilter",
        "IBL: preparing a map (studio) on the GPU: kernels, mip chain and split-sum table on the CPU, upload and prefiltering to the queue's completion (median of 3)",
        &["width", "height", "samples", "ms"],
    );
    let widths: &[u32] = if quick {
        &[512, 1024]
    } else {
        &[512, 1024, 2048, 4096]
    };
    let mut prefilter_series = series("prepare a map (studio)");
    let mut at_1024 = f64::NAN;
    for &width in widths {
        let map = Arc::new(Builtin::Studio.generate(width));
        let mut times = Vec::new();
        for _ in 0..3 {
            // A new Arc each time: the renderer keys its textures by the map's identity.
            let environment = Environment {
                map: Arc::new((*map).clone()),
                ..Environment::builtin(Builtin::White)
            };
            let scene = ibl_scene(environment, IblTerm::KullaConty);
            // The renderer submits the prefiltering without waiting: timed here to the
            // queue's completion.
            let t = std::time::Instant::now();
            renderer.prepare_environment(&scene)?;
            let _ = renderer
                .gpu()
                .device
                .poll(wgpu::PollType::wait_indefinitely());
            times.push(t.elapsed().as_secs_f64() * 1e3);
        }
        let ms = median(&mut times);
        if width == 1024 {
            at_1024 = ms;
        }
        prefilter_series
            .points
            .push(((width * width / 2) as f64, ms));
        prefilter.push(vec![
            width.to_string(),
            (width / 2).to_string(),
            SPECULAR_SAMPLES.to_string(),
            format!("{ms:.1}"),
        ]);
    }
    goals.push(Goal {
        what: "ibl: preparing a 1024x512 map in at most 200 ms".into(),
        figure: format!("{at_1024:.1} ms ({})", renderer.gpu().describe()),
        met: at_1024 <= 200.0,
    });
    plots.push((
        "prefilter".into(),
        Plot {
            title: "IBL: preparing a map against its size".into(),
            x_label: "texels".into(),
            y_label: "time (ms)".into(),
            series: vec![prefilter_series],
            goals: vec![("200 ms".into(), None, Some(200.0))],
        },
    ));

    // The term's cost in a frame under the map (the quick run's frame a quarter of the
    // pixels: under a map a lavapipe frame at 1280x720 takes a fifth of a second).
    let (fw, fh) = if quick { (640, 360) } else { (1280, 720) };
    let mut frame = Table::new(
        "ibl_frame",
        &format!("IBL: frame time with and without the term under studio ({fw}x{fh}, median; ratio: median over alternating pairs)"),
        &["method", "with_term_ms", "without_term_ms", "ratio"],
    );
    let repeats = if quick { 3 } else { 21 };
    let (_texture, view) = device::frame_target(renderer.gpu(), fw, fh);
    let target = Target {
        view: &view,
        format: device::FRAME_FORMAT,
        width: fw,
        height: fh,
    };
    let studio = Environment::builtin(Builtin::Studio);
    let mut worst_ratio = 0.0f64;
    for term in IblTerm::ALL {
        let scene = ibl_scene(studio.clone(), term);
        // Prefilter outside the timed frames.
        renderer.render(&scene, target)?;
        let (mut times, ratio) =
            super::render::alternate(renderer, [&scene, &scene], repeats, |r, k| {
                r.set_multiple_scattering_term(k == 0)
            })?;
        renderer.set_multiple_scattering_term(true);
        worst_ratio = worst_ratio.max(ratio);
        frame.push(vec![
            term.to_string(),
            format!("{:.2}", median(&mut times[0])),
            format!("{:.2}", median(&mut times[1])),
            format!("{ratio:.3}"),
        ]);
    }
    goals.push(Goal {
        what: format!(
            "ibl: each method's term at most 1.10x the frame without it (studio, {fw}x{fh})"
        ),
        figure: format!("worst {worst_ratio:.3}x (ibl_frame.csv)"),
        met: worst_ratio <= 1.10,
    });
    Ok(Sweep {
        tables: vec![accuracy, whereabouts, prefilter, frame],
        plots,
        goals,
    })
}
