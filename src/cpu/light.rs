//! What a CPU point's shading reads besides the ball, shared by the metal's (`shade.rs`),
//! the coating's (`coating.rs`) and the Monte Carlo's (`montecarlo.rs`): the E reads as the
//! shader reads them, per-channel helpers, the map prepared for shading ([`CpuEnvironment`]),
//! the scene-wide forms ([`Forms`]) and which of a pixel's samples the lobe mode takes.

use glam::DVec3;

use crate::brdf::GAMES202_EDGE_TINT;
use crate::brdf::{f_add_preset, FAvgForm, Geometry};
use crate::environment::sampler::LuminanceCdf;
use crate::environment::{lobe, Environment, IblMethod, MipChain, Prefiltered};
use crate::lut::{SplitSum, TableSet, Tables};
use crate::scene::Scene;

/// `1 - E(mu, roughness)` as the shader reads `e` (f32, [`TableSet::lut_loss`]), in f64.
pub(crate) fn loss(e: &TableSet, mu: f64, roughness: f64) -> f64 {
    e.lut_loss(mu as f32, roughness as f32) as f64
}

/// `1 - E_avg(roughness)` as the shader reads `e` ([`TableSet::lut_loss_avg`]), in f64.
pub(crate) fn loss_avg(e: &TableSet, roughness: f64) -> f64 {
    e.lut_loss_avg(roughness as f32) as f64
}

/// `f` applied to each channel of `v`.
pub(crate) fn per_channel(v: DVec3, f: impl Fn(f64) -> f64) -> DVec3 {
    DVec3::new(f(v.x), f(v.y), f(v.z))
}

/// `f_add_preset` per channel of `f0` (the games202 form's edge tint per channel).
pub(crate) fn f_add_rgb(form: FAvgForm, f0: DVec3, e_avg: f64) -> DVec3 {
    DVec3::new(
        f_add_preset(form, f0.x, GAMES202_EDGE_TINT[0], e_avg),
        f_add_preset(form, f0.y, GAMES202_EDGE_TINT[1], e_avg),
        f_add_preset(form, f0.z, GAMES202_EDGE_TINT[2], e_avg),
    )
}

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
    pub coat: Option<super::clearcoat::ClearcoatPoint>,
}

/// Which of a pixel's lobe samples a draw takes (`shade_environment_mis`): the pixel's
/// sequence rotation, the index of the first sample and the count (the GPU's `env.lobe.x`
/// and `IBL_SAMPLES`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct LobeSamples {
    pub scramble: [u32; 2],
    pub first: u32,
    pub count: u32,
}

impl LobeSamples {
    /// The samples of pixel `(px, py)` at frame `frame` under `scene`'s method (`None`
    /// under the split sum).
    pub fn of(scene: &Scene, (px, py): (u32, u32), frame: u32) -> Option<Self> {
        (scene.ibl_method == IblMethod::Lobe).then(|| {
            let count = scene
                .ibl_samples
                .clamp(1, crate::environment::MAX_IBL_SAMPLES);
            LobeSamples {
                scramble: lobe::pixel_scramble(px, py),
                // As the GPU's uniform holds it: an f32.
                first: (u64::from(frame) * u64::from(count)) as f32 as u32,
                count,
            }
        })
    }
}

/// An environment map prepared for the CPU renderer: the same mip chain, prefiltered
/// layers and split-sum table the GPU binds (`gpu::environment`), computed on the CPU.
pub struct CpuEnvironment {
    /// The map's mip chain (f16 values, as uploaded).
    pub chain: MipChain,
    /// The prefiltered layers.
    pub prefiltered: Prefiltered,
    /// The split sum's bias table.
    pub split: SplitSum,
    /// The map's luminance tables, as the GPU binds them for the lobe mode (`None` for a
    /// map without: a constant one).
    pub luminance: Option<LuminanceCdf>,
}

impl CpuEnvironment {
    /// Prepares `environment` for shading with E from `tables` (its geometry).
    pub fn new(environment: &Environment, tables: &Tables) -> Self {
        let chain = MipChain::new(&environment.map);
        let kernels = crate::environment::prefilter::kernels(tables);
        let prefiltered = Prefiltered::new(&chain, &kernels, tables.config.geometry);
        let unit = Environment {
            intensity: 1.0,
            ..environment.clone()
        };
        CpuEnvironment {
            chain,
            prefiltered,
            split: SplitSum::shipped(tables.config.geometry),
            luminance: LuminanceCdf::of(&unit),
        }
    }

    /// The intensity the GPU's uniform holds: the environment's times the chain's f16
    /// scale, which its levels and the prefiltered layers are divided by.
    pub fn intensity(&self, environment: &Environment) -> f64 {
        environment.intensity * f64::from(self.chain.scale)
    }

    /// `background_radiance`'s map part in `footprint.wgsl`: the map along world direction `d`
    /// (level 0, bilinear), times the intensity.
    pub fn background(&self, environment: &Environment, d: DVec3) -> DVec3 {
        let uv = crate::environment::direction_to_uv(environment.to_map(d));
        self.intensity(environment) * self.chain.levels[0].bilinear(uv)
    }
}
