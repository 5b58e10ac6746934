//! Harmonics or a map per roughness (issue 15, docs/design/environment.md, "Harmonics or a
//! map per roughness"): the Kulla-Conty multiple-scattering lobe under an environment
//! needs, per roughness, the zonal convolution `C(n) = int k(n.w) L(w) dw` with
//! `k(t) = (1 - E(t)) t`. Two ways to have it at shading time, measured against the exact
//! sum at random normals:
//! - `sh`: the map projected on spherical harmonics of `size` bands, convolved by
//!   Funk-Hecke at the ball's exact roughness (`environment::harmonics`);
//! - `map`: a convolved map `size` texels wide per roughness layer, nine layers, read
//!   bilinearly and linearly between the two layers around the roughness, as
//!   `Prefiltered::multiple` reads the renderer's 32-wide layers (the 32-wide row *is* the
//!   renderer's `Prefiltered::new`; 16 and 64 are the same code at other widths).
//!
//! The exact `C(n)` is the direct sum over the texels of the map's 256-wide mip level (the
//! kernel is smooth: the box filter of the chain costs it nothing) with `k` read from the
//! tables at each texel; the harmonics are projected from that same level, so the `sh`
//! error is the band limit alone. The error of one normal is the largest relative error of
//! its three channels.

use std::f64::consts::PI;
use std::hint::black_box;
use std::time::Instant;

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::table::{sci, Table};
use super::{median, Goal, Sweep};
use crate::plot::{Plot, Series, Style};
use shadeballs::environment::harmonics::{convolve_eval, project, zonal_coefficients};
use shadeballs::environment::prefilter::{
    convolved_roughness, kernels, layer, prefilter_convolved, Level, CONVOLVED_LEVELS,
    CONVOLVED_WIDTH,
};
use shadeballs::environment::{uv_to_direction, Builtin, EnvMap, MipChain, Prefiltered};
use shadeballs::error::Result;
use shadeballs::lut::{BakeConfig, Tables};

/// The roughness values measured.
pub const ROUGHNESS: [f64; 4] = [0.3, 0.5, 0.75, 1.0];
/// Band counts of the harmonics.
pub const BANDS: [usize; 6] = [3, 4, 5, 7, 9, 13];
/// Widths of the convolved maps (height half).
pub const MAP_WIDTHS: [u32; 3] = [16, 32, 64];
/// Width of the mip level the exact sum and the projection read.
pub const REFERENCE_WIDTH: u32 = 256;
/// Width the built-ins are generated at.
pub const ENVIRONMENT_WIDTH: u32 = 1024;
/// The goal: mean relative error of the lobe integral.
pub const GOAL_MEAN_REL_ERR: f64 = 0.02;
/// Seed of the random normals.
pub const SEED: u64 = 1999;

/// `n` uniformly random unit vectors (`z = 1 - 2 u`, azimuth `2 pi v`; fixed seed).
pub fn random_normals(n: usize, seed: u64) -> Vec<DVec3> {
    shadeballs::lut::accuracy::random_points(n, seed)
        .into_iter()
        .map(|(u, v)| {
            let z = 1.0 - 2.0 * u;
            let s = (1.0 - z * z).max(0.0).sqrt();
            let (sp, cp) = (2.0 * PI * v).sin_cos();
            DVec3::new(s * cp, s * sp, z)
        })
        .collect()
}

/// The Kulla-Conty kernel `(1 - E(t)) t` at `roughness` as the tables read it (0 below the
/// horizon).
pub fn kc_kernel(tables: &Tables, roughness: f64) -> impl Fn(f64) -> f64 + '_ {
    move |t| {
        if t <= 0.0 {
            0.0
        } else {
            let t = t.min(1.0);
            tables.lut_loss(t as f32, roughness as f32) as f64 * t
        }
    }
}

/// The level of `chain` `width` wide (else the narrowest wider one, else level 0) as a map
/// (its radiance: the level times the chain's scale).
pub fn level_map(chain: &MipChain, width: u32) -> EnvMap {
    let level = chain
        .levels
        .iter()
        .rev()
        .find(|l| l.width >= width)
        .unwrap_or(&chain.levels[0]);
    let s = chain.scale;
    let texels = level
        .texels
        .iter()
        .map(|t| [t[0] * s, t[1] * s, t[2] * s])
        .collect();
    EnvMap::new(level.width, level.height, texels).expect("a mip level is a valid map")
}

/// `map`'s texels as (centre direction, radiance times solid angle).
pub fn weighted_texels(map: &EnvMap) -> Vec<(DVec3, DVec3)> {
    let (w, h) = (map.width(), map.height());
    let mut out = Vec::with_capacity((w * h) as usize);
    for j in 0..h {
        let omega = map.texel_solid_angle(j);
        for i in 0..w {
            let uv = DVec2::new((i as f64 + 0.5) / w as f64, (j as f64 + 0.5) / h as f64);
            out.push((uv_to_direction(uv), map.texel(i, j) * omega));
        }
    }
    out
}

/// The direct sum `sum k(n.w) L dOmega` over `texels` ([`weighted_texels`]).
pub fn direct_convolution(
    texels: &[(DVec3, DVec3)],
    kernel: &impl Fn(f64) -> f64,
    n: DVec3,
) -> DVec3 {
    texels
        .iter()
        .map(|&(d, l)| {
            let t = n.dot(d);
            if t > 0.0 {
                l * kernel(t)
            } else {
                DVec3::ZERO
            }
        })
        .sum()
}

/// The convolved layers (`0..=CONVOLVED_LEVELS`, as `Prefiltered::convolved`) at `width`
/// (height half) from `source`: `prefilter_convolved` at each texel centre, rounded to f16
/// as the GPU stores them. At [`CONVOLVED_WIDTH`] this is what `Prefiltered::new` builds.
pub fn convolved_layers(source: &Level, kernels: &[f32], width: u32) -> Vec<Level> {
    (0..=CONVOLVED_LEVELS)
        .map(|j| {
            layer(width, width / 2, |n| {
                prefilter_convolved(source, kernels, j, n)
            })
        })
        .collect()
}

/// Mean and 99th percentile of `errors` (sorted in place).
fn mean_p99(errors: &mut [f64]) -> (f64, f64) {
    errors.sort_by(f64::total_cmp);
    let mean = errors.iter().sum::<f64>() / errors.len() as f64;
    let k = ((errors.len() as f64 * 0.99).ceil() as usize).clamp(1, errors.len()) - 1;
    (mean, errors[k])
}

/// The largest relative error over the channels of `estimate` against `exact`.
fn rel_err(estimate: DVec3, exact: DVec3) -> f64 {
    ((estimate - exact).abs() / exact.max(DVec3::splat(1e-30))).max_element()
}

/// Median nanoseconds of one call of `f` over `normals` (`repeats` passes over them).
fn eval_ns(normals: &[DVec3], repeats: usize, f: impl Fn(DVec3) -> DVec3) -> f64 {
    let mut times = Vec::with_capacity(repeats);
    for pass in 0..repeats + 1 {
        let start = Instant::now();
        let mut acc = DVec3::ZERO;
        for &n in normals {
            acc += f(black_box(n));
        }
        black_box(acc);
        let ns = start.elapsed().as_secs_f64() * 1e9 / normals.len() as f64;
        if pass > 0 {
            times.push(ns);
        }
    }
    median(&mut times)
}

/// One measured row.
struct Row {
    environment: &'static str,
    roughness: f64,
    method: &'static str,
    size: u32,
    mean: f64,
    p99: f64,
    ns: f64,
}

/// The sweep: `sh` at [`BANDS`] and `map` at [`MAP_WIDTHS`], for `studio` and `sky`, at
/// [`ROUGHNESS`], over 300 random normals (60 quick).
pub fn harmonics_sweep(quick: bool) -> Result<Sweep> {
    let normals = random_normals(if quick { 60 } else { 300 }, SEED);
    let repeats = if quick { 5 } else { 15 };
    // Height-correlated Smith G: the reference scene's (docs/truth.md).
    let tables = shadeballs::lut::bake(&BakeConfig {
        geometry: shadeballs::brdf::Geometry::SmithCorrelated,
        ..BakeConfig::default()
    });
    let kern = kernels(&tables);
    let max_bands = *BANDS.iter().max().expect("bands");
    let mut rows = Vec::new();
    let mut interpolation = Vec::new();
    for env in [Builtin::Studio, Builtin::Sky] {
        let map = env.generate(ENVIRONMENT_WIDTH);
        let chain = MipChain::new(&map);
        let reference = level_map(&chain, REFERENCE_WIDTH);
        let texels = weighted_texels(&reference);
        let unit: Vec<(DVec3, DVec3)> = texels
            .iter()
            .enumerate()
            .map(|(k, &(d, _))| {
                let j = k as u32 / reference.width();
                (d, DVec3::splat(reference.texel_solid_angle(j)))
            })
            .collect();
        let coeffs = project(&reference, max_bands);
        // The convolved layers alone (`multiple` reads nothing else; the specular layers
        // `Prefiltered::new` also builds took most of this sweep's time).
        let source = &chain.levels[chain.convolution_source() as usize];
        let maps: Vec<(u32, Prefiltered)> = MAP_WIDTHS
            .iter()
            .map(|&w| {
                let p = Prefiltered {
                    specular: Vec::new(),
                    convolved: convolved_layers(source, &kern, w),
                };
                (w, p)
            })
            .collect();
        for &r in &ROUGHNESS {
            let kernel = kc_kernel(&tables, r);
            let exact: Vec<DVec3> = normals
                .par_iter()
                .map(|&n| direct_convolution(&texels, &kernel, n))
                .collect();
            for &bands in &BANDS {
                let zonal = zonal_coefficients(&kernel, bands);
                let c = &coeffs[..bands * bands];
                let mut errors: Vec<f64> = normals
                    .iter()
                    .zip(&exact)
                    .map(|(&n, &e)| rel_err(convolve_eval(c, &zonal, n), e))
                    .collect();
                let (mean, p99) = mean_p99(&mut errors);
                let ns = eval_ns(&normals, repeats, |n| convolve_eval(c, &zonal, n));
                rows.push(Row {
                    environment: env.name(),
                    roughness: r,
                    method: "sh",
                    size: bands as u32,
                    mean,
                    p99,
                    ns,
                });
            }
            let scale = PI * tables.lut_loss_avg(r as f32) as f64;
            // The roughness interpolation alone: the exact sums at the two layers around
            // `r`, each over its own weight sum, interpolated as `Prefiltered::multiple` does.
            let s = r * (CONVOLVED_LEVELS - 1) as f64;
            let k0 = (s.floor() as u32).min(CONVOLVED_LEVELS - 2);
            let f = s - k0 as f64;
            if f > 1e-9 && f < 1.0 - 1e-9 {
                let normalised = |layer: u32| -> Vec<DVec3> {
                    let k = kc_kernel(&tables, convolved_roughness(layer));
                    normals
                        .par_iter()
                        .map(|&n| {
                            direct_convolution(&texels, &k, n)
                                / direct_convolution(&unit, &k, n).x.max(1e-30)
                        })
                        .collect()
                };
                let (a, b) = (normalised(k0 + 1), normalised(k0 + 2));
                let mut errors: Vec<f64> = (0..normals.len())
                    .map(|i| rel_err(a[i].lerp(b[i], f) * scale, exact[i]))
                    .collect();
                interpolation.push((env.name(), r, mean_p99(&mut errors).0));
            }
            for (w, p) in &maps {
                let mut errors: Vec<f64> = normals
                    .iter()
                    .zip(&exact)
                    .map(|(&n, &e)| rel_err(p.multiple(n, r) * scale, e))
                    .collect();
                let (mean, p99) = mean_p99(&mut errors);
                let ns = eval_ns(&normals, repeats, |n| p.multiple(n, r) * scale);
                rows.push(Row {
                    environment: env.name(),
                    roughness: r,
                    method: "map",
                    size: *w,
                    mean,
                    p99,
                    ns,
                });
            }
        }
    }
    Ok(build_sweep(&rows, &interpolation, normals.len()))
}

/// `interpolation`: (environment, roughness, mean relative error of the roughness
/// interpolation between the layers alone) for the roughness values between layers.
fn build_sweep(rows: &[Row], interpolation: &[(&str, f64, f64)], normals: usize) -> Sweep {
    let mut t = Table::new(
        "harmonics",
        "Harmonics or a map per roughness: the Kulla-Conty lobe integral under an environment",
        &[
            "environment",
            "roughness",
            "method",
            "size",
            "mean_rel_err",
            "p99_rel_err",
            "eval_ns",
        ],
    );
    for row in rows {
        t.push(vec![
            row.environment.to_string(),
            format!("{}", row.roughness),
            row.method.to_string(),
            row.size.to_string(),
            sci(row.mean),
            sci(row.p99),
            format!("{:.0}", row.ns),
        ]);
    }
    t.note = format!(
        "C(n) = int (1 - E(n.w)) (n.w) L(w) dw at {normals} random unit normals (seed {SEED}), \
         against the direct sum over the {REFERENCE_WIDTH}-wide mip level of the built-in \
         generated {ENVIRONMENT_WIDTH} wide; error: the largest relative error of the three \
         channels. `sh`: size = bands (size^2 RGB coefficients shared by every roughness, \
         size zonal factors per roughness), projected from the same level, Funk-Hecke at the \
         exact roughness. `map`: size = width of each of {CONVOLVED_LEVELS} convolved layers \
         (size x size/2 f16 RGBA texels each), summed over the 64-wide level with the \
         64-sample kernel table, read bilinearly and linearly between the two layers around \
         the roughness, times pi (1 - E_avg); the 32-wide row is the renderer's \
         `Prefiltered::new`. eval_ns: median CPU time of one evaluation (one thread)."
    );
    if !interpolation.is_empty() {
        let parts: Vec<String> = interpolation
            .iter()
            .map(|(e, r, m)| format!("{e} at {r}: {:.2} %", m * 100.0))
            .collect();
        t.note.push_str(&format!(
            " Of the map's error, the interpolation between the two roughness layers alone \
             (the exact sums at those layers, normalised and interpolated as the map is) \
             costs {} mean.",
            parts.join(", ")
        ));
    }
    let colours: [[u8; 3]; 4] = [[0, 114, 178], [213, 94, 0], [0, 158, 115], [204, 121, 167]];
    let mut plots = Vec::new();
    for env in ["studio", "sky"] {
        let mut series = Vec::new();
        for (k, &r) in ROUGHNESS.iter().enumerate() {
            for (method, style) in [("sh", Style::Marked), ("map", Style::Dashed)] {
                let points = rows
                    .iter()
                    .filter(|x| x.environment == env && x.roughness == r && x.method == method)
                    .map(|x| (x.size as f64, x.mean.max(1e-9)))
                    .collect();
                series.push(Series {
                    label: format!("{method}, roughness {r}"),
                    points,
                    colour: Some(colours[k % colours.len()]),
                    style,
                });
            }
        }
        plots.push((
            format!("harmonics_{env}"),
            Plot {
                title: format!("Kulla-Conty lobe integral under {env}: mean relative error"),
                x_label: "size: SH bands (solid) or map width in texels (dashed)".into(),
                y_label: "mean relative error".into(),
                series,
                goals: vec![("2 %".into(), None, Some(GOAL_MEAN_REL_ERR))],
            },
        ));
    }

    let map32: Vec<&Row> = rows
        .iter()
        .filter(|x| x.method == "map" && x.size == CONVOLVED_WIDTH && x.roughness >= 0.3)
        .collect();
    let worst = map32
        .iter()
        .max_by(|a, b| a.mean.total_cmp(&b.mean))
        .expect("map rows");
    let mut goals = vec![Goal {
        what: format!(
            "kulla-conty lobe integral within 2 % mean relative error for roughness >= 0.3 in \
             studio and sky: per-row map {CONVOLVED_WIDTH} wide"
        ),
        figure: format!(
            "worst {:.2} % ({}, roughness {}; p99 {:.2} %), {:.0} ns a read",
            worst.mean * 100.0,
            worst.environment,
            worst.roughness,
            worst.p99 * 100.0,
            worst.ns
        ),
        met: map32.iter().all(|x| x.mean < GOAL_MEAN_REL_ERR),
    }];
    let sh_at = |bands: usize| -> f64 {
        rows.iter()
            .filter(|x| x.method == "sh" && x.size == bands as u32 && x.roughness == 0.3)
            .map(|x| x.mean)
            .fold(0.0, f64::max)
    };
    let smallest = BANDS.iter().find(|&&b| sh_at(b) < GOAL_MEAN_REL_ERR);
    let max_bands = *BANDS.iter().max().expect("bands");
    goals.push(Goal {
        what: "kulla-conty lobe integral by spherical harmonics: the smallest band count within \
               2 % mean relative error at roughness 0.3 in studio and sky"
            .into(),
        figure: match smallest {
            Some(&b) => format!(
                "{b} bands ({} coefficients): worst {:.2} %",
                b * b,
                sh_at(b) * 100.0
            ),
            None => format!(
                "none up to {max_bands} bands ({max_bands} bands: worst {:.2} %)",
                sh_at(max_bands) * 100.0
            ),
        },
        met: smallest.is_some(),
    });
    Sweep {
        tables: vec![t],
        plots,
        goals,
    }
}
