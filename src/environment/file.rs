//! Reading and writing environment maps: Radiance `.hdr` (RGBE) and OpenEXR, both linear.

use std::path::Path;

use super::EnvMap;
use crate::error::{Error, Result};

/// Most texels a map may have: 8192 x 4096 (384 MiB as f32 RGB on the CPU).
pub const MAX_MAP_TEXELS: u64 = 8192 * 4096;

/// What loading found and fixed: texels that were NaN, infinite or negative, clamped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MapStats {
    /// NaN texel channels, set to 0.
    pub nan: u64,
    /// Infinite channels: +inf set to the largest finite value of the map, -inf to 0.
    pub infinite: u64,
    /// Negative channels, set to 0.
    pub negative: u64,
}

/// Reads the equirectangular map at `path` (`.hdr` or `.exr`).
pub fn load(path: &Path) -> Result<(EnvMap, MapStats)> {
    Err(Error::Invalid {
        what: "environment map",
        message: format!("{}: TODO", path.display()),
    })
}

/// Writes `map` to `path` (`.hdr` or `.exr`), atomically.
pub fn save(_map: &EnvMap, path: &Path) -> Result<()> {
    Err(Error::Invalid {
        what: "environment map",
        message: format!("{}: TODO", path.display()),
    })
}
