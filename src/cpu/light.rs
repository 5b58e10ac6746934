//! What a CPU point's shading reads besides the ball, shared by the metal's (`shade.rs`),
//! the coating's (`coating.rs`) and the Monte Carlo's (`montecarlo.rs`): the E reads as the
//! shader reads them, per-channel helpers, the map prepared for shading ([`CpuEnvironment`]),
//! the scene-wide forms ([`Forms`]) and the lobe's samples with their mean radiance.

use glam::DVec3;

use crate::brdf::GAMES202_EDGE_TINT;
use crate::brdf::{alpha_from_roughness, f_add_preset, f_micro, FAvgForm, Geometry, DIV_EPSILON};
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

/// Which of a pixel's lobe samples a draw takes (`shade_environment_lobe`): the pixel's
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
}

impl CpuEnvironment {
    /// Prepares `environment` for shading with E from `tables` (its geometry).
    pub fn new(environment: &Environment, tables: &Tables) -> Self {
        let chain = MipChain::new(&environment.map);
        let kernels = crate::environment::prefilter::kernels(tables);
        let prefiltered = Prefiltered::new(&chain, &kernels, tables.config.geometry);
        CpuEnvironment {
            chain,
            prefiltered,
            split: SplitSum::shipped(tables.config.geometry),
        }
    }

    /// The intensity the GPU's uniform holds: the environment's times the chain's f16
    /// scale, which its levels and the prefiltered layers are divided by.
    pub fn intensity(&self, environment: &Environment) -> f64 {
        environment.intensity * f64::from(self.chain.scale)
    }

    /// `background_radiance`'s map part in `balls.wgsl`: the map along world direction `d`
    /// (level 0, bilinear), times the intensity.
    pub fn background(&self, environment: &Environment, d: DVec3) -> DVec3 {
        let uv = crate::environment::direction_to_uv(environment.to_map(d));
        self.intensity(environment) * self.chain.levels[0].bilinear(uv)
    }
}

/// `lobe_mean_radiance` of `lighting.wgsl`: the self-normalised mean radiance `sum w L /
/// sum w` of the lobe of `roughness` at normal `n` towards `v` over `lobe.count` samples of
/// its GGX visible normals, each weighted by `w = f_micro mu_i / pdf` with the scene's G and
/// `fresnel(v.h)` per channel, read at its footprint's mip level; 0 where no sample lies
/// above the horizon.
pub(crate) fn lobe_mean_radiance(
    environment: &Environment,
    ibl: &CpuEnvironment,
    (n, v): (DVec3, DVec3),
    roughness: f64,
    fresnel: &dyn Fn(f64) -> DVec3,
    (lobe, geometry): (LobeSamples, Geometry),
) -> DVec3 {
    let mu_o = n.dot(v).max(0.0);
    let alpha = alpha_from_roughness(roughness);
    let frame = crate::sampling::duff_frame(n);
    let v_local = frame.to_local(v);
    let level0 = &ibl.chain.levels[0];
    let size = (f64::from(level0.width), f64::from(level0.height));
    let max_level = (ibl.chain.levels.len() - 1) as f64;
    let count = f64::from(lobe.first) + f64::from(lobe.count);
    let (mut sum, mut weights) = (DVec3::ZERO, DVec3::ZERO);
    for j in 0..lobe.count {
        let (u1, u2) = lobe::lobe_frame_point(lobe.first, j, lobe.count, lobe.scramble);
        let l = frame.to_world(crate::sampling::sample_vndf(v_local, alpha, u1, u2));
        let mu_i = n.dot(l);
        if mu_i <= 0.0 || mu_o <= 0.0 {
            continue;
        }
        let h = (v + l).normalize();
        let n_dot_h = n.dot(h);
        let pdf = crate::sampling::vndf_density(mu_o, n_dot_h, alpha);
        if pdf <= DIV_EPSILON {
            continue;
        }
        let w = per_channel(fresnel(v.dot(h)), |f| {
            f_micro(f, mu_o, mu_i, n_dot_h, roughness, geometry) * (mu_i / pdf)
        });
        let l_map = environment.to_map(l);
        let lod = lobe::lobe_lod(pdf, count, l_map, size, max_level);
        sum += w * ibl.chain.sample(l_map, lod);
        weights += w;
    }
    let mean = DVec3::from_array(std::array::from_fn(|c| {
        if weights[c] <= DIV_EPSILON {
            0.0
        } else {
            sum[c] / weights[c]
        }
    }));
    ibl.intensity(environment) * mean
}
