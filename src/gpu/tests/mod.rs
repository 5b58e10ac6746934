//! The GPU layer's tests that need the crate's internals (moved from the suite, tests/suite):
//! the CPU/GPU boundary, the shaders' composition and data flow, the plan, the WGSL functions
//! under stress and image-based lighting. They build with the command line's features only,
//! so `cargo test --no-default-features --lib` does not run them a second time.

mod boundary;
mod gpu_eval;
mod gpu_stress;
mod gpu_truth;
mod ibl;
mod montecarlo;
mod plan;
mod planned;
mod render;
mod shaders;
mod specialise;
mod stress;
mod tone_map;
mod uniform_flow;
