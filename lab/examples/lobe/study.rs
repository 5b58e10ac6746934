//! `lobe_sweep --study`: the lobe's single-frame estimator split into bias and noise, for
//! each candidate change (docs/design/environment.md, "Lighting that follows the lobe",
//! "What the error is made of").
//!
//! On the CPU in f64, from the same pieces as the renderers' lobe (the pixel's R2 points,
//! GGX visible normals, `lobe_lod` over the same f16 mip chain, the prefiltered layers and
//! the split sum's table of `CpuEnvironment`): frame `k` of a variant takes the sample
//! indices `k N .. (k + 1) N` with the level's count fixed at `N` (each frame an
//! independent draw of the one-frame estimator). Over `K` frames, against the Monte Carlo:
//! the one-frame error (the sweep's measure, averaged over the frames), the bias (the mean
//! image's error) and the noise (a frame's distance from the mean image), each the worst
//! over the metal balls of roughness >= 0.3 of the mean relative luminance error over the
//! ball's pixels.

use glam::DVec3;
use rayon::prelude::*;
use shadeballs::brdf::{
    alpha_from_roughness, f_add_preset, f_micro, f_ms, f_ms_norm, f_schlick, Geometry,
    GAMES202_EDGE_TINT,
};
use shadeballs::cpu::{self, CpuEnvironment, MonteCarloImage};
use shadeballs::environment::{lobe, prefilter, Environment};
use shadeballs::lut::TableSet;
use shadeballs::sampling::{sample_vndf, vndf_density, Frame};
use shadeballs::scene::Scene;

use super::{LUMINANCE, LUMINANCE_FLOOR};

/// Where the points of a pixel's frame come from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Points {
    /// Before: the R2 sequence rotated per pixel (Cranley-Patterson), every frame.
    Rotated,
    /// The R2 sequence rotated per frame, the same points for every pixel.
    Fixed,
    /// Hammersley's `N` points `(i / N, radical_inverse(i))`, rotated per pixel and frame.
    Hammersley,
    /// Hammersley's points in 32-bit fixed point, each coordinate XORed with a hash of the
    /// pixel and the frame (a digital shift: the set stays a (0, m, 2)-net for `N = 2^m`).
    HammersleyXor,
    /// The 2-D Sobol sequence (van der Corput, then the Pascal matrix's dimension),
    /// XORed with the pixel's hash: each aligned block of `2^m` indices is a
    /// (0, m, 2)-net, so frames continue it (shipped since issue 37's progressive
    /// measure: `lobe::lobe_frame_point`).
    SobolXor,
    /// Shipped when this study was made: frame 0 Hammersley's net XORed with the pixel's
    /// hash (`lobe::lobe_net_point`), later frames the R2 points from index `k N`.
    NetThenR2,
}

/// How the samples are combined into the single scattering.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Form {
    /// `sum w L / N` (before).
    Plain,
    /// `sum w L / sum w` times the split sum's `F0 A + B` (shipped).
    SelfNormalised,
    /// The split sum plus `sum w (L - P) / N`, `P` the prefiltered layers along each sample.
    ControlVariate,
}

/// One candidate estimator.
#[derive(Clone, Copy, Debug)]
pub struct Variant {
    pub name: &'static str,
    pub points: Points,
    pub form: Form,
    /// Added to each sample's level.
    pub lod_bias: f64,
    /// A sample's radiance clamped to this many times the prefiltered radiance along the
    /// dominant direction (per channel), or none.
    pub clamp: Option<f64>,
    /// The Kulla-Conty term from the same samples (`f_add f_ms mu_i / pdf`) instead of the
    /// convolved layer.
    pub ms_from_samples: bool,
}

impl Variant {
    /// The estimator before this study: R2 rotated per pixel, `sum w L / N`.
    pub const BEFORE: Variant = Variant {
        name: "before",
        points: Points::Rotated,
        form: Form::Plain,
        lod_bias: 0.0,
        clamp: None,
        ms_from_samples: false,
    };
    /// The shipped estimator (`lighting.wgsl` `lobe_mean_radiance`): the first frame's
    /// net, self-normalised.
    pub const SHIPPED: Variant = Variant {
        name: "shipped: net then r2, self-normalised",
        points: Points::NetThenR2,
        form: Form::SelfNormalised,
        ..Variant::BEFORE
    };
}

/// A ball pixel and what its shading forms once.
struct Px {
    i: usize,
    k: usize,
    px: u32,
    py: u32,
    n: DVec3,
    v: DVec3,
    f0: DVec3,
    roughness: f64,
    mu_o: f64,
    loss_o: f64,
    norm: f64,
    f_add: DVec3,
    fss_ess: DVec3,
    /// The split sum's single scattering: the prefiltered layers along the dominant
    /// direction times `F0 A + B`.
    split_single: DVec3,
    /// The prefiltered radiance along the dominant direction.
    dominant: DVec3,
    /// The term from the convolved layer.
    ms_convolved: DVec3,
}

/// The study's inputs for one map.
pub struct Setup<'a> {
    pub scene: &'a Scene,
    pub environment: &'a Environment,
    pub e: &'a TableSet,
    pub ibl: &'a CpuEnvironment,
    pub mc: &'a MonteCarloImage,
    pub size: (u32, u32),
}

fn pixels(s: &Setup) -> Vec<Px> {
    let (w, h) = s.size;
    let scene = s.scene;
    let basis = scene.camera.basis(w, h);
    let form = scene.preset.f_avg_form();
    let intensity = s.ibl.intensity(s.environment);
    let mut out = Vec::new();
    for py in 0..h {
        for px in 0..w {
            let d = basis.ray(px, py, w, h);
            let hit = cpu::nearest_ball(scene, basis.origin, d);
            let Some((t, k)) = hit else { continue };
            let b = &scene.balls[k];
            let i = (py * w + px) as usize;
            if s.mc.mean[i].dot(LUMINANCE) < LUMINANCE_FLOOR {
                continue;
            }
            let n = (basis.origin + t * d - b.center).normalize();
            let v = -d;
            let roughness = b.roughness;
            let f0 = b.material.f0;
            let mu_o = n.dot(v).max(0.0);
            let loss_o = f64::from(s.e.lut_loss(mu_o as f32, roughness as f32));
            let loss_avg = f64::from(s.e.lut_loss_avg(roughness as f32));
            let f_add = DVec3::from_array(std::array::from_fn(|c| {
                f_add_preset(form, f0[c], GAMES202_EDGE_TINT[c], 1.0 - loss_avg)
            }));
            let bias = f64::from(s.ibl.split.bias_at(mu_o as f32, roughness as f32));
            let fss_ess = f0 * (1.0 - loss_o) + (DVec3::ONE - f0) * bias;
            let r = 2.0 * n.dot(v) * n - v;
            let dom = prefilter::specular_direction(n, r, roughness);
            let dominant = intensity
                * s.ibl
                    .prefiltered
                    .specular(s.environment.to_map(dom), roughness);
            let n_map = s.environment.to_map(n);
            let ms_convolved =
                f_add * loss_o * intensity * s.ibl.prefiltered.multiple(n_map, roughness);
            out.push(Px {
                i,
                k,
                px,
                py,
                n,
                v,
                f0,
                roughness,
                mu_o,
                loss_o,
                norm: f_ms_norm(loss_avg),
                f_add,
                fss_ess,
                split_single: dominant * fss_ess,
                dominant,
                ms_convolved,
            });
        }
    }
    out
}

/// Point `j` of `n` of pixel `p`'s frame `frame` under `points`.
fn point(points: Points, p: &Px, frame: u32, j: u32, n: u32) -> (f64, f64) {
    match points {
        Points::Rotated => lobe::lobe_point(frame * n + j, lobe::pixel_scramble(p.px, p.py)),
        Points::Fixed => lobe::lobe_point(frame * n + j, lobe::pixel_scramble(frame, 0xffff)),
        Points::Hammersley => {
            let s = lobe::pixel_scramble(p.px ^ lobe::lobe_hash(frame), p.py);
            let unit = 1.0 / 4_294_967_296.0;
            let x = (f64::from(j) + 0.5) / f64::from(n) + f64::from(s[0]) * unit;
            let y = prefilter::radical_inverse(j) + f64::from(s[1]) * unit;
            (x.fract(), y.fract())
        }
        Points::NetThenR2 => {
            let s = lobe::pixel_scramble(p.px, p.py);
            if frame == 0 {
                lobe::lobe_net_point(j, n, s)
            } else {
                lobe::lobe_point(frame * n + j, s)
            }
        }
        Points::SobolXor => lobe::lobe_frame_point(frame * n, j, lobe::pixel_scramble(p.px, p.py)),
        Points::HammersleyXor => lobe::lobe_net_point(
            j,
            n,
            lobe::pixel_scramble(p.px ^ lobe::lobe_hash(frame), p.py),
        ),
    }
}

/// Pixel `p`'s outgoing radiance (the metal under the map alone) at frame `frame` of
/// `variant` with `n` samples.
fn estimate(
    s: &Setup,
    p: &Px,
    variant: &Variant,
    (frame, lod_count): (u32, u32),
    n: u32,
    geometry: Geometry,
) -> DVec3 {
    let alpha = alpha_from_roughness(p.roughness);
    let basis = Frame::new(p.n);
    let v_local = basis.to_local(p.v);
    let level0 = &s.ibl.chain.levels[0];
    let size = (f64::from(level0.width), f64::from(level0.height));
    let max_level = (s.ibl.chain.levels.len() - 1) as f64;
    let intensity = s.ibl.intensity(s.environment);
    let (mut sum_wl, mut sum_w, mut sum_wp, mut sum_ms) =
        (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
    for j in 0..n {
        let (u1, u2) = point(variant.points, p, frame, j, n);
        let l = basis.to_world(sample_vndf(v_local, alpha, u1, u2));
        let mu_i = p.n.dot(l);
        if mu_i <= 0.0 || p.mu_o <= 0.0 {
            continue;
        }
        let h = (p.v + l).normalize();
        let n_dot_h = p.n.dot(h);
        let pdf = vndf_density(p.mu_o, n_dot_h, alpha);
        if pdf <= shadeballs::brdf::DIV_EPSILON {
            continue;
        }
        let v_dot_h = p.v.dot(h);
        let f = DVec3::from_array(std::array::from_fn(|c| {
            let fresnel = f_schlick(p.f0[c], v_dot_h);
            f_micro(fresnel, p.mu_o, mu_i, n_dot_h, p.roughness, geometry)
        }));
        let w = f * (mu_i / pdf);
        let l_map = s.environment.to_map(l);
        let lod = (lobe::lobe_lod(pdf, f64::from(lod_count), l_map, size, max_level)
            + variant.lod_bias)
            .clamp(0.0, max_level);
        let mut radiance = intensity * s.ibl.chain.sample(l_map, lod);
        if let Some(c) = variant.clamp {
            radiance = radiance.min(c * p.dominant);
        }
        sum_wl += w * radiance;
        sum_w += w;
        if variant.form == Form::ControlVariate {
            sum_wp += w * intensity * s.ibl.prefiltered.specular(l_map, p.roughness);
        }
        if variant.ms_from_samples {
            let loss_i = f64::from(s.e.lut_loss(mu_i as f32, p.roughness as f32));
            sum_ms += p.f_add * f_ms(p.loss_o, loss_i, p.norm) * (mu_i / pdf) * radiance;
        }
    }
    let count = f64::from(n);
    let single = match variant.form {
        Form::Plain => sum_wl / count,
        Form::SelfNormalised => {
            let ratio = DVec3::from_array(std::array::from_fn(|c| {
                if sum_w[c] > 0.0 {
                    sum_wl[c] / sum_w[c]
                } else {
                    p.dominant[c]
                }
            }));
            ratio * p.fss_ess
        }
        Form::ControlVariate => p.split_single + (sum_wl - sum_wp) / count,
    };
    let multiple = if variant.ms_from_samples {
        sum_ms / count
    } else {
        p.ms_convolved
    };
    single + multiple
}

/// Per-ball mean relative luminance error of `image` (one value per pixel of `px`) against
/// `reference`, binned: index 0 the whole ball, then n.v in [0, 0.25), [0.25, 0.5), [0.5, 1].
type Errors = Vec<[(f64, usize); 4]>;

fn errors(px: &[Px], balls: usize, image: &[DVec3], reference: &[DVec3]) -> Errors {
    let mut per = vec![[(0.0, 0usize); 4]; balls];
    for (p, (a, r)) in px.iter().zip(image.iter().zip(reference)) {
        let y = r.dot(LUMINANCE);
        let e = (a.dot(LUMINANCE) - y).abs() / y;
        let bin = if p.mu_o < 0.25 {
            1
        } else if p.mu_o < 0.5 {
            2
        } else {
            3
        };
        for b in [0, bin] {
            per[p.k][b].0 += e;
            per[p.k][b].1 += 1;
        }
    }
    per
}

fn mean(e: (f64, usize)) -> f64 {
    if e.1 == 0 {
        0.0
    } else {
        e.0 / e.1 as f64
    }
}

/// One variant's figures: the one-frame error, the bias and the noise, each the worst ball's,
/// and for the ball of the worst one-frame error its bias and noise by n.v.
pub struct Figures {
    pub frame: f64,
    pub bias: f64,
    pub noise: f64,
    pub worst_ball: usize,
    pub by_mu: [(f64, f64); 3],
}

/// Runs `variant` at `n` samples over `frames` frames.
pub fn measure(s: &Setup, variant: &Variant, n: u32, frames: u32) -> Figures {
    let px = pixels(s);
    let geometry = s.scene.effective_geometry();
    let images: Vec<Vec<DVec3>> = px
        .par_iter()
        .map(|p| {
            (0..frames)
                .map(|k| estimate(s, p, variant, (k, n), n, geometry))
                .collect()
        })
        .collect();
    let balls = s.scene.balls.len();
    let reference: Vec<DVec3> = px.iter().map(|p| s.mc.mean[p.i]).collect();
    let mean_image: Vec<DVec3> = images
        .iter()
        .map(|f| f.iter().sum::<DVec3>() / f64::from(frames))
        .collect();
    let bias = errors(&px, balls, &mean_image, &reference);
    let mut frame_err: Errors = vec![[(0.0, 0); 4]; balls];
    let mut noise_err: Errors = vec![[(0.0, 0); 4]; balls];
    for k in 0..frames as usize {
        let image: Vec<DVec3> = images.iter().map(|f| f[k]).collect();
        // The noise: the frame against the mean image, relative to the reference.
        let shifted: Vec<DVec3> = image
            .iter()
            .zip(&mean_image)
            .zip(&reference)
            .map(|((a, m), r)| *a - *m + *r)
            .collect();
        for (acc, e) in [
            (&mut frame_err, errors(&px, balls, &image, &reference)),
            (&mut noise_err, errors(&px, balls, &shifted, &reference)),
        ] {
            for (a, b) in acc.iter_mut().zip(e) {
                for c in 0..4 {
                    a[c].0 += b[c].0;
                    a[c].1 += b[c].1;
                }
            }
        }
    }
    let eligible: Vec<usize> = (0..balls)
        .filter(|&k| s.scene.balls[k].roughness >= 0.3 && bias[k][0].1 > 0)
        .collect();
    let worst = |e: &Errors| eligible.iter().map(|&k| mean(e[k][0])).fold(0.0, f64::max);
    let worst_ball = eligible
        .iter()
        .copied()
        .max_by(|&a, &b| mean(frame_err[a][0]).total_cmp(&mean(frame_err[b][0])))
        .unwrap_or(0);
    Figures {
        frame: worst(&frame_err),
        bias: worst(&bias),
        noise: worst(&noise_err),
        worst_ball,
        by_mu: std::array::from_fn(|b| {
            (
                mean(bias[worst_ball][b + 1]),
                mean(noise_err[worst_ball][b + 1]),
            )
        }),
    }
}

/// The progressive image's error: the mean of frames `0..frames` of `variant`, frame `k`'s
/// levels read for `(k + 1) n` samples (as `render --ibl-frames`).
pub fn progressive(s: &Setup, variant: &Variant, n: u32, frames: u32) -> f64 {
    let px = pixels(s);
    let geometry = s.scene.effective_geometry();
    let image: Vec<DVec3> = px
        .par_iter()
        .map(|p| {
            (0..frames)
                .map(|k| estimate(s, p, variant, (k, (k + 1) * n), n, geometry))
                .sum::<DVec3>()
                / f64::from(frames)
        })
        .collect();
    let reference: Vec<DVec3> = px.iter().map(|p| s.mc.mean[p.i]).collect();
    let e = errors(&px, s.scene.balls.len(), &image, &reference);
    (0..s.scene.balls.len())
        .filter(|&k| s.scene.balls[k].roughness >= 0.3 && e[k][0].1 > 0)
        .map(|k| mean(e[k][0]))
        .fold(0.0, f64::max)
}

/// The split sum's error under the same measure (no noise: one image).
pub fn split_sum_error(s: &Setup) -> f64 {
    let px = pixels(s);
    let image: Vec<DVec3> = px.iter().map(|p| p.split_single + p.ms_convolved).collect();
    let reference: Vec<DVec3> = px.iter().map(|p| s.mc.mean[p.i]).collect();
    let e = errors(&px, s.scene.balls.len(), &image, &reference);
    (0..s.scene.balls.len())
        .filter(|&k| s.scene.balls[k].roughness >= 0.3 && e[k][0].1 > 0)
        .map(|k| mean(e[k][0]))
        .fold(0.0, f64::max)
}

/// The candidates the study measures, each with its sample count: each one change from
/// [`Variant::BEFORE`], then combinations. The shipped estimator's first frame is the
/// net's, self-normalised: independent draws of it are the "first frame as shipped" row's
/// (the net shifted by a hash of the pixel and the frame); its later frames are R2's
/// (the progressive figures).
pub fn candidates() -> Vec<(Variant, u32)> {
    let b = Variant::BEFORE;
    let net = Variant {
        points: Points::HammersleyXor,
        form: Form::SelfNormalised,
        ..b
    };
    let one = |name, v: Variant| Variant { name, ..v };
    let variants = [
        b,
        one(
            "lod bias -1",
            Variant {
                lod_bias: -1.0,
                ..b
            },
        ),
        one("lod bias 0.5", Variant { lod_bias: 0.5, ..b }),
        one("lod bias 1", Variant { lod_bias: 1.0, ..b }),
        one(
            "fixed per frame",
            Variant {
                points: Points::Fixed,
                ..b
            },
        ),
        one(
            "hammersley",
            Variant {
                points: Points::Hammersley,
                ..b
            },
        ),
        one(
            "hammersley xor",
            Variant {
                points: Points::HammersleyXor,
                ..b
            },
        ),
        one(
            "sobol xor",
            Variant {
                points: Points::SobolXor,
                ..b
            },
        ),
        one(
            "self-normalised",
            Variant {
                form: Form::SelfNormalised,
                ..b
            },
        ),
        one(
            "control variate",
            Variant {
                form: Form::ControlVariate,
                ..b
            },
        ),
        one(
            "clamp 4",
            Variant {
                clamp: Some(4.0),
                ..b
            },
        ),
        one(
            "clamp 16",
            Variant {
                clamp: Some(16.0),
                ..b
            },
        ),
        one(
            "ms from samples",
            Variant {
                ms_from_samples: true,
                ..b
            },
        ),
        one(
            "first frame as shipped: hammersley xor, self-normalised",
            net,
        ),
        one(
            "sobol xor, self-normalised",
            Variant {
                points: Points::SobolXor,
                ..net
            },
        ),
        one(
            "combined, lod bias -0.5",
            Variant {
                lod_bias: -0.5,
                ..net
            },
        ),
        one(
            "combined, lod bias 0.25",
            Variant {
                lod_bias: 0.25,
                ..net
            },
        ),
        one(
            "combined, clamp 16",
            Variant {
                clamp: Some(16.0),
                ..net
            },
        ),
    ];
    [16, 32, 64]
        .into_iter()
        .flat_map(|n| variants.iter().map(move |v| (*v, n)))
        .collect()
}

/// The candidates the progressive figures compare.
pub fn progressive_candidates() -> Vec<Variant> {
    let b = Variant::BEFORE;
    vec![
        b,
        Variant::SHIPPED,
        Variant {
            name: "self-normalised",
            form: Form::SelfNormalised,
            ..b
        },
        Variant {
            name: "hammersley xor, self-normalised",
            points: Points::HammersleyXor,
            form: Form::SelfNormalised,
            ..b
        },
        Variant {
            name: "sobol xor, self-normalised",
            points: Points::SobolXor,
            form: Form::SelfNormalised,
            ..b
        },
    ]
}
