//! The truth on the GPU (docs/design/gpu-truth.md): balls with `model = "truth"` path
//! traced by the random walks of `walk.wgsl` (Heitz et al. 2016: the conductor's, and the
//! rough dielectric coating's over its Lambertian base, mixed by `metallic`), one estimate
//! per pixel a frame, summed in an `Rgba32Float` target.
//!
//! Each frame, an accumulation pass draws every ball's quad into the next of two sum
//! textures with a depth test: a truth ball adds one estimate to the previous texture's
//! sum at its pixel (`fs_truth`, which reads it with `textureLoad`: a float target of 32
//! bits is not blendable without a feature), another ball writes a zero sum where it is
//! in front (`fs_truth_occluder`). The sum's alpha counts the estimates, so neither the
//! generator's seed nor the resolve reads a frame counter from a uniform buffer. The
//! resolve (`fs_truth_resolve`) then writes each truth pixel's mean over what the ball
//! pass drew into the target (tone-mapped, or linear for a float target).
//!
//! The sums start again from zero whenever the scene (but its exposure) or the image size
//! changes ([`same_scene`]).

use std::collections::HashMap;
use std::sync::Arc;

use super::bindings::BallInstance;
use super::pipelines::{self, is_bits, PipelineKey, Shape, DEPTH_FORMAT};
use super::plan::Variant;
use super::renderer::QUAD_PAD_PX;
use super::shaders;
use super::uniforms::GpuBall;
use crate::brdf::Geometry;
use crate::lut::MuAxis;
use crate::scene::{Model, Scene, MAX_BALLS};

/// The accumulation's format: f32 sums (rgb) and the count of estimates (alpha).
pub(crate) const SUM_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// What a truth pipeline is compiled for: G, mu axis, variant, and the entry point's role.
type Key = (Geometry, MuAxis, Variant, Role);

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Role {
    /// `fs_truth` into the sums.
    Truth,
    /// `fs_truth_occluder` into the sums.
    Occluder,
    /// `fs_truth_resolve` into a target of this format (from the bits module for a bits
    /// target).
    Resolve(wgpu::TextureFormat),
}

/// What the accumulation and resolve passes draw with: the device, the bind groups 0 and
/// 1, and the pipelines' compile-time choices.
pub struct Draw<'a> {
    pub device: &'a wgpu::Device,
    pub queue: &'a wgpu::Queue,
    pub group0: &'a wgpu::BindGroup,
    pub group1: &'a wgpu::BindGroup,
    pub geometry: Geometry,
    pub mu_axis: MuAxis,
    pub variant: Variant,
}

/// The truth's layout (group 2), modules (float or display output, and bits output: each
/// created on first use), pipelines, quads and the running sums.
pub(crate) struct TruthPass {
    layout: wgpu::BindGroupLayout,
    modules: [Option<wgpu::ShaderModule>; 2],
    pipeline_layout: wgpu::PipelineLayout,
    pipelines: HashMap<Key, wgpu::RenderPipeline>,
    /// The accumulation pass's quads: the truth balls', then the others'.
    instances: wgpu::Buffer,
    sums: Option<Sums>,
}

/// Two sum textures (ping-pong), a bind group reading each, and the depth target.
struct Sums {
    /// The scene (map compared by identity: [`same_scene`]) and size summed.
    scene: Scene,
    size: (u32, u32),
    /// Kept alive with their views.
    _textures: [wgpu::Texture; 2],
    views: [wgpu::TextureView; 2],
    groups: [wgpu::BindGroup; 2],
    depth: wgpu::TextureView,
    /// The texture holding the latest sums.
    latest: usize,
    /// Estimates per truth pixel so far.
    frames: u32,
}

/// Whether two scenes give the same truth image but for its exposure and display transform
/// (the sums are linear radiance): equal but for the exposure, tone mapper and transfer
/// curve, with the same map (the same shared texels, turned and scaled alike), so that
/// no frame compares a map's texels.
pub fn same_scene(a: &Scene, b: &Scene) -> bool {
    let strip = |s: &Scene| Scene {
        environment_map: None,
        exposure: 1.0,
        tone_map: None,
        transfer: None,
        ..s.clone()
    };
    let maps = match (&a.environment_map, &b.environment_map) {
        (None, None) => true,
        (Some(x), Some(y)) => {
            Arc::ptr_eq(&x.map, &y.map)
                && x.rotation_deg == y.rotation_deg
                && x.intensity == y.intensity
        }
        _ => false,
    };
    maps && strip(a) == strip(b)
}

/// The accumulation pass's quads of `scene` at `size`: the truth balls', then the other
/// balls' (they hide what is behind them), each over its bounds without the antialiasing
/// pad (the walk traces one ray through each pixel's centre); `hidden` balls (by an
/// identical earlier one) are left out.
pub fn quads(
    scene: &Scene,
    balls: &[GpuBall],
    hidden: &[bool],
    size: (u32, u32),
) -> (Vec<BallInstance>, Vec<BallInstance>) {
    let (w, h) = size;
    let basis = scene.camera.basis(w, h);
    let (mut truth, mut others) = (Vec::new(), Vec::new());
    for (k, b) in scene.balls.iter().take(balls.len()).enumerate() {
        if hidden[k] {
            continue;
        }
        let Some(rect) = basis.sphere_bounds(b.center, b.radius, w, h, QUAD_PAD_PX) else {
            continue;
        };
        let quad = BallInstance {
            rect: rect.map(|v| v as f32),
            ball: balls[k],
        };
        if b.model == Model::Truth {
            truth.push(quad);
        } else {
            others.push(quad);
        }
    }
    (truth, others)
}

impl TruthPass {
    pub fn new(
        device: &wgpu::Device,
        group0: &wgpu::BindGroupLayout,
        group1: &wgpu::BindGroupLayout,
    ) -> Self {
        let layout = super::bindings::texture_load_layout(device, "truth sums");
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("truth"),
            bind_group_layouts: &[Some(group0), Some(group1), Some(&layout)],
            immediate_size: 0,
        });
        let instances = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("truth quads"),
            size: (std::mem::size_of::<BallInstance>() * MAX_BALLS) as u64,
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        TruthPass {
            layout,
            modules: [None, None],
            pipeline_layout,
            pipelines: HashMap::new(),
            instances,
            sums: None,
        }
    }

    /// Estimates per truth pixel of the latest accumulation (`None` before any).
    pub fn frames(&self) -> Option<u32> {
        self.sums.as_ref().map(|s| s.frames)
    }

    /// Starts the sums again from zero at the next frame.
    pub fn reset(&mut self) {
        if let Some(s) = &mut self.sums {
            s.frames = 0;
        }
    }

    /// Records one frame of estimates for `scene` at `size`: `truth` are the truth balls'
    /// quads, `others` the other balls' (they hide what is behind them). Restarts the sums
    /// if the scene or the size changed.
    pub fn accumulate(
        &mut self,
        draw: &Draw<'_>,
        encoder: &mut wgpu::CommandEncoder,
        scene: &Scene,
        size: (u32, u32),
        quads: (&[BallInstance], &[BallInstance]),
    ) {
        let (truth, others) = quads;
        let keep = self
            .sums
            .as_ref()
            .is_some_and(|s| s.size == size && same_scene(&s.scene, scene));
        if !keep {
            let fresh = match self.sums.take() {
                Some(mut s) if s.size == size => {
                    s.frames = 0;
                    s.scene = scene.clone();
                    s
                }
                _ => Sums::new(draw.device, &self.layout, scene.clone(), size),
            };
            self.sums = Some(fresh);
        }
        let truth_pipeline = self.pipeline(draw, Role::Truth).clone();
        let occluder_pipeline = self.pipeline(draw, Role::Occluder).clone();
        let mut all = truth.to_vec();
        all.extend_from_slice(others);
        all.truncate(MAX_BALLS);
        if !all.is_empty() {
            draw.queue
                .write_buffer(&self.instances, 0, bytemuck::cast_slice(&all));
        }
        let sums = self.sums.as_mut().expect("made above");
        if sums.frames == 0 {
            // The first frame reads zero sums.
            clear(encoder, &sums.views[sums.latest]);
        }
        let next = 1 - sums.latest;
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("truth accumulation"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &sums.views[next],
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &sums.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            ..Default::default()
        });
        pass.set_bind_group(0, draw.group0, &[]);
        pass.set_bind_group(1, draw.group1, &[]);
        pass.set_bind_group(2, &sums.groups[sums.latest], &[]);
        let stride = std::mem::size_of::<BallInstance>() as u64;
        let n_truth = truth.len().min(all.len());
        for (pipeline, range) in [
            (&truth_pipeline, 0..n_truth),
            (&occluder_pipeline, n_truth..all.len()),
        ] {
            if range.is_empty() {
                continue;
            }
            pass.set_pipeline(pipeline);
            let bytes = range.start as u64 * stride..range.end as u64 * stride;
            pass.set_vertex_buffer(0, self.instances.slice(bytes));
            pass.draw(0..4, 0..range.len() as u32);
        }
        drop(pass);
        sums.latest = next;
        sums.frames = sums.frames.saturating_add(1);
    }

    /// Records the resolve of the latest sums into `view` (of `format`), over the
    /// `size` rectangle at its top-left corner, keeping what is drawn there elsewhere.
    pub fn resolve(
        &mut self,
        draw: &Draw<'_>,
        encoder: &mut wgpu::CommandEncoder,
        view: &wgpu::TextureView,
        format: wgpu::TextureFormat,
        size: (u32, u32),
    ) {
        let pipeline = self.pipeline(draw, Role::Resolve(format)).clone();
        let Some(sums) = &self.sums else {
            return;
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("truth resolve"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            ..Default::default()
        });
        let (w, h) = sums.size.min(size);
        pass.set_viewport(0.0, 0.0, w as f32, h as f32, 0.0, 1.0);
        pass.set_scissor_rect(0, 0, w, h);
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, draw.group0, &[]);
        pass.set_bind_group(1, draw.group1, &[]);
        pass.set_bind_group(2, &sums.groups[sums.latest], &[]);
        pass.draw(0..3, 0..1);
    }

    /// The pipeline of `role` for `draw`'s choices, created on first use.
    fn pipeline(&mut self, draw: &Draw<'_>, role: Role) -> &wgpu::RenderPipeline {
        let key = (draw.geometry, draw.mu_axis, draw.variant, role);
        let bits = matches!(role, Role::Resolve(f) if is_bits(f));
        let module = self.modules[bits as usize].get_or_insert_with(|| {
            draw.device
                .create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some(if bits { "truth bits" } else { "truth" }),
                    source: wgpu::ShaderSource::Wgsl(shaders::truth_source(bits).into()),
                })
        });
        let layout = &self.pipeline_layout;
        self.pipelines
            .entry(key)
            .or_insert_with(|| create(draw, layout, module, role))
    }
}

/// Clears a sum texture to zero (no draw).
fn clear(encoder: &mut wgpu::CommandEncoder, view: &wgpu::TextureView) {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("truth reset"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                store: wgpu::StoreOp::Store,
            },
        })],
        ..Default::default()
    });
}

impl Sums {
    fn new(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        scene: Scene,
        size: (u32, u32),
    ) -> Self {
        let extent = wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: 1,
        };
        let texture = |label, format, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: extent,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let textures = [
            texture("truth sums", SUM_FORMAT, usage),
            texture("truth sums", SUM_FORMAT, usage),
        ];
        let views = [
            textures[0].create_view(&Default::default()),
            textures[1].create_view(&Default::default()),
        ];
        let group = |view: &wgpu::TextureView| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("truth sums"),
                layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(view),
                }],
            })
        };
        let groups = [group(&views[0]), group(&views[1])];
        let depth = texture(
            "truth depth",
            DEPTH_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        )
        .create_view(&Default::default());
        Sums {
            scene,
            size,
            _textures: textures,
            views,
            groups,
            depth,
            latest: 0,
            frames: 0,
        }
    }
}

/// A truth pipeline: the per-ball quads into the sums (with the depth test) for
/// [`Role::Truth`] and [`Role::Occluder`], the full-screen triangle into a target for
/// [`Role::Resolve`].
fn create(
    draw: &Draw<'_>,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    role: Role,
) -> wgpu::RenderPipeline {
    let quads = [Some(BallInstance::LAYOUT)];
    let (format, shape) = match role {
        Role::Truth | Role::Occluder => (
            SUM_FORMAT,
            Shape {
                label: "truth",
                vs: shaders::VS_BALL,
                fs: if role == Role::Truth {
                    shaders::FS_TRUTH
                } else {
                    shaders::FS_TRUTH_OCCLUDER
                },
                buffers: &quads,
                topology: wgpu::PrimitiveTopology::TriangleStrip,
                depth: Some((true, wgpu::CompareFunction::Less)),
            },
        ),
        Role::Resolve(f) => (
            f,
            Shape {
                label: "truth resolve",
                vs: shaders::VS_MAIN,
                fs: shaders::FS_TRUTH_RESOLVE,
                buffers: &[],
                topology: wgpu::PrimitiveTopology::TriangleList,
                depth: None,
            },
        ),
    };
    let key = PipelineKey {
        format,
        geometry: draw.geometry,
        mu_axis: draw.mu_axis,
        variant: draw.variant,
    };
    pipelines::create(draw.device, layout, module, key, shape)
}
