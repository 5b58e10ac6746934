//! The ball renderer: plans each scene (`scene::Plan`: which tables, which shader
//! variants), bakes and binds what the plan needs (`tables.rs`), and draws into any colour
//! target: each ball's quad over its screen-space bounds with its variant's pipeline, the
//! background a clear (`balls.wgsl`). A window reuses [`Renderer::render`] with its
//! surface view.

use std::collections::HashMap;
use std::time::Duration;

use super::resources::Resources;
use super::tables::{Bound, TableCache};
use super::{shaders, Gpu};
use crate::brdf::{FAvgForm, Geometry};
use crate::error::Result;
use crate::gpu::{DrawOptions, Plan, TablePolicy, Variant};
use crate::lut::{BakeConfig, MuAxis};
use crate::scene::Scene;

pub use super::draw::QUAD_PAD_PX;

/// Where to draw: a view of a texture of `format`; the image is `width x height` pixels at
/// its top-left corner (the whole texture for a headless render, the scene area left of
/// the viewer's panel in a window; the rest of the texture is cleared only, to the
/// scene's background colour: the planned draw clears the whole attachment with it).
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

/// Target format, G, f_add form, the tables' mu axis, per-ball quads (or the full-screen
/// triangle), variant.
pub(super) type PipelineKey = (
    wgpu::TextureFormat,
    Geometry,
    FAvgForm,
    MuAxis,
    bool,
    Variant,
);

/// The pipeline that draws `variant` of `plan` (of `scene`) into `format`. The mu axis is
/// the plan's bake layout's: the tables it binds are baked with it (or, pinned by
/// `set_tables`, set it), and with no tables nothing reads the axis.
pub(super) fn pipeline_key(
    plan: &Plan,
    scene: &Scene,
    format: wgpu::TextureFormat,
    variant: Variant,
) -> PipelineKey {
    (
        format,
        plan.geometry,
        scene.preset.f_avg_form(),
        plan.bake.layout.mu_axis,
        plan.per_ball,
        variant,
    )
}

/// Device, shader module, pipelines, the plan of the latest scene and its tables.
pub struct Renderer {
    pub(super) gpu: Gpu,
    pub(super) resources: Resources,
    pub(super) module: wgpu::ShaderModule,
    pub(super) pipeline_layout: wgpu::PipelineLayout,
    pub(super) pipelines: HashMap<PipelineKey, wgpu::RenderPipeline>,
    /// The tables bound now and their bind group.
    pub(super) bound: Option<Bound>,
    /// Baked rows and the latest 2-D table.
    pub(super) cache: TableCache,
    /// `set_tables` was called: its table is used whatever the plan.
    pub(super) pinned: bool,
    pub(super) options: DrawOptions,
    /// How tables are baked; its `geometry` is replaced by the scene's.
    pub(super) bake_config: BakeConfig,
    /// Wall time of the latest bake, if any.
    pub(super) last_bake: Option<Duration>,
    pub(super) plan: Option<Plan>,
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
            self.pipeline(pipeline_key(&plan, scene, format, variant));
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
