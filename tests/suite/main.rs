//! The one test binary (each extra binary links wgpu again). Modules by layer.

mod bench;
mod brdf;
mod cli;
mod cli_bake;
mod cli_render;
mod golden;
mod lut;
mod lut_chebyshev;
mod pixels;
mod probe;
mod render;
mod scene;
mod shaders;
