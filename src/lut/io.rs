//! Writing baked tables: `.csv` (one row per texel), `.exr` (f32), `.png` (16 bit), and
//! `.ktx2`, the texture the shader reads, for other programs ([`super::ktx2`]).
//!
//! Image files hold both tables in one picture, `mu_size` wide and `r_size` tall, row `j` =
//! roughness texel `j` (top row = roughness 0): red = E(mu, r), green = E_avg(r) repeated
//! along the row, blue = 0. Texel coordinates follow the layout's convention (layout.rs).

use std::fmt::Write as _;
use std::path::Path;

use image::{DynamicImage, ImageBuffer, ImageFormat, Rgb};

use super::Tables;
use crate::error::{Error, Result};
use crate::output::{extension, write_atomic, write_image};

/// Writes `tables` to `path`, the format chosen by its extension.
pub fn write_tables(tables: &Tables, path: &Path) -> Result<()> {
    match extension(path).as_str() {
        "csv" => write_atomic(path, tables_csv(tables).as_bytes()),
        "exr" => write_image(path, &tables_image_f32(tables), ImageFormat::OpenExr),
        "png" => write_image(path, &tables_image_u16(tables), ImageFormat::Png),
        "ktx2" => write_atomic(path, &super::ktx2::encode_tables(tables)?),
        _ => Err(Error::Format {
            path: path.to_path_buf(),
            expected: "use .csv, .exr or .png, or .ktx2 (the texture the shader reads)",
        }),
    }
}

/// CSV with header `table,roughness,mu,value`; E_avg rows leave `mu` empty. Coordinates
/// are the texels' exact values; numbers are printed to round-trip.
pub fn tables_csv(tables: &Tables) -> String {
    let l = tables.layout();
    let mut s = String::with_capacity((l.texels() + l.r_size) * 48);
    s.push_str("table,roughness,mu,value\n");
    for j in 0..l.r_size {
        let r = l.roughness_of_texel(j);
        for i in 0..l.mu_size {
            let _ = writeln!(
                s,
                "E,{r},{},{}",
                l.mu_of_texel(i, j),
                tables.e[j * l.mu_size + i]
            );
        }
    }
    for j in 0..l.r_size {
        let _ = writeln!(s, "E_avg,{},,{}", l.roughness_of_texel(j), tables.e_avg[j]);
    }
    s
}

fn tables_image_f32(tables: &Tables) -> DynamicImage {
    let l = tables.layout();
    let img = ImageBuffer::from_fn(l.mu_size as u32, l.r_size as u32, |i, j| {
        let (i, j) = (i as usize, j as usize);
        Rgb([
            tables.e[j * l.mu_size + i] as f32,
            tables.e_avg[j] as f32,
            0.0,
        ])
    });
    DynamicImage::ImageRgb32F(img)
}

fn tables_image_u16(tables: &Tables) -> DynamicImage {
    let l = tables.layout();
    let q = |v: f64| (v.clamp(0.0, 1.0) * 65535.0).round() as u16;
    let img = ImageBuffer::from_fn(l.mu_size as u32, l.r_size as u32, |i, j| {
        let (i, j) = (i as usize, j as usize);
        Rgb([q(tables.e[j * l.mu_size + i]), q(tables.e_avg[j]), 0])
    });
    DynamicImage::ImageRgb16(img)
}
