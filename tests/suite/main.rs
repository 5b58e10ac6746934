//! The one test binary (each extra binary links wgpu again). Modules by layer.

mod bad_input;
mod bench;
mod brdf;
mod clamp;
mod cli;
mod cli_bake;
mod cli_fuzz;
mod cli_render;
mod extreme_scenes;
mod fuzz;
mod golden;
mod gpu_eval;
mod gpu_faults;
mod gpu_stress;
mod lut;
mod lut_chebyshev;
mod pixels;
mod probe;
mod props;
mod render;
mod scene;
mod scene_gen;
mod shaders;
mod stress;
mod truth;
mod viewer;
