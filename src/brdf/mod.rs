//! The BRDF maths (docs/design/model.md): plain functions over `f64`, one per term.
//!
//! Every function here is mirrored name for name in `shaders/brdf.wgsl`; the WGSL copy
//! evaluates the same formula in `f32`. The exceptions are bake-time averages, which the
//! GPU reads from tables rather than evaluates: `f_avg_dielectric`, `f_avg_inside`, and
//! the per-ball `clearcoat_inside_scale`. Conventions: the surface normal is +z,
//! `mu_o = n.v`, `mu_i = n.l`, `alpha = roughness^2`. Nothing in this layer knows of
//! tables, files or the GPU.

mod anisotropy;
mod clearcoat;
mod compensation;
mod fresnel;
mod geometry;
mod kulla_conty;
mod layering;
mod ndf;

pub(crate) use anisotropy::{
    anisotropic_alphas, ball_tangent, d_ggx_aniso, equal_area_roughness, f_micro_aniso,
    isotropic_roughness, lambda_smith_aniso,
};
pub use clearcoat::clearcoat_escape_nodes;
pub(crate) use clearcoat::{
    clearcoat_base_cosine, clearcoat_base_roughness, clearcoat_base_schlick_avg,
    clearcoat_escape_at, clearcoat_escape_pack, clearcoat_inside_scale, clearcoat_lobe_scale,
    clearcoat_through_engine, clearcoat_through_physical,
};
pub(crate) use compensation::{term_fdez_aguera, term_turquin};
pub use fresnel::f0_from_ior;
pub use fresnel::f_avg_games202;
#[cfg(test)]
pub(crate) use fresnel::f_avg_inside;
pub use fresnel::f_avg_schlick;
pub use fresnel::f_schlick;
pub use fresnel::GAMES202_EDGE_TINT;
pub(crate) use fresnel::{f_avg_dielectric, f_dielectric, fresnel_dielectric, DielectricFresnel};
pub use geometry::Geometry;
#[cfg(test)]
pub(crate) use geometry::{g1_schlick, g_smith, g_smith_correlated};
pub(crate) use geometry::{g1_smith, g_schlick, lambda_smith};
pub use kulla_conty::f_add_accurate;
pub use kulla_conty::f_add_games202;
pub use kulla_conty::f_add_preset;
pub use kulla_conty::f_ms;
pub use kulla_conty::f_ms_norm;
pub use kulla_conty::FAvgForm;
pub(crate) use layering::{
    base_albedo_constant, base_albedo_gltf, base_albedo_physical, base_albedo_view_only,
    coating_inside_reflectance, f_base_constant, f_base_gltf, f_base_physical, f_base_reciprocal,
    f_base_view_only, substrate_albedo,
};
pub(crate) use ndf::{d_ggx, visible_normal, visible_normal_aniso};

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
pub(crate) fn roughness_clamped(roughness: f64) -> f64 {
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

#[cfg(test)]
mod tests {
    //! The BRDF maths: normalisation, limits, identities, finiteness at the domain's edges.
    //!
    //! (They integrate with `lut::adaptive`: a unit test may use any layer of the library;
    //! tests/suite/layers.rs reads a file only up to its `#[cfg(test)] mod tests`.)

    use std::f64::consts::PI;

    use crate::brdf::*;
    use crate::lut::adaptive;

    /// Every f64 edge value the domain has, and the neighbours of the ends.
    fn edges() -> Vec<f64> {
        let mut v = vec![
            0.0,
            1.0,
            f64::MIN_POSITIVE,
            1e-300,
            1e-12,
            0.5,
            1.0 - f64::EPSILON,
        ];
        v.extend([-0.0, -1e-12, 1.0 + f64::EPSILON]);
        v
    }

    #[test]
    fn ggx_is_normalised_over_projected_area() {
        // int D(h) (n.h) dw_h = 1 (Walter et al. 2007, eq. 4). theta = atan(alpha tan(t)) maps
        // the peak smoothly, so the adaptive rule converges quickly.
        for roughness in [ROUGHNESS_MIN, 0.1, 0.3, 0.7, 1.0] {
            let alpha = alpha_from_roughness(roughness);
            let f = |t: f64| {
                let theta = (alpha * t.tan()).atan();
                let dtheta = alpha / (t.cos().powi(2) * (1.0 + (alpha * t.tan()).powi(2)));
                2.0 * PI * d_ggx(theta.cos(), alpha) * theta.cos() * theta.sin() * dtheta
            };
            let total = adaptive(&f, 0.0, PI / 2.0 - 1e-12, 1e-12);
            assert!((total - 1.0).abs() < 1e-7, "roughness {roughness}: {total}");
        }
    }

    #[test]
    fn geometry_terms_agree_where_they_must() {
        for c in [0.0, 0.01, 0.3, 0.7, 1.0] {
            // At roughness 1 (alpha = 1, k = 1/2) Schlick-GGX equals exact Smith: 2c / (1 + c).
            assert!(
                (g1_schlick(c, 0.5) - g1_smith(c, 1.0)).abs() < 1e-15,
                "c = {c}"
            );
            for roughness in [0.0, 0.2, 0.6, 1.0] {
                let alpha = alpha_from_roughness(roughness);
                // Smith G1 = 1 / (1 + Lambda).
                if c > 0.0 {
                    let via_lambda = 1.0 / (1.0 + lambda_smith(c, alpha));
                    assert!((g1_smith(c, alpha) - via_lambda).abs() < 1e-14);
                }
                // Height correlation only ever reduces the masking: G2 >= G1 G1.
                for mu_i in [0.05, 0.5, 1.0] {
                    assert!(
                        g_smith_correlated(c, mu_i, roughness)
                            >= g_smith(c, mu_i, roughness) - 1e-15
                    );
                }
            }
        }
        // Normal incidence is never masked.
        assert_eq!(g1_smith(1.0, 0.5), 1.0);
        assert_eq!(lambda_smith(1.0, 0.5), 0.0);
        assert_eq!(g1_schlick(1.0, 0.3), 1.0);
    }

    #[test]
    fn schlick_fresnel_and_its_average() {
        for f0 in [0.0, 0.04, 0.5, 0.95, 1.0] {
            assert_eq!(f_schlick(f0, 1.0), f0);
            assert_eq!(f_schlick(f0, 0.0), 1.0);
            // F_avg = 2 int_0^1 F(mu) mu dmu, integrated numerically.
            let numeric = adaptive(&|mu: f64| 2.0 * f_schlick(f0, mu) * mu, 0.0, 1.0, 1e-14);
            assert!((f_avg_schlick(f0) - numeric).abs() < 1e-12, "f0 {f0}");
        }
    }

    #[test]
    fn games202_fresnel_fit_matches_the_homework() {
        // The homework's copper: edge tint (0.827, 0.792, 0.678); at reflectivity = edge tint
        // = 1 the fit gives about 1 (a perfect mirror), as Kulla & Conty's fit is built to.
        let all_ones = f_avg_games202(1.0, 1.0);
        assert!((all_ones - 1.0).abs() < 0.01, "{all_ones}");
        // For the reference scene's albedo the fit and Schlick's F_avg disagree
        // (docs/design/model.md, "The homework's mistakes"): most in blue, the channel of least
        // reflectivity (0.2^2.2 = 0.029), where the fit gives 0.1141 and Schlick 0.0752.
        let albedo_b = 0.2f64.powf(2.2);
        let fit = f_avg_games202(albedo_b, GAMES202_EDGE_TINT[2]);
        let schlick = f_avg_schlick(albedo_b);
        assert!(
            (fit - 0.1141).abs() < 5e-4 && (schlick - 0.0752).abs() < 5e-4,
            "{fit} {schlick}"
        );
    }

    #[test]
    fn f_add_forms_differ_by_one_factor_of_f_avg() {
        for f_avg in [0.0, 0.3, 0.9, 1.0] {
            for e_avg in [0.0, 0.4, 0.99, 1.0] {
                let a = f_add_accurate(f_avg, e_avg);
                let g = f_add_games202(f_avg, e_avg);
                assert!((a - f_avg * g).abs() < 1e-12);
                assert!(a.is_finite() && g.is_finite() && a >= 0.0);
            }
        }
        // With F = 1 the accurate scale is exactly 1: the lobe restores all lost energy.
        assert!((f_add_accurate(1.0, 0.4) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn lobe_restores_the_lost_energy_exactly() {
        // int f_ms mu_i dw_i = 2 pi int_0^1 f_ms mu_i dmu_i = 1 - E(mu_o) when E_avg is the
        // cosine-weighted mean of E; checked with a synthetic 1 - E(mu) = 0.4 (1 - mu)^2.
        let loss = |mu: f64| 0.4 * (1.0 - mu).powi(2);
        let loss_avg = adaptive(&|mu: f64| 2.0 * loss(mu) * mu, 0.0, 1.0, 1e-14);
        for mu_o in [0.0, 0.3, 1.0] {
            let lobe = adaptive(
                &|mu_i: f64| 2.0 * PI * f_ms(loss(mu_o), loss(mu_i), f_ms_norm(loss_avg)) * mu_i,
                0.0,
                1.0,
                1e-14,
            );
            assert!((lobe - loss(mu_o)).abs() < 1e-12, "mu_o {mu_o}: {lobe}");
        }
    }

    #[test]
    fn every_function_is_finite_and_non_negative_on_the_edges() {
        let mut evaluated = 0usize;
        for &a in &edges() {
            for &b in &edges() {
                for &r in &edges() {
                    let values = [
                        d_ggx(a, alpha_from_roughness(r)),
                        g1_schlick(a, alpha_from_roughness(r) / 2.0),
                        g1_smith(a, alpha_from_roughness(r)),
                        g_schlick(a, b, r),
                        g_smith(a, b, r),
                        g_smith_correlated(a, b, r),
                        f_schlick(b.clamp(0.0, 1.0), a),
                        f_ms(
                            a.clamp(0.0, 1.0),
                            b.clamp(0.0, 1.0),
                            f_ms_norm(r.clamp(0.0, 1.0)),
                        ),
                        f_add_accurate(a.clamp(0.0, 1.0), b.clamp(0.0, 1.0)),
                        f_add_games202(a.clamp(0.0, 1.0), b.clamp(0.0, 1.0)),
                        f_micro(
                            1.0,
                            a,
                            b,
                            a.max(b).clamp(0.0, 1.0),
                            r,
                            Geometry::SmithCorrelated,
                        ),
                    ];
                    for v in values {
                        assert!(v.is_finite() && v >= 0.0, "({a}, {b}, {r}) gave {v}");
                        evaluated += 1;
                    }
                }
            }
        }
        assert_eq!(evaluated, 10 * 10 * 10 * 11);
        // NaN roughness is treated as the most diffuse lobe, not propagated.
        assert_eq!(roughness_clamped(f64::NAN), 1.0);
        assert_eq!(roughness_clamped(-3.0), ROUGHNESS_MIN);
    }

    #[test]
    fn f_add_preset_is_each_forms_f_add() {
        use crate::brdf::{f_add_preset, FAvgForm};
        for (f0, tint, e_avg) in [(0.04, 0.8, 0.9), (0.5, 0.83, 0.6), (1.0, 0.7, 0.41)] {
            let acc = f_add_preset(FAvgForm::Accurate, f0, tint, e_avg);
            assert_eq!(acc, f_add_accurate(f_avg_schlick(f0), e_avg));
            let hw = f_add_preset(FAvgForm::Games202, f0, tint, e_avg);
            assert_eq!(hw, f_add_games202(f_avg_games202(f0, tint), e_avg));
        }
    }
}
