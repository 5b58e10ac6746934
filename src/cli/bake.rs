//! `shadeballs bake`: bake the tables and write them to a file.

use std::time::Instant;

use super::args::BakeArgs;
use crate::lut::{self, io::write_tables, BakeConfig, Layout, Method};

pub(crate) fn run(args: BakeArgs) -> anyhow::Result<()> {
    crate::output::check_output_path(&args.out)?;
    super::guard::check_out(&args.out, &[])?;
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
    let estimate = estimated_seconds(&config);
    let tables = if estimate > PROGRESS_AFTER_S {
        eprintln!(
            "warning: this bake takes about {} ({} with {} on a {}x{} table); \
             elapsed time follows every {PROGRESS_EVERY_S} s, Ctrl-C stops it",
            duration(estimate),
            config.method,
            crate::stats::count(config.samples as u64, "sample"),
            layout.mu_size,
            layout.r_size
        );
        with_progress(estimate, || lut::bake(&config))
    } else {
        lut::bake(&config)
    };
    let elapsed = start.elapsed();
    write_tables(&tables, &args.out)?;
    eprintln!(
        "baked E {}x{} + E_avg {} ({} G, {} with {}, {} layout, {} storage) in {:.2} \
         ms -> {}",
        layout.mu_size,
        layout.r_size,
        layout.r_size,
        config.geometry,
        config.method,
        crate::stats::count(config.samples as u64, "sample"),
        layout.kind,
        layout.storage,
        elapsed.as_secs_f64() * 1e3,
        args.out.display()
    );
    Ok(())
}

/// A bake estimated to take longer than this warns first and reports its elapsed time.
const PROGRESS_AFTER_S: f64 = 10.0;
/// Seconds between progress lines.
const PROGRESS_EVERY_S: u64 = 10;

/// Seconds `config` should take to bake, from rates measured on the 2-core reference
/// machine (docs/reliability.md, "Reliability"): the Chebyshev bake runs 425 quadratures
/// whatever the table size, the quadrature one per texel, Monte Carlo one estimate of
/// `samples` points per texel. Within a factor of 2 or so on that machine.
pub(crate) fn estimated_seconds(config: &BakeConfig) -> f64 {
    let samples = config.samples as f64;
    let texels = config.layout.texels() as f64;
    match config.method {
        // 0.31 s at 1000 nodes; plus evaluating the series at every texel.
        Method::Chebyshev => 3.1e-4 * samples + 1.5e-7 * texels,
        // 0.92 s for 64 x 64 texels at 1000 nodes.
        Method::Quadrature => 2.3e-7 * samples * texels,
        // 0.27 s for 64 x 64 texels at 1000 points (vndf; cosine and ndf alike).
        _ => 6.5e-8 * samples * texels,
    }
}

fn duration(seconds: f64) -> String {
    if seconds < 120.0 {
        format!("{seconds:.0} s")
    } else {
        format!("{:.0} min", seconds / 60.0)
    }
}

/// Runs `bake`, printing the elapsed time against `estimate` every `PROGRESS_EVERY_S`
/// seconds on stderr until it returns.
fn with_progress<T>(estimate: f64, bake: impl FnOnce() -> T) -> T {
    let (done, wait) = std::sync::mpsc::channel::<()>();
    let start = Instant::now();
    std::thread::scope(|s| {
        // A progress thread that cannot start (short of memory or threads) leaves the bake
        // without its progress lines, rather than panicking as `Scope::spawn` would.
        let progress = std::thread::Builder::new().name("progress".into());
        let _progress = progress.spawn_scoped(s, move || {
            let every = std::time::Duration::from_secs(PROGRESS_EVERY_S);
            while let Err(std::sync::mpsc::RecvTimeoutError::Timeout) = wait.recv_timeout(every) {
                let elapsed = start.elapsed().as_secs_f64();
                eprintln!(
                    "baking: {} elapsed of about {} ({:.0} %)",
                    duration(elapsed),
                    duration(estimate),
                    (100.0 * elapsed / estimate).min(99.0)
                );
            }
        });
        let tables = bake();
        drop(done);
        tables
    })
}
