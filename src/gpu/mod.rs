//! The GPU renderer (docs/design/layers.md, "Imports run one way"): the device ([`Gpu`],
//! its own or a host's), the plan of a scene, the tables as textures ([`GpuTables`], usable
//! by any wgpu program), the ball pipelines, headless rendering, the Monte Carlo of the model and the table probe. Knows
//! nothing of windows: [`Renderer::render`] draws into any `TextureView`.

mod accumulate;
mod ball;
mod bindings;
#[cfg(test)] // the tests check the layouts on both sides against it
pub(crate) mod boundary;
mod context;
mod depth;
pub(crate) mod environment;
mod map_cache;
mod montecarlo;
mod pipelines;
pub(crate) mod plan;
pub mod readback;
mod renderer;
pub mod shaders;
mod specialise;
mod sums;
mod table_cache;
#[cfg(all(test, feature = "cli"))]
mod tests;
mod truth;
pub mod uniforms;
mod upload;

pub(crate) use bindings::texture_load_layout;
pub use context::Backend;
pub use context::Gpu;
#[cfg(test)]
pub(crate) use map_cache::MAX_PREFILTERED_MAPS;
#[cfg(test)]
pub(crate) use montecarlo::PASS_SAMPLES as MC_PASS_SAMPLES;
pub use plan::DrawOptions;
pub use plan::Plan;
#[cfg(test)]
pub use plan::TablePolicy;
pub use plan::TermMode;
pub(crate) use plan::Variant;
pub use plan::MAX_PLANNED_ROWS;
pub(crate) use renderer::headless::MAX_TRUTH_SPP;
pub(crate) use renderer::probe::MAX_PROBE_GRID;
pub use renderer::Renderer;
pub use renderer::Target;
pub use upload::loss_quads;
pub use upload::GpuTables;

/// Error scopes around one operation: validation and out-of-memory errors are returned by
/// [`Scopes::pop`] instead of reaching the uncaptured-error handler. Dropped without a pop
/// (an early return), the guards pop their scopes themselves: the fields drop in
/// declaration order, so the inner scope (validation, pushed last) is declared first, or
/// wgpu panics with "Mismatched pop_error_scope call" (issue 28, 1).
struct Scopes {
    validation: wgpu::ErrorScopeGuard,
    out_of_memory: wgpu::ErrorScopeGuard,
}

impl Scopes {
    fn push(device: &wgpu::Device) -> Self {
        let out_of_memory = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        Scopes {
            validation,
            out_of_memory,
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
