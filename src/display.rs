//! The display transform: exposure, a tone mapper ([`ToneMap`]) and a transfer curve
//! ([`Transfer`]), mirrored function for function by `shaders/screen.wgsl` (each WGSL
//! function of the same name, in f32): what both renderers apply to linear radiance for a
//! PNG or a window. On an sRGB target (`*Srgb` formats) the GPU writes the display value
//! decoded to linear (`target_value`) and the hardware encodes it, so that the target
//! holds the same display value as a plain `*Unorm` one (docs/design/library.md, "Colour").
//!
//! Each curve clamps its input to `[0, MAX_DISPLAY_RADIANCE]` after exposure (NaN to 0),
//! so negative, infinite or NaN radiance gives a display value in `[0, 1]`, never NaN.

use glam::DVec3;

/// The largest exposed radiance the tone mappers take (larger values, infinity included,
/// are clamped to it): every curve has reached its white long before (Reinhard's
/// `c / (c + 1)` is within 1e-6 of 1, the others saturate below 20), and its squares and
/// products stay far inside f32.
pub(crate) const MAX_DISPLAY_RADIANCE: f64 = 1.0e6;

/// Below this `p + 1 - 2 K_s` is never (it is at least `1 - K_s` for `p >= K_s`); the
/// divisions of [`tone_map_khronos_neutral`] and ACES' fit are guarded with it anyway.
pub(crate) const DISPLAY_EPSILON: f64 = 1e-9;

/// A tone mapper: how exposed linear radiance becomes display-linear values in `[0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ToneMap {
    /// Reinhard et al. 2002 (eq. 3), `c / (c + 1)` per channel: the homework's.
    Reinhard,
    /// Stephen Hill's fit of the ACES RRT + sRGB ODT (BakingLab, 2016): its input and
    /// output matrices around the rational fit.
    Aces,
    /// Troy Sobotka's AgX, base look (no punchy or golden), as fitted by Benjamin Wrensch's
    /// "minimal AgX" (2023): inset matrix, log2 encoding over [-12.47393, 4.026069] EV, the
    /// 6th-order polynomial fit of the sigmoid, outset matrix.
    Agx,
    /// The Khronos PBR Neutral tone mapper (Khronos 3D Commerce, 2024): made for material
    /// preview, it leaves base colours as they are up to its start of compression.
    KhronosNeutral,
    /// No tone mapping: clamped to `[0, 1]`.
    None,
}

impl ToneMap {
    /// Every tone mapper, in the order the help and the viewer list them.
    pub(crate) const ALL: [ToneMap; 5] = [
        ToneMap::Reinhard,
        ToneMap::Aces,
        ToneMap::Agx,
        ToneMap::KhronosNeutral,
        ToneMap::None,
    ];

    /// The name used on the command line and in scene files.
    pub(crate) fn name(self) -> &'static str {
        match self {
            ToneMap::Reinhard => "reinhard",
            ToneMap::Aces => "aces",
            ToneMap::Agx => "agx",
            ToneMap::KhronosNeutral => "khronos-neutral",
            ToneMap::None => "none",
        }
    }

    /// The value of the `TONE_MAP` override (`TONE_MAP_*` in `types.wgsl`, generated from
    /// this by src/gpu/tests/boundary.rs): its index in [`ToneMap::ALL`].
    pub(crate) fn code(self) -> u32 {
        ToneMap::ALL.iter().position(|&t| t == self).unwrap_or(0) as u32
    }
}

crate::named_enum!(ToneMap, "tone map");

/// A transfer curve: how display-linear values become the encoded values of an 8-bit image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Transfer {
    /// The sRGB curve of IEC 61966-2-1:1999 (linear toe, 1/2.4 power).
    Srgb,
    /// A pure `1/2.2` power: the homework's (the `games202` preset's).
    Gamma22,
}

impl Transfer {
    /// Every transfer curve, in a fixed order.
    pub(crate) const ALL: [Transfer; 2] = [Transfer::Srgb, Transfer::Gamma22];

    /// The name used in scene files.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Transfer::Srgb => "srgb",
            Transfer::Gamma22 => "gamma-2.2",
        }
    }

    /// The value of the `TRANSFER` override (`TRANSFER_*` in `types.wgsl`): its index in
    /// [`Transfer::ALL`].
    pub(crate) fn code(self) -> u32 {
        Transfer::ALL.iter().position(|&t| t == self).unwrap_or(0) as u32
    }
}

crate::named_enum!(Transfer, "transfer curve");

/// A tone mapper and a transfer curve: a scene's display transform
/// (`crate::scene::Scene::display`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct DisplayTransform {
    /// Exposed radiance to display-linear values.
    pub tone_map: ToneMap,
    /// Display-linear to encoded values.
    pub transfer: Transfer,
}

impl DisplayTransform {
    /// The homework's display: Reinhard, then gamma 1/2.2 (docs/design/reference-scene.md).
    pub(crate) const HOMEWORK: DisplayTransform = DisplayTransform {
        tone_map: ToneMap::Reinhard,
        transfer: Transfer::Gamma22,
    };
}

/// The encoded display value of linear `radiance` under `exposure`: `exposure`, the tone
/// mapper, the transfer curve (`display_value` of `screen.wgsl`).
pub(crate) fn display_value(radiance: DVec3, exposure: f64, display: DisplayTransform) -> DVec3 {
    let mapped = apply_tone_map(exposed(radiance, exposure), display.tone_map);
    encode_transfer(mapped, display.transfer)
}

/// The homework's display transform for one channel: `display_value` under
/// `DisplayTransform::HOMEWORK` (exposure, Reinhard `c / (c + 1)`, gamma 1/2.2), which
/// works channel by channel.
pub fn tone_map(radiance: f64, exposure: f64) -> f64 {
    display_value(DVec3::splat(radiance), exposure, DisplayTransform::HOMEWORK).x
}

/// What a display target holds for `radiance`: [`display_value`], or on an sRGB target
/// (`srgb`, whose hardware encodes what the shader writes) that value decoded with the sRGB
/// curve, so the stored bytes are the same (`target_value` of `screen.wgsl`). Under the
/// sRGB transfer curve that is the tone-mapped value itself.
pub(crate) fn target_value(
    radiance: DVec3,
    exposure: f64,
    display: DisplayTransform,
    srgb: bool,
) -> DVec3 {
    let mapped = apply_tone_map(exposed(radiance, exposure), display.tone_map);
    match (srgb, display.transfer) {
        (false, t) => encode_transfer(mapped, t),
        (true, Transfer::Srgb) => mapped,
        (true, t) => encode_transfer(mapped, t).map(decode_srgb),
    }
}

/// `radiance * exposure` clamped to `[0, MAX_DISPLAY_RADIANCE]`, NaN to 0 (`exposed` of
/// `screen.wgsl`).
pub(crate) fn exposed(radiance: DVec3, exposure: f64) -> DVec3 {
    (radiance * exposure).map(|c| {
        if c.is_nan() {
            0.0
        } else {
            c.clamp(0.0, MAX_DISPLAY_RADIANCE)
        }
    })
}

/// Exposed radiance `c` (non-negative, finite) through the tone mapper `mapper`, clamped
/// to `[0, 1]`.
pub(crate) fn apply_tone_map(c: DVec3, mapper: ToneMap) -> DVec3 {
    let mapped = match mapper {
        ToneMap::Reinhard => tone_map_reinhard(c),
        ToneMap::Aces => tone_map_aces(c),
        ToneMap::Agx => tone_map_agx(c),
        ToneMap::KhronosNeutral => tone_map_khronos_neutral(c),
        ToneMap::None => c,
    };
    mapped.clamp(DVec3::ZERO, DVec3::ONE)
}

/// Reinhard, Stark, Shirley and Ferwerda 2002, "Photographic Tone Reproduction for Digital
/// Images", eq. 3 (`L / (1 + L)`), per channel.
pub(crate) fn tone_map_reinhard(c: DVec3) -> DVec3 {
    c / (c + 1.0)
}

/// Stephen Hill's fit of the ACES reference rendering transform and sRGB output transform
/// (BakingLab `ACES.hlsl`, 2016): `M_out * rrt_odt_fit(M_in * c)`, the rows of each matrix
/// below as Hill gives them.
pub(crate) fn tone_map_aces(c: DVec3) -> DVec3 {
    let input = [
        [0.59719, 0.35458, 0.04823],
        [0.07600, 0.90834, 0.01566],
        [0.02840, 0.13383, 0.83777],
    ];
    let output = [
        [1.60475, -0.53108, -0.07367],
        [-0.10208, 1.10813, -0.00605],
        [-0.00327, -0.07276, 1.07602],
    ];
    let v = rows_times(input, c);
    let a = v * (v + 0.0245786) - 0.000090537;
    let b = v * (0.983729 * v + 0.4329510) + 0.238081;
    rows_times(output, a / b.max(DVec3::splat(DISPLAY_EPSILON)))
}

/// Sobotka's AgX, base look, in Wrensch's minimal fit (2023): the inset matrix, `log2`
/// clamped to [`AGX_MIN_EV`, `AGX_MAX_EV`] and normalised, the polynomial sigmoid, the
/// outset matrix. The sigmoid's output is display-encoded for a 2.2 power (Sobotka's
/// configuration), so it is decoded with `pow 2.2` to the display-linear value the
/// transfer curve then encodes.
pub(crate) fn tone_map_agx(c: DVec3) -> DVec3 {
    let inset = [
        [0.842479062253094, 0.0784335999999992, 0.0792237451477643],
        [0.0423282422610123, 0.878468636469772, 0.0791661274605434],
        [0.0423756549057051, 0.0784336, 0.879142973793104],
    ];
    let outset = [
        [1.19687900512017, -0.0980208811401368, -0.0990297440797205],
        [-0.0528968517574562, 1.15190312990417, -0.0989611768448433],
        [-0.0529716355144438, -0.0980434501171241, 1.15107367264116],
    ];
    let v = rows_times(inset, c).max(DVec3::splat(AGX_LOG_FLOOR));
    let ev = v
        .map(f64::log2)
        .clamp(DVec3::splat(AGX_MIN_EV), DVec3::splat(AGX_MAX_EV));
    let x = (ev - AGX_MIN_EV) / (AGX_MAX_EV - AGX_MIN_EV);
    let x2 = x * x;
    let x4 = x2 * x2;
    let s =
        15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2 + 0.1191 * x
            - 0.00232;
    rows_times(outset, s).max(DVec3::ZERO).powf(2.2)
}

/// AgX's darkest encoded exposure, in EV (`log2`) of the inset radiance.
pub(crate) const AGX_MIN_EV: f64 = -12.47393;
/// AgX's brightest encoded exposure, in EV.
pub(crate) const AGX_MAX_EV: f64 = 4.026069;
/// The inset radiance below which AgX takes no `log2` (black is its floor, `AGX_MIN_EV`).
pub(crate) const AGX_LOG_FLOOR: f64 = 1e-10;

/// Khronos PBR Neutral (the specification in KhronosGroup/ToneMapping, `PBR_Neutral`,
/// 2024): `F90 = 0.04`, `K_s = 0.8 - F90`, `K_d = 0.15`. An offset `f` (`x - x^2 / (4 F90)`
/// below `x = min(rgb) = 2 F90`, else `F90`) is taken off; where the peak `p` of the rest
/// exceeds `K_s`, it is compressed to `p_n = 1 - (1 - K_s)^2 / (p + 1 - 2 K_s)` and the
/// colour desaturated towards `p_n` with weight `1 - 1 / (K_d (p - p_n) + 1)`.
pub(crate) fn tone_map_khronos_neutral(c: DVec3) -> DVec3 {
    let (f90, k_d) = (0.04, 0.15);
    let k_s = 0.8 - f90;
    let x = c.min_element();
    let offset = if x < 2.0 * f90 {
        x - x * x / (4.0 * f90)
    } else {
        f90
    };
    let c = c - offset;
    let peak = c.max_element();
    if peak < k_s {
        return c;
    }
    let d = 1.0 - k_s;
    let new_peak = 1.0 - d * d / (peak + d - k_s).max(DISPLAY_EPSILON);
    let c = c * (new_peak / peak.max(DISPLAY_EPSILON));
    let g = 1.0 - 1.0 / (k_d * (peak - new_peak) + 1.0);
    c.lerp(DVec3::splat(new_peak), g)
}

/// `m * v` for the rows of `m`.
fn rows_times(m: [[f64; 3]; 3], v: DVec3) -> DVec3 {
    DVec3::new(
        DVec3::from_array(m[0]).dot(v),
        DVec3::from_array(m[1]).dot(v),
        DVec3::from_array(m[2]).dot(v),
    )
}

/// Display-linear `v` (in `[0, 1]`) through the transfer curve `t`.
pub(crate) fn encode_transfer(v: DVec3, t: Transfer) -> DVec3 {
    match t {
        Transfer::Srgb => v.map(encode_srgb),
        Transfer::Gamma22 => v.powf(1.0 / 2.2),
    }
}

/// The sRGB encoding of IEC 61966-2-1:1999: `12.92 v` up to `v = 0.0031308`, else
/// `1.055 v^(1/2.4) - 0.055`.
pub(crate) fn encode_srgb(v: f64) -> f64 {
    if v <= 0.0031308 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// The sRGB decoding of IEC 61966-2-1:1999, the inverse of [`encode_srgb`]: `v / 12.92` up
/// to `v = 0.04045`, else `((v + 0.055) / 1.055)^2.4`.
pub(crate) fn decode_srgb(v: f64) -> f64 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// A display value in [0, 1] as an 8-bit unorm (round to nearest, as the GPU stores it).
pub(crate) fn to_unorm8(v: f64) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

/// The RGBA8 pixel of linear `radiance` (alpha 255): `display_value`, each channel as
/// `to_unorm8`.
pub fn to_rgba8_pixel(radiance: DVec3, exposure: f64, display: DisplayTransform) -> [u8; 4] {
    let v = display_value(radiance, exposure, display);
    [to_unorm8(v.x), to_unorm8(v.y), to_unorm8(v.z), 255]
}
