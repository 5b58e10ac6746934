//! The lab's flags: what `shadeballs-lab bench`, `compare` and `truth` accept. Public so
//! that the lab's tests parse argv in-process with exactly the binary's rules
//! (`clap::Args::augment_args` and `FromArgMatches`). The scene's flags and the backend's
//! values are the `shadeballs` command line's ([`shadeballs::cli::SceneArgs`]).

use std::path::PathBuf;

use shadeballs::cli::SceneArgs;
use shadeballs::gpu::Backend;

use crate::bench::SweepKind;

impl clap::ValueEnum for SweepKind {
    fn value_variants<'a>() -> &'a [Self] {
        &SweepKind::ALL
    }
    fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
        Some(clap::builder::PossibleValue::new(self.name()))
    }
}

/// Flags of `shadeballs-lab bench`.
#[derive(clap::Args)]
pub struct BenchArgs {
    /// Fewer configurations and repeats (under a minute).
    #[arg(long)]
    pub quick: bool,
    /// Folder for the CSV files, plots (PNG) and summary.md.
    #[arg(long, default_value = "bench-results")]
    pub out: PathBuf,
    /// Only the sweeps that need no GPU: for a machine without a GPU driver.
    #[arg(long)]
    pub cpu_only: bool,
    /// Only these sweeps, comma-separated, given once (default: all).
    #[arg(long, value_delimiter = ',', action = clap::ArgAction::Set)]
    pub only: Vec<SweepKind>,
}

/// Flags of `shadeballs-lab truth`.
#[derive(clap::Args)]
pub struct TruthArgs {
    /// A few cells and slices with few paths (seconds) instead of the full study.
    #[arg(long)]
    pub quick: bool,
    /// Folder for the CSV files, the PNG plots and summary.md.
    #[arg(long, default_value = "truth-results")]
    pub out: PathBuf,
}

/// Flags of `shadeballs-lab compare`.
#[derive(clap::Args)]
pub struct CompareArgs {
    /// The scene: its roughness values, one ball's material (--ball), lights and environment.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Folder for compare.csv, compare.png, heatmaps.png, time_vs_error.png, summary.md.
    #[arg(long, default_value = "compare-results")]
    pub out: PathBuf,
    /// Estimates per pixel of the truth row, 2..=65536 (default 256; --quick 32).
    #[arg(long, allow_negative_numbers = true,
          value_parser = clap::value_parser!(u32).range(2..=i64::from(shadeballs::cpu::montecarlo::MAX_SPP)))]
    pub spp: Option<u32>,
    /// Random seed of the truth.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    pub seed: u64,
    /// The ball whose material the rows take, counted from 1 in the scene's order.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true,
          value_parser = clap::value_parser!(u32).range(1..))]
    pub ball: u32,
    /// Smaller rows (64 pixels a ball instead of 160), 32 truth estimates a pixel, frame
    /// times at 640x360: seconds instead of a minute.
    #[arg(long)]
    pub quick: bool,
    /// Where the models render (auto: any GPU adapter, else the CPU reference renderer).
    #[arg(long, default_value_t = Backend::Auto, value_parser = parse_compare_backend)]
    pub backend: Backend,
}

/// `compare --backend`: a GPU backend or the CPU reference renderer (the truth always
/// runs on the CPU).
pub fn parse_compare_backend(s: &str) -> Result<Backend, String> {
    match s.parse::<Backend>() {
        Ok(Backend::Montecarlo | Backend::MontecarloCpu | Backend::Truth) => Err(
            "the models render on auto, vulkan, gl or cpu (the truth row is always the CPU's)"
                .to_string(),
        ),
        Ok(b) => Ok(b),
        Err(_) => Err(format!(
            "'{s}' is not a backend: use auto, vulkan, gl or cpu"
        )),
    }
}
