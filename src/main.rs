//! The `shadeballs` command line: parses flags, calls the library, reports.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::{Parser, Subcommand};

mod render_cmd;

use shadeballs::brdf::Geometry;
use shadeballs::lut::{
    self, io::write_tables, BakeConfig, Layout, LayoutKind, Method, PointSet, Storage,
};

#[derive(Parser)]
#[command(
    name = "shadeballs",
    version,
    about = "Shading balls for the Kulla-Conty multiple-scattering BRDF"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Bake E(mu, roughness) and E_avg(roughness) and write them to a file.
    Bake(BakeArgs),
    /// Measure run time against error (writes CSV, PNG plots and a markdown summary).
    Bench(BenchArgs),
    /// Render the shading balls (GPU, or the CPU reference renderer) to .png or .exr.
    Render(render_cmd::RenderArgs),
    /// Evaluate on the GPU what the shader reads from the tables on an N x N grid (CSV).
    Probe(render_cmd::ProbeArgs),
}

#[derive(clap::Args)]
struct BakeArgs {
    /// Output file: .csv (one row per texel), .exr (f32) or .png (16 bit).
    #[arg(long)]
    out: PathBuf,
    /// Table size: N (N x N) or MUxR (mu texels x roughness texels). Default: the layout's.
    #[arg(long, value_parser = parse_size)]
    size: Option<(usize, usize)>,
    /// Masking-shadowing term: schlick, smith or smith-correlated.
    #[arg(long, default_value_t = Geometry::Schlick)]
    geometry: Geometry,
    /// Estimator: cosine, ndf, vndf or quadrature.
    #[arg(long, default_value_t = lut::DEFAULT_METHOD)]
    method: Method,
    /// Samples per texel (Monte Carlo) or Gauss-Legendre nodes per segment (quadrature).
    #[arg(long, default_value_t = lut::DEFAULT_SAMPLES as u32, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    samples: u32,
    /// Point set for Monte Carlo methods: random, hammersley or sobol.
    #[arg(long, default_value_t = PointSet::Sobol)]
    points: PointSet,
    /// Table layout: warped (default), sqrt-mu or games202 (the homework's).
    #[arg(long, default_value_t = LayoutKind::Warped)]
    layout: LayoutKind,
    /// Storage format the GPU will read: f32, f16 or unorm8. Default: the layout's.
    #[arg(long)]
    storage: Option<Storage>,
}

#[derive(clap::Args)]
struct BenchArgs {
    /// Fewer configurations and repeats (under a minute).
    #[arg(long)]
    quick: bool,
    /// Folder for the CSV files, plots (PNG) and summary.md.
    #[arg(long, default_value = "bench-results")]
    out: PathBuf,
    /// Only the CPU sweeps (bake, read): for a machine without a GPU driver.
    #[arg(long)]
    cpu_only: bool,
}

/// Largest table side accepted (wgpu's guaranteed 2-D texture limit is 8192).
const MAX_TABLE_SIDE: usize = 8192;

fn parse_size(s: &str) -> Result<(usize, usize), String> {
    let one = |t: &str| -> Result<usize, String> {
        let n: usize = t
            .trim()
            .parse()
            .map_err(|_| format!("'{t}' is not a whole number"))?;
        if !(2..=MAX_TABLE_SIDE).contains(&n) {
            return Err(format!("{n} is outside 2..={MAX_TABLE_SIDE}"));
        }
        Ok(n)
    };
    match s.split_once(['x', 'X']) {
        Some((a, b)) => Ok((one(a)?, one(b)?)),
        None => one(s).map(|n| (n, n)),
    }
}

fn bake(args: BakeArgs) -> anyhow::Result<()> {
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

/// Mesa's drivers print "error: XDG_RUNTIME_DIR is invalid or not set" on every start
/// without a private runtime folder, which reads like a failure. When none is set, point
/// it at a 0700 folder of this user's under the temp folder. Runs first, before any thread exists.
#[cfg(unix)]
fn give_mesa_a_runtime_dir() {
    use std::os::unix::fs::{MetadataExt, PermissionsExt};
    let usable = std::env::var_os("XDG_RUNTIME_DIR")
        .map(PathBuf::from)
        .is_some_and(|d| d.is_dir());
    if usable {
        return;
    }
    // One folder per user, reused by every run (the uid of this process owns /proc/self).
    let uid = std::fs::metadata("/proc/self")
        .map(|m| m.uid())
        .unwrap_or(0);
    let dir = std::env::temp_dir().join(format!("shadeballs-runtime-{uid}"));
    let made = std::fs::create_dir_all(&dir)
        .and_then(|_| std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o700)));
    if made.is_ok() {
        std::env::set_var("XDG_RUNTIME_DIR", &dir);
    }
}

#[cfg(not(unix))]
fn give_mesa_a_runtime_dir() {}

fn main() -> ExitCode {
    give_mesa_a_runtime_dir();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Bake(args) => bake(args),
        Command::Bench(args) => {
            let options = shadeballs::bench::BenchOptions {
                quick: args.quick,
                out: args.out,
                exe: std::env::current_exe().ok(),
                cpu_only: args.cpu_only,
            };
            shadeballs::bench::run(&options)
                .map(|summary| println!("{summary}"))
                .map_err(Into::into)
        }
        Command::Render(args) => render_cmd::render(args),
        Command::Probe(args) => render_cmd::probe(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
