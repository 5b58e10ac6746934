//! Baking the Kulla-Conty tables E(mu, roughness) and E_avg(roughness) on the CPU
//! (docs/design/baking.md), and the CPU model of how the shader reads them
//! (docs/design/gpu-tables.md, "The CPU model of the read"). Knows the maths; knows nothing
//! of the GPU.

pub mod accuracy;
mod chebyshev;
pub mod coating;
mod estimators;
mod integrand;
pub mod io;
pub mod ktx2;
mod layout;
pub mod plain;
mod quadrature;
mod reference;
pub mod rows;
pub mod split_sum;
mod table_set;

use rayon::prelude::*;

pub use chebyshev::{ChebyshevSurface, CHEBYSHEV_MU_NODES, CHEBYSHEV_R_NODES};
pub use coating::{
    coating_albedo, coating_albedo_avg, coating_albedo_quadrature, coating_row, CoatingKey,
    CoatingRows, CoatingRule, COATING_ROW_LEN,
};
pub use estimators::{Estimator, Method, PointSet};
pub use integrand::{phi_integral, EIntegrand, Mapping, Segment, MU_MIN, PEAK_WIDTH_PER_ALPHA};
pub use layout::{
    lut_texel_span, roughness_coord, Centres, EAvgRead, Layout, LayoutKind, LutParams, MuAxis,
    RAxis, Storage, DEFAULT_MU_SIZE, DEFAULT_R_SIZE, LOSS_AVG_MIN, UNIFORM_MU_SIZE,
    UNIFORM_PRECISE_MU_SIZE, UNIFORM_PRECISE_R_SIZE, UNIFORM_R_SIZE,
};
pub use quadrature::{adaptive, gauss_legendre_unit};
pub use reference::{e_avg_reference, e_reference, REFERENCE_TOL};
pub use rows::{bake_rows, Row, RowKey, RowSet};
pub use split_sum::{
    e_same_nodes, split_sum, split_sum_with, SplitSum, SPLIT_SUM_SIZE, SPLIT_SUM_TABLE_NODES,
};
pub use table_set::{TableKey, TableSet};

use crate::brdf::Geometry;

/// The default estimator and its node count a segment, chosen by measurement (docs/benchmarks.md,
/// "Measured results"): the Chebyshev bake keeps every texel of every layout within about
/// 1e-5 of the reference at a fixed cost of 425 quadratures a table.
pub const DEFAULT_METHOD: Method = Method::Chebyshev;
/// The default Gauss-Legendre nodes per segment of [`DEFAULT_METHOD`]'s quadrature.
pub const DEFAULT_SAMPLES: usize = 24;

/// Everything that changes the baked values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BakeConfig {
    /// The masking-shadowing term E is baked for (the shader must use the same).
    pub geometry: Geometry,
    /// How E is estimated.
    pub method: Method,
    /// The points a Monte Carlo method draws (unused by the quadratures).
    pub points: PointSet,
    /// Samples per texel (Monte Carlo) or nodes per segment (quadrature).
    pub samples: usize,
    /// Axes, size and storage of the tables.
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
    /// The settings the tables were baked with.
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
///
/// ```
/// use shadeballs::{bake, BakeConfig, Geometry};
/// let tables = bake(&BakeConfig {
///     geometry: Geometry::SmithCorrelated,
///     ..BakeConfig::default()
/// });
/// // The furnace: at roughness 1 a third of the energy is lost to multiple scattering
/// // (height-correlated Smith: E(mu = 1) = 0.306853).
/// assert!((tables.lut_e(1.0, 1.0) - 0.306853).abs() < 1e-4);
/// // What the shader reads is the stored loss 1 - E, row-major, `mu_size` per row.
/// assert_eq!(tables.stored_loss.len(), tables.layout().texels());
/// ```
pub fn bake(config: &BakeConfig) -> Tables {
    let layout = config.layout;
    let rows: Vec<(Vec<f64>, Vec<f32>, f64)> = if config.method == Method::Chebyshev {
        let surface = ChebyshevSurface::new(config.geometry, config.samples);
        (0..layout.r_size)
            .into_par_iter()
            .map(|j| finish_row(&layout, j, surface.texel_row(&layout, j)))
            .collect()
    } else {
        (0..layout.r_size)
            .into_par_iter()
            .map_init(
                || Estimator::new(config.method, config.points, config.samples),
                |est, j| bake_row(est, config, j),
            )
            .collect()
    };
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
    let e: Vec<f64> = (0..layout.mu_size)
        .map(|i| {
            est.e(
                layout.mu_of_texel(i, j),
                roughness,
                config.geometry,
                seed + i as u64,
            )
        })
        .collect();
    finish_row(layout, j, e)
}

/// Row `j` from its E per texel: E clamped to [0, 1], the stored `1 - E`, the row's E_avg.
fn finish_row(layout: &Layout, j: usize, e: Vec<f64>) -> (Vec<f64>, Vec<f32>, f64) {
    let alpha = crate::brdf::alpha_from_roughness(layout.roughness_of_texel(j));
    finish_row_at(layout, alpha, e)
}

/// [`finish_row`] of a row at `alpha`.
pub(crate) fn finish_row_at(
    layout: &Layout,
    alpha: f64,
    mut e: Vec<f64>,
) -> (Vec<f64>, Vec<f32>, f64) {
    // E is a reflectance: estimates outside [0, 1] (Monte Carlo noise) are clamped, as any
    // stored table would clamp them.
    for v in &mut e {
        *v = v.clamp(0.0, 1.0);
    }
    let loss: Vec<f32> = e
        .iter()
        .map(|&v| layout.storage.quantize(1.0 - v))
        .collect();
    let e_avg = 1.0 - row_loss_avg_at(layout, &loss, alpha);
    (e, loss, e_avg)
}

/// `1 - E_avg = 2 int_0^1 (1 - E(mu)) mu dmu` of a row at `alpha` as the shader reads it: linear in
/// the table coordinate x between texel centres.
///
/// Taking E_avg from the row as read, not from E itself, makes the lobe conserve energy by
/// construction: with F = 1, `int f_ms mu_i dw_i` equals `1 - E_read(mu_o)` at every row,
/// whatever the table's own error. Between two texel centres the read is `A + B x(mu)`,
/// and each piece has a closed form in mu ([`piece_integral`]); Gauss-Legendre in x would
/// fail on the warped axis, whose `d mu / d x` has a pole alpha beyond `x = 1`.
fn row_loss_avg_at(layout: &Layout, loss: &[f32], alpha: f64) -> f64 {
    let n = layout.mu_size;
    let (scale, bias) = layout.scale_bias(n);
    let axis = layout.mu_axis;
    // Break points in x: the ends and every texel centre inside (0, 1).
    let mut breaks: Vec<f64> = (0..n)
        .map(|i| layout.texel_coord(i, n))
        .chain([0.0, 1.0])
        .collect();
    breaks.sort_by(f64::total_cmp);
    breaks.dedup();
    let last = n.saturating_sub(1);
    let sum: f64 = breaks
        .windows(2)
        .map(|w| {
            // The read on this piece: clamped to an end texel, or between texels i, i + 1.
            let p = 0.5 * (w[0] + w[1]) * scale + bias;
            let (a, b) = if n < 2 || p <= 0.0 {
                (loss[0] as f64, 0.0)
            } else if p >= last as f64 {
                (loss[last] as f64, 0.0)
            } else {
                let i = (p.floor() as usize).min(n - 2);
                let (l0, l1) = (loss[i] as f64, loss[i + 1] as f64);
                (l0 + (l1 - l0) * (bias - i as f64), (l1 - l0) * scale)
            };
            let (m0, m1) = (axis.value(w[0], alpha), axis.value(w[1], alpha));
            piece_integral(axis, alpha, a, b, m0, m1)
        })
        .sum();
    sum.clamp(0.0, 1.0)
}

/// `int_m0^m1 2 (a + b x(mu)) mu dmu` for the axis's `x(mu)`, in closed form:
/// - linear, `x = mu`: `a (m1^2 - m0^2) + 2 b (m1^3 - m0^3) / 3`;
/// - square root, `x = mu^(1/2)`: `a (m1^2 - m0^2) + 4 b (m1^(5/2) - m0^(5/2)) / 5`;
/// - warped, `x = (1 + al) (1 - al / (mu + al))`: with `c = a + b (1 + al)`,
///   `c (m1^2 - m0^2) - 2 b (1 + al) al ((m1 - m0) - al ln((m1 + al) / (m0 + al)))`.
pub fn piece_integral(axis: MuAxis, alpha: f64, a: f64, b: f64, m0: f64, m1: f64) -> f64 {
    let sq = m1 * m1 - m0 * m0;
    match axis {
        MuAxis::Linear => a * sq + 2.0 * b * (m1 * m1 * m1 - m0 * m0 * m0) / 3.0,
        MuAxis::Sqrt => a * sq + 0.8 * b * (m1 * m1 * m1.sqrt() - m0 * m0 * m0.sqrt()),
        MuAxis::Warped => {
            let k = 1.0 + alpha;
            let log = ((m1 - m0) / (m0 + alpha)).ln_1p();
            (a + b * k) * sq - 2.0 * b * k * alpha * ((m1 - m0) - alpha * log)
        }
    }
}

/// The bilinear blend of texels `t(i, j)` of `lut_loss` in `shaders/lut.wgsl`: along mu
/// between `i0` and `i1` with weight `fx`, then between rows `j0` and `j1` with `fy`.
fn bilinear(
    t: impl Fn(usize, usize) -> f32,
    (i0, i1, fx): (usize, usize, f32),
    (j0, j1, fy): (usize, usize, f32),
) -> f32 {
    let top = t(i0, j0) + (t(i1, j0) - t(i0, j0)) * fx;
    let bottom = t(i0, j1) + (t(i1, j1) - t(i0, j1)) * fx;
    top + (bottom - top) * fy
}

/// `lut_loss_row` of `shaders/lut.wgsl` over `rows` rows of `layout.mu_size` texels,
/// texel (i, j) = `t(i, j)`: the mu half of the read at `mu`, the roughness half from `row`
/// (`[first row, weight of the next, alpha]`). The one CPU copy behind
/// [`Tables::lut_loss_row`] and [`RowSet::lut_loss_row`].
pub(crate) fn read_row(
    layout: &Layout,
    rows: usize,
    mu: f32,
    row: [f32; 3],
    t: impl Fn(usize, usize) -> f32,
) -> f32 {
    let (sx, bx) = layout.scale_bias(layout.mu_size);
    let x = layout.mu_axis.coord(mu, row[2]);
    let span = lut_texel_span(x, layout.mu_size, sx as f32, bx as f32);
    let last = rows.saturating_sub(1);
    let j0 = (row[0] as usize).min(last);
    bilinear(t, span, (j0, (j0 + 1).min(last), row[1]))
}

impl Tables {
    /// The tables' layout (`config.layout`).
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
        bilinear(t, (i0, i1, fx), (j0, j1, fy))
    }

    /// The roughness half of a read at `roughness`, done once per ball (`lut_row` in a ball's
    /// uniforms): `[first row index, weight of the next row, alpha]`, the same f32
    /// arithmetic as [`Tables::lut_loss`].
    pub fn lut_row(&self, roughness: f32) -> [f32; 3] {
        let l = self.layout();
        let (sy, by) = l.scale_bias(l.r_size);
        let (j0, _, fy) = lut_texel_span(l.r_coord(roughness), l.r_size, sy as f32, by as f32);
        let r = roughness_coord(roughness);
        [j0 as f32, fy, r * r]
    }

    /// `lut_loss_row` of `shaders/lut.wgsl`: [`Tables::lut_loss`] with the roughness half
    /// from [`Tables::lut_row`]; equal to `lut_loss(mu, roughness)`.
    pub fn lut_loss_row(&self, mu: f32, row: [f32; 3]) -> f32 {
        let l = self.layout();
        read_row(l, l.r_size, mu, row, |i, j| {
            self.stored_loss[j * l.mu_size + i]
        })
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
            // One row (j0 = j1): no second row to fit a power law through.
            EAvgRead::PowerLaw if j1 != j0 => {
                // Both rows have roughness >= ROUGHNESS_MIN > 0 (clamped reads).
                let (ra, rb) = (l.row_roughness(j0), l.row_roughness(j1));
                let w = (roughness_coord(roughness) / ra).ln() / (rb / ra).ln();
                let (la, lb) = (a.max(LOSS_AVG_MIN).ln(), b.max(LOSS_AVG_MIN).ln());
                (la + (lb - la) * w).exp()
            }
            _ => a + (b - a) * fy,
        }
    }

    /// E_avg as the shader reads it: `1 - lut_loss_avg`.
    pub fn lut_e_avg(&self, roughness: f32) -> f32 {
        1.0 - self.lut_loss_avg(roughness)
    }
}
