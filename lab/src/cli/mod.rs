//! The `shadeballs-lab` command line: `bench`, `compare` and `truth`, one file each (the
//! flags in `args.rs`), reporting on stderr as the `shadeballs` binary does (its one-line
//! errors and advice, [`shadeballs::cli`]).

pub mod args;
mod bench;
mod compare;
mod truth;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

pub use args::*;

#[derive(Parser)]
#[command(
    name = "shadeballs-lab",
    version,
    about = "The shadeballs measurement lab: benchmarks, the truth study, picture comparisons"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Measure run time against error (writes CSV, PNG plots and a markdown summary).
    Bench(BenchArgs),
    /// Render every model's row of balls beside the truth's (a random walk) and measure
    /// each image's error against it (CSV, labelled PNG, heatmaps, a time-error plot).
    Compare(CompareArgs),
    /// Compare the models with the exact multiple scattering of a random walk on the
    /// microsurface (CSV tables, PNG plots, summary.md).
    Truth(TruthArgs),
}

/// Parses `std::env::args`, runs the subcommand and turns its error into one line on stderr
/// and the exit code (2 for bad flags, 1 for a failed run).
pub fn main() -> ExitCode {
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
        Command::Bench(args) => bench::run(args),
        Command::Compare(args) => compare::run(args),
        Command::Truth(args) => truth::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let advice = shadeballs::cli::advice(&e).map_or(String::new(), |a| format!(" ({a})"));
            eprintln!(
                "error: {}{advice}",
                shadeballs::error::one_line(&format!("{e:#}"))
            );
            ExitCode::FAILURE
        }
    }
}
