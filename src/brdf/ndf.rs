//! The normal distribution function.

use std::f64::consts::PI;

use super::DIV_EPSILON;

/// GGX / Trowbridge-Reitz NDF (Walter et al. 2007, "Microfacet Models for Refraction
/// through Rough Surfaces", eq. 33):
/// `D(h) = alpha^2 / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2)`.
///
/// `1 - (n.h)^2` is formed before the product so that the denominator keeps its precision
/// near the mirror direction (`n.h -> 1`), where `(n.h)^2 (alpha^2 - 1) + 1` would cancel.
pub fn d_ggx(n_dot_h: f64, alpha: f64) -> f64 {
    if n_dot_h <= 0.0 {
        return 0.0;
    }
    let c2 = (n_dot_h * n_dot_h).min(1.0);
    let a2 = alpha * alpha;
    let s2 = 1.0 - c2;
    // denom >= alpha^2 for n.h in (0, 1]; it reaches 0 only for alpha = 0 at the mirror
    // direction, where the guard turns 0/0 into 0.
    let denom = (c2 * a2 + s2).max(DIV_EPSILON);
    a2 / (PI * denom * denom)
}
