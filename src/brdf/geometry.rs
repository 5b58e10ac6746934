//! Masking-shadowing terms. The bake and the shader must use the same one
//! (docs/design/model.md, "Single scattering"), so each variant is one value of
//! [`Geometry`].

use super::{alpha_from_roughness, DIV_EPSILON};

/// Which masking-shadowing term the model uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Geometry {
    /// Schlick-GGX with `k = roughness^2 / 2` (Karis 2013, UE4's IBL choice; the
    /// homework's lut-gen), separable.
    #[default]
    Schlick,
    /// Exact separable Smith G1 for GGX (Walter et al. 2007, eq. 34).
    Smith,
    /// Height-correlated Smith (Heitz 2014, "Understanding the Masking-Shadowing Function
    /// in Microfacet-Based BRDFs", eq. 99).
    SmithCorrelated,
}

impl Geometry {
    /// Every variant, in a fixed order (tests and benchmarks loop over it).
    pub const ALL: [Geometry; 3] = [
        Geometry::Schlick,
        Geometry::Smith,
        Geometry::SmithCorrelated,
    ];

    /// The name used on the command line and in files.
    pub fn name(self) -> &'static str {
        match self {
            Geometry::Schlick => "schlick",
            Geometry::Smith => "smith",
            Geometry::SmithCorrelated => "smith-correlated",
        }
    }

    /// `G(mu_o, mu_i)` for this variant at `roughness` (clamped like everywhere else).
    pub(crate) fn g(self, mu_o: f64, mu_i: f64, roughness: f64) -> f64 {
        match self {
            Geometry::Schlick => g_schlick(mu_o, mu_i, roughness),
            Geometry::Smith => g_smith(mu_o, mu_i, roughness),
            Geometry::SmithCorrelated => g_smith_correlated(mu_o, mu_i, roughness),
        }
    }
}

/// Schlick-GGX G1 (Schlick 1994, eq. 19, with Karis 2013's `k = alpha / 2`):
/// `G1(c) = c / (c (1 - k) + k)`.
pub(crate) fn g1_schlick(c: f64, k: f64) -> f64 {
    let c = c.max(0.0);
    c / (c * (1.0 - k) + k).max(DIV_EPSILON)
}

/// Separable Schlick-GGX: `G = G1(mu_o) G1(mu_i)`, `k = roughness^2 / 2`.
pub(crate) fn g_schlick(mu_o: f64, mu_i: f64, roughness: f64) -> f64 {
    let k = alpha_from_roughness(roughness) / 2.0;
    g1_schlick(mu_o, k) * g1_schlick(mu_i, k)
}

/// Smith's Lambda for GGX (Heitz 2014, eq. 72): `(-1 + sqrt(1 + alpha^2 tan^2)) / 2`,
/// written as `alpha^2 tan^2 / (2 (1 + sqrt(1 + alpha^2 tan^2)))` to avoid cancellation
/// when `alpha tan` is small, with `sin^2 = (1 - c)(1 + c)` (exact `1 - c` near the
/// normal, as in [`super::d_ggx`]). `c = 0` gives +infinity (fully masked).
pub(crate) fn lambda_smith(c: f64, alpha: f64) -> f64 {
    let c = c.clamp(0.0, 1.0);
    let c2 = c * c;
    if c2 <= 0.0 {
        return f64::INFINITY;
    }
    let a2t2 = alpha * alpha * ((1.0 - c) * (1.0 + c)) / c2;
    a2t2 / (2.0 * (1.0 + (1.0 + a2t2).sqrt()))
}

/// Exact Smith G1 for GGX (Walter et al. 2007, eq. 34): `2 / (1 + sqrt(1 + alpha^2 tan^2))`,
/// written as `2c / (c + sqrt(c^2 + alpha^2 (1 - c^2)))`, which is finite at `c = 0`.
pub(crate) fn g1_smith(c: f64, alpha: f64) -> f64 {
    let c = c.clamp(0.0, 1.0);
    let root = (c * c + alpha * alpha * (1.0 - c * c)).sqrt();
    2.0 * c / (c + root).max(DIV_EPSILON)
}

/// Separable Smith: `G = G1(mu_o) G1(mu_i)`.
pub(crate) fn g_smith(mu_o: f64, mu_i: f64, roughness: f64) -> f64 {
    let alpha = alpha_from_roughness(roughness);
    g1_smith(mu_o, alpha) * g1_smith(mu_i, alpha)
}

/// Height-correlated Smith (Heitz 2014, eq. 99): `G = 1 / (1 + Lambda(mu_o) + Lambda(mu_i))`.
pub(crate) fn g_smith_correlated(mu_o: f64, mu_i: f64, roughness: f64) -> f64 {
    let alpha = alpha_from_roughness(roughness);
    1.0 / (1.0 + lambda_smith(mu_o, alpha) + lambda_smith(mu_i, alpha))
}

crate::named_enum!(Geometry, "geometry term");
