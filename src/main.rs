//! The `shadeballs` binary: sets up the process ([`shadeballs::cli::process::init`]) and
//! runs the command line ([`shadeballs::cli`]).

use std::process::ExitCode;

/// A failed allocation is a one-line error, not an abort (`ExitsWhenShortOfMemory`).
#[global_allocator]
static ALLOCATOR: shadeballs::cli::process::ExitsWhenShortOfMemory =
    shadeballs::cli::process::ExitsWhenShortOfMemory;

fn main() -> ExitCode {
    shadeballs::cli::process::init();
    shadeballs::cli::main()
}
