//! The error of a model's image against the truth's, per ball: relative radiance errors
//! (mean and 99th percentile over the ball's pixels), the truth's own noise floor over the
//! same pixels, and FLIP (Andersson et al. 2020, "FLIP: A Difference Evaluator for
//! Alternating Images", through the `nv-flip` crate) on the tone-mapped pictures.

use glam::DVec3;

use shadeballs::brdf::DIV_EPSILON;
use shadeballs::cpu::{self, MonteCarloImage};

/// Rec. 709 luminance: a colour's relative error is its luminance's.
const LUMINANCE: DVec3 = cpu::montecarlo::LUMINANCE;

/// A figure below this many times the truth's noise floor is reported as within noise.
pub const NOISE_FACTOR: f64 = 3.0;

/// Relative errors divide by the truth's luminance plus this fraction of the ball's mean
/// luminance: the dark rim, where the truth tends to zero, would otherwise dominate every
/// mean with errors of thousands of per cent on invisible pixels.
pub const REL_FLOOR: f64 = 0.01;

/// Per ball of `index`, [`REL_FLOOR`] times the mean truth luminance of its pixels.
fn floors(balls: usize, index: &[Option<usize>], truth: &MonteCarloImage) -> Vec<f64> {
    let mut sums = vec![(0.0, 0usize); balls];
    for (p, ball) in index.iter().enumerate() {
        if let Some(k) = *ball {
            sums[k].0 += truth.mean[p].dot(LUMINANCE);
            sums[k].1 += 1;
        }
    }
    sums.into_iter()
        .map(|(s, n)| REL_FLOOR * s / n.max(1) as f64)
        .collect()
}

/// `|a - t| / (t + floor)` of luminances.
fn relative(a: DVec3, t: DVec3, floor: f64) -> f64 {
    (a.dot(LUMINANCE) - t.dot(LUMINANCE)).abs() / (t.dot(LUMINANCE) + floor)
}

/// One ball's errors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BallError {
    /// Pixels of the ball.
    pub pixels: usize,
    /// Mean over the pixels of `|Y(model) - Y(truth)| / (Y(truth) + f)`, `f` [`REL_FLOOR`]
    /// times the ball's mean truth luminance.
    pub mean_rel: f64,
    /// The 99th percentile of the same.
    pub p99_rel: f64,
    /// The truth's noise floor for the mean: the mean over the pixels of
    /// `Y(std_error) / (Y(truth) + f)`.
    pub floor_mean: f64,
    /// The truth's noise floor for the percentile: the 99th percentile of that ratio.
    pub floor_p99: f64,
    /// Mean FLIP error over the pixels (0: identical, 1: most different).
    pub flip_mean: f64,
}

impl BallError {
    /// Whether `value` is under [`NOISE_FACTOR`] times `floor`: within the truth's noise.
    pub fn within_noise(value: f64, floor: f64) -> bool {
        value < NOISE_FACTOR * floor
    }

    /// `value` as a figure, or "within noise" when under [`NOISE_FACTOR`] times `floor`.
    pub fn figure(value: f64, floor: f64) -> String {
        if Self::within_noise(value, floor) {
            "within noise".to_string()
        } else {
            format!("{value:.5}")
        }
    }
}

/// FLIP's error map of `test` against `reference` (RGBA8, tone-mapped sRGB-like display
/// values), at nv-flip's default 67 pixels per degree (a 0.7 m viewing distance from a
/// 24-inch 4K monitor).
pub fn flip_map(reference: &[u8], test: &[u8], width: u32, height: u32) -> Vec<f32> {
    let rgb = |rgba: &[u8]| -> Vec<u8> {
        rgba.chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect()
    };
    let r = nv_flip::FlipImageRgb8::with_data(width, height, &rgb(reference));
    let t = nv_flip::FlipImageRgb8::with_data(width, height, &rgb(test));
    nv_flip::flip(r, t, nv_flip::DEFAULT_PIXELS_PER_DEGREE).to_vec()
}

/// The 99th percentile of `values` (nearest rank; 0 for none).
fn p99(mut values: Vec<f64>) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    values.sort_by(f64::total_cmp);
    let rank = ((0.99 * values.len() as f64).ceil() as usize).clamp(1, values.len());
    values[rank - 1]
}

/// The errors of `model` (linear radiance per pixel) against `truth`, per ball of `index`
/// (from [`cpu::ball_index_map`]); `flip` is the FLIP map of the two pictures. Balls whose
/// mean truth luminance is below [`DIV_EPSILON`] count in FLIP only.
pub fn ball_errors(
    balls: usize,
    index: &[Option<usize>],
    model: &[DVec3],
    truth: &MonteCarloImage,
    flip: &[f32],
) -> Vec<BallError> {
    let mut rel = vec![Vec::new(); balls];
    let mut noise = vec![Vec::new(); balls];
    let mut flips = vec![(0.0, 0usize); balls];
    let floor = floors(balls, index, truth);
    for (p, ball) in index.iter().enumerate() {
        let Some(k) = *ball else { continue };
        flips[k].0 += f64::from(flip[p]);
        flips[k].1 += 1;
        if floor[k] <= DIV_EPSILON * REL_FLOOR {
            continue;
        }
        let t = truth.mean[p];
        rel[k].push(relative(model[p], t, floor[k]));
        noise[k].push(truth.std_error[p].dot(LUMINANCE) / (t.dot(LUMINANCE) + floor[k]));
    }
    (0..balls)
        .map(|k| {
            let n = rel[k].len().max(1) as f64;
            BallError {
                pixels: flips[k].1,
                mean_rel: rel[k].iter().sum::<f64>() / n,
                p99_rel: p99(rel[k].clone()),
                floor_mean: noise[k].iter().sum::<f64>() / n,
                floor_p99: p99(noise[k].clone()),
                flip_mean: flips[k].0 / flips[k].1.max(1) as f64,
            }
        })
        .collect()
}

/// A heatmap of relative errors (as [`BallError::mean_rel`] forms them): each ball pixel's
/// error against the truth mapped by
/// magma (nv-flip's colour map) from 0 to `full_scale`; black elsewhere. RGBA8.
pub fn heatmap(
    index: &[Option<usize>],
    model: &[DVec3],
    truth: &MonteCarloImage,
    full_scale: f64,
) -> Vec<u8> {
    let lut = nv_flip::magma_lut().to_vec();
    let balls = index.iter().flatten().max().map_or(0, |k| k + 1);
    let floor = floors(balls, index, truth);
    index
        .iter()
        .enumerate()
        .flat_map(|(p, ball)| match *ball {
            Some(k) if floor[k] > DIV_EPSILON * REL_FLOOR => {
                let e = relative(model[p], truth.mean[p], floor[k]);
                let i = ((e / full_scale).clamp(0.0, 1.0) * 255.0).round() as usize;
                [lut[3 * i], lut[3 * i + 1], lut[3 * i + 2], 255]
            }
            _ => [0, 0, 0, 255],
        })
        .collect()
}
