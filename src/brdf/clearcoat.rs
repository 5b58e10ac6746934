//! A clear coat over a whole ball's shading (docs/design/coat.md): a rough dielectric
//! interface of its own roughness and index over whatever the ball is (metal, plastic or
//! a mix), weighted by the coat's `weight` as OpenPBR's `coat_weight` is (a mix: a share
//! `1 - weight` of the surface has no coat).
//!
//! The physical form (the default) follows the layering of Weidlich and Wilkie 2007
//! ("Arbitrarily Layered Micro-Facet Surfaces") as Kulla and Conty 2017 ("Revisiting
//! Physically Based Shading at Imageworks", the layering section) write it with albedos: the
//! coat reflects its own specular albedo `E_c(mu)` (its single scattering and its
//! Kulla-Conty term), the base is seen through it with the transmission `1 - E_c` both ways,
//! and the light the base sends back up is partly reflected down again by the coat, the
//! internal reflections summed as a geometric series of the base's average albedo
//! `A_avg` and the coat's inside reflectance `F_in = 1 - (1 - E_c_avg) / eta^2`:
//! `f = f_c + (1 - E_c(mu_o)) (1 - E_c(mu_i)) f_base / (eta^2 (1 - A_avg F_in))`.
//! A white base (`A = 1` at every angle) then reflects everything under uniform light, as
//! [`crate::brdf::f_base_physical`] does for the Lambertian substrate.
//!
//! The engines' forms, for comparison, conserve no energy: Filament's (the clear coat of
//! "Physically Based Rendering in Filament", Guy and Agopian) attenuates the base by `1 -
//! F_c(v.h)`; glTF's `KHR_materials_clearcoat` mixes base and coat by `weight F_c(n.v)`.

use super::DIV_EPSILON;

/// The factor of the base's light seen through the physical coat, after the two
/// transmissions: `1 / (eta^2 (1 - A_avg F_in))`, `F_in = 1 - (1 - E_c_avg) / eta^2`
/// ([`super::coating_inside_reflectance`]): the internal reflections between the coat and a
/// base of average albedo `a_avg` summed, and the radiance's `1 / eta^2` on leaving the
/// denser coat.
pub(crate) fn clearcoat_inside_scale(a_avg: f64, e_coat_avg: f64, eta: f64) -> f64 {
    let f_in = super::coating_inside_reflectance(e_coat_avg, eta);
    1.0 / ((eta * eta) * (1.0 - a_avg * f_in)).max(DIV_EPSILON)
}

/// The share of the base's light under the physical coat of weight `weight` for light
/// arriving with the coat's transmission `1 - e_coat_i`: `(1 - weight) + weight out (1 -
/// e_coat_i)`, `out = (1 - E_c(mu_o)) clearcoat_inside_scale` the view's part.
pub(crate) fn clearcoat_through_physical(weight: f64, out: f64, e_coat_i: f64) -> f64 {
    (1.0 - weight) + weight * out * (1.0 - e_coat_i)
}

/// The share of the base's light under an engine's coat of weight `weight`: `1 - weight F`,
/// `F` the coat's Fresnel at `v.h` (Filament) or at `n.v` (glTF).
pub(crate) fn clearcoat_through_engine(weight: f64, fresnel: f64) -> f64 {
    1.0 - weight * fresnel
}
