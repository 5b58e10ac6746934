//! What a dielectric's `base_color` means (docs/interop.md, "Two readings of base
//! colour"): the colour a viewer sees (glTF's, OpenPBR's, Blender's Principled BSDF's
//! reading, the default) or the albedo of the substrate under the coating.
//!
//! The substrate the renderers shade and walk under the apparent reading is solved once per
//! ball when a scene is prepared (`prepared::substrate`).

/// What a dielectric's `base_color` (the [`Material::diffuse`](super::Material::diffuse)
/// of its balls) means.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum BaseReading {
    /// The albedo a viewer sees: the base's light through the coating averages to it
    /// (glTF, OpenPBR, Blender's Principled BSDF, the engines' charts).
    #[default]
    Apparent,
    /// The albedo of the Lambertian substrate under the coating (the design before issue
    /// 35's; darker than the colour, as a random walk through the coating shows it).
    Substrate,
}

impl BaseReading {
    /// Both readings, the default first.
    pub(crate) const ALL: [BaseReading; 2] = [BaseReading::Apparent, BaseReading::Substrate];

    /// The name the scene file (`base_reading`) and `--base-reading` use.
    pub(crate) fn name(self) -> &'static str {
        match self {
            BaseReading::Apparent => "apparent",
            BaseReading::Substrate => "substrate",
        }
    }
}

crate::named_enum!(BaseReading, "base reading");
