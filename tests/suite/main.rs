//! The one test binary (each extra binary links wgpu again). Modules by layer.

mod bad_input;
mod brdf;
mod cli;
mod cli_bake;
mod cli_render;
mod fuzz;
mod golden;
mod gpu_eval;
mod gpu_stress;
mod lut;
mod pixels;
mod probe;
mod props;
mod render;
mod scene;
mod scene_gen;
mod shaders;
mod stress;
