//! The measurement harness behind `shadeballs-lab bench` and `cargo bench -p shadeballs-lab`: run time against
//! error, each time the median of repeated runs in one process, errors always against the
//! precise reference. Writes one CSV per sweep, log-log plots as PNG and a markdown
//! summary that states each goal of issue 5 with its figure.
//!
//! Sweeps: baking (`bake.rs`), reading on the CPU and the GPU (`read.rs`, `lookup.rs`),
//! planning (`plan.rs`: a scene's rows against the table), rendering (`render.rs`,
//! `render_sweep.rs`, against the exact model of `exact.rs`), startup (`startup.rs`),
//! scale (`scale.rs`), image-based lighting (`ibl.rs`, `harmonics.rs`) and the cost against
//! error of each way the map lights the balls (`light.rs`).

mod bake;
pub mod device;
pub mod exact;
pub mod harmonics;
pub mod ibl;
mod kernel;
pub mod light;
pub mod lookup;
mod plan;
mod read;
pub mod reference_cache;
mod render;
mod render_sweep;
pub mod scale;
mod startup;
mod table;

use std::path::PathBuf;
use std::time::Instant;

pub use bake::{bake_errors, homework_config, HOMEWORK};
pub use render::{close_up, display_error};
pub use render_sweep::no_term;
pub use table::Table;

use crate::plot::{write_plot, Plot};
use shadeballs::error::{Error, Result};
use shadeballs::output::write_atomic;

/// What to measure and where to write it.
#[derive(Clone, Debug)]
pub struct BenchOptions {
    /// Fewer configurations and repeats: under a minute, for CI.
    pub quick: bool,
    /// Folder for the CSV files, plots and `summary.md`.
    pub out: PathBuf,
    /// The `shadeballs` executable the startup sweep runs (`None`: no startup sweep).
    pub exe: Option<PathBuf>,
    /// Skip the GPU sweeps (lookup, render, startup) instead of failing without an adapter.
    pub cpu_only: bool,
    /// The sweeps to run; empty: all of them.
    pub only: Vec<SweepKind>,
}

impl BenchOptions {
    /// Whether `kind` is among the sweeps to run.
    pub fn wants(&self, kind: SweepKind) -> bool {
        self.only.is_empty() || self.only.contains(&kind)
    }
}

/// One sweep of the harness, as `shadeballs-lab bench --only` names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SweepKind {
    Bake,
    Plan,
    Read,
    Lookup,
    Render,
    Startup,
    Scale,
    Ibl,
    Light,
}

impl SweepKind {
    pub const ALL: [SweepKind; 9] = [
        SweepKind::Bake,
        SweepKind::Plan,
        SweepKind::Read,
        SweepKind::Lookup,
        SweepKind::Render,
        SweepKind::Startup,
        SweepKind::Scale,
        SweepKind::Ibl,
        SweepKind::Light,
    ];

    pub fn name(self) -> &'static str {
        match self {
            SweepKind::Bake => "bake",
            SweepKind::Plan => "plan",
            SweepKind::Read => "read",
            SweepKind::Lookup => "lookup",
            SweepKind::Render => "render",
            SweepKind::Startup => "startup",
            SweepKind::Scale => "scale",
            SweepKind::Ibl => "ibl",
            SweepKind::Light => "light",
        }
    }

    /// Whether the sweep needs an adapter.
    pub fn needs_gpu(self) -> bool {
        matches!(
            self,
            SweepKind::Lookup
                | SweepKind::Render
                | SweepKind::Startup
                | SweepKind::Scale
                | SweepKind::Ibl
                | SweepKind::Light
        )
    }
}

shadeballs::named_enum!(SweepKind, "sweep");

/// A sweep's output: its tables, its plots (file stem, plot) and the goals it checks.
pub struct Sweep {
    pub tables: Vec<Table>,
    pub plots: Vec<(String, Plot)>,
    pub goals: Vec<Goal>,
}

/// A goal of the issue with the figure measured for it.
pub struct Goal {
    pub what: String,
    pub figure: String,
    pub met: bool,
}

/// Runs every sweep, writes its files, and returns the markdown summary. Without an adapter
/// it fails before measuring anything (naming the package to install), unless `cpu_only`.
pub fn run(options: &BenchOptions) -> Result<String> {
    let started = Instant::now();
    if options.out.exists() && !options.out.is_dir() {
        return Err(Error::Invalid {
            what: "bench output folder",
            message: format!("'{}' exists and is not a folder", options.out.display()),
        });
    }
    std::fs::create_dir_all(&options.out).map_err(|reason| Error::Write {
        path: options.out.clone(),
        reason,
    })?;
    let gpu_wanted = SweepKind::ALL
        .iter()
        .any(|&k| k.needs_gpu() && options.wants(k));
    let mut laps = Laps::new();
    let gpu = if options.cpu_only || !gpu_wanted {
        None
    } else {
        Some(device::open().map_err(|e| match e {
            Error::NoAdapter { .. } => Error::Invalid {
                what: "bench",
                message: format!(
                    "{e}; `shadeballs-lab bench --cpu-only` measures the CPU sweeps alone"
                ),
            },
            e => e,
        })?)
    };
    let quick = options.quick;
    laps.lap("opening the device");
    let mut sweeps = Vec::new();
    if options.wants(SweepKind::Bake) {
        sweeps.push(bake::bake_sweep(quick));
        laps.lap("bake");
    }
    if options.wants(SweepKind::Plan) {
        sweeps.push(plan::plan_sweep(quick));
        laps.lap("plan");
    }
    if options.wants(SweepKind::Read) {
        sweeps.push(read::read_sweep(quick));
        laps.lap("read");
    }
    let mut skipped = Vec::new();
    match gpu {
        Some(gpu) => {
            if options.wants(SweepKind::Lookup) {
                sweeps.push(read::lookup_sweep(&gpu, quick)?);
                laps.lap("lookup");
            }
            let renders = [
                SweepKind::Render,
                SweepKind::Scale,
                SweepKind::Ibl,
                SweepKind::Light,
            ];
            if renders.iter().any(|&k| options.wants(k)) {
                let mut renderer = shadeballs::gpu::Renderer::new(gpu);
                if options.wants(SweepKind::Render) {
                    sweeps.push(render_sweep::render_sweep(&mut renderer, quick)?);
                    laps.lap("render");
                }
                if options.wants(SweepKind::Scale) {
                    sweeps.push(scale::scale_sweep(&mut renderer, quick)?);
                    laps.lap("scale");
                }
                if options.wants(SweepKind::Ibl) {
                    sweeps.push(ibl::ibl_sweep(&mut renderer, quick)?);
                    laps.lap("ibl");
                    sweeps.push(harmonics::harmonics_sweep(quick)?);
                    laps.lap("harmonics");
                }
                if options.wants(SweepKind::Light) {
                    sweeps.push(light::light_sweep(&mut renderer, quick)?);
                    laps.lap("light");
                }
            } else {
                drop(gpu);
            }
            // The device is released above, before the startup runs open theirs.
            if options.wants(SweepKind::Startup) {
                match &options.exe {
                    Some(exe) => {
                        sweeps.push(startup::startup_sweep(exe, quick)?);
                        laps.lap("startup");
                    }
                    None => skipped.push(
                        "startup (no shadeballs executable beside shadeballs-lab: cargo build --release)"
                            .to_string(),
                    ),
                }
            }
        }
        None if options.cpu_only && gpu_wanted => {
            skipped.push("GPU lookup, rendering and startup (--cpu-only)".to_string())
        }
        None => {}
    }
    let unselected: Vec<&str> = SweepKind::ALL
        .iter()
        .filter(|&&k| !options.wants(k))
        .map(|k| k.name())
        .collect();
    if !unselected.is_empty() {
        skipped.push(format!("{} (not in --only)", unselected.join(", ")));
    }
    let mut summary = String::from("# shadeballs-lab bench\n\n");
    summary.push_str(&format!(
        "Mode: {}. Made at commit {} of the source tree. Times are medians of repeated runs in \
         one process; errors are against the precise reference (adaptive Gauss-Kronrod, \
         tolerance 1e-11).\n\n",
        if quick { "quick" } else { "full" },
        source_commit()
    ));
    summary.push_str("## Goals\n\n| goal | measured | met |\n|---|---|---|\n");
    for g in sweeps.iter().flat_map(|s| &s.goals) {
        summary.push_str(&format!(
            "| {} | {} | {} |\n",
            g.what,
            g.figure,
            if g.met { "yes" } else { "**no**" }
        ));
    }
    for s in &skipped {
        summary.push_str(&format!("\nNot measured: {s}.\n"));
    }
    summary.push('\n');
    for sweep in &sweeps {
        for table in &sweep.tables {
            write_atomic(
                &options.out.join(format!("{}.csv", table.name)),
                table.csv().as_bytes(),
            )?;
            summary.push_str(&table.markdown());
            summary.push('\n');
        }
        for (stem, p) in &sweep.plots {
            let file = format!("{stem}.png");
            write_plot(p, &options.out.join(&file))?;
            summary.push_str(&format!("![{}]({file})\n\n", p.title));
        }
    }
    summary.push_str(&format!(
        "Bench wall time: {:.1} s ({}).\n",
        started.elapsed().as_secs_f64(),
        laps.list()
    ));
    write_atomic(&options.out.join("summary.md"), summary.as_bytes())?;
    Ok(summary)
}

/// The wall time of each step of a run, in the order they ran.
struct Laps {
    last: Instant,
    times: Vec<(&'static str, f64)>,
}

impl Laps {
    fn new() -> Self {
        Laps {
            last: Instant::now(),
            times: Vec::new(),
        }
    }

    /// Records the time since the previous lap (or the start) as `step`'s.
    fn lap(&mut self, step: &'static str) {
        let now = Instant::now();
        self.times
            .push((step, now.duration_since(self.last).as_secs_f64()));
        self.last = now;
    }

    /// "bake 4.1 s, plan 1.0 s, ...".
    fn list(&self) -> String {
        let steps: Vec<String> = self
            .times
            .iter()
            .map(|(step, secs)| format!("{step} {secs:.1} s"))
            .collect();
        steps.join(", ")
    }
}

/// The commit of the source tree this lab was built from, its abbreviated hash as `git
/// describe` names it (`-dirty`: with uncommitted changes to tracked files), or why not.
pub fn source_commit() -> String {
    let out = std::process::Command::new("git")
        .args([
            "-C",
            env!("CARGO_MANIFEST_DIR"),
            "describe",
            "--always",
            "--dirty",
            "--exclude=*",
        ])
        .output();
    match out {
        Ok(o) if o.status.success() => String::from_utf8_lossy(&o.stdout).trim().to_string(),
        Ok(o) => format!("unknown ({})", String::from_utf8_lossy(&o.stderr).trim()),
        Err(e) => format!("unknown (git: {e})"),
    }
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
    (median(&mut times), last)
}

pub use shadeballs::stats::median;
