//! Output files: every write is atomic (the bytes go to a temporary file beside the target,
//! which is renamed over it only once complete, so a failed write leaves nothing
//! half-written), and rendered images are `.png` (tone-mapped 8-bit, gamma 1/2.2 applied in
//! the renderer) or `.exr` (linear radiance before exposure and tone mapping).

use std::io::Write;
use std::path::Path;

use crate::error::{Error, Result};

fn write_error(path: &Path, reason: std::io::Error) -> Error {
    Error::Write {
        path: path.to_path_buf(),
        reason,
    }
}

fn invalid(path: &Path, why: &str) -> Error {
    write_error(
        path,
        std::io::Error::new(std::io::ErrorKind::InvalidInput, why.to_string()),
    )
}

/// Checks, before any work, that `path` can name an output file: its folder exists and is a
/// folder, and the path is not something other than a regular file (a folder, a device, a
/// pipe), which the final rename would replace. Permissions are left to the write itself.
pub fn check_output_path(path: &Path) -> Result<()> {
    if path.file_name().is_none() {
        return Err(invalid(path, "not a file name"));
    }
    let dir = folder_of(path);
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => return Err(invalid(path, "its folder is not a folder")),
        Err(e) => return Err(write_error(path, e)),
    }
    match std::fs::metadata(path) {
        Ok(m) if !m.is_file() => Err(invalid(path, "it exists and is not a regular file")),
        _ => Ok(()),
    }
}

fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// Writes `bytes` to `path` atomically (temporary file in the same folder, then rename).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    check_output_path(path)?;
    let err = |reason| write_error(path, reason);
    let dir = folder_of(path);
    let name = path
        .file_name()
        .ok_or_else(|| invalid(path, "not a file name"))?;
    let tmp = dir.join(format!(
        ".{}.tmp-{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = std::fs::File::create(&tmp)
        .and_then(|mut f| f.write_all(bytes).and_then(|_| f.sync_all()))
        .and_then(|_| std::fs::rename(&tmp, path));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(err)
}

/// The lower-case extension of `path`, or "" when it has none.
pub fn extension(path: &Path) -> String {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default()
}

/// Encodes `image` in `format` and writes it atomically.
pub fn write_image(
    path: &Path,
    image: &image::DynamicImage,
    format: image::ImageFormat,
) -> Result<()> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    image
        .write_to(&mut bytes, format)
        .map_err(|e| Error::Encode {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
    write_atomic(path, bytes.get_ref())
}

/// What an output path asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageKind {
    /// `.png`: display values, RGBA8.
    Png,
    /// `.exr`: linear radiance, RGBA f32.
    Exr,
}

/// The kind of image `path` names by its extension, or an error naming the choices.
pub fn image_kind(path: &Path) -> Result<ImageKind> {
    match extension(path).as_str() {
        "png" => Ok(ImageKind::Png),
        "exr" => Ok(ImageKind::Exr),
        _ => Err(Error::Format {
            path: path.to_path_buf(),
            expected: "expected .png or .exr",
        }),
    }
}

/// Writes RGBA8 display values as PNG.
pub fn write_png(path: &Path, width: u32, height: u32, rgba: Vec<u8>) -> Result<()> {
    let image = image::RgbaImage::from_raw(width, height, rgba).ok_or_else(|| Error::Encode {
        path: path.to_path_buf(),
        message: "pixel count does not match the size".into(),
    })?;
    write_image(
        path,
        &image::DynamicImage::ImageRgba8(image),
        image::ImageFormat::Png,
    )
}

/// Writes RGBA f32 linear radiance as OpenEXR.
pub fn write_exr(path: &Path, width: u32, height: u32, rgba: Vec<f32>) -> Result<()> {
    let image =
        image::Rgba32FImage::from_raw(width, height, rgba).ok_or_else(|| Error::Encode {
            path: path.to_path_buf(),
            message: "pixel count does not match the size".into(),
        })?;
    write_image(
        path,
        &image::DynamicImage::ImageRgba32F(image),
        image::ImageFormat::OpenExr,
    )
}
