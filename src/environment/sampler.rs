//! Drawing directions from an environment map by its luminance: the map strategy of the
//! Monte Carlo backends (`crate::cpu::montecarlo` in f64, and its tables in f32 for
//! `shaders/montecarlo.wgsl`; docs/design/environment.md, "The Monte Carlo backend").

use glam::{DVec2, DVec3};

use super::{direction_to_uv, uv_to_direction, Environment};
use crate::brdf::DIV_EPSILON;
use crate::sampling::guide_buckets;

/// Rec. 709 luminance weights: what the environment strategy samples in proportion to, and
/// how `MonteCarloImage::mean_relative_std_error` reduces a colour to one number.
pub const LUMINANCE: DVec3 = DVec3::new(0.2126, 0.7152, 0.0722);

/// Draws directions from an environment map in proportion to its radiance: a texel with
/// probability `w_ij / sum w`, `w_ij = Y_max(i, j) * texel_solid_angle(j)`, then uniformly in
/// its `(u, v)` rectangle. `Y_max` is the largest luminance of the texel and its eight
/// neighbours (wrapping in `u`, clamped in `v`): the bilinear read is non-zero wherever a
/// neighbour is, so every texel rectangle the map lights has a positive density. The
/// density per solid angle is `p_ij W H / (2 pi^2 sin theta)` (the equirectangular
/// Jacobian), exactly.
pub(crate) struct EnvSampler<'a> {
    env: &'a Environment,
    width: usize,
    height: usize,
    /// Per texel, its weight.
    weight: Vec<f64>,
    /// Per texel, the running sum of its row's weights up to and including it.
    row_cdf: Vec<f64>,
    /// Per row, the running sum of the rows' weights up to and including it.
    marginal: Vec<f64>,
    total: f64,
}

impl<'a> EnvSampler<'a> {
    /// `None` for a map that needs no sampler: constant (cosine and VNDF sampling suit a
    /// uniform environment) or black.
    pub(crate) fn new(env: &'a Environment) -> Option<Self> {
        let map = &env.map;
        let first = map.texels()[0];
        if env.intensity <= 0.0 || map.texels().iter().all(|t| t == &first) {
            return None;
        }
        let (w, h) = (map.width() as usize, map.height() as usize);
        let lum: Vec<f64> = map
            .texels()
            .iter()
            .map(|t| LUMINANCE.dot(DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64)))
            .collect();
        // The largest luminance across each row's neighbours (u wraps), then down the rows.
        let mut across = vec![0.0; w * h];
        for j in 0..h {
            let row = &lum[j * w..(j + 1) * w];
            for i in 0..w {
                let left = row[(i + w - 1) % w];
                let right = row[(i + 1) % w];
                across[j * w + i] = row[i].max(left).max(right);
            }
        }
        let mut weight = vec![0.0; w * h];
        let mut row_cdf = vec![0.0; w * h];
        let mut marginal = vec![0.0; h];
        let mut total = 0.0;
        for j in 0..h {
            let up = j.saturating_sub(1);
            let down = (j + 1).min(h - 1);
            let omega = map.texel_solid_angle(j as u32);
            let mut sum = 0.0;
            for i in 0..w {
                let y = across[j * w + i]
                    .max(across[up * w + i])
                    .max(across[down * w + i]);
                let wt = y * omega;
                weight[j * w + i] = wt;
                sum += wt;
                row_cdf[j * w + i] = sum;
            }
            total += sum;
            marginal[j] = total;
        }
        (total > DIV_EPSILON).then_some(EnvSampler {
            env,
            width: w,
            height: h,
            weight,
            row_cdf,
            marginal,
            total,
        })
    }

    /// A world direction from four uniform numbers in `[0, 1)`; `None` in the rare case
    /// rounding lands on a texel of zero weight.
    pub(crate) fn sample(&self, u: [f64; 4]) -> Option<DVec3> {
        let target = u[0] * self.total;
        let j = self
            .marginal
            .partition_point(|&c| c <= target)
            .min(self.height - 1);
        let row = &self.row_cdf[j * self.width..(j + 1) * self.width];
        let row_target = u[1] * row[self.width - 1];
        let i = row
            .partition_point(|&c| c <= row_target)
            .min(self.width - 1);
        if self.weight[j * self.width + i] <= 0.0 {
            return None;
        }
        let uv = DVec2::new(
            (i as f64 + u[2]) / self.width as f64,
            (j as f64 + u[3]) / self.height as f64,
        );
        Some(self.env.from_map(uv_to_direction(uv)))
    }

    /// The density per solid angle of [`EnvSampler::sample`] at world direction `l`.
    pub(crate) fn pdf(&self, l: DVec3) -> f64 {
        let d = self.env.to_map(l);
        let uv = direction_to_uv(d);
        let (w, h) = (self.width as f64, self.height as f64);
        let i = ((uv.x * w).floor() as i64).rem_euclid(self.width as i64) as usize;
        let j = ((uv.y * h).floor().max(0.0) as usize).min(self.height - 1);
        let p_texel = self.weight[j * self.width + i] / self.total;
        crate::sampling::equirect_density(p_texel, d, (w, h))
    }
}

/// The environment strategy's tables of `env` in f32 for the GPU estimator
/// (`shaders/montecarlo.wgsl`): the same weights `cpu::render_montecarlo` samples from,
/// normalised. `None` where the CPU estimator draws no direction from the map (a constant
/// or black map), so the GPU combines the same strategies.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct LuminanceCdf {
    /// Texels across.
    pub width: u32,
    /// Texels down.
    pub height: u32,
    /// Per row, the running sum of the rows' weights up to and including it, over the
    /// total (the last is 1).
    pub marginal: Vec<f32>,
    /// Per texel (row-major), the running sum of its row's weights up to and including it,
    /// over the row's sum (the last of a lit row is 1; a black row's are 0).
    pub row_cdf: Vec<f32>,
    /// Per texel, the probability of drawing it, its weight over the total.
    pub texel: Vec<f32>,
    /// The marginal's guide ([`guide`]).
    pub marginal_guide: Vec<f32>,
    /// Each row's guide, one after another ([`guide`] of each row of `row_cdf`).
    pub row_guide: Vec<f32>,
}

/// The guide of a CDF `cdf` of `n` values, for [`luminance_partition`] (the cutpoint
/// method: Chen and Asau 1974, "On generating random variates from an empirical
/// distribution", AIIE Transactions 6(2)): with `m` buckets ([`guide_buckets`]: `n`
/// rounded up to a power of two), entry `k < m` is the first index whose value exceeds `k
/// / m` and entry `m` is `n`; `m + 1` values, indices as f32 (exact: `n` is at most a map's
/// width).
fn guide(cdf: &[f32]) -> Vec<f32> {
    let m = guide_buckets(cdf.len());
    let mut guide = Vec::with_capacity(m + 1);
    // One sweep: the bounds k / m rise with k, and so does the first index past each.
    let mut i = 0;
    for k in 0..m {
        let bound = k as f32 / m as f32;
        while i < cdf.len() && cdf[i] <= bound {
            i += 1;
        }
        guide.push(i as f32);
    }
    guide.push(cdf.len() as f32);
    guide
}

/// `luminance_partition` of `lighting.wgsl` (and `partition_point` of `montecarlo.wgsl`):
/// the first index of `cdf` whose value exceeds `x` in `[0, 1)` (`cdf.len()` if none), what
/// `partition_point(|c| c <= x)` gives, found from the guide of `cdf` ([`guide`]): a search
/// of the entries between two of the guide's, not of all `n`. With `m` a power of two,
/// `k = floor(x m)` is exact; every value before guide entry `k` is at most `k / m <= x`,
/// so the index is at least entry `k`; the value at entry `k + 1` exceeds `(k + 1) / m >
/// x`, so the index is at most entry `k + 1`: the search runs between the two.
pub(crate) fn luminance_partition(cdf: &[f32], guide: &[f32], x: f32) -> usize {
    let m = guide.len() - 1;
    let k = ((x * m as f32) as usize).min(m - 1);
    let mut lo = guide[k] as usize;
    let mut hi = guide[k + 1] as usize;
    while lo < hi {
        let mid = (lo + hi) / 2;
        if cdf[mid] <= x {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    lo
}

impl LuminanceCdf {
    /// The tables of `env`'s luminance sampler (`None`: no sampler, see the type).
    pub(crate) fn of(env: &Environment) -> Option<Self> {
        let s = EnvSampler::new(env)?;
        Self::from_weights(s.width, s.height, &s.weight)
    }

    /// The lobe mode's tables of `env` (`None`: no sampler, or no texel above the mean):
    /// the luminance sampler's density less its mean over the sphere, at least 0 (MIS
    /// compensation: Karlik, Sik, Vevoda, Skrivan and Krivanek 2019, "MIS Compensation:
    /// Optimizing Sampling Techniques in Multiple Importance Sampling", ACM TOG 38(6),
    /// article 151: a tabulated density less a constant, derived for the balance
    /// heuristic; the lobe mode now weighs its samples by the power heuristic, which
    /// measured closer with these same tables). Beside the lobe's visible normals and the
    /// cosine, which sample the map's dim parts well, the map's samples go to what stands
    /// out of it; those strategies cover the texels left at 0, so the estimate stays
    /// unbiased. The Monte Carlo references keep [`LuminanceCdf::of`]'s
    /// (docs/design/environment.md, "The map's samples where they count", "Four
    /// strategies, weighted by the power heuristic").
    pub(crate) fn compensated(env: &Environment) -> Option<Self> {
        let EnvSampler {
            width: w,
            height: h,
            mut weight,
            total,
            ..
        } = EnvSampler::new(env)?;
        let omega: Vec<f64> = (0..h)
            .map(|j| env.map.texel_solid_angle(j as u32))
            .collect();
        // The mean of the weights' luminance over the sphere (the weights are luminance
        // times solid angle).
        let mean = total / (w as f64 * omega.iter().sum::<f64>());
        for (row, &o) in weight.chunks_mut(w).zip(&omega) {
            for x in row {
                *x = (*x - mean * o).max(0.0);
            }
        }
        Self::from_weights(w, h, &weight)
    }

    /// The tables of texel weights `weight` (row-major, `w` by `h`, each at least 0);
    /// `None` where they sum to nothing.
    fn from_weights(w: usize, h: usize, weight: &[f64]) -> Option<Self> {
        let mut row_cdf = vec![0.0f32; w * h];
        let mut marginal64 = vec![0.0f64; h];
        let mut total = 0.0;
        for j in 0..h {
            let row = &weight[j * w..(j + 1) * w];
            let sum: f64 = row.iter().sum();
            if sum > 0.0 {
                let mut run = 0.0;
                for (out, &x) in row_cdf[j * w..(j + 1) * w].iter_mut().zip(row) {
                    run += x;
                    *out = (run / sum) as f32;
                }
            }
            total += sum;
            marginal64[j] = total;
        }
        if total <= DIV_EPSILON {
            return None;
        }
        let marginal: Vec<f32> = marginal64.iter().map(|&c| (c / total) as f32).collect();
        let texel = weight.iter().map(|&x| (x / total) as f32).collect();
        Some(LuminanceCdf {
            width: w as u32,
            height: h as u32,
            marginal_guide: guide(&marginal),
            row_guide: row_cdf.chunks(w).flat_map(guide).collect(),
            marginal,
            row_cdf,
            texel,
        })
    }
}

impl LuminanceCdf {
    /// The tables as group 1's `env_cdf` holds them (`bindings.wgsl`): the width and the
    /// height, then [`LuminanceCdf::table_words`].
    pub(crate) fn gpu_words(&self) -> Vec<f32> {
        [
            &[self.width as f32, self.height as f32][..],
            &self.table_words(),
        ]
        .concat()
    }

    /// The tables in the order both shaders read them (`env_cdf` after its size,
    /// `montecarlo.wgsl`'s `mc_cdf` whole): the marginal, the rows' CDFs, the texels'
    /// probabilities, the marginal's guide and the rows' guides.
    pub(crate) fn table_words(&self) -> Vec<f32> {
        [
            &self.marginal[..],
            &self.row_cdf,
            &self.texel,
            &self.marginal_guide,
            &self.row_guide,
        ]
        .concat()
    }

    /// Row `j`'s CDF and its guide.
    pub(crate) fn row(&self, j: usize) -> (&[f32], &[f32]) {
        let w = self.width as usize;
        let g = guide_buckets(w) + 1;
        (
            &self.row_cdf[j * w..(j + 1) * w],
            &self.row_guide[j * g..(j + 1) * g],
        )
    }

    /// `luminance_sample` of `lighting.wgsl`, in the same f32 arithmetic: a map-frame
    /// direction from four uniform numbers (each exact in f32: the lobe's 24-bit points), a
    /// row by the marginal, a texel by its row's CDF, a point uniformly in the texel's `(u,
    /// v)` rectangle, and its density there, the drawn texel's (not looked up again from
    /// the direction); `None` where rounding lands on a texel of zero weight.
    pub(crate) fn luminance_sample(&self, u: [f64; 4]) -> Option<(DVec3, f64)> {
        let (w, h) = (self.width as usize, self.height as usize);
        let j = luminance_partition(&self.marginal, &self.marginal_guide, u[0] as f32).min(h - 1);
        let (row, row_guide) = self.row(j);
        let i = luminance_partition(row, row_guide, u[1] as f32).min(w - 1);
        let p_texel = self.texel[j * w + i];
        if p_texel <= 0.0 {
            return None;
        }
        let uv = DVec2::new(
            f64::from((i as f32 + u[2] as f32) / w as f32),
            f64::from((j as f32 + u[3] as f32) / h as f32),
        );
        let d = uv_to_direction(uv);
        let size = (w as f64, h as f64);
        Some((
            d,
            crate::sampling::equirect_density(f64::from(p_texel), d, size),
        ))
    }

    /// `luminance_density` of `lighting.wgsl`: the density per solid angle of
    /// [`LuminanceCdf::luminance_sample`] at map-frame direction `d`.
    pub(crate) fn luminance_density(&self, d: DVec3) -> f64 {
        let (w, h) = (f64::from(self.width), f64::from(self.height));
        let uv = direction_to_uv(d);
        let i = ((uv.x * w).floor() as i64).rem_euclid(i64::from(self.width)) as usize;
        let j = ((uv.y * h).floor().max(0.0) as usize).min(self.height as usize - 1);
        let p_texel = f64::from(self.texel[j * self.width as usize + i]);
        crate::sampling::equirect_density(p_texel, d, (w, h))
    }
}
