//! An environment map on the GPU: the renderer's group 1 (`shaders/bindings.wgsl`). The map
//! and its mip chain ([`MipChain`], built on the CPU) and the split-sum table are uploaded;
//! the specular layers and the convolved layers are prefiltered here, at load, by
//! `shaders/prefilter.wgsl` (one compute dispatch a layer), the twin of
//! [`crate::environment::Prefiltered`].

use std::time::{Duration, Instant};

use super::shaders;
use crate::environment::prefilter::{
    fis_max_level, specular_mip, specular_mip_levels, specular_roughness, specular_samples,
    specular_size, sunless_source, Bright, BrightTexel, MipChain, BRIGHT_MAX, CONVOLVED_LEVELS,
    CONVOLVED_WIDTH, SPECULAR_LEVELS,
};
use crate::environment::Environment;
use crate::lut::{SplitSum, SPLIT_SUM_SIZE};
use crate::scene::Scene;

/// The format of the map, its mip chain and the prefiltered layers: filterable on every
/// backend, and a storage format the compute passes can write.
pub(crate) const ENVIRONMENT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The split sum's bias table: `SPLIT_SUM_SIZE` square, each texel the 2x2 block of the
/// table's texels from it (`upload::loss_quads`), read unfiltered (`split_sum_bias`).
pub(crate) const SPLIT_SUM_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// Mirrors `EnvUniform` in `types.wgsl` (member for member: src/gpu/tests/boundary.rs).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct EnvUniform {
    /// cos and sin of `-rotation_deg`.
    pub rotation: [f32; 2],
    /// The map's intensity (times the map's f16 scale).
    pub intensity: f32,
    /// The map's weight in the background: 1 when it shows the map, else 0.
    pub shows_map: f32,
    /// rgb: the background's fixed radiance (added to the map where it shows).
    pub background: [f32; 4],
    /// The lobe's samples (`ibl_method = "lobe"`): x: the index of this frame's first
    /// sample in each pixel's sequence (frame k of N samples: k N); y: unused; z, w: the
    /// map's base level, texels across and down.
    pub lobe: [f32; 4],
}

impl EnvUniform {
    /// The uniform of `scene`.
    pub(crate) fn of(scene: &Scene) -> Self {
        // The textures hold the map divided by its f16 scale (`MipChain::scale`): the
        // intensity multiplies it back, exactly (a power of two).
        let (rotation, intensity) = scene.environment_map.as_ref().map_or((0.0, 0.0), |e| {
            (e.rotation_deg, e.intensity * f64::from(e.map.f16_scale()))
        });
        let (s, c) = (-rotation.to_radians()).sin_cos();
        let shows_map = scene.background_shows_map();
        let colour = scene.background_radiance();
        let (w, h) = scene
            .environment_map
            .as_ref()
            .map_or((1, 1), |e| (e.map.width(), e.map.height()));
        EnvUniform {
            rotation: [c as f32, s as f32],
            intensity: intensity as f32,
            shows_map: shows_map as u32 as f32,
            background: [colour.x as f32, colour.y as f32, colour.z as f32, 0.0],
            lobe: [0.0, 0.0, w as f32, h as f32],
        }
    }

    /// The uniform with frame `frame` of the lobe's samples (`scene.ibl_samples` a frame):
    /// its first sample index `frame * ibl_samples`.
    pub(crate) fn at_lobe_frame(mut self, scene: &Scene, frame: u32) -> Self {
        self.lobe[0] = (u64::from(frame) * u64::from(scene.ibl_samples)) as f32;
        self
    }
}

/// Group 1's layout: the uniform, the map, the specular and convolved layers, the
/// split-sum table, the sampler, the map's luminance tables (the lobe mode's map samples).
pub(crate) fn layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let stages = wgpu::ShaderStages::FRAGMENT;
    let texture = |binding, dim, filterable| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: stages,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable },
            view_dimension: dim,
            multisampled: false,
        },
        count: None,
    };
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("group 1 (environment)"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: stages,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
            texture(1, wgpu::TextureViewDimension::D2, true),
            texture(2, wgpu::TextureViewDimension::D2Array, true),
            texture(3, wgpu::TextureViewDimension::D2Array, true),
            texture(4, wgpu::TextureViewDimension::D2, false),
            wgpu::BindGroupLayoutEntry {
                binding: 5,
                visibility: stages,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 6,
                visibility: stages,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: true },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
        ],
    })
}

/// The luminance tables' buffer of group 1 (`env_cdf` in `bindings.wgsl`): `words`
/// ([`crate::environment::sampler::LuminanceCdf::gpu_words`], or [`NO_LUMINANCE`]).
pub(crate) fn luminance_buffer(device: &wgpu::Device, words: &[f32]) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("luminance tables"),
        contents: bytemuck::cast_slice(words),
        usage: wgpu::BufferUsages::STORAGE,
    })
}

/// The luminance tables of a map without them (size 0 by 0: the lobe mode draws no map
/// samples).
pub(crate) const NO_LUMINANCE: [f32; 4] = [0.0; 4];

/// The sampler every environment read uses: linear within and between levels, `u`
/// repeating (the map wraps in azimuth), `v` clamped.
pub(crate) fn sampler(device: &wgpu::Device) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("environment"),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::ClampToEdge,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Linear,
        ..Default::default()
    })
}

/// The textures of one map, prefiltered.
pub(crate) struct EnvironmentTextures {
    /// The map and its mip chain.
    pub radiance: wgpu::TextureView,
    /// [`SPECULAR_LEVELS`] layers, twice for a map with a sun (the second set without it).
    pub specular: wgpu::TextureView,
    /// `1 + CONVOLVED_LEVELS` layers, twice for a map with a sun.
    pub convolved: wgpu::TextureView,
    /// The split-sum bias table, `R32Float`.
    pub split_sum: wgpu::TextureView,
    /// Wall time of the upload and the prefilter's encoding and submission (the GPU's work
    /// runs on behind: the renderer replaces it by the whole preparation's on the CPU).
    pub prefilter_time: Duration,
}

fn texture(
    device: &wgpu::Device,
    label: &str,
    size: (u32, u32, u32),
    levels: u32,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: size.2,
        },
        mip_level_count: levels,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

fn f16_bytes(texels: &[[f32; 4]]) -> Vec<u8> {
    texels
        .iter()
        .flat_map(|t| t.map(|c| half::f16::from_f32(c).to_bits()))
        .flat_map(u16::to_le_bytes)
        .collect()
}

/// Mirrors `PrefilterParams` in `prefilter.wgsl` (member for member: `gpu::boundary`).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct PrefilterParams {
    pub(crate) size: [u32; 4],
    pub(crate) source: [u32; 4],
    pub(crate) layer: [f32; 4],
    pub(crate) limits: [u32; 4],
}

/// The map's texture: `chain`'s levels uploaded as f16 (its mip levels).
fn upload_chain(device: &wgpu::Device, queue: &wgpu::Queue, chain: &MipChain) -> wgpu::Texture {
    let base = &chain.levels[0];
    let radiance = texture(
        device,
        "environment map",
        (base.width, base.height, 1),
        chain.levels.len() as u32,
        ENVIRONMENT_FORMAT,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
    );
    for (k, level) in chain.levels.iter().enumerate() {
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &radiance,
                mip_level: k as u32,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            &f16_bytes(&level.texels),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(level.width * 8),
                rows_per_image: Some(level.height),
            },
            wgpu::Extent3d {
                width: level.width,
                height: level.height,
                depth_or_array_layers: 1,
            },
        );
    }
    radiance
}

/// The split-sum bias table's texture (`R32Float`, `SPLIT_SUM_SIZE` square).
fn upload_split_sum(device: &wgpu::Device, queue: &wgpu::Queue, split: &SplitSum) -> wgpu::Texture {
    let n = SPLIT_SUM_SIZE as u32;
    let split_tex = texture(
        device,
        "split-sum bias",
        (n, n, 1),
        1,
        SPLIT_SUM_FORMAT,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
    );
    // As 2x2 blocks (the E table's layout, `loss_quads`): a bilinear read is one load, not
    // four (`split_sum_bias`).
    let blocks = crate::gpu::upload::loss_quads(&split.bias, n as usize, n as usize);
    queue.write_texture(
        split_tex.as_image_copy(),
        bytemuck::cast_slice(&blocks),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(n * 16),
            rows_per_image: Some(n),
        },
        wgpu::Extent3d {
            width: n,
            height: n,
            depth_or_array_layers: 1,
        },
    );
    split_tex
}

impl EnvironmentTextures {
    /// Uploads `chain` and `split` and submits their prefiltering on the GPU with `kernels`
    /// ([`crate::environment::prefilter::kernels`]), without waiting for it: the queue runs
    /// it while the CPU goes on (with the render pipelines' compilation, in a fresh
    /// process), and every later submission that reads the textures comes after it. With
    /// `sunless` (the map has a sun, `EnvMap::sun_of_chain`) a second set of layers, without
    /// it, is prefiltered too (src/environment/sun.rs).
    pub(crate) fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        chain: &MipChain,
        (kernels, split): (&[f32], &SplitSum),
        sunless: bool,
    ) -> Self {
        let start = Instant::now();
        let base = &chain.levels[0];
        let radiance = upload_chain(device, queue, chain);
        let split_tex = upload_split_sum(device, queue, split);
        let layered = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::STORAGE_BINDING;
        let (sw, sh) = specular_size(base.width);
        let bright = Bright::new(chain);
        let sets = 1 + u32::from(sunless);
        let specular = texture(
            device,
            "specular layers",
            (sw, sh, SPECULAR_LEVELS * sets),
            specular_mip_levels(base.width),
            ENVIRONMENT_FORMAT,
            layered,
        );
        let cw = CONVOLVED_WIDTH;
        let convolved = texture(
            device,
            "convolved layers",
            (cw, cw / 2, (CONVOLVED_LEVELS + 1) * sets),
            1,
            ENVIRONMENT_FORMAT,
            layered,
        );
        let radiance_view = radiance.create_view(&Default::default());
        let clipped = bright
            .as_ref()
            .map(|b| upload_chain(device, queue, &b.chain).create_view(&Default::default()));
        let sources = Sources {
            chain,
            radiance: &radiance_view,
            bright: bright.as_ref().zip(clipped.as_ref()),
            sunless,
        };
        prefilter(
            device,
            queue,
            &sources,
            kernels,
            split.geometry,
            [&specular, &convolved],
        );
        let array = |t: &wgpu::Texture| {
            t.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            })
        };
        EnvironmentTextures {
            radiance: radiance_view,
            specular: array(&specular),
            convolved: array(&convolved),
            split_sum: split_tex.create_view(&Default::default()),
            prefilter_time: start.elapsed(),
        }
    }

    /// Stand-ins for a scene with no map: one black texel each (nothing reads them: the
    /// pipelines compile the map's reads out), so one pipeline layout serves every scene.
    pub(crate) fn empty(device: &wgpu::Device) -> Self {
        let black = |label, layers| {
            let t = texture(
                device,
                label,
                (1, 1, layers),
                1,
                ENVIRONMENT_FORMAT,
                wgpu::TextureUsages::TEXTURE_BINDING,
            );
            t.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(if layers > 1 {
                    wgpu::TextureViewDimension::D2Array
                } else {
                    wgpu::TextureViewDimension::D2
                }),
                ..Default::default()
            })
        };
        let split = texture(
            device,
            "split-sum bias (none)",
            (1, 1, 1),
            1,
            SPLIT_SUM_FORMAT,
            wgpu::TextureUsages::TEXTURE_BINDING,
        );
        EnvironmentTextures {
            radiance: black("environment map (none)", 1),
            specular: black("specular layers (none)", 2),
            convolved: black("convolved layers (none)", 2),
            split_sum: split.create_view(&Default::default()),
            prefilter_time: Duration::ZERO,
        }
    }

    /// Group 1 of these textures with `uniform`, `sampler` and the luminance tables'
    /// buffer `luminance` ([`luminance_buffer`]).
    pub(crate) fn bind(
        &self,
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        (uniform, sampler): (&wgpu::Buffer, &wgpu::Sampler),
        luminance: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("group 1 (environment)"),
            layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: uniform.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&self.radiance),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&self.specular),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&self.convolved),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::TextureView(&self.split_sum),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: wgpu::BindingResource::Sampler(sampler),
                },
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: luminance.as_entire_binding(),
                },
            ],
        })
    }
}

/// What the prefilter reads: the map's chain and its texture, and its bright texels apart
/// with the texture of the chain they were clipped from, when it has any.
struct Sources<'a> {
    chain: &'a MipChain,
    radiance: &'a wgpu::TextureView,
    bright: Option<(&'a Bright, &'a wgpu::TextureView)>,
    /// Whether the map has a sun: the second set of layers, without it, is prefiltered too.
    sunless: bool,
}

/// One compute dispatch per layer of the specular and the convolved layers' textures.
fn prefilter(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    sources: &Sources<'_>,
    kernels: &[f32],
    geometry: crate::brdf::Geometry,
    [specular, convolved]: [&wgpu::Texture; 2],
) {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("prefilter"),
        source: wgpu::ShaderSource::Wgsl(shaders::prefilter_source().into()),
    });
    let group_layout = prefilter_layout(device);
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("prefilter"),
        bind_group_layouts: &[Some(&group_layout)],
        immediate_size: 0,
    });
    let pipeline = |entry: &str| {
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        })
    };
    let t0 = Instant::now();
    let pipelines = [pipeline("specular_main"), pipeline("convolved_main")];
    log::debug!(
        "prefilter pipelines {:.1} ms",
        t0.elapsed().as_secs_f64() * 1e3
    );
    let kernel_buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("kernels"),
        size: 160 * 16,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut padded = kernels.to_vec();
    padded.resize(160 * 4, 0.0);
    queue.write_buffer(&kernel_buffer, 0, bytemuck::cast_slice(&padded));
    let bright_buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("bright texels"),
        size: (BRIGHT_MAX * std::mem::size_of::<BrightTexel>()) as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    if let Some((bright, _)) = sources.bright {
        queue.write_buffer(&bright_buffer, 0, bytemuck::cast_slice(&bright.texels));
    }
    let sampler = sampler(device);
    let inputs = PrefilterInputs {
        layout: &group_layout,
        radiance: sources.radiance,
        clipped: sources.bright.map_or(sources.radiance, |(_, view)| view),
        sampler: &sampler,
        kernels: &kernel_buffer,
        bright: &bright_buffer,
    };
    let mut encoder = device.create_command_encoder(&Default::default());
    let mut keep = Vec::new();
    let bright = sources.bright.map(|(b, _)| b);
    for job in prefilter_jobs(sources.chain, bright, geometry, sources.sunless) {
        let target = [specular, convolved][job.pipeline];
        let pipeline = &pipelines[job.pipeline];
        keep.push(encode_job(
            device,
            queue,
            &inputs,
            &job,
            target,
            pipeline,
            &mut encoder,
        ));
    }
    queue.submit([encoder.finish()]);
}

/// The prefilter's one bind group layout for both entry points (each leaves the other's
/// bindings unused): the map, its sampler, the layer written, the layer's parameters, the
/// kernels, the bright texels.
fn prefilter_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let compute = wgpu::ShaderStages::COMPUTE;
    let uniform = |binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: compute,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("prefilter"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: compute,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: compute,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 2,
                visibility: compute,
                ty: wgpu::BindingType::StorageTexture {
                    access: wgpu::StorageTextureAccess::WriteOnly,
                    format: ENVIRONMENT_FORMAT,
                    view_dimension: wgpu::TextureViewDimension::D2,
                },
                count: None,
            },
            uniform(3),
            uniform(4),
            uniform(5),
        ],
    })
}

/// What every prefilter dispatch binds besides its own layer and parameters.
struct PrefilterInputs<'a> {
    layout: &'a wgpu::BindGroupLayout,
    radiance: &'a wgpu::TextureView,
    /// The map with its bright texels clipped (the map itself when it has none).
    clipped: &'a wgpu::TextureView,
    sampler: &'a wgpu::Sampler,
    kernels: &'a wgpu::Buffer,
    bright: &'a wgpu::Buffer,
}

/// One dispatch: which pipeline (0 specular, 1 convolved) writes which layer and mip level
/// of its texture, of what size, with which parameters.
struct PrefilterJob {
    pipeline: usize,
    /// Whether it samples the map with its bright texels clipped (the sampled specular
    /// layers of a map that has them).
    clipped: bool,
    layer: u32,
    mip: u32,
    size: (u32, u32),
    params: PrefilterParams,
}

/// The dispatches of `chain` prefiltered for `geometry`: every specular layer (roughness
/// `specular_roughness(k)`, its mip level and sample count; the sampled ones read
/// `bright`'s clipped chain when there is one), then every convolved one; with `sunless`
/// (a map with a sun, `crate::environment::Sun`), the same layers again after them from the
/// clipped chain alone, no excess added (`Prefiltered::sunless`).
fn prefilter_jobs(
    chain: &MipChain,
    bright: Option<&Bright>,
    geometry: crate::brdf::Geometry,
    sunless: bool,
) -> Vec<PrefilterJob> {
    let mut jobs = layer_jobs(chain, (chain, bright), geometry, 0);
    if let (true, Some(b)) = (sunless, bright) {
        jobs.extend(layer_jobs(chain, (&b.chain, None), geometry, 1));
    }
    jobs
}

/// The jobs of layer set `set` (`env_specular`'s) of a map whose chain is `chain`: the
/// mirror read from `mirror`, the sampled layers from `bright`'s clipped chain plus its
/// excess where there is one, else from `mirror`; the convolved ones over `mirror`'s
/// convolution source.
fn layer_jobs(
    chain: &MipChain,
    (mirror, bright): (&MipChain, Option<&Bright>),
    geometry: crate::brdf::Geometry,
    set: u32,
) -> Vec<PrefilterJob> {
    let base = &chain.levels[0];
    // Set 1 reads the clipped chain throughout (bound as the clipped texture).
    let clipped_mirror = set == 1;
    let sampled = bright.map_or(mirror, |b| &b.chain);
    let clipped_sampled = bright.is_some() || clipped_mirror;
    let sampled_size = [sampled.levels[0].width, sampled.levels[0].height];
    let bright_count = bright.map_or(0, |b| b.texels.len() as u32);
    let (sw, sh) = specular_size(base.width);
    let mirror_base = &mirror.levels[0];
    let lod0 = (mirror_base.width as f64 / sw as f64).log2() as f32;
    let source_level = if clipped_mirror {
        sunless_source(chain, mirror)
    } else {
        chain.convolution_source()
    };
    let source = &mirror.levels[source_level as usize];
    let cw = CONVOLVED_WIDTH;
    let levels = specular_mip_levels(base.width);
    let mirror_size = [mirror_base.width, mirror_base.height];
    let mut jobs = Vec::new();
    for k in 0..SPECULAR_LEVELS {
        let alpha = if k == 0 {
            0.0
        } else {
            crate::brdf::alpha_from_roughness(specular_roughness(k)) as f32
        };
        let m = specular_mip(k, levels);
        let size = (sw >> m, sh >> m);
        let geometry_id = shaders::geometry_id(geometry) as f32;
        let roughness = specular_roughness(k) as f32;
        // The mirror layer reads the map at its own scale; the sampled layers read the
        // sampled chain, whose level 0 sets their texel solid angle.
        let (clipped, level0, limits) = if k == 0 {
            (clipped_mirror, mirror_size, [0; 4])
        } else {
            let limits = [specular_samples(k), fis_max_level(sampled), bright_count, 0];
            (clipped_sampled, sampled_size, limits)
        };
        jobs.push(PrefilterJob {
            pipeline: 0,
            clipped,
            layer: set * SPECULAR_LEVELS + k,
            mip: m,
            size,
            params: PrefilterParams {
                size: [size.0, size.1, level0[0], level0[1]],
                source: [0; 4],
                layer: [alpha, lod0, roughness, geometry_id],
                limits,
            },
        });
    }
    for j in 0..=CONVOLVED_LEVELS {
        let size = (cw, cw / 2);
        jobs.push(PrefilterJob {
            pipeline: 1,
            clipped: clipped_mirror,
            layer: set * (CONVOLVED_LEVELS + 1) + j,
            mip: 0,
            size,
            params: PrefilterParams {
                size: [size.0, size.1, mirror_size[0], mirror_size[1]],
                source: [source.width, source.height, source_level, j],
                layer: [0.0; 4],
                limits: [0; 4],
            },
        });
    }
    jobs
}

/// Records `job` on `encoder`: its parameters' buffer, the view of its layer of `target`,
/// the bind group and the dispatch. Returns the buffer and group, kept until the submit.
fn encode_job(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    inputs: &PrefilterInputs<'_>,
    job: &PrefilterJob,
    target: &wgpu::Texture,
    pipeline: &wgpu::ComputePipeline,
    encoder: &mut wgpu::CommandEncoder,
) -> (wgpu::Buffer, wgpu::BindGroup) {
    let uniform = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("prefilter params"),
        size: std::mem::size_of::<PrefilterParams>() as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    queue.write_buffer(&uniform, 0, bytemuck::bytes_of(&job.params));
    let view = target.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2),
        base_mip_level: job.mip,
        mip_level_count: Some(1),
        base_array_layer: job.layer,
        array_layer_count: Some(1),
        ..Default::default()
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("prefilter"),
        layout: inputs.layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(if job.clipped {
                    inputs.clipped
                } else {
                    inputs.radiance
                }),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::Sampler(inputs.sampler),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::TextureView(&view),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: uniform.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: inputs.kernels.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 5,
                resource: inputs.bright.as_entire_binding(),
            },
        ],
    });
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups(job.size.0.div_ceil(8), job.size.1.div_ceil(8), 1);
    }
    (uniform, group)
}

/// What the prefiltered textures depend on: the map (by identity: scenes share it through
/// an `Arc`; the key holds a clone, so the address cannot be reused by another map while
/// the textures are kept) and the G of the tables the kernels and the split sum come from.
#[derive(Clone, Debug)]
pub(crate) struct EnvironmentKey {
    map: std::sync::Arc<crate::environment::EnvMap>,
    geometry: crate::brdf::Geometry,
}

impl PartialEq for EnvironmentKey {
    fn eq(&self, other: &Self) -> bool {
        std::sync::Arc::ptr_eq(&self.map, &other.map) && self.geometry == other.geometry
    }
}

impl EnvironmentKey {
    /// The key of `environment` shaded with `geometry`.
    pub(crate) fn new(environment: &Environment, geometry: crate::brdf::Geometry) -> Self {
        EnvironmentKey {
            map: environment.map.clone(),
            geometry,
        }
    }
}
