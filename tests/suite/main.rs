//! The one test binary (each extra binary links wgpu again). Modules by layer.

mod brdf;
mod cli;
mod cli_bake;
mod cli_render;
mod golden;
mod gpu_eval;
mod gpu_stress;
mod lut;
mod pixels;
mod probe;
mod props;
mod render;
mod scene;
mod shaders;
mod stress;
