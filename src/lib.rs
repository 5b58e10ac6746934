//! shadeballs: shading balls for the Kulla-Conty multiple-scattering microfacet BRDF.
//!
//! Layers (docs/design.md, "Layers"), each importing only those listed before it:
//! [`brdf`] (the maths), [`lut`] (baking and reading the tables), [`scene`], then the
//! renderers [`gpu`] and [`cpu`] with [`display`] and [`output`]. The front ends sit on top:
//! [`cli`] (feature `cli`) and [`viewer`] (feature `viewer`); the measurement lab, [`lab`]
//! (feature `lab`), imports the library and nothing imports it but the command line.

pub mod brdf;
pub mod cpu;
pub mod display;
pub mod error;
pub mod gpu;
pub mod lut;
pub mod output;
pub mod scene;
pub mod stats;

#[cfg(feature = "cli")]
pub mod cli;
#[cfg(feature = "lab")]
pub mod lab;
#[cfg(feature = "viewer")]
pub mod viewer;

pub use error::{Error, Result};
