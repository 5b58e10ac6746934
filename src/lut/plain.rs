//! The read of an engine that will not port ours: a plain bilinear `textureSample` with
//! clamp-to-edge (no mipmaps) at
//! `uv = (mu (N - 1) / N + 0.5 / N, roughness (M - 1) / M + 0.5 / M)` for a table of
//! `N x M` texels (mu x roughness), modelled on the CPU in f32.
//!
//! The sampler maps `u` to the texel space `p = u N - 0.5` and blends texels `floor(p)` and
//! `floor(p) + 1` (clamped to the edge) with weight `fract(p)` (Vulkan's and WebGPU's
//! linear filter). With the uv above, `p = mu (N - 1)`: texel `i` sits at `mu = i / (N - 1)`,
//! the end-point convention of [`super::Centres::Endpoints`], so a table with a linear mu
//! axis and a roughness axis linear over `[0, 1]` (the uniform layout,
//! [`super::LayoutKind::Uniform`]) is read correctly by it.
//!
//! Real GPUs quantise the filter weight to a few fractional bits (Vulkan requires at least 4
//! `subTexelPrecisionBits`; 8 is common); [`bilinear_clamped`] takes that as an option, the
//! measurement of the uniform layout uses exact f32 weights.

use super::Tables;

/// The texture coordinate `(u, v)` of a plain read at `(mu, roughness)` of a table of
/// `n x m` texels, in f32 as a shader computes it.
#[cfg(test)]
pub(crate) fn plain_uv(mu: f32, roughness: f32, n: usize, m: usize) -> (f32, f32) {
    let axis = |x: f32, n: usize| {
        let n = n as f32;
        x * ((n - 1.0) / n) + 0.5 / n
    };
    (axis(mu, n), axis(roughness, m))
}

/// The sampler's half of one axis: texel `i0`, texel `i1` (both clamped to the edge), and
/// the weight of `i1`, quantised to `weight_bits` fractional bits when given.
#[cfg(test)]
fn span(u: f32, n: usize, weight_bits: Option<u32>) -> (usize, usize, f32) {
    let p = u * n as f32 - 0.5;
    let floor = p.floor();
    let mut w = p - floor;
    if let Some(bits) = weight_bits {
        let scale = (1u64 << bits.min(24)) as f32;
        w = (w * scale).round() / scale;
    }
    let last = n.saturating_sub(1) as f32;
    // NaN coordinates clamp to texel 0 (`f32::clamp` would keep the NaN).
    let clamp = |x: f32| if x >= 0.0 { x.min(last) as usize } else { 0 };
    (
        clamp(floor),
        clamp(floor + 1.0),
        if w.is_nan() { 0.0 } else { w },
    )
}

/// Bilinear sample at `(u, v)` of `texels` (`width x height`, row-major, row 0 at `v = 0`)
/// with clamp-to-edge addressing: the weighted sum of the four texels around
/// `(u width - 0.5, v height - 0.5)`, weights `(1 - a)(1 - b)`, `a (1 - b)`, `(1 - a) b`,
/// `a b` in f32. `weight_bits`: quantise `a` and `b` to that many fractional bits (None:
/// exact f32 weights).
#[cfg(test)]
pub(crate) fn bilinear_clamped(
    texels: &[f32],
    width: usize,
    height: usize,
    (u, v): (f32, f32),
    weight_bits: Option<u32>,
) -> f32 {
    debug_assert_eq!(texels.len(), width * height);
    let (i0, i1, a) = span(u, width, weight_bits);
    let (j0, j1, b) = span(v, height, weight_bits);
    let t = |i: usize, j: usize| texels[j * width + i];
    t(i0, j0) * ((1.0 - a) * (1.0 - b))
        + t(i1, j0) * (a * (1.0 - b))
        + t(i0, j1) * ((1.0 - a) * b)
        + t(i1, j1) * (a * b)
}

impl Tables {
    /// `1 - E` as a plain bilinear read of the stored table at `(mu, roughness)` returns it
    /// (the red channel of the KTX2 file; see the module docs). Meaningful for the uniform
    /// layout, whose texels sit where this read expects them.
    #[cfg(test)]
    pub(crate) fn plain_loss(&self, mu: f32, roughness: f32, weight_bits: Option<u32>) -> f32 {
        let l = self.layout();
        let uv = plain_uv(mu, roughness, l.mu_size, l.r_size);
        bilinear_clamped(&self.stored_loss, l.mu_size, l.r_size, uv, weight_bits)
    }

    /// `1 - E_avg` as the same plain read of the green channel returns it: the row's value
    /// repeated along the row, so linear between rows.
    #[cfg(test)]
    pub(crate) fn plain_loss_avg(&self, roughness: f32, weight_bits: Option<u32>) -> f32 {
        let l = self.layout();
        let uv = plain_uv(0.5, roughness, 1, l.r_size);
        bilinear_clamped(&self.stored_loss_avg, 1, l.r_size, uv, weight_bits)
    }
}
