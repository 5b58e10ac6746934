//! The models' directional albedo on the study's cells, and its error against the walk.

use super::albedo::{Cell, Channel, FresnelKind};
use super::models::{
    fdez_aguera_albedo, kc_albedo, preset_f_add, turquin_scale, FAvgSource, KcParts, ModelTables,
};
use shadeballs::brdf::{f_avg_schlick, FAvgForm, Geometry};

/// Per roughness and G, what the Kulla-Conty lobe needs from the tables.
struct RowData {
    e_avg: f64,
    ms_norm: f64,
}

/// The models evaluated on the study's cells.
pub struct Comparison<'a> {
    pub cells: &'a [Cell],
    pub channels: &'a [Channel],
    pub tables: &'a ModelTables,
    /// The G the `accurate` preset renders with by default.
    pub accurate_geometry: Geometry,
    rows: Vec<(f64, Geometry, RowData)>,
}

/// Names of the main comparison's models, in column order.
pub const MODELS: [&str; 5] = ["none", "accurate", "games202", "turquin", "fdez-aguera"];

impl<'a> Comparison<'a> {
    pub fn new(
        cells: &'a [Cell],
        channels: &'a [Channel],
        tables: &'a ModelTables,
        accurate_geometry: Geometry,
    ) -> Self {
        let mut roughness: Vec<f64> = cells.iter().map(|c| c.roughness).collect();
        roughness.sort_by(f64::total_cmp);
        roughness.dedup();
        let mut rows = Vec::new();
        for &r in &roughness {
            for g in Geometry::ALL {
                let data = RowData {
                    e_avg: 1.0 - tables.loss_avg(g, r),
                    ms_norm: tables.ms_norm(g, r),
                };
                rows.push((r, g, data));
            }
        }
        Self {
            cells,
            channels,
            tables,
            accurate_geometry,
            rows,
        }
    }

    fn row(&self, r: f64, g: Geometry) -> &RowData {
        &self
            .rows
            .iter()
            .find(|(rr, gg, _)| *rr == r && *gg == g)
            .expect("row baked for every cell roughness")
            .2
    }

    /// A Kulla-Conty variant's albedo at `cell` for channel `ch`.
    pub fn kc(&self, cell: &Cell, ch: usize, parts: KcParts) -> f64 {
        let g = parts.geometry;
        let row = self.row(cell.roughness, g);
        let f_add = parts.f_add(&self.channels[ch].data, row.e_avg);
        let loss = self.tables.loss(g, cell.mu, cell.roughness);
        kc_albedo(cell.single_of(g, ch), f_add, loss, row.ms_norm)
    }

    /// A preset's albedo, through the renderer's `f_add_preset`.
    pub fn preset(&self, cell: &Cell, ch: usize, form: FAvgForm, g: Geometry) -> f64 {
        let row = self.row(cell.roughness, g);
        let c = &self.channels[ch];
        let f_add = preset_f_add(form, c.data.f0, c.index, row.e_avg);
        let loss = self.tables.loss(g, cell.mu, cell.roughness);
        kc_albedo(cell.single_of(g, ch), f_add, loss, row.ms_norm)
    }

    /// The main comparison's models ([`MODELS`] order) at `cell` for channel `ch`. The two
    /// later compensations use height-correlated G (the walk's single scattering).
    pub fn models(&self, cell: &Cell, ch: usize) -> [f64; 5] {
        let sc = Geometry::SmithCorrelated;
        let a = self.accurate_geometry;
        let c = &self.channels[ch];
        let e_sc = 1.0 - self.tables.loss(sc, cell.mu, cell.roughness);
        let ss_sc = cell.single_of(sc, ch);
        [
            cell.single_of(a, ch),
            self.preset(cell, ch, FAvgForm::Accurate, a),
            self.preset(cell, ch, FAvgForm::Games202, Geometry::Schlick),
            ss_sc * turquin_scale(c.data.f0, e_sc),
            fdez_aguera_albedo(ss_sc, f_avg_schlick(c.data.f0), e_sc),
        ]
    }

    /// Channels of `kind` (white counts as both Schlick and conductor) of `material` (or
    /// all materials for `None`).
    pub fn channel_ids(&self, kind: FresnelKind, material: Option<&str>) -> Vec<usize> {
        (0..self.channels.len())
            .filter(|&k| {
                let c = &self.channels[k];
                (c.kind == kind || c.kind == FresnelKind::White)
                    && material.is_none_or(|m| m == c.material)
            })
            .collect()
    }

    /// Largest `|value(cell, ch) - truth|` over every cell and the channels `ids`, with the
    /// (cell, channel) where it occurs.
    pub fn max_error(
        &self,
        ids: &[usize],
        value: impl Fn(&Cell, usize) -> f64,
    ) -> (f64, usize, usize) {
        let mut worst = (0.0, 0, 0);
        for (n, cell) in self.cells.iter().enumerate() {
            for &ch in ids {
                let e = (value(cell, ch) - cell.truth(ch)).abs();
                if e > worst.0 {
                    worst = (e, n, ch);
                }
            }
        }
        worst
    }

    /// Largest standard error of the walk over the cells and channels `ids`.
    pub fn max_stderr(&self, ids: &[usize]) -> f64 {
        self.cells
            .iter()
            .flat_map(|c| ids.iter().map(move |&k| c.truth_stderr(k)))
            .fold(0.0, f64::max)
    }
}

/// Every Kulla-Conty variant of the ablation: G x F_avg source x form.
pub fn ablation_variants() -> Vec<KcParts> {
    let mut out = Vec::new();
    for geometry in Geometry::ALL {
        for f_avg in [FAvgSource::Own, FAvgSource::ConductorFit] {
            for form in [FAvgForm::Accurate, FAvgForm::Games202] {
                out.push(KcParts {
                    geometry,
                    f_avg,
                    form,
                });
            }
        }
    }
    out
}
