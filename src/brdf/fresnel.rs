//! Fresnel reflectance and its hemispherical average.

/// Schlick's approximation (Schlick 1994, "An Inexpensive BRDF Model for Physically-based
/// Rendering", eq. 15): `F = F0 + (1 - F0) (1 - cos)^5`, `cos = v.h`, clamped to [0, 1].
pub fn f_schlick(f0: f64, cos_theta: f64) -> f64 {
    let m = (1.0 - cos_theta.clamp(0.0, 1.0)).clamp(0.0, 1.0);
    let m2 = m * m;
    f0 + (1.0 - f0) * m2 * m2 * m
}

/// Cosine-weighted average of Schlick's Fresnel, `F_avg = 2 int_0^1 F(mu) mu dmu`, in
/// closed form: `2 int_0^1 (1 - mu)^5 mu dmu = 2 B(2, 6) = 1/21`, so
/// `F_avg = F0 + (1 - F0) / 21` (Kulla & Conty 2017, slide 26 gives the same integral).
pub fn f_avg_schlick(f0: f64) -> f64 {
    f0 + (1.0 - f0) / 21.0
}

/// The edge tint the GAMES202 homework passes to its F_avg fit ("copper"), per channel.
pub const GAMES202_EDGE_TINT: [f64; 3] = [0.827, 0.792, 0.678];

/// The homework's F_avg: Kulla & Conty 2017 (slide 26)'s polynomial fit of the average
/// Fresnel of Gulbrandsen 2014's artist-friendly conductor, in reflectivity `r` and edge
/// tint `g` (one channel). It describes a different Fresnel from the Schlick F of the
/// single-scattering term; the `games202` preset keeps it to reproduce the homework.
pub fn f_avg_games202(r: f64, g: f64) -> f64 {
    0.087237 + 0.0230685 * g - 0.0864902 * g * g + 0.0774594 * g * g * g + 0.782654 * r
        - 0.136432 * r * r
        + 0.278708 * r * r * r
        + 0.19744 * g * r
        + 0.0360605 * g * g * r
        - 0.2586 * g * r * r
}

/// The exact unpolarised Fresnel reflectance of a dielectric interface (Walter, Marschner,
/// Li and Torrance 2007, "Microfacet Models for Refraction through Rough Surfaces", eq. 22),
/// for light arriving at cosine `cos_theta` to the (micro)normal from the side of index
/// `n_i`, with `eta = n_t / n_i` the relative index of the other side: `g^2 = eta^2 - 1 +
/// c^2`; `F = (g - c)^2 / (2 (g + c)^2) (1 + ((c (g + c) - 1) / (c (g - c) + 1))^2)`, and 1
/// past the critical angle (`g^2 < 0`, total internal reflection).
pub(crate) fn fresnel_dielectric(cos_theta: f64, eta: f64) -> f64 {
    let c = cos_theta.abs().min(1.0);
    let g2 = eta * eta - 1.0 + c * c;
    if g2 < 0.0 {
        return 1.0;
    }
    let g = g2.sqrt();
    let a = (g - c) / (g + c).max(super::DIV_EPSILON);
    let b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0).max(super::DIV_EPSILON);
    (0.5 * a * a * (1.0 + b * b)).clamp(0.0, 1.0)
}

/// The normal-incidence reflectance of a dielectric of relative index `eta`,
/// `F0 = ((eta - 1) / (eta + 1))^2` (glTF's `KHR_materials_ior`: 0.04 at 1.5); Schlick's
/// `F0` for that interface.
pub fn f0_from_ior(eta: f64) -> f64 {
    let r = (eta - 1.0) / (eta + 1.0).max(super::DIV_EPSILON);
    r * r
}

/// Intervals of [`f_avg_dielectric`]'s composite Simpson rule (even): the integrands are
/// smooth on the interval, so the error is below 1e-12.
const F_AVG_INTERVALS: usize = 1024;

/// The cosine-weighted hemispherical average of [`fresnel_dielectric`] seen from the side of
/// index `n_i`, `F_avg = 2 int_0^1 F(mu, eta) mu dmu`: 0.09178 at `eta = 1.5` (Kulla and
/// Conty 2017's fit, `(eta - 1) / (4.08567 + 1.00071 eta)`, gives 0.0895 there). For
/// `eta >= 1` the integrand is smooth in `mu`; for `eta < 1`, F is 1 below the critical
/// cosine `mu_c = sqrt(1 - eta^2)` (that part is `mu_c^2`) and has a square-root kink
/// there, which the substitution `g = sqrt(eta^2 - 1 + mu^2)` (`mu dmu = g dg`) removes.
pub(crate) fn f_avg_dielectric(eta: f64) -> f64 {
    if eta >= 1.0 {
        simpson(|mu| 2.0 * fresnel_dielectric(mu, eta) * mu, 0.0, 1.0)
    } else {
        let mu_c2 = 1.0 - eta * eta;
        let outside = |g: f64| 2.0 * fresnel_dielectric((g * g + mu_c2).sqrt(), eta) * g;
        mu_c2 + simpson(outside, 0.0, eta.max(0.0))
    }
}

/// Composite Simpson's rule of `f` over `[a, b]` with [`F_AVG_INTERVALS`] intervals.
fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    let n = F_AVG_INTERVALS;
    let h = (b - a) / n as f64;
    let inner: f64 = (1..n)
        .map(|k| f(a + k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 })
        .sum();
    h / 3.0 * (f(a) + inner + f(b))
}

/// The hemispherical average of the reflectance inside a medium of relative index `eta`
/// (over its outside) for light arriving from within, total internal reflection included:
/// `1 - (1 - F_avg(eta)) / eta^2` (reciprocity across the interface: radiance crossing it
/// is divided by `eta^2`), 0.5963 at `eta = 1.5`. Equals [`f_avg_dielectric`]`(1 / eta)`.
#[cfg(test)]
pub fn f_avg_inside(eta: f64) -> f64 {
    1.0 - (1.0 - f_avg_dielectric(eta)) / (eta * eta).max(super::DIV_EPSILON)
}

/// Which Fresnel a dielectric coating uses: the preset's choice (`accurate`: the exact
/// one; `games202`: Schlick's of the same index).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum DielectricFresnel {
    /// [`fresnel_dielectric`].
    Exact,
    /// [`f_schlick`] with `F0 = f0_from_ior(eta)`.
    Schlick,
}

/// The coating's Fresnel at cosine `cos_theta` for relative index `eta`, in `form`.
pub(crate) fn f_dielectric(cos_theta: f64, eta: f64, form: DielectricFresnel) -> f64 {
    match form {
        DielectricFresnel::Exact => fresnel_dielectric(cos_theta, eta),
        DielectricFresnel::Schlick => f_schlick(f0_from_ior(eta), cos_theta),
    }
}
