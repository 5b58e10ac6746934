//! The `shadeballs-lab` binary: the process set up as the `shadeballs` binary's
//! ([`shadeballs::cli::process::init`]), then the lab's command line ([`shadeballs_lab::cli`]).

use std::process::ExitCode;

fn main() -> ExitCode {
    shadeballs::cli::process::init();
    shadeballs_lab::cli::main()
}
