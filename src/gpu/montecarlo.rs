//! The Monte Carlo of the model on the GPU ([`super::Renderer::render_montecarlo`];
//! `shaders/montecarlo.wgsl`; docs/design/environment.md, "The Monte Carlo backend"): the
//! CPU estimator's strategies and weights (`crate::cpu::montecarlo`) in f32, one pass of
//! [`PASS_SAMPLES`] estimates a pixel at a time, so a large `spp` runs as many short
//! draws (no watchdog-length dispatch) and a caller may stop after any pass.
//!
//! Each pass draws every ball's quad with a depth test into two `Rgba32Float` targets:
//! the mean (rgb) with the count of estimates (alpha), and the sum of squared deviations
//! from it (rgb), read by the next pass from the other pair of textures (ping-pong: a
//! float target of 32 bits is not blendable without a feature). The map's luminance
//! tables ([`LuminanceCdf`], the CPU sampler's weights) ride in a storage buffer.

use std::collections::HashMap;

use glam::DVec3;
use wgpu::util::DeviceExt as _;

use super::bindings::BallInstance;
use super::pipelines::DEPTH_FORMAT;
use super::plan::Variant;
use super::readback::Readback;
use super::shaders;
use super::specialise::ParsedProgram;
use super::sums::{self, Sums, SumsSpec, SUM_FORMAT};
use super::uniforms::GpuBall;
use super::Gpu;
use crate::brdf::Geometry;
use crate::environment::sampler::LuminanceCdf;
use crate::error::{Error, Result};
use crate::lut::MuAxis;
use crate::scene::Scene;
use crate::stats::{MonteCarloImage, Part};

/// Estimates a pixel each pass draws (the last pass draws the rest): 16 keeps a pass of a
/// 1280x720 frame of metal balls under a second on lavapipe (docs/design/environment.md,
/// "The Monte Carlo backend").
pub(crate) const PASS_SAMPLES: u32 = 16;

/// `McParams.strategies`' bits (`montecarlo.wgsl`): GGX visible normals, the cosine
/// hemisphere, the map's luminance.
const STRATEGY_VNDF: u32 = 1;
const STRATEGY_COSINE: u32 = 2;
const STRATEGY_MAP: u32 = 4;

/// `McParams.shape`: every step of `estimate` on (the shader branches on these bits, a
/// uniform value, where lavapipe crashed running the same steps without the branches).
const SHAPE_ALL: u32 = 7;

/// The shader's `McParams` (group 2, binding 2; member for member: `gpu::boundary`).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct McParams {
    pub(crate) seed: [u32; 2],
    pub(crate) pass_index: u32,
    pub(crate) lit: u32,
    pub(crate) map_size: [u32; 2],
    pub(crate) strategies: u32,
    pub(crate) shape: u32,
    /// [`PART_WHOLE`] or [`PART_MULTIPLE`].
    pub(crate) part: u32,
    pub(crate) padding: u32,
}

/// `McParams.part`: the whole model, or the term's lobe alone ([`Part`]).
const PART_WHOLE: u32 = 0;
const PART_MULTIPLE: u32 = 1;

/// What a Monte Carlo pass draws with: the frame's bind groups 0 and 1, its balls (and
/// those hidden by an identical earlier one), the pipelines' choices and the image size.
pub(crate) struct McFrame<'a> {
    pub group0: &'a wgpu::BindGroup,
    pub group1: &'a wgpu::BindGroup,
    pub balls: &'a [GpuBall],
    pub hidden: &'a [bool],
    pub geometry: Geometry,
    pub mu_axis: MuAxis,
    pub variant: Variant,
    pub size: (u32, u32),
    /// The part of the model integrated.
    pub part: Part,
}

/// Group 2's layout, the program, the pipelines by their choices and samples a pass, and
/// the quads' buffer.
pub(crate) struct MonteCarloPass {
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    program: Option<ParsedProgram>,
    pipelines: HashMap<(Geometry, MuAxis, Variant, u32), wgpu::RenderPipeline>,
    instances: wgpu::Buffer,
}

impl MonteCarloPass {
    pub(crate) fn new(
        device: &wgpu::Device,
        group0: &wgpu::BindGroupLayout,
        group1: &wgpu::BindGroupLayout,
    ) -> Self {
        let layout = group2_layout(device);
        MonteCarloPass {
            pipeline_layout: sums::pipeline_layout(device, "montecarlo", [group0, group1, &layout]),
            layout,
            program: None,
            pipelines: HashMap::new(),
            instances: sums::quad_buffer(device, "montecarlo quads"),
        }
    }

    /// Renders `spp` estimates a covered pixel of `scene` with `seed`, in passes of
    /// [`PASS_SAMPLES`]; after each pass `keep_going(samples so far)` may stop it (the
    /// image then holds the passes done). The background comes from [`fill_background`].
    pub(crate) fn render(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        frame: &McFrame<'_>,
        (spp, seed): (u32, u64),
        mut keep_going: impl FnMut(u32) -> bool,
    ) -> Result<MonteCarloImage> {
        let device = &gpu.device;
        let quads = quads(scene, frame);
        if !quads.is_empty() {
            gpu.queue
                .write_buffer(&self.instances, 0, bytemuck::cast_slice(&quads));
        }
        let (params, cdf) = inputs(gpu, scene, seed, frame.part)?;
        // Two targets a side: the mean with the count of estimates, and the squared
        // deviations; the parameters and the luminance tables bound after them.
        let spec = SumsSpec {
            label: "montecarlo state",
            format: SUM_FORMAT,
            targets: 2,
            size: frame.size,
            copy_src: true,
            depth: true,
        };
        let trailing = [params.0.as_entire_binding(), cdf.as_entire_binding()];
        let mut state = Sums::new(device, &self.layout, spec, &[], &trailing);
        let mut encoder = device.create_command_encoder(&Default::default());
        state.clear_if_empty(&mut encoder);
        gpu.queue.submit([encoder.finish()]);
        let (mut done, mut pass_index) = (0u32, 0u32);
        while done < spp {
            let k = PASS_SAMPLES.min(spp - done);
            let pipeline = self.pipeline(device, frame, k).clone();
            let mut p: McParams = bytemuck::pod_read_unaligned(&params.1);
            p.pass_index = pass_index;
            gpu.queue.write_buffer(&params.0, 0, bytemuck::bytes_of(&p));
            let mut encoder = device.create_command_encoder(&Default::default());
            let zero = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
            let mut pass = state.next_pass(&mut encoder, (frame.group0, frame.group1), zero);
            if !quads.is_empty() {
                pass.set_pipeline(&pipeline);
                pass.set_vertex_buffer(0, self.instances.slice(..));
                pass.draw(0..4, 0..quads.len() as u32);
            }
            drop(pass);
            gpu.queue.submit([encoder.finish()]);
            let _ = device.poll(wgpu::PollType::wait_indefinitely());
            gpu.check()?;
            state.advance();
            done += k;
            pass_index += 1;
            if done < spp && !keep_going(done) {
                break;
            }
        }
        let mut image = read_state(gpu, &state, frame.size, done)?;
        image.antialias = frame.variant.aa;
        fill_background(scene, &mut image);
        Ok(image)
    }

    /// The pipeline of `frame`'s choices drawing `k` estimates a pass, created on first use.
    fn pipeline(
        &mut self,
        device: &wgpu::Device,
        frame: &McFrame<'_>,
        k: u32,
    ) -> &wgpu::RenderPipeline {
        let key = (frame.geometry, frame.mu_axis, frame.variant, k);
        let program = self
            .program
            .get_or_insert_with(|| ParsedProgram::new("montecarlo", shaders::montecarlo_source()));
        let layout = &self.pipeline_layout;
        self.pipelines
            .entry(key)
            .or_insert_with(|| create_pipeline(device, layout, program, key))
    }
}

/// The parameters' buffer (and its bytes before the pass index is set) and the luminance
/// tables' buffer of `scene`'s map (one zero where it has no sampler). Fails where the
/// tables exceed the device's storage binding.
fn inputs(
    gpu: &Gpu,
    scene: &Scene,
    seed: u64,
    part: Part,
) -> Result<((wgpu::Buffer, Vec<u8>), wgpu::Buffer)> {
    let map = scene.environment_map.as_ref();
    let lit = scene.environment != DVec3::ZERO || map.is_some_and(|m| !m.is_black());
    let cdf = map.and_then(LuminanceCdf::of);
    let params = McParams {
        seed: [seed as u32, (seed >> 32) as u32],
        pass_index: 0,
        lit: u32::from(lit),
        map_size: cdf.as_ref().map_or([1, 1], |c| [c.width, c.height]),
        strategies: STRATEGY_VNDF | STRATEGY_COSINE | if cdf.is_some() { STRATEGY_MAP } else { 0 },
        shape: SHAPE_ALL,
        part: match part {
            Part::Whole => PART_WHOLE,
            Part::Multiple => PART_MULTIPLE,
        },
        padding: 0,
    };
    let tables: Vec<f32> = match &cdf {
        Some(c) => c.table_words(),
        None => vec![0.0],
    };
    let bytes = std::mem::size_of_val(tables.as_slice()) as u64;
    let max = gpu.device.limits().max_storage_buffer_binding_size;
    if bytes > max {
        return Err(Error::Invalid {
            what: "environment",
            message: format!(
                "the map's luminance tables need {bytes} bytes; this device binds {max} \
                 (use a smaller map, or --backend montecarlo-cpu)"
            ),
        });
    }
    let device = &gpu.device;
    let bytes = bytemuck::bytes_of(&params).to_vec();
    let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("montecarlo params"),
        contents: &bytes,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
    });
    let storage = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("montecarlo luminance tables"),
        contents: bytemuck::cast_slice(&tables),
        usage: wgpu::BufferUsages::STORAGE,
    });
    Ok(((uniform, bytes), storage))
}

/// Every ball's quad over its bounds without the antialiasing pad (one ray through each
/// pixel's centre, as the CPU estimator), but those hidden by an identical earlier ball.
fn quads(scene: &Scene, frame: &McFrame<'_>) -> Vec<BallInstance> {
    let all = 0..scene.balls.len();
    sums::quads(
        scene,
        (frame.balls, frame.hidden),
        frame.size,
        crate::scene::bounds_pad_px(frame.variant.aa),
        all,
    )
}

/// Group 2: the two state textures (read with `textureLoad`), the parameters and the
/// luminance tables.
fn group2_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let texture = |binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    };
    let buffer = |binding, ty| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("montecarlo state"),
        entries: &[
            texture(0),
            texture(1),
            buffer(2, wgpu::BufferBindingType::Uniform),
            buffer(3, wgpu::BufferBindingType::Storage { read_only: true }),
        ],
    })
}

/// Fills the pixels of `image` no ball covers with `scene`'s background along each
/// pixel's ray ([`Scene::background_along`], as the CPU estimator).
fn fill_background(scene: &Scene, image: &mut MonteCarloImage) {
    let (width, height) = (image.width, image.height);
    let basis = scene.camera.basis(width, height);
    for (k, (m, &c)) in image.mean.iter_mut().zip(&image.covered).enumerate() {
        if !c {
            let (px, py) = ((k as u32) % width, (k as u32) / width);
            *m = scene.background_along(basis.ray(px, py, width, height));
        }
    }
}

/// Reads the latest pair back into an image of `spp` estimates a covered pixel: the mean,
/// and the standard error `sqrt(M2 / ((n - 1) n))` (0 where `n < 2`); a pixel no ball
/// covers (count 0) is left black for [`fill_background`].
fn read_state(
    gpu: &Gpu,
    state: &Sums,
    (width, height): (u32, u32),
    spp: u32,
) -> Result<MonteCarloImage> {
    let device = &gpu.device;
    let readbacks = [
        Readback::new(device, SUM_FORMAT, (width, height))?,
        Readback::new(device, SUM_FORMAT, (width, height))?,
    ];
    let mut encoder = device.create_command_encoder(&Default::default());
    for (r, t) in readbacks.iter().zip(state.latest_textures()) {
        r.record(&mut encoder, t);
    }
    gpu.queue.submit([encoder.finish()]);
    gpu.check()?;
    let [mean, m2] = readbacks;
    let mean: Vec<f32> = bytemuck::pod_collect_to_vec(&mean.read(device)?);
    let m2: Vec<f32> = bytemuck::pod_collect_to_vec(&m2.read(device)?);
    gpu.check()?;
    let pixels = (width as usize) * (height as usize);
    let mut image = MonteCarloImage {
        width,
        height,
        spp,
        mean: Vec::with_capacity(pixels),
        std_error: Vec::with_capacity(pixels),
        covered: Vec::with_capacity(pixels),
        // Set by the caller: the pipeline's AA.
        antialias: false,
    };
    for (m, s) in mean.chunks_exact(4).zip(m2.chunks_exact(4)) {
        let n = f64::from(m[3]);
        let mean = DVec3::new(m[0].into(), m[1].into(), m[2].into());
        let m2 = DVec3::new(s[0].into(), s[1].into(), s[2].into()).max(DVec3::ZERO);
        let err = if n >= 2.0 {
            (m2 / ((n - 1.0) * n)).powf(0.5)
        } else {
            DVec3::ZERO
        };
        image.mean.push(mean);
        image.std_error.push(err);
        image.covered.push(n > 0.0);
    }
    Ok(image)
}

/// A Monte Carlo pipeline: the per-ball quads into the two state targets with the depth
/// test, compiled with the variant's override constants, the term a branch on each
/// ball's flag (`MS_TERM = 1`), and `MC_SAMPLES = k`.
fn create_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    program: &ParsedProgram,
    (geometry, mu_axis, variant, k): (Geometry, MuAxis, Variant, u32),
) -> wgpu::RenderPipeline {
    let mut constants: Vec<(&str, f64)> =
        shaders::overrides_for(geometry, true, mu_axis, variant, false).to_vec();
    for c in &mut constants {
        if c.0 == "MS_TERM" {
            c.1 = 1.0;
        }
    }
    constants.push(("MC_SAMPLES", f64::from(k)));
    let vertex = program.stage(
        device,
        naga::ShaderStage::Vertex,
        shaders::VS_BALL,
        &constants,
    );
    let fragment = program.stage(
        device,
        naga::ShaderStage::Fragment,
        shaders::FS_MONTECARLO,
        &constants,
    );
    let target = Some(wgpu::ColorTargetState {
        format: SUM_FORMAT,
        blend: None,
        write_mask: wgpu::ColorWrites::ALL,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("montecarlo"),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module: &vertex.module,
            entry_point: Some(shaders::VS_BALL),
            compilation_options: vertex.options(),
            buffers: &[Some(BallInstance::LAYOUT)],
        },
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleStrip,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        }),
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module: &fragment.module,
            entry_point: Some(shaders::FS_MONTECARLO),
            compilation_options: fragment.options(),
            targets: &[target.clone(), target],
        }),
        multiview_mask: None,
        cache: None,
    })
}
