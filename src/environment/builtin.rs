//! Generated environments, so nothing is downloaded: `studio`, `sky` and `white`.
//!
//! Directions are given as an azimuth `phi` and an elevation `e` in the map's convention
//! (`super`): `d = (cos e sin phi, sin e, -cos e cos phi)`, so azimuth 0 is `-z` (where the
//! reference camera looks), +90 degrees is `+x` and +-180 degrees is `+z` (behind the
//! camera). The reference camera at `(0, 80, 300)` sees the balls from `+z`: a light at
//! azimuth -145 degrees is in front of the balls and to the camera's left.

use std::f64::consts::PI;

use glam::DVec3;
use rayon::prelude::*;

use super::file::MAX_MAP_TEXELS;
use super::EnvMap;

/// A built-in environment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Builtin {
    /// Soft rectangular lights over a dim gradient: the look-dev studio.
    Studio,
    /// An analytic daylight sky with a sun.
    Sky,
    /// Uniform radiance 1, taken through the map path (the furnace of the whole path).
    White,
}

/// The width a built-in is generated at unless asked otherwise (height is half).
pub(crate) const DEFAULT_BUILTIN_WIDTH: u32 = 1024;

/// The widest built-in: 8192 x 4096 is [`MAX_MAP_TEXELS`].
pub(crate) const MAX_BUILTIN_WIDTH: u32 = 8192;

impl Builtin {
    /// Every built-in, in the order the help lists them.
    pub(crate) const ALL: [Builtin; 3] = [Builtin::Studio, Builtin::Sky, Builtin::White];

    /// The name the command line and the scene file use.
    pub fn name(self) -> &'static str {
        match self {
            Builtin::Studio => "studio",
            Builtin::Sky => "sky",
            Builtin::White => "white",
        }
    }

    /// The map, `width x width / 2` texels (`width` rounded down to even and clamped to
    /// `2..=MAX_BUILTIN_WIDTH`). Every texel is finite and non-negative.
    pub fn generate(self, width: u32) -> EnvMap {
        let width = width.clamp(2, MAX_BUILTIN_WIDTH) & !1;
        let height = width / 2;
        debug_assert!(u64::from(width) * u64::from(height) <= MAX_MAP_TEXELS);
        match self {
            Builtin::White => EnvMap::uniform(DVec3::ONE, width, height),
            Builtin::Studio => fill(width, height, |_| (), |_, t| studio_at(t)),
            Builtin::Sky => {
                let sky = Sky::new(SKY_TURBIDITY, sun_direction());
                let mut map = fill(
                    width,
                    height,
                    |cos_theta| sky.row(cos_theta.max(0.0)),
                    |row, t| sky.radiance(t.d, t.elevation_deg, row),
                );
                // Average radiance 1 over the sphere (solid-angle weighted luminance).
                let mean = mean_luminance(&map);
                let scale = if mean > 0.0 && mean.is_finite() {
                    1.0 / mean
                } else {
                    1.0
                };
                for t in &mut map.texels {
                    for c in t.iter_mut() {
                        *c = sanitize(f64::from(*c) * scale);
                    }
                }
                // The texels changed: their peak too.
                EnvMap::with_peak(width, height, map.texels)
            }
        }
    }
}

crate::named_enum!(Builtin, "built-in environment");

/// The unit direction of azimuth `phi_deg` and elevation `elevation_deg` (the module's
/// convention).
pub(crate) fn direction(phi_deg: f64, elevation_deg: f64) -> DVec3 {
    let (sp, cp) = phi_deg.to_radians().sin_cos();
    let (se, ce) = elevation_deg.to_radians().sin_cos();
    DVec3::new(ce * sp, se, -ce * cp)
}

/// Luminance of linear sRGB (Rec. 709 weights).
pub(crate) fn luminance(c: DVec3) -> f64 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// The solid-angle weighted mean luminance of `map`.
pub(crate) fn mean_luminance(map: &EnvMap) -> f64 {
    let w = map.width() as usize;
    let sum: f64 = (0..map.height())
        .map(|j| {
            let row = &map.texels()[j as usize * w..(j as usize + 1) * w];
            let l: f64 = row
                .iter()
                .map(|t| luminance(DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64)))
                .sum();
            l * map.texel_solid_angle(j)
        })
        .sum();
    sum / (4.0 * PI)
}

/// A finite non-negative f32 of `v` (NaN to 0, beyond f32 to its largest).
fn sanitize(v: f64) -> f32 {
    if v.is_nan() || v <= 0.0 {
        0.0
    } else {
        v.min(f64::from(f32::MAX)) as f32
    }
}

/// Where a texel centre looks: its unit direction, azimuth and elevation (degrees).
#[derive(Clone, Copy, Debug)]
struct Texel {
    d: DVec3,
    phi_deg: f64,
    elevation_deg: f64,
}

/// A map whose texel `(i, j)` is `f` at its centre, rows in parallel: `row` of the
/// row's `cos theta` is computed once a row, the sines and cosines of each column's
/// azimuth once a map.
fn fill<R>(
    width: u32,
    height: u32,
    row: impl Fn(f64) -> R + Sync,
    f: impl Fn(&R, Texel) -> DVec3 + Sync,
) -> EnvMap {
    let (w, h) = (width as usize, height as usize);
    let columns: Vec<(f64, f64, f64)> = (0..w)
        .map(|i| {
            let phi = ((i as f64 + 0.5) / w as f64 - 0.5) * 2.0 * PI;
            let (s, c) = phi.sin_cos();
            (phi.to_degrees(), s, c)
        })
        .collect();
    let mut texels = vec![[0.0f32; 3]; w * h];
    texels.par_chunks_mut(w).enumerate().for_each(|(j, out)| {
        let theta = (j as f64 + 0.5) / h as f64 * PI;
        let (st, ct) = theta.sin_cos();
        let elevation_deg = 90.0 - theta.to_degrees();
        let state = row(ct);
        for (t, &(phi_deg, sp, cp)) in out.iter_mut().zip(&columns) {
            let c = f(
                &state,
                Texel {
                    d: DVec3::new(st * sp, ct, -st * cp),
                    phi_deg,
                    elevation_deg,
                },
            );
            *t = [sanitize(c.x), sanitize(c.y), sanitize(c.z)];
        }
    });
    EnvMap::with_peak(width, height, texels)
}

fn smoothstep(e0: f64, e1: f64, x: f64) -> f64 {
    let t = if e1 > e0 {
        ((x - e0) / (e1 - e0)).clamp(0.0, 1.0)
    } else if x >= e0 {
        1.0
    } else {
        0.0
    };
    t * t * (3.0 - 2.0 * t)
}

// ---------------------------------------------------------------------------------------
// studio

/// A soft rectangle of light in (azimuth, elevation): centre, full sizes and radiance.
#[derive(Clone, Copy, Debug)]
pub(crate) struct AreaLight {
    /// Azimuth of the centre, degrees.
    pub phi_deg: f64,
    /// Elevation of the centre, degrees.
    pub elevation_deg: f64,
    /// Full width in azimuth, degrees.
    pub width_deg: f64,
    /// Full height in elevation, degrees.
    pub height_deg: f64,
    /// Linear RGB radiance inside.
    pub radiance: DVec3,
}

/// Half-width of the smoothstep that softens each light's edges, degrees: a 1024-wide map
/// has texels of 0.35 degrees, so the edge spans about 6 texels.
pub(crate) const STUDIO_EDGE_DEG: f64 = 1.0;

/// The studio's lights: key (up, front-left of the balls as the reference camera sees
/// them: the direction towards it is about `(-0.5, 0.5, 0.7)`), fill (front-right, dimmer,
/// lower) and rim (behind and above the balls, for their silhouettes).
pub(crate) const STUDIO_LIGHTS: [AreaLight; 3] = [
    AreaLight {
        phi_deg: -145.0,
        elevation_deg: 30.0,
        width_deg: 40.0,
        height_deg: 30.0,
        radiance: DVec3::new(15.0, 14.4, 13.5),
    },
    AreaLight {
        phi_deg: 135.0,
        elevation_deg: 12.0,
        width_deg: 30.0,
        height_deg: 24.0,
        radiance: DVec3::new(4.5, 4.8, 5.2),
    },
    AreaLight {
        phi_deg: 15.0,
        elevation_deg: 40.0,
        width_deg: 24.0,
        height_deg: 36.0,
        radiance: DVec3::splat(10.0),
    },
];

/// The studio's dim grey gradient: floor 0.03, horizon 0.08, top 0.12.
pub(crate) fn studio_gradient(d: DVec3) -> DVec3 {
    let y = d.y.clamp(-1.0, 1.0);
    let g = if y >= 0.0 {
        0.08 + (0.12 - 0.08) * y
    } else {
        // The floor darkens within a few degrees below the horizon.
        0.08 + (0.03 - 0.08) * smoothstep(0.0, 0.15, -y)
    };
    DVec3::splat(g)
}

/// How much of light `l` covers direction `d`: 1 inside, 0 outside, a smoothstep across
/// [`STUDIO_EDGE_DEG`] either side of each edge.
fn coverage(l: &AreaLight, phi: f64, e: f64) -> f64 {
    let dphi = (phi - l.phi_deg + 180.0).rem_euclid(360.0) - 180.0;
    let de = e - l.elevation_deg;
    let edge = |delta: f64, half: f64| {
        1.0 - smoothstep(half - STUDIO_EDGE_DEG, half + STUDIO_EDGE_DEG, delta.abs())
    };
    edge(dphi, 0.5 * l.width_deg) * edge(de, 0.5 * l.height_deg)
}

fn studio_at(t: Texel) -> DVec3 {
    let mut c = studio_gradient(t.d);
    for l in &STUDIO_LIGHTS {
        let w = coverage(l, t.phi_deg, t.elevation_deg);
        if w > 0.0 {
            c = c.lerp(l.radiance, w);
        }
    }
    c
}

/// The direction towards the studio's key light.
#[cfg(test)]
pub(crate) fn studio_key_direction() -> DVec3 {
    let k = STUDIO_LIGHTS[0];
    direction(k.phi_deg, k.elevation_deg)
}

// ---------------------------------------------------------------------------------------
// sky

/// The sky's turbidity (Preetham: 2 very clear, 3 clear, 6 hazy).
pub(crate) const SKY_TURBIDITY: f64 = 3.0;
/// The sun's elevation above the horizon, degrees.
pub(crate) const SUN_ELEVATION_DEG: f64 = 35.0;
/// The sun's azimuth: front-left of the balls, like the studio's key light.
pub(crate) const SUN_AZIMUTH_DEG: f64 = -145.0;
/// The sun disk's angular radius, degrees: widened from the real 0.27 so that a
/// 1024-wide map (0.35-degree texels) resolves it over some 50 texels.
pub(crate) const SUN_RADIUS_DEG: f64 = 1.5;
/// The sun disk's radiance as a multiple of the zenith sky's.
pub(crate) const SUN_TO_ZENITH: f64 = 150.0;
/// The ground's grey albedo: below the horizon the map shows this times the average
/// radiance along the horizon.
pub(crate) const GROUND_ALBEDO: f64 = 0.3;

/// The direction towards the sky's sun.
pub(crate) fn sun_direction() -> DVec3 {
    direction(SUN_AZIMUTH_DEG, SUN_ELEVATION_DEG)
}

/// Coefficients A..E of the Perez et al. 1993 all-weather luminance distribution.
#[derive(Clone, Copy, Debug)]
struct Perez([f64; 5]);

impl Perez {
    /// `F(theta, gamma) = (1 + A e^(B / cos theta)) (1 + C e^(D gamma) + E cos^2 gamma)`,
    /// `cos theta` held above 0.01 at the horizon.
    fn f(&self, cos_theta: f64, gamma: f64) -> f64 {
        self.theta_part(cos_theta) * self.gamma_part(gamma, gamma.cos())
    }

    /// `1 + A e^(B / cos theta)`.
    fn theta_part(&self, cos_theta: f64) -> f64 {
        let [a, b, ..] = self.0;
        1.0 + a * (b / cos_theta.max(0.01)).exp()
    }

    /// `1 + C e^(D gamma) + E cos^2 gamma`.
    fn gamma_part(&self, gamma: f64, cos_gamma: f64) -> f64 {
        let [_, _, c, d, e] = self.0;
        1.0 + c * (d * gamma).exp() + e * cos_gamma * cos_gamma
    }
}

/// The Preetham, Shirley & Smits 1999 analytic daylight sky ("A Practical Analytic Model
/// for Daylight", SIGGRAPH 99, appendix A.2): the Perez distribution of luminance `Y` and
/// chromaticity `x`, `y`, each relative to its zenith value, for a turbidity and a sun
/// direction; `xyY -> XYZ -> linear sRGB` (IEC 61966-2-1 matrix, D65).
#[derive(Clone, Copy, Debug)]
struct Sky {
    sun: DVec3,
    perez: [Perez; 3],
    /// Zenith `Y` (kcd/m^2), `x`, `y`.
    zenith: [f64; 3],
    /// `F(0, theta_s)` per channel, the zenith's own Perez value.
    f_zenith: [f64; 3],
    sun_radiance: DVec3,
    ground: DVec3,
}

impl Sky {
    fn new(turbidity: f64, sun: DVec3) -> Self {
        let t = turbidity;
        let sun = sun.normalize_or(DVec3::Y);
        let theta_s = sun.y.clamp(-1.0, 1.0).acos();
        // Appendix A.2: the distribution coefficients as linear functions of turbidity.
        let perez = [
            Perez([
                0.1787 * t - 1.4630,
                -0.3554 * t + 0.4275,
                -0.0227 * t + 5.3251,
                0.1206 * t - 2.5771,
                -0.0670 * t + 0.3703,
            ]),
            Perez([
                -0.0193 * t - 0.2592,
                -0.0665 * t + 0.0008,
                -0.0004 * t + 0.2125,
                -0.0641 * t - 0.8989,
                -0.0033 * t + 0.0452,
            ]),
            Perez([
                -0.0167 * t - 0.2608,
                -0.0950 * t + 0.0092,
                -0.0079 * t + 0.2102,
                -0.0441 * t - 1.6537,
                -0.0109 * t + 0.0529,
            ]),
        ];
        // Zenith luminance and chromaticity.
        let chi = (4.0 / 9.0 - t / 120.0) * (PI - 2.0 * theta_s);
        let y_z = ((4.0453 * t - 4.9710) * chi.tan() - 0.2155 * t + 2.4192).max(0.0);
        let (s1, s2, s3) = (theta_s, theta_s * theta_s, theta_s * theta_s * theta_s);
        let x_z = t * t * (0.00166 * s3 - 0.00375 * s2 + 0.00209 * s1)
            + t * (-0.02903 * s3 + 0.06377 * s2 - 0.03202 * s1 + 0.00394)
            + (0.11693 * s3 - 0.21196 * s2 + 0.06052 * s1 + 0.25886);
        let yy_z = t * t * (0.00275 * s3 - 0.00610 * s2 + 0.00317 * s1)
            + t * (-0.04214 * s3 + 0.08970 * s2 - 0.04153 * s1 + 0.00516)
            + (0.15346 * s3 - 0.26756 * s2 + 0.06670 * s1 + 0.26688);
        let f_zenith = perez.map(|p| p.f(1.0, theta_s));
        let mut sky = Sky {
            sun,
            perez,
            zenith: [y_z, x_z, yy_z],
            f_zenith,
            sun_radiance: DVec3::ZERO,
            ground: DVec3::ZERO,
        };
        // The sun: SUN_TO_ZENITH times the zenith's luminance, in the colour of the sky
        // next to it (warm at low elevation).
        let zenith_rgb = sky.sky(DVec3::Y);
        let near_sun = sky.sky(sun);
        let near_lum = luminance(near_sun);
        let tint = if near_lum > 0.0 {
            near_sun / near_lum
        } else {
            DVec3::ONE
        };
        sky.sun_radiance = tint * SUN_TO_ZENITH * luminance(zenith_rgb);
        // The ground: the albedo times the horizon's mean radiance (the ground is lit by
        // the sky, roughly as bright as the horizon).
        let n = 64;
        let horizon = (0..n)
            .map(|k| sky.sky(direction(360.0 * k as f64 / n as f64, 0.0)))
            .fold(DVec3::ZERO, |a, c| a + c)
            / n as f64;
        sky.ground = GROUND_ALBEDO * horizon;
        sky
    }

    /// Per channel, the zenith value over `F(0, theta_s)` times the Perez factor of
    /// `cos theta` (one per row of a map).
    fn row(&self, cos_theta: f64) -> [f64; 3] {
        std::array::from_fn(|k| {
            let f0 = self.f_zenith[k];
            if f0.abs() > 1e-12 {
                self.zenith[k] * self.perez[k].theta_part(cos_theta) / f0
            } else {
                self.zenith[k]
            }
        })
    }

    /// The sky alone (no sun disk) towards `d`, above the horizon (`d.y` held at 0 below).
    fn sky(&self, d: DVec3) -> DVec3 {
        self.sky_in_row(d, &self.row(d.y.max(0.0)))
    }

    /// [`Sky::sky`] with the row's factors given.
    fn sky_in_row(&self, d: DVec3, row: &[f64; 3]) -> DVec3 {
        let d = DVec3::new(d.x, d.y.max(0.0), d.z).normalize_or(DVec3::Y);
        let cos_gamma = d.dot(self.sun).clamp(-1.0, 1.0);
        let gamma = cos_gamma.acos();
        let rel = |k: usize| row[k] * self.perez[k].gamma_part(gamma, cos_gamma);
        let (lum, x, y) = (rel(0), rel(1), rel(2));
        if y.is_nan() || lum.is_nan() || y <= 1e-6 || lum <= 0.0 {
            return DVec3::ZERO;
        }
        // xyY -> XYZ -> linear sRGB.
        let big_x = x / y * lum;
        let big_z = (1.0 - x - y) / y * lum;
        let rgb = DVec3::new(
            3.2406 * big_x - 1.5372 * lum - 0.4986 * big_z,
            -0.9689 * big_x + 1.8758 * lum + 0.0415 * big_z,
            0.0557 * big_x - 0.2040 * lum + 1.0570 * big_z,
        );
        rgb.max(DVec3::ZERO)
    }

    /// Sky, sun disk and ground towards `d` at `elevation` degrees, with the row's factors.
    fn radiance(&self, d: DVec3, elevation: f64, row: &[f64; 3]) -> DVec3 {
        // Half a degree of blend at the horizon, then the ground.
        let below = smoothstep(0.0, 0.5, -elevation);
        let mut c = if below >= 1.0 {
            self.ground
        } else {
            self.sky_in_row(d, row).lerp(self.ground, below)
        };
        let cos_gamma = d.dot(self.sun).clamp(-1.0, 1.0);
        if cos_gamma > (SUN_RADIUS_DEG + 0.2).to_radians().cos() && elevation > -0.5 {
            let gamma = cos_gamma.acos().to_degrees();
            let disk = 1.0 - smoothstep(SUN_RADIUS_DEG - 0.2, SUN_RADIUS_DEG + 0.2, gamma);
            c = c.lerp(self.sun_radiance, disk);
        }
        c
    }
}
