//! Small statistics shared by the viewer's readouts and the lab's measurements, and the
//! Monte Carlo image both estimators return (CPU and GPU).

use glam::DVec3;

use crate::brdf::DIV_EPSILON;
use crate::environment::sampler::LUMINANCE;
use crate::error::{Error, Result};
use crate::scene::Scene;

/// A count for a message, its noun singular for one: `1 sample`, `16 samples` (issue 38, 9:
/// "1 samples").
pub(crate) fn count(n: impl Into<u64>, noun: &str) -> String {
    match n.into() {
        1 => format!("1 {noun}"),
        n => format!("{n} {noun}s"),
    }
}

/// Most samples per pixel the Monte Carlo estimators accept (`--spp`).
pub const MAX_SPP: u32 = 65536;

/// The median of `v` (the upper of the two middle values for an even count; NaN when
/// empty), sorting it.
pub fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

/// Which part of the model a Monte Carlo render integrates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// The whole BRDF.
    Whole,
    /// The multiple-scattering lobe alone (what the term adds; zero on balls without it).
    Multiple,
}

/// A Monte Carlo image: per pixel (row-major, row 0 at the top) the mean linear radiance of
/// `spp` independent estimates and the standard error of that mean.
#[derive(Clone, Debug, PartialEq)]
pub struct MonteCarloImage {
    /// Pixels across.
    pub width: u32,
    /// Pixels down.
    pub height: u32,
    /// Estimates per covered pixel.
    pub spp: u32,
    /// Mean radiance per pixel (the background where no ball covers it).
    pub mean: Vec<DVec3>,
    /// Standard error of the mean per pixel and channel, `s / sqrt(spp)` with `s` the
    /// sample standard deviation of the `spp` estimates; 0 where there is no noise (the
    /// background, a pixel only lights reach) and where `spp < 2` leaves it unknown.
    pub std_error: Vec<DVec3>,
    /// Whether a ball covers the pixel.
    pub covered: Vec<bool>,
    /// The pixel filter: `true` where a pixel a ball's silhouette crosses mixes the ball's
    /// estimate and the background by the fraction it covers, as the real-time renderers
    /// antialias ([`crate::scene::Scene::antialias`]); `false`: one ray through each
    /// pixel's centre. An image compares with another only under the same filter.
    pub antialias: bool,
}

impl MonteCarloImage {
    /// Errors unless an image rendered with `antialias` (its pixel filter,
    /// [`crate::scene::Scene::antialias`]) compares like with like with this one: the same
    /// filter on both sides. A silhouette pixel mixes ball and background where one side
    /// antialiases, and is one ball's or the background's where the other does not: an
    /// error measured across the two is the filters', not the lighting's.
    pub fn compares_with(&self, antialias: bool) -> Result<()> {
        if antialias == self.antialias {
            return Ok(());
        }
        let filter = |aa: bool| {
            if aa {
                "antialiased"
            } else {
                "one ray through each pixel's centre"
            }
        };
        Err(Error::Invalid {
            what: "comparison",
            message: format!(
                "unlike pixel filters: the image is {}, its reference {} (render both with the same antialiasing)",
                filter(antialias),
                filter(self.antialias)
            ),
        })
    }

    /// The mean over the covered pixels of `Y(std_error) / Y(mean)` (`Y`: [`LUMINANCE`];
    /// `Y(std_error)` bounds the standard error of the luminance from above), skipping
    /// pixels whose mean luminance is below [`DIV_EPSILON`]. `None` when `spp < 2` (no
    /// variance estimate) or no covered pixel counts.
    pub(crate) fn mean_relative_std_error(&self) -> Option<f64> {
        if self.spp < 2 {
            return None;
        }
        let (sum, count) = self
            .mean
            .iter()
            .zip(&self.std_error)
            .zip(&self.covered)
            .filter(|&(_, &c)| c)
            .map(|((m, s), _)| (m.dot(LUMINANCE), s.dot(LUMINANCE)))
            .filter(|&(m, _)| m > DIV_EPSILON)
            .fold((0.0, 0usize), |(sum, n), (m, s)| (sum + s / m, n + 1));
        (count > 0).then(|| sum / count as f64)
    }
}

/// What the Monte Carlo estimators refuse (`crate::cpu::render_montecarlo` and the GPU's): `spp` outside
/// `1..=MAX_SPP`, a map whose rotation or intensity is not finite (or whose intensity is
/// negative).
pub(crate) fn check_montecarlo_inputs(scene: &Scene, spp: u32) -> Result<()> {
    if !(1..=MAX_SPP).contains(&spp) {
        return Err(Error::Invalid {
            what: "samples per pixel",
            message: format!("{spp}: must be in 1..={MAX_SPP}"),
        });
    }
    if let Some(env) = &scene.environment_map {
        if !env.rotation_deg.is_finite() || !env.intensity.is_finite() || env.intensity < 0.0 {
            return Err(Error::Invalid {
                what: "environment",
                message: format!(
                    "rotation {} and intensity {} must be finite, the intensity >= 0",
                    env.rotation_deg, env.intensity
                ),
            });
        }
    }
    Ok(())
}
