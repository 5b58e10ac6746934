//! A ball's clear coat (docs/design/coat.md): a rough dielectric layer of its own
//! roughness and index over the ball's whole material, and the forms that weight the base
//! under it ([`CoatForm`]). What is constant over a ball is formed here once, for both
//! renderers ([`ClearcoatConstants`]: the GPU's `Ball.clearcoat*` members, `cpu::clearcoat`).

use glam::DVec3;

use super::{Ball, CoatingConstants, Layering, Scene};
use crate::brdf::{
    base_albedo_physical, clearcoat_inside_scale, f_add_preset, f_avg_schlick, DielectricFresnel,
    GAMES202_EDGE_TINT,
};
use crate::environment::IblTerm;
use crate::lut::{CoatingKey, CoatingRows, TableSet};

/// The coat's index of refraction when none is given: glTF's and OpenPBR's 1.5.
pub const DEFAULT_CLEARCOAT_IOR: f64 = 1.5;

/// A clear coat: `weight` in `[0, 1]` (OpenPBR's `coat_weight`, glTF's `clearcoat`: a
/// share `1 - weight` of the surface is bare), the coat's `roughness` in `[0, 1]` and its
/// index `ior` (in [`super::IOR_RANGE`]). Weight 0 (the default) is no coat.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClearCoat {
    /// How much of the surface the coat covers, in `[0, 1]`.
    pub weight: f64,
    /// The coat's own roughness, in `[0, 1]` (clamped like every roughness when shading).
    pub roughness: f64,
    /// The coat's index of refraction relative to the outside.
    pub ior: f64,
}

impl Default for ClearCoat {
    /// No coat: weight 0, roughness 0 and index 1.5 (glTF's `KHR_materials_clearcoat`
    /// defaults, OpenPBR's).
    fn default() -> Self {
        ClearCoat::NONE
    }
}

impl ClearCoat {
    /// No coat.
    pub const NONE: ClearCoat = ClearCoat {
        weight: 0.0,
        roughness: 0.0,
        ior: DEFAULT_CLEARCOAT_IOR,
    };

    /// Whether there is a coat at all (`weight > 0`).
    pub fn is_on(&self) -> bool {
        self.weight > 0.0
    }
}

/// How the base is weighted under a clear coat (docs/design/coat.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum CoatForm {
    /// The coat's own GGX lobe with its Kulla-Conty term, the base seen through it with the
    /// transmission `1 - E_c` both ways and the internal reflections summed (Weidlich and
    /// Wilkie 2007; Kulla and Conty 2017): energy-conserving.
    #[default]
    Physical,
    /// Filament's: the coat's single scattering (Schlick's F, no term) and the base times
    /// `1 - weight F_c(v.h)`.
    Filament,
    /// glTF's `KHR_materials_clearcoat`: the base and the coat's Fresnel-free lobe mixed by
    /// `weight F_c(n.v)` (Schlick's F).
    Gltf,
}

impl CoatForm {
    /// Every form, in the order the help and the charts list them.
    pub const ALL: [CoatForm; 3] = [CoatForm::Physical, CoatForm::Filament, CoatForm::Gltf];

    /// The name the scene file and the command line use.
    pub fn name(self) -> &'static str {
        match self {
            CoatForm::Physical => "physical",
            CoatForm::Filament => "filament",
            CoatForm::Gltf => "gltf",
        }
    }

    /// The Fresnel the coat's lobe takes under this form: the preset's for the physical
    /// form, Schlick's (of the coat's `F0`) for the engines'.
    pub fn fresnel(self, preset: DielectricFresnel) -> DielectricFresnel {
        match self {
            CoatForm::Physical => preset,
            CoatForm::Filament | CoatForm::Gltf => DielectricFresnel::Schlick,
        }
    }
}

crate::named_enum!(CoatForm, "coat form");

impl Scene {
    /// The coating row ball `b`'s clear coat reads (its roughness, index, the form's
    /// Fresnel and the scene's G); `None` without a coat.
    pub fn clearcoat_key(&self, b: &Ball) -> Option<CoatingKey> {
        let c = b.material.clearcoat;
        c.is_on().then(|| {
            CoatingKey::new(
                c.roughness,
                c.ior,
                self.coat_form.fresnel(self.preset.dielectric_fresnel()),
                self.effective_geometry(),
            )
        })
    }

    /// Every coating row ball `b` reads: its dielectric's and its clear coat's.
    pub fn ball_coating_keys(&self, b: &Ball) -> impl Iterator<Item = CoatingKey> {
        self.coating_key(b).into_iter().chain(self.clearcoat_key(b))
    }
}

/// What a ball's clear coat takes that is constant over the ball, formed once per ball on
/// the CPU (the GPU's `Ball.clearcoat*`; `cpu::clearcoat`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClearcoatConstants {
    /// The coat's weight.
    pub weight: f64,
    /// The coat's roughness.
    pub roughness: f64,
    /// The coat's index.
    pub eta: f64,
    /// The coat's Kulla-Conty `f_add` (0 without the ball's term and under the engines'
    /// forms).
    pub f_add: f64,
    /// `f_ms_norm` of the coat's `1 - E_avg` (0 where `f_add` is).
    pub ms_norm: f64,
    /// `E_c_avg`, the cosine-weighted average of the coat's specular albedo (its row and
    /// its term) as the shader reads it.
    pub e_avg: f64,
    /// `1 / (eta^2 (1 - A_avg F_in))` per channel ([`clearcoat_inside_scale`]): the
    /// internal reflections under the physical form (1 under the others).
    pub inside: DVec3,
    /// The form.
    pub form: CoatForm,
    /// The coat's Fresnel ([`CoatForm::fresnel`]).
    pub fresnel: DielectricFresnel,
}

impl ClearcoatConstants {
    /// Ball `b`'s coat constants, from its row of `rows` and E read from `e`; `None`
    /// without a coat.
    pub fn of_ball(scene: &Scene, b: &Ball, e: &TableSet, rows: &CoatingRows) -> Option<Self> {
        let key = scene.clearcoat_key(b)?;
        let row = rows.row(&key).expect("every clear coat's row is baked");
        let coat = b.material.clearcoat;
        let form = scene.coat_form;
        let physical = form == CoatForm::Physical;
        let ms = if physical && b.model.has_term() {
            1.0
        } else {
            0.0
        };
        let r = coat.roughness as f32;
        let loss_avg = f64::from(e.lut_loss_avg(r));
        let loss = |mu: f64| f64::from(e.lut_loss(mu as f32, r));
        let c = CoatingConstants::new(
            coat.ior,
            row,
            scene.preset,
            (ms, IblTerm::KullaConty),
            1.0 - loss_avg,
            loss,
        );
        let inside = if physical {
            let a_avg = base_average_albedo(scene, b, e, rows);
            let k = |a: f64| clearcoat_inside_scale(a, c.e_spec_avg, coat.ior);
            DVec3::new(k(a_avg.x), k(a_avg.y), k(a_avg.z))
        } else {
            DVec3::ONE
        };
        Some(ClearcoatConstants {
            weight: coat.weight,
            roughness: coat.roughness,
            eta: coat.ior,
            f_add: c.f_add,
            ms_norm: if ms > 0.0 {
                crate::brdf::f_ms_norm(loss_avg)
            } else {
                0.0
            },
            e_avg: c.e_spec_avg,
            inside,
            form,
            fresnel: form.fresnel(scene.preset.dielectric_fresnel()),
        })
    }
}

/// The cosine-weighted average of ball `b`'s own directional albedo under uniform light
/// (without its coat), per channel, as the renderers' uniform-light shading gives it: the
/// metal's `F_avg E_avg + f_add (1 - E_avg)` and the dielectric's `E_spec_avg` plus its
/// base's average under the scene's layering form, mixed by `metallic`.
pub fn base_average_albedo(scene: &Scene, b: &Ball, e: &TableSet, rows: &CoatingRows) -> DVec3 {
    let ms = if b.model.has_term() { 1.0 } else { 0.0 };
    let m = &b.material;
    let e_avg = 1.0 - f64::from(e.lut_loss_avg(b.roughness as f32));
    let metal = if m.has_metal() {
        let f0 = m.f0.to_array();
        let tint = GAMES202_EDGE_TINT;
        let c = |k: usize| {
            let f_add = f_add_preset(scene.preset.f_avg_form(), f0[k], tint[k], e_avg);
            f_avg_schlick(f0[k]) * e_avg + ms * f_add * (1.0 - e_avg)
        };
        DVec3::new(c(0), c(1), c(2))
    } else {
        DVec3::ZERO
    };
    let dielectric = match CoatingConstants::of_ball(scene, b, e, rows) {
        Some(c) => {
            let row = scene.coating_key(b).and_then(|k| rows.row(&k));
            let albedo = super::base_albedo(scene, b, e, row, Some(&c));
            let base = |a: f64| match scene.layering {
                Layering::Constant | Layering::Gltf => a * (1.0 - c.f_avg),
                Layering::ViewOnly | Layering::Reciprocal => a * (1.0 - c.e_spec_avg),
                Layering::Physical => base_albedo_physical(a, c.e_spec_avg, c.e_spec_avg, c.eta),
            };
            DVec3::splat(c.e_spec_avg) + DVec3::new(base(albedo.x), base(albedo.y), base(albedo.z))
        }
        None => DVec3::ZERO,
    };
    m.metallic * metal + (1.0 - m.metallic) * dielectric
}
