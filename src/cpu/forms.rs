//! The scene-wide choices a point's shading takes ([`Forms`]) and which of a pixel's lobe
//! samples a draw takes ([`LobeSamples`]), handed by `shade_point` to the metal's, the
//! coating's and the clear coat's shading.

use super::clearcoat::ClearcoatPoint;
use super::light::CpuEnvironment;
use crate::brdf::{FAvgForm, Geometry};
use crate::environment::{lobe, IblMethod};
use crate::scene::Scene;

/// The scene-wide choices a point's shading takes: the preset's forms, G, and the map
/// prepared for shading where the scene has one (its split sum's table gives `FssEss`).
pub(crate) struct Forms<'a> {
    pub form: FAvgForm,
    pub geometry: Geometry,
    pub map: Option<&'a CpuEnvironment>,
    /// The pixel's lobe samples where the scene's `ibl_method` is the lobe's, else `None`.
    pub lobe: Option<LobeSamples>,
    /// The point's clear coat (`clearcoat.wgsl`'s `clearcoat_point`), set by `shade_point`
    /// for a coated ball: the base's light is weighted by what it lets through.
    pub coat: Option<ClearcoatPoint>,
}

/// Which of a pixel's lobe samples a draw takes (`shade_environment_mis`): the pixel's
/// sequence rotation, the index of the first sample and the count (the GPU's `env.lobe.x`
/// and `IBL_SAMPLES`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct LobeSamples {
    pub scramble: [u32; 2],
    pub first: u32,
    pub count: u32,
    /// The cosine strategy's samples ([`Scene::cosine_samples`]; the GPU's `IBL_COSINE_SAMPLES`).
    pub cosine: u32,
}

impl LobeSamples {
    /// The samples of pixel `(px, py)` at frame `frame` under `scene`'s method (`None`
    /// under the split sum).
    pub(crate) fn of(scene: &Scene, (px, py): (u32, u32), frame: u32) -> Option<Self> {
        (scene.ibl_method == IblMethod::Lobe).then(|| {
            let count = scene.lobe_sample_count();
            LobeSamples {
                scramble: lobe::pixel_scramble(px, py),
                // As the GPU's uniform holds it: an f32.
                first: (u64::from(frame) * u64::from(count)) as f32 as u32,
                count,
                cosine: scene.cosine_samples(),
            }
        })
    }
}
