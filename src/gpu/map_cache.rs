//! Group 1 of the ball renderer: the environment maps' bind groups. Preparing a map (its
//! kernels, mip chain and split-sum table on the CPU, the upload and the GPU's
//! prefiltering: [`prepare_map`]) is the costly part, so the last few maps prepared are
//! kept, the least recently drawn dropped first (the viewer's picker switches between
//! built-ins without preparing one again).

use std::sync::Arc;
use std::time::{Duration, Instant};

use super::context::Gpu;
use super::environment::{self as env_gpu, EnvUniform, EnvironmentKey, EnvironmentTextures};
use crate::environment::sampler::LuminanceCdf;
use crate::environment::{prefilter, ChainOn, EnvMap, Environment, IblMethod, MipChain};
use crate::error::Result;
use crate::lut::{self, BakeConfig, SplitSum};
use crate::scene::Scene;

/// Prefiltered maps a renderer keeps: a few megabytes each at 1024 x 512 (the map's f16 mip
/// chain and the prefiltered layers).
pub(crate) const MAX_PREFILTERED_MAPS: usize = 4;

/// A prepared map: its key, textures, luminance tables (`None` until a scene in the lobe
/// mode draws with it: the split sum never reads them; then `Some(None)` where the map has
/// none) and bind group.
struct Loaded {
    key: EnvironmentKey,
    textures: EnvironmentTextures,
    luminance: Option<Option<wgpu::Buffer>>,
    group: wgpu::BindGroup,
}

/// Group 1's layout, uniform and sampler, the stand-in bind group for scenes without a
/// map, and the latest maps' prefiltered textures with their bind groups, most recently
/// drawn first.
pub(crate) struct PrefilteredMaps {
    pub layout: wgpu::BindGroupLayout,
    /// The map's uniform ([`EnvUniform`]), written every frame.
    pub uniform: wgpu::Buffer,
    sampler: wgpu::Sampler,
    /// The luminance tables' stand-in ([`env_gpu::NO_LUMINANCE`]).
    no_luminance: wgpu::Buffer,
    empty: wgpu::BindGroup,
    loaded: Vec<Loaded>,
    /// Wall time of the latest preparation.
    last_prepared: Option<Duration>,
    /// A mip chain built ahead for the map it holds (compared by identity), used by that
    /// map's next preparation ([`PrefilteredMaps::offer_chain`]).
    ahead: Option<(Arc<EnvMap>, MipChain)>,
}

impl PrefilteredMaps {
    pub(crate) fn new(device: &wgpu::Device) -> Self {
        let layout = env_gpu::layout(device);
        let uniform = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("environment"),
            size: std::mem::size_of::<EnvUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let sampler = env_gpu::sampler(device);
        let no_luminance = env_gpu::luminance_buffer(device, &env_gpu::NO_LUMINANCE);
        let empty = EnvironmentTextures::empty(device).bind(
            device,
            &layout,
            (&uniform, &sampler),
            &no_luminance,
        );
        PrefilteredMaps {
            layout,
            uniform,
            sampler,
            no_luminance,
            empty,
            loaded: Vec::new(),
            last_prepared: None,
            ahead: None,
        }
    }

    /// Keeps `chain`, built from `map`, for that map's next preparation (the CLI builds it
    /// while the device opens). Any other map's preparation builds its own.
    pub(crate) fn offer_chain(&mut self, map: Arc<EnvMap>, chain: MipChain) {
        self.ahead = Some((map, chain));
    }

    /// The bind group for `scene`: its map, prepared on the first draw with it (or with
    /// another G) and kept, or the stand-ins for a scene without one. Fails, before any
    /// work, where the map's mip chain would not fit in memory.
    pub(crate) fn bind_group(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        config: BakeConfig,
    ) -> Result<wgpu::BindGroup> {
        let Some(environment) = &scene.environment_map else {
            return Ok(self.empty.clone());
        };
        let geometry = scene.effective_geometry();
        let key = EnvironmentKey::new(environment, geometry);
        let lobe = scene.ibl_method == IblMethod::Lobe;
        if let Some(i) = self.loaded.iter().position(|l| l.key == key) {
            let mut entry = self.loaded.remove(i);
            if lobe && entry.luminance.is_none() {
                entry.luminance = Some(luminance_tables(gpu, environment));
                entry.group = self.bind(gpu, &entry.textures, entry.luminance.as_ref());
            }
            let group = entry.group.clone();
            self.loaded.insert(0, entry);
            return Ok(group);
        }
        environment.map.check_chain_memory(ChainOn::Gpu)?;
        // Dropped first: at most MAX_PREFILTERED_MAPS maps' textures at once.
        self.loaded.truncate(MAX_PREFILTERED_MAPS - 1);
        let ahead = match self.ahead.take() {
            Some((map, chain)) if Arc::ptr_eq(&map, &environment.map) => Some(chain),
            _ => None,
        };
        let config = BakeConfig { geometry, ..config };
        let textures = prepare_map(gpu, environment, config, ahead);
        self.last_prepared = Some(textures.prefilter_time);
        let luminance = lobe.then(|| luminance_tables(gpu, environment));
        let group = self.bind(gpu, &textures, luminance.as_ref());
        self.loaded.insert(
            0,
            Loaded {
                key,
                textures,
                luminance,
                group: group.clone(),
            },
        );
        Ok(group)
    }

    /// Group 1 of `textures` with `luminance`'s tables (the stand-in where there are none).
    fn bind(
        &self,
        gpu: &Gpu,
        textures: &EnvironmentTextures,
        luminance: Option<&Option<wgpu::Buffer>>,
    ) -> wgpu::BindGroup {
        let buffer = luminance
            .and_then(Option::as_ref)
            .unwrap_or(&self.no_luminance);
        textures.bind(
            &gpu.device,
            &self.layout,
            (&self.uniform, &self.sampler),
            buffer,
        )
    }

    /// Wall time of the latest preparation (see `Renderer::last_prefilter_time`).
    pub(crate) fn last_prepared(&self) -> Option<Duration> {
        self.last_prepared
    }
}

/// The lobe mode's luminance tables of `environment`'s map on the GPU (the Monte Carlo
/// sampler's weights less their mean, [`LuminanceCdf::compensated`], whatever the
/// intensity: they depend on the texels alone), or `None` where the map has none (a
/// constant map, or no texel above the mean) or they exceed the device's storage binding
/// (then the lobe mode draws no map samples, and says so).
fn luminance_tables(gpu: &Gpu, environment: &Environment) -> Option<wgpu::Buffer> {
    let unit = Environment {
        intensity: 1.0,
        ..environment.clone()
    };
    let words = LuminanceCdf::compensated(&unit)?.gpu_words();
    let bytes = std::mem::size_of_val(words.as_slice()) as u64;
    let max = gpu.device.limits().max_storage_buffer_binding_size;
    if bytes > max {
        log::warn!(
            "environment {}: its luminance tables need {bytes} bytes, this device binds {max}: \
             the lobe mode samples its lobe and cosine alone",
            environment.source
        );
        return None;
    }
    Some(env_gpu::luminance_buffer(&gpu.device, &words))
}

/// Prepares `environment` for shading with tables baked with `config` (its G the scene's):
/// the kernels from those tables, the mip chain (`ahead`, where it was built beforehand)
/// and the shipped split-sum table on the CPU, then the upload and the GPU's prefilter.
/// The textures' `prefilter_time` is the whole preparation's wall time.
fn prepare_map(
    gpu: &Gpu,
    environment: &Environment,
    config: BakeConfig,
    ahead: Option<MipChain>,
) -> EnvironmentTextures {
    let start = Instant::now();
    let kernels = prefilter::kernels(&lut::bake(&config));
    let t_kernels = start.elapsed();
    let chain = ahead.unwrap_or_else(|| MipChain::new(&environment.map));
    // The map's sun, found on this chain: the plan asks for it next, and a map with one
    // has a second set of layers.
    let sunless = environment.map.sun_of_chain(&chain).is_some();
    let t_chain = start.elapsed();
    let split = SplitSum::shipped(config.geometry);
    let t_split = start.elapsed();
    let mut textures =
        EnvironmentTextures::new(&gpu.device, &gpu.queue, &chain, (&kernels, &split), sunless);
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    log::debug!(
        "environment {}: kernels {:.1} ms, mip chain {:.1} ms, split sum {:.1} ms, \
         GPU upload and prefilter submitted in {:.1} ms",
        environment.source,
        ms(t_kernels),
        ms(t_chain - t_kernels),
        ms(t_split - t_chain),
        ms(textures.prefilter_time)
    );
    textures.prefilter_time = start.elapsed();
    textures
}
