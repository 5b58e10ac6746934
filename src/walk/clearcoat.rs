//! The truth of a clear coat: a rough dielectric coat over a whole ball's material, walked
//! as Heitz, Hanika, d'Eon and Dachsbacher 2016 walk a dielectric microsurface (section 5;
//! [`super::coating`]), with the ball's own walk as the base at the bottom of the coat's
//! medium: the conductor's walk ([`super::microsurface`], Schlick's F per channel) or the
//! plastic's ([`super::coating::Coating`]), chosen per arrival with probability
//! `metallic`. The base's walk runs as it does in air (the coat's medium changes neither
//! the metal's Fresnel nor the plastic's index): the models make the same assumption.
//!
//! The coat's weight mixes, as OpenPBR's `coat_weight` and glTF's `clearcoat` do: a path
//! meets the coat with probability `weight`, the bare base otherwise. Every choice is
//! drawn, so a lossless path weighs 1; only Russian roulette ends a path early.
//!
//! Frames as in [`super::coating`]: inside the coat `+z` points down, towards the base. A
//! ray that leaves the interface downward reaches the base along `dir`; in the base's own
//! frame (its normal up, towards the coat) that ray arrives from `(-dir.x, -dir.y, dir.z)`,
//! and the base's exit `o` goes back up as `(o.x, o.y, -o.z)`.

use glam::DVec3;

use super::coating::{refract, russian_roulette, Coating};
use super::microsurface::{reflect, Microsurface};
use super::rng::Rng;
use super::MAX_ORDER;
use crate::brdf::{f_schlick, fresnel_dielectric};

/// A ball's material under its clear coat, as the walk sees it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Layered {
    /// The coat's interface (roughness and relative index).
    pub coat: Coating,
    /// The coat's weight in `[0, 1]`.
    pub weight: f64,
    /// The metal's share of the base.
    pub metallic: f64,
    /// The metal's microsurface.
    pub metal: Microsurface,
    /// The metal's `F0` per channel (Schlick's F).
    pub f0: [f64; 3],
    /// The plastic: its coating over a Lambertian substrate of albedo `rho`.
    pub plastic: Coating,
    /// The plastic's substrate albedo per channel.
    pub rho: [f64; 3],
}

impl Layered {
    /// One path arriving from the outside direction `wi` (`wi.z > 0`): its exit direction
    /// and per-channel weight, or `None` where it ended inside (Russian roulette, or cut at
    /// [`MAX_ORDER`]).
    pub(crate) fn sample(&self, wi: DVec3, rng: &mut Rng) -> Option<(DVec3, [f64; 3])> {
        let mut w = [1.0; 3];
        let dir = if rng.uniform() < self.weight {
            self.through_coat(wi, &mut w, rng)?
        } else {
            self.base(wi, &mut w, rng)?
        };
        Some((dir, w))
    }

    /// The bare base's exit from `wi` (its own frame), weights multiplied into `w`.
    pub(crate) fn base(&self, wi: DVec3, w: &mut [f64; 3], rng: &mut Rng) -> Option<DVec3> {
        if rng.uniform() < self.metallic {
            conductor_exit(&self.metal, wi, &self.f0, w, rng)
        } else {
            let mut exit = None;
            self.plastic
                .trace(wi, &self.rho, u32::MAX, rng, |_, dir, weights| {
                    exit = Some(dir);
                    for (wk, x) in w.iter_mut().zip(weights) {
                        *wk *= x;
                    }
                });
            exit
        }
    }

    /// The walk through the coat: the dielectric interface's events, the base at the
    /// bottom of its medium.
    fn through_coat(&self, wi: DVec3, w: &mut [f64; 3], rng: &mut Rng) -> Option<DVec3> {
        let s = &self.coat.surface;
        let eta = self.coat.eta;
        let mut inside = false;
        let mut dir = -wi;
        let mut c = 1.0;
        let mut order = 0u32;
        loop {
            if dir.z > 0.0 && rng.uniform() < s.g1(dir, c) {
                if !inside {
                    return Some(dir);
                }
                // Down to the base and back up to the interface.
                let arriving = DVec3::new(-dir.x, -dir.y, dir.z);
                let o = self.base(arriving, w, rng)?;
                if !russian_roulette(w, rng) {
                    return None;
                }
                dir = DVec3::new(o.x, o.y, -o.z);
                c = 1.0;
                continue;
            }
            c = s.next_height(dir, c, rng.uniform());
            order += 1;
            if order > MAX_ORDER {
                return None;
            }
            let wi_k = -dir;
            let m = s.sample_visible_normal(wi_k, rng.uniform(), rng.uniform());
            let relative = if inside { 1.0 / eta } else { eta };
            let refracted = (rng.uniform() >= fresnel_dielectric(wi_k.dot(m), relative))
                .then(|| refract(dir, m, relative))
                .flatten();
            match refracted {
                Some(t) => {
                    inside = !inside;
                    c = (1.0 - c).max(f64::EPSILON);
                    dir = -t;
                }
                None => dir = reflect(dir, m),
            }
        }
    }

    /// The directional albedo at `mu` per channel by `paths` walks: the mean and its
    /// standard error.
    #[cfg(test)]
    pub(crate) fn albedo(&self, mu: f64, paths: u32, rng: &mut Rng) -> ([f64; 3], [f64; 3]) {
        let wi = super::incident(mu);
        let (mut sum, mut sum2) = ([0.0; 3], [0.0; 3]);
        for _ in 0..paths {
            let w = self.sample(wi, rng).map_or([0.0; 3], |(_, w)| w);
            for k in 0..3 {
                sum[k] += w[k];
                sum2[k] += w[k] * w[k];
            }
        }
        let n = f64::from(paths.max(1));
        let mean = sum.map(|s| s / n);
        let mut stderr = [0.0; 3];
        for k in 0..3 {
            stderr[k] = ((sum2[k] / n - mean[k] * mean[k]).max(0.0) / (n - 1.0).max(1.0)).sqrt();
        }
        (mean, stderr)
    }
}

/// The conductor's walk with its exit drawn (Heitz et al. 2016: an upward ray escapes with
/// probability `G1`, else hits again): the exit direction from `wi`, the Fresnel of each
/// event (Schlick's, `f0` per channel) multiplied into `w`; `None` where Russian roulette
/// ended it or it was cut at [`MAX_ORDER`].
pub(crate) fn conductor_exit(
    s: &Microsurface,
    wi: DVec3,
    f0: &[f64; 3],
    w: &mut [f64; 3],
    rng: &mut Rng,
) -> Option<DVec3> {
    let mut dir = -wi;
    let mut c = 1.0;
    let mut order = 0u32;
    loop {
        if dir.z > 0.0 && rng.uniform() < s.g1(dir, c) {
            return Some(dir);
        }
        c = s.next_height(dir, c, rng.uniform());
        order += 1;
        if order > MAX_ORDER {
            return None;
        }
        let wi_k = -dir;
        let m = s.sample_visible_normal(wi_k, rng.uniform(), rng.uniform());
        let cos = wi_k.dot(m).max(0.0);
        for (wk, f) in w.iter_mut().zip(f0) {
            *wk *= f_schlick(*f, cos);
        }
        dir = reflect(dir, m);
        if !russian_roulette(w, rng) {
            return None;
        }
    }
}
