//! The one test binary (each extra binary links wgpu again). Modules by layer.

mod brdf;
mod lut;
