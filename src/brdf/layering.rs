//! The base under a dielectric coating: the light the coating's specular lobe does not
//! reflect reaches the base, and part of it comes back out. Engines weight the base in
//! different ways; each function here is one of those forms, as a BRDF (the base's share,
//! `1/pi` included), of a scalar albedo (one channel) and the coating's specular
//! directional albedo `E_spec(mu)` (its single scattering with the multiple-scattering
//! term: what the tables give) at the two directions, and its cosine-weighted average
//! `E_spec_avg`.
//!
//! With a lossless coating, a form passes the white furnace when
//! `E_spec(mu_o) + int f_base mu_i dw_i = 1` for a white base: the view-only, the
//! reciprocal and the physical forms do by construction; the constant and glTF's do not.
//!
//! The physical form (a Lambertian substrate of albedo `rho` inside a medium of relative
//! index `eta`) follows the smooth coating's closed form with the rough interface's
//! albedo in place of the Fresnel factor: `rho (1 - E(mu_i)) (1 - E(mu_o)) / (pi eta^2 (1 -
//! rho F_in))`, `F_in = 1 - (1 - E_avg) / eta^2` the fraction of the substrate's diffuse
//! light the interface sends back. Read with `base_color` as the albedo a viewer sees (glTF's
//! and OpenPBR's reading), the substrate albedo that gives it ([`substrate_albedo`]) turns
//! the physical form into the reciprocal one exactly: they differ only in what the colour
//! means.

use std::f64::consts::FRAC_1_PI;

use super::DIV_EPSILON;

/// Today's constant weighting: `albedo (1 - F_avg) / pi`, with `F_avg` the coating's
/// average Fresnel (the single-scattering one in the shader's `kd`).
pub(crate) fn f_base_constant(albedo: f64, f_avg: f64) -> f64 {
    albedo * (1.0 - f_avg) * FRAC_1_PI
}

/// glTF 2.0's `fresnel_mix` (the specification's appendix B): `albedo (1 - F(v.h)) / pi`,
/// the Fresnel of the light's half vector.
pub(crate) fn f_base_gltf(albedo: f64, fresnel_vh: f64) -> f64 {
    albedo * (1.0 - fresnel_vh) * FRAC_1_PI
}

/// The view-only albedo scaling of Cycles' Principled BSDF v2 and MaterialX:
/// `albedo (1 - E_spec(mu_o)) / pi` (energy-conserving, not reciprocal).
pub(crate) fn f_base_view_only(albedo: f64, e_spec_o: f64) -> f64 {
    albedo * (1.0 - e_spec_o) * FRAC_1_PI
}

/// OpenPBR's reciprocal albedo scaling (OpenPBR Surface 1.0, "dielectric base"; Kutz et
/// al. 2021): `albedo (1 - E_spec(mu_i)) (1 - E_spec(mu_o)) / (pi (1 - E_spec_avg))`,
/// normalised so a white base passes the furnace.
pub(crate) fn f_base_reciprocal(albedo: f64, e_spec_o: f64, e_spec_i: f64, e_spec_avg: f64) -> f64 {
    albedo * (1.0 - e_spec_o) * (1.0 - e_spec_i) * FRAC_1_PI / (1.0 - e_spec_avg).max(DIV_EPSILON)
}

/// The fraction of a Lambertian substrate's light that the coating of relative index `eta`
/// reflects back down: `F_in = 1 - (1 - E_spec_avg) / eta^2` (what leaves divided by
/// `eta^2`, radiance crossing into the thinner medium; total internal reflection included).
pub(crate) fn coating_inside_reflectance(e_spec_avg: f64, eta: f64) -> f64 {
    1.0 - (1.0 - e_spec_avg) / (eta * eta).max(DIV_EPSILON)
}

/// The physical form: a Lambertian substrate of albedo `rho` under the coating of relative
/// index `eta`, the internal reflections summed:
/// `rho (1 - E_spec(mu_i)) (1 - E_spec(mu_o)) / (pi eta^2 (1 - rho F_in))`
/// ([`coating_inside_reflectance`]). Smooth, it is the closed form of a smooth coating over a
/// Lambertian base (Fresnel in and out, the geometric series of the internal bounces).
pub(crate) fn f_base_physical(
    rho: f64,
    e_spec_o: f64,
    e_spec_i: f64,
    e_spec_avg: f64,
    eta: f64,
) -> f64 {
    let f_in = coating_inside_reflectance(e_spec_avg, eta);
    rho * (1.0 - e_spec_o) * (1.0 - e_spec_i) * FRAC_1_PI
        / ((eta * eta) * (1.0 - rho * f_in)).max(DIV_EPSILON)
}

/// The substrate albedo `rho` whose light, seen through the coating, has the average
/// albedo `apparent` (the diffuse part's albedo over the light that entered,
/// `rho T / (1 - rho F_in)` with `T = 1 - F_in`): `rho = apparent / (T + apparent F_in)`.
/// With it, [`f_base_physical`] equals [`f_base_reciprocal`] of `apparent`.
pub(crate) fn substrate_albedo(apparent: f64, e_spec_avg: f64, eta: f64) -> f64 {
    let f_in = coating_inside_reflectance(e_spec_avg, eta);
    apparent / ((1.0 - f_in) + apparent * f_in).max(DIV_EPSILON)
}

/// The directional albedo of [`f_base_constant`]: `albedo (1 - F_avg)`.
pub(crate) fn base_albedo_constant(albedo: f64, f_avg: f64) -> f64 {
    albedo * (1.0 - f_avg)
}

/// The directional albedo glTF's viewers give [`f_base_gltf`] under image-based light, the
/// Fresnel of the view direction in place of the half vector's: `albedo (1 - F(mu_o))`.
pub(crate) fn base_albedo_gltf(albedo: f64, fresnel_o: f64) -> f64 {
    albedo * (1.0 - fresnel_o)
}

/// The directional albedo of [`f_base_view_only`] and of [`f_base_reciprocal`] (its
/// normalisation makes the integral over `mu_i` one): `albedo (1 - E_spec(mu_o))`.
pub(crate) fn base_albedo_view_only(albedo: f64, e_spec_o: f64) -> f64 {
    albedo * (1.0 - e_spec_o)
}

/// The directional albedo of [`f_base_physical`]: `rho (1 - E_spec(mu_o)) (1 -
/// E_spec_avg) / (eta^2 (1 - rho F_in))`.
pub(crate) fn base_albedo_physical(rho: f64, e_spec_o: f64, e_spec_avg: f64, eta: f64) -> f64 {
    let f_in = coating_inside_reflectance(e_spec_avg, eta);
    rho * (1.0 - e_spec_o) * (1.0 - e_spec_avg)
        / ((eta * eta) * (1.0 - rho * f_in)).max(DIV_EPSILON)
}
