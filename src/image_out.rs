//! Writing rendered images: `.png` = tone-mapped 8-bit (gamma 1/2.2 applied in the
//! renderer), `.exr` = linear radiance before exposure and tone mapping. Files are written
//! atomically through [`crate::output`].

use std::path::Path;

use crate::error::{Error, Result};
use crate::output::{extension, write_image};

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
