//! A ball's clear coat on the CPU, term for term `shaders/clearcoat.wgsl` in f64: the
//! coat's own lobe and the share of the base's light that comes through it
//! (docs/design/coat.md).

use glam::DVec3;

use super::light::{loss, CpuEnvironment};
use crate::brdf::{
    alpha_from_roughness, clearcoat_base_cosine, clearcoat_base_schlick_avg, clearcoat_escape_at,
    clearcoat_inside_scale, clearcoat_lobe_scale, clearcoat_through_engine,
    clearcoat_through_physical, f_avg_schlick, f_dielectric, f_micro, f_ms, Geometry, DIV_EPSILON,
};
use crate::lut::{coating_albedo, lut_row_unpack, TableSet, COATING_ROW_LEN};
use crate::prepared::{Clearcoat, ClearcoatConstants};
use crate::scene::{Ball, CoatForm, Scene};

/// What `clearcoat_begin` forms once per pixel (`ClearcoatPoint` of `clearcoat.wgsl`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct ClearcoatPoint {
    row: [f32; COATING_ROW_LEN],
    c: ClearcoatConstants,
    fresnel_form: crate::brdf::DielectricFresnel,
    mu_o: f64,
    /// The view's part of a Lambertian base's weight, per channel (1 under the engines').
    out: DVec3,
    /// The view's part of a glossy base's weight, per channel (1 under the engines').
    out_lobe: DVec3,
    /// The coat's directional albedo at the view under its form.
    albedo_o: f64,
    /// A Lambertian base's weight under uniform light and the map.
    environment: DVec3,
    /// A glossy base's weight under uniform light and the map.
    environment_lobe: DVec3,
    loss_o: f64,
    e_f_o: f64,
    fresnel_o: f64,
    ms: f64,
    /// A glossy base's lobe under the coat at the view ([`clearcoat_base_lobe`]).
    base_lobe: BaseLobe,
}

/// A glossy base's single-scattering lobe as it leaves a clear coat (`clearcoat_base_lobe`
/// of `coating.wgsl`, whose vec3 holds the three fields in this order).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct BaseLobe {
    /// The roughness the lobe is read at.
    pub roughness: f64,
    /// The factor that keeps its albedo at the view the base's own.
    pub energy: f64,
    /// The factor of an anisotropic lobe's alphas.
    pub alpha_scale: f64,
}

impl BaseLobe {
    /// The lobe of a base of `roughness` seen bare.
    pub(crate) fn bare(roughness: f64) -> Self {
        BaseLobe {
            roughness,
            energy: 1.0,
            alpha_scale: 1.0,
        }
    }
}

/// `clearcoat_base_lobe` of `coating.wgsl`: the lobe of a glossy base of `roughness` under
/// the coat `c` at the view's cosine `mu_o` (docs/design/coat.md, "The base's lobe leaves
/// the coat wider"). Under the physical form it is read at `c.base_roughness`, scaled by
/// `E(mu_o) / E_wide(mu_o)` (`E_wide` along `c.base_row`) so that its albedo at the view
/// stays the base's own (as the split sum reads the map at the widened roughness and the
/// albedos at the base's), and an anisotropic lobe's alphas scale as its isotropic
/// equivalent's; the bare lobe otherwise.
pub(crate) fn clearcoat_base_lobe(
    c: &ClearcoatConstants,
    roughness: f64,
    mu_o: f64,
    e: &TableSet,
) -> BaseLobe {
    if c.form != CoatForm::Physical {
        return BaseLobe::bare(roughness);
    }
    let wide = c.base_roughness;
    let e_own = 1.0 - loss(e, mu_o, roughness);
    let row = lut_row_unpack(c.base_row, wide as f32);
    let e_wide = 1.0 - f64::from(e.lut_loss_row(mu_o as f32, row));
    BaseLobe {
        roughness: wide,
        energy: e_own / e_wide.max(DIV_EPSILON),
        // alpha_from_roughness clamps the roughness: the denominator is at least
        // ROUGHNESS_MIN^2.
        alpha_scale: alpha_from_roughness(wide) / alpha_from_roughness(roughness),
    }
}

/// Ball `b`'s clear coat as its glossy base's Fresnel sees it: the coat's index and weight
/// under the physical form, `None` bare or under an engine's form (`coating.wgsl`'s
/// `clearcoat_base_fresnel_cosine` and `clearcoat_base_f_avg` read them from the ball).
pub(crate) fn clearcoat_refraction(scene: &Scene, b: &Ball) -> Option<(f64, f64)> {
    let c = b.material.clearcoat;
    (c.is_on() && scene.coat_form == CoatForm::Physical).then_some((c.ior, c.weight))
}

/// `clearcoat_base_fresnel_cosine` of `coating.wgsl`: the cosine at which a glossy base's
/// Fresnel is read under the coat `refraction` ([`clearcoat_refraction`]): `c` refracted
/// into it ([`clearcoat_base_cosine`]), `c` bare.
pub(crate) fn clearcoat_base_fresnel_cosine(refraction: Option<(f64, f64)>, c: f64) -> f64 {
    refraction.map_or(c, |(eta, weight)| clearcoat_base_cosine(c, eta, weight))
}

/// `clearcoat_base_f_avg` of `coating.wgsl`: the cosine-weighted average of Schlick's
/// Fresnel of `f0` as a glossy base sees uniform light under the coat `refraction`
/// ([`clearcoat_base_schlick_avg`]), `F0 + (1 - F0) / 21` bare.
pub(crate) fn clearcoat_base_f_avg(refraction: Option<(f64, f64)>, f0: DVec3) -> DVec3 {
    match refraction {
        Some((eta, weight)) => f0 + (DVec3::ONE - f0) * clearcoat_base_schlick_avg(eta, weight),
        None => f0.map(f_avg_schlick),
    }
}

impl ClearcoatPoint {
    /// `clearcoat_begin`: ball `b`'s coat `coat` at unit normal `n` towards `v`, `ms_ball`
    /// the ball's term weight.
    pub(crate) fn new(
        scene: &Scene,
        b: &Ball,
        coat: &Clearcoat,
        (n, v): (DVec3, DVec3),
        e: &TableSet,
    ) -> Self {
        let c = coat.constants;
        let ms_ball = if b.model.has_term() { 1.0 } else { 0.0 };
        let w = c.weight;
        let form = c.form;
        let mu_o = n.dot(v).max(0.0);
        let ms = match form {
            CoatForm::Physical => ms_ball,
            CoatForm::Filament | CoatForm::Gltf => 0.0,
        };
        let lit = scene.environment != DVec3::ZERO || scene.environment_map.is_some();
        let loss_o = if ms > 0.0 || (form == CoatForm::Gltf && lit) {
            loss(e, mu_o, c.roughness)
        } else {
            0.0
        };
        let e_f_o = f64::from(coating_albedo(&coat.row, mu_o as f32));
        let fresnel_o = f_dielectric(mu_o, c.eta, c.fresnel);
        // The engines' forms: the base's light times 1 - w F, the same for every base.
        let engine = DVec3::splat(clearcoat_through_engine(w, fresnel_o));
        let (albedo_o, (out, out_lobe), (environment, environment_lobe)) = match form {
            CoatForm::Filament => (e_f_o, (DVec3::ONE, DVec3::ONE), (engine, engine)),
            CoatForm::Gltf => (
                fresnel_o * (1.0 - loss_o),
                (DVec3::ONE, DVec3::ONE),
                (engine, engine),
            ),
            CoatForm::Physical => {
                let e_o = e_f_o + ms * c.f_add * loss_o;
                let (a, e_avg, eta) = (c.base_avg, c.e_avg, c.eta);
                let escape = clearcoat_escape_at(c.escape, mu_o);
                let out = (1.0 - e_o) * a.map(|a| clearcoat_inside_scale(a, e_avg, eta));
                let out_lobe = (1.0 - e_o) * a.map(|a| clearcoat_lobe_scale(a, escape, e_avg, eta));
                let through = |o: DVec3| o.map(|o| clearcoat_through_physical(w, o, 1.0 - e_avg));
                (e_o, (out, out_lobe), (through(out), through(out_lobe)))
            }
        };
        let base_lobe = clearcoat_base_lobe(&c, b.shading_roughness(), mu_o, e);
        ClearcoatPoint {
            base_lobe,
            row: coat.row,
            c,
            fresnel_form: c.fresnel,
            mu_o,
            out,
            out_lobe,
            albedo_o,
            environment,
            environment_lobe,
            loss_o,
            e_f_o,
            fresnel_o,
            ms,
        }
    }

    /// The coat lobe's GGX alpha (the Monte Carlo draws the coat's visible normals with it).
    pub(crate) fn alpha(&self) -> f64 {
        crate::brdf::alpha_from_roughness(self.c.roughness)
    }

    /// The roughness at which the base reads the map's prefiltered layers under the coat
    /// (`Ball.clearcoat_base_roughness`).
    pub(crate) fn base_roughness(&self) -> f64 {
        self.c.base_roughness
    }

    /// A glossy base's lobe under the coat at the view ([`clearcoat_base_lobe`]).
    pub(crate) fn base_lobe(&self) -> BaseLobe {
        self.base_lobe
    }

    /// `clearcoat_albedo`: the physical coat's `E_c(mu)`.
    fn albedo(&self, e: &TableSet, mu: f64) -> f64 {
        let l = if self.ms > 0.0 {
            loss(e, mu, self.c.roughness)
        } else {
            0.0
        };
        f64::from(coating_albedo(&self.row, mu as f32)) + self.ms * self.c.f_add * l
    }

    /// `clearcoat_in`: the coat's transmission of a light at cosine `mu_i` (`v_dot_h` the
    /// view's cosine to the half vector) under its form.
    pub(crate) fn transmit(&self, e: &TableSet, mu_i: f64, v_dot_h: f64) -> f64 {
        match self.c.form {
            CoatForm::Filament => 1.0 - f_dielectric(v_dot_h, self.c.eta, self.fresnel_form),
            CoatForm::Gltf => 1.0 - self.fresnel_o,
            CoatForm::Physical => 1.0 - self.albedo(e, mu_i),
        }
    }

    /// `clearcoat_through`: the share of a Lambertian base's light from a light the coat
    /// transmits with `t_in` ([`ClearcoatPoint::transmit`]) that comes through.
    pub(crate) fn through(&self, t_in: f64) -> DVec3 {
        self.out
            .map(|o| clearcoat_through_physical(self.c.weight, o, t_in))
    }

    /// `clearcoat_through_lobe`: [`ClearcoatPoint::through`] for a glossy base's light.
    pub(crate) fn through_lobe(&self, t_in: f64) -> DVec3 {
        self.out_lobe
            .map(|o| clearcoat_through_physical(self.c.weight, o, t_in))
    }

    /// `clearcoat_environment`: the share of uniform light and the map that comes
    /// through, for a Lambertian base's light.
    pub(crate) fn environment(&self) -> DVec3 {
        self.environment
    }

    /// `clearcoat_environment_lobe`: the same for a glossy base's light.
    pub(crate) fn environment_lobe(&self) -> DVec3 {
        self.environment_lobe
    }

    /// The coat's own BRDF towards the light `l` under its form, times its weight (the
    /// lights' loop of `shade_clearcoat`; 0 with `l` or `v` below the horizon), its GGX
    /// lobe at the coat's roughness.
    pub(crate) fn brdf(
        &self,
        (n, v, l): (DVec3, DVec3, DVec3),
        e: &TableSet,
        geometry: Geometry,
    ) -> f64 {
        let c = &self.c;
        let mu_i = n.dot(l);
        if mu_i <= 0.0 || self.mu_o <= 0.0 {
            return 0.0;
        }
        let h = (v + l).normalize();
        let fresnel = match c.form {
            CoatForm::Gltf => 1.0,
            _ => f_dielectric(v.dot(h), c.eta, self.fresnel_form),
        };
        let mut spec = f_micro(fresnel, self.mu_o, mu_i, n.dot(h), c.roughness, geometry);
        if c.form == CoatForm::Gltf {
            spec *= self.fresnel_o;
        }
        if self.ms > 0.0 {
            let loss_i = loss(e, mu_i, c.roughness);
            spec += self.ms * c.f_add * f_ms(self.loss_o, loss_i, c.ms_norm);
        }
        c.weight * spec
    }
}

/// `shade_clearcoat` of `clearcoat.wgsl`: the coat's own radiance at unit normal `n`
/// towards `v`, times its weight; the map's part where the scene has one (`map`).
pub(super) fn shade_clearcoat(
    scene: &Scene,
    p: &ClearcoatPoint,
    (n, v): (DVec3, DVec3),
    e: &TableSet,
    (map, geometry): (Option<&CpuEnvironment>, Geometry),
) -> DVec3 {
    let c = &p.c;
    let mut lo = scene.environment * p.albedo_o;
    if let Some(map) = map {
        lo += shade_clearcoat_map(scene, p, (n, v), map);
    }
    let mut lights = DVec3::ZERO;
    for light in &scene.lights {
        lights +=
            p.brdf((n, v, light.direction), e, geometry) * light.radiance * n.dot(light.direction);
    }
    c.weight * lo + lights
}

/// `shade_clearcoat_map` of `clearcoat.wgsl`.
fn shade_clearcoat_map(
    scene: &Scene,
    p: &ClearcoatPoint,
    (n, v): (DVec3, DVec3),
    map: &CpuEnvironment,
) -> DVec3 {
    let Some(environment) = &scene.environment_map else {
        return DVec3::ZERO;
    };
    let c = &p.c;
    let roughness = c.roughness;
    let intensity = map.intensity(environment);
    // The prefiltered layers in the lobe mode too (its samples are the base's).
    let r = 2.0 * n.dot(v) * n - v;
    let dominant = crate::environment::prefilter::specular_direction(n, r, roughness);
    let radiance = intensity
        * map
            .prefiltered
            .specular(environment.to_map(dominant), roughness);
    if c.form == CoatForm::Physical && p.ms > 0.0 {
        let multiple = intensity * map.prefiltered.multiple(environment.to_map(n), roughness);
        return radiance * p.e_f_o + p.ms * c.f_add * p.loss_o * multiple;
    }
    radiance * p.albedo_o
}
