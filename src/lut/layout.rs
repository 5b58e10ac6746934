//! Where each texel sits and how the shader reads it.
//!
//! ## Texel-centre convention (stated once)
//!
//! A table axis with `n` texels maps its coordinate `x` in `[0, 1]` to the continuous
//! texel index `p = clamp(x * scale + bias, 0, n - 1)`; texel `i` holds the value at the `x`
//! where `p = i`. Bilinear reads interpolate between `floor(p)` and `floor(p) + 1`.
//!
//! - `Endpoints` (the default layouts): `scale = n - 1`, `bias = 0`: texel `i` is at
//!   `x = i / (n - 1)`, so `x = 0` and `x = 1` are texel centres and never extrapolated.
//! - `HalfTexel` (the homework's, GL's texture convention): `scale = n`, `bias = -0.5`:
//!   texel `i` is at `x = (i + 0.5) / n`; the ends are clamped, not interpolated.
//!
//! The mu axis is linear, square-root, or warped by alpha ([`MuAxis`]); the roughness axis
//! is linear in the clamped roughness over `[r_min, 1]` ([`RAxis`]).
//!
//! Tables hold the missing energy `1 - E` and `1 - E_avg` rather than E: the lobe needs
//! exactly these, and they are small where E is near 1, where floating point keeps their
//! relative precision (docs/design/gpu-tables.md, "Storage").
//! Tables are stored row-major: row `j` (roughness) holds `mu_size` texels.

use crate::brdf::{roughness_clamped, ROUGHNESS_MIN};

/// The mapping from mu to the table's x coordinate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MuAxis {
    /// `x = mu` (the homework's).
    Linear,
    /// `x = sqrt(mu)` (the first candidate: docs/design/gpu-tables.md, "Layouts").
    Sqrt,
    /// `x = mu (1 + a) / (mu + a)`, `a = alpha` at the read roughness (the default).
    ///
    /// At low roughness E has a feature at grazing angles whose width in mu scales with
    /// alpha (the dip where `mu ~ alpha`, then the rise to E(0)); in `(mu, roughness)` it sits
    /// on a curve that no fixed mu axis follows, and bilinear reads across roughness rows
    /// blur it (3e-2 error with `Sqrt` at 64 x 64). This warp pins the feature to the same
    /// x in every row (`mu = a` maps to `x = (1 + a) / 2`), keeps x in `[0, 1]` with
    /// `x(0) = 0`, `x(1) = 1`, and tends to the identity as alpha grows. Measured: 1.1e-4
    /// max read error at 64 x 64 (docs/benchmarks.md, "Measured results").
    Warped,
}

impl MuAxis {
    /// Every value, in a fixed order (their names parse in scene files and table files).
    pub(crate) const ALL: [MuAxis; 3] = [MuAxis::Linear, MuAxis::Sqrt, MuAxis::Warped];

    /// The name in files (the KTX2 layout text).
    pub(crate) fn name(self) -> &'static str {
        match self {
            MuAxis::Linear => "linear",
            MuAxis::Sqrt => "sqrt",
            MuAxis::Warped => "warped",
        }
    }

    /// The coordinate of `mu`, in f32 as the shader computes it (`mu_coord` in
    /// `shaders/lut.wgsl`); `alpha` is the clamped alpha of the read. `mu + alpha >= alpha_min
    /// > 0`, so the warp never divides by zero.
    pub(crate) fn coord(self, mu: f32, alpha: f32) -> f32 {
        let mu = mu.clamp(0.0, 1.0);
        match self {
            MuAxis::Linear => mu,
            MuAxis::Sqrt => mu.sqrt(),
            MuAxis::Warped => mu * (1.0 + alpha) / (mu + alpha),
        }
    }

    /// The mu at coordinate `x` in a row of the given alpha (exact inverse, f64).
    pub(crate) fn value(self, x: f64, alpha: f64) -> f64 {
        match self {
            MuAxis::Linear => x,
            MuAxis::Sqrt => x * x,
            MuAxis::Warped => (x * alpha / (1.0 + alpha - x)).clamp(0.0, 1.0),
        }
    }

    /// The coordinate of `mu` in f64 (the bake's exact version of [`MuAxis::coord`]).
    pub(crate) fn coord_f64(self, mu: f64, alpha: f64) -> f64 {
        let mu = mu.clamp(0.0, 1.0);
        match self {
            MuAxis::Linear => mu,
            MuAxis::Sqrt => mu.sqrt(),
            MuAxis::Warped => mu * (1.0 + alpha) / (mu + alpha),
        }
    }

    /// The id the shader switches on (`MU_AXIS_*` in `shaders/lut.wgsl`).
    pub(crate) fn id(self) -> u32 {
        match self {
            MuAxis::Linear => 0,
            MuAxis::Sqrt => 1,
            MuAxis::Warped => 2,
        }
    }
}

/// How a read interpolates `1 - E_avg` between two roughness rows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum EAvgRead {
    /// Linear (the homework's).
    Linear,
    /// As a power law through the two rows: `a (r / r_a)^p` with `p` such that it meets `b`
    /// at `r_b`, i.e. linear in `ln(1 - E_avg)` against `ln r`.
    ///
    /// At low roughness `1 - E_avg` follows a power of roughness (about r^2 with Schlick G,
    /// r^4 with Smith's), and `f_ms` divides by it: a linear read between rows 1/63 apart
    /// is off by 40 % of `1 - E_avg` at roughness 0.025 and breaks the furnace by 4e-2; a
    /// geometric read in r, 7 %. The power-law read is exact for any exponent.
    PowerLaw,
}

impl EAvgRead {
    /// Every value, in a fixed order (their names parse in scene files and table files).
    pub(crate) const ALL: [EAvgRead; 2] = [EAvgRead::Linear, EAvgRead::PowerLaw];

    /// The name in files (the KTX2 layout text).
    pub(crate) fn name(self) -> &'static str {
        match self {
            EAvgRead::Linear => "linear",
            EAvgRead::PowerLaw => "power-law",
        }
    }

    /// The id the shader switches on (`E_AVG_READ_*` in `shaders/lut.wgsl`).
    pub(crate) fn id(self) -> u32 {
        match self {
            EAvgRead::Linear => 0,
            EAvgRead::PowerLaw => 1,
        }
    }
}

/// Smallest stored `1 - E_avg` a power-law read takes the logarithm of: far below any value
/// the model produces (1.3e-6 at roughness 0.02 with Smith G), far above f32's subnormals.
pub(crate) const LOSS_AVG_MIN: f32 = 1e-20;

/// The range the roughness axis spans, linearly.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RAxis {
    /// `[0, 1]` (the homework's): rows below ROUGHNESS_MIN hold the clamp's values.
    Full,
    /// `[ROUGHNESS_MIN, 1]`: no row below the clamp. Rows below it would hold the clamp's
    /// values at other coordinates, and a read at the clamp would lean towards the next row
    /// (3e-2 furnace error at roughness 0 with Schlick G).
    Clamped,
}

impl RAxis {
    /// Roughness of the first row.
    pub(crate) fn r_min(self) -> f64 {
        match self {
            RAxis::Full => 0.0,
            RAxis::Clamped => ROUGHNESS_MIN,
        }
    }
}

/// Where the texel centres sit (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Centres {
    /// Texel `i` at `x = i / (n - 1)`: both ends are texel centres (the default layouts).
    Endpoints,
    /// Texel `i` at `x = (i + 0.5) / n` (the homework's, GL's texture convention).
    HalfTexel,
}

impl Centres {
    /// Every value, in a fixed order (their names parse in scene files and table files).
    pub(crate) const ALL: [Centres; 2] = [Centres::Endpoints, Centres::HalfTexel];

    /// The name in files (the KTX2 layout text).
    pub(crate) fn name(self) -> &'static str {
        match self {
            Centres::Endpoints => "endpoints",
            Centres::HalfTexel => "half-texel",
        }
    }
}

/// How texel values are stored on the GPU.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Storage {
    /// `R32Float`.
    F32,
    /// `R16Float`.
    F16,
    /// `R8Unorm` (the homework's 8-bit PNG): step 1/255.
    Unorm8,
}

impl Storage {
    /// Every storage, in a fixed order.
    pub const ALL: [Storage; 3] = [Storage::F32, Storage::F16, Storage::Unorm8];

    /// The name used on the command line and in messages.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Storage::F32 => "f32",
            Storage::F16 => "f16",
            Storage::Unorm8 => "unorm8",
        }
    }

    /// The value the GPU reads back after storing `v`.
    pub(crate) fn quantize(self, v: f64) -> f32 {
        match self {
            Storage::F32 => v as f32,
            Storage::F16 => half::f16::from_f64(v).to_f32(),
            Storage::Unorm8 => ((v.clamp(0.0, 1.0) * 255.0).round() / 255.0) as f32,
        }
    }

    /// Bytes a texel takes on the GPU.
    pub fn bytes_per_texel(self) -> usize {
        match self {
            Storage::F32 => 4,
            Storage::F16 => 2,
            Storage::Unorm8 => 1,
        }
    }
}

/// A named table layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LayoutKind {
    /// The default: alpha-warped mu axis, texel centres on the end points, f32, 64 x 64.
    Warped,
    /// `x = sqrt(mu)`, texel centres on the end points, f32, 64 x 64.
    SqrtMu,
    /// The homework's: linear mu and roughness, centres at `(i + 0.5) / n`, 128 x 128, 8 bit.
    Games202,
    /// For engines that will not port our read: linear mu, roughness linear over `[0, 1]`,
    /// texel centres on the end points, f32, E_avg read linearly; a plain bilinear
    /// `textureSample` with clamp-to-edge at `uv = (mu (N-1)/N + 0.5/N, r (M-1)/M + 0.5/M)`
    /// reads it (`super::plain`). Its default size ([`UNIFORM_MU_SIZE`] x
    /// [`UNIFORM_R_SIZE`], 128 x 128) is the engines'; `UNIFORM_PRECISE_MU_SIZE` x
    /// `UNIFORM_PRECISE_R_SIZE` keeps a plain read within 1e-3 of the reference at
    /// roughness >= 0.1, with f32 or 8-bit filter weights.
    Uniform,
}

impl LayoutKind {
    /// Every named layout, in a fixed order.
    pub(crate) const ALL: [LayoutKind; 4] = [
        LayoutKind::Warped,
        LayoutKind::SqrtMu,
        LayoutKind::Games202,
        LayoutKind::Uniform,
    ];

    /// The name used on the command line and in messages.
    pub(crate) fn name(self) -> &'static str {
        match self {
            LayoutKind::Warped => "warped",
            LayoutKind::SqrtMu => "sqrt-mu",
            LayoutKind::Games202 => "games202",
            LayoutKind::Uniform => "uniform",
        }
    }
}

crate::named_enum!(MuAxis, "mu axis");
crate::named_enum!(EAvgRead, "E_avg read");
crate::named_enum!(Centres, "texel-centre convention");
crate::named_enum!(Storage, "storage");
crate::named_enum!(LayoutKind, "layout");

/// A table layout: axes, sizes, storage.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Layout {
    /// The named layout it was made from ([`Layout::of_kind`]; [`Layout::with_size`] and
    /// [`Layout::with_storage`] keep it).
    pub kind: LayoutKind,
    /// How mu maps to the table's x coordinate.
    pub mu_axis: MuAxis,
    /// The range of the roughness axis.
    pub r_axis: RAxis,
    /// How a read interpolates `1 - E_avg` between rows.
    pub e_avg_read: EAvgRead,
    /// Where the texel centres sit.
    pub centres: Centres,
    /// Texels along mu (a row's length).
    pub mu_size: usize,
    /// Texels along roughness (rows).
    pub r_size: usize,
    /// How texel values are stored on the GPU.
    pub storage: Storage,
}

/// Default texels along mu. The default table size (mu x roughness) was chosen by
/// measurement: the smallest that keeps the read-path error within max 1e-3 and mean 1e-4
/// (see docs/benchmarks.md, "Measured results").
pub(crate) const DEFAULT_MU_SIZE: usize = 64;
/// Default texels along roughness (see [`DEFAULT_MU_SIZE`]).
pub(crate) const DEFAULT_R_SIZE: usize = 64;

/// Default size of the [`LayoutKind::Uniform`] layout (mu x roughness): 128 x 128, the
/// size engines ship such tables at (32^2 to 128^2; Filament's DFG table is 128 x 128),
/// 131 KB as R32G32_SFLOAT. A plain bilinear read (`super::plain`) of it is within 1e-3
/// of the reference on average but not at grazing mu and low roughness, where a linear
/// mu axis needs texels 4.6e-4 apart: docs/accuracy.md, "Tables for engines (KTX2,
/// uniform layout)", states its error and that of 64 x 64 (`src/lut/ktx2/tests.rs` holds
/// them). `UNIFORM_PRECISE_MU_SIZE` x `UNIFORM_PRECISE_R_SIZE` is the size for 1e-3
/// everywhere.
pub const UNIFORM_MU_SIZE: usize = 128;
/// Default roughness rows of the [`LayoutKind::Uniform`] layout (see [`UNIFORM_MU_SIZE`]).
pub const UNIFORM_R_SIZE: usize = 128;

/// The smallest [`LayoutKind::Uniform`] size (mu x roughness) whose plain bilinear read
/// ([`super::plain`]) stays within 1e-3 of the reference over mu in `[0, 1]` and roughness
/// in `[0.1, 1]`, chosen by measurement (`src/lut/ktx2/tests.rs`), for Schlick and
/// height-correlated Smith G, with f32 filter weights and with the 8-bit fractional
/// weights of real GPUs' samplers. The error lives at grazing mu and roughness 0.1, where a
/// linear mu axis needs texels 4.6e-4 apart, and between rows there. With f32 weights
/// 2176 x 100 is enough (9.75e-4, Schlick) but 8-bit weights take it to 1.02e-3; 2304 x 112
/// leaves a margin for both. 2.1 MB as R32G32_SFLOAT (`bake --layout uniform --size
/// 2304x112`).
#[cfg(test)]
pub(crate) const UNIFORM_PRECISE_MU_SIZE: usize = 2304;
/// Roughness rows of the 1e-3 uniform size (see [`UNIFORM_PRECISE_MU_SIZE`]).
#[cfg(test)]
pub(crate) const UNIFORM_PRECISE_R_SIZE: usize = 112;

impl Default for Layout {
    fn default() -> Self {
        Layout::of_kind(LayoutKind::Warped)
    }
}

impl Layout {
    /// A layout with its own default size and storage.
    pub fn of_kind(kind: LayoutKind) -> Self {
        match kind {
            LayoutKind::Warped | LayoutKind::SqrtMu => Layout {
                kind,
                mu_axis: if kind == LayoutKind::Warped {
                    MuAxis::Warped
                } else {
                    MuAxis::Sqrt
                },
                r_axis: RAxis::Clamped,
                e_avg_read: if kind == LayoutKind::Warped {
                    EAvgRead::PowerLaw
                } else {
                    EAvgRead::Linear
                },
                centres: Centres::Endpoints,
                mu_size: DEFAULT_MU_SIZE,
                r_size: DEFAULT_R_SIZE,
                storage: Storage::F32,
            },
            LayoutKind::Games202 => Layout {
                kind,
                mu_axis: MuAxis::Linear,
                r_axis: RAxis::Full,
                e_avg_read: EAvgRead::Linear,
                centres: Centres::HalfTexel,
                mu_size: 128,
                r_size: 128,
                storage: Storage::Unorm8,
            },
            LayoutKind::Uniform => Layout {
                kind,
                mu_axis: MuAxis::Linear,
                r_axis: RAxis::Full,
                // What a plain bilinear read of the second channel does.
                e_avg_read: EAvgRead::Linear,
                centres: Centres::Endpoints,
                mu_size: UNIFORM_MU_SIZE,
                r_size: UNIFORM_R_SIZE,
                storage: Storage::F32,
            },
        }
    }

    /// This layout with `mu_size x r_size` texels.
    pub fn with_size(mut self, mu_size: usize, r_size: usize) -> Self {
        self.mu_size = mu_size;
        self.r_size = r_size;
        self
    }

    /// This layout with its texels stored as `storage`.
    pub fn with_storage(mut self, storage: Storage) -> Self {
        self.storage = storage;
        self
    }

    /// `(scale, bias)` of an axis with `n` texels (see the module docs).
    pub(crate) fn scale_bias(&self, n: usize) -> (f64, f64) {
        match self.centres {
            Centres::Endpoints => ((n as f64 - 1.0).max(0.0), 0.0),
            Centres::HalfTexel => (n as f64, -0.5),
        }
    }

    /// The table coordinate x of texel `i` on an axis of `n` texels.
    pub(crate) fn texel_coord(&self, i: usize, n: usize) -> f64 {
        let (scale, bias) = self.scale_bias(n);
        if scale == 0.0 {
            return 0.0;
        }
        ((i as f64 - bias) / scale).clamp(0.0, 1.0)
    }

    /// mu of the texel in column `i` of row `j`.
    pub fn mu_of_texel(&self, i: usize, j: usize) -> f64 {
        let alpha = crate::brdf::alpha_from_roughness(self.roughness_of_texel(j));
        self.mu_axis.value(self.texel_coord(i, self.mu_size), alpha)
    }

    /// Roughness of the texel in row `j`.
    pub fn roughness_of_texel(&self, j: usize) -> f64 {
        let r_min = self.r_axis.r_min();
        r_min + (1.0 - r_min) * self.texel_coord(j, self.r_size)
    }

    /// Roughness of row `j` as the shader's E_avg read uses it: clamped, in f32.
    pub(crate) fn row_roughness(&self, j: usize) -> f32 {
        roughness_coord(self.roughness_of_texel(j) as f32)
    }

    /// The roughness axis coordinate of a read, in f32 as the shader computes it (`r_coord`
    /// in `shaders/lut.wgsl`): the clamped roughness mapped from `[r_min, 1]` to `[0, 1]`.
    pub(crate) fn r_coord(&self, roughness: f32) -> f32 {
        let r_min = self.r_axis.r_min() as f32;
        ((roughness_coord(roughness) - r_min) / (1.0 - r_min)).clamp(0.0, 1.0)
    }

    /// Texels of the E table: `mu_size * r_size`.
    pub fn texels(&self) -> usize {
        self.mu_size * self.r_size
    }

    /// GPU memory of the E table plus the E_avg row, in bytes.
    pub fn bytes(&self) -> usize {
        (self.texels() + self.r_size) * self.storage.bytes_per_texel()
    }
}

/// How a shader addresses and reads a table: everything `lut_loss`, `lut_loss_avg` and
/// their kin in the crate's WGSL ([`crate::wgsl::KULLA_CONTY`], `struct LutParams`) take
/// besides the textures. A plain `repr(C)` struct laid out as the WGSL one in a uniform
/// buffer (48 bytes), so a host uploads it with `bytemuck::bytes_of`.
///
/// Texel `i` of an axis of `n` texels sits where `x * scale + bias = i` (the module docs'
/// texel-centre convention); `x` is the mu axis's coordinate of mu (`MuAxis::coord`, by
/// `mu_axis`) or the roughness coordinate `(roughness - r_min) / (1 - r_min)`.
///
/// ```
/// use shadeballs::{Layout, LayoutKind};
/// // The homework's layout: linear axes, texel centres at (i + 0.5) / n.
/// let p = Layout::of_kind(LayoutKind::Games202).lut_params();
/// let texel = |x: f32, scale: f32, bias: f32, n: u32| (x * scale + bias).clamp(0.0, (n - 1) as f32);
/// // mu = 0.5 falls between texels 63 and 64 of 128; roughness 1 on the last row.
/// assert_eq!(texel(0.5, p.mu_scale, p.mu_bias, p.mu_size), 63.5);
/// assert_eq!(texel(1.0, p.r_scale, p.r_bias, p.r_size), 127.0);
/// // The default layout puts texel centres on the end points: x = 1 is the last texel.
/// let p = Layout::default().lut_params();
/// assert_eq!(p.mu_scale + p.mu_bias, (p.mu_size - 1) as f32);
/// ```
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LutParams {
    /// Scale of the mu axis (`Layout::scale_bias` of `mu_size`).
    pub mu_scale: f32,
    /// Bias of the mu axis.
    pub mu_bias: f32,
    /// Scale of the roughness axis (of `r_size`; 0 for a scene's rows, where each ball
    /// names its row).
    pub r_scale: f32,
    /// Bias of the roughness axis (0 for a scene's rows).
    pub r_bias: f32,
    /// Texels along mu.
    pub mu_size: u32,
    /// Texels along roughness (rows).
    pub r_size: u32,
    /// `MuAxis::id`: `MU_AXIS_LINEAR`, `MU_AXIS_SQRT` or `MU_AXIS_WARPED` in the WGSL.
    pub mu_axis: u32,
    /// `EAvgRead::id`: `E_AVG_READ_LINEAR` or `E_AVG_READ_POWER_LAW`.
    pub e_avg_read: u32,
    /// Roughness of the first row (the roughness axis spans `[r_min, 1]`).
    pub r_min: f32,
    /// Padding to the WGSL struct's 48-byte uniform size (three scalars, as in the WGSL,
    /// where a vector of three would align to 16 bytes; no name ends in a digit, which
    /// naga's WGSL writer renames and naga_oil then rejects); zero.
    pub padding_a: f32,
    /// Padding; zero.
    pub padding_b: f32,
    /// Padding; zero.
    pub padding_c: f32,
}

impl Layout {
    /// The read parameters of a table of this layout.
    pub fn lut_params(&self) -> LutParams {
        let (sx, bx) = self.scale_bias(self.mu_size);
        let (sy, by) = self.scale_bias(self.r_size);
        LutParams {
            mu_scale: sx as f32,
            mu_bias: bx as f32,
            r_scale: sy as f32,
            r_bias: by as f32,
            mu_size: self.mu_size as u32,
            r_size: self.r_size as u32,
            mu_axis: self.mu_axis.id(),
            e_avg_read: self.e_avg_read.id(),
            r_min: self.r_axis.r_min() as f32,
            padding_a: 0.0,
            padding_b: 0.0,
            padding_c: 0.0,
        }
    }
}

/// The two texels and the weight of the second, for a bilinear read along one axis:
/// exactly the f32 arithmetic of `lut_texel_span` in `shaders/lut.wgsl`.
pub(crate) fn lut_texel_span(x: f32, n: usize, scale: f32, bias: f32) -> (usize, usize, f32) {
    if n <= 1 {
        return (0, 0, 0.0);
    }
    let last = (n - 1) as f32;
    let p = (x * scale + bias).clamp(0.0, last);
    let i0 = p.floor().min(last - 1.0);
    let i = i0 as usize;
    (i, i + 1, p - i0)
}

/// The clamped roughness the model uses, as the shader computes it (f32,
/// `roughness_clamped` in `shaders/brdf.wgsl`).
pub(crate) fn roughness_coord(roughness: f32) -> f32 {
    // Exact: every f32 is an f64, and the clamp's result is the input or an f32 bound.
    roughness_clamped(roughness as f64) as f32
}
