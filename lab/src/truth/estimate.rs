//! Monte Carlo bookkeeping for the walk: per-path means with standard errors, and
//! seeded chunks of paths on rayon's pool.

use rayon::prelude::*;

use super::rng::Rng;

/// Paths per independent random stream (and per rayon task).
const CHUNK: usize = 4096;

/// Mean and standard error of a per-path value.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stat {
    pub sum: f64,
    pub sum_sq: f64,
    pub n: u64,
}

impl Stat {
    pub fn add(&mut self, x: f64) {
        self.sum += x;
        self.sum_sq += x * x;
        self.n += 1;
    }
    pub fn merge(&mut self, o: &Stat) {
        self.sum += o.sum;
        self.sum_sq += o.sum_sq;
        self.n += o.n;
    }
    pub fn mean(&self) -> f64 {
        self.sum / self.n.max(1) as f64
    }
    /// Standard error of the mean.
    pub fn stderr(&self) -> f64 {
        let n = self.n.max(2) as f64;
        let var = (self.sum_sq / n - self.mean() * self.mean()).max(0.0) * n / (n - 1.0);
        (var / n).sqrt()
    }
}

/// Splits `paths` into seeded chunks, runs `chunk(rng, count)` on rayon's pool and merges
/// the results in chunk order (deterministic for any thread count).
pub fn chunked<T: Send>(
    paths: usize,
    seed: &[u64],
    chunk: impl Fn(&mut Rng, usize) -> T + Sync,
    merge: impl Fn(T, T) -> T,
) -> Option<T> {
    let chunks = paths.div_ceil(CHUNK);
    let parts: Vec<T> = (0..chunks)
        .into_par_iter()
        .map(|k| {
            let mut keys = seed.to_vec();
            keys.push(k as u64);
            let count = CHUNK.min(paths - k * CHUNK);
            chunk(&mut Rng::new(&keys), count)
        })
        .collect();
    parts.into_iter().reduce(merge)
}
