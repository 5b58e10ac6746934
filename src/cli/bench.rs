//! `shadeballs bench`: run time against error (the lab's [`crate::lab::bench`]).

use super::args::BenchArgs;

pub fn run(args: BenchArgs) -> anyhow::Result<()> {
    let options = crate::lab::bench::BenchOptions {
        quick: args.quick,
        out: args.out,
        exe: std::env::current_exe().ok(),
        cpu_only: args.cpu_only,
        only: args.only,
    };
    let summary = crate::lab::bench::run(&options)?;
    println!("{summary}");
    Ok(())
}
