//! The Monte Carlo reference (`render --backend montecarlo`): the chosen model
//! ([`crate::environment::IblTerm`]) integrated against the directional lights and the
//! environment without any real-time approximation: no split sum, no harmonics, no
//! prefiltering (docs/design/environment.md, "The Monte Carlo backend").
//!
//! The camera, the primary rays (one per pixel, through its centre) and the sphere hits are
//! those of [`super::render_radiance`], and E and E_avg come from the same
//! [`TableSet`], so an image compares pixel for pixel with the real-time renderers' and
//! only the integration over incident directions differs. Lights are evaluated directly
//! (`f_r L mu_i`); the environment is integrated by importance sampling with three
//! strategies (GGX visible normals, cosine-weighted hemisphere, the map's luminance; at a
//! clear-coated point the coat's visible normals a fourth) combined by the multi-sample
//! balance heuristic (Veach & Guibas 1995, "Optimally
//! Combining Sampling Techniques for Monte Carlo Rendering").

use std::f64::consts::PI;

use glam::DVec3;
use rayon::prelude::*;

use super::{surface_normal, Bins, PixelView};
use crate::brdf::{alpha_from_roughness, DIV_EPSILON};
use crate::environment::sampler::EnvSampler;
use crate::error::Result;
use crate::lut::{SplitSum, TableSet};
use crate::prepared::Prepared;
use crate::sampling::{arriving, sample_cosine, sample_vndf, Frame};
use crate::scene::{bounds_pad_px, Model, Scene, MAX_BALLS};
use crate::walk::Rng;

pub use crate::stats::MAX_SPP;

pub use crate::environment::sampler::LUMINANCE;
pub use crate::stats::MonteCarloImage;
pub use crate::stats::Part;

use super::model::{coated_point, pdf_vndf, pdf_vndf_lobe, sample_lobe};
pub(crate) use super::model::{model_brdf, ShadingPoint};

/// Renders `scene` at `width x height` with `spp` estimates per covered pixel, drawing its
/// random numbers from `seed`. Rows run on rayon's pool; each pixel seeds its own generator
/// from `(seed, px, py)`, so the image does not depend on the number of threads.
///
/// Errors when `spp` is outside `1..=MAX_SPP` or the scene's environment map has a
/// rotation or intensity that is not finite (or a negative intensity).
pub fn render_montecarlo(
    scene: &Scene,
    prepared: &Prepared,
    width: u32,
    height: u32,
    spp: u32,
    seed: u64,
) -> Result<MonteCarloImage> {
    render_montecarlo_part(scene, prepared, width, height, spp, seed, Part::Whole)
}

/// [`render_montecarlo`] of one [`Part`] of the model: `Part::Multiple` integrates only
/// the lobe the term adds, the reference for a real-time method's term alone.
pub fn render_montecarlo_part(
    scene: &Scene,
    prepared: &Prepared,
    width: u32,
    height: u32,
    spp: u32,
    seed: u64,
    part: Part,
) -> Result<MonteCarloImage> {
    let e = prepared.tables();
    crate::stats::check_montecarlo_inputs(scene, spp)?;
    let basis = scene.camera.basis(width, height);
    let balls = &scene.balls[..scene.balls.len().min(MAX_BALLS)];
    // The pixels see what the real-time renderers' pixels see: with antialiasing, a
    // silhouette pixel's estimate along its covered part's ray, mixed with the background
    // by the coverage (docs/design/antialiasing.md, "Monte Carlo").
    let size = (width, height);
    let bins = Bins::new(&basis, balls, width, height, bounds_pad_px(scene.antialias));
    let lighting = Lighting::new(scene);
    let (bins, lighting) = (&bins, &lighting);
    // Fdez-Aguera's FssEss is F0 A + B where the scene has a map: the split sum's table, as
    // the real-time renderers read it (they bind it with the map).
    let split = (scene.environment_map.is_some()
        && scene.balls.iter().any(|b| b.model == Model::FdezAguera))
    .then(|| SplitSum::shipped(scene.effective_geometry()));
    let split = &split;
    let pixels: Vec<(DVec3, DVec3, bool)> = (0..height)
        .into_par_iter()
        .flat_map_iter(|py| {
            (0..width).map(move |px| {
                let o = basis.origin;
                let view = match bins.view(&basis, balls, size, scene.antialias, (px, py)) {
                    PixelView::Miss(d) => return (lighting.background(d), DVec3::ZERO, false),
                    PixelView::Ball(view) => view,
                };
                let (d, t) = (view.hit, view.footprint.t);
                let b = &balls[view.k];
                let n = surface_normal(o + t * d - b.center, d);
                let mut point =
                    ShadingPoint::with_coat(scene, (b, prepared.coat(view.k)), (n, -d), e);
                point.part = part;
                // A clear coat: its lobe and its shares of the base's light in the BRDF.
                let coat = prepared
                    .clearcoat(view.k)
                    .map(|c| super::clearcoat::ClearcoatPoint::new(scene, b, c, (n, -d), e));
                point = coated_point(point, coat);
                if let Some(split) = split {
                    point = point.with_split_sum(split);
                }
                let mut rng = Rng::new(&[seed, u64::from(px), u64::from(py)]);
                let (mut mean, err) = lighting.estimate(&point, e, spp, &mut rng);
                // The ball's emission, exact (no part of the BRDF: the term's lobe alone
                // has none).
                if part == Part::Whole {
                    mean += b.material.emission;
                }
                // The background is exact: only the ball's share is noisy.
                let mean = view.mix(mean, || lighting.background(view.miss));
                (mean, err * view.footprint.coverage, true)
            })
        })
        .collect();
    let mut image = MonteCarloImage {
        width,
        height,
        spp,
        mean: Vec::with_capacity(pixels.len()),
        std_error: Vec::with_capacity(pixels.len()),
        covered: Vec::with_capacity(pixels.len()),
        antialias: scene.antialias,
    };
    for (m, s, c) in pixels {
        image.mean.push(m);
        image.std_error.push(s);
        image.covered.push(c);
    }
    Ok(image)
}

/// What lights the balls: the directional lights, the uniform environment, the map and
/// its sampler.
pub(super) struct Lighting<'a> {
    scene: &'a Scene,
    /// Whether any environment radiance can be non-zero (else the integral is skipped).
    lit: bool,
    sampler: Option<EnvSampler<'a>>,
}

impl<'a> Lighting<'a> {
    pub(super) fn new(scene: &'a Scene) -> Self {
        let map_lit = scene
            .environment_map
            .as_ref()
            .is_some_and(|m| m.intensity > 0.0 && m.map.texels().iter().any(|t| t != &[0.0; 3]));
        Lighting {
            scene,
            lit: map_lit || scene.environment != DVec3::ZERO,
            sampler: scene.environment_map.as_ref().and_then(EnvSampler::new),
        }
    }

    /// Radiance arriving from world direction `w`: the uniform environment plus the map.
    fn incident(&self, w: DVec3) -> DVec3 {
        let map = self.scene.environment_map.as_ref();
        arriving(w, self.scene.environment, map.map(|m| |d| m.radiance(d)))
    }

    pub(super) fn background(&self, d: DVec3) -> DVec3 {
        self.scene.background_along(d)
    }

    /// The lights' exact contribution plus `spp` estimates of the environment's; returns
    /// the mean and its standard error.
    pub(super) fn estimate(
        &self,
        p: &ShadingPoint,
        e: &TableSet,
        spp: u32,
        rng: &mut Rng,
    ) -> (DVec3, DVec3) {
        let mut direct = DVec3::ZERO;
        for light in &self.scene.lights {
            let mu_i = p.n.dot(light.direction);
            if mu_i <= 0.0 || p.mu_o <= 0.0 {
                continue;
            }
            direct += model_brdf(p, light.direction, e) * light.radiance * mu_i;
        }
        if !self.lit || p.mu_o <= 0.0 {
            return (direct, DVec3::ZERO);
        }
        // The lobe's visible normals (an anisotropic lobe's own, in its tangent frame:
        // sample_lobe); the other strategies in any frame about n.
        let alpha = alpha_from_roughness(p.lobe.roughness);
        let frame = Frame::new(p.n);
        let v_local = frame.to_local(p.v);
        // A clear coat's own lobe, a fourth strategy at a coated point: its visible normals
        // (isotropic: any frame about n).
        let coat_alpha = p.clearcoat.as_ref().map(|c| c.alpha());
        // Welford's running mean and sum of squared deviations, per channel.
        let mut mean = DVec3::ZERO;
        let mut m2 = DVec3::ZERO;
        for k in 0..spp {
            let mut x = DVec3::ZERO;
            let u = (rng.uniform(), rng.uniform());
            x += self.contribution(p, e, sample_lobe(p, &frame, v_local, alpha, u), alpha);
            let l = frame.to_world(sample_cosine(rng.uniform(), rng.uniform()));
            x += self.contribution(p, e, l, alpha);
            if let Some(s) = &self.sampler {
                let u = [rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform()];
                if let Some(l) = s.sample(u) {
                    x += self.contribution(p, e, l, alpha);
                }
            }
            if let Some(a) = coat_alpha {
                let (u1, u2) = (rng.uniform(), rng.uniform());
                let l = frame.to_world(sample_vndf(v_local, a, u1, u2));
                x += self.contribution(p, e, l, alpha);
            }
            let delta = x - mean;
            mean += delta / (k + 1) as f64;
            m2 += delta * (x - mean);
        }
        let err = if spp >= 2 {
            let n = spp as f64;
            (m2 / ((n - 1.0) * n)).max(DVec3::ZERO).powf(0.5)
        } else {
            DVec3::ZERO
        };
        (direct + mean, err)
    }

    /// One sample's share of the multi-sample balance-heuristic estimator:
    /// `f_r L mu_i / sum_k pdf_k(l)` (each strategy draws one direction per estimate, so
    /// the weight `pdf_s / sum_k pdf_k` over `pdf_s` leaves the sum).
    fn contribution(&self, p: &ShadingPoint, e: &TableSet, l: DVec3, alpha: f64) -> DVec3 {
        let mu_i = p.n.dot(l);
        if mu_i <= 0.0 {
            return DVec3::ZERO;
        }
        let pdf = self.pdf(p, l, mu_i, alpha);
        if pdf <= DIV_EPSILON {
            return DVec3::ZERO;
        }
        let f = model_brdf(p, l, e);
        if f == DVec3::ZERO {
            return DVec3::ZERO;
        }
        f * self.incident(l) * (mu_i / pdf)
    }

    /// The sum of the strategies' densities (per unit solid angle) at `l`, `mu_i > 0`: the
    /// lobe's visible normals, the cosine, the map's texels, and a coat's visible normals.
    fn pdf(&self, p: &ShadingPoint, l: DVec3, mu_i: f64, alpha: f64) -> f64 {
        let mut pdf = pdf_vndf_lobe(p, l, alpha) + mu_i / PI;
        if let Some(s) = &self.sampler {
            pdf += s.pdf(l);
        }
        if let Some(c) = &p.clearcoat {
            pdf += pdf_vndf(p, l, c.alpha());
        }
        pdf
    }
}
