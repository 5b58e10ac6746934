//! The `shadeballs` binary: sets up the process ([`shadeballs::cli::process::init`]) and
//! runs the command line ([`shadeballs::cli`]).

use std::process::ExitCode;

fn main() -> ExitCode {
    shadeballs::cli::process::init();
    shadeballs::cli::main()
}
