//! shadeballs: shading balls for the Kulla-Conty multiple-scattering microfacet BRDF.
//!
//! Layers (DESIGN.md section 7), each importing only those above it in this list:
//! [`brdf`] (the maths), [`lut`] (baking and reading the tables).

pub mod bench;
pub mod brdf;
pub mod cli;
pub mod cpu;
pub mod error;
pub mod gpu;
pub mod image_out;
pub mod lut;
pub mod output;
pub mod scene;
pub mod truth;
pub mod viewer;

pub use error::{Error, Result};
