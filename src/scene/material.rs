//! A ball's material as engines have it (docs/design/materials.md): a metal and a
//! dielectric mixed by `metallic`, the dielectric a rough coating of index `ior` over a
//! Lambertian base, and the layering form that weights the base.

use glam::DVec3;

/// The index of refraction a dielectric gets when none is given: glTF's
/// `KHR_materials_ior` default, common plastics and glass (`F0 = 0.04`).
pub const DEFAULT_IOR: f64 = 1.5;

/// The range of indices a material may have: 1 (no interface) to 4 (above every common
/// dielectric: diamond is 2.42, silicon's real part about 4).
pub(crate) const IOR_RANGE: (f64, f64) = (1.0, 4.0);

/// A ball's material, resolved to linear values: `metallic` mixes the metal's shading
/// (specular only, `F0` coloured) and the dielectric's (a coating of index `ior` over a
/// base of colour `diffuse`), each with its own multiple-scattering term.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// How much of the ball is metal, in `[0, 1]` (glTF's and OpenPBR's `metallic`).
    pub metallic: f64,
    /// The metal's linear reflectance at normal incidence, per channel.
    pub f0: DVec3,
    /// The dielectric's base colour, linear: the albedo a viewer sees or the substrate's,
    /// as the scene's [`Layering`] reads it.
    pub diffuse: DVec3,
    /// The dielectric coating's index of refraction (relative to the outside).
    pub ior: f64,
    /// The metal lobe's anisotropy in `[0, 1]` (glTF's `KHR_materials_anisotropy`
    /// `anisotropyStrength`; docs/design/anisotropy.md): 0 is isotropic.
    pub anisotropy: f64,
    /// The anisotropy's direction, radians counter-clockwise from the ball's tangent
    /// (`brdf::ball_tangent`; glTF's `anisotropyRotation`).
    pub anisotropy_rotation: f64,
    /// The clear coat over the whole material (`super::ClearCoat::NONE`: none).
    pub clearcoat: super::ClearCoat,
    /// Linear radiance the surface emits, the same towards every direction (glTF's
    /// `emissiveFactor` x `KHR_materials_emissive_strength`; 0: none). It is added to the
    /// light the ball reflects where a ray first meets it; it is no part of the BRDF
    /// (docs/interop.md, "Emission").
    pub emission: DVec3,
}

impl Material {
    /// A metal of linear `F0`.
    pub fn metal(f0: DVec3) -> Self {
        Material {
            metallic: 1.0,
            f0,
            diffuse: DVec3::ZERO,
            ior: DEFAULT_IOR,
            anisotropy: 0.0,
            anisotropy_rotation: 0.0,
            clearcoat: super::ClearCoat::NONE,
            emission: DVec3::ZERO,
        }
    }

    /// A metal whose `F0` is the sRGB colour `albedo` decoded with the sRGB curve
    /// ([`srgb_decode`], as a `base_color` is).
    pub fn metal_srgb(albedo: [f64; 3]) -> Self {
        Material::metal(srgb_decode(albedo))
    }

    /// A metal whose `F0` is the colour `albedo` decoded with `pow 2.2`, the homework's
    /// decoding ([`gamma22_decode`]; docs/design/reference-scene.md, "The balls, the light
    /// and the camera"): the reference scene's copper and a scene file's `albedo` key.
    pub(crate) fn metal_gamma22(albedo: [f64; 3]) -> Self {
        Material::metal(gamma22_decode(albedo))
    }

    /// A dielectric: a coating of index `ior` over a base of linear colour `diffuse`.
    pub fn dielectric(diffuse: DVec3, ior: f64) -> Self {
        Material {
            metallic: 0.0,
            f0: DVec3::ZERO,
            diffuse,
            ior,
            anisotropy: 0.0,
            anisotropy_rotation: 0.0,
            clearcoat: super::ClearCoat::NONE,
            emission: DVec3::ZERO,
        }
    }

    /// The engines' metallic-roughness material: `base_color` (linear) is the metal's
    /// `F0` and the dielectric's base alike.
    pub fn metallic_roughness(base_color: DVec3, metallic: f64, ior: f64) -> Self {
        Material {
            metallic,
            f0: base_color,
            diffuse: base_color,
            ior,
            anisotropy: 0.0,
            anisotropy_rotation: 0.0,
            clearcoat: super::ClearCoat::NONE,
            emission: DVec3::ZERO,
        }
    }

    /// The material with the metal's lobe made anisotropic: `anisotropy` in `[0, 1]`,
    /// turned by `rotation` radians (glTF's `KHR_materials_anisotropy`).
    pub(crate) fn with_anisotropy(self, anisotropy: f64, rotation: f64) -> Self {
        Material {
            anisotropy,
            anisotropy_rotation: rotation,
            ..self
        }
    }

    /// Whether the lobe is anisotropic (`anisotropy > 0`): then its lights' single
    /// scattering is the anisotropic lobe's, and everything isotropic about the ball reads
    /// its isotropic stand-in's roughness ([`Material::shading_roughness`]), the
    /// prefiltered map's level excepted ([`Material::map_roughness`]).
    pub(crate) fn is_anisotropic(&self) -> bool {
        self.anisotropy > 0.0
    }

    /// The lobe's `(alpha_t, alpha_b)` at `roughness` ([`crate::brdf::anisotropic_alphas`]).
    pub(crate) fn anisotropic_alphas(&self, roughness: f64) -> (f64, f64) {
        crate::brdf::anisotropic_alphas(roughness, self.anisotropy)
    }

    /// The roughness every isotropic part of the ball reads at `roughness` (its E and
    /// E_avg, the term's `f_add`, the split sum's tables, the coating): for an anisotropic
    /// lobe its isotropic stand-in of equal mean squared slope
    /// ([`crate::brdf::isotropic_roughness`]), `roughness` itself otherwise.
    pub(crate) fn shading_roughness(&self, roughness: f64) -> f64 {
        if !self.is_anisotropic() {
            return roughness;
        }
        let (t, b) = self.anisotropic_alphas(roughness);
        crate::brdf::isotropic_roughness(t, b)
    }

    /// The level the split sum reads the prefiltered map at for a lobe of `roughness`: an
    /// anisotropic lobe's equal solid angle ([`crate::brdf::equal_area_roughness`]),
    /// `roughness` itself otherwise (`equal_area_roughness` of `brdf.wgsl` in
    /// `lighting.wgsl`'s `shade_environment_map`).
    pub(crate) fn map_roughness(&self, roughness: f64) -> f64 {
        if !self.is_anisotropic() {
            return roughness;
        }
        let (t, b) = self.anisotropic_alphas(roughness);
        crate::brdf::equal_area_roughness(t, b)
    }

    /// `(cos, sin)` of the anisotropy's rotation.
    pub(crate) fn anisotropy_turn(&self) -> (f64, f64) {
        (
            self.anisotropy_rotation.cos(),
            self.anisotropy_rotation.sin(),
        )
    }

    /// Whether any part is metal.
    pub(crate) fn has_metal(&self) -> bool {
        self.metallic > 0.0
    }

    /// This material under the clear coat `clearcoat`.
    pub(crate) fn with_clearcoat(self, clearcoat: super::ClearCoat) -> Self {
        Material { clearcoat, ..self }
    }

    /// Whether any part is dielectric.
    pub fn has_dielectric(&self) -> bool {
        self.metallic < 1.0
    }
}

/// `pow(c, 2.2)` per channel: the homework's decoding of its colours (a scene file's
/// `albedo` keys), close to but not the sRGB curve ([`srgb_decode`], which every colour
/// called sRGB goes through).
pub fn gamma22_decode(c: [f64; 3]) -> DVec3 {
    DVec3::from_array(c).powf(2.2)
}

/// The sRGB transfer function's inverse (IEC 61966-2-1): `c / 12.92` up to 0.04045, else
/// `((c + 0.055) / 1.055)^2.4`, per channel (`base_color` keys, as glTF reads them).
pub fn srgb_decode(c: [f64; 3]) -> DVec3 {
    let f = |c: f64| {
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    DVec3::new(f(c[0]), f(c[1]), f(c[2]))
}

/// How the dielectric's base is weighted under its coating (docs/design/materials.md,
/// "Layering forms"; each form is a function of `brdf::layering`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Layering {
    /// `albedo (1 - F_avg) / pi`: the design before the materials work.
    Constant,
    /// glTF 2.0's `fresnel_mix`: `albedo (1 - F(v.h)) / pi`.
    Gltf,
    /// Cycles' Principled v2 and MaterialX: `albedo (1 - E_spec(mu_o)) / pi`.
    ViewOnly,
    /// OpenPBR's reciprocal albedo scaling: `albedo (1 - E_spec(mu_i)) (1 - E_spec(mu_o))
    /// / (pi (1 - E_spec_avg))`, the colour the albedo a viewer sees.
    Reciprocal,
    /// A Lambertian substrate of albedo `diffuse` inside the coating, its internal
    /// reflections summed: closest to the random walk (docs/design/materials.md, "The
    /// physical form against the truth").
    #[default]
    Physical,
}

impl Layering {
    /// Every form, in the order the help and the charts list them.
    pub const ALL: [Layering; 5] = [
        Layering::Constant,
        Layering::Gltf,
        Layering::ViewOnly,
        Layering::Reciprocal,
        Layering::Physical,
    ];

    /// The name the scene file and the command line use.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Layering::Constant => "constant",
            Layering::Gltf => "gltf",
            Layering::ViewOnly => "view-only",
            Layering::Reciprocal => "reciprocal",
            Layering::Physical => "physical",
        }
    }
}

crate::named_enum!(Layering, "layering");
