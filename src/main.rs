//! The `shadeballs` command line: parses flags, calls the library, reports.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::{Parser, Subcommand};

mod render_cmd;

use shadeballs::cli::{BakeArgs, BenchArgs, ProbeArgs, RenderArgs, TruthArgs, ViewArgs};
use shadeballs::lut::{self, io::write_tables, BakeConfig, Layout};

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
    Render(RenderArgs),
    /// Evaluate on the GPU what the shader reads from the tables on an N x N grid (CSV).
    Probe(ProbeArgs),
    /// Compare the models with the exact multiple scattering of a random walk on the
    /// microsurface (CSV tables, PNG plots, summary.md).
    Truth(TruthArgs),
    /// Open a window showing the shading balls, with a panel to change them live.
    View(ViewArgs),
}

fn truth(args: TruthArgs) -> anyhow::Result<()> {
    let start = Instant::now();
    let options = shadeballs::truth::TruthOptions {
        quick: args.quick,
        out: args.out,
    };
    let (summary, headline) = shadeballs::truth::run(&options)?;
    println!("{summary}");
    eprintln!(
        "truth: largest albedo error against the walk: accurate {:.2e}, games202 {:.2e} \
         (ratio {:.2}; walk standard error <= {:.1e}) in {:.1} s -> {}",
        headline.accurate,
        headline.games202,
        headline.accurate / headline.games202.max(f64::MIN_POSITIVE),
        headline.max_stderr,
        start.elapsed().as_secs_f64(),
        options.out.display()
    );
    Ok(())
}

fn bake(args: BakeArgs) -> anyhow::Result<()> {
    shadeballs::output::check_output_path(&args.out)?;
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
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => match shadeballs::cli::one_line_error(&e) {
            Some(line) => {
                eprintln!("{line}");
                return ExitCode::from(2);
            }
            None => e.exit(),
        },
    };
    let result = match cli.command {
        Command::Bake(args) => bake(args),
        Command::Bench(args) => {
            let options = shadeballs::bench::BenchOptions {
                quick: args.quick,
                out: args.out,
                exe: std::env::current_exe().ok(),
                cpu_only: args.cpu_only,
                only: args.only,
            };
            shadeballs::bench::run(&options)
                .map(|summary| println!("{summary}"))
                .map_err(Into::into)
        }
        Command::Render(args) => render_cmd::render(args),
        Command::Probe(args) => render_cmd::probe(args),
        Command::Truth(args) => truth(args),
        Command::View(args) => render_cmd::view(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", shadeballs::error::one_line(&format!("{e:#}")));
            ExitCode::FAILURE
        }
    }
}
