//! E(mu_o) as a one-dimensional integral: the azimuth is integrated in closed form.
//!
//! ## Derivation
//!
//! With `F = 1`, `E(mu_o) = int f_micro mu_i dw_i = int D G / (4 mu_o) dmu_i dphi`, because
//! `f_micro mu_i = D G / (4 mu_o)` and `dw_i = dmu_i dphi`. All three G variants depend on
//! `(mu_o, mu_i)` only, so the azimuth enters through D alone:
//!
//! ```text
//! E(mu_o) = 1 / (4 mu_o) int_0^1 G(mu_o, mu_i) Phi(mu_o, mu_i) dmu_i,
//! Phi     = int_0^{2 pi} D(h(phi)) dphi.
//! ```
//!
//! Put `o = (s_o, 0, c_o)`, `i = (s_i cos phi, s_i sin phi, c_i)`, `P = (c_o + c_i)^2`.
//! Then `(n.h)^2 = P / (2 (1 + o.i))` and, with `b = 2 s_o s_i`,
//!
//! ```text
//! D = alpha^2 / pi * ((e + b cos phi) / (a + b cos phi))^2,
//! e = 2 + 2 c_o c_i,    a = P alpha^2 + s_o^2 + s_i^2,    e - a = P (1 - alpha^2).
//! ```
//!
//! Writing the ratio as `1 + (e - a) / (a + b cos phi)` and using
//! `int_0^{2pi} dphi / (a + b cos phi) = 2 pi / R` and
//! `int_0^{2pi} dphi / (a + b cos phi)^2 = 2 pi a / R^3`, `R = sqrt(a^2 - b^2)`:
//!
//! ```text
//! Phi = 2 alpha^2 (1 + 2 (e - a) / R + (e - a)^2 a / R^3).
//! ```
//!
//! `a - b = P alpha^2 + (s_o - s_i)^2` and `a + b = P alpha^2 + (s_o + s_i)^2` are sums of
//! non-negative terms, so `R` keeps full precision at the mirror direction, where the
//! textbook form `(a - b)` would cancel to `4 alpha^2 c^2`. Check: `alpha = 1` gives D = 1/pi
//! and `Phi = 2`.
//!
//! The remaining integrand is peaked at `theta_i = theta_o` with an angular width of about
//! `2 alpha`, and has a `1 / d^2` tail in the distance `d = |theta_i - theta_o|`.
//! [`EIntegrand::segments`] splits `[0, pi/2]` at the peak and, on each side, maps
//! - the peak, `d` in `[0, PEAK_SPAN * w]`, by `d = w tan t` (`w = PEAK_WIDTH_PER_ALPHA
//!   alpha`), which turns GGX's `1 / (w^2 + d^2)^2` shape into a smooth `cos^2 t`;
//! - the tail, out to the end of the range, by `d = exp(s)`, which makes the `1 / d^2` tail
//!   smooth and keeps the cut-off at `theta_i = 0` (the `sin theta_i` factor) or at the
//!   horizon (`G1(mu_i) -> 0`) spread over a fair share of the nodes. Mapping the whole side
//!   by `tan` would squeeze the tail, and that cut-off, into the last `w / theta_o` of `t`:
//!   a near-jump that no fixed rule integrates (measured: 2e-4 error at 64 nodes for
//!   roughness 0.02, mu = 1e-4).
//!
//! With height-correlated Smith G, `G = 1 / (1 + L(mu_o) + L(mu_i))` changes with mu_i
//! on the scale of mu_o: at grazing that is a feature near the peak far narrower than it,
//! and the peak segment towards the normal is split at `d = GRAZING_SPLIT mu_o` (measured
//! in the unit tests of lut/chebyshev.rs: at mu = 4.5e-4, roughness 1, 24 nodes a segment go
//! from 1.8e-4 to 8.5e-6 error).
//!
//! Each segment is smooth in its variable, so a few Gauss-Legendre nodes integrate it to
//! 1e-6 and better.

use std::f64::consts::FRAC_PI_2;

use crate::brdf::{alpha_from_roughness, Geometry};

/// Smallest `mu_o` at which E is evaluated: `E(0)` is defined as the limit, and the
/// integrand's `G / mu_o` is finite there but `0 / 0` when evaluated literally.
/// Near 0, E is linear in mu with a slope of up to about 2.4e3 (Schlick G, roughness 0.02:
/// E(1e-6) is 2.4e-3 below E(1e-12)), so 1e-12 moves E by less than 1e-8; f64 evaluates the
/// integrand there without loss (tested).
pub(crate) const MU_MIN: f64 = 1e-12;

/// Width `w` of the substitution `d = w tan t` over the peak, in units of alpha.
pub(crate) const PEAK_WIDTH_PER_ALPHA: f64 = 2.0;

/// The peak segment reaches `d = PEAK_SPAN * w` (`t` up to `atan(4)`, 76 degrees).
pub(crate) const PEAK_SPAN: f64 = 4.0;

/// With height-correlated Smith G, the side towards the normal is split at
/// `d = GRAZING_SPLIT * mu_o` when that is within half the peak segment (see `segments`).
pub(crate) const GRAZING_SPLIT: f64 = 8.0;

/// How a segment's variable maps to the distance `d` from the peak.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Mapping {
    /// `d = w tan x`.
    Tan,
    /// `d = exp(x)`.
    Log,
}

/// One piece of the `theta_i` range: `theta_i = theta_o + sign d(x)`, `x` in `[lo, hi]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Segment {
    /// `1` on the side towards the horizon (`theta_i > theta_o`), `-1` towards the normal.
    pub sign: f64,
    /// How `x` maps to `d`.
    pub mapping: Mapping,
    /// Start of the range of `x`.
    pub lo: f64,
    /// End of the range of `x`.
    pub hi: f64,
}

/// `Phi(mu_o, mu_i) = int_0^{2pi} D dphi` (see the module docs).
pub fn phi_integral(mu_o: f64, s_o: f64, mu_i: f64, s_i: f64, alpha: f64) -> f64 {
    let a2 = alpha * alpha;
    let p = (mu_o + mu_i) * (mu_o + mu_i);
    let pa = p * a2;
    let diff = s_o - s_i;
    let sum = s_o + s_i;
    let a_minus_b = pa + diff * diff;
    let a_plus_b = pa + sum * sum;
    let a = pa + s_o * s_o + s_i * s_i;
    let r = (a_minus_b * a_plus_b).sqrt();
    if r <= 0.0 {
        // Only at alpha = 0 and mu_o = mu_i = 0 (both grazing): no finite lobe.
        return 0.0;
    }
    let ea = p * (1.0 - a2);
    let q = ea / r;
    2.0 * a2 * (1.0 + 2.0 * q + q * q * a / r)
}

/// The E integrand over `theta_i` (includes the `sin theta_i` Jacobian of `dmu_i`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct EIntegrand {
    /// mu of the outgoing direction, clamped to `[MU_MIN, 1]`.
    pub mu_o: f64,
    s_o: f64,
    /// Angle of the outgoing direction to the normal, `acos(mu_o)`, in radians: the peak.
    pub theta_o: f64,
    /// Roughness as given (G clamps it).
    pub roughness: f64,
    /// `alpha = roughness^2` after the roughness clamp.
    pub alpha: f64,
    /// The masking-shadowing term.
    pub geometry: Geometry,
}

impl EIntegrand {
    /// The integrand of `E(mu_o, roughness)` for `geometry`; `mu_o` is clamped to
    /// `[MU_MIN, 1]`.
    pub(crate) fn new(mu_o: f64, roughness: f64, geometry: Geometry) -> Self {
        let mu_o = mu_o.clamp(MU_MIN, 1.0);
        Self {
            mu_o,
            s_o: (1.0 - mu_o * mu_o).max(0.0).sqrt(),
            theta_o: mu_o.acos(),
            roughness,
            alpha: alpha_from_roughness(roughness),
            geometry,
        }
    }

    /// `G Phi sin(theta_i) / (4 mu_o)`, the integrand of E over `theta_i` in `[0, pi/2]`.
    pub(crate) fn at_theta(&self, theta_i: f64) -> f64 {
        let (s_i, mu_i) = theta_i.sin_cos();
        if mu_i <= 0.0 {
            return 0.0;
        }
        let g = self.geometry.g(self.mu_o, mu_i, self.roughness);
        g * phi_integral(self.mu_o, self.s_o, mu_i, s_i, self.alpha) * s_i / (4.0 * self.mu_o)
    }

    /// The pieces of `[0, pi/2]` in their mapped variables (see the module docs): up to
    /// four (five with height-correlated G at grazing, `GRAZING_SPLIT`), each integrated over `[seg.lo, seg.hi]` by [`EIntegrand::at_segment`]. An
    /// iterator, not a vector: the bake asks for them once per texel.
    pub(crate) fn segments(&self) -> impl Iterator<Item = Segment> {
        let w = self.width();
        let (mu_o, correlated) = (self.mu_o, self.geometry == Geometry::SmithCorrelated);
        // (sign, distance to the end of the range) for the side towards the horizon and
        // the side towards the normal.
        [(1.0, FRAC_PI_2 - self.theta_o), (-1.0, self.theta_o)]
            .into_iter()
            .filter(|&(_, reach)| reach > 0.0)
            .flat_map(move |(sign, reach)| {
                let peak = reach.min(PEAK_SPAN * w);
                // Height-correlated G couples mu_i to mu_o: towards the normal it changes
                // over d ~ mu_o, a feature far narrower than the peak when mu_o is small.
                let split = GRAZING_SPLIT * mu_o;
                let coupled = correlated && sign < 0.0 && split < 0.5 * peak;
                let first = if coupled { split } else { peak };
                let near = Segment {
                    sign,
                    mapping: Mapping::Tan,
                    lo: 0.0,
                    hi: (first / w).atan(),
                };
                let rest = coupled.then(|| Segment {
                    sign,
                    mapping: Mapping::Tan,
                    lo: (first / w).atan(),
                    hi: (peak / w).atan(),
                });
                let log = (reach > peak).then(|| Segment {
                    sign,
                    mapping: Mapping::Log,
                    lo: peak.ln(),
                    hi: reach.ln(),
                });
                std::iter::once(near).chain(rest).chain(log)
            })
    }

    /// The integrand in a segment's variable `x` (Jacobian included).
    pub(crate) fn at_segment(&self, seg: &Segment, x: f64) -> f64 {
        let (theta_i, jacobian) = self.theta_at_segment(seg, x);
        self.at_theta(theta_i) * jacobian
    }

    /// `theta_i` at a segment's variable `x`, and `d theta_i / dx`.
    pub(crate) fn theta_at_segment(&self, seg: &Segment, x: f64) -> (f64, f64) {
        let (d, jacobian) = match seg.mapping {
            Mapping::Tan => {
                let w = self.width();
                let (s, c) = x.sin_cos();
                (w * s / c, w / (c * c))
            }
            Mapping::Log => {
                let d = x.exp();
                (d, d)
            }
        };
        (self.theta_o + seg.sign * d, jacobian)
    }

    fn width(&self) -> f64 {
        PEAK_WIDTH_PER_ALPHA * self.alpha
    }
}
