//! The precise reference: E and E_avg in f64 to better than 1e-6 (tests check 1e-9 level
//! self-consistency, published values and an independent 2-D integration). Used by tests,
//! the benchmark and error reports, never at startup.

use super::integrand::EIntegrand;
use super::quadrature::adaptive;
use crate::brdf::Geometry;

/// Absolute tolerance of each adaptive integral of E.
pub(crate) const REFERENCE_TOL: f64 = 1e-11;

/// Precise `E(mu, roughness)` with `F = 1`.
pub fn e_reference(mu: f64, roughness: f64, geometry: Geometry) -> f64 {
    let f = EIntegrand::new(mu, roughness, geometry);
    f.segments()
        .map(|seg| adaptive(&|x| f.at_segment(&seg, x), seg.lo, seg.hi, REFERENCE_TOL))
        .sum()
}

/// Precise `E_avg(roughness) = 2 int_0^1 E(mu) mu dmu`, integrated in `x = sqrt(mu)`:
/// `E_avg = 4 int_0^1 E(x^2) x^3 dx` (the same axis the default table uses, where E is
/// smoother).
pub fn e_avg_reference(roughness: f64, geometry: Geometry) -> f64 {
    adaptive(
        &|x: f64| 4.0 * x * x * x * e_reference(x * x, roughness, geometry),
        0.0,
        1.0,
        1e-10,
    )
}
