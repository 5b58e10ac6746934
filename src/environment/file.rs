//! Reading and writing environment maps: Radiance `.hdr` (RGBE) and OpenEXR, both linear.
//!
//! The rules for bad input (docs/design/environment.md, "Bad input"): the size is read from
//! the header before anything is decoded, so a map over [`MAX_MAP_TEXELS`] or not 2:1 is
//! one error without allocating its texels; a missing, truncated or corrupt file, or one
//! with another extension, is one error naming the path; NaN, infinite and negative
//! channels are clamped, counted in [`MapStats`] and reported in one warning.

#[cfg(feature = "image-files")]
use std::fs::File;
#[cfg(feature = "image-files")]
use std::io::BufReader;
use std::path::Path;

use super::EnvMap;
use crate::error::{Error, Result};
#[cfg(feature = "image-files")]
use crate::output;

/// Most texels a map may have: 8192 x 4096 (384 MiB as f32 RGB on the CPU).
pub(crate) const MAX_MAP_TEXELS: u64 = 8192 * 4096;

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

impl MapStats {
    /// Channels clamped in all.
    pub(crate) fn total(&self) -> u64 {
        self.nan + self.infinite + self.negative
    }
}

fn error(path: &Path, message: impl Into<String>) -> Error {
    Error::Environment {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

#[cfg(feature = "image-files")]
/// The image format `path` names by its extension: `.hdr` or `.exr`.
fn format_of(path: &Path) -> Option<image::ImageFormat> {
    match output::extension(path).as_str() {
        "hdr" => Some(image::ImageFormat::Hdr),
        "exr" => Some(image::ImageFormat::OpenExr),
        _ => None,
    }
}

#[cfg(feature = "image-files")]
/// One line for an error of the image crate while reading `path`.
fn decode_error(e: image::ImageError) -> String {
    match e {
        image::ImageError::IoError(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            "the file ends early (truncated)".to_string()
        }
        image::ImageError::IoError(io) => crate::error::one_line(&io.to_string()),
        e => {
            let message = crate::error::one_line(&e.to_string());
            if message.contains("EOF") || message.contains("end of file") {
                format!("the file ends early (truncated): {message}")
            } else {
                format!("corrupt or unsupported data: {message}")
            }
        }
    }
}

#[cfg(feature = "image-files")]
/// Why a `width x height` map is refused, if it is: no texels, more than
/// [`MAX_MAP_TEXELS`], or not equirectangular (2:1).
pub(crate) fn size_problem(width: u32, height: u32) -> Option<String> {
    let count = u64::from(width) * u64::from(height);
    if count == 0 {
        Some(format!("{width}x{height} has no texels"))
    } else if count > MAX_MAP_TEXELS {
        Some(format!(
            "{width}x{height} is more than {MAX_MAP_TEXELS} texels (the largest map is 8192x4096)"
        ))
    } else if u64::from(width) != 2 * u64::from(height) {
        Some(format!(
            "{width}x{height} is not an equirectangular map: the width must be twice the \
             height (e.g. 2048x1024)"
        ))
    } else {
        None
    }
}

#[cfg(feature = "image-files")]
/// Peak bytes a texel costs while a map is read: the decoder's image and the map's own
/// texels, both alive at once: an `.hdr` decodes to RGB f32 (12 + 12), an `.exr` may
/// decode to RGBA f32 and be converted to RGB f32 (16 + 12 + 12).
pub(crate) fn load_bytes_per_texel(format: image::ImageFormat) -> u64 {
    if format == image::ImageFormat::Hdr {
        24
    } else {
        40
    }
}

#[cfg(feature = "image-files")]
/// Opens `path` once, for reading, refusing anything but a regular file before it is
/// opened: a FIFO would block the open until a writer comes, and a device or socket is
/// no map (issue 28, 8). The file's own type is checked again once open.
fn open_regular(path: &Path) -> Result<File> {
    let io = |e: std::io::Error| error(path, crate::error::one_line(&e.to_string()));
    let kind = |m: &std::fs::Metadata| -> Result<()> {
        if m.is_dir() {
            Err(error(path, "is a folder, not a file"))
        } else if !m.is_file() {
            Err(error(
                path,
                "is not a regular file (a FIFO, a device or a socket): a map is read from a file",
            ))
        } else {
            Ok(())
        }
    };
    kind(&std::fs::metadata(path).map_err(io)?)?;
    let file = File::open(path).map_err(io)?;
    kind(&file.metadata().map_err(io)?)?;
    Ok(file)
}

#[cfg(feature = "image-files")]
/// Reads the equirectangular map at `path` (`.hdr` or `.exr`): 2:1, at most
/// `MAX_MAP_TEXELS`, and within the memory available (`crate::memory::check` of
/// `super::load_bytes_per_texel`), all checked from the header, before decoding; the
/// file is opened once, and only a regular file is. NaN, infinite and negative channels
/// are clamped (NaN and negative to 0, -inf to 0, +inf to the largest finite channel of
/// the map, or 0 if none), counted in the `MapStats`, and reported in one `log::warn!`
/// line.
pub fn load(path: &Path) -> Result<(EnvMap, MapStats)> {
    let format = format_of(path).ok_or_else(|| {
        error(
            path,
            "expected a .hdr (Radiance RGBE) or .exr (OpenEXR) file",
        )
    })?;
    let file = open_regular(path)?;
    let decoder: Box<dyn image::ImageDecoder> = if format == image::ImageFormat::Hdr {
        let io = |e: std::io::Error| error(path, crate::error::one_line(&e.to_string()));
        let reader = radiance_magic(BufReader::new(file)).map_err(io)?;
        let decoder = image::codecs::hdr::HdrDecoder::new(reader)
            .map_err(|e| error(path, decode_error(e)))?;
        Box::new(decoder)
    } else {
        let mut reader = image::ImageReader::with_format(BufReader::new(file), format);
        // The size is bounded above: the decoder's own allocation limit (512 MiB) would
        // refuse an RGBA f32 EXR of the largest size.
        reader.no_limits();
        Box::new(
            reader
                .into_decoder()
                .map_err(|e| error(path, decode_error(e)))?,
        )
    };
    let (width, height) = image::ImageDecoder::dimensions(&decoder);
    if let Some(problem) = size_problem(width, height) {
        return Err(error(path, problem));
    }
    crate::memory::check(
        &format!("reading the {width}x{height} environment map"),
        u64::from(width) * u64::from(height) * load_bytes_per_texel(format),
    )
    .map_err(|e| error(path, e.to_string()))?;
    let image = image::DynamicImage::from_decoder(decoder)
        .map_err(|e| error(path, decode_error(e)))?
        .into_rgb32f();
    if image.dimensions() != (width, height) {
        return Err(error(
            path,
            format!(
                "the header says {width}x{height} but the image decoded as {}x{}",
                image.width(),
                image.height()
            ),
        ));
    }
    let mut texels: Vec<[f32; 3]> = image.pixels().map(|p| p.0).collect();
    drop(image);
    let stats = clamp_texels(&mut texels);
    if stats.total() > 0 {
        log::warn!(
            "environment map '{}': clamped {} NaN, {} infinite and {} negative channels \
             (NaN and negative to 0, +inf to the largest finite value)",
            path.display(),
            stats.nan,
            stats.infinite,
            stats.negative
        );
    }
    let map = EnvMap::new(width, height, texels).map_err(|e| error(path, e.to_string()))?;
    Ok((map, stats))
}

#[cfg(feature = "image-files")]
/// The longest first line of a Radiance file looked at: its magic, `#?` and a program name.
const MAGIC_LINE_BYTES: u64 = 64;

#[cfg(feature = "image-files")]
/// A Radiance file's bytes with its magic line made `#?RADIANCE`, the only one the decoder
/// takes: the format's magic is `#?` followed by the writing program's name, and other
/// writers put theirs (Mitsuba and others write `#?RGBE`). Any other first line is left as
/// it is, for the decoder to refuse.
fn radiance_magic<R: std::io::BufRead>(mut file: R) -> std::io::Result<impl std::io::BufRead> {
    use std::io::{BufRead as _, Read as _};
    let mut first = Vec::new();
    (&mut file)
        .take(MAGIC_LINE_BYTES)
        .read_until(b'\n', &mut first)?;
    let named = first.starts_with(b"#?")
        && first.ends_with(b"\n")
        && first[2..first.len() - 1]
            .iter()
            .all(|c| c.is_ascii_alphanumeric() || b"_-. ".contains(c));
    if named {
        first = b"#?RADIANCE\n".to_vec();
    }
    Ok(std::io::Cursor::new(first).chain(file))
}

#[cfg(feature = "image-files")]
/// Makes every channel finite and non-negative: NaN, -inf and negative values to 0, +inf to
/// the largest finite channel (0 if there is none); returns what it changed.
pub(crate) fn clamp_texels(texels: &mut [[f32; 3]]) -> MapStats {
    let largest = texels
        .iter()
        .flatten()
        .filter(|c| c.is_finite())
        .fold(0.0f32, |m, &c| m.max(c));
    let mut stats = MapStats::default();
    for c in texels.iter_mut().flatten() {
        if c.is_nan() {
            stats.nan += 1;
            *c = 0.0;
        } else if c.is_infinite() {
            stats.infinite += 1;
            *c = if *c > 0.0 { largest } else { 0.0 };
        } else if *c < 0.0 {
            stats.negative += 1;
            *c = 0.0;
        }
    }
    stats
}

#[cfg(feature = "image-files")]
/// Writes `map` to `path` (`.hdr` or `.exr`, f32 RGB), atomically
/// (`output::write_atomic_with`: a failed write leaves no partial file).
pub fn save(map: &EnvMap, path: &Path) -> Result<()> {
    let format = format_of(path).ok_or_else(|| Error::Format {
        path: path.to_path_buf(),
        expected: output::format_hint(path, "expected .hdr or .exr"),
    })?;
    let flat: Vec<f32> = map.texels().iter().flatten().copied().collect();
    let image = image::Rgb32FImage::from_raw(map.width(), map.height(), flat).ok_or_else(|| {
        Error::Encode {
            path: path.to_path_buf(),
            message: "texel count does not match the size".into(),
        }
    })?;
    output::write_image(path, &image::DynamicImage::ImageRgb32F(image), format)
}

/// Without the crate feature `image-files` this build decodes no map file: every path is
/// one error saying so (built-in maps and maps made in code still work).
#[cfg(not(feature = "image-files"))]
pub fn load(path: &Path) -> Result<(EnvMap, MapStats)> {
    Err(error(path, WITHOUT_IMAGE_FILES))
}

/// Without the crate feature `image-files` this build encodes no map file.
#[cfg(not(feature = "image-files"))]
pub fn save(_map: &EnvMap, path: &Path) -> Result<()> {
    Err(error(path, WITHOUT_IMAGE_FILES))
}

/// Why a build without the crate feature `image-files` refuses a map file.
#[cfg(not(feature = "image-files"))]
const WITHOUT_IMAGE_FILES: &str =
    "this build reads and writes no .hdr or .exr files (the crate feature `image-files` is off)";
