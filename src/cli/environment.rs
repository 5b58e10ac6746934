//! `shadeballs environment`: generate a built-in environment map and write it to a file:
//! the map itself (.exr, .hdr) or a preview to look at (.png, tone-mapped).

use std::time::Instant;

use super::args::EnvironmentArgs;
use crate::display::{to_unorm8, tone_map};
use crate::environment::{self, EnvMap};

pub fn run(args: EnvironmentArgs) -> anyhow::Result<()> {
    let kind = crate::output::extension(&args.out);
    if !matches!(kind.as_str(), "exr" | "hdr" | "png") {
        return Err(crate::Error::Format {
            path: args.out.clone(),
            expected: crate::output::format_hint(&args.out, "expected .exr, .hdr or .png"),
        }
        .into());
    }
    crate::output::check_output_path(&args.out)?;
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

/// The map as an opaque RGBA8 picture, each texel through the renderers' display
/// transform at exposure 1 ([`tone_map`]): what `render --background environment` shows
/// of it, unwrapped.
pub fn preview(map: &EnvMap) -> Vec<u8> {
    map.texels()
        .iter()
        .flat_map(|t| {
            let c = |v: f32| to_unorm8(tone_map(f64::from(v), 1.0));
            [c(t[0]), c(t[1]), c(t[2]), 255]
        })
        .collect()
}
