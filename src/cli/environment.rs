//! `shadeballs environment`: generate a built-in environment map and write it to a file:
//! the map itself (.exr, .hdr) or a preview to look at (.png, tone-mapped).

use std::time::Instant;

use super::args::EnvironmentArgs;
use glam::DVec3;

use crate::display::{to_rgba8_pixel, DisplayTransform};
use crate::environment::{self, EnvMap};
use crate::scene::Preset;

pub(crate) fn run(args: EnvironmentArgs) -> anyhow::Result<()> {
    let kind = crate::output::extension(&args.out);
    if !matches!(kind.as_str(), "exr" | "hdr" | "png") {
        return Err(crate::Error::Format {
            path: args.out.clone(),
            expected: crate::output::format_hint(&args.out, "expected .exr, .hdr or .png"),
        }
        .into());
    }
    crate::output::check_output_path(&args.out)?;
    super::guard::check_out(&args.out, &[])?;
    let start = Instant::now();
    let map = args.name.generate(args.width);
    let generated = start.elapsed();
    if kind == "png" {
        crate::output::write_png(&args.out, map.width(), map.height(), preview(&map))?;
    } else {
        environment::save(&map, &args.out)?;
    }
    eprintln!(
        "generated {} {}x{} (mean radiance {:.3}) in {:.1} ms -> {}{}",
        args.name,
        map.width(),
        map.height(),
        environment::builtin::mean_luminance(&map),
        generated.as_secs_f64() * 1e3,
        args.out.display(),
        if kind == "png" {
            " (a preview: tone-mapped as render's PNGs are; .exr or .hdr keep the radiance)"
        } else {
            ""
        }
    );
    Ok(())
}

/// The map as an opaque RGBA8 picture, each texel through the display transform of the
/// default (accurate) preset at exposure 1 ([`to_rgba8_pixel`]): what `render
/// --background environment` shows of it in the default scene, unwrapped.
pub(crate) fn preview(map: &EnvMap) -> Vec<u8> {
    let preset = Preset::default();
    let display = DisplayTransform {
        tone_map: preset.tone_map(),
        transfer: preset.transfer(),
    };
    map.texels()
        .iter()
        .flat_map(|t| {
            let c = DVec3::new(f64::from(t[0]), f64::from(t[1]), f64::from(t[2]));
            to_rgba8_pixel(c, 1.0, display)
        })
        .collect()
}
