//! `shadeballs bench`: run time against error (the lab's [`crate::lab::bench`]).

use super::args::BenchArgs;

pub fn run(args: BenchArgs) -> anyhow::Result<()> {
    crate::output::check_output_folder(&args.out)?;
    // `--cpu-only` skips the GPU sweeps: a selection of GPU sweeps only would measure
    // nothing.
    if args.cpu_only && !args.only.is_empty() && args.only.iter().all(|k| k.needs_gpu()) {
        let names: Vec<&str> = args.only.iter().map(|k| k.name()).collect();
        anyhow::bail!(
            "--only {} needs a GPU and --cpu-only skips it: nothing to measure (drop \
             --cpu-only, or add a CPU sweep: bake, plan, read)",
            names.join(",")
        );
    }
    let options = crate::lab::bench::BenchOptions {
        quick: args.quick,
        out: args.out,
        exe: std::env::current_exe().ok(),
        cpu_only: args.cpu_only,
        only: args.only,
    };
    let summary = crate::lab::bench::run(&options)?;
    super::print_stdout(&summary);
    Ok(())
}
