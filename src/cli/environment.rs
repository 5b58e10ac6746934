//! `shadeballs environment`: generate a built-in environment map and write it to a file.

use std::time::Instant;

use super::args::EnvironmentArgs;
use crate::environment;

pub fn run(args: EnvironmentArgs) -> anyhow::Result<()> {
    let kind = crate::output::extension(&args.out);
    if kind != "exr" && kind != "hdr" {
        return Err(crate::Error::Format {
            path: args.out.clone(),
            expected: crate::output::format_hint(&args.out, "expected .exr or .hdr"),
        }
        .into());
    }
    crate::output::check_output_path(&args.out)?;
    let start = Instant::now();
    let map = args.name.generate(args.width);
    let generated = start.elapsed();
    environment::save(&map, &args.out)?;
    eprintln!(
        "generated {} {}x{} (mean radiance {:.3}) in {:.1} ms -> {}",
        args.name,
        map.width(),
        map.height(),
        environment::builtin::mean_luminance(&map),
        generated.as_secs_f64() * 1e3,
        args.out.display()
    );
    Ok(())
}
