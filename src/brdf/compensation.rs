//! The multiple-scattering compensations other than Kulla-Conty's lobe, per channel
//! (`term_turquin` and `term_fdez_aguera` in `shaders/brdf.wgsl`).

use super::{f_avg_schlick, DIV_EPSILON};

/// Turquin 2019 ("Practical multiple scattering compensation for microfacet models"): the
/// single-scattering result `single` times `1 + F0 (1 / E - 1)`; returns the added part.
pub(crate) fn term_turquin(single: f64, f0: f64, e_o: f64) -> f64 {
    single * f0 * (1.0 / e_o.max(DIV_EPSILON) - 1.0)
}

/// Fdez-Aguera 2019 ("A Multiple-Scattering Microfacet Model for Real-Time Image-based
/// Lighting"): the multiple-scattering energy `FmsEms = FssEss F_avg Ems / (1 - Ems F_avg)`,
/// `Ems = 1 - E(mu_o)`, `F_avg = F0 + (1 - F0) / 21`; it reflects light as if diffuse.
pub(crate) fn term_fdez_aguera(fss_ess: f64, f0: f64, loss_o: f64) -> f64 {
    let f_avg = f_avg_schlick(f0);
    fss_ess * f_avg * loss_o / (1.0 - loss_o * f_avg).max(DIV_EPSILON)
}
