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
//! The mu axis is either linear (`x = mu`) or square-root (`x = sqrt(mu)`), which spends
//! texels where E changes fastest: at grazing angles. The roughness axis is linear.
//! Tables are stored row-major: row `j` (roughness) holds `mu_size` texels.

use crate::brdf::roughness_clamped;

/// The mapping from mu to the table's x coordinate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MuAxis {
    Linear,
    Sqrt,
}

/// Where the texel centres sit (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Centres {
    Endpoints,
    HalfTexel,
}

/// How texel values are stored on the GPU.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Storage {
    /// `R32Float`: exact to f32.
    F32,
    /// `R16Float`, storing E as is (step 9.8e-4 just below 1).
    F16,
    /// `R8Unorm` (the homework's 8-bit PNG): step 1/255.
    Unorm8,
}

impl Storage {
    pub const ALL: [Storage; 3] = [Storage::F32, Storage::F16, Storage::Unorm8];

    pub fn name(self) -> &'static str {
        match self {
            Storage::F32 => "f32",
            Storage::F16 => "f16",
            Storage::Unorm8 => "unorm8",
        }
    }

    /// The value the GPU reads back after storing `v`.
    pub fn quantize(self, v: f64) -> f32 {
        match self {
            Storage::F32 => v as f32,
            Storage::F16 => half::f16::from_f64(v).to_f32(),
            Storage::Unorm8 => ((v.clamp(0.0, 1.0) * 255.0).round() / 255.0) as f32,
        }
    }

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
    /// The default: `x = sqrt(mu)`, texel centres on the end points, f32.
    SqrtMu,
    /// The homework's: linear mu and roughness, centres at `(i + 0.5) / n`, 128 x 128, 8 bit.
    Games202,
}

impl LayoutKind {
    pub const ALL: [LayoutKind; 2] = [LayoutKind::SqrtMu, LayoutKind::Games202];

    pub fn name(self) -> &'static str {
        match self {
            LayoutKind::SqrtMu => "sqrt-mu",
            LayoutKind::Games202 => "games202",
        }
    }
}

crate::named_enum!(Storage, "storage");
crate::named_enum!(LayoutKind, "layout");

/// A table layout: axes, sizes, storage.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Layout {
    pub kind: LayoutKind,
    pub mu_axis: MuAxis,
    pub centres: Centres,
    pub mu_size: usize,
    pub r_size: usize,
    pub storage: Storage,
}

/// Default table size (mu x roughness), chosen by measurement: the smallest that keeps the
/// read-path error within max 1e-3 and mean 1e-4 (see README, "Measured results").
pub const DEFAULT_MU_SIZE: usize = 64;
pub const DEFAULT_R_SIZE: usize = 64;

impl Default for Layout {
    fn default() -> Self {
        Layout::of_kind(LayoutKind::SqrtMu)
    }
}

impl Layout {
    /// A layout with its own default size and storage.
    pub fn of_kind(kind: LayoutKind) -> Self {
        match kind {
            LayoutKind::SqrtMu => Layout {
                kind,
                mu_axis: MuAxis::Sqrt,
                centres: Centres::Endpoints,
                mu_size: DEFAULT_MU_SIZE,
                r_size: DEFAULT_R_SIZE,
                storage: Storage::F32,
            },
            LayoutKind::Games202 => Layout {
                kind,
                mu_axis: MuAxis::Linear,
                centres: Centres::HalfTexel,
                mu_size: 128,
                r_size: 128,
                storage: Storage::Unorm8,
            },
        }
    }

    pub fn with_size(mut self, mu_size: usize, r_size: usize) -> Self {
        self.mu_size = mu_size;
        self.r_size = r_size;
        self
    }

    pub fn with_storage(mut self, storage: Storage) -> Self {
        self.storage = storage;
        self
    }

    /// `(scale, bias)` of an axis with `n` texels (see the module docs).
    pub fn scale_bias(&self, n: usize) -> (f64, f64) {
        match self.centres {
            Centres::Endpoints => ((n as f64 - 1.0).max(0.0), 0.0),
            Centres::HalfTexel => (n as f64, -0.5),
        }
    }

    /// The table coordinate x of texel `i` on an axis of `n` texels.
    pub fn texel_coord(&self, i: usize, n: usize) -> f64 {
        let (scale, bias) = self.scale_bias(n);
        if scale == 0.0 {
            return 0.0;
        }
        ((i as f64 - bias) / scale).clamp(0.0, 1.0)
    }

    /// mu of the texel in column `i`.
    pub fn mu_of_texel(&self, i: usize) -> f64 {
        let x = self.texel_coord(i, self.mu_size);
        match self.mu_axis {
            MuAxis::Linear => x,
            MuAxis::Sqrt => x * x,
        }
    }

    /// Roughness of the texel in row `j`.
    pub fn roughness_of_texel(&self, j: usize) -> f64 {
        self.texel_coord(j, self.r_size)
    }

    /// x coordinate of `mu` on the mu axis, in f32 as the shader computes it.
    pub fn mu_coord(&self, mu: f32) -> f32 {
        let mu = mu.clamp(0.0, 1.0);
        match self.mu_axis {
            MuAxis::Linear => mu,
            MuAxis::Sqrt => mu.sqrt(),
        }
    }

    pub fn texels(&self) -> usize {
        self.mu_size * self.r_size
    }

    /// GPU memory of the E table plus the E_avg row, in bytes.
    pub fn bytes(&self) -> usize {
        (self.texels() + self.r_size) * self.storage.bytes_per_texel()
    }
}

/// The two texels and the weight of the second, for a bilinear read along one axis:
/// exactly the f32 arithmetic of `lut_texel_span` in `shaders/lut.wgsl`.
pub fn lut_texel_span(x: f32, n: usize, scale: f32, bias: f32) -> (usize, usize, f32) {
    if n <= 1 {
        return (0, 0, 0.0);
    }
    let last = (n - 1) as f32;
    let p = (x * scale + bias).clamp(0.0, last);
    let i0 = p.floor().min(last - 1.0);
    let i = i0 as usize;
    (i, i + 1, p - i0)
}

/// The clamped roughness the model uses, as the shader computes it (f32).
pub fn roughness_coord(roughness: f32) -> f32 {
    roughness_clamped(roughness as f64) as f32
}
