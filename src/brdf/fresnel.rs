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
