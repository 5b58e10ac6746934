//! `cargo bench`: the same harness as `shadeballs bench` (one bench binary).
//! `cargo bench -- --quick` runs the short version.

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let out = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/bench-results");
    match shadeballs::lab::bench::run(&shadeballs::lab::bench::BenchOptions {
        quick,
        out: out.clone(),
        exe: Some(env!("CARGO_BIN_EXE_shadeballs").into()),
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
