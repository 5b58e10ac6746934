//! Writing baked tables: `.csv` (one row per texel), `.exr` (f32), `.png` (16 bit), and
//! `.ktx2`, the texture the shader reads, for other programs ([`super::ktx2`]).
//!
//! Image files hold both tables in one picture, `mu_size` wide and `r_size` tall, row `j` =
//! roughness texel `j` (top row = roughness 0): red = E(mu, r), green = E_avg(r) repeated
//! along the row, blue = 0. Every format holds the values the layout's storage keeps
//! (`1 -` the stored loss, after f32, f16 or unorm8 rounding), the ones the shader reads.
//! Texel coordinates follow the layout's convention (layout.rs).

use std::io::Write;
use std::path::Path;

#[cfg(feature = "image-files")]
use image::{DynamicImage, ImageBuffer, ImageFormat, Rgb};

use super::Tables;
use crate::error::{Error, Result};
#[cfg(feature = "image-files")]
use crate::output::write_image;
use crate::output::{extension, write_atomic, write_atomic_with};

/// Writes `tables` to `path`, the format chosen by its extension.
pub(crate) fn write_tables(tables: &Tables, path: &Path) -> Result<()> {
    match extension(path).as_str() {
        // Streamed into the temporary file: a 4096 x 4096 table is 1 GB of text.
        "csv" => write_atomic_with(path, |w| {
            write_csv(tables, w).map_err(|reason| Error::Write {
                path: path.to_path_buf(),
                reason,
            })
        }),
        #[cfg(feature = "image-files")]
        "exr" => write_image(path, &tables_image_f32(tables), ImageFormat::OpenExr),
        #[cfg(feature = "image-files")]
        "png" => write_image(path, &tables_image_u16(tables), ImageFormat::Png),
        #[cfg(not(feature = "image-files"))]
        "exr" | "png" => Err(Error::Format {
            path: path.to_path_buf(),
            expected: "this build writes .csv and .ktx2 (.exr and .png need the crate feature `image-files`)",
        }),
        "ktx2" => write_atomic(path, &super::ktx2::encode_tables(tables)?),
        // Source code for another engine: C arrays, GLSL arrays (lut::header).
        "h" => write_atomic(path, super::header::source(tables, super::header::Language::C).as_bytes()),
        "glsl" => write_atomic(path, super::header::source(tables, super::header::Language::Glsl).as_bytes()),
        _ => Err(Error::Format {
            path: path.to_path_buf(),
            expected: crate::output::format_hint(
                path,
                "use .csv, .exr or .png, .ktx2 (the texture the shader reads), or .h or .glsl \
                 (C or GLSL arrays)",
            ),
        }),
    }
}

/// E of texel `k` as the table stores it: `1 - ` the stored loss, after the layout's
/// storage rounding (f32, f16 or unorm8), the value the shader reads.
fn stored_e(tables: &Tables, k: usize) -> f64 {
    1.0 - f64::from(tables.stored_loss[k])
}

/// E_avg of row `j` as stored.
fn stored_e_avg(tables: &Tables, j: usize) -> f64 {
    1.0 - f64::from(tables.stored_loss_avg[j])
}

/// CSV with header `table,roughness,mu,value`; E_avg rows leave `mu` empty. Coordinates
/// are the texels' exact values; values are what the storage holds (`stored_e`), printed
/// to round-trip.
pub(crate) fn write_csv(tables: &Tables, w: &mut impl Write) -> std::io::Result<()> {
    let l = tables.layout();
    w.write_all(b"table,roughness,mu,value\n")?;
    for j in 0..l.r_size {
        let r = l.roughness_of_texel(j);
        for i in 0..l.mu_size {
            writeln!(
                w,
                "E,{r},{},{}",
                l.mu_of_texel(i, j),
                stored_e(tables, j * l.mu_size + i)
            )?;
        }
    }
    for j in 0..l.r_size {
        writeln!(
            w,
            "E_avg,{},,{}",
            l.roughness_of_texel(j),
            stored_e_avg(tables, j)
        )?;
    }
    Ok(())
}

#[cfg(feature = "image-files")]
fn tables_image_f32(tables: &Tables) -> DynamicImage {
    let l = tables.layout();
    let img = ImageBuffer::from_fn(l.mu_size as u32, l.r_size as u32, |i, j| {
        let (i, j) = (i as usize, j as usize);
        Rgb([
            stored_e(tables, j * l.mu_size + i) as f32,
            stored_e_avg(tables, j) as f32,
            0.0,
        ])
    });
    DynamicImage::ImageRgb32F(img)
}

#[cfg(feature = "image-files")]
fn tables_image_u16(tables: &Tables) -> DynamicImage {
    let l = tables.layout();
    let q = |v: f64| (v.clamp(0.0, 1.0) * 65535.0).round() as u16;
    let img = ImageBuffer::from_fn(l.mu_size as u32, l.r_size as u32, |i, j| {
        let (i, j) = (i as usize, j as usize);
        Rgb([
            q(stored_e(tables, j * l.mu_size + i)),
            q(stored_e_avg(tables, j)),
            0,
        ])
    });
    DynamicImage::ImageRgb16(img)
}

// Tests that need the crate's internals (moved from the suite); with the command line's
// features only, so `cargo test --no-default-features --lib` runs them once.
#[cfg(all(test, feature = "cli"))]
mod tests;
