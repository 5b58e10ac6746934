//! The ball renderer: one full-screen draw into any colour target (see `balls.wgsl` for why
//! a full-screen triangle). A window reuses [`Renderer::render`] with its surface view.

use std::collections::HashMap;
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::resources::Resources;
use super::{shaders, uniforms, Gpu};
use crate::brdf::{FAvgForm, Geometry};
use crate::error::Result;
use crate::lut::{self, BakeConfig, Tables};
use crate::scene::Scene;

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

/// Target format, G, f_add form, multiple-scattering term compiled in.
type PipelineKey = (wgpu::TextureFormat, Geometry, FAvgForm, bool);

/// Device, shader modules, pipelines and the tables of the current geometry.
pub struct Renderer {
    pub(super) gpu: Gpu,
    pub(super) resources: Resources,
    module: wgpu::ShaderModule,
    pub(super) pipeline_layout: wgpu::PipelineLayout,
    pipelines: HashMap<PipelineKey, wgpu::RenderPipeline>,
    pub(super) tables: Option<(Arc<Tables>, wgpu::BindGroup)>,
    /// Whether pipelines compile the multiple-scattering term in (`MS_TERM`).
    ms_term: bool,
    /// How tables are baked; its `geometry` is replaced by the scene's.
    bake_config: BakeConfig,
    /// Wall time of the latest bake, if any.
    last_bake: Option<Duration>,
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
            tables: None,
            ms_term: true,
            bake_config: BakeConfig::default(),
            last_bake: None,
        }
    }

    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// Compiles the multiple-scattering term in (`true`, the default) or out of the ball
    /// shader from now on; out, the image equals the one with every ball's flag off
    /// (`shadeballs bench` measures what the term costs with it).
    pub fn set_multiple_scattering_term(&mut self, on: bool) {
        self.ms_term = on;
    }

    /// Creates, if not yet held, the pipeline that draws `scene` into `format` (otherwise
    /// created at the first draw), so that its cost can be timed apart.
    pub fn prepare(&mut self, scene: &Scene, format: wgpu::TextureFormat) {
        let key = (
            format,
            scene.effective_geometry(),
            scene.preset.f_avg_form(),
            self.ms_term,
        );
        self.pipeline(key);
    }

    /// Bakes with `config` (layout, estimator, samples; its geometry is ignored) from the
    /// next draw on; the held tables are kept if they already match.
    pub fn set_bake_config(&mut self, config: BakeConfig) {
        self.bake_config = config;
    }

    /// The bake settings in use (`geometry` is the last one baked for).
    pub fn bake_config(&self) -> BakeConfig {
        self.bake_config
    }

    /// Wall time of the latest bake this renderer did itself, if any.
    pub fn last_bake_time(&self) -> Option<Duration> {
        self.last_bake
    }

    /// Uses `tables` (baked for their `config.geometry`) from now on, and bakes with their
    /// config when the geometry changes.
    pub fn set_tables(&mut self, tables: Arc<Tables>) {
        self.bake_config = tables.config;
        let bind = self
            .resources
            .bind_tables(&self.gpu.device, &self.gpu.queue, &tables);
        self.tables = Some((tables, bind));
    }

    /// The tables for `geometry`, baked with the bake config (default: layout and
    /// estimator of [`BakeConfig::default`]) if not yet held.
    pub fn tables_for(&mut self, geometry: Geometry) -> Arc<Tables> {
        self.bake_config.geometry = geometry;
        match &self.tables {
            Some((t, _)) if t.config == self.bake_config => t.clone(),
            _ => {
                let start = Instant::now();
                let tables = Arc::new(lut::bake(&self.bake_config));
                self.last_bake = Some(start.elapsed());
                self.set_tables(tables.clone());
                tables
            }
        }
    }

    fn pipeline(&mut self, key: PipelineKey) -> &wgpu::RenderPipeline {
        let (format, geometry, form, term) = key;
        let device = &self.gpu.device;
        let (module, layout) = (&self.module, &self.pipeline_layout);
        self.pipelines.entry(key).or_insert_with(|| {
            let constants = shaders::overrides_with_term(geometry, form, is_linear(format), term);
            let options = wgpu::PipelineCompilationOptions {
                constants: &constants,
                ..Default::default()
            };
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("balls"),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module,
                    entry_point: Some(shaders::VS_MAIN),
                    compilation_options: options.clone(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: None,
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module,
                    entry_point: Some(shaders::FS_MAIN),
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

    /// Records the draw of `scene` into `target` on `encoder` (uploads uniforms now; bakes
    /// tables if the scene's geometry changed).
    pub fn encode(
        &mut self,
        scene: &Scene,
        target: Target<'_>,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        let geometry = scene.effective_geometry();
        let tables = self.tables_for(geometry);
        let queue = &self.gpu.queue;
        let globals = uniforms::globals(scene, &tables, target.width, target.height);
        queue.write_buffer(&self.resources.globals, 0, bytemuck::bytes_of(&globals));
        let balls = uniforms::balls(scene, &tables);
        if !balls.is_empty() {
            queue.write_buffer(&self.resources.balls, 0, bytemuck::cast_slice(&balls));
        }
        let lights = uniforms::lights(scene);
        if !lights.is_empty() {
            queue.write_buffer(&self.resources.lights, 0, bytemuck::cast_slice(&lights));
        }
        let pipeline = self
            .pipeline((
                target.format,
                geometry,
                scene.preset.f_avg_form(),
                self.ms_term,
            ))
            .clone();
        let bind = &self.tables.as_ref().expect("tables bound above").1;
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("balls"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target.view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            ..Default::default()
        });
        // The image's rectangle: the whole target headless, the scene area in a window.
        let (w, h) = (target.width as f32, target.height as f32);
        pass.set_viewport(0.0, 0.0, w, h, 0.0, 1.0);
        pass.set_scissor_rect(0, 0, target.width, target.height);
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, bind, &[]);
        pass.draw(0..3, 0..1);
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
