//! Single scattering by deterministic quadrature: the directional albedo of `f_micro` with
//! a per-channel Fresnel, for any G, without Monte Carlo noise.
//!
//! `E_F(mu_o) = int_0^{pi/2} G(mu_o, mu_i) Phi_F(theta_i) sin(theta_i) / (4 mu_o) dtheta_i`
//! with `Phi_F = int_0^{2 pi} F(o.h) D(h) dphi`. The outer integral uses the baker's
//! segments of `theta_i` (`lut::EIntegrand::segments`: the GGX peak mapped by `tan`, the
//! tails by `exp`; the horizon is an end point, where G falls to 0). With `F = 1`, `Phi_F`
//! has a closed form (`lut::phi_integral`); with a Fresnel factor it is integrated here:
//! `D` depends on `phi` through `(e + b cos phi) / (a + b cos phi)` (see `src/lut/integrand.rs`),
//! peaked at `phi = pi` with half width `w = sqrt(2 (a - b) / b)`: `phi = pi - w tan t`
//! turns the peak into a smooth `cos^2 t` and `phi = pi - exp(s)` flattens the tail, each
//! integrated with Gauss-Legendre (the baker's split, in the azimuth). Tests
//! hold both parts to the closed forms and to `lut::e_reference`.

use glam::DVec3;

use super::Reflectance;
use crate::brdf::{alpha_from_roughness, d_ggx, Geometry};
use crate::lut::{gauss_legendre_unit, EIntegrand, Mapping, PEAK_WIDTH_PER_ALPHA};

/// Gauss-Legendre nodes per `theta_i` segment.
pub(crate) const THETA_NODES: usize = 48;
/// Gauss-Legendre nodes per segment of the azimuth.
pub(crate) const PHI_NODES: usize = 48;

/// The azimuth's peak segment reaches `PHI_PEAK_SPAN` half widths; the rest is mapped by
/// `exp` (as the baker splits `theta_i`).
const PHI_PEAK_SPAN: f64 = 4.0;

/// The fixed rules, built once.
pub struct Rules {
    theta: (Vec<f64>, Vec<f64>),
    phi: (Vec<f64>, Vec<f64>),
}

impl Default for Rules {
    fn default() -> Self {
        Self {
            theta: gauss_legendre_unit(THETA_NODES),
            phi: gauss_legendre_unit(PHI_NODES),
        }
    }
}

/// `Phi_F[k] = int_0^{2 pi} F_k(o.h) D(h) dphi` for `o = (s_o, 0, mu_o)` and incident polar
/// angle of sine/cosine `(s_i, mu_i)`, added into `out` times `scale`.
pub fn phi_fresnel(
    rules: &Rules,
    (s_o, mu_o): (f64, f64),
    (s_i, mu_i): (f64, f64),
    alpha: f64,
    channels: &[impl Reflectance],
    scale: f64,
    out: &mut [f64],
) {
    let o = DVec3::new(s_o, 0.0, mu_o);
    let p = (mu_o + mu_i) * (mu_o + mu_i);
    let a_minus_b = p * alpha * alpha + (s_o - s_i) * (s_o - s_i);
    let b = 2.0 * s_o * s_i;
    // Half width of the peak at phi = pi; with b = 0 (o or i normal) D is constant in phi.
    let w = if b > 0.0 {
        (2.0 * a_minus_b / b).sqrt().max(1e-300)
    } else {
        1.0
    };
    let pi = std::f64::consts::PI;
    let peak = pi.min(PHI_PEAK_SPAN * w);
    let (x, wx) = &rules.phi;
    // (delta, d delta / d node) over the peak (`w tan t`) and the tail (`exp s`).
    let t_max = (peak / w).atan();
    let tail = (peak < pi).then(|| (peak.ln(), pi.ln()));
    let nodes = x.iter().zip(wx).flat_map(|(xk, wk)| {
        let t = xk * t_max;
        let (st, ct) = t.sin_cos();
        let head = (w * st / ct, wk * t_max * w / (ct * ct));
        let rest = tail.map(|(lo, hi)| {
            let d = (lo + (hi - lo) * xk).exp();
            (d, wk * (hi - lo) * d)
        });
        std::iter::once(head).chain(rest)
    });
    for (delta, dd) in nodes {
        // phi = pi - delta, and the mirror half pi + delta: twice the half range.
        let phi = pi - delta;
        let i = DVec3::new(s_i * phi.cos(), s_i * phi.sin(), mu_i);
        let sum = o + i;
        let len = sum.length();
        if len <= 0.0 {
            continue;
        }
        let h = sum / len;
        let d = d_ggx(h.z, alpha) * 2.0 * dd * scale;
        let cos = o.dot(h);
        for (acc, f) in out.iter_mut().zip(channels) {
            *acc += d * f.eval(cos);
        }
    }
}

/// `int f_micro(F_k, G) mu_i dw_i` at `mu_o` and `roughness`, for every geometry term in
/// `geometries` (outer index) and every channel in `channels` (inner index).
pub fn single_albedo(
    rules: &Rules,
    mu_o: f64,
    roughness: f64,
    channels: &[impl Reflectance],
    geometries: &[Geometry],
) -> Vec<Vec<f64>> {
    let integrand = EIntegrand::new(mu_o, roughness, Geometry::SmithCorrelated);
    let mu_o = integrand.mu_o;
    let s_o = (1.0 - mu_o * mu_o).max(0.0).sqrt();
    let alpha = alpha_from_roughness(roughness);
    let width = PEAK_WIDTH_PER_ALPHA * alpha;
    let mut sums = vec![vec![0.0; channels.len()]; geometries.len()];
    let mut phi = vec![0.0; channels.len()];
    let (x, wx) = &rules.theta;
    for seg in integrand.segments() {
        for (xk, wk) in x.iter().zip(wx) {
            let u = seg.lo + (seg.hi - seg.lo) * xk;
            let (d, jac) = match seg.mapping {
                Mapping::Tan => {
                    let (s, c) = u.sin_cos();
                    (width * s / c, width / (c * c))
                }
                Mapping::Log => (u.exp(), u.exp()),
            };
            let theta_i = integrand.theta_o + seg.sign * d;
            let (s_i, mu_i) = theta_i.sin_cos();
            if mu_i <= 0.0 || s_i < 0.0 {
                continue;
            }
            phi.fill(0.0);
            let weight = wk * (seg.hi - seg.lo) * jac * s_i / (4.0 * mu_o);
            phi_fresnel(
                rules,
                (s_o, mu_o),
                (s_i, mu_i),
                alpha,
                channels,
                weight,
                &mut phi,
            );
            for (sum, g) in sums.iter_mut().zip(geometries) {
                let gv = g.g(mu_o, mu_i, roughness);
                for (s, p) in sum.iter_mut().zip(&phi) {
                    *s += gv * p;
                }
            }
        }
    }
    sums
}
