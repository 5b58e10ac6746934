//! `shadeballs-lab bench`: run time against error (the lab's [`crate::bench`]).

use super::args::BenchArgs;

pub fn run(args: BenchArgs) -> anyhow::Result<()> {
    shadeballs::output::check_output_folder(&args.out)?;
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
    let options = crate::bench::BenchOptions {
        quick: args.quick,
        out: args.out,
        exe: shadeballs_beside_this_binary(),
        cpu_only: args.cpu_only,
        only: args.only,
    };
    let summary = crate::bench::run(&options)?;
    shadeballs::cli::print_stdout(&summary);
    Ok(())
}

/// The `shadeballs` executable the startup sweep runs: the one beside this binary (cargo
/// builds both into the same folder), if it is there.
fn shadeballs_beside_this_binary() -> Option<std::path::PathBuf> {
    let exe = std::env::current_exe().ok()?;
    let name = format!("shadeballs{}", std::env::consts::EXE_SUFFIX);
    Some(exe.with_file_name(name)).filter(|p| p.is_file())
}
