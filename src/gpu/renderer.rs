//! The ball renderer: plans each scene (`scene::Plan`: which tables, which shader
//! variants), bakes and binds what the plan needs (`tables.rs`), and draws into any colour
//! target: each ball's quad over its screen-space bounds with its variant's pipeline, the
//! background a clear (`balls.wgsl`). A window reuses [`Renderer::render`] with its
//! surface view.

use std::collections::HashMap;
use std::time::Duration;

use super::resources::{BallInstance, Resources};
use super::tables::{Bound, TableCache};
use super::{shaders, uniforms, Gpu};
use crate::brdf::{FAvgForm, Geometry};
use crate::error::Result;
use crate::lut::BakeConfig;
use crate::scene::{DrawOptions, Plan, Scene, TablePolicy, Variant};

/// Where to draw: a view of a texture of `format`; the image is `width x height` pixels at
/// its top-left corner (the whole texture for a headless render, the scene area left of
/// the viewer's panel in a window; the rest of the texture is cleared only).
/// Float formats receive linear radiance (for EXR); others the tone-mapped value.
#[derive(Clone, Copy)]
pub struct Target<'a> {
    pub view: &'a wgpu::TextureView,
    pub format: wgpu::TextureFormat,
    pub width: u32,
    pub height: u32,
}

/// Whether `format` gets linear radiance rather than display values.
pub fn is_linear(format: wgpu::TextureFormat) -> bool {
    matches!(
        format,
        wgpu::TextureFormat::Rgba32Float
            | wgpu::TextureFormat::Rgba16Float
            | wgpu::TextureFormat::R32Float
    )
}

/// Target format, G, f_add form, per-ball quads (or the full-screen triangle), variant.
type PipelineKey = (wgpu::TextureFormat, Geometry, FAvgForm, bool, Variant);

/// Device, shader module, pipelines, the plan of the latest scene and its tables.
pub struct Renderer {
    pub(super) gpu: Gpu,
    pub(super) resources: Resources,
    module: wgpu::ShaderModule,
    pub(super) pipeline_layout: wgpu::PipelineLayout,
    pipelines: HashMap<PipelineKey, wgpu::RenderPipeline>,
    /// The tables bound now and their bind group.
    pub(super) bound: Option<Bound>,
    /// Baked rows and the latest 2-D table.
    pub(super) cache: TableCache,
    /// `set_tables` was called: its table is used whatever the plan.
    pub(super) pinned: bool,
    options: DrawOptions,
    /// How tables are baked; its `geometry` is replaced by the scene's.
    pub(super) bake_config: BakeConfig,
    /// Wall time of the latest bake, if any.
    pub(super) last_bake: Option<Duration>,
    plan: Option<Plan>,
}

impl Renderer {
    pub fn new(gpu: Gpu) -> Self {
        let device = &gpu.device;
        let resources = Resources::new(device);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("balls"),
            source: wgpu::ShaderSource::Wgsl(shaders::balls_source().into()),
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("balls"),
            bind_group_layouts: &[Some(&resources.layout)],
            immediate_size: 0,
        });
        Renderer {
            gpu,
            resources,
            module,
            pipeline_layout,
            pipelines: HashMap::new(),
            bound: None,
            cache: TableCache::default(),
            pinned: false,
            options: DrawOptions::default(),
            bake_config: BakeConfig::default(),
            last_bake: None,
            plan: None,
        }
    }

    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// Compiles the multiple-scattering term in where balls use it (`true`, the default) or
    /// out of every pipeline from now on; out, the image equals the one with every ball's
    /// flag off (`shadeballs bench` measures what the term costs with it).
    pub fn set_multiple_scattering_term(&mut self, on: bool) {
        self.options.term = on;
    }

    /// How the next draws plan and draw (default: [`DrawOptions::default`], planned;
    /// [`DrawOptions::unplanned`] is the design before planning, for comparison).
    pub fn set_draw_options(&mut self, options: DrawOptions) {
        self.options = options;
    }

    pub fn draw_options(&self) -> DrawOptions {
        self.options
    }

    /// The plan of `scene` under the current options (nothing baked or bound).
    fn make_plan(&self, scene: &Scene) -> Plan {
        let mut options = self.options;
        if self.pinned {
            options.tables = TablePolicy::Full;
        }
        Plan::new(scene, self.bake_config, options)
    }

    /// Plans `scene`, bakes what the plan needs and is not cached, and binds it; returns
    /// the plan. Cheap when nothing changed (a pass over the balls).
    pub fn plan_for(&mut self, scene: &Scene) -> &Plan {
        let plan = self.make_plan(scene);
        let changed = self
            .plan
            .as_ref()
            .is_none_or(|p| p.tables != plan.tables || p.bake != plan.bake);
        if changed {
            // A change that bakes nothing reports zero (ensure_tables sets any bake).
            self.last_bake = Some(Duration::ZERO);
        }
        self.ensure_tables(&plan);
        self.bake_config = plan.bake;
        self.plan.insert(plan)
    }

    /// The plan of the latest scene planned or drawn.
    pub fn plan(&self) -> Option<&Plan> {
        self.plan.as_ref()
    }

    /// Creates, if not yet held, the pipelines that draw `scene` into `format` (otherwise
    /// created at the first draw), so that their cost can be timed apart.
    pub fn prepare(&mut self, scene: &Scene, format: wgpu::TextureFormat) {
        let plan = self.make_plan(scene);
        for variant in plan.variants() {
            self.pipeline((
                format,
                plan.geometry,
                scene.preset.f_avg_form(),
                plan.per_ball,
                variant,
            ));
        }
    }

    /// Bakes with `config` (layout, estimator, samples; its geometry is ignored) from the
    /// next draw on, planning the tables again (after [`Renderer::set_tables`]); what is
    /// held is kept where it already matches.
    pub fn set_bake_config(&mut self, config: BakeConfig) {
        self.bake_config = config;
        self.pinned = false;
    }

    /// The bake settings in use (`geometry` is the last one baked for).
    pub fn bake_config(&self) -> BakeConfig {
        self.bake_config
    }

    /// Wall time of the latest bake this renderer did itself: after planning, of the rows
    /// or table baked for the latest change of plan, zero when that change baked nothing
    /// (no table needed, or every row cached); `None` before any.
    pub fn last_bake_time(&self) -> Option<Duration> {
        self.last_bake
    }

    fn pipeline(&mut self, key: PipelineKey) -> &wgpu::RenderPipeline {
        let (format, geometry, form, per_ball, variant) = key;
        let device = &self.gpu.device;
        let (module, layout) = (&self.module, &self.pipeline_layout);
        self.pipelines.entry(key).or_insert_with(|| {
            let constants = shaders::overrides_for(geometry, form, is_linear(format), variant);
            let options = wgpu::PipelineCompilationOptions {
                constants: &constants,
                ..Default::default()
            };
            let (vs, fs, buffers): (_, _, &[Option<wgpu::VertexBufferLayout>]) = if per_ball {
                (
                    shaders::VS_BALL,
                    shaders::FS_BALL,
                    &[Some(BallInstance::LAYOUT)],
                )
            } else {
                (shaders::VS_MAIN, shaders::FS_MAIN, &[])
            };
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("balls"),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module,
                    entry_point: Some(vs),
                    compilation_options: options.clone(),
                    buffers,
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: None,
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module,
                    entry_point: Some(fs),
                    compilation_options: options,
                    targets: &[Some(wgpu::ColorTargetState {
                        format,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        })
    }

    /// Records the draw of `scene` into `target` on `encoder` (plans the scene, bakes what
    /// its plan needs and is not cached, uploads uniforms and quads now).
    pub fn encode(
        &mut self,
        scene: &Scene,
        target: Target<'_>,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        let plan = self.plan_for(scene).clone();
        let bound = self.bound.as_ref().expect("ensure_tables binds");
        let read = bound.read.clone();
        let bind = bound.bind.clone();
        let queue = &self.gpu.queue;
        let (w, h) = (target.width, target.height);
        let globals = uniforms::globals(scene, &read, w, h);
        queue.write_buffer(&self.resources.globals, 0, bytemuck::bytes_of(&globals));
        let balls = uniforms::balls(scene, &read);
        if !balls.is_empty() {
            queue.write_buffer(&self.resources.balls, 0, bytemuck::cast_slice(&balls));
        }
        let lights = uniforms::lights(scene);
        if !lights.is_empty() {
            queue.write_buffer(&self.resources.lights, 0, bytemuck::cast_slice(&lights));
        }
        // Per variant: its pipeline and the range of its quads in the instance buffer.
        let mut draws = Vec::new();
        let mut quads: Vec<BallInstance> = Vec::new();
        let basis = scene.camera.basis(w, h);
        for (variant, members) in &plan.draws {
            let start = quads.len() as u32;
            if plan.per_ball {
                quads.extend(members.iter().filter_map(|&k| {
                    let b = &scene.balls[k];
                    let rect = basis.sphere_bounds(b.center, b.radius, w, h, QUAD_PAD_PX)?;
                    Some(BallInstance {
                        rect: rect.map(|v| v as f32),
                        ball: k as u32,
                    })
                }));
            }
            let key = (
                target.format,
                plan.geometry,
                scene.preset.f_avg_form(),
                plan.per_ball,
                *variant,
            );
            draws.push((self.pipeline(key).clone(), start..quads.len() as u32));
        }
        if !quads.is_empty() {
            let queue = &self.gpu.queue;
            queue.write_buffer(&self.resources.instances, 0, bytemuck::cast_slice(&quads));
        }
        let clear = if plan.per_ball {
            background(scene, target.format)
        } else {
            wgpu::Color::BLACK
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("balls"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target.view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(clear),
                    store: wgpu::StoreOp::Store,
                },
            })],
            ..Default::default()
        });
        // The image's rectangle: the whole target headless, the scene area in a window.
        pass.set_viewport(0.0, 0.0, w as f32, h as f32, 0.0, 1.0);
        pass.set_scissor_rect(0, 0, w, h);
        pass.set_bind_group(0, &bind, &[]);
        let stride = std::mem::size_of::<BallInstance>() as u64;
        for (pipeline, range) in draws {
            pass.set_pipeline(&pipeline);
            if plan.per_ball {
                if range.is_empty() {
                    continue;
                }
                let bytes = range.start as u64 * stride..range.end as u64 * stride;
                pass.set_vertex_buffer(0, self.resources.instances.slice(bytes));
                pass.draw(0..6, 0..range.len() as u32);
            } else {
                pass.draw(0..3, 0..1);
            }
        }
    }

    /// Draws `scene` into `target` and submits.
    pub fn render(&mut self, scene: &Scene, target: Target<'_>) -> Result<()> {
        self.gpu.check()?;
        let scopes = super::Scopes::push(&self.gpu.device);
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        self.encode(scene, target, &mut encoder);
        self.gpu.queue.submit([encoder.finish()]);
        scopes.pop()?;
        self.gpu.check()
    }
}

/// Pixels added around each ball's exact bounds: the shader's f32 ray may hit a pixel
/// whose centre the f64 silhouette just misses.
pub const QUAD_PAD_PX: f64 = 2.0;

/// The clear colour: what the shader would give a pixel that hits no ball (the
/// environment, linear on a float target, else through `tone_map`, the CPU renderer's f64
/// mirror of the shader's).
fn background(scene: &Scene, format: wgpu::TextureFormat) -> wgpu::Color {
    let env = scene.environment;
    let value = |c: f64| {
        if is_linear(format) {
            c as f32 as f64
        } else {
            crate::cpu::tone_map(c, scene.exposure)
        }
    };
    wgpu::Color {
        r: value(env.x),
        g: value(env.y),
        b: value(env.z),
        a: 1.0,
    }
}
