//! Prefiltering an environment map for real-time shading (docs/design/environment.md,
//! "Shading under a map (image-based lighting)"), on the CPU: the twin of
//! `shaders/prefilter.wgsl`, which does the same work on the GPU at load. Both start from
//! the same [`MipChain`] (built here, uploaded as is) and take the same samples, so the CPU
//! renderer reads what the GPU's prefiltered textures hold.
//!
//! Three products, each a weighted average of the map, so a uniform map gives back its
//! radiance exactly (the furnace holds through the whole path):
//! - **specular**: `SPECULAR_LEVELS` layers, layer `k` the map convolved with the GGX lobe of
//!   roughness `k / (SPECULAR_LEVELS - 1)` seen with `n = v = R` (Karis 2013, "Real Shading in
//!   Unreal Engine 4": the split sum's first factor), by [`SPECULAR_SAMPLES`] GGX samples
//!   weighted by `G(1, n.l)` (not Karis's `n.l`: `prefilter_specular` says why), each read from the mip level its solid angle covers (filtered
//!   importance sampling, Krivanek & Colbert 2008, "Real-time Shading with Filtered
//!   Importance Sampling"); a map's bright texels (a sun, a lamp: `Bright`) are taken out
//!   of what the samples read and integrated against the lobe directly, so a small bright
//!   source gives no blotches; a read interpolates linearly between the two layers around
//!   the ball's roughness;
//! - **irradiance**: layer 0 of the convolved maps, the cosine-weighted average of the map
//!   about the normal (irradiance over pi);
//! - **multiple scattering**: layers `1..=CONVOLVED_LEVELS` of the convolved maps, the map
//!   averaged with the Kulla-Conty zonal kernel `k(t) = (1 - E(t)) t` about the normal at
//!   roughness `(j - 1) / (CONVOLVED_LEVELS - 1)`: the integral `int (1 - E(mu_i)) mu_i L dw_i`
//!   of the term's lobe divided by its uniform-environment value `pi (1 - E_avg)`.
//!   The convolution is a direct sum over the texels of the mip level
//!   `CONVOLUTION_SOURCE_WIDTH` wide, so it has no band limit (spherical harmonics, the
//!   alternative, need 9 to 13 bands at roughness 0.3 to 0.5: docs/design/environment.md,
//!   "Harmonics or a map per roughness").

use std::f64::consts::PI;

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::{direction_to_uv, uv_to_direction, EnvMap};
use crate::brdf::{alpha_from_roughness, Geometry, DIV_EPSILON};
use crate::lut::Tables;

/// Layers of the specular prefilter: roughness 0, 1/6, ..., 1.
pub(crate) const SPECULAR_LEVELS: u32 = 7;
/// Width of the sharpest specular layers (height half): the map's own width when narrower.
/// Rougher layers are smaller ([`specular_mip`]).
pub(crate) const SPECULAR_WIDTH: u32 = 256;
/// Mip levels of the specular texture: layer `k` is stored at level [`specular_mip`]`(k)`,
/// `SPECULAR_WIDTH >> level` wide.
pub(crate) const SPECULAR_MIP_LEVELS: u32 = 3;
/// GGX samples per texel of the sharpest prefiltered layer (roughness 1/6); rougher
/// layers take more (`specular_samples`).
pub const SPECULAR_SAMPLES: u32 = 64;
/// Added to filtered importance sampling's level (Krivanek & Colbert suggest 1: a
/// smoother result with fewer samples, at the price of a wider lobe).
pub(crate) const FIS_LOD_BIAS: f64 = 0.0;
/// The coarsest mip level filtered importance sampling reads is at least this wide (22.5
/// degree texels): a bilinear read of an equirectangular level of 4 x 2 texels spreads a
/// light over a hemisphere, beyond any lobe. The rough layers take more samples instead
/// ([`specular_samples`]).
pub(crate) const FIS_MIN_WIDTH: u32 = 16;
/// A texel of the map's [`BRIGHT_WIDTH`] level is bright when its luminance is above this
/// many times the level's mean (solid-angle weighted): a sun or a lamp, which a few GGX
/// samples a texel would find by chance ([`Bright`]).
pub(crate) const BRIGHT_RATIO: f64 = 16.0;
/// At most this many bright texels, the brightest (the GPU holds them in a uniform buffer
/// of two `vec4` each: 16 KiB, every backend's smallest uniform binding).
pub(crate) const BRIGHT_MAX: usize = 512;
/// Bright texels are found on the first mip level at most this wide (the sharpest sampled
/// layer's own width, [`SPECULAR_WIDTH`]).
pub(crate) const BRIGHT_WIDTH: u32 = SPECULAR_WIDTH;
/// Kulla-Conty kernel layers: roughness 0, 1/8, ..., 1.
pub const CONVOLVED_LEVELS: u32 = 9;
/// Width of each convolved layer (height half).
pub const CONVOLVED_WIDTH: u32 = 32;
/// The mip level the convolutions sum over: the first at most this wide.
pub(crate) const CONVOLUTION_SOURCE_WIDTH: u32 = 64;
/// Samples of each zonal kernel over `t = n.w` in `[0, 1]` (linear between them).
pub(crate) const KERNEL_SIZE: usize = 64;
/// Largest radiance the f16 textures hold; a brighter map is divided by a power of two to
/// fit ([`EnvMap::f16_scale`]).
pub(crate) const F16_MAX: f32 = 65504.0;
/// The smallest positive f16 (a subnormal, 2^-24); half of it rounds to 0.
pub(crate) const F16_MIN_SUBNORMAL: f32 = 5.960_464_5e-8;
/// A weight sum below this is treated as zero (no texel in the kernel's support).
pub(crate) const WEIGHT_EPSILON: f64 = 1e-30;
/// Smallest `sin theta` the texel solid angle uses at the poles (filtered importance
/// sampling's level choice; the equirectangular texel shrinks to nothing there).
pub(crate) const POLE_SIN_MIN: f64 = 1e-4;

/// Round to f16 and back: the value a `Rgba16Float` texel holds.
fn f16_round(v: f32) -> f32 {
    half::f16::from_f32(v.min(F16_MAX)).to_f32()
}

/// One level of an RGBA image in the layout the GPU textures use (alpha unused, 1).
#[derive(Clone, Debug, PartialEq)]
pub struct Level {
    /// Texels across.
    pub width: u32,
    /// Texels down.
    pub height: u32,
    /// Row-major, row 0 at the top; each value as its f16 texel holds it.
    pub texels: Vec<[f32; 4]>,
}

impl Level {
    fn texel(&self, i: u32, j: u32) -> DVec3 {
        let t = self.texels[(j * self.width + i) as usize];
        DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64)
    }

    /// Bilinear at `uv` as a linear sampler reads it: texel centres at half-integers, `u`
    /// repeating, `v` clamped to the edge.
    pub(crate) fn bilinear(&self, uv: DVec2) -> DVec3 {
        let x = uv.x * self.width as f64 - 0.5;
        let y = uv.y * self.height as f64 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let w = self.width as i64;
        let i0 = (x0 as i64).rem_euclid(w) as u32;
        let i1 = (x0 as i64 + 1).rem_euclid(w) as u32;
        let h = self.height as i64 - 1;
        let j0 = (y0 as i64).clamp(0, h) as u32;
        let j1 = (y0 as i64 + 1).clamp(0, h) as u32;
        let top = self.texel(i0, j0).lerp(self.texel(i1, j0), fx);
        let bottom = self.texel(i0, j1).lerp(self.texel(i1, j1), fx);
        top.lerp(bottom, fy)
    }

    /// The solid angle of a texel of row `j`.
    pub(crate) fn texel_solid_angle(&self, j: u32) -> f64 {
        let h = self.height as f64;
        let (t0, t1) = (PI * j as f64 / h, PI * (j + 1) as f64 / h);
        2.0 * PI / self.width as f64 * (t0.cos() - t1.cos())
    }
}

/// The map and its mip levels (each texel the solid-angle weighted mean of the 2 x 2
/// below it; odd sizes drop their last row or column, as a texture's mip sizes do), with
/// f16 values of the map divided by [`MipChain::scale`].
#[derive(Clone, Debug, PartialEq)]
pub struct MipChain {
    /// Level 0 (the map) first, down to 1 texel on the shorter side.
    pub levels: Vec<Level>,
    /// The map's `EnvMap::f16_scale`: every level holds the map's radiance divided by it,
    /// and a read multiplies it back (on the GPU it is folded into the uniform's intensity).
    pub scale: f32,
    /// Texel channels that f16 cannot hold once divided by the scale: non-zero values
    /// below its smallest subnormal, flushed to 0 (the scale keeps every value under
    /// `F16_MAX`, so none is clipped at the top).
    pub clamped: u64,
}

impl MipChain {
    /// Builds the chain of `map`, with one `log::warn!` line when texels are lost to f16
    /// and one `log::info!` line when the map is scaled to fit it.
    pub fn new(map: &EnvMap) -> Self {
        let scale = map.f16_scale();
        let clamped = map
            .texels()
            .par_iter()
            .map(|t| {
                t.iter()
                    .filter(|&&c| c > 0.0 && f16_round(c / scale) == 0.0)
                    .count() as u64
            })
            .sum();
        if scale > 1.0 {
            log::info!(
                "environment map: peak {:.4e} is above f16's {F16_MAX}: its textures hold it \
                 divided by {scale} (multiplied back where they are read)",
                map.peak()
            );
        }
        if clamped > 0 {
            log::warn!(
                "environment map: {clamped} channels below {:.3e} became 0 in its half-float \
                 textures (a dynamic range beyond f16's, peak {:.4e})",
                0.5 * scale * F16_MIN_SUBNORMAL,
                map.peak()
            );
        }
        let texels = map
            .texels()
            .par_iter()
            .map(|t| {
                [
                    f16_round(t[0] / scale),
                    f16_round(t[1] / scale),
                    f16_round(t[2] / scale),
                    1.0,
                ]
            })
            .collect();
        let mut levels = vec![Level {
            width: map.width(),
            height: map.height(),
            texels,
        }];
        while let Some(next) = downsample(levels.last().expect("level 0 is there")) {
            levels.push(next);
        }
        MipChain {
            levels,
            scale,
            clamped,
        }
    }

    /// Trilinear at direction `d` and level `lod` (clamped to the chain), as
    /// `textureSampleLevel` with a linear sampler reads it.
    pub fn sample(&self, d: DVec3, lod: f64) -> DVec3 {
        let uv = direction_to_uv(d);
        let lod = lod.clamp(0.0, (self.levels.len() - 1) as f64);
        let l0 = lod.floor() as usize;
        let f = lod - l0 as f64;
        let a = self.levels[l0].bilinear(uv);
        if f == 0.0 {
            return a;
        }
        a.lerp(self.levels[l0 + 1].bilinear(uv), f)
    }

    /// The level the convolutions sum over (`CONVOLUTION_SOURCE_WIDTH`).
    pub fn convolution_source(&self) -> u32 {
        self.levels
            .iter()
            .position(|l| l.width <= CONVOLUTION_SOURCE_WIDTH)
            .unwrap_or(self.levels.len() - 1) as u32
    }
}

/// The next level of `l`: each texel the solid-angle weighted mean of the 2 x 2 below it
/// (the upper row of a pair covers less of the sphere towards the poles; an unweighted
/// mean would over-weight it, and at the coarse levels filtered importance sampling reads
/// that moves light towards the poles).
fn downsample(l: &Level) -> Option<Level> {
    if l.width < 2 || l.height < 2 {
        return None;
    }
    let (w, h) = (l.width / 2, l.height / 2);
    let texels = (0..h)
        .into_par_iter()
        .flat_map_iter(|j| {
            let w0 = l.texel_solid_angle(2 * j) as f32;
            let w1 = l.texel_solid_angle(2 * j + 1) as f32;
            let norm = 0.5 / (w0 + w1).max(f32::MIN_POSITIVE);
            (0..w).map(move |i| {
                let mut sum = [0f32; 3];
                for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let t = l.texels[((2 * j + dj) * l.width + 2 * i + di) as usize];
                    let weight = if dj == 0 { w0 } else { w1 };
                    for c in 0..3 {
                        sum[c] += t[c] * weight;
                    }
                }
                [
                    f16_round(sum[0] * norm),
                    f16_round(sum[1] * norm),
                    f16_round(sum[2] * norm),
                    1.0,
                ]
            })
        })
        .collect();
    Some(Level {
        width: w,
        height: h,
        texels,
    })
}

/// The zonal kernels of the convolved layers, `KERNEL_SIZE` samples each over `t` in
/// `[0, 1]`: layer 0 the cosine `t`, layer `j` the Kulla-Conty `(1 - E(t)) t` at roughness
/// `(j - 1) / (CONVOLVED_LEVELS - 1)`, E as the shader reads it from `tables`.
pub fn kernels(tables: &Tables) -> Vec<f32> {
    let mut out = Vec::with_capacity((CONVOLVED_LEVELS as usize + 1) * KERNEL_SIZE);
    for layer in 0..=CONVOLVED_LEVELS {
        for i in 0..KERNEL_SIZE {
            let t = i as f32 / (KERNEL_SIZE - 1) as f32;
            out.push(if layer == 0 {
                t
            } else {
                let r = convolved_roughness(layer);
                tables.lut_loss(t, r as f32) * t
            });
        }
    }
    out
}

/// The roughness of convolved layer `layer >= 1`.
pub fn convolved_roughness(layer: u32) -> f64 {
    (layer - 1) as f64 / (CONVOLVED_LEVELS - 1) as f64
}

/// The roughness of specular layer `layer`.
pub(crate) fn specular_roughness(layer: u32) -> f64 {
    layer as f64 / (SPECULAR_LEVELS - 1) as f64
}

/// `specular_direction` of `environment.wgsl`: the direction the prefiltered specular is
/// read along at normal `n`, mirror direction `r`: `r` bent towards `n` as the lobe widens
/// (Lagarde & de Rousiers 2014, "Moving Frostbite to Physically Based Rendering", 4.9.3).
pub fn specular_direction(n: DVec3, r: DVec3, roughness: f64) -> DVec3 {
    n.lerp(r, dominant_weight(alpha_from_roughness(roughness)))
        .normalize()
}

/// `dominant_weight` of `environment.wgsl`: the weight of the mirror direction against
/// the normal in [`specular_direction`] for a lobe of GGX `alpha` in `[0, 1]`.
pub(crate) fn dominant_weight(alpha: f64) -> f64 {
    let smooth = 1.0 - alpha;
    smooth * (smooth.sqrt() + alpha)
}

/// `specular_direction_aniso` of `environment.wgsl`: [`specular_direction`] for an
/// anisotropic lobe of `(alpha_t, alpha_b)` along the unit tangent `t` and bitangent `b`,
/// read at the level `roughness` (the lobe's equal solid angle, or the wider one under a
/// clear coat, which scales both alphas alike). `r`'s component along each axis leans towards `n` by
/// that axis's own [`dominant_weight`], so that the read follows the lobe along its rough
/// axis (docs/design/anisotropy.md, "The split sum's direction"). Equal alphas give
/// [`specular_direction`].
pub(crate) fn specular_direction_aniso(
    (n, r): (DVec3, DVec3),
    (t, b): (DVec3, DVec3),
    (alpha_t, alpha_b): (f64, f64),
    roughness: f64,
) -> DVec3 {
    let alpha = alpha_from_roughness(roughness);
    let scale = alpha / (alpha_t * alpha_b).sqrt().max(DIV_EPSILON);
    let w = dominant_weight(alpha);
    let w_t = dominant_weight((alpha_t * scale).min(1.0));
    let w_b = dominant_weight((alpha_b * scale).min(1.0));
    ((1.0 - w + w * r.dot(n)) * n + w_t * r.dot(t) * t + w_b * r.dot(b) * b).normalize()
}

/// `kernel_at` of `prefilter.wgsl`: layer `layer` of `kernels` at `t` (0 below the horizon).
pub(crate) fn kernel_at(kernels: &[f32], layer: u32, t: f64) -> f64 {
    if t <= 0.0 {
        return 0.0;
    }
    let x = t.min(1.0) * (KERNEL_SIZE - 1) as f64;
    let i0 = (x.floor() as usize).min(KERNEL_SIZE - 2);
    let f = x - i0 as f64;
    let row = &kernels[layer as usize * KERNEL_SIZE..];
    (row[i0] as f64) * (1.0 - f) + (row[i0 + 1] as f64) * f
}

/// `radical_inverse` of `prefilter.wgsl`: the bits of `i` mirrored about the binary point
/// (van der Corput); with `i / n` it gives the Hammersley points.
pub fn radical_inverse(i: u32) -> f64 {
    i.reverse_bits() as f64 / 4294967296.0
}

/// `prefilter_specular` of `prefilter.wgsl`: the GGX-filtered radiance about `r` (`n = v =
/// r`) at `roughness`, from `chain`. Each sample is weighted by `G(1, n.l)` of `geometry`,
/// not by Karis's `n.l`: with `v = n` the radiance the lobe reflects is
/// `int L D G / 4 dw`, so this weighting makes the split sum exact at normal incidence
/// (measured against Monte Carlo: the `n.l` weighting left rough balls under the studio
/// 20 % off where they face the camera).
///
/// `chain` is the map with its [`Bright`] texels clipped when it has any, and `bright` those
/// texels' excess: the samples read the clipped map, and the excess is added as the
/// integral it is ([`bright_specular`]), over the samples' own weight sum (their mean `G`
/// estimates the lobe's integral `int D G / 4 dw`, so the two parts share one normalisation).
pub(crate) fn prefilter_specular(
    chain: &MipChain,
    bright: &[BrightTexel],
    r: DVec3,
    roughness: f64,
    geometry: Geometry,
    samples: u32,
) -> DVec3 {
    let alpha = alpha_from_roughness(roughness);
    let max_lod = fis_max_level(chain) as f64;
    let level0 = &chain.levels[0];
    let (w0, h0) = (level0.width as f64, level0.height as f64);
    let (t, b) = crate::sampling::duff_frame(r).tangents();
    let a2 = alpha * alpha;
    let mut sum = DVec3::ZERO;
    let mut weight = 0.0;
    for i in 0..samples {
        let u1 = (i as f64 + 0.5) / samples as f64;
        let u2 = radical_inverse(i);
        // GGX half-vector with pdf D(h) cos(theta_h): cos^2 = (1 - u) / (1 + (a^2 - 1) u).
        let cos2 = (1.0 - u1) / (1.0 + (a2 - 1.0) * u1);
        let cos_h = cos2.sqrt();
        let sin_h = (1.0 - cos2).max(0.0).sqrt();
        let phi = 2.0 * PI * u2;
        let h = t * (sin_h * phi.cos()) + b * (sin_h * phi.sin()) + r * cos_h;
        let v_dot_h = cos_h; // v = r = n
        let l = 2.0 * v_dot_h * h - r;
        let n_dot_l = l.dot(r);
        if n_dot_l <= 0.0 {
            continue;
        }
        // pdf(l) = D(h) cos(theta_h) / (4 v.h) = D / 4 with n = v; the sample covers
        // 1 / (N pdf) steradians, a level-0 texel (2 pi / w0)(pi / h0) sin(theta).
        let denom = cos2 * (a2 - 1.0) + 1.0;
        let d = a2 / (PI * denom * denom);
        let omega_s = 4.0 / (samples as f64 * d);
        let sin_l = (1.0 - l.y * l.y).max(0.0).sqrt().max(POLE_SIN_MIN);
        let omega_p = 2.0 * PI * PI / (w0 * h0) * sin_l;
        let lod = (0.5 * (omega_s / omega_p).log2() + FIS_LOD_BIAS).clamp(0.0, max_lod);
        let g = geometry.g(1.0, n_dot_l, roughness);
        sum += chain.sample(l, lod) * g;
        weight += g;
    }
    let excess = bright_specular(bright, r, alpha, roughness, geometry);
    (sum + excess * samples as f64) / weight.max(WEIGHT_EPSILON)
}

/// `bright_specular` of `prefilter.wgsl`: `int L_b D G / 4 dw` about `r` (`n = v = r`) for
/// the bright texels' excess `L_b`, each texel a point of its solid angle: the lobe's
/// value `D(h) G(1, n.l) / 4` at its centre times its excess radiance times its solid
/// angle. With `n = v`, `n.h = sqrt((1 + n.l) / 2)`.
pub(crate) fn bright_specular(
    bright: &[BrightTexel],
    r: DVec3,
    alpha: f64,
    roughness: f64,
    geometry: Geometry,
) -> DVec3 {
    let mut sum = DVec3::ZERO;
    for b in bright {
        let t = r.dot(b.direction());
        if t <= 0.0 {
            continue;
        }
        let n_dot_h = (0.5 * (1.0 + t)).sqrt();
        let k = crate::brdf::d_ggx(n_dot_h, alpha) * geometry.g(1.0, t, roughness) / 4.0;
        sum += b.power() * k;
    }
    sum
}

/// One bright texel of [`Bright`], as the GPU's uniform holds it (f32).
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
pub(crate) struct BrightTexel {
    /// xyz: the texel centre's direction (map frame); w: unused.
    pub direction: [f32; 4],
    /// rgb: the excess radiance taken out of the texel times the texel's solid angle
    /// (divided by the chain's f16 scale, as the textures hold it); w: unused.
    pub power: [f32; 4],
}

impl BrightTexel {
    pub(crate) fn direction(&self) -> DVec3 {
        DVec3::new(
            self.direction[0] as f64,
            self.direction[1] as f64,
            self.direction[2] as f64,
        )
    }

    pub(crate) fn power(&self) -> DVec3 {
        DVec3::new(
            self.power[0] as f64,
            self.power[1] as f64,
            self.power[2] as f64,
        )
    }
}

/// A map's bright texels apart (issue 37, a split sum without blotches under a sun). A
/// few GGX samples a texel find a small bright source by chance, and filtered importance
/// sampling reads it from coarse mip levels where the samples of the lobe's tail land: the
/// rough layers showed the sun as blocks and rings. Here the texels of the
/// [`BRIGHT_WIDTH`] level above [`BRIGHT_RATIO`] times its mean luminance (at most
/// [`BRIGHT_MAX`], the brightest) are clipped to that threshold in a copy of the chain from
/// that level down, which the samples read, and their excess is integrated against the
/// lobe directly ([`bright_specular`]). The excess plus the clipped texel is the texel, so
/// no energy is lost or added (up to the f16 rounding of the clipped value, which the
/// excess takes back).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Bright {
    /// The chain from the bright level down, bright texels clipped.
    pub chain: MipChain,
    /// The bright texels' excess.
    pub texels: Vec<BrightTexel>,
}

impl Bright {
    /// The bright texels of `chain`, or none when no texel is bright.
    pub(crate) fn new(chain: &MipChain) -> Option<Self> {
        let level_index = chain
            .levels
            .iter()
            .position(|l| l.width <= BRIGHT_WIDTH)
            .unwrap_or(chain.levels.len() - 1);
        let level = &chain.levels[level_index];
        let luminance = |t: &[f32; 4]| {
            crate::environment::sampler::LUMINANCE.dot(DVec3::new(
                t[0] as f64,
                t[1] as f64,
                t[2] as f64,
            ))
        };
        let (mut total, mut area) = (0.0, 0.0);
        for j in 0..level.height {
            let omega = level.texel_solid_angle(j);
            for i in 0..level.width {
                total += luminance(&level.texels[(j * level.width + i) as usize]) * omega;
                area += omega;
            }
        }
        let mut threshold = BRIGHT_RATIO * total / area;
        let mut bright: Vec<(f64, usize)> = level
            .texels
            .iter()
            .enumerate()
            .map(|(k, t)| (luminance(t), k))
            .filter(|&(y, _)| y > threshold)
            .collect();
        if bright.is_empty() {
            return None;
        }
        bright.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        if bright.len() > BRIGHT_MAX {
            threshold = bright[BRIGHT_MAX].0;
            bright.truncate(BRIGHT_MAX);
            bright.retain(|&(y, _)| y > threshold);
        }
        log::debug!(
            "environment map: {} bright texels of its {}x{} level apart (luminance above {:.4e})",
            bright.len(),
            level.width,
            level.height,
            threshold
        );
        let mut clipped = level.clone();
        let texels = bright
            .iter()
            .map(|&(y, k)| {
                let t = level.texels[k];
                let keep = threshold / y;
                let (i, j) = (k as u32 % level.width, k as u32 / level.width);
                let omega = level.texel_solid_angle(j);
                let mut power = [0f32; 4];
                for c in 0..3 {
                    let rest = f16_round((t[c] as f64 * keep) as f32);
                    clipped.texels[k][c] = rest;
                    power[c] = ((t[c] - rest) as f64 * omega) as f32;
                }
                let uv = DVec2::new(
                    (i as f64 + 0.5) / level.width as f64,
                    (j as f64 + 0.5) / level.height as f64,
                );
                let d = uv_to_direction(uv).as_vec3();
                BrightTexel {
                    direction: [d.x, d.y, d.z, 0.0],
                    power,
                }
            })
            .collect();
        let mut levels = vec![clipped];
        while let Some(next) = downsample(levels.last().expect("the bright level is there")) {
            levels.push(next);
        }
        Some(Bright {
            chain: MipChain {
                levels,
                scale: chain.scale,
                clamped: 0,
            },
            texels,
        })
    }
}

/// The level of `clipped` (a chain from one of `chain`'s levels down, [`Bright`]'s) that
/// the convolutions sum over: `chain`'s convolution source, or `clipped`'s first level when
/// that source is above it.
pub(crate) fn sunless_source(chain: &MipChain, clipped: &MipChain) -> u32 {
    let skipped = (chain.levels.len() - clipped.levels.len()) as u32;
    chain.convolution_source().saturating_sub(skipped)
}

/// `prefilter_convolved` of `prefilter.wgsl`: the kernel-weighted average of `source`
/// about unit `n`, with `n.w` formed from polar angles as the shader does.
pub fn prefilter_convolved(source: &Level, kernels: &[f32], layer: u32, n: DVec3) -> DVec3 {
    let uv_n = direction_to_uv(n);
    let (sin_n, cos_n) = (uv_n.y * PI).sin_cos();
    let cos_dphi: Vec<f64> = (0..source.width)
        .map(|i| (((i as f64 + 0.5) / source.width as f64 - uv_n.x) * 2.0 * PI).cos())
        .collect();
    let mut sum = DVec3::ZERO;
    let mut weight = 0.0;
    for j in 0..source.height {
        let omega = source.texel_solid_angle(j);
        let (sin_t, cos_t) = ((j as f64 + 0.5) / source.height as f64 * PI).sin_cos();
        let (a, b) = (cos_n * cos_t, sin_n * sin_t);
        for (i, cos_dphi) in cos_dphi.iter().enumerate() {
            let i = i as u32;
            let w = kernel_at(kernels, layer, a + b * cos_dphi) * omega;
            sum += source.texel(i, j) * w;
            weight += w;
        }
    }
    if weight < WEIGHT_EPSILON {
        return DVec3::ZERO;
    }
    sum / weight
}

/// `specular_samples` of `prefilter.wgsl`: GGX samples per texel of specular layer
/// `layer`: the rough layers are small (`specular_mip`) and read levels no coarser than
/// [`FIS_MIN_WIDTH`], so they take more samples at little cost.
pub(crate) fn specular_samples(layer: u32) -> u32 {
    match layer {
        0 | 1 => SPECULAR_SAMPLES,
        2 => 2 * SPECULAR_SAMPLES,
        _ => 4 * SPECULAR_SAMPLES,
    }
}

/// The coarsest mip level filtered importance sampling reads in `chain`: the last at
/// least [`FIS_MIN_WIDTH`] wide (level 0 for a narrower map).
pub(crate) fn fis_max_level(chain: &MipChain) -> u32 {
    chain
        .levels
        .iter()
        .rposition(|l| l.width >= FIS_MIN_WIDTH)
        .unwrap_or(0) as u32
}

/// Size of the specular texture's level 0 for a map `width` wide.
pub(crate) fn specular_size(width: u32) -> (u32, u32) {
    let w = width.clamp(2, SPECULAR_WIDTH);
    (w, w / 2)
}

/// `specular_mip` of `environment.wgsl`: the mip level specular layer `layer` is stored at
/// in a texture of `levels` mip levels: roughness 0 and 1/6 at full size, 1/3 at half,
/// rougher at a quarter (the GGX lobe at roughness 1/2 is about 14 degrees wide, 10 texels
/// of a 64-wide layer), so the rough layers cost a sixteenth of the samples.
pub(crate) fn specular_mip(layer: u32, levels: u32) -> u32 {
    let m = match layer {
        0 | 1 => 0,
        2 => 1,
        _ => 2,
    };
    m.min(levels - 1)
}

/// Mip levels of the specular texture for a map `width` wide (fewer for tiny maps: the
/// smallest level is at least 2 x 1).
pub(crate) fn specular_mip_levels(width: u32) -> u32 {
    let (_, h) = specular_size(width);
    SPECULAR_MIP_LEVELS.min(h.ilog2() + 1)
}

/// The prefiltered layers (every value rounded to f16, as the GPU stores them).
#[derive(Clone, Debug, PartialEq)]
pub struct Prefiltered {
    /// `SPECULAR_LEVELS` layers, layer `k` of `specular_size` halved
    /// `specular_mip``(k)` times.
    pub specular: Vec<Level>,
    /// `1 + CONVOLVED_LEVELS` layers, [`CONVOLVED_WIDTH`] wide: irradiance, then the
    /// multiple-scattering kernels.
    pub convolved: Vec<Level>,
}

/// A `width x height` layer whose texels are `f` of their centres' directions, rounded to
/// f16 as the GPU stores them (rayon over the texels).
pub fn layer(width: u32, height: u32, f: impl Fn(DVec3) -> DVec3 + Sync) -> Level {
    let texels = (0..width * height)
        .into_par_iter()
        .map(|k| {
            let uv = DVec2::new(
                ((k % width) as f64 + 0.5) / width as f64,
                ((k / width) as f64 + 0.5) / height as f64,
            );
            let v = f(uv_to_direction(uv)).as_vec3();
            [f16_round(v.x), f16_round(v.y), f16_round(v.z), 1.0]
        })
        .collect();
    Level {
        width,
        height,
        texels,
    }
}

impl Prefiltered {
    /// Prefilters on the CPU (rayon) for `geometry`: what `gpu::EnvironmentTextures`
    /// computes on the GPU.
    pub fn new(chain: &MipChain, kernels: &[f32], geometry: Geometry) -> Self {
        let bright = Bright::new(chain);
        let (sampled, excess) = match &bright {
            Some(b) => (&b.chain, &b.texels[..]),
            None => (chain, &[][..]),
        };
        let source = &chain.levels[chain.convolution_source() as usize];
        let width = chain.levels[0].width;
        Self::from_sources(width, (chain, sampled, excess), source, kernels, geometry)
    }

    /// The layers without the map's sun ([`crate::environment::Sun`]): every layer from
    /// `bright`'s clipped chain, no excess added, the convolved layers summed over its
    /// level of the convolution source's width. The balls that take the sun as a light read
    /// these.
    pub(crate) fn sunless(
        chain: &MipChain,
        bright: &Bright,
        kernels: &[f32],
        geometry: Geometry,
    ) -> Self {
        let clipped = &bright.chain;
        let source = &clipped.levels[sunless_source(chain, clipped) as usize];
        let width = chain.levels[0].width;
        Self::from_sources(width, (clipped, clipped, &[]), source, kernels, geometry)
    }

    /// The layers of a map `width` texels across: the mirror layer from `mirror`, the
    /// sampled ones from `sampled` plus `excess`, the convolved ones summed over `source`.
    fn from_sources(
        width: u32,
        (mirror, sampled, excess): (&MipChain, &MipChain, &[BrightTexel]),
        source: &Level,
        kernels: &[f32],
        geometry: Geometry,
    ) -> Self {
        let (sw, sh) = specular_size(width);
        // The mirror layer reads `mirror` at this layer's scale (a clipped chain may start
        // narrower than the layer: its level 0, magnified).
        let lod0 = (mirror.levels[0].width as f64 / sw as f64).log2();
        let levels = specular_mip_levels(width);
        let specular = (0..SPECULAR_LEVELS)
            .map(|k| {
                let m = specular_mip(k, levels);
                let (w, h) = (sw >> m, sh >> m);
                if k == 0 {
                    // Roughness 0: the mirror, the map read at this layer's scale.
                    layer(w, h, |r| mirror.sample(r, lod0))
                } else {
                    let roughness = specular_roughness(k);
                    let samples = specular_samples(k);
                    layer(w, h, |r| {
                        prefilter_specular(sampled, excess, r, roughness, geometry, samples)
                    })
                }
            })
            .collect();
        let cw = CONVOLVED_WIDTH;
        let convolved = (0..=CONVOLVED_LEVELS)
            .map(|j| layer(cw, cw / 2, |n| prefilter_convolved(source, kernels, j, n)))
            .collect();
        Prefiltered {
            specular,
            convolved,
        }
    }

    /// `env_specular` of `environment.wgsl`: the prefiltered radiance about map-frame
    /// direction `r` at `roughness`, linear between the two layers around it.
    pub fn specular(&self, r: DVec3, roughness: f64) -> DVec3 {
        let uv = direction_to_uv(r);
        let s = roughness.clamp(0.0, 1.0) * (SPECULAR_LEVELS - 1) as f64;
        let k0 = (s.floor() as usize).min(SPECULAR_LEVELS as usize - 2);
        let f = s - k0 as f64;
        let a = self.specular[k0].bilinear(uv);
        let b = self.specular[k0 + 1].bilinear(uv);
        a.lerp(b, f)
    }

    /// `env_irradiance` of `environment.wgsl`: irradiance about map-frame normal `n`, over
    /// pi (the radiance of a white Lambertian surface).
    pub(crate) fn irradiance(&self, n: DVec3) -> DVec3 {
        self.convolved[0].bilinear(direction_to_uv(n))
    }

    /// `env_multiple` of `environment.wgsl`: `int (1 - E(mu_i)) mu_i L dw_i / (pi (1 -
    /// E_avg))` about map-frame normal `n` at `roughness`, linear between the two layers
    /// around it.
    pub fn multiple(&self, n: DVec3, roughness: f64) -> DVec3 {
        let uv = direction_to_uv(n);
        let s = roughness.clamp(0.0, 1.0) * (CONVOLVED_LEVELS - 1) as f64;
        let k0 = (s.floor() as usize).min(CONVOLVED_LEVELS as usize - 2);
        let f = s - k0 as f64;
        let a = self.convolved[k0 + 1].bilinear(uv);
        let b = self.convolved[k0 + 2].bilinear(uv);
        a.lerp(b, f)
    }
}

/// Where a map's mip chain is built, for [`crate::environment::EnvMap::check_chain_memory`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ChainOn {
    /// The GPU renderer's path, once the map is read: its mip chain (RGBA f32 values, 16 a
    /// texel and a third more for the smaller levels: 21.3), the texture (f16, 8 and a
    /// third: 10.7; lavapipe keeps it in the host's memory), and level 0's f16 upload bytes
    /// and wgpu's staging copy of them (8 each, transient). Issue 28, 3: an 8192x4096 map on
    /// lavapipe fails between 2.8 and 3.0 GB of address space with 1.4 GB mapped before the
    /// chain, so it needs 1.4 to 1.6 GB more: 48 bytes a texel is the upper end.
    Gpu,
    /// The CPU renderers': the mip chain (the prefiltered layers are small). Issue 28, 3: an
    /// 8192x4096 map renders in 1.5 GB of address space, not 1.3: 22 bytes a texel.
    Cpu,
}

impl ChainOn {
    /// Bytes a map texel adds on this path (see the variants).
    pub(crate) fn bytes_per_texel(self) -> u64 {
        match self {
            ChainOn::Gpu => 48,
            ChainOn::Cpu => 22,
        }
    }
}
