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
pub fn d_ggx(n_dot_h: f64, alpha: f64) -> f64 {
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
