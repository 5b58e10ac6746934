//! A scene's own rows: one row of E along mu per roughness the scene uses, baked at that
//! roughness exactly, instead of a 2-D table read between rows.
//!
//! ## Why
//!
//! A shading-ball scene holds a few roughness values (the default scene five). A 2-D table
//! answers every roughness by blending two rows, and its error is largest between rows
//! (docs/benchmarks.md, "Measured results": 1.1e-4 at 64 x 64). A row baked at the ball's own roughness
//! leaves only the read along mu: the shader reads it with the same `lut_loss_row` and a
//! row weight of 0, and the ball's `1 - E_avg` is that row's integral as read, so the lobe
//! restores exactly the energy the read E misses (`row_loss_avg_at` in `mod.rs`). Each
//! row costs the quadrature at [`CHEBYSHEV_MU_NODES`] points (Chebyshev bake) or one
//! estimate a texel (the other methods), so a few rows cost less than the 2-D table's 425
//! quadratures; past a count measured by `shadeballs-lab bench` the 2-D table is cheaper
//! (`gpu::plan::MAX_PLANNED_ROWS`).
//!
//! Rows are keyed by everything that changes their values ([`RowKey`]), so a cache can hand
//! out a row baked once to any scene that needs it again.

use std::sync::Arc;

use rayon::prelude::*;

use super::chebyshev::{ChebyshevSurface, CHEBYSHEV_MU_NODES};
use super::estimators::{Estimator, Method};
use super::layout::{roughness_coord, Layout};
use super::{finish_row_at, read_row, BakeConfig};
use crate::brdf::alpha_from_roughness;

/// Everything that changes a row's values: the bake settings (the layout's `r_size`
/// normalised away; its other fields are kept, so two layouts that differ only along
/// roughness bake their rows twice, never read a stale one), and the row's roughness (the
/// f32 the shader reads at, clamped, as bits).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RowKey {
    /// The bake settings, `layout.r_size` set to 1.
    pub config: BakeConfig,
    /// The row's roughness (clamped, f32) as bits, so the key is `Eq` and `Hash`.
    pub roughness_bits: u32,
}

impl RowKey {
    /// The key of the row at `roughness` (clamped like every read) baked with `config`.
    pub fn new(config: &BakeConfig, roughness: f32) -> Self {
        let mut config = *config;
        config.layout.r_size = 1;
        RowKey {
            config,
            roughness_bits: roughness_coord(roughness).to_bits(),
        }
    }

    /// The row's roughness (clamped).
    pub(crate) fn roughness(&self) -> f32 {
        f32::from_bits(self.roughness_bits)
    }
}

/// One baked row.
#[derive(Clone, Debug)]
pub struct Row {
    /// What the row was baked for.
    pub key: RowKey,
    /// E per texel (f64), `layout.mu_size` of them.
    pub e: Vec<f64>,
    /// `1 - E` after the layout's storage quantisation: what the shader reads.
    pub stored_loss: Vec<f32>,
    /// `2 int_0^1 E(mu) mu dmu` of the row as the shader reads it.
    pub e_avg: f64,
    /// `1 - e_avg` in f32: a per-ball uniform, never stored in the table's format.
    pub loss_avg: f32,
}

/// Bakes the row of `key`.
pub(crate) fn bake_row(key: &RowKey) -> Row {
    let config = &key.config;
    let layout = &config.layout;
    let roughness = key.roughness() as f64;
    let alpha = alpha_from_roughness(roughness);
    let mu_of = |i: usize| {
        layout
            .mu_axis
            .value(layout.texel_coord(i, layout.mu_size), alpha)
    };
    let e: Vec<f64> = if config.method == Method::Chebyshev {
        let series = super::chebyshev::exact_row(
            config.geometry,
            config.samples,
            roughness,
            CHEBYSHEV_MU_NODES,
        );
        (0..layout.mu_size)
            .map(|i| ChebyshevSurface::e_in_row(&series, mu_of(i), roughness))
            .collect()
    } else {
        let mut est = Estimator::new(config.method, config.points, config.samples);
        let seed = key.roughness_bits as u64 * layout.mu_size as u64;
        (0..layout.mu_size)
            .map(|i| est.e(mu_of(i), roughness, config.geometry, seed + i as u64))
            .collect()
    };
    let (e, stored_loss, e_avg) = finish_row_at(layout, alpha, e);
    Row {
        key: *key,
        e,
        stored_loss,
        e_avg,
        loss_avg: (1.0 - e_avg) as f32,
    }
}

/// Bakes the rows of `keys`, one task a row on rayon's pool.
pub fn bake_rows(keys: &[RowKey]) -> Vec<Row> {
    keys.par_iter().map(bake_row).collect()
}

/// The rows a scene reads, in order: row `j` of the GPU's E texture.
#[derive(Clone, Debug)]
pub struct RowSet {
    /// The bake settings; `layout.r_size` is the number of rows.
    pub config: BakeConfig,
    /// The rows, row `j` of the texture at index `j`.
    pub rows: Vec<Arc<Row>>,
}

impl RowSet {
    /// The set of `rows` (at least one), all baked with one config.
    pub(crate) fn new(rows: Vec<Arc<Row>>) -> Self {
        let mut config = rows.first().map(|r| r.key.config).unwrap_or_default();
        config.layout.r_size = rows.len().max(1);
        RowSet { config, rows }
    }

    /// The rows of `config` at each of `roughness`, baked from nothing (no cache).
    pub fn bake(config: &BakeConfig, roughness: &[f32]) -> Self {
        let keys: Vec<RowKey> = roughness.iter().map(|&r| RowKey::new(config, r)).collect();
        RowSet::new(bake_rows(&keys).into_iter().map(Arc::new).collect())
    }

    /// The rows' layout as one table: `config.layout`, one row per roughness.
    pub(crate) fn layout(&self) -> &Layout {
        &self.config.layout
    }

    /// The rows' stored `1 - E`, row after row (a `mu_size x rows` table).
    pub(crate) fn stored_loss(&self) -> Vec<f32> {
        self.rows
            .iter()
            .flat_map(|r| r.stored_loss.iter().copied())
            .collect()
    }

    /// The index of the row nearest `roughness` (clamped; the exact row when the set holds
    /// it, as a planned set does for every ball it was planned for).
    pub(crate) fn index_of(&self, roughness: f32) -> usize {
        let r = roughness_coord(roughness);
        self.rows
            .iter()
            .enumerate()
            .min_by(|a, b| {
                let da = (a.1.key.roughness() - r).abs();
                let db = (b.1.key.roughness() - r).abs();
                da.total_cmp(&db)
            })
            .map_or(0, |(j, _)| j)
    }

    /// The read parameters of the rows as one table: the mu axis of their layout, one row
    /// each, no roughness axis (each ball names its row: [`RowSet::lut_row`]).
    pub(crate) fn lut_params(&self) -> crate::lut::LutParams {
        let l = self.layout();
        crate::lut::LutParams {
            r_scale: 0.0,
            r_bias: 0.0,
            r_size: self.rows.len() as u32,
            r_min: 0.0,
            ..l.lut_params()
        }
    }

    /// A ball's row for `lut_loss_row` (`Tables::lut_row`'s form): `[row index, 0 (no
    /// weight on the next row), alpha]`, alpha in f32 as `Tables::lut_row` forms it.
    pub(crate) fn lut_row(&self, roughness: f32) -> [f32; 3] {
        let r = roughness_coord(roughness);
        [self.index_of(roughness) as f32, 0.0, r * r]
    }

    /// `lut_loss_row` of `shaders/lut.wgsl` on these rows: the f32 arithmetic of
    /// `Tables::lut_loss_row`, the next row weighted by `row[1]` (0 from [`RowSet::lut_row`]).
    pub(crate) fn lut_loss_row(&self, mu: f32, row: [f32; 3]) -> f32 {
        let t = |i: usize, j: usize| self.rows[j].stored_loss[i];
        read_row(self.layout(), self.rows.len(), mu, row, t)
    }

    /// `1 - E` as a ball at `roughness` reads it.
    pub fn lut_loss(&self, mu: f32, roughness: f32) -> f32 {
        self.lut_loss_row(mu, self.lut_row(roughness))
    }

    /// `1 - E_avg` of the ball's row (a per-ball uniform).
    pub(crate) fn lut_loss_avg(&self, roughness: f32) -> f32 {
        self.rows[self.index_of(roughness)].loss_avg
    }
}
