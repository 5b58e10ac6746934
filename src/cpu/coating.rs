//! The dielectric part of a ball's shading on the CPU, term for term
//! `shaders/coating.wgsl` in f64: a rough coating of the ball's index over a Lambertian
//! base weighted by the scene's layering form.

use std::f64::consts::PI;

use glam::DVec3;

use super::clearcoat::{clearcoat_base_fresnel_cosine, clearcoat_refraction, BaseLobe};
use super::forms::Forms;
use super::light::{loss, CpuEnvironment};
use crate::brdf::{
    base_albedo_constant, base_albedo_gltf, base_albedo_physical, base_albedo_view_only,
    f0_from_ior, f_base_constant, f_base_gltf, f_base_physical, f_base_reciprocal,
    f_base_view_only, f_dielectric, f_micro, f_ms, f_ms_norm, term_fdez_aguera, term_turquin,
};
use crate::environment::IblTerm;
use crate::lut::{coating_albedo, TableSet, COATING_ROW_LEN};
use crate::prepared::{coating_spec_albedo, Coat, CoatingConstants};
use crate::scene::{Ball, Layering, Scene};

/// A point of a ball's coating: what `shade_coating` forms once per pixel (the GPU's
/// per-ball members and its per-pixel reads at the view), for its light loop and the
/// Monte Carlo of the model (`montecarlo::model_brdf`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct CoatingPoint {
    row: [f32; COATING_ROW_LEN],
    constants: CoatingConstants,
    layering: Layering,
    albedo: DVec3,
    fresnel_form: crate::brdf::DielectricFresnel,
    geometry: crate::brdf::Geometry,
    roughness: f64,
    ms: f64,
    term: IblTerm,
    f0: f64,
    norm: f64,
    mu_o: f64,
    /// `1 - E(mu_o)` (0 without the term).
    pub loss_o: f64,
    /// The row's `E_F(mu_o)`.
    pub e_f_o: f64,
    /// `E_spec(mu_o)`.
    pub e_spec_o: f64,
    /// Fdez-Aguera's energy (0 for the other terms).
    pub fms_ems: f64,
    /// The base's directional albedo at the view.
    pub base_o: DVec3,
    /// The ball's clear coat as the coating's Fresnel sees it
    /// ([`super::clearcoat::clearcoat_refraction`]).
    refraction: Option<(f64, f64)>,
}

/// The coating's BRDF at one light direction, by part.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CoatingBrdf {
    /// The interface's single scattering.
    pub spec: f64,
    /// The term's lobe, weighted by `ms`.
    pub multiple: f64,
    /// The base under the layering form.
    pub base: DVec3,
}

impl CoatingPoint {
    /// Ball `b`'s coating `coat` seen at unit normal `n` from `v`, with E from `e`.
    pub(crate) fn new(
        scene: &Scene,
        b: &Ball,
        coat: &Coat,
        (n, v): (DVec3, DVec3),
        e: &TableSet,
    ) -> Self {
        let Coat {
            row,
            constants,
            albedo,
        } = *coat;
        let roughness = b.shading_roughness();
        let ms = if b.model.has_term() { 1.0 } else { 0.0 };
        let term = b.model.term().unwrap_or(IblTerm::KullaConty);
        let loss_avg = super::light::loss_avg(e, roughness);
        let read = |mu: f64| loss(e, mu, roughness);
        let eta = constants.eta;
        let f0 = f0_from_ior(eta);
        let fresnel_form = scene.preset.dielectric_fresnel();
        let mu_o = n.dot(v).max(0.0);
        let loss_o = if ms > 0.0 { read(mu_o) } else { 0.0 };
        // Under a clear coat the coating's Fresnel is read inside the coat (refracted
        // cosines): its albedo E_F and the base's share with it.
        let refraction = clearcoat_refraction(scene, b);
        let mu_fresnel = clearcoat_base_fresnel_cosine(refraction, mu_o);
        let e_f_o = f64::from(coating_albedo(&row, mu_fresnel as f32));
        let e_spec_o = coating_spec_albedo(e_f_o, loss_o, f0, constants.f_add, ms, term);
        let fms_ems = if ms > 0.0 && term == IblTerm::FdezAguera {
            term_fdez_aguera(e_f_o, f0, loss_o)
        } else {
            0.0
        };
        let mut point = CoatingPoint {
            row,
            constants,
            layering: scene.layering,
            albedo,
            fresnel_form,
            geometry: scene.effective_geometry(),
            roughness,
            ms,
            term,
            f0,
            norm: if ms > 0.0 { f_ms_norm(loss_avg) } else { 0.0 },
            mu_o,
            loss_o,
            e_f_o,
            e_spec_o,
            fms_ems,
            base_o: DVec3::ZERO,
            refraction,
        };
        point.base_o = point.base_albedo(e_spec_o, f_dielectric(mu_fresnel, eta, fresnel_form));
        point
    }

    /// The coating's directional albedo at the view: `E_spec(mu_o)` and the base's.
    #[allow(dead_code)] // the point's albedo, read by no caller yet
    pub(crate) fn albedo(&self) -> DVec3 {
        DVec3::splat(self.e_spec_o) + self.base_o
    }

    /// The coating's BRDF towards unit light direction `l` (`mu_i = n.l > 0`), `e` the
    /// tables (the light loop of `shade_coating`), its specular read as `lobe` says (the
    /// coating's own, or widened under a clear coat:
    /// [`super::clearcoat::clearcoat_base_lobe`]).
    pub(crate) fn brdf(
        &self,
        (v, l): (DVec3, DVec3),
        n: DVec3,
        e: &TableSet,
        lobe: BaseLobe,
    ) -> CoatingBrdf {
        let mu_i = n.dot(l);
        let h = (v + l).normalize();
        let eta = self.constants.eta;
        let f_add = self.constants.f_add;
        let v_dot_h = clearcoat_base_fresnel_cosine(self.refraction, v.dot(h));
        let fresnel = f_dielectric(v_dot_h, eta, self.fresnel_form);
        let spec = lobe.energy
            * f_micro(
                fresnel,
                self.mu_o,
                mu_i,
                n.dot(h),
                lobe.roughness,
                self.geometry,
            );
        let (mut lobe, mut loss_i) = (0.0, 0.0);
        if self.ms > 0.0 {
            loss_i = loss(e, mu_i, self.roughness);
            lobe = match self.term {
                IblTerm::Turquin => term_turquin(spec, self.f0, 1.0 - self.loss_o),
                IblTerm::FdezAguera => self.fms_ems / PI,
                IblTerm::KullaConty => f_add * f_ms(self.loss_o, loss_i, self.norm),
            };
        }
        let e_spec_i = if self.two_sided() {
            let mu_fresnel = clearcoat_base_fresnel_cosine(self.refraction, mu_i);
            let e_f_i = f64::from(coating_albedo(&self.row, mu_fresnel as f32));
            coating_spec_albedo(e_f_i, loss_i, self.f0, f_add, self.ms, self.term)
        } else {
            0.0
        };
        CoatingBrdf {
            spec,
            multiple: self.ms * lobe,
            base: self.base(self.e_spec_o, e_spec_i, fresnel),
        }
    }

    /// `coating_base` of `coating.wgsl`: the base's BRDF under the layering form.
    fn base(&self, e_spec_o: f64, e_spec_i: f64, fresnel_vh: f64) -> DVec3 {
        let c = &self.constants;
        let f = |a: f64| match self.layering {
            Layering::Constant => f_base_constant(a, c.f_avg),
            Layering::Gltf => f_base_gltf(a, fresnel_vh),
            Layering::ViewOnly => f_base_view_only(a, e_spec_o),
            Layering::Reciprocal => f_base_reciprocal(a, e_spec_o, e_spec_i, c.e_spec_avg),
            Layering::Physical => f_base_physical(a, e_spec_o, e_spec_i, c.e_spec_avg, c.eta),
        };
        DVec3::new(f(self.albedo.x), f(self.albedo.y), f(self.albedo.z))
    }

    /// `coating_base_albedo` of `coating.wgsl`: the base's directional albedo.
    fn base_albedo(&self, e_spec_o: f64, fresnel_o: f64) -> DVec3 {
        let c = &self.constants;
        let f = |a: f64| match self.layering {
            Layering::Constant => base_albedo_constant(a, c.f_avg),
            Layering::Gltf => base_albedo_gltf(a, fresnel_o),
            Layering::ViewOnly | Layering::Reciprocal => base_albedo_view_only(a, e_spec_o),
            Layering::Physical => base_albedo_physical(a, e_spec_o, c.e_spec_avg, c.eta),
        };
        DVec3::new(f(self.albedo.x), f(self.albedo.y), f(self.albedo.z))
    }

    /// Whether the form reads `E_spec` at the light's direction too (`two_sided`).
    fn two_sided(&self) -> bool {
        matches!(self.layering, Layering::Reciprocal | Layering::Physical)
    }
}

/// `shade_coating` of `coating.wgsl`, the map's part (`shade_coating_map`) included where
/// the scene has one (`forms.map`): radiance leaving ball `b`'s coating `coat` at unit
/// normal `n` towards `v`.
pub(super) fn shade_coating(
    scene: &Scene,
    (b, coat): (&Ball, &Coat),
    n: DVec3,
    v: DVec3,
    e: &TableSet,
    forms: &Forms<'_>,
) -> DVec3 {
    let point = CoatingPoint::new(scene, b, coat, (n, v), e);
    // The shares of uniform light and the map that a clear coat lets through (1 without):
    // the specular's as a glossy base's, the base's as a Lambertian one's.
    let through = forms.coat.map_or((DVec3::ONE, DVec3::ONE), |c| {
        (c.environment_lobe(), c.environment())
    });
    let mut lo = scene.environment * (point.e_spec_o * through.0 + point.base_o * through.1);
    // The lobe mode: the map's part is the whole model's (`shade::shade_environment_mis`).
    if let (Some(map), None) = (forms.map, forms.lobe) {
        let map_roughness = forms
            .coat
            .map_or(b.shading_roughness(), |c| c.base_roughness());
        lo += shade_coating_map(scene, (b, &point), (n, v), (map, map_roughness), through);
    }
    // Under a clear coat the specular leaves the coat wider (clearcoat_base_lobe).
    let lobe_of = forms
        .coat
        .map_or(BaseLobe::bare(point.roughness), |c| c.base_lobe());
    for light in &scene.lights {
        let mu_i = n.dot(light.direction);
        if mu_i <= 0.0 || point.mu_o <= 0.0 {
            continue;
        }
        let f = point.brdf((v, light.direction), n, e, lobe_of);
        let (lobe, base) = forms.coat.map_or((DVec3::ONE, DVec3::ONE), |c| {
            let t_in = c.transmit(e, mu_i, v.dot((v + light.direction).normalize()));
            (c.through_lobe(t_in), c.through(t_in))
        });
        let f_r = lobe * (f.spec + f.multiple) + base * f.base;
        lo += f_r * light.radiance * mu_i;
    }
    lo
}

/// `shade_coating_map` of `coating.wgsl` (the split sum's): the prefiltered layers along the
/// dominant direction times `E_F(mu_o)`, the base's albedo times the irradiance, the term.
fn shade_coating_map(
    scene: &Scene,
    (b, p): (&Ball, &CoatingPoint),
    (n, v): (DVec3, DVec3),
    (map, map_roughness): (&CpuEnvironment, f64),
    (through_lobe, through_base): (DVec3, DVec3),
) -> DVec3 {
    let Some(environment) = &scene.environment_map else {
        return DVec3::ZERO;
    };
    let roughness = b.shading_roughness();
    let intensity = map.intensity(environment);
    let n_map = environment.to_map(n);
    let irradiance = intensity * map.prefiltered.irradiance(n_map);
    let r = 2.0 * n.dot(v) * n - v;
    let dominant = crate::environment::prefilter::specular_direction(n, r, map_roughness);
    let radiance = intensity
        * map
            .prefiltered
            .specular(environment.to_map(dominant), map_roughness);
    let single = radiance * p.e_f_o;
    let mut lobe = single;
    if p.ms > 0.0 {
        lobe += p.ms
            * match p.term {
                IblTerm::Turquin => single * term_turquin(1.0, p.f0, 1.0 - p.loss_o),
                IblTerm::FdezAguera => p.fms_ems * irradiance,
                IblTerm::KullaConty => {
                    p.constants.f_add
                        * p.loss_o
                        * intensity
                        * map.prefiltered.multiple(n_map, roughness)
                }
            };
    }
    // A clear coat's shares (1 without): the specular's and the base's.
    lobe * through_lobe + p.base_o * irradiance * through_base
}
