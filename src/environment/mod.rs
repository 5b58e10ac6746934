//! Environment maps: equirectangular linear radiance around the scene
//! (docs/design/environment.md, "The map: convention, files, built-ins"), where they come
//! from (a `.hdr`/`.exr` file or a generated built-in) and how a direction reads them.
//! Knows nothing of the GPU.
//!
//! Convention (stated once, here): a unit direction `d = (x, y, z)`, `+y` up, maps to
//! `u = atan2(x, -z) / 2 pi + 1/2`, `v = acos(y) / pi`; texel `(i, j)` of a `W x H` map has
//! its centre at `((i + 1/2) / W, (j + 1/2) / H)`, row 0 at the top (`+y`). So `-z` (the
//! direction the reference camera looks) is the middle of the map, `+x` three quarters
//! across. Reads are bilinear between texel centres, wrapping in `u` and clamped in `v`
//! (`env_radiance` in `shaders/environment.wgsl` is the GPU's twin).

pub(crate) mod builtin;
mod file;
pub mod harmonics;
pub mod lobe;
pub mod prefilter;
pub(crate) mod sampler;
mod sun;
#[cfg(all(test, feature = "cli"))]
mod tests;

use std::f64::consts::PI;
use std::sync::Arc;

use glam::{DVec2, DVec3};

pub use builtin::Builtin;
pub use file::load;
pub use file::save;
#[cfg(test)]
pub(crate) use file::MapStats;
pub(crate) use file::MAX_MAP_TEXELS;
pub use lobe::IblMethod;
pub use lobe::DEFAULT_IBL_SAMPLES;
pub(crate) use lobe::MAX_IBL_SAMPLES;
pub(crate) use prefilter::ChainOn;
pub use prefilter::MipChain;
pub use prefilter::Prefiltered;
pub use sun::Sun;

use crate::error::{Error, Result};

/// An equirectangular map of linear RGB radiance, `width x height` texels, row-major, row
/// 0 at the top. Every texel is finite and non-negative (the loaders clamp and count bad
/// ones, `MapStats`).
#[derive(Clone, Debug)]
pub struct EnvMap {
    width: u32,
    height: u32,
    texels: Vec<[f32; 3]>,
    /// The largest channel of any texel.
    peak: f32,
    /// The map's sun ([`EnvMap::sun`]), found at its first use.
    sun: std::sync::OnceLock<Option<Sun>>,
    /// [`EnvMap::light_below_mean`], found at its first use.
    below_mean: std::sync::OnceLock<f64>,
}

impl PartialEq for EnvMap {
    /// The same size and texels (the sun follows from them).
    fn eq(&self, other: &Self) -> bool {
        (self.width, self.height, self.peak) == (other.width, other.height, other.peak)
            && self.texels == other.texels
    }
}

impl EnvMap {
    /// A map of `width x height` texels. Errors when a side is zero, the count does not
    /// match, the map exceeds `MAX_MAP_TEXELS`, or a texel is negative, NaN or infinite.
    pub fn new(width: u32, height: u32, texels: Vec<[f32; 3]>) -> Result<Self> {
        let invalid = |message: String| Error::Invalid {
            what: "environment map",
            message,
        };
        if width == 0 || height == 0 {
            return Err(invalid(format!("{width}x{height} has no texels")));
        }
        let count = width as u64 * height as u64;
        if count > MAX_MAP_TEXELS {
            return Err(invalid(format!(
                "{width}x{height} is more than {MAX_MAP_TEXELS} texels (8192x4096)"
            )));
        }
        if texels.len() as u64 != count {
            return Err(invalid(format!(
                "{} texels for {width}x{height}",
                texels.len()
            )));
        }
        if let Some(t) = texels
            .iter()
            .find(|t| !t.iter().all(|c| c.is_finite() && *c >= 0.0))
        {
            return Err(invalid(format!("texel {t:?} is negative, NaN or infinite")));
        }
        Ok(Self::with_peak(width, height, texels))
    }

    /// The map of checked texels (finite, non-negative, as many as the size says), with
    /// its peak found.
    pub(crate) fn with_peak(width: u32, height: u32, texels: Vec<[f32; 3]>) -> Self {
        let peak = texels.iter().flatten().fold(0.0f32, |m, &c| m.max(c));
        EnvMap {
            width,
            height,
            texels,
            peak,
            sun: std::sync::OnceLock::new(),
            below_mean: std::sync::OnceLock::new(),
        }
    }

    /// The share of the map's light (luminance times solid angle, over the sphere) that
    /// lies below its mean luminance: `sum min(Y, mean) omega / sum Y omega`, 1 for a
    /// constant or black map. The lobe mode's map samples follow what stands above the
    /// mean (the compensated luminance tables, `LuminanceCdf::compensated`) and leave
    /// this share to the other strategies ([`lobe::cosine_samples`]). The built-ins: the
    /// studio 0.16, the sky 0.72. Found once.
    pub fn light_below_mean(&self) -> f64 {
        *self.below_mean.get_or_init(|| {
            let luminance = |t: &[f32; 3]| {
                sampler::LUMINANCE.dot(DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64))
            };
            let rows = || {
                self.texels
                    .chunks(self.width as usize)
                    .zip(0..)
                    .map(|(row, j)| (row, self.texel_solid_angle(j)))
            };
            let (light, area) = rows().fold((0.0, 0.0), |(l, a), (row, omega)| {
                let sum: f64 = row.iter().map(luminance).sum();
                (l + sum * omega, a + omega * row.len() as f64)
            });
            if light <= 0.0 {
                return 1.0;
            }
            let mean = light / area;
            let below: f64 = rows()
                .map(|(row, omega)| row.iter().map(|t| luminance(t).min(mean)).sum::<f64>() * omega)
                .sum();
            (below / light).min(1.0)
        })
    }

    /// The map's sun ([`Sun`]: its bright texels when they are one small source), found
    /// once, from the mip chain the map's preparation builds (`EnvMap::sun_of_chain`) or
    /// else from one of its own.
    pub fn sun(&self) -> Option<Sun> {
        *self.sun.get_or_init(|| sun_of(&MipChain::new(self)))
    }

    /// [`EnvMap::sun`] from `chain`, this map's mip chain, already built: the preparations
    /// that build it call this first, so that finding the sun builds no chain of its own.
    pub(crate) fn sun_of_chain(&self, chain: &MipChain) -> Option<Sun> {
        *self.sun.get_or_init(|| sun_of(chain))
    }

    /// A map of one radiance everywhere (negative and non-finite channels as 0).
    pub fn uniform(radiance: DVec3, width: u32, height: u32) -> Self {
        let t = radiance
            .as_vec3()
            .to_array()
            .map(|c| if c.is_finite() && c > 0.0 { c } else { 0.0 });
        Self::with_peak(width, height, vec![t; width as usize * height as usize])
    }

    /// The largest channel of any texel (0 for a black map).
    pub(crate) fn peak(&self) -> f32 {
        self.peak
    }

    /// The power of two the GPU's half-float textures hold this map divided by, so that its
    /// peak fits under [`prefilter::F16_MAX`]: 1 for a map that fits, else the smallest
    /// `2^k` that brings the peak under it. Exact in f32 and f64, so dividing the texels and
    /// multiplying the reads back changes no bit beyond f16's own rounding (issue 28, 2:
    /// a sun above 65504 keeps its energy instead of being clipped).
    pub(crate) fn f16_scale(&self) -> f32 {
        let mut scale = 1.0f32;
        while self.peak / scale > prefilter::F16_MAX {
            scale *= 2.0;
        }
        scale
    }

    /// Whether every texel is black.
    pub(crate) fn is_black(&self) -> bool {
        self.peak == 0.0
    }

    /// Fails in one line, before the mip chain is built, when this map's chain and textures
    /// on `on` need more memory than is available ([`crate::memory::check`]; issue 28, 3).
    pub(crate) fn check_chain_memory(&self, on: ChainOn) -> Result<()> {
        let (w, h) = (self.width, self.height);
        let (device, margin) = match on {
            ChainOn::Gpu => ("GPU", crate::memory::GPU_MARGIN),
            ChainOn::Cpu => ("CPU", crate::memory::CPU_MARGIN),
        };
        crate::memory::check_with_margin(
            &format!("the {w}x{h} environment map's mip chain and textures on the {device}"),
            u64::from(w) * u64::from(h) * on.bytes_per_texel(),
            margin,
        )
    }

    /// Texels across.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Texels down.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The texels, row-major, row 0 at the top.
    pub fn texels(&self) -> &[[f32; 3]] {
        &self.texels
    }

    /// Texel `(i, j)` (column, row).
    pub fn texel(&self, i: u32, j: u32) -> DVec3 {
        let t = self.texels[j as usize * self.width as usize + i as usize];
        DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64)
    }

    /// Bilinear radiance at `uv` (texel centres at half-integers; `u` wraps, `v` clamps).
    pub(crate) fn bilinear(&self, uv: DVec2) -> DVec3 {
        let x = uv.x * self.width as f64 - 0.5;
        let y = (uv.y * self.height as f64 - 0.5).clamp(0.0, (self.height - 1) as f64);
        let x0 = x.floor();
        let y0 = y.floor();
        let (fx, fy) = (x - x0, y - y0);
        let w = self.width as i64;
        let i0 = (x0 as i64).rem_euclid(w) as u32;
        let i1 = (x0 as i64 + 1).rem_euclid(w) as u32;
        let j0 = y0 as u32;
        let j1 = (j0 + 1).min(self.height - 1);
        let top = self.texel(i0, j0).lerp(self.texel(i1, j0), fx);
        let bottom = self.texel(i0, j1).lerp(self.texel(i1, j1), fx);
        top.lerp(bottom, fy)
    }

    /// Bilinear radiance seen along unit direction `d` in the map's own frame.
    pub(crate) fn radiance(&self, d: DVec3) -> DVec3 {
        self.bilinear(direction_to_uv(d))
    }

    /// The solid angle of a texel of row `j`: `(2 pi / W) (cos theta_0 - cos theta_1)`;
    /// the rows' angles sum to `4 pi`.
    pub fn texel_solid_angle(&self, j: u32) -> f64 {
        let h = self.height as f64;
        let t0 = PI * j as f64 / h;
        let t1 = PI * (j + 1) as f64 / h;
        2.0 * PI / self.width as f64 * (t0.cos() - t1.cos())
    }
}

/// `(u, v)` of unit direction `d` (the module's convention).
pub(crate) fn direction_to_uv(d: DVec3) -> DVec2 {
    let u = d.x.atan2(-d.z) / (2.0 * PI) + 0.5;
    let v = d.y.clamp(-1.0, 1.0).acos() / PI;
    DVec2::new(u, v)
}

/// The sun of a map whose mip chain is `chain` ([`Sun::of`] its bright texels).
fn sun_of(chain: &MipChain) -> Option<Sun> {
    prefilter::Bright::new(chain).and_then(|bright| Sun::of(chain, &bright))
}

/// The unit direction at `(u, v)` (the inverse of `direction_to_uv`).
pub fn uv_to_direction(uv: DVec2) -> DVec3 {
    let phi = (uv.x - 0.5) * 2.0 * PI;
    let theta = uv.y * PI;
    DVec3::new(
        theta.sin() * phi.sin(),
        theta.cos(),
        -theta.sin() * phi.cos(),
    )
}

/// The largest radiance a map may reach once scaled by its intensity: the bound every
/// radiance of a scene keeps, `scene::MAX_MAGNITUDE` (the scene's layer is above this one;
/// a constant assertion there checks that the two agree).
pub(crate) const MAX_MAP_RADIANCE: f64 = 1e12;

/// Checks that a map whose brightest texel is `peak`, times `intensity`, stays within the
/// bound every radiance of a scene keeps, [`MAX_MAP_RADIANCE`] (issue 38, 1: a
/// map of 1e30 at intensity 1e9 rendered infinite pixels, and f32's 3.4e38 is passed by
/// any sum of such texels, an exposure, a Monte Carlo estimate's square). The message says
/// the largest intensity the map takes.
pub(crate) fn check_map_radiance(peak: f32, intensity: f64) -> std::result::Result<(), String> {
    let bound = MAX_MAP_RADIANCE;
    let radiance = f64::from(peak) * intensity;
    if radiance <= bound {
        return Ok(());
    }
    let short = crate::error::short_number;
    Err(format!(
        "its brightest texel {} times intensity {} is a radiance of {}, beyond the {bound:e} \
         every radiance of a scene is held to (use an intensity of at most {})",
        short(f64::from(peak)),
        short(intensity),
        short(radiance),
        short(max_map_intensity(peak))
    ))
}

/// The largest intensity a map whose brightest texel is `peak` takes
/// ([`check_map_radiance`]), rounded down to 3 significant digits.
pub(crate) fn max_map_intensity(peak: f32) -> f64 {
    let bound = MAX_MAP_RADIANCE;
    if peak <= 0.0 {
        return bound;
    }
    let exact = (bound / f64::from(peak)).min(bound);
    let digits = 10f64.powi(exact.log10().floor() as i32 - 2);
    let rounded = (exact / digits).floor() * digits;
    // The rounding of `digits` may leave it a hair above the bound.
    if f64::from(peak) * rounded <= bound {
        rounded
    } else {
        exact * (1.0 - 1e-12)
    }
}

/// Where an environment map came from (for messages and the viewer's picker).
#[derive(Clone, Debug, PartialEq)]
pub enum Source {
    /// A generated built-in.
    Builtin(Builtin),
    /// A file: the path it was read from (a scene's relative `map` joined to the scene
    /// file's folder; the command line's path as given).
    File(std::path::PathBuf),
}

impl std::fmt::Display for Source {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Source::Builtin(b) => write!(f, "{b}"),
            Source::File(p) => write!(f, "{}", p.display()),
        }
    }
}

/// A scene's environment map: the map, turned about `+y` and scaled.
#[derive(Clone, Debug, PartialEq)]
pub struct Environment {
    /// Where the map came from.
    pub source: Source,
    /// The map (shared: the renderers and the viewer keep it without copying).
    pub map: Arc<EnvMap>,
    /// Turns the environment about `+y` by this many degrees (right-handed: a feature at
    /// `-z` moves towards `-x` for a positive angle).
    pub rotation_deg: f64,
    /// Multiplies the map's radiance.
    pub intensity: f64,
}

impl Environment {
    /// A built-in map generated at `builtin::DEFAULT_BUILTIN_WIDTH`, not turned, intensity
    /// 1.
    pub fn builtin(b: Builtin) -> Self {
        Environment {
            source: Source::Builtin(b),
            map: Arc::new(b.generate(builtin::DEFAULT_BUILTIN_WIDTH)),
            rotation_deg: 0.0,
            intensity: 1.0,
        }
    }

    /// The map in the file at `path` ([`load`]), not turned, intensity 1; refused where its
    /// brightest texel is beyond the scene's bound on radiance (`check_map_radiance`).
    pub fn from_file(path: &std::path::Path) -> Result<Self> {
        let (map, _stats) = load(path)?;
        check_map_radiance(map.peak(), 1.0).map_err(|message| Error::Environment {
            path: path.to_path_buf(),
            message,
        })?;
        Ok(Environment {
            source: Source::File(path.to_path_buf()),
            map: Arc::new(map),
            rotation_deg: 0.0,
            intensity: 1.0,
        })
    }

    /// A built-in by its name (`studio`, `sky`, `white`), else the `.hdr`/`.exr` file at
    /// that path: what the command line's `--environment` takes.
    pub(crate) fn named(name_or_path: &str) -> Result<Self> {
        if let Ok(b) = name_or_path.parse::<Builtin>() {
            return Ok(Self::builtin(b));
        }
        let path = std::path::Path::new(name_or_path);
        if !matches!(crate::output::extension(path).as_str(), "hdr" | "exr") {
            let names: Vec<_> = Builtin::ALL.iter().map(|b| b.name()).collect();
            return Err(Error::Invalid {
                what: "environment",
                message: format!(
                    "'{name_or_path}' is neither a built-in ({}) nor a .hdr or .exr file",
                    names.join(", ")
                ),
            });
        }
        Self::from_file(path)
    }

    /// A world direction in the map's frame: turned by `-rotation_deg` about `+y`.
    pub fn to_map(&self, world: DVec3) -> DVec3 {
        let (s, c) = (-self.rotation_deg.to_radians()).sin_cos();
        DVec3::new(
            c * world.x + s * world.z,
            world.y,
            -s * world.x + c * world.z,
        )
    }

    /// A direction of the map's frame in the world: turned by `+rotation_deg` about `+y`
    /// (the inverse of [`Environment::to_map`]).
    #[allow(clippy::wrong_self_convention)] // the inverse of `to_map`, named so
    pub(crate) fn from_map(&self, map: DVec3) -> DVec3 {
        let (s, c) = self.rotation_deg.to_radians().sin_cos();
        DVec3::new(c * map.x + s * map.z, map.y, -s * map.x + c * map.z)
    }

    /// Whether the environment adds no light: intensity 0 or a black map.
    pub(crate) fn is_black(&self) -> bool {
        self.intensity == 0.0 || self.map.is_black()
    }

    /// Radiance arriving from world direction `d` (towards the light): bilinear in the map,
    /// times the intensity.
    pub(crate) fn radiance(&self, d: DVec3) -> DVec3 {
        self.intensity * self.map.radiance(self.to_map(d))
    }
}

/// What the pixels no ball covers show.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Background {
    /// Whatever the environment shows along the pixel's ray (the uniform radiance, or the
    /// map): the default.
    Environment,
    /// Black.
    Black,
    /// A fixed linear radiance.
    Colour(DVec3),
}

/// How the multiple-scattering term is formed under an environment map (`--ibl-term`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum IblTerm {
    /// Turquin 2019: the split-sum specular scaled by `1 + F0 (1 / E - 1)`.
    Turquin,
    /// Fdez-Aguera 2019: the multiple-scattering energy lit by the irradiance.
    FdezAguera,
    /// Kulla & Conty 2017, the whole lobe: `f_add f_ms` integrated against the map.
    KullaConty,
}

impl IblTerm {
    /// Every method, in the order the help lists them.
    pub const ALL: [IblTerm; 3] = [IblTerm::Turquin, IblTerm::FdezAguera, IblTerm::KullaConty];

    /// The name the command line and the scene file use.
    pub(crate) fn name(self) -> &'static str {
        match self {
            IblTerm::Turquin => "turquin",
            IblTerm::FdezAguera => "fdez-aguera",
            IblTerm::KullaConty => "kulla-conty",
        }
    }
}

crate::named_enum!(IblTerm, "ibl term");
