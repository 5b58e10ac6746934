//! The Chebyshev bake: the quadrature at a small grid of Chebyshev points in (warped mu,
//! roughness), interpolated to every texel by a tensor Chebyshev series.
//!
//! ## Why
//!
//! In the warped coordinate `x = mu (1 + alpha) / (mu + alpha)` ([`MuAxis::Warped`]) and
//! in roughness, E is smooth with no feature narrower than the square: the grazing dip
//! that moves with alpha sits at a fixed x. Interpolation at Chebyshev points then
//! converges fast (Trefethen 2013, "Approximation Theory and Approximation Practice",
//! ch. 7-8), and a table of any size costs a fixed number of quadratures plus one cheap
//! series evaluation a texel, where the per-texel bake costs one quadrature a texel
//! (16,384 for the homework's table).
//!
//! One exception shapes the grid: with height-correlated Smith G, E has a `mu ln mu` term
//! at grazing (`G = 1 / (1 + L(mu_o) + L(mu_i))` couples the two near-horizon poles), a
//! singularity at `x = 0` that a series in x resolves only slowly (its error falls
//! algebraically, not geometrically, with the number of points). The series runs in
//! `y = sqrt(x)` instead, where the term is `y^2 ln y`. With precise values at the points
//! (48 nodes a segment), 25 points along y and 17 along roughness interpolate E within
//! 1.9e-7 (Schlick), 6.0e-7 (Smith) and 1.9e-6 (height-correlated Smith) at every texel of
//! the 64 x 64 default and the homework's 128 x 128 layout (its unit tests, below).

//! ## How
//!
//! Values at the Chebyshev-Lobatto points `s_k = cos(pi k / N)` of each axis give the
//! coefficients of the interpolating series `sum'' a_j T_j(s)` by a discrete cosine
//! transform (Trefethen 2013, ch. 3); a row of the table takes the series in roughness at
//! its roughness (one coefficient row in x), and each texel evaluates that row by
//! Clenshaw's recurrence (Clenshaw 1955) at its `y = sqrt(x)`. Both axes map `[0, 1]` to
//! `s = 2 t - 1`; the roughness axis is linear over the clamped range `[ROUGHNESS_MIN, 1]`.

use rayon::prelude::*;

use super::estimators::{Estimator, Method, PointSet};
use super::layout::{Layout, MuAxis};
use crate::brdf::{alpha_from_roughness, roughness_clamped, Geometry, ROUGHNESS_MIN};

/// Chebyshev points along `y = sqrt(x)`, chosen by measurement (see the module docs).
pub(crate) const CHEBYSHEV_MU_NODES: usize = 25;
/// Chebyshev points along roughness, chosen by measurement (see the module docs).
pub(crate) const CHEBYSHEV_R_NODES: usize = 17;

/// E as a tensor Chebyshev series in (warped x, roughness).
#[derive(Clone, Debug)]
pub(crate) struct ChebyshevSurface {
    /// `coeffs[m * n + k]`: coefficient of `T_m(s_r) T_k(s_y)`, `n` along y, `nr` along
    /// roughness, the `''` halvings already applied.
    coeffs: Vec<f64>,
    n: usize,
    nr: usize,
}

/// `cos(pi k / (n - 1))` mapped to `[0, 1]`: `(1 + s) / 2`.
fn node(k: usize, n: usize) -> f64 {
    0.5 * (1.0 + (std::f64::consts::PI * k as f64 / (n - 1) as f64).cos())
}

fn roughness_at(t: f64) -> f64 {
    ROUGHNESS_MIN + (1.0 - ROUGHNESS_MIN) * t
}

/// Coefficients of the series interpolating `values` at the `n` Chebyshev-Lobatto points
/// `s_k = cos(pi k / (n - 1))`, the first and last already halved so that the series is a
/// plain sum `sum_j a_j T_j(s)`.
fn coefficients(values: &[f64]) -> Vec<f64> {
    let n = values.len();
    let big_n = (n - 1) as f64;
    let halve = |k: usize| if k == 0 || k == n - 1 { 0.5 } else { 1.0 };
    (0..n)
        .map(|j| {
            let sum: f64 = values
                .iter()
                .enumerate()
                .map(|(k, &f)| halve(k) * f * (std::f64::consts::PI * (j * k) as f64 / big_n).cos())
                .sum();
            halve(j) * 2.0 / big_n * sum
        })
        .collect()
}

/// `sum_j a_j T_j(s)` by Clenshaw's recurrence.
fn clenshaw(a: &[f64], s: f64) -> f64 {
    let (mut b1, mut b2) = (0.0, 0.0);
    for &c in a.iter().skip(1).rev() {
        let b0 = c + 2.0 * s * b1 - b2;
        b2 = b1;
        b1 = b0;
    }
    a[0] + s * b1 - b2
}

/// The series in `y = sqrt(x)` of E along one row at `roughness` alone: the quadrature
/// (`samples` nodes a segment) at `n` Chebyshev points of that row and nothing across
/// roughness, so the row carries no interpolation error in roughness (a scene's own rows,
/// `rows.rs`). Evaluate with [`ChebyshevSurface::e_in_row`].
pub(crate) fn exact_row(geometry: Geometry, samples: usize, roughness: f64, n: usize) -> Vec<f64> {
    let n = n.max(2);
    let alpha = alpha_from_roughness(roughness);
    let mut est = Estimator::new(Method::Quadrature, PointSet::Sobol, samples);
    let values: Vec<f64> = (0..n)
        .map(|k| {
            let y = node(k, n);
            est.e(MuAxis::Warped.value(y * y, alpha), roughness, geometry, 0)
        })
        .collect();
    coefficients(&values)
}

impl ChebyshevSurface {
    /// Quadrature (`samples` Gauss-Legendre nodes a segment) at the default grid of
    /// Chebyshev points, in parallel on rayon's pool.
    pub(crate) fn new(geometry: Geometry, samples: usize) -> Self {
        Self::with_grid(geometry, samples, CHEBYSHEV_MU_NODES, CHEBYSHEV_R_NODES)
    }

    /// As [`ChebyshevSurface::new`] with `n` points along `y = sqrt(x)` and `nr` along
    /// roughness (each at least 2).
    pub(crate) fn with_grid(geometry: Geometry, samples: usize, n: usize, nr: usize) -> Self {
        let (n, nr) = (n.max(2), nr.max(2));
        let values: Vec<f64> = (0..n * nr)
            .into_par_iter()
            .map_init(
                || Estimator::new(Method::Quadrature, PointSet::Sobol, samples),
                |est, idx| {
                    let r = roughness_at(node(idx / n, nr));
                    let y = node(idx % n, n);
                    let mu = MuAxis::Warped.value(y * y, alpha_from_roughness(r));
                    est.e(mu, r, geometry, 0)
                },
            )
            .collect();
        // Transform along x (each roughness node), then along roughness (each x coefficient).
        let along_x: Vec<f64> = values.chunks(n).flat_map(coefficients).collect();
        let mut coeffs = vec![0.0; n * nr];
        for k in 0..n {
            let column: Vec<f64> = (0..nr).map(|m| along_x[m * n + k]).collect();
            for (m, c) in coefficients(&column).into_iter().enumerate() {
                coeffs[m * n + k] = c;
            }
        }
        Self { coeffs, n, nr }
    }

    /// The series in `y = sqrt(x)` at `roughness` (clamped): `n` coefficients.
    pub(crate) fn row(&self, roughness: f64) -> Vec<f64> {
        let n = self.n;
        let nr = self.nr;
        let t = (roughness_clamped(roughness) - ROUGHNESS_MIN) / (1.0 - ROUGHNESS_MIN);
        let s = 2.0 * t - 1.0;
        // T_m(s) by the three-term recurrence.
        let mut tm = vec![1.0; nr];
        if nr > 1 {
            tm[1] = s;
        }
        for m in 2..nr {
            tm[m] = 2.0 * s * tm[m - 1] - tm[m - 2];
        }
        (0..n)
            .map(|k| (0..nr).map(|m| self.coeffs[m * n + k] * tm[m]).sum())
            .collect()
    }

    /// E at `mu` from a row's series ([`ChebyshevSurface::row`] at the same roughness).
    pub(crate) fn e_in_row(row: &[f64], mu: f64, roughness: f64) -> f64 {
        let x = MuAxis::Warped.coord_f64(mu, alpha_from_roughness(roughness));
        clenshaw(row, 2.0 * x.sqrt() - 1.0)
    }

    /// E at every texel of row `j` of `layout`.
    pub(crate) fn texel_row(&self, layout: &Layout, j: usize) -> Vec<f64> {
        let r = layout.roughness_of_texel(j);
        let row = self.row(r);
        (0..layout.mu_size)
            .map(|i| Self::e_in_row(&row, layout.mu_of_texel(i, j), r))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    //! The Chebyshev bake (`src/lut/chebyshev.rs`): its series interpolates E at any texel of
    //! any layout, for every geometry term, within the bounds its documentation states.

    use crate::brdf::Geometry;
    use crate::lut::accuracy::ReferenceTables;
    use crate::lut::{self, BakeConfig, ChebyshevSurface, Layout, LayoutKind, Method};

    /// With precise values at the points (48 nodes a segment), the default 25 x 17 grid
    /// interpolates E within 1.9e-7 (Schlick), 6.0e-7 (Smith), 1.9e-6 (height-correlated) at
    /// every texel of the 64 x 64 default and the homework's 128 x 128 layout.
    #[test]
    fn series_interpolates_e_at_every_texel() {
        let bounds = [2e-7, 7e-7, 2e-6];
        for (g, bound) in Geometry::ALL.into_iter().zip(bounds) {
            let surface =
                ChebyshevSurface::with_grid(g, 48, lut::CHEBYSHEV_MU_NODES, lut::CHEBYSHEV_R_NODES);
            let mut worst: f64 = 0.0;
            for layout in [Layout::default(), Layout::of_kind(LayoutKind::Games202)] {
                let reference = ReferenceTables::new(layout, g);
                for j in 0..layout.r_size {
                    let row = surface.texel_row(&layout, j);
                    for (i, e) in row.iter().enumerate() {
                        worst = worst.max((e - reference.e[j * layout.mu_size + i]).abs());
                    }
                }
            }
            println!("{g}: series within {worst:.2e} of the reference");
            assert!(worst <= bound, "{g}: {worst:.2e} > {bound:.1e}");
        }
    }

    /// The default bake on layouts it was not tuned on: as accurate as the per-texel quadrature
    /// with the same nodes, to within 1e-5 (the interpolation's share), and both within 2e-5
    /// of the reference.
    #[test]
    fn chebyshev_bake_matches_the_quadrature_on_other_layouts() {
        for layout in [
            Layout::of_kind(LayoutKind::SqrtMu).with_size(48, 32),
            Layout::default().with_size(200, 7),
            Layout::default().with_size(2, 2),
        ] {
            for g in Geometry::ALL {
                let reference = ReferenceTables::new(layout, g);
                let error = |method| {
                    let tables = lut::bake(&BakeConfig {
                        geometry: g,
                        layout,
                        method,
                        ..BakeConfig::default()
                    });
                    reference.bake_error(&tables).0
                };
                let (cheb, quad) = (error(Method::Chebyshev), error(Method::Quadrature));
                println!(
                    "{g} {}x{} {}: chebyshev {:.2e} at {:?}, quadrature {:.2e} at {:?}",
                    layout.mu_size,
                    layout.r_size,
                    layout.kind,
                    cheb.max,
                    cheb.worst_at,
                    quad.max,
                    quad.worst_at
                );
                assert!(
                    cheb.max <= quad.max.max(1e-5) + 1e-5,
                    "{g} {layout:?}: {cheb:?} vs {quad:?}"
                );
            }
        }
    }
}
