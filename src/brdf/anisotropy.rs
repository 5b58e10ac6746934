//! Anisotropic GGX (docs/design/anisotropy.md): the roughness pair glTF's
//! `KHR_materials_anisotropy` defines, the NDF, Smith's Lambda and the masking-shadowing
//! terms for it. Vectors are in the local frame (tangent `x`, bitangent `y`, normal `z`),
//! the tangent being the direction of `alpha_t`.

use std::f64::consts::PI;

use super::{alpha_from_roughness, Geometry, DIV_EPSILON};

/// The lobe's `(alpha_t, alpha_b)` for `roughness` and `anisotropy` in `[0, 1]`, as glTF's
/// `KHR_materials_anisotropy` defines them (its "Individual Lights" section):
/// `alpha_t = mix(alpha, 1, anisotropy^2)`, `alpha_b = alpha`, `alpha = roughness^2`
/// after the roughness clamp. `anisotropy = 0` gives the isotropic pair.
pub(crate) fn anisotropic_alphas(roughness: f64, anisotropy: f64) -> (f64, f64) {
    let alpha = alpha_from_roughness(roughness);
    let k = anisotropy.clamp(0.0, 1.0);
    let k2 = k * k;
    (alpha + (1.0 - alpha) * k2, alpha)
}

/// The roughness of the isotropic lobe that stands in for the pair's energy (its E rows,
/// `E_avg`, the term's `f_add`, the split sum's tables): the lobe of equal mean squared
/// slope, `alpha^2 = (alpha_t^2 + alpha_b^2) / 2`, roughness `sqrt(alpha)`. Of the
/// stand-ins measured, its loss `1 - E(v)` is the nearest to the stretched lobe's own
/// (docs/design/anisotropy.md, "Other equivalents"); engines take `sqrt(alpha_t alpha_b)`.
pub(crate) fn isotropic_roughness(alpha_t: f64, alpha_b: f64) -> f64 {
    (0.5 * (alpha_t * alpha_t + alpha_b * alpha_b))
        .sqrt()
        .sqrt()
}

/// The roughness of the isotropic lobe of the pair's solid angle, `alpha = sqrt(alpha_t
/// alpha_b)`, roughness `sqrt(alpha)`: the level the split sum reads the prefiltered map at
/// (the map blurred over as much of the sphere as the lobe covers).
pub(crate) fn equal_area_roughness(alpha_t: f64, alpha_b: f64) -> f64 {
    (alpha_t * alpha_b).max(0.0).sqrt().sqrt()
}

/// Anisotropic GGX (Heitz 2014, "Understanding the Masking-Shadowing Function in
/// Microfacet-Based BRDFs", JCGT 3(2), its anisotropic GGX): `D(h) = 1 / (pi alpha_t alpha_b ((h_x / alpha_t)^2 +
/// (h_y / alpha_b)^2 + h_z^2)^2)` for a unit local `h`; 0 below the horizon. Equals
/// [`super::d_ggx`] when `alpha_t = alpha_b`.
pub(crate) fn d_ggx_aniso(h: glam::DVec3, alpha_t: f64, alpha_b: f64) -> f64 {
    if h.z <= 0.0 {
        return 0.0;
    }
    let x = h.x / alpha_t;
    let y = h.y / alpha_b;
    let s = x * x + y * y + h.z * h.z;
    1.0 / (PI * alpha_t * alpha_b * s * s).max(DIV_EPSILON)
}

/// Smith's Lambda for anisotropic GGX (Heitz 2014, the same paper: GGX's Lambda with the
/// projected roughness
/// `alpha_o^2 = alpha_t^2 cos^2 phi + alpha_b^2 sin^2 phi`): `(-1 + sqrt(1 + a))/2`,
/// `a = (alpha_t^2 w_x^2 + alpha_b^2 w_y^2) / w_z^2`, written `a / (2 (1 + sqrt(1 + a)))`
/// against cancellation, as [`super::lambda_smith`]. `w_z <= 0` gives +infinity.
pub(crate) fn lambda_smith_aniso(w: glam::DVec3, alpha_t: f64, alpha_b: f64) -> f64 {
    let z2 = w.z.max(0.0) * w.z.max(0.0);
    if z2 <= 0.0 {
        return f64::INFINITY;
    }
    let a = (alpha_t * alpha_t * w.x * w.x + alpha_b * alpha_b * w.y * w.y) / z2;
    a / (2.0 * (1.0 + (1.0 + a).sqrt()))
}

/// The masking-shadowing term of `geometry` for the anisotropic lobe, local `o` and `i`:
/// height-correlated Smith `1 / (1 + Lambda(o) + Lambda(i))` (Heitz 2014, eq. 99, as
/// [`super::g_smith_correlated`]),
/// separable Smith `1 / ((1 + Lambda(o)) (1 + Lambda(i)))`, or Schlick-GGX at the
/// isotropic-equivalent roughness (Schlick's form has no anisotropic version).
pub(crate) fn g_aniso(
    o: glam::DVec3,
    i: glam::DVec3,
    alpha_t: f64,
    alpha_b: f64,
    g: Geometry,
) -> f64 {
    match g {
        Geometry::SmithCorrelated => {
            1.0 / (1.0
                + lambda_smith_aniso(o, alpha_t, alpha_b)
                + lambda_smith_aniso(i, alpha_t, alpha_b))
        }
        Geometry::Smith => {
            1.0 / ((1.0 + lambda_smith_aniso(o, alpha_t, alpha_b))
                * (1.0 + lambda_smith_aniso(i, alpha_t, alpha_b)))
        }
        Geometry::Schlick => super::g_schlick(o.z, i.z, isotropic_roughness(alpha_t, alpha_b)),
    }
}

/// The single-scattering Cook-Torrance BRDF of the anisotropic lobe, `F G D / (4 mu_i
/// mu_o)`, for local `o`, `i` and their unit half vector `h`; 0 below the horizon.
pub(crate) fn f_micro_aniso(
    fresnel: f64,
    o: glam::DVec3,
    i: glam::DVec3,
    h: glam::DVec3,
    (alpha_t, alpha_b): (f64, f64),
    geometry: Geometry,
) -> f64 {
    if o.z <= 0.0 || i.z <= 0.0 {
        return 0.0;
    }
    let d = d_ggx_aniso(h, alpha_t, alpha_b);
    let g = g_aniso(o, i, alpha_t, alpha_b, geometry);
    fresnel * g * d / (4.0 * i.z * o.z).max(DIV_EPSILON)
}

/// The ball's tangent field at unit normal `n` (relative to the ball's centre, world
/// space), turned by `rotation` radians about `n` (glTF's `anisotropyRotation`:
/// counter-clockwise from the tangent towards the bitangent): the tangent of the circle of
/// latitude about the world's vertical axis `+y`, as on a ball turned on a lathe,
/// `normalize(y x n)`, with the bitangent `n x t` along the meridian. At the poles, where
/// `y x n` vanishes (squared length at most [`DIV_EPSILON`]), the tangent is `+x`. Returns `(t, b)`.
pub(crate) fn ball_tangent(
    n: glam::DVec3,
    (cos_r, sin_r): (f64, f64),
) -> (glam::DVec3, glam::DVec3) {
    use glam::DVec3;
    let around = DVec3::new(n.z, 0.0, -n.x);
    let len2 = around.length_squared();
    let t0 = if len2 > DIV_EPSILON {
        around / len2.sqrt()
    } else {
        DVec3::X
    };
    let b0 = n.cross(t0);
    let t = cos_r * t0 + sin_r * b0;
    (t, n.cross(t))
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use glam::DVec3;

    use super::*;
    use crate::brdf::{d_ggx, lambda_smith};

    #[test]
    fn the_pair_is_gltfs_and_isotropic_at_zero() {
        let (t, b) = anisotropic_alphas(0.5, 0.0);
        assert_eq!((t, b), (0.25, 0.25));
        let (t, b) = anisotropic_alphas(0.5, 1.0);
        assert_eq!((t, b), (1.0, 0.25));
        let (t, _) = anisotropic_alphas(0.5, 0.5);
        assert!((t - (0.25 + 0.75 * 0.25)).abs() < 1e-15);
        assert!((isotropic_roughness(0.25, 0.25) - 0.5).abs() < 1e-15);
    }

    #[test]
    fn equal_alphas_give_the_isotropic_terms() {
        for alpha in [0.01, 0.2, 0.7] {
            for theta in [0.0f64, 0.3, 1.2] {
                let w = DVec3::new(theta.sin() * 0.6, theta.sin() * 0.8, theta.cos());
                let d = d_ggx_aniso(w, alpha, alpha);
                assert!((d - d_ggx(w.z, alpha)).abs() <= 1e-9 * d, "{alpha} {theta}");
                let l = lambda_smith_aniso(w, alpha, alpha);
                assert!(
                    (l - lambda_smith(w.z, alpha)).abs() <= 1e-12,
                    "{alpha} {theta}"
                );
            }
        }
    }

    #[test]
    fn anisotropic_ggx_is_normalised_over_projected_area() {
        // int D(h) h_z dw_h = 1: a midpoint rule in (u, phi), theta = atan(alpha_max tan u)
        // spreading the peak.
        for (at, ab) in [(0.3, 0.1), (1.0, 0.25), (0.05, 0.05)] {
            let n = 800;
            let amax = f64::max(at, ab);
            let mut total = 0.0;
            for i in 0..n {
                let u = (i as f64 + 0.5) / n as f64 * (PI / 2.0);
                let theta = (amax * u.tan()).atan();
                let dtheta = amax / (u.cos().powi(2) * (1.0 + (amax * u.tan()).powi(2)));
                for j in 0..n {
                    let phi = (j as f64 + 0.5) / n as f64 * 2.0 * PI;
                    let h = DVec3::new(
                        theta.sin() * phi.cos(),
                        theta.sin() * phi.sin(),
                        theta.cos(),
                    );
                    total += d_ggx_aniso(h, at, ab) * h.z * theta.sin() * dtheta;
                }
            }
            total *= (PI / 2.0) / n as f64 * 2.0 * PI / n as f64;
            assert!((total - 1.0).abs() < 2e-3, "({at}, {ab}): {total}");
        }
    }

    #[test]
    fn the_tangent_field_is_orthonormal_and_turns() {
        for n in [
            DVec3::new(0.3, 0.4, 0.866).normalize(),
            DVec3::Y,
            DVec3::new(-0.9, 0.1, 0.2).normalize(),
        ] {
            for r in [0.0, 0.7, PI] {
                let (t, b) = ball_tangent(n, (f64::cos(r), f64::sin(r)));
                assert!((t.length() - 1.0).abs() < 1e-12 && (b.length() - 1.0).abs() < 1e-12);
                assert!(t.dot(n).abs() < 1e-12 && b.dot(n).abs() < 1e-12 && t.dot(b).abs() < 1e-12);
                let (t0, _) = ball_tangent(n, (1.0, 0.0));
                assert!((t.dot(t0) - r.cos()).abs() < 1e-12, "turned by {r}");
            }
        }
        // Around the vertical axis: horizontal.
        let (t, _) = ball_tangent(DVec3::new(0.6, 0.0, 0.8), (1.0, 0.0));
        assert!(t.y.abs() < 1e-15);
    }
}
