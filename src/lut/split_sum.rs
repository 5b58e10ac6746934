//! The split sum's second factor (Karis 2013, "Real Shading in Unreal Engine 4"): with
//! Schlick's F, `int f_micro mu_i dw_i = F0 A + B`, where
//!
//! ```text
//! A(mu_o) = int (f_micro / F) (1 - (1 - v.h)^5) mu_i dw_i,
//! B(mu_o) = int (f_micro / F) (1 - v.h)^5 mu_i dw_i,
//! ```
//!
//! so `A + B = E` (F = 1). The same integrand as E ([`EIntegrand`]: the same G, the same
//! segments over `theta_i`), but the Fresnel weight depends on the azimuth, so `phi` is
//! integrated numerically here: about the mirror azimuth `D` is a squared Lorentzian of
//! width `delta = sqrt(2 (a - b) / b)` (the closed form's `a`, `b`; module `integrand`),
//! flattened by `phi' = delta tan s`. Both factors are summed in one pass, so `A + B`
//! against the 1-D bake of E checks the 2-D quadrature (tests: within 1e-6).
//!
//! The real-time renderer stores only B ([`SplitSum`]) and takes `A = E - B` with its own
//! E read, which keeps the furnace exact (`F0 = 1`: `A + B = E`).

#[cfg(test)]
use std::f64::consts::PI;

#[cfg(test)]
use rayon::prelude::*;

#[cfg(test)]
use super::integrand::EIntegrand;
#[cfg(test)]
use super::quadrature::gauss_legendre_unit;
use crate::brdf::Geometry;

/// Gauss-Legendre nodes per `theta_i` segment.
#[cfg(test)]
pub(crate) const SPLIT_SUM_THETA_NODES: usize = 24;
/// Gauss-Legendre nodes per piece of the mapped azimuth (peak and tail).
#[cfg(test)]
pub(crate) const SPLIT_SUM_PHI_NODES: usize = 32;
/// The nodes (per `theta_i` segment, per piece of the azimuth) the table is baked with:
/// fewer than [`split_sum`]'s, as the table's bilinear read between 32 x 32 texels is
/// itself good to about 1e-3 (tests hold the bake within 5e-5 of `split_sum`).
#[cfg(test)]
pub(crate) const SPLIT_SUM_TABLE_NODES: [usize; 2] = [12, 16];
/// The tan-mapped peak of the azimuth reaches this many widths from the mirror azimuth.
#[cfg(test)]
pub(crate) const PHI_PEAK_SPAN: f64 = 4.0;
/// Texels of the B table along mu and along roughness: texel `(i, j)` holds `mu = i /
/// (N - 1)`, `roughness = j / (N - 1)` (centres on the end points, read with
/// `SPLIT_SUM_SCALE` and `SPLIT_SUM_BIAS`).
pub(crate) const SPLIT_SUM_SIZE: usize = 32;

/// `A` and `B` at `(mu_o, roughness)` for `geometry`, to about 1e-6
/// ([`SPLIT_SUM_THETA_NODES`], [`SPLIT_SUM_PHI_NODES`]).
#[cfg(test)]
pub(crate) fn split_sum(mu_o: f64, roughness: f64, geometry: Geometry) -> (f64, f64) {
    split_sum_with(
        mu_o,
        roughness,
        geometry,
        SPLIT_SUM_THETA_NODES,
        SPLIT_SUM_PHI_NODES,
    )
}

/// [`split_sum`] with `theta_nodes` Gauss-Legendre nodes per `theta_i` segment and
/// `phi_nodes` per piece of the azimuth.
#[cfg(test)]
pub(crate) fn split_sum_with(
    mu_o: f64,
    roughness: f64,
    geometry: Geometry,
    theta_nodes: usize,
    phi_nodes: usize,
) -> (f64, f64) {
    let f = EIntegrand::new(mu_o, roughness, geometry);
    let (tn, tw) = gauss_legendre_unit(theta_nodes);
    let (pn, pw) = gauss_legendre_unit(phi_nodes);
    let (mu_o, s_o) = (f.mu_o, (1.0 - f.mu_o * f.mu_o).max(0.0).sqrt());
    let a2 = f.alpha * f.alpha;
    let (mut a_sum, mut b_sum) = (0.0, 0.0);
    for seg in f.segments() {
        let span = seg.hi - seg.lo;
        for (&x, &wx) in tn.iter().zip(&tw) {
            let (theta_i, jac) = f.theta_at_segment(&seg, seg.lo + span * x);
            let (s_i, mu_i) = theta_i.sin_cos();
            if mu_i <= 0.0 {
                continue;
            }
            let g = geometry.g(mu_o, mu_i, roughness);
            let common = g * s_i / (4.0 * mu_o) * jac * wx * span;
            let (a_phi, b_phi) = azimuth(mu_o, s_o, mu_i, s_i, a2, &pn, &pw);
            a_sum += common * a_phi;
            b_sum += common * b_phi;
        }
    }
    (a_sum, b_sum)
}

/// E by the same `theta_i` nodes as [`split_sum`], the azimuth in closed form
/// (`phi_integral`): `A + B` against it isolates the azimuth's quadrature.
#[cfg(test)]
pub(crate) fn e_same_nodes(mu_o: f64, roughness: f64, geometry: Geometry) -> f64 {
    let f = EIntegrand::new(mu_o, roughness, geometry);
    let (tn, tw) = gauss_legendre_unit(SPLIT_SUM_THETA_NODES);
    f.segments()
        .map(|seg| {
            let span = seg.hi - seg.lo;
            tn.iter()
                .zip(&tw)
                .map(|(&x, &w)| f.at_segment(&seg, seg.lo + span * x) * w * span)
                .sum::<f64>()
        })
        .sum()
}

/// `int_0^{2 pi} D (1 - w) dphi` and `int_0^{2 pi} D w dphi`, `w = (1 - v.h)^5`.
#[cfg(test)]
fn azimuth(
    mu_o: f64,
    s_o: f64,
    mu_i: f64,
    s_i: f64,
    a2: f64,
    nodes: &[f64],
    weights: &[f64],
) -> (f64, f64) {
    let p = (mu_o + mu_i) * (mu_o + mu_i);
    let b = 2.0 * s_o * s_i;
    let a_minus_b = p * a2 + (s_o - s_i) * (s_o - s_i);
    // Width of the peak about the mirror azimuth; a flat D (b = 0) gets the whole range.
    let delta = if b > 0.0 {
        (2.0 * a_minus_b / b).sqrt().max(1e-300)
    } else {
        PI
    };
    let e = 2.0 + 2.0 * mu_o * mu_i;
    let a = p * a2 + s_o * s_o + s_i * s_i;
    // D and the Fresnel weight at `phi_m` from the mirror azimuth, times `jac`, summed.
    let (mut a_sum, mut b_sum) = (0.0, 0.0);
    let mut add = |phi_m: f64, jac: f64| {
        let cos_phi = -phi_m.cos();
        let den = a + b * cos_phi;
        if den <= 0.0 {
            // Only at alpha = 0 with both directions grazing: no finite lobe (as
            // `phi_integral`).
            return;
        }
        // D = alpha^2 / pi ((e + b cos phi) / (a + b cos phi))^2 (module `integrand`).
        let ratio = (e + b * cos_phi) / den;
        let d = a2 / PI * ratio * ratio;
        let o_dot_i = mu_o * mu_i + s_o * s_i * cos_phi;
        let v_dot_h = ((1.0 + o_dot_i) * 0.5).max(0.0).sqrt();
        let fw = (1.0 - v_dot_h).powi(5);
        // Both sides of the mirror azimuth.
        a_sum += 2.0 * d * (1.0 - fw) * jac;
        b_sum += 2.0 * d * fw * jac;
    };
    // The peak, phi_m = delta tan s out to PHI_PEAK_SPAN delta; then the rest to pi by
    // phi_m = exp(x): near grazing D does not fall off (it tends to alpha^2 / pi), which
    // the tan map alone would squeeze against its end.
    let peak = PI.min(PHI_PEAK_SPAN * delta);
    let s_max = (peak / delta).atan();
    for (&x, &w) in nodes.iter().zip(weights) {
        let (sn, cs) = (s_max * x).sin_cos();
        add(delta * sn / cs, delta / (cs * cs) * s_max * w);
    }
    if peak < PI {
        let (lo, hi) = (peak.ln(), PI.ln());
        for (&x, &w) in nodes.iter().zip(weights) {
            let phi_m = (lo + (hi - lo) * x).exp();
            add(phi_m, phi_m * (hi - lo) * w);
        }
    }
    (a_sum, b_sum)
}

/// The B table the renderers read: [`SPLIT_SUM_SIZE`] squared texels, row = roughness.
#[derive(Clone, Debug, PartialEq)]
pub struct SplitSum {
    /// The G it was baked for.
    pub geometry: Geometry,
    /// B per texel, row-major (`SPLIT_SUM_SIZE` per row), as f32.
    pub bias: Vec<f32>,
}

impl SplitSum {
    /// Bakes the table (rows on rayon) with [`SPLIT_SUM_TABLE_NODES`]: a few
    /// milliseconds at startup.
    #[cfg(test)]
    pub(crate) fn bake(geometry: Geometry) -> Self {
        let n = SPLIT_SUM_SIZE;
        let bias = (0..n * n)
            .into_par_iter()
            .map(|k| {
                let mu = (k % n) as f64 / (n - 1) as f64;
                let r = (k / n) as f64 / (n - 1) as f64;
                let [t, p] = SPLIT_SUM_TABLE_NODES;
                split_sum_with(mu, r, geometry, t, p).1 as f32
            })
            .collect();
        SplitSum { geometry, bias }
    }

    /// The table as shipped with the crate (`assets/split_sum_bias.bin`: every G's table,
    /// in `Geometry::ALL` order, little-endian f32), what the renderers use: no bake at
    /// startup. A test holds it bit for bit equal to [`SplitSum::bake`].
    pub(crate) fn shipped(geometry: Geometry) -> Self {
        const BYTES: &[u8] = include_bytes!("../../assets/split_sum_bias.bin");
        let n = SPLIT_SUM_SIZE * SPLIT_SUM_SIZE;
        let index = Geometry::ALL
            .iter()
            .position(|&g| g == geometry)
            .unwrap_or(0);
        let bias = BYTES[index * n * 4..(index + 1) * n * 4]
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        SplitSum { geometry, bias }
    }

    /// Every G's table as [`SplitSum::shipped`] reads them (what the test writes when the
    /// bake changes).
    #[cfg(test)]
    pub(crate) fn shipped_bytes() -> Vec<u8> {
        Geometry::ALL
            .iter()
            .flat_map(|&g| SplitSum::bake(g).bias)
            .flat_map(f32::to_le_bytes)
            .collect()
    }

    /// `split_sum_bias` of `shaders/environment.wgsl`: B at `(mu, roughness)`, bilinear
    /// between the texels around it (clamped to the table), in f32 as the shader does.
    pub fn bias_at(&self, mu: f32, roughness: f32) -> f32 {
        let n = SPLIT_SUM_SIZE;
        let x = mu.clamp(0.0, 1.0) * (n - 1) as f32;
        let y = roughness.clamp(0.0, 1.0) * (n - 1) as f32;
        let (i0, j0) = ((x as usize).min(n - 2), (y as usize).min(n - 2));
        let (fx, fy) = (x - i0 as f32, y - j0 as f32);
        let t = |i: usize, j: usize| self.bias[j * n + i];
        let top = t(i0, j0) + (t(i0 + 1, j0) - t(i0, j0)) * fx;
        let bottom = t(i0, j0 + 1) + (t(i0 + 1, j0 + 1) - t(i0, j0 + 1)) * fx;
        top + (bottom - top) * fy
    }
}
