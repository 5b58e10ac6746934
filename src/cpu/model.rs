//! The model's BRDF at one visible point, for the estimators that sample it (the Monte
//! Carlo backend and the lobe mode's multiple importance sampling): the CPU twin of
//! `shaders/model.wgsl`. The point ([`ShadingPoint`]) holds what does not depend on the
//! incident direction; [`model_brdf`] evaluates the BRDF and [`pdf_vndf`] the visible
//! normals' density.

use std::f64::consts::PI;

use glam::DVec3;

use super::clearcoat::{
    clearcoat_base_fresnel_cosine, clearcoat_refraction, BaseLobe, ClearcoatPoint,
};
use super::coating::CoatingPoint;
use super::light::{f_add_rgb, loss, loss_avg, per_channel};
use crate::brdf::{
    ball_tangent, f_avg_schlick, f_micro, f_ms, f_ms_norm, f_schlick, Geometry, DIV_EPSILON,
};
use crate::environment::IblTerm;
use crate::lut::{CoatingRows, SplitSum, TableSet};
use crate::prepared::Coat;
use crate::sampling::{sample_vndf, sample_vndf_aniso, vndf_density, vndf_density_aniso, Frame};
use crate::scene::{Ball, Scene};
use crate::stats::Part;

/// One visible surface point: the ball's model and what does not depend on the incident
/// direction (E(mu_o), E_avg, f_add, the diffuse weight), formed once per pixel.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShadingPoint {
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
    /// The ball's clear coat at the point, where [`model_brdf`] takes it (the Monte Carlo
    /// backend's and the lobe mode's; `None` without a coat: [`coated_point`] sets it).
    pub clearcoat: Option<ClearcoatPoint>,
    /// The single-scattering lobes as [`model_brdf`] reads them: the ball's own, widened
    /// under a clear coat ([`coated_point`]).
    pub lobe: BaseLobe,
    /// The ball's clear coat as the metal's Fresnel sees it
    /// ([`super::clearcoat::clearcoat_refraction`]).
    pub refraction: Option<(f64, f64)>,
}

impl ShadingPoint {
    /// Ball `b` seen at unit normal `n` from unit direction `v`, under `scene`'s preset
    /// and geometry and the ball's model, with E and E_avg from `e` (its coating formed
    /// for the call: [`ShadingPoint::with_coat`] takes one formed once per ball).
    pub(crate) fn new(scene: &Scene, b: &Ball, n: DVec3, v: DVec3, e: &TableSet) -> Self {
        let rows = CoatingRows::bake(scene.ball_coating_keys(b), &mut Default::default());
        let coat = Coat::of_ball(scene, b, e, &rows);
        Self::with_coat(scene, (b, coat.as_ref()), (n, v), e)
    }

    /// [`ShadingPoint::new`] with the ball's coating `coat` (`None` for an all-metal ball).
    pub(crate) fn with_coat(
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
            anisotropy: anisotropic_frame(b, n),
            clearcoat: None,
            lobe: BaseLobe::bare(roughness),
            refraction: clearcoat_refraction(scene, b),
        }
    }

    /// The point with `FssEss = F0 A + B` from the split sum's table (`A = E - B` with E
    /// from the tables, as `split_sum_scale` in `environment.wgsl`).
    pub(crate) fn with_split_sum(mut self, split: &SplitSum) -> Self {
        let bias = split.bias_at(self.mu_o as f32, self.roughness as f32) as f64;
        let e_o = 1.0 - self.loss_o;
        self.fss_ess = self.f0 * e_o + (DVec3::ONE - self.f0) * bias;
        self
    }
}

/// `coated_point` of `model.wgsl`: point `p` under its ball's clear coat `cc` (`None`: `p`
/// as it is). [`model_brdf`] then adds the coat's lobe and its shares of the base's light,
/// and reads the base's lobes as they leave the coat, wider
/// ([`super::clearcoat::clearcoat_base_lobe`]; an anisotropic lobe's alphas scaled with it).
pub(crate) fn coated_point(mut p: ShadingPoint, cc: Option<ClearcoatPoint>) -> ShadingPoint {
    let Some(cc) = cc else {
        return p;
    };
    p.clearcoat = Some(cc);
    p.lobe = cc.base_lobe();
    if let Some((_, alphas)) = &mut p.anisotropy {
        *alphas = (alphas.0 * p.lobe.alpha_scale, alphas.1 * p.lobe.alpha_scale);
    }
    p
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
///   ([`ShadingPoint::with_split_sum`], which [`super::render_montecarlo`] applies; without it
///   `F_avg E(mu_o)`).
pub(crate) fn model_brdf(p: &ShadingPoint, l: DVec3, e: &TableSet) -> DVec3 {
    let mu_i = p.n.dot(l);
    if mu_i <= 0.0 || p.mu_o <= 0.0 {
        return DVec3::ZERO;
    }
    let sum = p.v + l;
    let len = sum.length();
    if len <= DIV_EPSILON {
        return DVec3::ZERO;
    }
    let h = sum / len;
    // A clear coat (docs/design/coat.md): its own lobe, and the base's light through it,
    // a glossy base's (the metal, the coating's specular) and a Lambertian one's.
    let (lobe, base, coat) = match &p.clearcoat {
        Some(cc) => {
            let t_in = cc.transmit(e, mu_i, p.v.dot(h));
            let coat = match p.part {
                Part::Whole => cc.brdf((p.n, p.v, l), e, p.geometry),
                Part::Multiple => 0.0,
            };
            (cc.through_lobe(t_in), cc.through(t_in), coat)
        }
        None => (DVec3::ONE, DVec3::ONE, 0.0),
    };
    let coating = p.coating.map(|c| {
        let f = c.brdf((p.v, l), p.n, e, p.lobe);
        match p.part {
            Part::Whole => lobe * (f.spec + f.multiple) + base * f.base,
            Part::Multiple => lobe * f.multiple,
        }
    });
    let model = match coating {
        Some(c) if p.metallic <= 0.0 => c,
        Some(c) => p.metallic * lobe * metal_brdf(p, l, h, e) + (1.0 - p.metallic) * c,
        None => lobe * metal_brdf(p, l, h, e),
    };
    model + DVec3::splat(coat)
}

/// The metal's part of [`model_brdf`], `h` the half vector.
fn metal_brdf(p: &ShadingPoint, l: DVec3, h: DVec3, e: &TableSet) -> DVec3 {
    let mu_i = p.n.dot(l);
    let v_dot_h = p.v.dot(h);
    let n_dot_h = p.n.dot(h);
    // Under a clear coat the base's Fresnel is read inside the coat (a refracted cosine).
    let fresnel_cosine = clearcoat_base_fresnel_cosine(p.refraction, v_dot_h);
    let spec = per_channel(p.f0, |f| {
        let fresnel = f_schlick(f, fresnel_cosine);
        match &p.anisotropy {
            Some((frame, alphas)) => crate::brdf::f_micro_aniso(
                fresnel,
                frame.to_local(p.v),
                frame.to_local(l),
                frame.to_local(h),
                *alphas,
                p.geometry,
            ),
            None => f_micro(fresnel, p.mu_o, mu_i, n_dot_h, p.lobe.roughness, p.geometry),
        }
    }) * p.lobe.energy;
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

/// Ball `b`'s tangent frame at unit normal `n` and its lobe's `(alpha_t, alpha_b)` where
/// the lobe is anisotropic (`ball_tangent_frame` of `brdf.wgsl`, `brdf::ball_tangent`).
pub(crate) fn anisotropic_frame(b: &Ball, n: DVec3) -> Option<(Frame, (f64, f64))> {
    b.material.is_anisotropic().then(|| {
        let (t, bt) = ball_tangent(n, b.material.anisotropy_turn());
        (
            Frame::from_axes(t, bt, n),
            b.material.anisotropic_alphas(b.roughness),
        )
    })
}

/// Density (solid angle) of [`crate::sampling::sample_vndf`] at `l`: [`vndf_density`] at `l`'s half vector.
pub(super) fn pdf_vndf(p: &ShadingPoint, l: DVec3, alpha: f64) -> f64 {
    let sum = p.v + l;
    let len = sum.length();
    if len <= DIV_EPSILON {
        return 0.0;
    }
    vndf_density(p.mu_o, p.n.dot(sum / len), alpha)
}

/// A direction drawn from the metal lobe's visible normals, reflected (`sample_lobe` of
/// `model.wgsl`): an anisotropic lobe's own in its tangent frame ([`sample_vndf_aniso`]),
/// an isotropic one's of `alpha` in `frame`, any orthonormal frame about `n`, where `v` is
/// `v_local` ([`sample_vndf`]). Its density is [`pdf_vndf_lobe`]'s.
pub(super) fn sample_lobe(
    p: &ShadingPoint,
    frame: &Frame,
    v_local: DVec3,
    alpha: f64,
    (u1, u2): (f64, f64),
) -> DVec3 {
    match &p.anisotropy {
        Some((tangent, alphas)) => {
            tangent.to_world(sample_vndf_aniso(tangent.to_local(p.v), *alphas, u1, u2))
        }
        None => frame.to_world(sample_vndf(v_local, alpha, u1, u2)),
    }
}

/// Density (solid angle) of [`sample_lobe`] at `l`: [`vndf_density_aniso`] at `l`'s half
/// vector in the tangent frame of an anisotropic lobe, else [`pdf_vndf`] of `alpha`.
pub(super) fn pdf_vndf_lobe(p: &ShadingPoint, l: DVec3, alpha: f64) -> f64 {
    let Some((tangent, alphas)) = &p.anisotropy else {
        return pdf_vndf(p, l, alpha);
    };
    let sum = p.v + l;
    let len = sum.length();
    if len <= DIV_EPSILON {
        return 0.0;
    }
    vndf_density_aniso(tangent.to_local(p.v), tangent.to_local(sum / len), *alphas)
}
