//! A Monte Carlo reference kept on disk between runs of the lab's examples
//! (`lab/examples/lobe_sweep.rs`, `lab/examples/light_trial.rs`): each pixel's mean and
//! standard error, six f64 little-endian, written atomically. A cache: a file that is
//! missing or does not fit reads as none, and a failure to keep one costs the next run the
//! render, nothing else.

use std::path::Path;

use glam::DVec3;
use shadeballs::cpu::MonteCarloImage;
use shadeballs::output::write_atomic;

/// Bytes a pixel takes: its mean and its standard error, three f64 each.
const PIXEL_BYTES: usize = 48;

/// `shape` (its size, estimates, coverage and pixel filter: the caller's) with the means and
/// standard errors kept at `path`; `None` where there is no such file or its size is not
/// `shape`'s.
pub fn read(path: &Path, mut shape: MonteCarloImage) -> Option<MonteCarloImage> {
    let bytes = std::fs::read(path).ok()?;
    let pixels = (shape.width * shape.height) as usize;
    if bytes.len() != pixels * PIXEL_BYTES {
        return None;
    }
    let values: Vec<f64> = bytes
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect();
    let vec = |k: usize| DVec3::new(values[k], values[k + 1], values[k + 2]);
    shape.mean = (0..pixels).map(|i| vec(6 * i)).collect();
    shape.std_error = (0..pixels).map(|i| vec(6 * i + 3)).collect();
    Some(shape)
}

/// Keeps `mc`'s means and standard errors at `path` (its folder made where missing), for
/// [`read`]; a failure is ignored (see the module).
pub fn write(path: &Path, mc: &MonteCarloImage) {
    let mut bytes = Vec::with_capacity(mc.mean.len() * PIXEL_BYTES);
    for (m, s) in mc.mean.iter().zip(&mc.std_error) {
        for x in m.to_array().into_iter().chain(s.to_array()) {
            bytes.extend_from_slice(&x.to_le_bytes());
        }
    }
    if let Some(dir) = path.parent() {
        if std::fs::create_dir_all(dir).is_ok() {
            let _ = write_atomic(path, &bytes);
        }
    }
}
