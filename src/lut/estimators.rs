//! Estimators of `E(mu, roughness)` (F = 1) and the point sets that drive them.
//! All return the estimate of the same integral as [`super::reference::e_reference`].

use std::f64::consts::PI;

use super::integrand::{EIntegrand, MU_MIN};
use super::quadrature::gauss_legendre_unit;
use crate::brdf::{alpha_from_roughness, d_ggx, g1_smith, Geometry};

/// How E is estimated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// Cosine-weighted sampling of l (the homework's `Emu_MC`): weight `pi f`.
    Cosine,
    /// GGX NDF importance sampling of h (the homework's `Emu_IS`): weight
    /// `G (v.h) / (mu_o (n.h))`.
    Ndf,
    /// Visible-normal sampling (Dupuy & Benyoub 2023, "Sampling Visible GGX Normals with
    /// Spherical Caps"): weight `G / G1(mu_o)`, bounded.
    Vndf,
    /// Gauss-Legendre over `theta_i` after the azimuth is integrated in closed form
    /// (see `integrand.rs`); `samples` nodes in each of its (up to five) segments.
    Quadrature,
    /// The quadrature at a Chebyshev grid in (warped mu, roughness), interpolated to each
    /// texel (`chebyshev.rs`): the same value at a single point, a fixed cost per table.
    Chebyshev,
}

impl Method {
    /// Every method, in a fixed order.
    pub const ALL: [Method; 5] = [
        Method::Cosine,
        Method::Ndf,
        Method::Vndf,
        Method::Quadrature,
        Method::Chebyshev,
    ];

    /// The name used on the command line and in messages.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Method::Cosine => "cosine",
            Method::Ndf => "ndf",
            Method::Vndf => "vndf",
            Method::Quadrature => "quadrature",
            Method::Chebyshev => "chebyshev",
        }
    }
}

/// The 2-D point set a Monte Carlo estimator draws from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PointSet {
    /// Independent uniform points (PCG32, a fixed seed per texel): the homework's choice.
    Random,
    /// Hammersley: `(i / N, radical_inverse_2(i))` (Hammersley & Handscomb 1964).
    Hammersley,
    /// The first two dimensions of Sobol' (Sobol' 1967), a (0, 2)-sequence.
    Sobol,
}

impl PointSet {
    /// Every point set, in a fixed order.
    pub(crate) const ALL: [PointSet; 3] = [PointSet::Random, PointSet::Hammersley, PointSet::Sobol];

    /// The name used on the command line and in messages.
    pub(crate) fn name(self) -> &'static str {
        match self {
            PointSet::Random => "random",
            PointSet::Hammersley => "hammersley",
            PointSet::Sobol => "sobol",
        }
    }

    /// Fills `out` with `n` points in `[0, 1)^2`; `seed` decorrelates texels (Random only).
    pub(crate) fn points(self, n: usize, seed: u64, out: &mut Vec<[f64; 2]>) {
        out.clear();
        const TO_UNIT: f64 = 1.0 / 4_294_967_296.0;
        match self {
            PointSet::Random => {
                let mut rng = Pcg32::new(seed);
                out.extend((0..n).map(|_| [rng.unit(), rng.unit()]));
            }
            PointSet::Hammersley => out.extend((0..n).map(|i| {
                [
                    (i as f64 + 0.5) / n as f64,
                    (i as u32).reverse_bits() as f64 * TO_UNIT,
                ]
            })),
            PointSet::Sobol => out.extend((0..n as u32).map(|i| {
                [
                    i.reverse_bits() as f64 * TO_UNIT,
                    sobol_dim2(i) as f64 * TO_UNIT,
                ]
            })),
        }
    }
}

crate::named_enum!(Method, "method");
crate::named_enum!(PointSet, "point set");

/// Sobol's second dimension: direction numbers `v_k = v_{k-1} ^ (v_{k-1} >> 1)` from
/// `v_0 = 2^31` (the Pascal-matrix generator; Kollig & Keller 2002).
fn sobol_dim2(mut i: u32) -> u32 {
    let mut r = 0;
    let mut v = 1u32 << 31;
    while i != 0 {
        if i & 1 != 0 {
            r ^= v;
        }
        i >>= 1;
        v ^= v >> 1;
    }
    r
}

/// PCG32 (O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient Statistically Good
/// Algorithms for Random Number Generation"), XSH-RR output.
struct Pcg32 {
    state: u64,
}

impl Pcg32 {
    const MUL: u64 = 6_364_136_223_846_793_005;
    const INC: u64 = 1_442_695_040_888_963_407;

    fn new(seed: u64) -> Self {
        let mut rng = Self { state: 0 };
        rng.next();
        rng.state = rng.state.wrapping_add(seed);
        rng.next();
        rng
    }

    fn next(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(Self::MUL).wrapping_add(Self::INC);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        xorshifted.rotate_right((old >> 59) as u32)
    }

    fn unit(&mut self) -> f64 {
        self.next() as f64 / 4_294_967_296.0
    }
}

/// Per-bake scratch state: quadrature nodes, point buffers.
pub(crate) struct Estimator {
    method: Method,
    points: PointSet,
    samples: usize,
    gl: (Vec<f64>, Vec<f64>),
    scratch: Vec<[f64; 2]>,
}

impl Estimator {
    /// An estimator of `method` with `samples` (at least 1) points of `points` a texel
    /// (Monte Carlo) or Gauss-Legendre nodes a segment (quadrature).
    pub(crate) fn new(method: Method, points: PointSet, samples: usize) -> Self {
        let samples = samples.max(1);
        let gl = if matches!(method, Method::Quadrature | Method::Chebyshev) {
            gauss_legendre_unit(samples)
        } else {
            (Vec::new(), Vec::new())
        };
        Self {
            method,
            points,
            samples,
            gl,
            scratch: Vec::with_capacity(samples),
        }
    }

    /// Estimate of `E(mu, roughness)`; `seed` decorrelates random points between texels.
    pub(crate) fn e(&mut self, mu: f64, roughness: f64, geometry: Geometry, seed: u64) -> f64 {
        if matches!(self.method, Method::Quadrature | Method::Chebyshev) {
            return self.e_quadrature(mu, roughness, geometry);
        }
        let mu_o = mu.clamp(MU_MIN, 1.0);
        let v = [(1.0 - mu_o * mu_o).max(0.0).sqrt(), 0.0, mu_o];
        let alpha = alpha_from_roughness(roughness);
        let mut points = std::mem::take(&mut self.scratch);
        self.points.points(self.samples, seed, &mut points);
        let sum: f64 = points
            .iter()
            .map(|&u| match self.method {
                Method::Cosine => weight_cosine(v, u, alpha, roughness, geometry),
                Method::Ndf => weight_ndf(v, u, alpha, roughness, geometry),
                Method::Vndf => weight_vndf(v, u, alpha, roughness, geometry),
                Method::Quadrature | Method::Chebyshev => unreachable!("handled above"),
            })
            .sum();
        self.scratch = points;
        sum / self.samples as f64
    }

    fn e_quadrature(&self, mu: f64, roughness: f64, geometry: Geometry) -> f64 {
        let f = EIntegrand::new(mu, roughness, geometry);
        let (nodes, weights) = &self.gl;
        f.segments()
            .map(|seg| {
                let span = seg.hi - seg.lo;
                let sum: f64 = nodes
                    .iter()
                    .zip(weights)
                    .map(|(&x, &w)| w * f.at_segment(&seg, seg.lo + x * span))
                    .sum();
                sum * span
            })
            .sum()
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn normalize(a: [f64; 3]) -> [f64; 3] {
    let len = dot(a, a).sqrt();
    [a[0] / len, a[1] / len, a[2] / len]
}

fn reflect(v: [f64; 3], h: [f64; 3]) -> [f64; 3] {
    let d = 2.0 * dot(v, h);
    [d * h[0] - v[0], d * h[1] - v[1], d * h[2] - v[2]]
}

/// Cosine-weighted l, pdf `mu_i / pi`: the estimate of `f mu_i / pdf` is `pi f`.
fn weight_cosine(v: [f64; 3], u: [f64; 2], alpha: f64, roughness: f64, geometry: Geometry) -> f64 {
    let r = u[0].sqrt();
    let phi = 2.0 * PI * u[1];
    let l = [r * phi.cos(), r * phi.sin(), (1.0 - u[0]).max(0.0).sqrt()];
    let mu_i = l[2];
    if mu_i <= 0.0 {
        return 0.0;
    }
    let h = normalize([v[0] + l[0], v[1] + l[1], v[2] + l[2]]);
    let d = d_ggx(h[2], alpha);
    let g = geometry.g(v[2], mu_i, roughness);
    PI * d * g / (4.0 * mu_i * v[2])
}

/// GGX NDF sample of h (Walter et al. 2007, eq. 35-36: `tan^2 theta = alpha^2 u / (1 - u)`),
/// pdf `D (n.h)` in h: weight `G (v.h) / (mu_o (n.h))`.
fn weight_ndf(v: [f64; 3], u: [f64; 2], alpha: f64, roughness: f64, geometry: Geometry) -> f64 {
    let tan2 = alpha * alpha * u[0] / (1.0 - u[0]).max(f64::MIN_POSITIVE);
    let cos_t = 1.0 / (1.0 + tan2).sqrt();
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let phi = 2.0 * PI * u[1];
    let h = [sin_t * phi.cos(), sin_t * phi.sin(), cos_t];
    let l = reflect(v, h);
    let v_dot_h = dot(v, h);
    if l[2] <= 0.0 || v_dot_h <= 0.0 {
        return 0.0;
    }
    geometry.g(v[2], l[2], roughness) * v_dot_h / (v[2] * cos_t)
}

/// Visible-normal sample of h with spherical caps (Dupuy & Benyoub 2023, listing 3): sample
/// the cap of the unit sphere cut at `-v_h.z` around the stretched view, add the view,
/// unstretch. pdf in l is `G1(v) D (v.h)^+ / (4 mu_o (v.h))`, so the weight is
/// `G(v, l) / G1(v)` with Smith's G1 (the one that normalises the visible normals).
fn weight_vndf(v: [f64; 3], u: [f64; 2], alpha: f64, roughness: f64, geometry: Geometry) -> f64 {
    let vh = normalize([alpha * v[0], alpha * v[1], v[2]]);
    let phi = 2.0 * PI * u[0];
    let z = (1.0 - u[1]) * (1.0 + vh[2]) - vh[2];
    let sin_t = (1.0 - z * z).clamp(0.0, 1.0).sqrt();
    let c = [sin_t * phi.cos(), sin_t * phi.sin(), z];
    let hh = [c[0] + vh[0], c[1] + vh[1], c[2] + vh[2]];
    let h = normalize([alpha * hh[0], alpha * hh[1], hh[2].max(0.0)]);
    let l = reflect(v, h);
    if l[2] <= 0.0 {
        return 0.0;
    }
    geometry.g(v[2], l[2], roughness) / g1_smith(v[2], alpha)
}
