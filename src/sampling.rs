//! The sampling maths once, the f64 twin of `shaders/sampling.wgsl` name for name: the
//! orthonormal frame about a normal (`duff_frame`), GGX's visible normals reflected
//! ([`sample_vndf`]) and their density ([`vndf_density`]), the cosine hemisphere
//! (`sample_cosine`), the equirectangular map's density (`equirect_density`), the power
//! heuristic (`power_estimate`) and the radiance arriving along a direction (`arriving`).
//! The lobe (`cpu::shade`), the Monte Carlo (`cpu::montecarlo`), the truth (`cpu::truth`)
//! and the prefilter's twin (`environment::prefilter`) take them from here. Above the maths
//! (`brdf`) alone.

use std::f64::consts::PI;

use glam::DVec3;

use crate::brdf::{d_ggx, DIV_EPSILON};

/// An orthonormal frame about a unit normal, columns (tangent, bitangent, normal).
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    t: DVec3,
    b: DVec3,
    n: DVec3,
}

/// The orthonormal frame about unit `n` (Duff et al. 2017, "Building an Orthonormal Basis,
/// Revisited", JCGT 6(1)).
pub(crate) fn duff_frame(n: DVec3) -> Frame {
    let sign = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    Frame {
        t: DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        b: DVec3::new(b, sign + n.y * n.y * a, -n.y),
        n,
    }
}

impl Frame {
    /// The frame about unit `n` (`duff_frame`).
    pub fn new(n: DVec3) -> Self {
        duff_frame(n)
    }
    /// The frame of the orthonormal `t`, `b`, `n` (a ball's tangent field:
    /// `brdf::ball_tangent`).
    pub(crate) fn from_axes(t: DVec3, b: DVec3, n: DVec3) -> Self {
        Frame { t, b, n }
    }
    /// The tangent and the bitangent.
    pub(crate) fn tangents(&self) -> (DVec3, DVec3) {
        (self.t, self.b)
    }
    /// `w` in the frame (normal `+z`).
    pub fn to_local(&self, w: DVec3) -> DVec3 {
        DVec3::new(w.dot(self.t), w.dot(self.b), w.dot(self.n))
    }
    /// Local `l` in the world.
    pub fn to_world(&self, l: DVec3) -> DVec3 {
        l.x * self.t + l.y * self.b + l.z * self.n
    }
}

/// A reflected direction (local frame, normal `+z`) whose half vector follows GGX's
/// distribution of normals visible from `v` (Heitz 2018, "Sampling the GGX Distribution of
/// Visible Normals", JCGT 7(4), listing 1): stretch `v` to the hemisphere configuration,
/// sample the projected disk, warp to the visible half, unstretch. May lie below the
/// horizon (the caller's `mu_i <= 0` gives it no weight). The walk's visible normal
/// (`crate::brdf::visible_normal`) takes `v` on either side of the horizon; this one
/// clamps it to the upper side, as the shaders' lobe does.
pub fn sample_vndf(v: DVec3, alpha: f64, u1: f64, u2: f64) -> DVec3 {
    sample_vndf_aniso(v, (alpha, alpha), u1, u2)
}

/// The density per solid angle of [`sample_vndf`]'s direction with half vector at `n.h`
/// (Heitz 2018, eq. 17 with the reflection's Jacobian `1 / (4 v.h)`): `G1(v) D(h) / (4
/// mu_o)`, with `G1(v) / mu_o = 2 / (mu_o + sqrt(mu_o^2 + alpha^2 (1 - mu_o^2)))` (exact
/// Smith G1 for GGX, whatever G the model uses: the distribution the sampler draws from),
/// finite at grazing `v`.
pub fn vndf_density(mu_o: f64, n_dot_h: f64, alpha: f64) -> f64 {
    let c = mu_o.clamp(0.0, 1.0);
    let root = (c * c + alpha * alpha * (1.0 - c * c)).sqrt();
    let g1_over_mu = 2.0 / (c + root).max(DIV_EPSILON);
    d_ggx(n_dot_h, alpha) * g1_over_mu / 4.0
}

/// [`sample_vndf`] of anisotropic GGX, `alpha_t` along local `x` and `alpha_b` along `y`
/// (Heitz 2018's listing 1 takes the two alphas: the stretch is per axis).
pub(crate) fn sample_vndf_aniso(
    v: DVec3,
    (alpha_t, alpha_b): (f64, f64),
    u1: f64,
    u2: f64,
) -> DVec3 {
    let vh = DVec3::new(alpha_t * v.x, alpha_b * v.y, v.z.max(0.0));
    let vh = vh / vh.length().max(DIV_EPSILON);
    let lensq = vh.x * vh.x + vh.y * vh.y;
    let t1 = if lensq > DIV_EPSILON {
        DVec3::new(-vh.y, vh.x, 0.0) / lensq.sqrt()
    } else {
        DVec3::X
    };
    let t2 = vh.cross(t1);
    let r = u1.sqrt();
    let phi = 2.0 * PI * u2;
    let p1 = r * phi.cos();
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
    let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * vh;
    let ne = DVec3::new(alpha_t * nh.x, alpha_b * nh.y, nh.z.max(0.0));
    let h = ne / ne.length().max(DIV_EPSILON);
    2.0 * v.dot(h) * h - v
}

/// The density per solid angle of [`sample_vndf_aniso`]'s direction with local half
/// vector `h`, local `v`: `G1(v) D(h) / (4 v_z)`, `G1(v) / v_z = 2 / (v_z + sqrt(v_z^2 +
/// alpha_t^2 v_x^2 + alpha_b^2 v_y^2))` (exact anisotropic Smith G1), finite at grazing `v`.
pub(crate) fn vndf_density_aniso(v: DVec3, h: DVec3, (alpha_t, alpha_b): (f64, f64)) -> f64 {
    let c = v.z.clamp(0.0, 1.0);
    let (x, y) = (alpha_t * v.x, alpha_b * v.y);
    let root = (c * c + x * x + y * y).sqrt();
    let g1_over_mu = 2.0 / (c + root).max(DIV_EPSILON);
    crate::brdf::d_ggx_aniso(h, alpha_t, alpha_b) * g1_over_mu / 4.0
}

/// A cosine-distributed direction about `+z` (Malley's method: the unit disk projected up),
/// density `mu_i / pi`.
pub(crate) fn sample_cosine(u1: f64, u2: f64) -> DVec3 {
    let r = u1.sqrt();
    let phi = 2.0 * PI * u2;
    DVec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt())
}

/// The density per solid angle of a direction `d` (the map's frame) drawn by picking a texel
/// of a `w x h` equirectangular map with probability `p_texel`, then uniformly in its
/// `(u, v)` rectangle: `p_texel w h / (2 pi^2 sin theta)`, the mapping's Jacobian (Pharr,
/// Jakob & Humphreys, *Physically Based Rendering*, 3rd ed., 2016, section 14.2.4).
pub(crate) fn equirect_density(p_texel: f64, d: DVec3, (w, h): (f64, f64)) -> f64 {
    let sin_theta = (1.0 - d.y * d.y).max(0.0).sqrt();
    p_texel * w * h / (2.0 * PI * PI * sin_theta.max(DIV_EPSILON))
}

/// The buckets of the guide of a CDF of `n >= 1` values (the cutpoint method;
/// `crate::environment::sampler::luminance_partition`): `n` rounded up to a power of two,
/// so that a uniform number's bucket, `floor(x buckets)`, is exact in f32.
pub(crate) fn guide_buckets(n: usize) -> usize {
    n.next_power_of_two()
}

/// The power heuristic's estimate, exponent 2, of one sample of one of several strategies
/// drawn equally often (Veach 1997, *Robust Monte Carlo Methods for Light Transport
/// Simulation*, PhD thesis, Stanford, section 9.2.4): the integrand `f L mu_i` over the
/// drawing strategy's density `pdf_own`, weighted by `pdf_own^2 / sum_k pdf_k(l)^2`; written
/// `f L mu_i pdf_own / sum_k pdf_k(l)^2` (`pdf_square_sum`), 0 where that sum is below
/// `DIV_EPSILON^2` (a guard on densities, squared).
pub(crate) fn power_estimate(integrand: DVec3, pdf_own: f64, pdf_square_sum: f64) -> DVec3 {
    let guard = DIV_EPSILON * DIV_EPSILON;
    if pdf_square_sum > guard {
        integrand * (pdf_own / pdf_square_sum)
    } else {
        DVec3::ZERO
    }
}

/// Radiance arriving from world direction `d`: the uniform `environment` plus the `map`'s
/// radiance along `d` (none without a map).
pub(crate) fn arriving(
    d: DVec3,
    environment: DVec3,
    map: Option<impl Fn(DVec3) -> DVec3>,
) -> DVec3 {
    environment + map.map_or(DVec3::ZERO, |m| m(d))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The power heuristic's weights at one direction, `pdf_own^2 / sum_k pdf_k^2` (each
    /// strategy's estimate times its density over the integrand), sum to 1 over the
    /// strategies whose density is positive, which keeps the combined estimate unbiased;
    /// an estimate whose square sum is under the guard is 0.
    #[test]
    fn the_power_heuristics_weights_sum_to_one() {
        let f = DVec3::new(0.5, 2.0, 7.0);
        for pdf in [
            [3.0, 0.3, 0.0, 0.0],
            [1e-3, 2.5, 40.0, 0.7],
            [5e6, 0.1, 1e4, 0.0],
            [0.0, 0.0, 1e-5, 0.0],
        ] {
            let square_sum: f64 = pdf.iter().map(|q| q * q).sum();
            let weights: DVec3 = pdf
                .iter()
                .map(|&own| power_estimate(f, own, square_sum) * own / f)
                .sum();
            assert!(
                (weights - DVec3::ONE).abs().max_element() < 1e-12,
                "{pdf:?}: {weights}"
            );
        }
        assert_eq!(power_estimate(f, 1e-13, 1e-26), DVec3::ZERO);
    }
}
