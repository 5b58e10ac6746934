//! `shadeballs bake`: bake the tables and write them to a file.

use std::time::Instant;

use super::args::BakeArgs;
use crate::lut::{self, io::write_tables, BakeConfig, Layout};

pub fn run(args: BakeArgs) -> anyhow::Result<()> {
    crate::output::check_output_path(&args.out)?;
    let mut layout = Layout::of_kind(args.layout);
    if let Some((mu, r)) = args.size {
        layout = layout.with_size(mu, r);
    }
    if let Some(storage) = args.storage {
        layout = layout.with_storage(storage);
    }
    let config = BakeConfig {
        geometry: args.geometry,
        method: args.method,
        points: args.points,
        samples: args.samples as usize,
        layout,
    };
    let start = Instant::now();
    let tables = lut::bake(&config);
    let elapsed = start.elapsed();
    write_tables(&tables, &args.out)?;
    eprintln!(
        "baked E {}x{} + E_avg {} ({} G, {} with {} samples, {} layout) in {:.2} ms -> {}",
        layout.mu_size,
        layout.r_size,
        layout.r_size,
        config.geometry,
        config.method,
        config.samples,
        layout.kind,
        elapsed.as_secs_f64() * 1e3,
        args.out.display()
    );
    Ok(())
}
