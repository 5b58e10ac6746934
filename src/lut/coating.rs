//! The dielectric coating's tables: its single-scattering albedo with the Fresnel of its
//! index, `E_F(mu) = int f_micro(F(o.h), G) mu_i dw_i`, one row along mu per
//! (roughness, index, Fresnel form, G) a scene uses (docs/design/materials.md, "The
//! coating's tables").
//!
//! ## Why rows, and why this quadrature
//!
//! The metal's single scattering splits around a Fresnel-free table (Schlick's `F0 A + B`),
//! the exact dielectric Fresnel does not: its steep rise towards grazing, and total
//! internal reflection below the interface, are no polynomial in `(1 - o.h)`. A scene holds
//! a few indices and roughness values, so each is baked at startup as its own row, like the
//! scene's E rows (`lut::rows`).
//!
//! The integral is taken over the distribution of visible normals (Heitz 2018): with
//! `D_o(m) = G1(o) (o.m) D(m) / mu_o`, `f_micro mu_i dw_i = F G / G1(o) D_o(m) dw_m`, and
//! the visible normals are the image of the unit disk under a smooth map
//! ([`crate::brdf::visible_normal`]). In the disk's polar coordinates the integrand is
//! smooth except where the reflected direction crosses the horizon, so a tensor
//! Gauss-Legendre rule of [`COATING_NODES`] nodes a side integrates it (the disk's `p2`
//! symmetry across the plane of `o` halves the azimuth). Its error against the precise quadrature of
//! `walk::single_albedo`, and the read's, are measured in `src/scene/tests/materials.rs`.

use std::collections::HashMap;

use glam::DVec3;
use rayon::prelude::*;

use super::gauss_legendre_unit;
use crate::brdf::{
    alpha_from_roughness, f_dielectric, g1_smith, visible_normal, DielectricFresnel, Geometry,
};

/// Values a coating row holds, at `sqrt(mu) = k / (COATING_ROW_LEN - 1)`; read by linear
/// interpolation in `sqrt(mu)` ([`coating_albedo`], `coating_albedo` in
/// `shaders/coating.wgsl`). The square root spends the nodes where `E_F` changes fastest,
/// towards grazing.
pub(crate) const COATING_ROW_LEN: usize = 48;

/// Gauss-Legendre nodes along each polar coordinate of the visible-normal disk.
pub(crate) const COATING_NODES: usize = 12;

/// The smallest `mu_o` a row is evaluated at: `G / G1(o)` is `0 / 0` at grazing; `E_F`
/// is continuous there, and 1e-4 moves it by less than the read's own error.
pub(crate) const COATING_MU_MIN: f64 = 1e-4;

/// Everything that changes a row: the roughness and index the shader reads at (f32, as
/// bits, clamped like every read), the Fresnel form and G.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CoatingKey {
    /// The roughness (clamped, f32) as bits.
    pub roughness_bits: u32,
    /// The relative index `eta` (f32) as bits.
    pub eta_bits: u32,
    /// The coating's Fresnel.
    pub(crate) fresnel: DielectricFresnel,
    /// The masking-shadowing term.
    pub geometry: Geometry,
}

impl CoatingKey {
    /// The key of the row at `roughness` and `eta`.
    pub(crate) fn new(
        roughness: f64,
        eta: f64,
        fresnel: DielectricFresnel,
        geometry: Geometry,
    ) -> Self {
        CoatingKey {
            roughness_bits: (crate::brdf::roughness_clamped(roughness) as f32).to_bits(),
            eta_bits: (eta as f32).to_bits(),
            fresnel,
            geometry,
        }
    }

    /// The row's roughness.
    pub(crate) fn roughness(&self) -> f64 {
        f64::from(f32::from_bits(self.roughness_bits))
    }

    /// The row's relative index.
    pub(crate) fn eta(&self) -> f64 {
        f64::from(f32::from_bits(self.eta_bits))
    }
}

/// The rule over the disk's radius and half azimuth, built once a bake.
pub(crate) struct CoatingRule {
    /// Gauss-Legendre nodes and weights on `[0, 1]`, for both coordinates.
    x: Vec<f64>,
    w: Vec<f64>,
}

impl CoatingRule {
    /// The rule of `n` nodes along the radius and `n` along the half azimuth.
    pub(crate) fn new(n: usize) -> Self {
        let (x, w) = gauss_legendre_unit(n);
        CoatingRule { x, w }
    }
}

impl Default for CoatingRule {
    fn default() -> Self {
        Self::new(COATING_NODES)
    }
}

/// Bisection steps that find where a ray of the disk crosses the horizon cut: 2^-12 of
/// the radius.
const CUT_STEPS: usize = 12;

/// The incident direction's cosine for the visible normal at disk point `(p1, p2)`: the
/// mirror of `o` about it.
fn mirror_mu(alpha: f64, o: DVec3, p1: f64, p2: f64) -> (f64, f64) {
    let m = visible_normal(alpha, o, p1, p2);
    let c = o.dot(m);
    (c, 2.0 * c * m.z - o.z)
}

/// The Fresnel-free part of `E_F(mu_o)` at `roughness` for `geometry`: the cosines `o.m`
/// of the rule's visible normals and their weights `G(mu_o, mu_i) / G1(mu_o)` times the
/// rule's, so that `E_F = sum F(o.m) weight` for any Fresnel (every index of a roughness
/// shares them). The disk's `p1` runs along y, across the plane of `o`, so the integrand is
/// even in `p1` and the azimuth covers the half `p1 >= 0`, doubled. Along each azimuth the
/// radius stops where the mirror direction crosses the horizon (found by bisection): the
/// integrand is smooth up to there and zero beyond, so the radial rule sees no kink.
pub(crate) fn coating_weights(
    rule: &CoatingRule,
    mu_o: f64,
    roughness: f64,
    geometry: Geometry,
) -> Vec<(f64, f64)> {
    let alpha = alpha_from_roughness(roughness);
    let mu_o = mu_o.clamp(COATING_MU_MIN, 1.0);
    let o = DVec3::new((1.0 - mu_o * mu_o).max(0.0).sqrt(), 0.0, mu_o);
    let g1_o = g1_smith(mu_o, alpha).max(crate::brdf::DIV_EPSILON);
    let mut out = Vec::with_capacity(rule.x.len() * rule.x.len());
    for (t, wt) in rule.x.iter().zip(&rule.w) {
        let (sin, cos) = (std::f64::consts::PI * (t - 0.5)).sin_cos();
        let r_max = if mirror_mu(alpha, o, cos, sin).1 > 0.0 {
            1.0
        } else {
            // The centre's mirror direction is above the horizon (it is `o`'s neighbour).
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..CUT_STEPS {
                let mid = 0.5 * (lo + hi);
                if mirror_mu(alpha, o, mid * cos, mid * sin).1 > 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            lo
        };
        for (x, wr) in rule.x.iter().zip(&rule.w) {
            let r = r_max * x;
            let (c, mu_i) = mirror_mu(alpha, o, r * cos, r * sin);
            if mu_i <= 0.0 {
                continue;
            }
            // Area element r dr dphi over pi (the disk's area), doubled for p1 < 0.
            let weight = 2.0 * wt * wr * r * r_max;
            out.push((c, weight * geometry.g(mu_o, mu_i, roughness) / g1_o));
        }
    }
    out
}

/// `E_F(mu_o)` of the coating `key` by `rule`: `int F(o.m) G(mu_o, mu_i) / G1(mu_o)
/// D_o(m) dw_m` over the visible normals `m`, `i` the mirror of `o` about `m`
/// ([`coating_weights`]); [`coating_albedo`] reads it from a row.
#[cfg(test)]
pub(crate) fn coating_albedo_quadrature(rule: &CoatingRule, mu_o: f64, key: &CoatingKey) -> f64 {
    let weights = coating_weights(rule, mu_o, key.roughness(), key.geometry);
    fresnel_sum(&weights, key)
}

fn fresnel_sum(weights: &[(f64, f64)], key: &CoatingKey) -> f64 {
    let eta = key.eta();
    weights
        .iter()
        .map(|&(c, w)| w * f_dielectric(c, eta, key.fresnel))
        .sum()
}

/// The mu of row value `k`: `sqrt(mu) = k / (COATING_ROW_LEN - 1)`.
fn row_mu(k: usize) -> f64 {
    let x = k as f64 / (COATING_ROW_LEN - 1) as f64;
    x * x
}

/// The rows of `keys`, which share one roughness and G: the weights once a value.
fn coating_rows_sharing(rule: &CoatingRule, keys: &[CoatingKey]) -> Vec<[f32; COATING_ROW_LEN]> {
    let mut rows = vec![[0.0; COATING_ROW_LEN]; keys.len()];
    for k in 0..COATING_ROW_LEN {
        let weights = coating_weights(rule, row_mu(k), keys[0].roughness(), keys[0].geometry);
        for (row, key) in rows.iter_mut().zip(keys) {
            row[k] = fresnel_sum(&weights, key) as f32;
        }
    }
    rows
}

/// The row of `key`: [`coating_albedo`] at `sqrt(mu) = k / (COATING_ROW_LEN - 1)`, as f32.
#[cfg(test)]
pub(crate) fn coating_row(rule: &CoatingRule, key: &CoatingKey) -> [f32; COATING_ROW_LEN] {
    coating_rows_sharing(rule, std::slice::from_ref(key))[0]
}

/// `coating_albedo` of `shaders/coating.wgsl`: the row read at `mu` in f32, linear in `sqrt(mu)`
/// between its values.
pub(crate) fn coating_albedo(row: &[f32; COATING_ROW_LEN], mu: f32) -> f32 {
    let x = mu.clamp(0.0, 1.0).sqrt() * (COATING_ROW_LEN - 1) as f32;
    let k = (x.floor() as usize).min(COATING_ROW_LEN - 2);
    let t = x - k as f32;
    row[k] + t * (row[k + 1] - row[k])
}

/// `2 int_0^1 E_F(mu) mu dmu` of the row as read ([`coating_albedo`]), exactly:
/// with `x = sqrt(mu)`, `2 mu dmu = 4 x^3 dx` and the read is linear in `x` between
/// nodes, so each interval's integral is a polynomial's.
pub(crate) fn coating_albedo_avg(row: &[f32; COATING_ROW_LEN]) -> f64 {
    let h = 1.0 / (COATING_ROW_LEN - 1) as f64;
    (0..COATING_ROW_LEN - 1)
        .map(|k| {
            let (a, b) = (f64::from(row[k]), f64::from(row[k + 1]));
            let (x0, x1) = (k as f64 * h, (k + 1) as f64 * h);
            // int_x0^x1 (a + (b - a) (x - x0) / h) 4 x^3 dx
            let p4 = x1.powi(4) - x0.powi(4);
            let p5 = x1.powi(5) - x0.powi(5);
            let slope = (b - a) / h;
            (a - slope * x0) * p4 + slope * 4.0 / 5.0 * p5
        })
        .sum()
}

/// A scene's coating rows: one per distinct key, in the order the balls first name them.
#[derive(Clone, Debug, Default)]
pub struct CoatingRows {
    /// The keys, index for index with `rows`.
    pub keys: Vec<CoatingKey>,
    /// The rows.
    pub rows: Vec<[f32; COATING_ROW_LEN]>,
    /// Each key's index (a scene of `MAX_BALLS` balls looks its rows up every frame).
    index: HashMap<CoatingKey, usize>,
}

impl CoatingRows {
    /// The rows of `keys` (duplicates baked once), in parallel; rows already in `cache`
    /// are taken from it and new ones added to it.
    pub fn bake(
        keys: impl IntoIterator<Item = CoatingKey>,
        cache: &mut HashMap<CoatingKey, [f32; COATING_ROW_LEN]>,
    ) -> Self {
        let mut unique: Vec<CoatingKey> = Vec::new();
        let mut index = HashMap::new();
        for k in keys {
            index.entry(k).or_insert_with(|| {
                unique.push(k);
                unique.len() - 1
            });
        }
        let missing: Vec<CoatingKey> = unique
            .iter()
            .filter(|k| !cache.contains_key(k))
            .copied()
            .collect();
        if !missing.is_empty() {
            let rule = CoatingRule::default();
            // Grouped by roughness and G, which the weights depend on.
            let mut groups: Vec<Vec<CoatingKey>> = Vec::new();
            for k in missing {
                match groups.iter_mut().find(|g| {
                    g[0].roughness_bits == k.roughness_bits && g[0].geometry == k.geometry
                }) {
                    Some(g) => g.push(k),
                    None => groups.push(vec![k]),
                }
            }
            let baked: Vec<_> = groups
                .par_iter()
                .flat_map_iter(|g| g.iter().copied().zip(coating_rows_sharing(&rule, g)))
                .collect();
            cache.extend(baked);
        }
        let rows = unique.iter().map(|k| cache[k]).collect();
        CoatingRows {
            keys: unique,
            rows,
            index,
        }
    }

    /// The index of `key`'s row (0 when absent: a ball without a coating reads none).
    pub(crate) fn index_of(&self, key: &CoatingKey) -> usize {
        self.index.get(key).copied().unwrap_or(0)
    }

    /// The row of `key`, if baked.
    pub(crate) fn row(&self, key: &CoatingKey) -> Option<&[f32; COATING_ROW_LEN]> {
        self.index.get(key).map(|&i| &self.rows[i])
    }

    /// Every row's values one after the other (the storage buffer's contents; one row of
    /// zeros when there is none, so the binding is never empty).
    pub(crate) fn flat(&self) -> Vec<f32> {
        if self.rows.is_empty() {
            return vec![0.0; COATING_ROW_LEN];
        }
        self.rows.iter().flatten().copied().collect()
    }
}
