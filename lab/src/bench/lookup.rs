//! Reading on the GPU: what one read of the E table costs in a compute shader and what it
//! returns, for the shader's manual bilinear read (`lut_loss`: one `textureLoad` of a 2x2
//! block, three lerps) against the sampler's hardware filtering of a one-texel-per-value
//! texture, per layout and storage (`lookup.wgsl` beside this file).
//!
//! Cost: the median wall time of a dispatch (submit to idle) of `INVOCATIONS` invocations
//! doing `reads` reads each at hashed `(mu, roughness)`, divided by the reads; the
//! `lookup_none` row does the same loop without the read. Error: one read per invocation
//! read back and compared with the precise reference at the same points.

pub use super::kernel::{lookup_source, Filter, INVOCATIONS};

use super::device::filterable;
use super::kernel::Kernel;
use super::median_ms;
use shadeballs::error::{Error, Result};
use shadeballs::gpu::Gpu;
use shadeballs::lut::accuracy::{ErrorStats, ReferencePoints};
use shadeballs::lut::Tables;

/// PCG hash, as `pcg_hash` in `lookup.wgsl`.
pub fn pcg_hash(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// The first point of invocation `k`: `(mu, roughness)` as the shader draws them.
pub fn first_point(k: u32) -> (f32, f32) {
    let a = pcg_hash(k);
    let b = pcg_hash(a);
    let unit = |h: u32| (h >> 8) as f32 / 16_777_216.0;
    (unit(a), unit(b))
}

/// One measured read: cost per read and the error of the values it returns.
pub struct Lookup {
    pub ns_per_read: f64,
    /// Error of E against the reference at the first point of each invocation (`None` for
    /// [`Filter::None`]).
    pub error: Option<ErrorStats>,
}

/// Bytes of the E texture `filter` reads `tables` from: 2x2 blocks of f32 for the manual
/// read, the storage format for the sampler.
pub fn texture_bytes(tables: &Tables, filter: Filter) -> usize {
    let l = tables.layout();
    match filter {
        Filter::Hardware => l.texels() * l.storage.bytes_per_texel(),
        Filter::None | Filter::Manual => l.texels() * 16,
    }
}

/// Times `filter` reading `tables` (`reads` per invocation, median of `repeats`) and
/// measures its error against `reference` (points from [`first_point`]).
pub fn measure(
    gpu: &Gpu,
    tables: &Tables,
    filter: Filter,
    reads: u32,
    repeats: usize,
    reference: &ReferencePoints,
) -> Result<Lookup> {
    if filter == Filter::Hardware && !filterable(gpu, tables.layout().storage) {
        return Err(Error::Gpu {
            message: format!(
                "{} cannot filter {} textures",
                gpu.describe(),
                tables.layout().storage
            ),
        });
    }
    let kernel = Kernel::new(gpu, tables, filter)?;
    let (ms, _) = median_ms(repeats, || kernel.run(gpu, reads, INVOCATIONS, false));
    let ns_per_read = ms * 1e6 / (reads as f64 * INVOCATIONS as f64);
    let error = if filter == Filter::None {
        None
    } else {
        let n = reference.points.len() as u32;
        let values = kernel.run(gpu, 1, n, true)?;
        Some(ErrorStats::from_errors(
            values
                .iter()
                .zip(&reference.e)
                .zip(&reference.points)
                .map(|((&loss, &exact), &(mu, r))| ((1.0 - loss as f64 - exact).abs(), mu, r)),
        ))
    };
    Ok(Lookup { ns_per_read, error })
}

/// `n` points exactly as the shader's invocations `0..n` draw their first read, in f64.
pub fn shader_points(n: u32) -> Vec<(f64, f64)> {
    (0..n)
        .map(|k| {
            let (mu, r) = first_point(k);
            (mu as f64, r as f64)
        })
        .collect()
}
