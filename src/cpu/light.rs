//! What a CPU point's shading reads besides the ball, shared by the metal's (`shade.rs`),
//! the coating's (`coating.rs`) and the Monte Carlo's (`montecarlo.rs`): the E reads as the
//! shader reads them, per-channel helpers and the map prepared for shading
//! ([`CpuEnvironment`]). The scene-wide forms and the lobe's samples are in `forms.rs`.

use glam::DVec3;

use crate::brdf::GAMES202_EDGE_TINT;
use crate::brdf::{f_add_preset, FAvgForm};
use crate::environment::sampler::LuminanceCdf;
use crate::environment::{Environment, MipChain, Prefiltered};
use crate::lut::{SplitSum, TableSet, Tables};

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
    /// map without, a constant one, and where the scene draws with the split sum: the
    /// tables of a large map take hundreds of MB that the split sum never reads).
    pub(crate) luminance: Option<LuminanceCdf>,
}

impl CpuEnvironment {
    /// Prepares `environment` for shading with E from `tables` (its geometry), with its
    /// luminance tables where the lobe mode samples them (`lobe`).
    pub fn new(environment: &Environment, tables: &Tables, lobe: bool) -> Self {
        let chain = MipChain::new(&environment.map);
        let kernels = crate::environment::prefilter::kernels(tables);
        let prefiltered = Prefiltered::new(&chain, &kernels, tables.config.geometry);
        // The tables of the map at unit intensity (its own is applied where it is read).
        let luminance = lobe
            .then(|| {
                LuminanceCdf::of(&Environment {
                    intensity: 1.0,
                    ..environment.clone()
                })
            })
            .flatten();
        CpuEnvironment {
            chain,
            prefiltered,
            split: SplitSum::shipped(tables.config.geometry),
            luminance,
        }
    }

    /// The intensity the GPU's uniform holds: the environment's times the chain's f16
    /// scale, which its levels and the prefiltered layers are divided by.
    pub fn intensity(&self, environment: &Environment) -> f64 {
        environment.intensity * f64::from(self.chain.scale)
    }

    /// `background_radiance`'s map part in `footprint.wgsl`: the map along world direction `d`
    /// (level 0, bilinear), times the intensity.
    pub(crate) fn background(&self, environment: &Environment, d: DVec3) -> DVec3 {
        let uv = crate::environment::direction_to_uv(environment.to_map(d));
        self.intensity(environment) * self.chain.levels[0].bilinear(uv)
    }
}
