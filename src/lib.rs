//! shadeballs: shading balls for the Kulla-Conty multiple-scattering microfacet BRDF, and
//! the tables behind it for any wgpu program.
//!
//! The crate root is the facade a host program needs to bake the Kulla-Conty tables at
//! startup and shade with them on its own device:
//!
//! - [`bake`] a [`BakeConfig`] into [`Tables`]: `E(mu, roughness)` and `E_avg(roughness)`
//!   in about a millisecond on the CPU;
//! - [`LutParams`]: how to address a texel of them (a plain `repr(C)` struct, also the
//!   WGSL struct of that name);
//! - [`GpuTables::upload`] them onto the caller's `wgpu::Device` and `Queue`;
//! - [`wgsl::KULLA_CONTY`]: the WGSL of the BRDF and the table reads, functions that take
//!   the textures and the parameters as arguments, to put before the host's own shader;
//! - [`Renderer`]: draws a [`Scene`] of shading balls into any [`Target`] view the caller
//!   owns ([`Renderer::from_device`]).
//!
//! ```
//! // Bake at startup: the default table (64 x 64, the alpha-warped mu axis, Schlick G).
//! let tables = shadeballs::bake(&shadeballs::BakeConfig::default());
//! let params = tables.layout().lut_params();
//! assert_eq!((params.mu_size, params.r_size), (64, 64));
//! // E at normal incidence, roughness 0.5, as the shader reads it.
//! let e = tables.lut_e(1.0, 0.5);
//! assert!((e - 0.89507).abs() < 1e-3);
//! ```
//!
//! The modules, one line each, and who may import whom: docs/design/layers.md (a test
//! holds that list equal to the modules). With `default-features = false` the crate is the
//! library alone (no winit, egui, clap or plotting crate).

#![warn(missing_docs)]
// Crate-private code that only the command line (feature `cli`, which the lab builds on)
// or the tests beside it use is unused without it; the default build (`cli`, linted with
// `-D warnings`) still finds dead code.
#![cfg_attr(not(feature = "cli"), allow(dead_code, unused_imports))]

pub mod brdf;
pub mod cpu;
pub mod display;
pub mod environment;
pub mod error;
pub mod gpu;
#[cfg(feature = "gltf")]
pub mod import;
pub mod labels;
pub mod lut;
pub mod memory;
pub mod output;
pub mod prepared;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod stats;
pub mod walk;
pub mod wgsl;

#[cfg(feature = "cli")]
pub mod cli;
#[cfg(feature = "viewer")]
pub mod viewer;

/// The glam a [`Scene`]'s vectors are (`glam::DVec3`): a host builds scenes with it, no
/// version of its own to match.
pub use glam;
/// The wgpu the renderer draws with: a host's device, textures and views are of this
/// version.
pub use wgpu;

pub use brdf::Geometry;
pub use error::{Error, Result};
pub use gpu::{Gpu, GpuTables, Renderer, Target};
pub use lut::{bake, BakeConfig, Layout, LayoutKind, LutParams, Storage, Tables};
pub use scene::Scene;

// The crate's own tests that need its internals (`gpu::tests`, ...) share the suite's GPU
// and image helpers (tests/suite/pixels.rs, one copy), which name the crate `shadeballs`.
#[cfg(all(test, feature = "cli"))]
extern crate self as shadeballs;
#[cfg(all(test, feature = "cli"))]
#[allow(dead_code)] // the suite's helpers: the crate's tests use some of them
#[path = "../tests/suite/pixels.rs"]
mod pixels;
