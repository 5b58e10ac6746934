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
