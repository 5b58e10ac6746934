//! The models the walk is compared with, per colour channel: Kulla-Conty as the presets
//! compute it (the renderer's own functions and tables), its variants, and two later
//! compensations. Everything here reads E through the tables the renderer bakes
//! (`lut::bake` with the default configuration), so the study measures what renders.

use shadeballs::brdf::{
    f_add_accurate, f_add_games202, f_avg_games202, f_avg_schlick, FAvgForm, Geometry,
};
use shadeballs::brdf::{f_add_preset, DIV_EPSILON};
use shadeballs::lut::{self, adaptive, BakeConfig, Tables};

/// The renderer's tables, one per geometry term (`Geometry::ALL` order).
pub struct ModelTables {
    tables: Vec<Tables>,
}

impl Default for ModelTables {
    fn default() -> Self {
        Self::new()
    }
}

impl ModelTables {
    /// Bakes the tables as the renderer does (default configuration, one per G).
    pub fn new() -> Self {
        let tables = Geometry::ALL
            .iter()
            .map(|&geometry| {
                lut::bake(&BakeConfig {
                    geometry,
                    ..Default::default()
                })
            })
            .collect();
        Self { tables }
    }

    fn of(&self, g: Geometry) -> &Tables {
        let k = Geometry::ALL.iter().position(|&x| x == g).unwrap_or(0);
        &self.tables[k]
    }

    /// `1 - E(mu, roughness)` as the shader reads it.
    pub fn loss(&self, g: Geometry, mu: f64, roughness: f64) -> f64 {
        self.of(g).lut_loss(mu as f32, roughness as f32) as f64
    }

    /// `1 - E_avg(roughness)` as the shader reads it.
    pub fn loss_avg(&self, g: Geometry, roughness: f64) -> f64 {
        self.of(g).lut_loss_avg(roughness as f32) as f64
    }

    /// `int f_ms mu_i dw_i / (1 - E(mu_o))` for the tables as read:
    /// `2 int_0^1 loss(mu) mu dmu / loss_avg` (1 when E_avg is consistent with E).
    pub fn ms_norm(&self, g: Geometry, roughness: f64) -> f64 {
        let avg = adaptive(
            &|mu: f64| 2.0 * self.loss(g, mu, roughness) * mu,
            0.0,
            1.0,
            1e-9,
        );
        avg / self.loss_avg(g, roughness).max(DIV_EPSILON)
    }
}

/// Where a Kulla-Conty variant takes `F_avg` from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FAvgSource {
    /// The exact cosine-weighted average of the channel's own Fresnel (for Schlick:
    /// `F0 + (1 - F0) / 21`): one consistent Fresnel.
    Own,
    /// Kulla & Conty 2017's polynomial fit for the Gulbrandsen conductor of the channel's
    /// (reflectivity, edge tint) pair (`f_avg_games202`).
    ConductorFit,
    /// Schlick's closed form `F0 + (1 - F0) / 21` with `F0` the channel's reflectivity,
    /// whatever its Fresnel (the `accurate` preset's F_avg).
    SchlickF0,
}

impl FAvgSource {
    pub fn name(self) -> &'static str {
        match self {
            FAvgSource::Own => "own-fresnel",
            FAvgSource::ConductorFit => "conductor-fit",
            FAvgSource::SchlickF0 => "schlick-f0",
        }
    }
}

/// A Kulla-Conty variant: its G, its F_avg and whether f_add has the square.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct KcParts {
    pub geometry: Geometry,
    pub f_avg: FAvgSource,
    pub form: FAvgForm,
}

/// One colour channel as the models see it.
#[derive(Clone, Copy, Debug)]
pub struct ChannelData {
    /// Reflectance at normal incidence (`F0`, or the conductor's `r`).
    pub f0: f64,
    /// The edge tint of the channel's artist-friendly pair.
    pub edge_tint: f64,
    /// Exact cosine-weighted average of the channel's Fresnel.
    pub f_avg: f64,
}

impl KcParts {
    /// The Fresnel scale of the lobe for `ch` and `E_avg`.
    pub fn f_add(self, ch: &ChannelData, e_avg: f64) -> f64 {
        let f_avg = match self.f_avg {
            FAvgSource::Own => ch.f_avg,
            FAvgSource::ConductorFit => f_avg_games202(ch.f0, ch.edge_tint),
            FAvgSource::SchlickF0 => f_avg_schlick(ch.f0),
        };
        match self.form {
            FAvgForm::Accurate => f_add_accurate(f_avg, e_avg),
            FAvgForm::Games202 => f_add_games202(f_avg, e_avg),
        }
    }
}

/// A preset's `f_add` for a channel, through the renderer's own `f_add_preset` (the
/// `games202` preset always uses the homework's copper edge tint, as the renderer does).
pub fn preset_f_add(form: FAvgForm, f0: f64, channel: usize, e_avg: f64) -> f64 {
    let tint = shadeballs::brdf::GAMES202_EDGE_TINT[channel.min(2)];
    f_add_preset(form, f0, tint, e_avg)
}

/// Directional albedo of a Kulla-Conty BRDF: single scattering `ss_f` plus
/// `f_add int f_ms mu_i dw_i = f_add (1 - E(mu_o)) ms_norm`.
pub fn kc_albedo(ss_f: f64, f_add: f64, loss_o: f64, ms_norm: f64) -> f64 {
    ss_f + f_add * loss_o * ms_norm
}

/// Turquin 2019 ("Practical multiple scattering compensation for microfacet models",
/// for conductors) scales the single-scattering lobe by
/// `1 + F0 (1 - E(mu_o)) / E(mu_o)`; its albedo is that factor times `ss_f`.
pub fn turquin_scale(f0: f64, e_o: f64) -> f64 {
    1.0 + f0 * (1.0 - e_o) / e_o.max(DIV_EPSILON)
}

/// Fdez-Aguera 2019 ("A Multiple-Scattering Microfacet Model for Real-Time Image-based
/// Lighting", JCGT 8(1)): the bounces after the first as a geometric series in
/// `F_avg (1 - E(mu_o))` started by the single-scattering albedo,
/// `ss_f + ss_f F_avg (1 - E) / (1 - F_avg (1 - E))`. An albedo model (for image-based
/// lighting): its lobe is taken as Lambertian in the incident direction.
pub fn fdez_aguera_albedo(ss_f: f64, f_avg: f64, e_o: f64) -> f64 {
    let loss = 1.0 - e_o;
    ss_f + ss_f * f_avg * loss / (1.0 - f_avg * loss).max(DIV_EPSILON)
}
