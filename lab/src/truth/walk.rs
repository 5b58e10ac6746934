//! The random walk on the microsurface (Heitz, Hanika, d'Eon and Dachsbacher 2016): the
//! exact multiple-scattering BRDF of a GGX conductor with height-correlated Smith masking.
//!
//! A path enters along `-wi` from above, alternates "next intersection height" and
//! "reflect off a visible microfacet" (the phase function), and leaves when an upward ray
//! escapes. Two estimators ride on the same paths:
//! - *escape* ([`albedo`]): the energy that leaves, per scattering order, which is the
//!   directional albedo;
//! - *next-event* ([`lobe`]): at every scattering event, the phase function towards a fixed
//!   outgoing direction `wo` times the probability `G1(wo, h)` that `wo` escapes from that
//!   height (Heitz et al. 2016's evaluation), which is `f(wi, wo) wo.z`.
//!
//! Variance reduction (unbiased, so the expectation is the paper's walk): an upward ray
//! does not draw "escape or hit"; it deposits its escape probability `G1` times the path
//! weight and always continues with the weight scaled by `1 - G1`, down to a Russian
//! roulette. With `F = 1` every path's deposits sum to (nearly) 1, so the white albedo has
//! almost no noise; the tests check it with the independent next-event estimator instead.

use glam::DVec3;

use super::estimate::{chunked, Stat};
use super::fresnel::Fresnel;
use shadeballs::walk::microsurface::Microsurface;
use shadeballs::walk::Rng;
pub use shadeballs::walk::{incident, trace, MAX_CHANNELS, MAX_ORDER};

/// Directional albedo per channel, split into single scattering (order 1) and multiple
/// scattering (order >= 2).
#[derive(Clone, Debug, Default)]
pub struct Albedo {
    pub single: Vec<Stat>,
    pub multiple: Vec<Stat>,
    /// Paths cut at [`MAX_ORDER`].
    pub truncated: u64,
}

impl Albedo {
    fn new(n: usize) -> Self {
        Self {
            single: vec![Stat::default(); n],
            multiple: vec![Stat::default(); n],
            truncated: 0,
        }
    }
    fn merge(mut self, o: Albedo) -> Self {
        for (a, b) in self.single.iter_mut().zip(&o.single) {
            a.merge(b);
        }
        for (a, b) in self.multiple.iter_mut().zip(&o.multiple) {
            a.merge(b);
        }
        self.truncated += o.truncated;
        self
    }
}

/// Directional albedo of the walk at incidence cosine `mu` with `paths` paths.
pub fn albedo(
    s: &Microsurface,
    mu: f64,
    channels: &[Fresnel],
    paths: usize,
    seed: &[u64],
) -> Albedo {
    assert!(channels.len() <= MAX_CHANNELS, "too many channels");
    let n = channels.len();
    let wi = incident(mu);
    let run = |rng: &mut Rng, count: usize| {
        let mut out = Albedo::new(n);
        let mut single = [0.0; MAX_CHANNELS];
        let mut multiple = [0.0; MAX_CHANNELS];
        for _ in 0..count {
            single[..n].fill(0.0);
            multiple[..n].fill(0.0);
            let done = trace(
                s,
                wi,
                channels,
                u32::MAX,
                rng,
                |order, _, mass, w| {
                    let acc = if order <= 1 {
                        &mut single
                    } else {
                        &mut multiple
                    };
                    for (a, wk) in acc.iter_mut().zip(w) {
                        *a += mass * wk;
                    }
                },
                |_, _, _, _, _| {},
            );
            out.truncated += u64::from(!done);
            for k in 0..n {
                out.single[k].add(single[k]);
                out.multiple[k].add(multiple[k]);
            }
        }
        out
    };
    chunked(paths, seed, run, Albedo::merge).unwrap_or_else(|| Albedo::new(n))
}

/// `f(wi, wo) wo.z` per outgoing direction and channel, split by scattering order like
/// [`Albedo`]; index `[j * channels + k]` for direction `j`, channel `k`.
pub type Lobe = Albedo;

/// Next-event estimate of `f(wi, wo) wo.z` for every `wo` in `outgoing` (all with
/// `wo.z > 0`), from the same `paths` paths.
pub fn lobe(
    s: &Microsurface,
    wi: DVec3,
    outgoing: &[DVec3],
    channels: &[Fresnel],
    paths: usize,
    seed: &[u64],
) -> Lobe {
    assert!(channels.len() <= MAX_CHANNELS, "too many channels");
    let n = channels.len();
    let size = outgoing.len() * n;
    // Lambda of each outgoing direction, once.
    let lambdas: Vec<f64> = outgoing.iter().map(|wo| s.lambda(*wo)).collect();
    let run = |rng: &mut Rng, count: usize| {
        let mut out = Albedo::new(size);
        let mut single = vec![0.0; size];
        let mut multiple = vec![0.0; size];
        for _ in 0..count {
            single.fill(0.0);
            multiple.fill(0.0);
            let done = trace(
                s,
                wi,
                channels,
                u32::MAX,
                rng,
                |_, _, _, _| {},
                |order, wi_k, c, carry, w| {
                    let acc = if order <= 1 {
                        &mut single
                    } else {
                        &mut multiple
                    };
                    for (j, (wo, lambda)) in outgoing.iter().zip(&lambdas).enumerate() {
                        let (p, cos) = s.phase(wi_k, *wo);
                        if p <= 0.0 {
                            continue;
                        }
                        let base = carry * p * c.powf(*lambda);
                        for (k, f) in channels.iter().enumerate() {
                            acc[j * n + k] += base * w[k] * f.eval(cos);
                        }
                    }
                },
            );
            out.truncated += u64::from(!done);
            for i in 0..size {
                out.single[i].add(single[i]);
                out.multiple[i].add(multiple[i]);
            }
        }
        out
    };
    chunked(paths, seed, run, Albedo::merge).unwrap_or_else(|| Albedo::new(size))
}

/// The directional albedo by next-event estimation instead of escape: every path's
/// next-event estimates of `f(wi, wo) wo.z` summed over the quadrature `(wo_j, weight_j)` of
/// the hemisphere. An estimator independent of [`albedo`] (the tests check that with
/// `F = 1` it gives 1).
pub fn albedo_next_event(
    s: &Microsurface,
    mu: f64,
    rule: &[(DVec3, f64)],
    channel: Fresnel,
    paths: usize,
    seed: &[u64],
) -> Stat {
    let wi = incident(mu);
    let lambdas: Vec<f64> = rule.iter().map(|(wo, _)| s.lambda(*wo)).collect();
    let run = |rng: &mut Rng, count: usize| {
        let mut out = Stat::default();
        for _ in 0..count {
            let mut total = 0.0;
            trace(
                s,
                wi,
                &[channel],
                u32::MAX,
                rng,
                |_, _, _, _| {},
                |_, wi_k, c, carry, w| {
                    for ((wo, weight), lambda) in rule.iter().zip(&lambdas) {
                        let (p, cos) = s.phase(wi_k, *wo);
                        if p > 0.0 {
                            total +=
                                weight * carry * p * c.powf(*lambda) * w[0] * channel.eval(cos);
                        }
                    }
                },
            );
            out.add(total);
        }
        out
    };
    chunked(paths, seed, run, |mut a, b| {
        a.merge(&b);
        a
    })
    .unwrap_or_default()
}
