//! The random walk on the microsurface (Heitz, Hanika, d'Eon and Dachsbacher 2016,
//! "Multiple-Scattering Microfacet BSDFs with the Smith Model"): the exact
//! multiple-scattering BRDF of a GGX conductor with height-correlated Smith masking, the
//! truth the models are measured against. The library's part: the microsurface
//! ([`microsurface`]), one path at a time ([`trace`]), its seeded generator ([`rng`]) and
//! the exact single scattering by quadrature ([`single`]), and the walk through a rough
//! dielectric coating over a Lambertian base (`coating`, the truth for plastics); the truth renderer
//! (`cpu::render_truth`) and the study (`shadeballs-lab truth`, feature `lab`) build on it.
//!
//! Variance reduction (unbiased, so the expectation is the paper's walk): an upward ray
//! does not draw "escape or hit"; it deposits its escape probability `G1` times the path
//! weight and always continues with the weight scaled by `1 - G1`, down to a Russian
//! roulette.

pub(crate) mod clearcoat;
pub(crate) mod coating;
pub mod microsurface;
pub mod rng;
pub mod single;
#[cfg(all(test, feature = "cli"))]
mod tests;

use glam::DVec3;

use crate::brdf::f_schlick;
use microsurface::{reflect, Microsurface};
pub use rng::Rng;

/// A colour channel's Fresnel reflectance as a function of the cosine between the
/// incident direction and the microfacet normal.
pub trait Reflectance {
    /// Reflectance at cosine `cos`.
    fn eval(&self, cos: f64) -> f64;
}

/// The exact Fresnel of a dielectric interface of this relative index (`n_t / n_i`;
/// [`crate::brdf::fresnel_dielectric`]).
#[cfg(test)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Dielectric(pub f64);

#[cfg(test)]
impl Reflectance for Dielectric {
    fn eval(&self, cos: f64) -> f64 {
        crate::brdf::fresnel_dielectric(cos, self.0)
    }
}

/// Schlick's approximation with this `F0` (what the renderer's `f_micro` uses).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Schlick(pub f64);

impl Reflectance for Schlick {
    fn eval(&self, cos: f64) -> f64 {
        f_schlick(self.0, cos)
    }
}

/// Most colour channels one walk carries (each path's Fresnel weights live on the stack).
pub const MAX_CHANNELS: usize = 16;

/// Below this common weight a path plays Russian roulette: it survives with probability
/// `weight / RR_BELOW` and then carries `RR_BELOW`.
pub(crate) const RR_BELOW: f64 = 0.05;

/// Scattering events after which a path is cut (and counted): never reached in practice,
/// a guard against a walk stuck at the bottom of the surface.
pub const MAX_ORDER: u32 = 10_000;

/// One path, one event at a time. `on_escape(order, dir, mass, weights)`: an upward ray
/// along `dir` leaves with probability mass `mass` after `order` scattering events; `weights` are the
/// per-channel Fresnel products so far. `on_event(order, wi_k, c, carry, weights)`: the
/// `order`-th scattering event at height `c`, `wi_k` pointing back along the arriving ray,
/// `carry` the probability mass that reached it, `weights` before this event's Fresnel.
/// A path ends after `limit` events (`u32::MAX`: never, short of [`MAX_ORDER`]); returns
/// false if it was cut at [`MAX_ORDER`].
pub fn trace<F: Reflectance>(
    s: &Microsurface,
    wi: DVec3,
    channels: &[F],
    limit: u32,
    rng: &mut Rng,
    mut on_escape: impl FnMut(u32, DVec3, f64, &[f64]),
    mut on_event: impl FnMut(u32, DVec3, f64, f64, &[f64]),
) -> bool {
    let n = channels.len();
    let mut w = [1.0; MAX_CHANNELS];
    let mut dir = -wi;
    let mut c = 1.0;
    let mut carry = 1.0;
    let mut order = 0u32;
    loop {
        if dir.z > 0.0 {
            let escape = s.g1(dir, c);
            on_escape(order, dir, carry * escape, &w[..n]);
            carry *= 1.0 - escape;
            if carry <= 0.0 {
                return true;
            }
        }
        if order >= limit {
            return true;
        }
        c = s.next_height(dir, c, rng.uniform());
        order += 1;
        if order > MAX_ORDER {
            return false;
        }
        let wi_k = -dir;
        on_event(order, wi_k, c, carry, &w[..n]);
        let m = s.sample_visible_normal(wi_k, rng.uniform(), rng.uniform());
        let cos = wi_k.dot(m).max(0.0);
        for (wk, f) in w.iter_mut().zip(channels) {
            *wk *= f.eval(cos);
        }
        dir = reflect(dir, m);
        if carry < RR_BELOW {
            if rng.uniform() * RR_BELOW < carry {
                carry = RR_BELOW;
            } else {
                return true;
            }
        }
    }
}

/// The incident direction of cosine `mu` in the xz plane, `x <= 0` (so the mirror
/// direction has `x >= 0`).
pub fn incident(mu: f64) -> DVec3 {
    let mu = mu.clamp(0.0, 1.0);
    DVec3::new(-(1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu)
}
