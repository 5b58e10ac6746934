//! The Monte Carlo reference (`render --backend montecarlo`): the chosen model
//! ([`IblTerm`]) integrated against the directional lights and the environment without any
//! real-time approximation: no split sum, no harmonics, no prefiltering
//! (docs/design/environment.md, "The Monte Carlo backend").
//!
//! The camera, the primary rays (one per pixel, through its centre) and the sphere hits are
//! those of [`super::render_radiance`], and E and E_avg come from the same
//! [`TableSet`], so an image compares pixel for pixel with the real-time renderers' and
//! only the integration over incident directions differs. Lights are evaluated directly
//! (`f_r L mu_i`); the environment is integrated by importance sampling with three
//! strategies (GGX visible normals, cosine-weighted hemisphere, the map's luminance)
//! combined by the multi-sample balance heuristic (Veach & Guibas 1995, "Optimally
//! Combining Sampling Techniques for Monte Carlo Rendering").

use std::f64::consts::PI;

use glam::DVec3;
use rayon::prelude::*;

use super::coating::CoatingPoint;
use super::light::{f_add_rgb, loss, loss_avg, per_channel};
use super::{surface_normal, Bins, PixelView};
use crate::brdf::{
    alpha_from_roughness, f_avg_schlick, f_micro, f_ms, f_ms_norm, f_schlick, Geometry, DIV_EPSILON,
};
use crate::environment::sampler::EnvSampler;
use crate::environment::IblTerm;
use crate::error::Result;
use crate::lut::{CoatingRows, SplitSum, TableSet};
use crate::prepared::{Coat, Prepared};
use crate::sampling::{
    arriving, sample_cosine, sample_vndf_aniso, vndf_density, vndf_density_aniso, Frame,
};
use crate::scene::{bounds_pad_px, Ball, Model, Scene, MAX_BALLS};
use crate::walk::Rng;

pub use crate::stats::MAX_SPP;

pub use crate::environment::sampler::LUMINANCE;
pub use crate::stats::{MonteCarloImage, Part};

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
                if let Some(split) = split {
                    point = point.with_split_sum(split);
                }
                let mut rng = Rng::new(&[seed, u64::from(px), u64::from(py)]);
                let (mean, err) = lighting.estimate(&point, e, spp, &mut rng);
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

/// One visible surface point: the ball's model and what does not depend on the incident
/// direction (E(mu_o), E_avg, f_add, the diffuse weight), formed once per pixel.
#[derive(Clone, Copy, Debug)]
pub struct ShadingPoint {
    /// Unit surface normal.
    pub n: DVec3,
    /// Unit direction towards the eye.
    pub v: DVec3,
    /// `max(n.v, 0)`.
    pub mu_o: f64,
    /// The ball's roughness (the model clamps it).
    pub roughness: f64,
    /// `F0` per channel.
    pub f0: DVec3,
    /// 1 when the ball has the multiple-scattering term, else 0.
    pub ms: f64,
    /// `1 - E(mu_o)`.
    pub loss_o: f64,
    /// The Kulla-Conty normalisation `f_ms_norm(1 - E_avg)`.
    pub norm: f64,
    /// The preset's Fresnel scale of the Kulla-Conty lobe, per channel.
    pub f_add: DVec3,
    /// The metal's share (the metal's and the coating's BRDFs are mixed by it).
    pub metallic: f64,
    /// The dielectric coating's part (`None` for an all-metal ball).
    pub coating: Option<CoatingPoint>,
    /// Which multiple-scattering model.
    pub term: IblTerm,
    /// The scene's effective G.
    pub geometry: Geometry,
    /// Fdez-Aguera's `FssEss`, the single-scattering albedo per channel: `F_avg E(mu_o)`
    /// unless [`ShadingPoint::with_split_sum`] gives it exactly.
    pub fss_ess: DVec3,
    /// Which part of the BRDF [`model_brdf`] returns.
    pub part: Part,
    /// An anisotropic metal lobe's tangent frame and `(alpha_t, alpha_b)`
    /// (docs/design/anisotropy.md); `roughness` is then its isotropic equivalent.
    pub anisotropy: Option<(Frame, (f64, f64))>,
}

impl ShadingPoint {
    /// Ball `b` seen at unit normal `n` from unit direction `v`, under `scene`'s preset
    /// and geometry and the ball's model, with E and E_avg from `e` (its coating formed
    /// for the call: [`ShadingPoint::with_coat`] takes one formed once per ball).
    pub fn new(scene: &Scene, b: &Ball, n: DVec3, v: DVec3, e: &TableSet) -> Self {
        let rows = CoatingRows::bake(scene.ball_coating_keys(b), &mut Default::default());
        let coat = Coat::of_ball(scene, b, e, &rows);
        Self::with_coat(scene, (b, coat.as_ref()), (n, v), e)
    }

    /// [`ShadingPoint::new`] with the ball's coating `coat` (`None` for an all-metal ball).
    pub fn with_coat(
        scene: &Scene,
        (b, coat): (&Ball, Option<&Coat>),
        (n, v): (DVec3, DVec3),
        e: &TableSet,
    ) -> Self {
        let roughness = b.shading_roughness();
        let f0 = b.material.f0;
        let mu_o = n.dot(v).max(0.0);
        let loss_avg = loss_avg(e, roughness);
        let e_avg = 1.0 - loss_avg;
        let form = scene.preset.f_avg_form();
        ShadingPoint {
            n,
            v,
            mu_o,
            roughness,
            f0,
            ms: if b.model.has_term() { 1.0 } else { 0.0 },
            loss_o: loss(e, mu_o, roughness),
            norm: f_ms_norm(loss_avg),
            f_add: f_add_rgb(form, f0, e_avg),
            metallic: b.material.metallic,
            coating: coat.map(|coat| CoatingPoint::new(scene, b, coat, (n, v), e)),
            term: b.model.term().unwrap_or(IblTerm::KullaConty),
            geometry: scene.effective_geometry(),
            fss_ess: per_channel(f0, f_avg_schlick) * (1.0 - loss(e, mu_o, roughness)),
            part: Part::Whole,
            anisotropy: super::shade::anisotropic_frame(b, n),
        }
    }

    /// The point with `FssEss = F0 A + B` from the split sum's table (`A = E - B` with E
    /// from the tables, as `split_sum_scale` in `environment.wgsl`).
    pub fn with_split_sum(mut self, split: &SplitSum) -> Self {
        let bias = split.bias_at(self.mu_o as f32, self.roughness as f32) as f64;
        let e_o = 1.0 - self.loss_o;
        self.fss_ess = self.f0 * e_o + (DVec3::ONE - self.f0) * bias;
        self
    }
}

/// The BRDF `f_r(v, l)` of the point's model, per channel (0 when `l` or `v` is below the
/// horizon): the metal's and the coating's (`CoatingPoint::brdf`, the lights' loop of
/// `shade_coating`) mixed by `metallic`. The metal's is the single-scattering Cook-Torrance
/// lobe `f_micro` with Schlick's F per channel and a multiple-scattering lobe on balls with
/// the term:
///
/// - [`IblTerm::KullaConty`] (Kulla & Conty 2017, "Revisiting Physically Based Shading at
///   Imageworks"): `f_add f_ms(1 - E(mu_o), 1 - E(mu_i))`, term for term the
///   directional-light branch of [`super::shade`].
/// - [`IblTerm::Turquin`] (Turquin 2019, "Practical multiple scattering compensation for
///   microfacet models"): the single-scattering lobe scaled by `1 + F0 (1 / E(mu_o) - 1)`,
///   `E` guarded by [`DIV_EPSILON`].
/// - [`IblTerm::FdezAguera`] (Fdez-Aguera 2019, "A Multiple-Scattering Microfacet Model for
///   Real-Time Image-based Lighting"): a Lambertian lobe of albedo
///   `FmsEms = FssEss F_avg Ems / (1 - F_avg Ems)`, `Ems = 1 - E(mu_o)`,
///   `F_avg = F0 + (1 - F0) / 21`, `FssEss = F0 A + B` from the split sum's table
///   ([`ShadingPoint::with_split_sum`], which [`render_montecarlo`] applies; without it
///   `F_avg E(mu_o)`).
pub fn model_brdf(p: &ShadingPoint, l: DVec3, e: &TableSet) -> DVec3 {
    let mu_i = p.n.dot(l);
    if mu_i <= 0.0 || p.mu_o <= 0.0 {
        return DVec3::ZERO;
    }
    let sum = p.v + l;
    let len = sum.length();
    if len <= DIV_EPSILON {
        return DVec3::ZERO;
    }
    let coating = p.coating.map(|c| {
        let f = c.brdf((p.v, l), p.n, e);
        match p.part {
            Part::Whole => DVec3::splat(f.spec + f.multiple) + f.base,
            Part::Multiple => DVec3::splat(f.multiple),
        }
    });
    match coating {
        Some(c) if p.metallic <= 0.0 => c,
        Some(c) => p.metallic * metal_brdf(p, l, sum / len, e) + (1.0 - p.metallic) * c,
        None => metal_brdf(p, l, sum / len, e),
    }
}

/// The metal's part of [`model_brdf`], `h` the half vector.
fn metal_brdf(p: &ShadingPoint, l: DVec3, h: DVec3, e: &TableSet) -> DVec3 {
    let mu_i = p.n.dot(l);
    let v_dot_h = p.v.dot(h);
    let n_dot_h = p.n.dot(h);
    let spec = per_channel(p.f0, |f| {
        let fresnel = f_schlick(f, v_dot_h);
        match &p.anisotropy {
            Some((frame, alphas)) => crate::brdf::f_micro_aniso(
                fresnel,
                frame.to_local(p.v),
                frame.to_local(l),
                frame.to_local(h),
                *alphas,
                p.geometry,
            ),
            None => f_micro(fresnel, p.mu_o, mu_i, n_dot_h, p.roughness, p.geometry),
        }
    });
    let multiple = match p.term {
        IblTerm::KullaConty => {
            let loss_i = loss(e, mu_i, p.roughness);
            p.ms * p.f_add * f_ms(p.loss_o, loss_i, p.norm)
        }
        IblTerm::Turquin => {
            let e_o = (1.0 - p.loss_o).max(DIV_EPSILON);
            spec * p.ms * p.f0 * (p.loss_o / e_o)
        }
        IblTerm::FdezAguera => {
            let f_avg = per_channel(p.f0, f_avg_schlick);
            let denom = (DVec3::ONE - f_avg * p.loss_o).max(DVec3::splat(DIV_EPSILON));
            let fms_ems = p.fss_ess * f_avg * p.loss_o / denom;
            p.ms * fms_ems / PI
        }
    };
    match p.part {
        Part::Whole => spec + multiple,
        Part::Multiple => multiple,
    }
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
        // An anisotropic lobe draws its own visible normals in its tangent frame.
        let (frame, alphas) = p.anisotropy.unwrap_or_else(|| {
            let alpha = alpha_from_roughness(p.roughness);
            (Frame::new(p.n), (alpha, alpha))
        });
        let v_local = frame.to_local(p.v);
        // Welford's running mean and sum of squared deviations, per channel.
        let mut mean = DVec3::ZERO;
        let mut m2 = DVec3::ZERO;
        for k in 0..spp {
            let mut x = DVec3::ZERO;
            let (u1, u2) = (rng.uniform(), rng.uniform());
            let l = frame.to_world(sample_vndf_aniso(v_local, alphas, u1, u2));
            x += self.contribution(p, e, l, alphas);
            let l = frame.to_world(sample_cosine(rng.uniform(), rng.uniform()));
            x += self.contribution(p, e, l, alphas);
            if let Some(s) = &self.sampler {
                let u = [rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform()];
                if let Some(l) = s.sample(u) {
                    x += self.contribution(p, e, l, alphas);
                }
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
    fn contribution(&self, p: &ShadingPoint, e: &TableSet, l: DVec3, alphas: (f64, f64)) -> DVec3 {
        let mu_i = p.n.dot(l);
        if mu_i <= 0.0 {
            return DVec3::ZERO;
        }
        let pdf = self.pdf(p, l, mu_i, alphas);
        if pdf <= DIV_EPSILON {
            return DVec3::ZERO;
        }
        let f = model_brdf(p, l, e);
        if f == DVec3::ZERO {
            return DVec3::ZERO;
        }
        f * self.incident(l) * (mu_i / pdf)
    }

    /// The sum of the strategies' densities (per unit solid angle) at `l`, `mu_i > 0`.
    fn pdf(&self, p: &ShadingPoint, l: DVec3, mu_i: f64, alphas: (f64, f64)) -> f64 {
        let mut pdf = pdf_vndf_lobe(p, l, alphas) + mu_i / PI;
        if let Some(s) = &self.sampler {
            pdf += s.pdf(l);
        }
        pdf
    }
}

/// Density (solid angle) of [`sample_vndf`] at `l`: [`vndf_density`] at `l`'s half vector.
pub(super) fn pdf_vndf(p: &ShadingPoint, l: DVec3, alpha: f64) -> f64 {
    let sum = p.v + l;
    let len = sum.length();
    if len <= DIV_EPSILON {
        return 0.0;
    }
    vndf_density(p.mu_o, p.n.dot(sum / len), alpha)
}

/// Density (solid angle) of [`sample_vndf_aniso`] at `l`: [`vndf_density_aniso`] at `l`'s
/// half vector (in the lobe's tangent frame where it is anisotropic; an isotropic lobe's
/// is [`vndf_density`] of its alpha, the same density).
fn pdf_vndf_lobe(p: &ShadingPoint, l: DVec3, alphas: (f64, f64)) -> f64 {
    let sum = p.v + l;
    let len = sum.length();
    if len <= DIV_EPSILON {
        return 0.0;
    }
    let h = sum / len;
    match &p.anisotropy {
        Some((frame, _)) => vndf_density_aniso(frame.to_local(p.v), frame.to_local(h), alphas),
        None => vndf_density(p.mu_o, p.n.dot(h), alphas.0),
    }
}
