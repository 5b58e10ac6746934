//! The lab's one test binary (each extra binary links wgpu again): the benchmark harness,
//! the picture comparison, the truth study, the scale, harmonics and light sweeps, and the
//! `shadeballs-lab` command line.

mod bench;
mod cli;
mod compare;
mod harmonics;
mod light;
// The GPU tests' shared helpers, the library suite's own file.
#[allow(dead_code)]
#[path = "../../../tests/suite/pixels.rs"]
mod pixels;
mod scale;
mod truth;

/// Held by each test that runs a `--quick` bench, and by the lab's heaviest tests in this
/// process (a second or more of both cores each): `bench --quick` has a goal in seconds
/// (under a minute on the 2-core machine), which a second bench or a heavy test on the
/// same two cores would measure instead (a clean-clone CI measured 61.7 s beside them,
/// 39.4 s alone). The lighter tests still run beside them.
pub static QUICK_BENCH: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Takes [`QUICK_BENCH`] (a test that panicked while holding it leaves it usable).
pub fn quick_bench_turn() -> std::sync::MutexGuard<'static, ()> {
    QUICK_BENCH.lock().unwrap_or_else(|e| e.into_inner())
}
