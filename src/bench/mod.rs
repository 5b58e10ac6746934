//! The measurement harness behind `shadeballs bench` and `cargo bench`: run time against
//! error, each time the median of repeated runs in one process, errors always against the
//! precise reference. Writes one CSV per sweep and a markdown summary.

mod bake;
mod table;

use std::path::PathBuf;
use std::time::Instant;

pub use table::Table;

use crate::error::{Error, Result};
use crate::output::write_atomic;

/// What to measure and where to write it.
#[derive(Clone, Debug)]
pub struct BenchOptions {
    /// Fewer configurations and repeats: under a minute, for CI.
    pub quick: bool,
    /// Folder for the CSV files and `summary.md`.
    pub out: PathBuf,
}

/// Runs every sweep, writes its files, and returns the markdown summary.
pub fn run(options: &BenchOptions) -> Result<String> {
    std::fs::create_dir_all(&options.out).map_err(|reason| Error::Write {
        path: options.out.clone(),
        reason,
    })?;
    let mut summary = String::from("# shadeballs bench\n\n");
    summary.push_str(&format!(
        "Mode: {}. Times are medians of repeated runs in one process; errors are against the \
         precise reference (adaptive Gauss-Kronrod, tolerance 1e-11).\n\n",
        if options.quick { "quick" } else { "full" }
    ));
    for sweep in [bake::bake_sweep as fn(bool) -> Vec<Table>, bake::read_sweep] {
        for table in sweep(options.quick) {
            write_atomic(
                &options.out.join(format!("{}.csv", table.name)),
                table.csv().as_bytes(),
            )?;
            summary.push_str(&table.markdown());
            summary.push('\n');
        }
    }
    write_atomic(&options.out.join("summary.md"), summary.as_bytes())?;
    Ok(summary)
}

/// Median wall time of `f` in milliseconds over `repeats` runs (after one warm-up run).
pub fn median_ms<T>(repeats: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut last = f();
    let mut times = Vec::with_capacity(repeats);
    for _ in 0..repeats.max(1) {
        let start = Instant::now();
        last = f();
        times.push(start.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    (times[times.len() / 2], last)
}
