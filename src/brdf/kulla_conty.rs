//! The Kulla-Conty multiple-scattering lobe and its Fresnel scale.

use std::f64::consts::PI;

use super::{f_avg_games202, f_avg_schlick, DIV_EPSILON};

/// Which form of the Fresnel scale `f_add` a preset uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FAvgForm {
    /// `F_avg^2 E_avg / (1 - F_avg (1 - E_avg))`: the sum over bounces k >= 1
    /// (docs/design/model.md, "Where F_avg^2 comes from"; Filament and Blender Cycles use
    /// it).
    Accurate,
    /// The homework's `F_avg E_avg / (1 - F_avg (1 - E_avg))`: brighter by `1 / F_avg`.
    Games202,
}

/// The energy-compensation lobe (Kulla & Conty 2017, slide 18):
/// `f_ms = (1 - E(mu_o)) (1 - E(mu_i)) / (pi (1 - E_avg))`.
/// With `F = 1` its cosine-weighted integral over `mu_i` is exactly `1 - E(mu_o)`.
///
/// The arguments are the energies single scattering misses, `loss = 1 - E`, as the tables
/// store them (at low roughness `1 - E_avg` falls to 1e-6 with Smith G, where `1 - E` formed
/// from an f32 E would keep a few per cent of it), and the normalisation
/// [`f_ms_norm`]`(1 - E_avg)`, constant over a ball: the shader receives it per ball rather
/// than dividing per pixel.
pub fn f_ms(loss_o: f64, loss_i: f64, norm: f64) -> f64 {
    loss_o * loss_i * norm
}

/// The lobe's normalisation `1 / (pi (1 - E_avg))` from `loss_avg = 1 - E_avg` (the
/// denominator of [`f_ms`]).
pub fn f_ms_norm(loss_avg: f64) -> f64 {
    1.0 / (PI * loss_avg).max(DIV_EPSILON)
}

/// Fresnel scale of the lobe, summed over all bounces after the first (Kulla & Conty 2017,
/// slide 26, with the square that the geometric series gives; docs/design/model.md, "Where
/// F_avg^2 comes from"): `F_avg^2 E_avg / (1 - F_avg (1 - E_avg))`.
pub fn f_add_accurate(f_avg: f64, e_avg: f64) -> f64 {
    f_avg * f_avg * e_avg / f_add_denominator(f_avg, e_avg)
}

/// The homework's Fresnel scale `F_avg E_avg / (1 - F_avg (1 - E_avg))` (no square).
pub fn f_add_games202(f_avg: f64, e_avg: f64) -> f64 {
    f_avg * e_avg / f_add_denominator(f_avg, e_avg)
}

/// `1 - F_avg (1 - E_avg)`, written `(1 - F_avg) + F_avg E_avg`: a sum of two non-negative
/// terms for `F_avg`, `E_avg` in [0, 1], so it never cancels. The direct form loses all
/// digits as `F_avg -> 1` with small `E_avg` (measured in f32 before: 1.7e-5 absolute error
/// in `f_add`); it reaches 0 only at `F_avg = 1, E_avg = 0`, where the guard makes 0/0 a 0.
pub(crate) fn f_add_denominator(f_avg: f64, e_avg: f64) -> f64 {
    ((1.0 - f_avg) + f_avg * e_avg).max(DIV_EPSILON)
}

/// The Fresnel scale `f_add` of one colour channel as a preset computes it
/// (docs/design/model.md, "Presets"; Kulla & Conty 2017, slide 26): `Accurate` takes
/// `F_avg` from Schlick's closed form for `f0` and sums the bounces with the square;
/// `Games202` takes the homework's polynomial `F_avg` for `f0` and the channel's
/// `edge_tint`, without the square. The renderers (`shaders/lighting.wgsl`, `src/cpu`) and
/// the truth study call this one function, so they compare the same model.
pub fn f_add_preset(form: FAvgForm, f0: f64, edge_tint: f64, e_avg: f64) -> f64 {
    match form {
        FAvgForm::Accurate => f_add_accurate(f_avg_schlick(f0), e_avg),
        FAvgForm::Games202 => f_add_games202(f_avg_games202(f0, edge_tint), e_avg),
    }
}
