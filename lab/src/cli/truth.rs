//! `shadeballs-lab truth`: the random-walk study of how far each model is from exact multiple
//! scattering (the lab's [`crate::truth`]).

use std::time::Instant;

use super::args::TruthArgs;

pub fn run(args: TruthArgs) -> anyhow::Result<()> {
    let start = Instant::now();
    shadeballs::output::check_output_folder(&args.out)?;
    let options = crate::truth::TruthOptions {
        quick: args.quick,
        out: args.out,
    };
    let (summary, headline) = crate::truth::run(&options)?;
    shadeballs::cli::print_stdout(&summary);
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
