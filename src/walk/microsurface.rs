//! The GGX microsurface that the random walk travels on (Heitz, Hanika, d'Eon and
//! Dachsbacher 2016, "Multiple-Scattering Microfacet BSDFs with the Smith Model"): GGX
//! slopes, Smith's uncorrelated-heights-and-normals assumption, and a
//! height distribution that enters only through its CDF `C1(h)`.
//!
//! The walk keeps `c = C1(h)` in `[0, 1]` instead of the height itself: the paper shows the
//! result does not depend on the height distribution, and with `c` the formulas need no
//! `C1` or `C1^-1` (`c = 1` is above the surface). Directions are unit vectors with the
//! macro normal +z; a ray travels along `dir` (`dir.z < 0` goes down).

use glam::DVec3;

use crate::brdf::{
    alpha_from_roughness, d_ggx, d_ggx_aniso, lambda_smith, lambda_smith_aniso, DIV_EPSILON,
};

/// A GGX microsurface of one roughness, isotropic or anisotropic: the stretch of Heitz et
/// al. 2016 (section 4), `alpha` along the local `x` (the tangent) and `alpha_b` along `y`.
#[derive(Clone, Copy, Debug)]
pub struct Microsurface {
    /// GGX `alpha` (`roughness^2`, clamped); along `x` (`alpha_t`) when anisotropic.
    pub alpha: f64,
    /// GGX `alpha` along `y` (`alpha_b`); equal to `alpha` on an isotropic surface.
    pub alpha_b: f64,
}

impl Microsurface {
    /// The surface of `roughness` (clamped like everywhere else; `alpha = roughness^2`).
    pub fn new(roughness: f64) -> Self {
        let alpha = alpha_from_roughness(roughness);
        Self {
            alpha,
            alpha_b: alpha,
        }
    }

    /// The anisotropic surface of `alpha_t` along `x` and `alpha_b` along `y`
    /// (`brdf::anisotropic_alphas`). With equal alphas it walks through the anisotropic
    /// formulas all the same (the law "anisotropy 0 is the isotropic walk" compares them).
    pub(crate) fn anisotropic(alpha_t: f64, alpha_b: f64) -> Self {
        Self {
            alpha: alpha_t,
            alpha_b,
        }
    }

    /// Whether the surface takes the isotropic formulas (equal alphas).
    fn isotropic(&self) -> bool {
        self.alpha == self.alpha_b
    }

    /// Smith's Lambda for the direction `w`, signed as Heitz et al. 2016 extend it below
    /// the horizon: `Lambda(-w) = -1 - Lambda(w)`, so a downward direction has
    /// `Lambda <= -1`. `z = +-0` gives `+-infinity`.
    pub fn lambda(&self, w: DVec3) -> f64 {
        let z = w.z;
        let up = z >= 0.0 && !z.is_sign_negative();
        if self.isotropic() {
            return if up {
                lambda_smith(z, self.alpha)
            } else {
                -1.0 - lambda_smith(-z, self.alpha)
            };
        }
        if up {
            lambda_smith_aniso(w, self.alpha, self.alpha_b)
        } else {
            -1.0 - lambda_smith_aniso(-w, self.alpha, self.alpha_b)
        }
    }

    /// GGX's `D(h)` of the surface at unit local `h`.
    pub(crate) fn d(&self, h: DVec3) -> f64 {
        if self.isotropic() {
            d_ggx(h.z, self.alpha)
        } else {
            d_ggx_aniso(h, self.alpha, self.alpha_b)
        }
    }

    /// Probability that a ray leaving height `c = C1(h)` along upward `dir` escapes
    /// (Heitz et al. 2016, height-correlated masking): `G1 = c^Lambda`; 0 for a
    /// direction at or below the horizon.
    pub(crate) fn g1(&self, dir: DVec3, c: f64) -> f64 {
        if dir.z <= 0.0 {
            return 0.0;
        }
        c.powf(self.lambda(dir))
    }

    /// Height (as `C1`) of the next intersection of a ray from `c` along `dir`, given that it
    /// hits the surface, from `u` uniform in `[0, 1)`. Inverting the non-intersection
    /// probability `(c / c')^Lambda` (Heitz et al. 2016, the walk's height sampling): upward rays
    /// hit with probability `1 - G1`, so `u` is scaled into `[0, 1 - G1)`; downward rays
    /// always hit.
    pub(crate) fn next_height(&self, dir: DVec3, c: f64, u: f64) -> f64 {
        let lambda = self.lambda(dir);
        if dir.z > 0.0 {
            let escape = c.powf(lambda);
            let v = u * (1.0 - escape);
            (c / (1.0 - v).powf(1.0 / lambda)).min(1.0)
        } else {
            // lambda <= -1: the exponent -1/lambda is in (0, 1].
            c * (1.0 - u).powf(-1.0 / lambda)
        }
    }

    /// Projected area of the microsurface seen along `w` (either side of the horizon):
    /// `(1 + Lambda(w)) w.z = (w.z + sqrt(w.z^2 + alpha^2 (1 - w.z^2))) / 2` (Heitz 2014,
    /// "Understanding the Masking-Shadowing Function": projected area under Smith); the
    /// anisotropic surface's `alpha^2 (1 - z^2)` is `alpha_t^2 w_x^2 + alpha_b^2 w_y^2`.
    pub(crate) fn projected_area(&self, w: DVec3) -> f64 {
        let z = w.z.clamp(-1.0, 1.0);
        if self.isotropic() {
            return 0.5 * (z + (z * z + self.alpha * self.alpha * (1.0 - z * z)).sqrt());
        }
        let (x, y) = (self.alpha * w.x, self.alpha_b * w.y);
        0.5 * (z + (z * z + x * x + y * y).sqrt())
    }

    /// The conductor's phase function without its Fresnel factor (Heitz et al. 2016, the
    /// microflake-like phase function of a reflecting microsurface): `p(wi, wo) = D_wi(h) / (4 wi.h) = D(h) / (4 A(wi))`, `h = normalize(wi + wo)`,
    /// where `wi` points back along the arriving ray. Returns `(p, wi.h)`; `p = 0` where
    /// `h` faces down or away from `wi`.
    pub fn phase(&self, wi: DVec3, wo: DVec3) -> (f64, f64) {
        let sum = wi + wo;
        let len = sum.length();
        if len <= DIV_EPSILON {
            return (0.0, 0.0);
        }
        let h = sum / len;
        let cos = wi.dot(h);
        if h.z <= 0.0 || cos <= 0.0 {
            return (0.0, 0.0);
        }
        let area = self.projected_area(wi).max(DIV_EPSILON);
        (self.d(h) / (4.0 * area), cos)
    }

    /// A microfacet normal drawn from the distribution of normals visible from `wi`
    /// (Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4)): stretch
    /// to `alpha = 1`, draw a uniform point on the disk, warp it onto the projected visible
    /// hemisphere (`s = (1 + z) / 2`), lift it and unstretch. Valid for `wi` on either side
    /// of the horizon (the visible region is then the disk minus a half ellipse).
    pub(crate) fn sample_visible_normal(&self, wi: DVec3, u1: f64, u2: f64) -> DVec3 {
        let r = u1.sqrt();
        let (s, c) = (std::f64::consts::TAU * u2).sin_cos();
        crate::brdf::visible_normal_aniso((self.alpha, self.alpha_b), wi, r * c, r * s)
    }
}

/// Mirror reflection of the ray direction `dir` about the microfacet normal `m`.
pub(crate) fn reflect(dir: DVec3, m: DVec3) -> DVec3 {
    dir - 2.0 * dir.dot(m) * m
}
