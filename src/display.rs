//! The display transform, mirrored name for name by `tone_map` in
//! `shaders/lighting.wgsl`: what both renderers apply to linear radiance for a PNG or a
//! window.

/// The display transform of `shaders/screen.wgsl` `tone_map` for one channel:
/// exposure, Reinhard `c / (c + 1)`, gamma 1/2.2.
pub fn tone_map(radiance: f64, exposure: f64) -> f64 {
    let c = (radiance * exposure).max(0.0);
    (c / (c + 1.0)).powf(1.0 / 2.2)
}

/// A display value in [0, 1] as an 8-bit unorm (round to nearest, as the GPU stores it).
pub fn to_unorm8(v: f64) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}
