//! The scenes' tests that need the crate's internals (moved from the suite, tests/suite):
//! materials, anisotropy, the clear coat, emission, the showcase and antialiasing, on the GPU and the
//! CPU. They build with the command line's features only, so `cargo test
//! --no-default-features --lib` does not run them a second time.

mod anisotropy;
mod antialias;
mod base_reading;
mod clamp;
mod clearcoat;
mod emission;
mod materials;
mod reading_table;
mod showcase;
