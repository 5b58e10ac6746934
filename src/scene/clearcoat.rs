//! A ball's clear coat (docs/design/coat.md): a rough dielectric layer of its own
//! roughness and index over the ball's whole material, and the forms that weight the base
//! under it ([`CoatForm`]). What is constant over a ball is formed once, for both renderers,
//! in `prepared::clearcoat`.

use super::{Ball, Scene};
use crate::brdf::DielectricFresnel;
use crate::lut::CoatingKey;

/// The coat's index of refraction when none is given: glTF's and OpenPBR's 1.5.
pub(crate) const DEFAULT_CLEARCOAT_IOR: f64 = 1.5;

/// A clear coat: `weight` in `[0, 1]` (OpenPBR's `coat_weight`, glTF's `clearcoat`: a
/// share `1 - weight` of the surface is bare), the coat's `roughness` in `[0, 1]` and its
/// index `ior` (in `super::IOR_RANGE`). Weight 0 (the default) is no coat.
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
    pub(crate) const NONE: ClearCoat = ClearCoat {
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
    pub(crate) fn name(self) -> &'static str {
        match self {
            CoatForm::Physical => "physical",
            CoatForm::Filament => "filament",
            CoatForm::Gltf => "gltf",
        }
    }

    /// The Fresnel the coat's lobe takes under this form: the preset's for the physical
    /// form, Schlick's (of the coat's `F0`) for the engines'.
    pub(crate) fn fresnel(self, preset: DielectricFresnel) -> DielectricFresnel {
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
    pub(crate) fn clearcoat_key(&self, b: &Ball) -> Option<CoatingKey> {
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
