//! The GPU renderer (DESIGN.md section 7, layer 4): device creation, the ball pipeline,
//! the tables as textures, headless rendering and the table probe. Knows nothing of
//! windows: [`Renderer::render`] draws into any `TextureView`.

mod context;
mod draw;
mod headless;
pub mod plan;
mod probe;
pub mod readback;
mod renderer;
pub mod resources;
pub mod shaders;
mod tables;
pub mod uniforms;

pub use context::{Backend, Gpu};
pub use headless::{HdrImage, LdrImage};
pub use plan::{DrawOptions, Plan, TablePlan, TablePolicy, TermMode, Variant, MAX_PLANNED_ROWS};
pub use probe::{ProbeSample, MAX_PROBE_GRID};
pub use renderer::{is_linear, Renderer, Target, QUAD_PAD_PX};
pub use tables::MAX_CACHED_ROWS;
pub use uniforms::BoundTables;

/// Error scopes around one operation: validation and out-of-memory errors are returned by
/// [`Scopes::pop`] instead of reaching the uncaptured-error handler.
struct Scopes {
    out_of_memory: wgpu::ErrorScopeGuard,
    validation: wgpu::ErrorScopeGuard,
}

impl Scopes {
    fn push(device: &wgpu::Device) -> Self {
        Scopes {
            out_of_memory: device.push_error_scope(wgpu::ErrorFilter::OutOfMemory),
            validation: device.push_error_scope(wgpu::ErrorFilter::Validation),
        }
    }

    /// Pops both scopes (innermost first); out of memory, the likelier root cause, wins.
    fn pop(self) -> crate::Result<()> {
        let validation = pollster::block_on(self.validation.pop());
        let out_of_memory = pollster::block_on(self.out_of_memory.pop());
        match out_of_memory.or(validation) {
            Some(e) => Err(gpu_error(e)),
            None => Ok(()),
        }
    }
}

/// Turns a wgpu error captured by an error scope into the library's error.
fn gpu_error(e: wgpu::Error) -> crate::Error {
    crate::Error::Gpu {
        message: crate::error::one_line(&e.to_string()),
    }
}
