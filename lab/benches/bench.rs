//! `cargo bench -p shadeballs-lab`: the same harness as `shadeballs-lab bench` (one bench
//! binary). `cargo bench -p shadeballs-lab -- --quick` runs the short version. The startup
//! sweep runs the `shadeballs` binary of the same target folder (`cargo build --release`
//! builds it).

use std::path::PathBuf;

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let lab = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let out = lab.join("../target/bench-results");
    // The bench binary lies in target/release/deps; the `shadeballs` binary one folder up.
    let exe = std::env::current_exe()
        .ok()
        .and_then(|p| Some(p.parent()?.parent()?.join("shadeballs")))
        .filter(|p| p.is_file());
    match shadeballs_lab::bench::run(&shadeballs_lab::bench::BenchOptions {
        quick,
        out: out.clone(),
        exe,
        cpu_only: false,
        only: Vec::new(),
    }) {
        Ok(summary) => println!("{summary}\nwritten to {}", out.display()),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    }
}
