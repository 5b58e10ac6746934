//! Fresnel factors for the random walk and the models it is compared with: constant 1
//! (the white furnace), Schlick with `F0`, and the full Fresnel of a conductor whose
//! complex index of refraction comes from an artist-friendly (reflectivity, edge tint)
//! pair (Gulbrandsen 2014, "Artist Friendly Metallic Fresnel", JCGT 3(4)).

use shadeballs::brdf::{f_avg_schlick, f_schlick, DIV_EPSILON, GAMES202_EDGE_TINT};
use shadeballs::lut::adaptive;
use shadeballs::scene::gamma22_decode;

/// Largest reflectivity the Gulbrandsen mapping accepts: its `k` divides by `1 - r`.
pub const REFLECTIVITY_MAX: f64 = 0.999;

/// The Fresnel factor of one colour channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fresnel {
    /// `F = 1`: a perfect reflector (the white furnace).
    One,
    /// Schlick's approximation with this `F0`, as the renderer's `f_micro` uses it.
    Schlick(f64),
    /// The exact Fresnel reflectance of a conductor of complex index `eta + i k`.
    Conductor { eta: f64, k: f64 },
}

impl shadeballs::walk::Reflectance for Fresnel {
    fn eval(&self, cos: f64) -> f64 {
        Fresnel::eval(*self, cos)
    }
}

impl Fresnel {
    /// Reflectance for a cosine `cos` between the incident direction and the facet normal.
    pub fn eval(self, cos: f64) -> f64 {
        match self {
            Fresnel::One => 1.0,
            Fresnel::Schlick(f0) => f_schlick(f0, cos),
            Fresnel::Conductor { eta, k } => fresnel_conductor(eta, k, cos),
        }
    }

    /// Reflectance at normal incidence.
    pub fn f0(self) -> f64 {
        self.eval(1.0)
    }

    /// The cosine-weighted average `F_avg = 2 int_0^1 F(mu) mu dmu` (closed form for
    /// Schlick, adaptive quadrature for a conductor).
    pub fn average(self) -> f64 {
        match self {
            Fresnel::One => 1.0,
            Fresnel::Schlick(f0) => f_avg_schlick(f0),
            Fresnel::Conductor { .. } => {
                adaptive(&|mu: f64| 2.0 * self.eval(mu) * mu, 0.0, 1.0, 1e-12)
            }
        }
    }
}

/// A minimal complex number for the conductor Fresnel equations.
#[derive(Clone, Copy, Debug)]
struct Complex(f64, f64);

impl Complex {
    fn add(self, o: Complex) -> Complex {
        Complex(self.0 + o.0, self.1 + o.1)
    }
    fn sub(self, o: Complex) -> Complex {
        Complex(self.0 - o.0, self.1 - o.1)
    }
    fn mul(self, o: Complex) -> Complex {
        Complex(self.0 * o.0 - self.1 * o.1, self.0 * o.1 + self.1 * o.0)
    }
    fn norm_sqr(self) -> f64 {
        self.0 * self.0 + self.1 * self.1
    }
    fn scale(self, s: f64) -> Complex {
        Complex(self.0 * s, self.1 * s)
    }
    /// Principal square root.
    fn sqrt(self) -> Complex {
        let r = self.norm_sqr().sqrt();
        let re = (0.5 * (r + self.0)).max(0.0).sqrt();
        let im = (0.5 * (r - self.0)).max(0.0).sqrt();
        Complex(re, if self.1 < 0.0 { -im } else { im })
    }
    /// `|a / b|^2` without forming the quotient.
    fn ratio_norm_sqr(a: Complex, b: Complex) -> f64 {
        a.norm_sqr() / b.norm_sqr().max(DIV_EPSILON)
    }
}

/// Unpolarised Fresnel reflectance from air onto a conductor of index `eta + i k` at
/// incidence cosine `cos` (Pharr, Jakob and Humphreys, "Physically Based Rendering", 4th
/// ed., section 9.3.6: the dielectric equations with a complex index):
/// `cos_t = sqrt(1 - sin^2 / n^2)`, `r_s = (cos - n cos_t) / (cos + n cos_t)`,
/// `r_p = (n cos - cos_t) / (n cos + cos_t)`, `F = (|r_s|^2 + |r_p|^2) / 2`.
pub fn fresnel_conductor(eta: f64, k: f64, cos: f64) -> f64 {
    let c = cos.clamp(0.0, 1.0);
    let n = Complex(eta, k);
    let n2 = n.mul(n);
    let sin2 = 1.0 - c * c;
    // 1 / n^2 = conj(n^2) / |n^2|^2
    let inv_n2 = Complex(n2.0, -n2.1).scale(1.0 / n2.norm_sqr().max(DIV_EPSILON));
    let cos_t = Complex(1.0, 0.0).sub(inv_n2.scale(sin2)).sqrt();
    let ci = Complex(c, 0.0);
    let n_cos_t = n.mul(cos_t);
    let rs = Complex::ratio_norm_sqr(ci.sub(n_cos_t), ci.add(n_cos_t));
    let n_cos = n.scale(c);
    let rp = Complex::ratio_norm_sqr(n_cos.sub(cos_t), n_cos.add(cos_t));
    (0.5 * (rs + rp)).clamp(0.0, 1.0)
}

/// Gulbrandsen 2014's mapping from reflectivity `r` (= F0) and edge tint `g` to a complex
/// index: `n = g n_min + (1 - g) n_max` with `n_min = (1 - r) / (1 + r)`,
/// `n_max = (1 + sqrt r) / (1 - sqrt r)`, and `k^2 = (r (n + 1)^2 - (n - 1)^2) / (1 - r)`.
/// `r` is clamped to `[0, REFLECTIVITY_MAX]`, `g` to `[0, 1]`.
pub fn gulbrandsen_ior(r: f64, g: f64) -> (f64, f64) {
    let r = r.clamp(0.0, REFLECTIVITY_MAX);
    let g = g.clamp(0.0, 1.0);
    let sr = r.sqrt();
    let n_min = (1.0 - r) / (1.0 + r);
    let n_max = (1.0 + sr) / (1.0 - sr);
    let n = g * n_min + (1.0 - g) * n_max;
    let k2 = (r * (n + 1.0) * (n + 1.0) - (n - 1.0) * (n - 1.0)) / (1.0 - r);
    (n, k2.max(0.0).sqrt())
}

/// The inverse of [`gulbrandsen_ior`] (Gulbrandsen 2014):
/// `r = ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2)`, `g = (n_max - n) / (n_max - n_min)`.
pub fn gulbrandsen_pair(eta: f64, k: f64) -> (f64, f64) {
    let r = ((eta - 1.0).powi(2) + k * k) / ((eta + 1.0).powi(2) + k * k).max(DIV_EPSILON);
    let sr = r.sqrt();
    let n_min = (1.0 - r) / (1.0 + r);
    let n_max = (1.0 + sr) / (1.0 - sr).max(DIV_EPSILON);
    (r, (n_max - eta) / (n_max - n_min).max(DIV_EPSILON))
}

/// A material of the study: three channels, each with an artist-friendly pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metal {
    pub name: &'static str,
    /// Reflectivity (= F0) per channel.
    pub r: [f64; 3],
    /// Edge tint per channel.
    pub g: [f64; 3],
}

impl Metal {
    /// The homework's copper: F0 = the scene's sRGB albedo (0.7216, 0.451, 0.2) decoded with
    /// pow 2.2 (docs/design/reference-scene.md, "The balls, the light and the camera"),
    /// edge tint [`GAMES202_EDGE_TINT`].
    pub fn copper() -> Self {
        Metal {
            name: "copper",
            r: gamma22_decode([0.7216, 0.451, 0.2]).to_array(),
            g: GAMES202_EDGE_TINT,
        }
    }

    /// Gold: the pair of a commonly used RGB complex index of gold,
    /// eta = (0.143, 0.375, 1.442), k = (3.983, 2.386, 1.603), through
    /// [`gulbrandsen_pair`]. Illustrative (a plausible gold), not measured data.
    pub fn gold() -> Self {
        let eta = [0.143, 0.375, 1.442];
        let k = [3.983, 2.386, 1.603];
        let pair = |c: usize| gulbrandsen_pair(eta[c], k[c]);
        Metal {
            name: "gold",
            r: [pair(0).0, pair(1).0, pair(2).0],
            g: [pair(0).1, pair(1).1, pair(2).1],
        }
    }

    /// Channel `c` with Schlick's Fresnel and `F0 = r`.
    pub fn schlick(&self, c: usize) -> Fresnel {
        Fresnel::Schlick(self.r[c])
    }

    /// Channel `c` with the full conductor Fresnel of its (r, g) pair.
    pub fn conductor(&self, c: usize) -> Fresnel {
        let (eta, k) = gulbrandsen_ior(self.r[c], self.g[c]);
        Fresnel::Conductor { eta, k }
    }
}
