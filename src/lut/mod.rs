//! Baking the Kulla-Conty tables E(mu, roughness) and E_avg(roughness) on the CPU
//! (DESIGN.md section 2), and the CPU model of how the shader reads them (section 3).
//! Knows the maths; knows nothing of the GPU.

pub mod accuracy;
mod estimators;
mod integrand;
pub mod io;
mod layout;
mod quadrature;
mod reference;

use rayon::prelude::*;

pub use estimators::{Estimator, Method, PointSet};
pub use integrand::{phi_integral, EIntegrand, Mapping, Segment, MU_MIN, PEAK_WIDTH_PER_ALPHA};
pub use layout::{
    lut_texel_span, roughness_coord, Centres, EAvgRead, Layout, LayoutKind, MuAxis, Storage,
    DEFAULT_MU_SIZE, DEFAULT_R_SIZE, LOSS_AVG_MIN,
};
pub use quadrature::{adaptive, gauss_legendre_unit};
pub use reference::{e_avg_reference, e_reference, REFERENCE_TOL};

use crate::brdf::Geometry;

/// The default estimator and its sample count, chosen by measurement (README, "Measured
/// results"): the fastest that keeps every texel within 1e-4 of the reference.
pub const DEFAULT_METHOD: Method = Method::Quadrature;
pub const DEFAULT_SAMPLES: usize = 16;

/// Everything that changes the baked values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BakeConfig {
    pub geometry: Geometry,
    pub method: Method,
    pub points: PointSet,
    /// Samples per texel (Monte Carlo) or nodes per segment (quadrature).
    pub samples: usize,
    pub layout: Layout,
}

impl Default for BakeConfig {
    fn default() -> Self {
        Self {
            geometry: Geometry::Schlick,
            method: DEFAULT_METHOD,
            points: PointSet::Sobol,
            samples: DEFAULT_SAMPLES,
            layout: Layout::default(),
        }
    }
}

/// Baked tables: the values per texel and what the GPU stores.
#[derive(Clone, Debug)]
pub struct Tables {
    pub config: BakeConfig,
    /// E per texel, row-major (row = roughness), `layout.mu_size` per row.
    pub e: Vec<f64>,
    /// E_avg per roughness row: `2 int_0^1 E(mu) mu dmu` of the row as the shader reads it.
    pub e_avg: Vec<f64>,
    /// `1 - e` after the layout's storage quantisation: what the shader reads.
    pub stored_loss: Vec<f32>,
    /// `1 - e_avg` after quantisation.
    pub stored_loss_avg: Vec<f32>,
}

/// Bakes E and E_avg for `config`, one roughness row per task on rayon's pool.
pub fn bake(config: &BakeConfig) -> Tables {
    let layout = config.layout;
    let rows: Vec<(Vec<f64>, Vec<f32>, f64)> = (0..layout.r_size)
        .into_par_iter()
        .map_init(
            || Estimator::new(config.method, config.points, config.samples),
            |est, j| bake_row(est, config, j),
        )
        .collect();
    let mut tables = Tables {
        config: *config,
        e: Vec::with_capacity(layout.texels()),
        e_avg: Vec::with_capacity(layout.r_size),
        stored_loss: Vec::with_capacity(layout.texels()),
        stored_loss_avg: Vec::with_capacity(layout.r_size),
    };
    for (e, loss, e_avg) in rows {
        tables.e.extend(e);
        tables.stored_loss.extend(loss);
        tables.e_avg.push(e_avg);
        tables
            .stored_loss_avg
            .push(layout.storage.quantize(1.0 - e_avg));
    }
    tables
}

/// One row: E per texel (f64), the stored `1 - E`, and the row's E_avg.
fn bake_row(est: &mut Estimator, config: &BakeConfig, j: usize) -> (Vec<f64>, Vec<f32>, f64) {
    let layout = &config.layout;
    let roughness = layout.roughness_of_texel(j);
    let seed = (j * layout.mu_size) as u64;
    // E is a reflectance: estimates outside [0, 1] (Monte Carlo noise) are clamped, as any
    // stored table would clamp them.
    let e: Vec<f64> = (0..layout.mu_size)
        .map(|i| {
            est.e(
                layout.mu_of_texel(i, j),
                roughness,
                config.geometry,
                seed + i as u64,
            )
            .clamp(0.0, 1.0)
        })
        .collect();
    let loss: Vec<f32> = e
        .iter()
        .map(|&v| layout.storage.quantize(1.0 - v))
        .collect();
    let e_avg = 1.0 - row_loss_avg(layout, &loss, j);
    (e, loss, e_avg)
}

/// Absolute tolerance of each texel piece of the row integral of `1 - E_avg`.
const ROW_TOL: f64 = 1e-13;

/// `1 - E_avg = 2 int_0^1 (1 - E(mu)) mu dmu` of row `j` as the shader reads it: linear in
/// the table coordinate x between texel centres.
///
/// Taking E_avg from the row as read, not from E itself, makes the lobe conserve energy by
/// construction: with F = 1, `int f_ms mu_i dw_i` equals `1 - E_read(mu_o)` at every row,
/// whatever the table's own error. Each piece between texel centres is integrated in mu,
/// where the read is smooth within the piece, by the adaptive rule: Gauss-Legendre in x
/// fails here, because the warped axis's `d mu / d x` has a pole alpha beyond `x = 1`.
fn row_loss_avg(layout: &Layout, loss: &[f32], j: usize) -> f64 {
    let n = layout.mu_size;
    let alpha = crate::brdf::alpha_from_roughness(layout.roughness_of_texel(j));
    let (scale, bias) = layout.scale_bias(n);
    let axis = layout.mu_axis;
    let read = |mu: f64| {
        let x = axis.coord_f64(mu, alpha);
        let p = (x * scale + bias).clamp(0.0, (n - 1) as f64);
        let i = (p.floor() as usize).min(n.saturating_sub(2));
        let f = p - i as f64;
        let (a, b) = (loss[i] as f64, loss[(i + 1).min(n - 1)] as f64);
        2.0 * (a + (b - a) * f) * mu
    };
    // Break points in mu: the ends and every texel centre inside (0, 1).
    let mut breaks: Vec<f64> = (0..n)
        .map(|i| axis.value(layout.texel_coord(i, n), alpha))
        .chain([0.0, 1.0])
        .collect();
    breaks.sort_by(f64::total_cmp);
    breaks.dedup();
    let sum: f64 = breaks
        .windows(2)
        .map(|w| adaptive(&read, w[0], w[1], ROW_TOL))
        .sum();
    sum.clamp(0.0, 1.0)
}

impl Tables {
    pub fn layout(&self) -> &Layout {
        &self.config.layout
    }

    /// What the shader's bilinear read of the table returns at `(mu, roughness)`: the missing
    /// energy `1 - E`, with the same f32 arithmetic as `lut_loss` in `shaders/lut.wgsl`.
    pub fn lut_loss(&self, mu: f32, roughness: f32) -> f32 {
        let l = self.layout();
        let (sx, bx) = l.scale_bias(l.mu_size);
        let (sy, by) = l.scale_bias(l.r_size);
        let r = roughness_coord(roughness);
        let x = l.mu_axis.coord(mu, r * r);
        let (i0, i1, fx) = lut_texel_span(x, l.mu_size, sx as f32, bx as f32);
        let (j0, j1, fy) = lut_texel_span(l.r_coord(roughness), l.r_size, sy as f32, by as f32);
        let t = |i: usize, j: usize| self.stored_loss[j * l.mu_size + i];
        let top = t(i0, j0) + (t(i1, j0) - t(i0, j0)) * fx;
        let bottom = t(i0, j1) + (t(i1, j1) - t(i0, j1)) * fx;
        top + (bottom - top) * fy
    }

    /// E as the shader reads it: `1 - lut_loss`.
    pub fn lut_e(&self, mu: f32, roughness: f32) -> f32 {
        1.0 - self.lut_loss(mu, roughness)
    }

    /// What the shader's read of the E_avg row returns at `roughness`: `1 - E_avg`,
    /// linear or as a power law between the two nearest rows as the layout says
    /// ([`EAvgRead`]; `lut_loss_avg` in `shaders/lut.wgsl`).
    pub fn lut_loss_avg(&self, roughness: f32) -> f32 {
        let l = self.layout();
        let (sy, by) = l.scale_bias(l.r_size);
        let (j0, j1, fy) = lut_texel_span(l.r_coord(roughness), l.r_size, sy as f32, by as f32);
        let (a, b) = (self.stored_loss_avg[j0], self.stored_loss_avg[j1]);
        match l.e_avg_read {
            EAvgRead::Linear => a + (b - a) * fy,
            EAvgRead::PowerLaw => {
                // Both rows have roughness >= ROUGHNESS_MIN > 0 (clamped reads).
                let (ra, rb) = (l.row_roughness(j0), l.row_roughness(j1));
                let w = (roughness_coord(roughness) / ra).ln() / (rb / ra).ln();
                let (la, lb) = (a.max(LOSS_AVG_MIN).ln(), b.max(LOSS_AVG_MIN).ln());
                (la + (lb - la) * w).exp()
            }
        }
    }

    /// E_avg as the shader reads it: `1 - lut_loss_avg`.
    pub fn lut_e_avg(&self, roughness: f32) -> f32 {
        1.0 - self.lut_loss_avg(roughness)
    }
}
