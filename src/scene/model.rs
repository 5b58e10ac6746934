//! Which BRDF model a ball is shaded with.

use crate::environment::IblTerm;

/// A ball's BRDF model: the single-scattering lobe alone, one of the real-time
/// multiple-scattering terms added to it, or the truth they approximate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Model {
    /// The single-scattering Cook-Torrance lobe alone (energy lost at high roughness).
    None,
    /// Kulla & Conty 2017: the lobe `f_add f_ms`, `f_add` of the scene's preset.
    KullaConty,
    /// Turquin 2019: the single-scattering lobe scaled by `1 + F0 (1 / E - 1)`.
    Turquin,
    /// Fdez-Aguera 2019: a Lambertian lobe of the multiple-scattering energy.
    FdezAguera,
    /// The random walk of Heitz et al. 2016: the exact multiple scattering of the
    /// microsurface (rendered by `--backend truth`, or path traced on the GPU).
    Truth,
}

impl Model {
    /// Every model, in the order the help and the charts list them.
    pub(crate) const ALL: [Model; 5] = [
        Model::None,
        Model::KullaConty,
        Model::Turquin,
        Model::FdezAguera,
        Model::Truth,
    ];

    /// The name the scene file and the command line use.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Model::None => "none",
            Model::KullaConty => "kulla-conty",
            Model::Turquin => "turquin",
            Model::FdezAguera => "fdez-aguera",
            Model::Truth => "truth",
        }
    }

    /// The real-time multiple-scattering term the model adds; `None` for `none` and
    /// `truth`.
    pub(crate) fn term(self) -> Option<IblTerm> {
        match self {
            Model::KullaConty => Some(IblTerm::KullaConty),
            Model::Turquin => Some(IblTerm::Turquin),
            Model::FdezAguera => Some(IblTerm::FdezAguera),
            Model::None | Model::Truth => None,
        }
    }

    /// Whether a real-time term is added (what `multiple_scattering = true` meant).
    pub fn has_term(self) -> bool {
        self.term().is_some()
    }

    /// The model of a real-time term.
    pub fn from_term(term: IblTerm) -> Model {
        match term {
            IblTerm::KullaConty => Model::KullaConty,
            IblTerm::Turquin => Model::Turquin,
            IblTerm::FdezAguera => Model::FdezAguera,
        }
    }
}

crate::named_enum!(Model, "model");
