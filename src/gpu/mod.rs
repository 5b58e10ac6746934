//! The GPU renderer (DESIGN.md section 7, layer 4): device creation, the ball pipeline,
//! the tables as textures, headless rendering and the table probe. Knows nothing of
//! windows: [`Renderer::render`] draws into any `TextureView`.

mod context;
mod headless;
mod probe;
mod renderer;
pub mod resources;
pub mod shaders;
pub mod uniforms;

pub use context::{Backend, Gpu};
pub use headless::{HdrImage, LdrImage};
pub use probe::{ProbeSample, MAX_PROBE_GRID};
pub use renderer::{Renderer, Target};

/// Turns a wgpu error captured by an error scope into the library's error.
fn gpu_error(e: wgpu::Error) -> crate::Error {
    crate::Error::Gpu {
        message: e.to_string(),
    }
}
