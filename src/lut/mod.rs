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
pub use integrand::{phi_integral, EIntegrand, MU_MIN};
pub use layout::{
    lut_texel_span, roughness_coord, Centres, Layout, LayoutKind, MuAxis, Storage,
    DEFAULT_MU_SIZE, DEFAULT_R_SIZE,
};
pub use quadrature::{adaptive, gauss_legendre_unit};
pub use reference::{e_avg_reference, e_reference, REFERENCE_TOL};

use crate::brdf::Geometry;

/// The default estimator and its sample count, chosen by measurement (README, "Measured
/// results"): the fastest that keeps every texel within 1e-4 of the reference.
pub const DEFAULT_METHOD: Method = Method::Quadrature;
pub const DEFAULT_SAMPLES: usize = 16;

/// Gauss-Legendre nodes in `x = sqrt(mu)` for `E_avg = 4 int_0^1 E(x^2) x^3 dx`.
pub const E_AVG_NODES: usize = 16;

/// Everything that changes the baked values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BakeConfig {
    pub geometry: Geometry,
    pub method: Method,
    pub points: PointSet,
    /// Samples per texel (Monte Carlo) or nodes per side of the peak (quadrature).
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

/// Baked tables: exact f64 values per texel and what the GPU stores.
#[derive(Clone, Debug)]
pub struct Tables {
    pub config: BakeConfig,
    /// E per texel, row-major (row = roughness), `layout.mu_size` per row.
    pub e: Vec<f64>,
    /// E_avg per roughness texel.
    pub e_avg: Vec<f64>,
    /// `e` after the layout's storage quantisation: what the shader reads.
    pub stored_e: Vec<f32>,
    /// `e_avg` after quantisation.
    pub stored_e_avg: Vec<f32>,
}

/// Bakes E and E_avg for `config`, one roughness row per task on rayon's pool.
pub fn bake(config: &BakeConfig) -> Tables {
    let layout = config.layout;
    let rows: Vec<(Vec<f64>, f64)> = (0..layout.r_size)
        .into_par_iter()
        .map_init(
            || Estimator::new(config.method, config.points, config.samples),
            |est, j| bake_row(est, config, j),
        )
        .collect();
    let mut e = Vec::with_capacity(layout.texels());
    let mut e_avg = Vec::with_capacity(layout.r_size);
    for (row, avg) in rows {
        e.extend(row);
        e_avg.push(avg);
    }
    let stored_e = e.iter().map(|&v| layout.storage.quantize(v)).collect();
    let stored_e_avg = e_avg.iter().map(|&v| layout.storage.quantize(v)).collect();
    Tables { config: *config, e, e_avg, stored_e, stored_e_avg }
}

fn bake_row(est: &mut Estimator, config: &BakeConfig, j: usize) -> (Vec<f64>, f64) {
    let layout = &config.layout;
    let roughness = layout.roughness_of_texel(j);
    let seed = (j * (layout.mu_size + E_AVG_NODES)) as u64;
    let row = (0..layout.mu_size)
        .map(|i| est.e(layout.mu_of_texel(i), roughness, config.geometry, seed + i as u64))
        .collect();
    let avg = e_avg_of(est, roughness, config.geometry, seed + layout.mu_size as u64);
    (row, avg)
}

/// `E_avg = 4 int_0^1 E(x^2) x^3 dx` by Gauss-Legendre in `x = sqrt(mu)`, E from `est`.
fn e_avg_of(est: &mut Estimator, roughness: f64, geometry: Geometry, seed: u64) -> f64 {
    let (nodes, weights) = gauss_legendre_unit(E_AVG_NODES);
    let sum: f64 = nodes
        .iter()
        .zip(&weights)
        .enumerate()
        .map(|(k, (&x, &w))| w * 4.0 * x * x * x * est.e(x * x, roughness, geometry, seed + k as u64))
        .sum();
    sum.clamp(0.0, 1.0)
}

impl Tables {
    pub fn layout(&self) -> &Layout {
        &self.config.layout
    }

    /// What the shader's bilinear read of the E table returns at `(mu, roughness)`:
    /// the same f32 arithmetic as `lut_e` in `shaders/lut.wgsl`.
    pub fn lut_e(&self, mu: f32, roughness: f32) -> f32 {
        let l = self.layout();
        let (sx, bx) = l.scale_bias(l.mu_size);
        let (sy, by) = l.scale_bias(l.r_size);
        let x = l.mu_coord(mu);
        let y = roughness_coord(roughness);
        let (i0, i1, fx) = lut_texel_span(x, l.mu_size, sx as f32, bx as f32);
        let (j0, j1, fy) = lut_texel_span(y, l.r_size, sy as f32, by as f32);
        let t = |i: usize, j: usize| self.stored_e[j * l.mu_size + i];
        let top = t(i0, j0) + (t(i1, j0) - t(i0, j0)) * fx;
        let bottom = t(i0, j1) + (t(i1, j1) - t(i0, j1)) * fx;
        top + (bottom - top) * fy
    }

    /// What the shader's linear read of the E_avg row returns at `roughness`
    /// (`lut_e_avg` in `shaders/lut.wgsl`).
    pub fn lut_e_avg(&self, roughness: f32) -> f32 {
        let l = self.layout();
        let (sy, by) = l.scale_bias(l.r_size);
        let (j0, j1, fy) = lut_texel_span(roughness_coord(roughness), l.r_size, sy as f32, by as f32);
        let a = self.stored_e_avg[j0];
        a + (self.stored_e_avg[j1] - a) * fy
    }
}
