//! The random walk through a rough dielectric coating over a Lambertian base: the truth
//! for plastics. The interface is the dielectric microsurface of Heitz, Hanika, d'Eon and
//! Dachsbacher 2016 ("Multiple-Scattering Microfacet BSDFs with the Smith Model", section
//! 5): at each scattering event a microfacet normal is drawn from the normals visible from
//! the arriving direction, the path reflects with probability `F(i.m)` (exact dielectric
//! Fresnel, [`fresnel_dielectric`]) and refracts otherwise. Below the interface lies a
//! non-absorbing medium of index `eta` (relative to the outside) and, at its bottom, a
//! Lambertian base of albedo `rho` per channel. Light inside is reflected back by the
//! interface again and again (total internal reflection included), reaching the base each
//! time; only Russian roulette ends a path early, so a lossless coating over a white base
//! reflects everything.
//!
//! Frames: the walk works in the frame of the side the path is on, with `+z` pointing away
//! from the other medium (outside: the macro normal; inside: down, towards the base) and
//! `c = C1(h)` the height in that frame. Crossing the interface flips the frame: the height
//! becomes `1 - c` (the height's distribution function seen from the other side) and the
//! direction is negated. The interface's statistics (GGX slopes, Smith's
//! uncorrelated-heights-and-normals) are the same from either side.

use glam::DVec3;

use super::microsurface::{reflect, Microsurface};
use super::rng::Rng;
use super::{MAX_CHANNELS, MAX_ORDER, RR_BELOW};
#[cfg(test)]
use crate::brdf::f_avg_dielectric;
use crate::brdf::{d_ggx, fresnel_dielectric, DIV_EPSILON};

/// A rough dielectric interface of relative index `eta` over a Lambertian base.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Coating {
    /// The interface's microsurface (its roughness).
    pub surface: Microsurface,
    /// The coating medium's index over the outside's (`> 0`; 1 is no interface at all).
    pub eta: f64,
}

/// What a walk reports as it goes ([`Coating::walk`]); each method ignores it by default.
pub(crate) trait Visit {
    /// The path leaves upward along `dir` (outside frame) after `order` interface events,
    /// with per-channel `weights`.
    fn exit(&mut self, _order: u32, _dir: DVec3, _weights: &[f64]) {}
    /// An interface event, `weights` before it.
    fn event(&mut self, _event: &Event<'_>, _weights: &[f64]) {}
    /// The path arrives at the base, `weights` before the base's albedo.
    fn base(&mut self, _weights: &[f64], _rng: &mut Rng) {}
}

/// A visitor of exits only.
struct Exits<F>(F);

impl<F: FnMut(u32, DVec3, &[f64])> Visit for Exits<F> {
    fn exit(&mut self, order: u32, dir: DVec3, weights: &[f64]) {
        (self.0)(order, dir, weights)
    }
}

/// [`Coating::estimate`]'s visitor: next-event estimation before the base, the base's
/// gathering after.
struct Gather<'a, F> {
    coating: &'a Coating,
    base: &'a [f64],
    lights: &'a [DVec3],
    towards: &'a mut [[f64; MAX_CHANNELS]],
    /// Each light's `tau` draw, made at the first arrival at the base.
    tau: Option<Vec<bool>>,
    on_exit: F,
}

impl<F: FnMut(u32, DVec3, &[f64])> Visit for Gather<'_, F> {
    fn exit(&mut self, order: u32, dir: DVec3, weights: &[f64]) {
        (self.on_exit)(order, dir, weights)
    }

    fn event(&mut self, event: &Event<'_>, weights: &[f64]) {
        if self.tau.is_some() {
            return;
        }
        for (out, &l) in self.towards.iter_mut().zip(self.lights) {
            let p = event.towards(l);
            for (o, w) in out.iter_mut().zip(weights) {
                *o += w * p;
            }
        }
    }

    fn base(&mut self, weights: &[f64], rng: &mut Rng) {
        let coating = self.coating;
        let lights = self.lights;
        let tau = self.tau.get_or_insert_with(|| {
            lights
                .iter()
                .map(|&l| coating.reaches_base(l, rng))
                .collect()
        });
        let eta2 = (coating.eta * coating.eta).max(DIV_EPSILON);
        for ((out, &l), &reached) in self.towards.iter_mut().zip(lights).zip(tau.iter()) {
            if !reached {
                continue;
            }
            let share = l.z * std::f64::consts::FRAC_1_PI / eta2;
            for ((o, w), rho) in out.iter_mut().zip(weights).zip(self.base) {
                *o += w * rho * share;
            }
        }
    }
}

/// One scattering event on the interface, for next-event estimation.
pub(crate) struct Event<'a> {
    coating: &'a Coating,
    /// The event's order (1 for the first; no caller reads it yet).
    #[allow(dead_code)]
    pub order: u32,
    /// Whether the path arrived from inside the coating.
    pub inside: bool,
    /// The arriving direction, pointing back along the ray, in the frame of its side.
    wi: DVec3,
    /// The event's height `C1(h)` in that frame.
    c: f64,
}

impl Event<'_> {
    /// The relative index across the interface from the path's side.
    fn eta(&self) -> f64 {
        if self.inside {
            1.0 / self.coating.eta
        } else {
            self.coating.eta
        }
    }

    /// The density of leaving this event towards the outside direction `l` (unit, `l.z >
    /// 0`, the macro normal's frame) and escaping the surface along it: outside, the
    /// reflection's phase function times the escape probability from the event's height;
    /// inside, the transmission's, times the escape from the flipped height. With a
    /// directional light of radiance `L` along `l`, `weights * towards(l) * L` is this
    /// event's share of the light (Heitz et al. 2016's next-event estimation).
    pub(crate) fn towards(&self, l: DVec3) -> f64 {
        let s = &self.coating.surface;
        if self.inside {
            // In the inside frame the outside lies at -z: leave along -l, then escape
            // outside along l from the height 1 - c.
            let p = transmission_phase(s, self.wi, -l, self.eta());
            p * s.g1(l, (1.0 - self.c).max(f64::EPSILON))
        } else {
            let (p, cos) = s.phase(self.wi, l);
            p * fresnel_dielectric(cos, self.eta()) * s.g1(l, self.c)
        }
    }
}

/// The dielectric microsurface's transmission phase function (Walter et al. 2007, eqs. 16
/// and 21; Heitz et al. 2016, the dielectric phase function): from `wi` (pointing back
/// along the arriving ray, the incident side above) into the other side along `wo` (`wo.z
/// < 0` in the same frame) across a relative index `eta = n_t / n_i`: with the half vector
/// `h = -(wi + eta wo) / |wi + eta wo|` (turned up),
/// `p = (1 - F(wi.h)) D_wi(h) eta^2 |wo.h| / (wi.h + eta wo.h)^2`, `D_wi(h) = max(0, wi.h)
/// D(h) / A(wi)` the normals visible from `wi`. Zero where `h` does not separate the two.
pub(crate) fn transmission_phase(s: &Microsurface, wi: DVec3, wo: DVec3, eta: f64) -> f64 {
    let sum = wi + eta * wo;
    let len = sum.length();
    if len <= DIV_EPSILON {
        return 0.0;
    }
    let mut h = -sum / len;
    if h.z < 0.0 {
        h = -h;
    }
    let (cos_i, cos_o) = (wi.dot(h), wo.dot(h));
    if cos_i <= 0.0 || cos_o >= 0.0 {
        return 0.0;
    }
    let visible = cos_i * d_ggx(h.z, s.alpha) / s.projected_area(wi).max(DIV_EPSILON);
    let denominator = (cos_i + eta * cos_o).powi(2).max(DIV_EPSILON);
    (1.0 - fresnel_dielectric(cos_i, eta)) * visible * eta * eta * (-cos_o) / denominator
}

/// The side of the interface a path is on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Side {
    Outside,
    Inside,
}

impl Coating {
    /// The coating of `roughness` (clamped like everywhere) and relative index `eta`.
    pub(crate) fn new(roughness: f64, eta: f64) -> Self {
        Coating {
            surface: Microsurface::new(roughness),
            eta,
        }
    }

    /// One path arriving from the unit direction `wi` (outside, `wi.z > 0`, pointing back
    /// along the arriving ray) over a base of per-channel albedo `base` (at most
    /// [`MAX_CHANNELS`]). `on_exit(order, dir, weights)`: the path leaves upward along `dir`
    /// (outside frame) after `order` interface events; `weights` are the per-channel
    /// products of the base's albedo (and of Russian roulette's boosts). The path ends
    /// after `limit` interface events (`u32::MAX`: never, short of [`MAX_ORDER`]); returns
    /// false if it was cut at [`MAX_ORDER`].
    ///
    /// Every choice is drawn: an upward ray escapes or hits again with its escape
    /// probability (outside it then leaves, inside it goes down to the base and back), and
    /// each event reflects with probability F. A lossless path keeps weight 1, so a white
    /// base's estimate is 1 path by path; where the base absorbs, a path whose largest
    /// weight falls below [`RR_BELOW`] plays Russian roulette (survive with probability
    /// `max / RR_BELOW`, weights scaled up by its inverse).
    pub(crate) fn trace(
        &self,
        wi: DVec3,
        base: &[f64],
        limit: u32,
        rng: &mut Rng,
        on_exit: impl FnMut(u32, DVec3, &[f64]),
    ) -> bool {
        self.walk(wi, base, limit, rng, &mut Exits(on_exit))
    }

    /// [`Coating::trace`] reporting every step to `visit`: the exit, each interface event
    /// and each arrival at the base.
    pub(crate) fn walk(
        &self,
        wi: DVec3,
        base: &[f64],
        limit: u32,
        rng: &mut Rng,
        visit: &mut impl Visit,
    ) -> bool {
        let n = base.len().min(MAX_CHANNELS);
        let mut w = [1.0; MAX_CHANNELS];
        let s = &self.surface;
        let mut side = Side::Outside;
        let mut dir = -wi;
        let mut c = 1.0;
        let mut order = 0u32;
        loop {
            if dir.z > 0.0 && rng.uniform() < s.g1(dir, c) {
                if side == Side::Outside {
                    visit.exit(order, dir, &w[..n]);
                    return true;
                }
                // Down through the medium to the base, and back up to the interface.
                visit.base(&w[..n], rng);
                for (wk, rho) in w.iter_mut().zip(&base[..n]) {
                    *wk *= rho;
                }
                if !russian_roulette(&mut w[..n], rng) {
                    return true;
                }
                dir = lambertian_towards_interface(rng.uniform(), rng.uniform());
                c = 1.0;
                continue;
            }
            if order >= limit {
                return true;
            }
            // Given that it hits (an upward ray's draw above said so).
            c = s.next_height(dir, c, rng.uniform());
            order += 1;
            if order > MAX_ORDER {
                return false;
            }
            let wi_k = -dir;
            let event = Event {
                coating: self,
                order,
                inside: side == Side::Inside,
                wi: wi_k,
                c,
            };
            visit.event(&event, &w[..n]);
            let m = s.sample_visible_normal(wi_k, rng.uniform(), rng.uniform());
            let eta = event.eta();
            let refracted = (rng.uniform() >= fresnel_dielectric(wi_k.dot(m), eta))
                .then(|| refract(dir, m, eta))
                .flatten();
            match refracted {
                Some(t) => {
                    side = match side {
                        Side::Outside => Side::Inside,
                        Side::Inside => Side::Outside,
                    };
                    // Kept off 0, where no ray could leave (`G1 = 0^Lambda`).
                    c = (1.0 - c).max(f64::EPSILON);
                    dir = -t;
                }
                None => dir = reflect(dir, m),
            }
        }
    }

    /// Whether light arriving from the outside direction `l` reaches the base (one draw):
    /// the walk from `l` over a black base, stopped at its first arrival. Its mean is the
    /// coating's transmittance `tau(l)`, interface's multiple scattering included.
    pub(crate) fn reaches_base(&self, l: DVec3, rng: &mut Rng) -> bool {
        struct First(bool);
        impl Visit for First {
            fn base(&mut self, _: &[f64], _: &mut Rng) {
                self.0 = true;
            }
        }
        let mut first = First(false);
        self.walk(l, &[0.0], u32::MAX, rng, &mut first);
        first.0
    }

    /// One walk's estimate of `f(wi, l) mu_l` per channel towards each outside direction of
    /// `lights` (unit, `z > 0`), added to `towards`, reporting its exit to `on_exit` (for
    /// the environment). Light that reaches the base is gathered there: because the base is
    /// Lambertian, the light leaving it towards `l` before returning is `tau(l) mu_l / (pi
    /// eta^2)` of what it receives (reciprocity across the interface, `tau` drawn by
    /// [`Coating::reaches_base`] once a light and walk), so each arrival at the base adds its
    /// weight times `rho tau(l) mu_l / (pi eta^2)`; before the first arrival, next-event
    /// estimation at each interface event ([`Event::towards`]) adds the paths that never
    /// reach it. No delta lobe is sampled, so a smooth coating is no harder than a rough one.
    pub(crate) fn estimate(
        &self,
        wi: DVec3,
        base: &[f64],
        lights: &[DVec3],
        rng: &mut Rng,
        towards: &mut [[f64; MAX_CHANNELS]],
        on_exit: impl FnMut(u32, DVec3, &[f64]),
    ) -> bool {
        let mut gather = Gather {
            coating: self,
            base,
            lights,
            towards,
            tau: None,
            on_exit,
        };
        self.walk(wi, base, u32::MAX, rng, &mut gather)
    }

    /// The directional albedo at `mu` (the fraction of light arriving at cosine `mu` that
    /// the coated base reflects), per channel of `base`, by `paths` walks: the mean and its
    /// standard error per channel.
    #[cfg(test)]
    pub(crate) fn albedo(
        &self,
        mu: f64,
        base: &[f64],
        paths: u32,
        rng: &mut Rng,
    ) -> (Vec<f64>, Vec<f64>) {
        let wi = super::incident(mu);
        let n = base.len().min(MAX_CHANNELS);
        let (mut sum, mut sum2) = (vec![0.0; n], vec![0.0; n]);
        let mut path = vec![0.0; n];
        for _ in 0..paths {
            path.fill(0.0);
            self.trace(wi, base, u32::MAX, rng, |_, _, weights| {
                path[..weights.len()].copy_from_slice(weights);
            });
            for ((s, s2), p) in sum.iter_mut().zip(sum2.iter_mut()).zip(&path) {
                *s += p;
                *s2 += p * p;
            }
        }
        let count = f64::from(paths.max(1));
        let mean: Vec<f64> = sum.iter().map(|s| s / count).collect();
        let stderr = sum2
            .iter()
            .zip(&mean)
            .map(|(s2, m)| ((s2 / count - m * m).max(0.0) / (count - 1.0).max(1.0)).sqrt())
            .collect();
        (mean, stderr)
    }
}

/// The directional albedo of a smooth coating of relative index `eta` over a Lambertian
/// base of albedo `rho` (no absorption in the coating), light arriving at cosine `mu`: the
/// interface reflects `F(mu)`; the rest reaches the base, whose diffuse light escapes with
/// `T_in = (1 - F_avg(eta)) / eta^2` at each arrival and is reflected back with `1 - T_in`,
/// so the internal reflections sum to `F(mu) + (1 - F(mu)) rho T_in / (1 - rho (1 - T_in))`.
/// With `rho = 1` it is exactly 1. The closed form the walk's smooth limit must meet.
#[cfg(test)]
pub(crate) fn smooth_coating_albedo(mu: f64, eta: f64, rho: f64) -> f64 {
    let f = fresnel_dielectric(mu, eta);
    let t_in = (1.0 - f_avg_dielectric(eta)) / (eta * eta).max(crate::brdf::DIV_EPSILON);
    let denominator = (1.0 - rho * (1.0 - t_in)).max(crate::brdf::DIV_EPSILON);
    f + (1.0 - f) * rho * t_in / denominator
}

/// Russian roulette on a path's per-channel weights: below [`RR_BELOW`] (their largest),
/// the path survives with probability `max / RR_BELOW` and its weights are divided by it;
/// whether it survives (a path of zero weights does not).
pub(crate) fn russian_roulette(w: &mut [f64], rng: &mut Rng) -> bool {
    let max = w.iter().copied().fold(0.0, f64::max);
    if max >= RR_BELOW {
        return true;
    }
    if max <= 0.0 || rng.uniform() * RR_BELOW >= max {
        return false;
    }
    let boost = RR_BELOW / max;
    w.iter_mut().for_each(|x| *x *= boost);
    true
}

/// Snell's refraction of the ray direction `dir` (arriving: `dir.m < 0`) through a
/// microfacet of unit normal `m` into the side of relative index `eta = n_t / n_i`:
/// `t = dir / eta + (cos_i / eta - cos_t) m`; `None` past the critical angle.
pub(crate) fn refract(dir: DVec3, m: DVec3, eta: f64) -> Option<DVec3> {
    let cos_i = (-dir.dot(m)).clamp(0.0, 1.0);
    let r = 1.0 / eta.max(crate::brdf::DIV_EPSILON);
    let sin2_t = r * r * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((r * dir + (r * cos_i - cos_t) * m).normalize())
}

/// A direction leaving the Lambertian base towards the interface, in the inside frame
/// (`z < 0`), cosine-distributed about the base's normal: `r = sqrt(u1)`, `phi = 2 pi u2`.
fn lambertian_towards_interface(u1: f64, u2: f64) -> DVec3 {
    let r = u1.sqrt();
    let phi = std::f64::consts::TAU * u2;
    DVec3::new(r * phi.cos(), r * phi.sin(), -(1.0 - u1).max(0.0).sqrt())
}
