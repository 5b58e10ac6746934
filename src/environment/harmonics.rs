//! Real spherical harmonics: projecting an environment map onto the first bands and
//! convolving it with a zonal kernel by the Funk-Hecke theorem (docs/design/environment.md,
//! "Harmonics or a map per roughness"). The renderer prefilters a small map per roughness
//! instead ([`super::prefilter`]); this module is the alternative it was measured against.
//!
//! **Basis.** Orthonormal real harmonics `Y_lm`, `l` in `0..bands`, `m` in `-l..=l`, stored at
//! index `l * l + l + m`, with the polar axis `+z` of the direction as given (any fixed frame
//! serves: a zonal convolution does not depend on it):
//! `Y_l0 = K_l0 P_l0(z)`, `Y_lm = sqrt 2 K_lm cos(m phi) P_lm(z)` and
//! `Y_l(-m) = sqrt 2 K_lm sin(m phi) P_lm(z)` for `m > 0`, with
//! `K_lm = sqrt((2l + 1) / 4 pi (l - m)! / (l + m)!)` (Green 2003, "Spherical Harmonic
//! Lighting: The Gritty Details", section 3; without the Condon-Shortley phase).
//!
//! **Evaluation.** `P_lm(z) = sin^m(theta) Q_lm(z)` where `Q` follows the associated
//! Legendre recurrences of Green 2003 with the `sin^m` factor taken out:
//! `Q_mm = (2m - 1)!!`, `Q_(m+1)m = (2m + 1) z Q_mm`,
//! `(l - m) Q_lm = (2l - 1) z Q_(l-1)m - (l + m - 1) Q_(l-2)m`;
//! and `sin^m(theta) (cos m phi, sin m phi)` is `(x + i y)^m`, built one power at a time
//! (Sloan 2008, "Stupid Spherical Harmonics (SH) Tricks", appendix: the polynomial form).
//! So no angle, square root of `1 - z^2` or division appears and the poles are regular.
//! `K_lm` is carried along the same loops by its ratios. In `f64` it is good to about 80
//! bands (`(2m - 1)!!` and `1 / (2m)!` stay in range); the lab uses at most 13.
//!
//! **Convolution.** For a zonal kernel `k(n.w)`, Funk-Hecke gives
//! `int k(n.w) Y_lm(w) dw = Lambda_l Y_lm(n)` with `Lambda_l = 2 pi int_-1^1 k(t) P_l(t) dt`
//! (Ramamoorthi & Hanrahan 2001, "An Efficient Representation for Irradiance Environment
//! Maps", equation 5 without their normalising factor), so
//! `int k(n.w) L(w) dw = sum_l Lambda_l sum_m L_lm Y_lm(n)` for the band-limited `L`. The
//! cosine kernel gives `Lambda = pi, 2 pi / 3, pi / 4, 0, -pi / 24, ...`.

use std::f64::consts::PI;

use glam::{DVec2, DVec3};

use super::{uv_to_direction, EnvMap};
use crate::lut::gauss_legendre_unit;

/// Coefficients of `bands` bands: `bands^2`.
pub(crate) fn coefficient_count(bands: usize) -> usize {
    bands * bands
}

/// The index of `Y_lm` (`-l <= m <= l`) in the coefficient vectors: `l * l + l + m`.
pub fn index(l: usize, m: i64) -> usize {
    (l as i64 * l as i64 + l as i64 + m) as usize
}

/// The real harmonics `Y_lm(d)` of bands `0..bands` at unit direction `d` into
/// `out[..bands^2]` (module docs for the basis and the recurrences). Panics when `out` is
/// shorter than `bands^2`.
pub fn sh_basis(d: DVec3, bands: usize, out: &mut [f64]) {
    assert!(
        out.len() >= coefficient_count(bands),
        "sh_basis: out too short"
    );
    let (x, y, z) = (d.x, d.y, d.z);
    // (c, s) = (x + i y)^m, q_mm = (2m - 1)!!, k2_mm = K_mm^2 = (2m + 1) / (4 pi (2m)!).
    let (mut c, mut s) = (1.0, 0.0);
    let mut q_mm = 1.0;
    let mut k2_mm = 1.0 / (4.0 * PI);
    for m in 0..bands {
        let mf = m as f64;
        if m > 0 {
            let (c1, s1) = (x * c - y * s, x * s + y * c);
            c = c1;
            s = s1;
            q_mm *= 2.0 * mf - 1.0;
            // K_mm^2 / K_(m-1)(m-1)^2 = (2m + 1) / (2m - 1) / ((2m - 1) 2m).
            k2_mm *= (2.0 * mf + 1.0) / ((2.0 * mf - 1.0) * (2.0 * mf - 1.0) * 2.0 * mf);
        }
        let (mut q_prev, mut q) = (0.0, q_mm);
        let mut k2 = k2_mm;
        for l in m..bands {
            let lf = l as f64;
            if l > m {
                let q_next = if l == m + 1 {
                    (2.0 * mf + 1.0) * z * q
                } else {
                    ((2.0 * lf - 1.0) * z * q - (lf + mf - 1.0) * q_prev) / (lf - mf)
                };
                q_prev = q;
                q = q_next;
                // K_lm^2 / K_(l-1)m^2 = (2l + 1) / (2l - 1) (l - m) / (l + m).
                k2 *= (2.0 * lf + 1.0) / (2.0 * lf - 1.0) * (lf - mf) / (lf + mf);
            }
            let kq = k2.sqrt() * q;
            if m == 0 {
                out[index(l, 0)] = kq;
            } else {
                let kq = std::f64::consts::SQRT_2 * kq;
                out[index(l, m as i64)] = kq * c;
                out[index(l, -(m as i64))] = kq * s;
            }
        }
    }
}

/// The coefficients `L_lm = sum over texels of L Y_lm(texel centre) dOmega` of `map` for
/// bands `0..bands` (RGB each, [`index`] order): the midpoint rule on the map's texels,
/// each weighted by its exact solid angle.
pub fn project(map: &EnvMap, bands: usize) -> Vec<DVec3> {
    let count = coefficient_count(bands);
    let mut coeffs = vec![DVec3::ZERO; count];
    let mut y = vec![0.0; count];
    let (w, h) = (map.width(), map.height());
    for j in 0..h {
        let omega = map.texel_solid_angle(j);
        let v = (j as f64 + 0.5) / h as f64;
        for i in 0..w {
            let d = uv_to_direction(DVec2::new((i as f64 + 0.5) / w as f64, v));
            sh_basis(d, bands, &mut y);
            let l = map.texel(i, j) * omega;
            for (c, &b) in coeffs.iter_mut().zip(&y) {
                *c += l * b;
            }
        }
    }
    coeffs
}

/// Gauss-Legendre nodes [`zonal_coefficients`] integrates with, for `bands` bands: exact
/// for a polynomial kernel of degree below `2 * nodes - bands`.
pub(crate) fn zonal_nodes(bands: usize) -> usize {
    128 + bands
}

/// The Funk-Hecke factors `Lambda_l = 2 pi int_0^1 k(t) P_l(t) dt` of a zonal kernel that is
/// zero below the horizon (`k(t)` for `t` in `[0, 1]`), `l` in `0..bands`: Gauss-Legendre
/// with `zonal_nodes` nodes, the Legendre polynomials by Bonnet's recurrence
/// `l P_l = (2l - 1) t P_(l-1) - (l - 1) P_(l-2)`.
pub fn zonal_coefficients(kernel: impl Fn(f64) -> f64, bands: usize) -> Vec<f64> {
    let (nodes, weights) = gauss_legendre_unit(zonal_nodes(bands));
    let mut out = vec![0.0; bands];
    for (&t, &wt) in nodes.iter().zip(&weights) {
        let kw = kernel(t) * wt * 2.0 * PI;
        let (mut p_prev, mut p) = (0.0, 1.0);
        for (l, o) in out.iter_mut().enumerate() {
            if l > 0 {
                let lf = l as f64;
                let next = ((2.0 * lf - 1.0) * t * p - (lf - 1.0) * p_prev) / lf;
                p_prev = p;
                p = next;
            }
            *o += kw * p;
        }
    }
    out
}

/// `sum_l zonal[l] sum_m coeffs[lm] Y_lm(n)` over the bands of `zonal` (at most those of
/// `coeffs`): the band-limited convolution `int k(n.w) L(w) dw` at unit normal `n`.
pub fn convolve_eval(coeffs: &[DVec3], zonal: &[f64], n: DVec3) -> DVec3 {
    let bands = zonal.len();
    assert!(
        coeffs.len() >= coefficient_count(bands),
        "convolve_eval: {} coefficients for {bands} bands",
        coeffs.len()
    );
    // 32 bands on the stack; more on the heap.
    let mut stack = [0.0; 1024];
    let mut heap = Vec::new();
    let y: &mut [f64] = if coefficient_count(bands) <= stack.len() {
        &mut stack[..]
    } else {
        heap.resize(coefficient_count(bands), 0.0);
        &mut heap[..]
    };
    sh_basis(n, bands, y);
    let mut sum = DVec3::ZERO;
    for (l, &k) in zonal.iter().enumerate() {
        let mut band = DVec3::ZERO;
        for i in l * l..(l + 1) * (l + 1) {
            band += coeffs[i] * y[i];
        }
        sum += band * k;
    }
    sum
}
