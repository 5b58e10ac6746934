//! A map's sun taken as a light by the split sum (issue 37, part 2).
//!
//! The split sum reads a rough lobe's light from layers prefiltered about the mirror
//! direction with `n = v = r`: under a small bright source it draws the highlight in the
//! wrong shape and lights the ball up to the mirror direction's horizon, not the
//! surface's (a crescent past the terminator). Engines take the sun out of the sky and
//! shade it as a light (Lagarde and de Rousiers 2014, *Moving Frostbite to Physically
//! Based Rendering*, section 4.7.3). Here a map's bright texels ([`Bright`]) are its sun
//! when they all lie within [`SUN_MAX_RADIUS`] of their power-weighted axis. Their excess
//! over the clipping threshold becomes one directional light along that axis; a second set
//! of prefiltered layers, from the map with that excess clipped, serves the balls that take
//! it ([`Sun::roughness_min`]); smoother balls keep the first set, whose layers hold the
//! sun as before. The background, the lobe mode, the Monte Carlo and the walk read the
//! map itself.

use glam::DVec3;

use super::prefilter::{Bright, MipChain};

/// The largest angle between the sun's axis and a bright texel's centre, plus half a
/// texel's diagonal, for the bright texels to be one sun (radians; 10 degrees). The
/// studio's three panels (hundreds of bright texels far apart) are not a sun.
pub(crate) const SUN_MAX_RADIUS: f64 = 10.0 * std::f64::consts::PI / 180.0;

/// A map's sun, in the map's frame and its own radiance units (the chain's f16 scale
/// multiplied back; the environment's intensity not applied).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sun {
    /// Unit direction towards the sun's axis: its bright texels' directions weighted by
    /// their excess luminance.
    pub direction: DVec3,
    /// The excess radiance times solid angle, summed over the bright texels: the
    /// irradiance it gives a surface facing it.
    pub irradiance: DVec3,
    /// The sun's angular radius (radians), as a uniform disc's: from the bright texels'
    /// second moment of angle about `direction`, weighted as the axis is.
    pub radius: f64,
}

impl Sun {
    /// The sun of `chain`'s bright texels, when they are one ([`SUN_MAX_RADIUS`]).
    pub(crate) fn of(chain: &MipChain, bright: &Bright) -> Option<Sun> {
        let scale = f64::from(chain.scale);
        let luminance = |t: &super::prefilter::BrightTexel| {
            crate::environment::sampler::LUMINANCE.dot(t.power() * scale)
        };
        let mut axis = DVec3::ZERO;
        let mut irradiance = DVec3::ZERO;
        let mut weight = 0.0;
        for t in &bright.texels {
            axis += t.direction() * luminance(t);
            irradiance += t.power() * scale;
            weight += luminance(t);
        }
        let direction = axis.try_normalize()?;
        let angle = |t: &super::prefilter::BrightTexel| {
            t.direction().dot(direction).clamp(-1.0, 1.0).acos()
        };
        // The texels' angular size at the equator, the widest.
        let texel = std::f64::consts::PI / f64::from(bright.chain.levels[0].height);
        let extent = bright.texels.iter().map(angle).fold(0.0, f64::max) + texel / 2f64.sqrt();
        if extent > SUN_MAX_RADIUS {
            return None;
        }
        // A uniform disc of radius R has E[theta^2] = R^2 / 2 about its centre. The texels'
        // centres, weighted by their excess, stand for it: an inner texel's light spreads
        // over its area, an edge texel's lies inside its centre, and the two nearly cancel
        // (a 3.62-degree disc on a 512-wide map comes out at 3.70 degrees, the sky's
        // 1.5-degree sun at 1.45).
        let second_moment = bright
            .texels
            .iter()
            .map(|t| luminance(t) * angle(t).powi(2))
            .sum::<f64>()
            / weight.max(f64::MIN_POSITIVE);
        let radius = (2.0 * second_moment).sqrt();
        Some(Sun {
            direction,
            irradiance,
            radius,
        })
    }

    /// The roughness from which a ball's lobe takes the sun as a light: where GGX's `alpha`
    /// reaches the sine of the sun's angular radius, the lobe is at least as wide as the
    /// sun, and a point along its axis stands for it. Smoother lobes read it from the
    /// layers, which hold its shape.
    pub fn roughness_min(&self) -> f64 {
        self.radius.sin().sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::environment::builtin::{sun_direction, SUN_RADIUS_DEG};
    use crate::environment::{uv_to_direction, Builtin, EnvMap};
    use glam::DVec2;

    /// A 512 x 256 map of 0.5 with a disc of `radiance` and angular radius `radius_deg`
    /// about `axis`.
    fn disc_map(axis: DVec3, radius_deg: f64, radiance: f32) -> EnvMap {
        let (w, h) = (512u32, 256u32);
        let cos_cap = radius_deg.to_radians().cos();
        let texels = (0..w * h)
            .map(|k| {
                let uv = DVec2::new(
                    (f64::from(k % w) + 0.5) / f64::from(w),
                    (f64::from(k / w) + 0.5) / f64::from(h),
                );
                let inside = uv_to_direction(uv).dot(axis) >= cos_cap;
                [if inside { radiance } else { 0.5 }; 3]
            })
            .collect();
        EnvMap::new(w, h, texels).unwrap()
    }

    /// The sky's sun is found along its own direction, about as wide as its disc (the
    /// bright level's 1.4-degree texels blur it); a 3-degree disc's radius within 10 %,
    /// its irradiance is its radiance times its solid angle, less
    /// the threshold it is clipped to; the studio's three panels and a disc wider than
    /// `SUN_MAX_RADIUS` are not a sun. Each can fail: the axis within 0.5 degrees, the
    /// irradiance within 3 % (the disc's texels at the bright level's resolution).
    #[test]
    fn a_small_bright_source_is_the_maps_sun() {
        let sky = Builtin::Sky
            .generate(1024)
            .sun()
            .expect("the sky has a sun");
        let off = sky.direction.dot(sun_direction()).clamp(-1.0, 1.0).acos();
        assert!(off.to_degrees() < 0.5, "{:.3} degrees", off.to_degrees());
        let radius = sky.radius.to_degrees();
        assert!(
            (0.8 * SUN_RADIUS_DEG..1.5 * SUN_RADIUS_DEG).contains(&radius),
            "{radius:.3} degrees"
        );
        assert!(Builtin::Studio.generate(1024).sun().is_none());
        let axis = DVec3::new(-0.45, 0.55, 0.7).normalize();
        let disc = disc_map(axis, 3.0, 1e4)
            .sun()
            .expect("a 3-degree disc is a sun");
        let omega = 2.0 * std::f64::consts::PI * (1.0 - 3f64.to_radians().cos());
        let expected = 1e4 * omega;
        let got = disc.irradiance.x;
        assert!(
            (got / expected - 1.0).abs() < 0.03,
            "{got:.4} against {expected:.4}"
        );
        assert!(disc.direction.dot(axis).acos().to_degrees() < 0.5);
        let radius = disc.radius.to_degrees();
        assert!((2.85..3.3).contains(&radius), "{radius:.3} degrees");
        assert!(
            disc_map(axis, 12.0, 1e4).sun().is_none(),
            "12 degrees is too wide"
        );
    }
}
