//! The BRDF maths (docs/design/model.md): plain functions over `f64`, one per term.
//!
//! Every function here is mirrored name for name in `shaders/brdf.wgsl`; the WGSL copy
//! evaluates the same formula in `f32`. The exceptions are bake-time averages, which the
//! GPU reads from tables rather than evaluates: `f_avg_dielectric`, `f_avg_inside`. Conventions: the surface normal is +z,
//! `mu_o = n.v`, `mu_i = n.l`, `alpha = roughness^2`. Nothing in this layer knows of
//! tables, files or the GPU.

mod compensation;
mod fresnel;
mod geometry;
mod kulla_conty;
mod layering;
mod ndf;

pub use compensation::{term_fdez_aguera, term_turquin};
pub use fresnel::{
    f0_from_ior, f_avg_dielectric, f_avg_games202, f_avg_inside, f_avg_schlick, f_dielectric,
    f_schlick, fresnel_dielectric, DielectricFresnel, GAMES202_EDGE_TINT,
};
pub use geometry::{
    g1_schlick, g1_smith, g_schlick, g_smith, g_smith_correlated, lambda_smith, Geometry,
};
pub use kulla_conty::{
    f_add_accurate, f_add_denominator, f_add_games202, f_add_preset, f_ms, f_ms_norm, FAvgForm,
};
pub use layering::{
    base_albedo_constant, base_albedo_gltf, base_albedo_physical, base_albedo_view_only,
    coating_inside_reflectance, f_base_constant, f_base_gltf, f_base_physical, f_base_reciprocal,
    f_base_view_only, substrate_albedo,
};
pub use ndf::{d_ggx, visible_normal};

/// Smallest roughness the model evaluates. Roughness 0 makes GGX a delta (alpha = 0, a
/// division by zero at the mirror direction); every layer clamps to this value first, so
/// the tables, the shader and the CPU renderer agree on what "roughness 0" means.
/// 0.02 gives alpha = 4e-4 and a peak D of 2e6, well inside f32 range.
pub const ROUGHNESS_MIN: f64 = 0.02;

/// Guard for divisions whose denominator can reach zero at the edge of the domain
/// (grazing angles, `E_avg -> 1`, `F_avg -> 1`). Chosen far below any value the model
/// produces inside the domain, so it changes no result there.
pub const DIV_EPSILON: f64 = 1e-12;

/// The roughness the model actually uses: clamped to `[ROUGHNESS_MIN, 1]`.
/// NaN is mapped to 1 (the most diffuse lobe) rather than propagated.
pub fn roughness_clamped(roughness: f64) -> f64 {
    if roughness.is_nan() {
        return 1.0;
    }
    roughness.clamp(ROUGHNESS_MIN, 1.0)
}

/// `alpha = roughness^2` (Burley 2012's remapping), after the roughness clamp.
pub fn alpha_from_roughness(roughness: f64) -> f64 {
    let r = roughness_clamped(roughness);
    r * r
}

/// The single-scattering Cook-Torrance BRDF (Cook & Torrance 1982; Walter et al. 2007):
/// `F G D / (4 mu_i mu_o)` for a scalar Fresnel value `fresnel`. Directions below the
/// horizon give 0.
pub fn f_micro(
    fresnel: f64,
    mu_o: f64,
    mu_i: f64,
    n_dot_h: f64,
    roughness: f64,
    geometry: Geometry,
) -> f64 {
    if mu_o <= 0.0 || mu_i <= 0.0 {
        return 0.0;
    }
    let alpha = alpha_from_roughness(roughness);
    let d = d_ggx(n_dot_h, alpha);
    let g = geometry.g(mu_o, mu_i, roughness);
    fresnel * g * d / (4.0 * mu_i * mu_o).max(DIV_EPSILON)
}
