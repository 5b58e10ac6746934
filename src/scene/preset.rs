//! Presets: which Fresnel average and which `f_add` form the multiple-scattering term uses
//! (docs/design/model.md, "Presets").

use crate::brdf::{DielectricFresnel, FAvgForm, Geometry};
use crate::display::{ToneMap, Transfer};

/// A named choice of `F_avg`, `f_add` and (for `games202`) G.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Preset {
    /// One consistent Fresnel: Schlick with `F0`, `F_avg = f_avg_schlick(F0)` per channel,
    /// `f_add_accurate` (with the square); G from `--geometry` (default smith-correlated:
    /// each part chosen by `shadeballs-lab truth`, docs/truth.md "How close to the truth").
    #[default]
    Accurate,
    /// The GAMES202 homework: schlick G, `F_avg = f_avg_games202(F0, GAMES202_EDGE_TINT)`
    /// per channel, `f_add_games202` (without the square).
    Games202,
}

impl Preset {
    /// Every preset, in a fixed order.
    pub(crate) const ALL: [Preset; 2] = [Preset::Accurate, Preset::Games202];

    /// The name used on the command line and in scene files.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Preset::Accurate => "accurate",
            Preset::Games202 => "games202",
        }
    }

    /// The form of `F_avg` and `f_add` this preset uses.
    pub fn f_avg_form(self) -> FAvgForm {
        match self {
            Preset::Accurate => FAvgForm::Accurate,
            Preset::Games202 => FAvgForm::Games202,
        }
    }

    /// The Fresnel of a dielectric coating: the exact one (`accurate`) or Schlick's of the
    /// same index (`games202`).
    pub(crate) fn dielectric_fresnel(self) -> DielectricFresnel {
        match self {
            Preset::Accurate => DielectricFresnel::Exact,
            Preset::Games202 => DielectricFresnel::Schlick,
        }
    }

    /// The tone mapper of a scene that names none. `accurate`: Khronos PBR Neutral, the
    /// curve made for material preview (a base colour shows as itself up to its start of
    /// compression, so the balls' albedo reads true, as in three.js's and model-viewer's
    /// neutral mode); `games202`: Reinhard, the homework's.
    pub fn tone_map(self) -> ToneMap {
        match self {
            Preset::Accurate => ToneMap::KhronosNeutral,
            Preset::Games202 => ToneMap::Reinhard,
        }
    }

    /// The transfer curve of a scene that names none: `accurate`, the sRGB curve (what a
    /// display decodes); `games202`, gamma 1/2.2, the homework's.
    pub fn transfer(self) -> Transfer {
        match self {
            Preset::Accurate => Transfer::Srgb,
            Preset::Games202 => Transfer::Gamma22,
        }
    }

    /// The G this preset forces, if any.
    pub(crate) fn geometry(self) -> Option<Geometry> {
        match self {
            Preset::Accurate => None,
            Preset::Games202 => Some(Geometry::Schlick),
        }
    }
}

crate::named_enum!(Preset, "preset");
