//! Errors of baked tables against the precise reference: the bake error (each texel's value
//! at its exact coordinates) and the read-path error (what the shader's lookup returns at
//! arbitrary `(mu, roughness)`).

use rayon::prelude::*;

use super::{e_avg_reference, e_reference, Layout, Tables};
use crate::brdf::Geometry;

/// Summary of absolute errors.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ErrorStats {
    /// Largest error (infinite when any error is NaN).
    pub max: f64,
    /// Mean error (0 for no errors).
    pub mean: f64,
    /// How many errors were folded.
    pub count: usize,
    /// `(mu, roughness)` of the largest error (mu is NaN for E_avg).
    pub worst_at: (f64, f64),
}

impl ErrorStats {
    /// Folds `(error, mu, roughness)` triples.
    pub fn from_errors(errors: impl IntoIterator<Item = (f64, f64, f64)>) -> Self {
        let mut s = ErrorStats::default();
        let mut sum = 0.0;
        for (e, mu, r) in errors {
            let e = if e.is_nan() { f64::INFINITY } else { e };
            if e > s.max || s.count == 0 {
                s.max = e;
                s.worst_at = (mu, r);
            }
            sum += e;
            s.count += 1;
        }
        s.mean = if s.count > 0 {
            sum / s.count as f64
        } else {
            0.0
        };
        s
    }
}

/// Precise values at every texel of a layout: what a perfect bake would hold.
#[derive(Clone, Debug)]
pub struct ReferenceTables {
    /// The layout whose texels these are.
    pub layout: Layout,
    /// The masking-shadowing term.
    pub geometry: Geometry,
    /// Precise E per texel, row-major (row = roughness), `layout.mu_size` per row.
    pub e: Vec<f64>,
    /// Precise E_avg per roughness row.
    pub e_avg: Vec<f64>,
}

impl ReferenceTables {
    /// [`e_reference`] at every texel of `layout` and [`e_avg_reference`] of every row, on
    /// rayon's pool.
    pub fn new(layout: Layout, geometry: Geometry) -> Self {
        let l = layout;
        let e = (0..l.texels())
            .into_par_iter()
            .map(|k| {
                e_reference(
                    l.mu_of_texel(k % l.mu_size, k / l.mu_size),
                    l.roughness_of_texel(k / l.mu_size),
                    geometry,
                )
            })
            .collect();
        let e_avg = (0..l.r_size)
            .into_par_iter()
            .map(|j| e_avg_reference(l.roughness_of_texel(j), geometry))
            .collect();
        Self {
            layout,
            geometry,
            e,
            e_avg,
        }
    }

    /// Bake error of every E texel and every E_avg texel of `tables`: `(E, E_avg)`.
    /// `tables` must have this layout's texel coordinates and geometry.
    pub fn bake_error(&self, tables: &Tables) -> (ErrorStats, ErrorStats) {
        let l = self.layout;
        assert_eq!(
            tables.config.geometry, self.geometry,
            "reference of another geometry term"
        );
        assert_eq!(tables.e.len(), self.e.len(), "reference of another layout");
        let e = (0..l.texels()).map(|k| {
            let (mu, r) = (
                l.mu_of_texel(k % l.mu_size, k / l.mu_size),
                l.roughness_of_texel(k / l.mu_size),
            );
            ((tables.e[k] - self.e[k]).abs(), mu, r)
        });
        let avg = (0..l.r_size).map(|j| {
            (
                (tables.e_avg[j] - self.e_avg[j]).abs(),
                f64::NAN,
                l.roughness_of_texel(j),
            )
        });
        (ErrorStats::from_errors(e), ErrorStats::from_errors(avg))
    }
}

/// Precise E at sample points, kept to compare many tables against the same points.
#[derive(Clone, Debug)]
pub struct ReferencePoints {
    /// The masking-shadowing term.
    pub geometry: Geometry,
    /// The sample points, `(mu, roughness)`.
    pub points: Vec<(f64, f64)>,
    /// Precise E at each point.
    pub e: Vec<f64>,
}

impl ReferencePoints {
    /// [`e_reference`] at each of `points` (`(mu, roughness)`), on rayon's pool.
    pub fn new(points: Vec<(f64, f64)>, geometry: Geometry) -> Self {
        let e = points
            .par_iter()
            .map(|&(mu, r)| e_reference(mu, r, geometry))
            .collect();
        Self {
            geometry,
            points,
            e,
        }
    }

    /// Read-path error of E: the shader's lookup of `tables` against the reference.
    pub fn read_error(&self, tables: &Tables) -> ErrorStats {
        assert_eq!(
            tables.config.geometry, self.geometry,
            "reference of another geometry term"
        );
        ErrorStats::from_errors(self.points.iter().zip(&self.e).map(|(&(mu, r), &exact)| {
            (
                (tables.lut_e(mu as f32, r as f32) as f64 - exact).abs(),
                mu,
                r,
            )
        }))
    }
}

/// `n` uniformly random points in `[0, 1]^2` (SplitMix64, fixed `seed`): reproducible.
pub fn random_points(n: usize, seed: u64) -> Vec<(f64, f64)> {
    let mut state = seed;
    let mut next = move || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n).map(|_| (next(), next())).collect()
}
