//! The normal distribution function.

use std::f64::consts::PI;

use super::DIV_EPSILON;

/// GGX / Trowbridge-Reitz NDF (Walter et al. 2007, "Microfacet Models for Refraction
/// through Rough Surfaces", eq. 33):
/// `D(h) = alpha^2 / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2)`.
///
/// `1 - (n.h)^2` is formed before the product so that the denominator keeps its precision
/// near the mirror direction (`n.h -> 1`), where `(n.h)^2 (alpha^2 - 1) + 1` would cancel;
/// and as `(1 - n.h)(1 + n.h)`, where `1 - n.h` is exact: `1 - (n.h)^2` would inherit the
/// rounding of the square, which in f32 is 6e-8, a third of the denominator's
/// `alpha^2 = 1.6e-7` at the roughness clamp (measured in the shader: 1.7e-4 relative
/// error in D near the peak before, see docs/reliability.md "Reliability").
pub(crate) fn d_ggx(n_dot_h: f64, alpha: f64) -> f64 {
    if n_dot_h <= 0.0 {
        return 0.0;
    }
    let c = n_dot_h.min(1.0);
    let c2 = c * c;
    let a2 = alpha * alpha;
    let s2 = (1.0 - c) * (1.0 + c);
    // denom >= alpha^2 for n.h in (0, 1]; it reaches 0 only for alpha = 0 at the mirror
    // direction, where the guard turns 0/0 into 0.
    let denom = (c2 * a2 + s2).max(DIV_EPSILON);
    a2 / (PI * denom * denom)
}

/// A microfacet normal of GGX drawn from the distribution of normals visible from `wi`
/// (Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4)), at the
/// point `(p1, p2)` of the unit disk: stretch `wi` to `alpha = 1`, warp the disk onto the
/// projected visible hemisphere (`p2 -> (1 - s) sqrt(1 - p1^2) + s p2`, `s = (1 + z) / 2`),
/// lift it and unstretch. The walk draws the disk point at random; the coating's tables
/// (`lut::coating`) take it from a quadrature rule.
pub(crate) fn visible_normal(alpha: f64, wi: glam::DVec3, p1: f64, p2: f64) -> glam::DVec3 {
    visible_normal_aniso((alpha, alpha), wi, p1, p2)
}

/// [`visible_normal`] of anisotropic GGX (`alpha_t` along local `x`, `alpha_b` along `y`):
/// the same construction with the stretch `(alpha_t, alpha_b)` (Heitz 2018, as Heitz et
/// al. 2016 stretch the walk's microsurface).
pub(crate) fn visible_normal_aniso(
    (alpha_t, alpha_b): (f64, f64),
    wi: glam::DVec3,
    p1: f64,
    p2: f64,
) -> glam::DVec3 {
    use glam::DVec3;
    let vh = DVec3::new(alpha_t * wi.x, alpha_b * wi.y, wi.z).normalize();
    let lensq = vh.x * vh.x + vh.y * vh.y;
    let t1 = if lensq > 0.0 {
        DVec3::new(-vh.y, vh.x, 0.0) / lensq.sqrt()
    } else {
        DVec3::X
    };
    let t2 = vh.cross(t1);
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * p2;
    let lift = (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
    let nh = p1 * t1 + p2 * t2 + lift * vh;
    DVec3::new(alpha_t * nh.x, alpha_b * nh.y, nh.z.max(0.0)).normalize()
}
