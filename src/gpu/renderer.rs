//! The ball renderer: plans each scene ([`Plan`]: which tables, which shader variants),
//! bakes and binds what the plan needs ([`TableCache`]), and draws into any colour target:
//! each ball's quad over its screen-space bounds with its variant's pipeline
//! ([`Pipelines`]), the background a clear (`balls.wgsl`). A window reuses
//! [`Renderer::render`] with its surface view; a host program hands its own device
//! ([`Renderer::from_device`]).

use std::collections::HashMap;
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::accumulate::{LobeKey, LobePass, LOBE_FORMAT, LOBE_IBL};
use super::bindings::{BallInstance, Bindings};
use super::context::Gpu;
use super::depth::DepthTarget;
use super::environment::EnvUniform;
use super::headless::{self, HdrImage, LdrImage};
use super::map_cache::PrefilteredMaps;
use super::montecarlo::{McFrame, MonteCarloPass};
use super::pipelines::{is_bits, is_linear, pipeline_key, Pipelines};
use super::plan::{DrawOptions, Plan, TablePolicy};
use super::probe::{self, ProbeSample};
use super::table_cache::{Bound, TableCache};
use super::truth::{self as truth_pass, Draw, TruthPass, SUM_FORMAT};
use super::uniforms::{self, GpuBall};
use crate::brdf::Geometry;
use crate::error::{Error, Result};
use crate::lut::{BakeConfig, CoatingKey, CoatingRows, RowSet, TableSet, Tables, COATING_ROW_LEN};
use crate::scene::Scene;

/// Where to draw: a view of a texture of `format`; the image is `width x height` pixels at
/// its top-left corner (the whole texture for a headless render, the scene area left of
/// the viewer's panel in a window; the rest of the texture is cleared only, to the
/// scene's background colour: the planned draw clears the whole attachment with it).
/// Float formats receive linear radiance (for EXR), `Rgba32Uint` its f32 bits; others the
/// tone-mapped value.
#[derive(Clone, Copy)]
pub struct Target<'a> {
    /// The view drawn into (a render attachment).
    pub view: &'a wgpu::TextureView,
    /// The view's format (linear radiance where [`crate::gpu::is_linear`], else tone-mapped).
    pub format: wgpu::TextureFormat,
    /// Width of the image in pixels, from the texture's left edge.
    pub width: u32,
    /// Height of the image in pixels, from the texture's top edge.
    pub height: u32,
}

/// Pixels added around each ball's exact bounds without antialiasing: the shader's f32 ray
/// may hit a pixel whose centre the f64 silhouette just misses (the CPU renderer's bins use
/// the same). With antialiasing the pad is [`crate::scene::AA_BOUNDS_PAD_PX`]
/// ([`crate::scene::bounds_pad_px`]).
pub const QUAD_PAD_PX: f64 = crate::scene::BOUNDS_PAD_PX;

/// Device, group 0, pipelines, tables, and the plan of the latest scene.
pub struct Renderer {
    gpu: Gpu,
    bindings: Bindings,
    pipelines: Pipelines,
    tables: TableCache,
    /// Wall time of the latest bake ([`Renderer::last_bake_time`]).
    last_bake: Option<Duration>,
    /// `set_tables` was called: its table is used whatever the plan.
    pinned: bool,
    options: DrawOptions,
    /// How tables are baked; its `geometry` is replaced by the scene's.
    bake_config: BakeConfig,
    plan: Option<Plan>,
    /// The per-ball draw's depth target.
    depth: DepthTarget,
    /// Group 1: the environment maps' textures, prefiltered for the latest maps drawn.
    environment: PrefilteredMaps,
    /// The truth balls' accumulation (`walk.wgsl`, `truth.rs`).
    truth: TruthPass,
    /// The Monte Carlo of the model (`montecarlo.wgsl`, `montecarlo.rs`), made on first use.
    montecarlo: Option<MonteCarloPass>,
    /// Every coating row baked so far, by key (`lut::coating`), and the latest scene's.
    coating_cache: HashMap<CoatingKey, [f32; COATING_ROW_LEN]>,
    coating: CoatingRows,
    /// The frame of the lobe's samples the next draw takes ([`Renderer::set_lobe_frame`]).
    lobe_frame: u32,
    /// The lobe's progressive image (`accumulate.wgsl`, `accumulate.rs`).
    lobe: LobePass,
    /// Most lobe samples a pixel [`Renderer::encode_progressive`] sums before it only
    /// resolves ([`Renderer::set_lobe_sample_cap`]).
    lobe_cap: Option<u32>,
}

impl Renderer {
    /// A renderer on `gpu` (its own device: [`Gpu::new`]; or a host's: [`Gpu::from_device`]).
    pub fn new(gpu: Gpu) -> Self {
        let bindings = Bindings::new(&gpu.device);
        let environment = PrefilteredMaps::new(&gpu.device);
        let pipelines = Pipelines::new(&gpu.device, &bindings, &environment.layout);
        let truth = TruthPass::new(&gpu.device, &bindings.layout, &environment.layout);
        let lobe = LobePass::new(&gpu.device, &bindings.layout, &environment.layout);
        let tables = TableCache::new(&gpu.device, &gpu.queue, &bindings);
        Renderer {
            gpu,
            bindings,
            pipelines,
            tables,
            last_bake: None,
            pinned: false,
            options: DrawOptions::default(),
            bake_config: BakeConfig::default(),
            plan: None,
            depth: DepthTarget::default(),
            coating_cache: HashMap::new(),
            coating: CoatingRows::default(),
            environment,
            truth,
            lobe_frame: 0,
            lobe,
            lobe_cap: None,
            montecarlo: None,
        }
    }

    /// Which frame of the lobe's samples the next draws take under `ibl_method = "lobe"`:
    /// frame k reads the sample indices `k N .. (k + 1) N` of each pixel's sequence (`N`
    /// the scene's `ibl_samples`), so the mean of frames `0..K` is the estimate of `K N`
    /// samples (what `render --ibl-frames` and a progressive viewer accumulate). 0 until set.
    pub fn set_lobe_frame(&mut self, frame: u32) {
        self.lobe_frame = frame;
    }

    /// The frame of the lobe's samples the next draw takes.
    pub fn lobe_frame(&self) -> u32 {
        self.lobe_frame
    }

    /// A renderer on a host program's device and queue: no device of its own, no error
    /// handler installed (wgpu's own, or the host's, sees any error that escapes the error
    /// scopes this crate pushes around each of its operations).
    ///
    /// ```
    /// # let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    /// # let adapter = pollster::block_on(instance.request_adapter(&Default::default()))
    /// #     .expect("a GPU adapter (lavapipe: apt-get install mesa-vulkan-drivers)");
    /// # let (device, queue) = pollster::block_on(adapter.request_device(&Default::default())).unwrap();
    /// // The host's own colour target.
    /// let texture = device.create_texture(&wgpu::TextureDescriptor {
    ///     label: None,
    ///     size: wgpu::Extent3d { width: 320, height: 180, depth_or_array_layers: 1 },
    ///     mip_level_count: 1,
    ///     sample_count: 1,
    ///     dimension: wgpu::TextureDimension::D2,
    ///     format: wgpu::TextureFormat::Rgba8Unorm,
    ///     usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
    ///     view_formats: &[],
    /// });
    /// let view = texture.create_view(&Default::default());
    /// let mut renderer = shadeballs::Renderer::from_device(&device, &queue);
    /// let scene = shadeballs::Scene::reference();
    /// let target = shadeballs::Target {
    ///     view: &view,
    ///     format: wgpu::TextureFormat::Rgba8Unorm,
    ///     width: 320,
    ///     height: 180,
    /// };
    /// renderer.render(&scene, target)?;
    /// # Ok::<(), shadeballs::Error>(())
    /// ```
    pub fn from_device(device: &wgpu::Device, queue: &wgpu::Queue) -> Self {
        Self::new(Gpu::from_device(device, queue))
    }

    /// The device the renderer draws with.
    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// Compiles the multiple-scattering term in where balls use it (`true`, the default) or
    /// out of every pipeline from now on; out, the image equals the one with every ball's
    /// flag off (`shadeballs-lab bench` measures what the term costs with it).
    pub fn set_multiple_scattering_term(&mut self, on: bool) {
        self.options.term = on;
    }

    /// How the next draws plan and draw (default: [`DrawOptions::default`]).
    pub fn set_draw_options(&mut self, options: DrawOptions) {
        self.options = options;
    }

    /// How draws plan and draw now ([`Renderer::set_draw_options`]).
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
        let mut baked = self.tables.ensure(&plan.tables);
        // The coating rows the scene's dielectrics read, baked where not yet cached.
        let (rows_before, start) = (self.coating_cache.len(), Instant::now());
        self.coating = scene.coating_rows(&mut self.coating_cache);
        if self.coating_cache.len() > rows_before {
            baked += start.elapsed();
        }
        // A change of plan that bakes nothing reports zero.
        if changed || !baked.is_zero() {
            self.last_bake = Some(baked);
        }
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
            self.pipelines
                .get(&self.gpu.device, pipeline_key(&plan, format, variant));
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

    /// The 2-D table for `geometry` with the bake config (baked if not held) and bound.
    pub fn tables_for(&mut self, geometry: Geometry) -> Arc<Tables> {
        self.bake_config.geometry = geometry;
        let (tables, baked) = self.tables.full_table(self.bake_config);
        if !baked.is_zero() {
            self.last_bake = Some(baked);
        }
        tables
    }

    /// Uses `tables` (baked for their `config.geometry`) for every scene from now on, as
    /// the 2-D table whatever the plan would choose, and bakes with their config when the
    /// geometry changes; [`Renderer::set_bake_config`] returns to planning.
    pub fn set_tables(&mut self, tables: Arc<Tables>) {
        self.bake_config = tables.config;
        self.pinned = true;
        self.tables.pin(tables);
    }

    /// The tables bound now (what the last draw read).
    pub fn bound_tables(&self) -> TableSet {
        self.tables
            .bound()
            .map_or(TableSet::None, |b| b.tables.clone())
    }

    /// Wall time of the latest preparation of an environment map: the kernels, its mip
    /// chain and the split-sum table on the CPU, the upload and the submission of the GPU's
    /// prefiltering (which runs on behind; wait on the queue to time it whole, as the lab's
    /// `bench --only ibl` does); `None` before any. A map drawn again while held (up to
    /// [`MAX_PREFILTERED_MAPS`](super::MAX_PREFILTERED_MAPS)) is not prepared again.
    pub fn last_prefilter_time(&self) -> Option<Duration> {
        self.environment.last_prepared()
    }

    /// Prefilters `scene`'s environment map now if it has one not yet held (otherwise done
    /// at the first draw), so that its cost can be timed apart. Fails where its mip chain
    /// would not fit in memory.
    pub fn prepare_environment(&mut self, scene: &Scene) -> Result<()> {
        self.environment
            .bind_group(&self.gpu, scene, self.bake_config)
            .map(drop)
    }

    /// Hands over `chain`, built from `map` ([`MipChain::new`](crate::environment::MipChain::new))
    /// beforehand (the CLI builds it while the device opens), for the next preparation of
    /// that very map (the same `Arc`); a preparation of any other map builds its own.
    pub fn offer_mip_chain(
        &mut self,
        map: Arc<crate::environment::EnvMap>,
        chain: crate::environment::MipChain,
    ) {
        self.environment.offer_chain(map, chain);
    }

    /// Rows in the memory cache.
    pub fn cached_rows(&self) -> usize {
        self.tables.cached_rows()
    }

    /// Group 0's buffers and layout and the bound tables' bind group (the probe binds them
    /// too).
    pub(crate) fn group0(&self) -> (&Bindings, Option<&Bound>) {
        (&self.bindings, self.tables.bound())
    }

    /// Draws `scene` into `target` and submits. Truth balls (`model = "truth"`) are path
    /// traced: each draw of an unchanged scene at the same size adds one estimate a pixel
    /// to their sums and shows the mean ([`Renderer::truth_samples`]).
    pub fn render(&mut self, scene: &Scene, target: Target<'_>) -> Result<()> {
        self.gpu.check()?;
        self.check_truth_supported(scene)?;
        let scopes = super::Scopes::push(&self.gpu.device);
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        let encoded = self.encode(scene, target, &mut encoder);
        self.gpu.queue.submit([encoder.finish()]);
        scopes.pop()?;
        encoded?;
        self.gpu.check()
    }

    /// Records the draw of `scene` into `target` on `encoder` (plans the scene, bakes what
    /// its plan needs and is not cached, uploads uniforms and quads now): the balls' pass,
    /// then the truth balls' accumulation and resolve. Fails, recording nothing, where the
    /// scene's map is new and its mip chain would not fit in memory.
    pub fn encode(
        &mut self,
        scene: &Scene,
        target: Target<'_>,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Result<()> {
        let frame = self.prepare_frame(scene, target.width, target.height)?;
        self.encode_balls(scene, &frame, target, encoder);
        if !frame.plan.truth.is_empty() && self.truth_frame(scene, &frame, encoder) {
            let draw = truth_draw(&self.gpu, &frame);
            self.truth
                .resolve(&draw, encoder, target.view, target.format, frame.size);
        }
        Ok(())
    }

    /// Records the balls' pass of `frame` into `target`: each variant's quads with its
    /// pipeline, then the map behind the balls (a full-screen draw at the far plane, where
    /// no ball is).
    fn encode_balls(
        &mut self,
        scene: &Scene,
        frame: &Frame,
        target: Target<'_>,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        let (quads, ranges) = ball_quads(scene, frame);
        let (background_pipeline, draws) = self.ball_pipelines(frame, target.format, ranges);
        if !quads.is_empty() {
            let queue = &self.gpu.queue;
            queue.write_buffer(&self.bindings.instances, 0, bytemuck::cast_slice(&quads));
        }
        let clear = background(scene, target.format);
        // The per-ball draw's depth target, the size of the whole colour attachment.
        let depth = {
            let texture = target.view.texture();
            let size = (texture.width(), texture.height());
            self.depth.view(&self.gpu.device, size)
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
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            ..Default::default()
        });
        // The image's rectangle: the whole target headless, the scene area in a window.
        let (w, h) = frame.size;
        pass.set_viewport(0.0, 0.0, w as f32, h as f32, 0.0, 1.0);
        pass.set_scissor_rect(0, 0, w, h);
        pass.set_bind_group(0, &frame.group0, &[]);
        pass.set_bind_group(1, &frame.group1, &[]);
        let stride = std::mem::size_of::<BallInstance>() as u64;
        for (pipeline, range) in draws {
            if range.is_empty() {
                continue;
            }
            pass.set_pipeline(&pipeline);
            let bytes = range.start as u64 * stride..range.end as u64 * stride;
            pass.set_vertex_buffer(0, self.bindings.instances.slice(bytes));
            pass.draw(0..4, 0..range.len() as u32);
        }
        // The map behind the balls last, at the far plane: the depth test skips every pixel
        // a ball wrote (a third of the showcase's frame), where it would be overdrawn.
        if let Some(pipeline) = background_pipeline {
            pass.set_pipeline(&pipeline);
            pass.draw(0..3, 0..1);
        }
    }

    /// The pipelines of `frame`'s balls' pass into `format`: the map's background draw
    /// (where the background shows it), and each planned draw's pipeline with its range
    /// of quads.
    fn ball_pipelines(
        &mut self,
        frame: &Frame,
        format: wgpu::TextureFormat,
        ranges: Vec<std::ops::Range<u32>>,
    ) -> (
        Option<wgpu::RenderPipeline>,
        Vec<(wgpu::RenderPipeline, std::ops::Range<u32>)>,
    ) {
        let plan = &frame.plan;
        let device = &self.gpu.device;
        let shows_map = frame.env_uniform.shows_map == 1.0;
        // A scene of truth balls alone has no per-ball draw: its background is drawn with
        // the truth's variant (same map and display), not left the clear colour.
        let first = plan.draws.first().map(|(v, _)| v);
        let first = first.or((!plan.truth.is_empty()).then_some(&plan.truth_variant));
        let background = match first {
            Some(variant) if shows_map => Some(
                self.pipelines
                    .background(
                        device,
                        format,
                        *variant,
                        plan.geometry,
                        plan.bake.layout.mu_axis,
                    )
                    .clone(),
            ),
            _ => None,
        };
        let draws = plan
            .draws
            .iter()
            .zip(ranges)
            .map(|((variant, _), range)| {
                let key = pipeline_key(plan, format, *variant);
                (self.pipelines.get(device, key).clone(), range)
            })
            .collect();
        (background, draws)
    }

    /// Plans `scene`, binds its tables and map, and uploads the uniforms of a `w x h`
    /// frame at the lobe frame set ([`Renderer::set_lobe_frame`]).
    fn prepare_frame(&mut self, scene: &Scene, w: u32, h: u32) -> Result<Frame> {
        self.prepare_frame_at(scene, (w, h), self.lobe_frame)
    }

    /// [`Renderer::prepare_frame`] at frame `lobe_frame` of the lobe's samples.
    fn prepare_frame_at(
        &mut self,
        scene: &Scene,
        (w, h): (u32, u32),
        lobe_frame: u32,
    ) -> Result<Frame> {
        let env_group = self
            .environment
            .bind_group(&self.gpu, scene, self.bake_config)?;
        let plan = self.plan_for(scene).clone();
        let bound = self.tables.bound().expect("plan_for binds");
        let tables = bound.tables.clone();
        let bind = bound.bind.clone();
        let queue = &self.gpu.queue;
        let globals = uniforms::globals(scene, &tables, w, h);
        queue.write_buffer(&self.bindings.globals, 0, bytemuck::bytes_of(&globals));
        // The quads carry their ball (the balls' storage buffer is no longer read).
        let balls = uniforms::balls(scene, &tables, &self.coating);
        let rows = self.coating.flat();
        queue.write_buffer(&self.bindings.coating_rows, 0, bytemuck::cast_slice(&rows));
        let env_uniform = EnvUniform::of(scene).at_lobe_frame(scene, lobe_frame);
        queue.write_buffer(
            &self.environment.uniform,
            0,
            bytemuck::bytes_of(&env_uniform),
        );
        let lights = uniforms::lights(scene);
        if !lights.is_empty() {
            queue.write_buffer(&self.bindings.lights, 0, bytemuck::cast_slice(&lights));
        }
        let hidden = hidden_duplicates(&balls);
        Ok(Frame {
            plan,
            size: (w, h),
            group0: bind,
            group1: env_group,
            balls,
            hidden,
            env_uniform,
        })
    }

    /// Whether this device can accumulate the truth: it renders to `Rgba32Float` (GL
    /// does not).
    pub fn truth_supported(&self) -> bool {
        self.gpu.renderable(SUM_FORMAT)
    }

    /// [`Error::TruthUnsupported`] if `scene` has truth balls and this device cannot
    /// accumulate them.
    pub(crate) fn check_truth_supported(&self, scene: &Scene) -> Result<()> {
        if scene.has_truth() && !self.truth_supported() {
            return Err(Error::TruthUnsupported {
                device: self.gpu.describe(),
            });
        }
        Ok(())
    }

    /// Records one frame of the truth balls' estimates (returns false, logging why, where
    /// the device cannot: [`Renderer::truth_supported`]).
    fn truth_frame(
        &mut self,
        scene: &Scene,
        frame: &Frame,
        encoder: &mut wgpu::CommandEncoder,
    ) -> bool {
        if !self.truth_supported() {
            // Once a process, not every frame of the viewer (issue 28, 11).
            static SAID: std::sync::Once = std::sync::Once::new();
            SAID.call_once(|| {
                log::error!(
                    "{} cannot render to Rgba32Float: the truth balls are not drawn",
                    self.gpu.describe()
                )
            });
            return false;
        }
        let quads = truth_pass::quads(scene, &frame.balls, &frame.hidden, frame.size);
        let draw = truth_draw(&self.gpu, frame);
        self.truth
            .accumulate(&draw, encoder, scene, frame.size, (&quads.0, &quads.1));
        true
    }

    /// Adds one frame of estimates to the truth balls' sums of `scene` at `w x h` (starting
    /// them again if the scene or the size changed) without drawing an image, and submits.
    /// A scene without truth balls does nothing.
    pub fn accumulate_truth(&mut self, scene: &Scene, w: u32, h: u32) -> Result<()> {
        self.gpu.check()?;
        let scopes = super::Scopes::push(&self.gpu.device);
        let frame = match self.prepare_frame(scene, w, h) {
            Ok(frame) => frame,
            Err(e) => {
                scopes.pop()?;
                return Err(e);
            }
        };
        if frame.plan.truth.is_empty() {
            scopes.pop()?;
            return Ok(());
        }
        if !self.truth_supported() {
            scopes.pop()?;
            return self.check_truth_supported(scene);
        }
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        self.truth_frame(scene, &frame, &mut encoder);
        self.gpu.queue.submit([encoder.finish()]);
        scopes.pop()?;
        self.gpu.check()
    }

    /// Estimates per pixel the truth balls' image holds now (after the latest draw or
    /// [`Renderer::accumulate_truth`]); `None` before any scene with truth balls.
    pub fn truth_samples(&self) -> Option<u32> {
        self.truth.frames()
    }

    /// Starts the truth balls' sums again from zero at the next frame (they restart by
    /// themselves when the scene or the size changes).
    pub fn reset_truth(&mut self) {
        self.truth.reset();
    }

    /// Draws `scene` into `target` as [`Renderer::encode`] does, but a scene whose balls
    /// use the lobe (`ibl_method = "lobe"` with a map) converges: each call while the scene
    /// is unchanged (but for its exposure and display transform; the size, tables and draw
    /// options too) adds the next frame of the lobe's samples to sums held on the GPU and
    /// writes their mean (the lobe frame advances by itself; [`Renderer::set_lobe_frame`]
    /// is not read), and a changed scene starts again from one frame
    /// ([`Renderer::lobe_samples`]). Past [`Renderer::set_lobe_sample_cap`]'s cap it adds
    /// nothing and writes the mean held. A scene without the lobe is drawn by `encode`.
    pub fn encode_progressive(
        &mut self,
        scene: &Scene,
        target: Target<'_>,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Result<()> {
        let capped = |samples: Option<u32>, cap: Option<u32>| {
            samples.zip(cap).is_some_and(|(n, cap)| n >= cap)
        };
        self.progressive(scene, target, encoder, |r| {
            !capped(r.lobe_samples(), r.lobe_cap)
        })
    }

    /// [`Renderer::encode_progressive`] without the cap: always adds a frame (the headless
    /// render's last frame, [`Renderer::render_lobe_hdr`]).
    pub(super) fn encode_lobe_mean(
        &mut self,
        scene: &Scene,
        target: Target<'_>,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Result<()> {
        self.progressive(scene, target, encoder, |_| true)
    }

    /// [`Renderer::encode_progressive`] adding no frame where the sums already hold this
    /// scene's (the image the latest progressive draw showed; one frame where they do not).
    pub(super) fn encode_lobe_held(
        &mut self,
        scene: &Scene,
        target: Target<'_>,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Result<()> {
        self.progressive(scene, target, encoder, |_| false)
    }

    /// [`Renderer::encode_progressive`] and submits.
    pub fn render_progressive(&mut self, scene: &Scene, target: Target<'_>) -> Result<()> {
        self.gpu.check()?;
        self.check_truth_supported(scene)?;
        let scopes = super::Scopes::push(&self.gpu.device);
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        let encoded = self.encode_progressive(scene, target, &mut encoder);
        self.gpu.queue.submit([encoder.finish()]);
        scopes.pop()?;
        encoded?;
        self.gpu.check()
    }

    /// Samples a pixel the lobe's progressive image holds (frames summed times the scene's
    /// `ibl_samples`) after the latest [`Renderer::encode_progressive`],
    /// [`Renderer::accumulate_lobe`] or [`Renderer::render_lobe_hdr`]; `None` when that
    /// scene's balls use no lobe (or before any).
    pub fn lobe_samples(&self) -> Option<u32> {
        let frames = self.lobe.frames()?;
        Some(frames.saturating_mul(self.lobe.samples_a_frame()))
    }

    /// Stops [`Renderer::encode_progressive`] adding frames once the image holds `cap`
    /// samples a pixel (`None`, the default: no cap), so that an idle viewer goes idle.
    pub fn set_lobe_sample_cap(&mut self, cap: Option<u32>) {
        self.lobe_cap = cap;
    }

    /// Starts the lobe's sums again from zero at the next frame (they restart by
    /// themselves when the scene changes).
    pub fn reset_lobe(&mut self) {
        self.lobe.reset();
    }

    /// Adds the next frame of the lobe's samples of `scene` at `w x h` to the sums
    /// (starting them again if the scene changed) without drawing an image, and submits.
    /// A scene whose balls use no lobe does nothing.
    pub fn accumulate_lobe(&mut self, scene: &Scene, w: u32, h: u32) -> Result<()> {
        self.gpu.check()?;
        let scopes = super::Scopes::push(&self.gpu.device);
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        let added = match self.start_lobe(scene, (w, h)) {
            Some(frames) => self
                .add_lobe_frame(scene, (w, h), frames, &mut encoder)
                .map(drop),
            None => Ok(()),
        };
        self.gpu.queue.submit([encoder.finish()]);
        scopes.pop()?;
        added?;
        self.gpu.check()
    }

    /// Records the addition of frame `frames` (the count summed so far) of `scene` at `size`
    /// to the lobe's sums (after [`Renderer::start_lobe`]); returns the frame's uniforms.
    fn add_lobe_frame(
        &mut self,
        scene: &Scene,
        size: (u32, u32),
        frames: u32,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Result<Frame> {
        let frame = self.prepare_frame_at(scene, size, frames)?;
        self.encode_lobe_frame(scene, &frame, encoder);
        Ok(frame)
    }

    /// Keeps or starts the lobe's sums for `scene` at `size`: the frames summed so far, or
    /// `None` (the sums dropped) where its balls use no lobe.
    fn start_lobe(&mut self, scene: &Scene, size: (u32, u32)) -> Option<u32> {
        let plan = self.make_plan(scene);
        if !plan.draws.iter().any(|(v, _)| v.ibl == LOBE_IBL) {
            self.lobe.forget();
            return None;
        }
        let key = LobeKey::new(scene, size, &plan, self.options);
        Some(self.lobe.start(&self.gpu.device, key))
    }

    /// Records the balls' pass of `frame` into the lobe's frame texture and its addition to
    /// the sums (after [`Renderer::start_lobe`]).
    fn encode_lobe_frame(
        &mut self,
        scene: &Scene,
        frame: &Frame,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        let Some(view) = self.lobe.frame_view().cloned() else {
            return;
        };
        let target = Target {
            view: &view,
            format: LOBE_FORMAT,
            width: frame.size.0,
            height: frame.size.1,
        };
        self.encode_balls(scene, frame, target, encoder);
        let draw = truth_draw(&self.gpu, frame);
        self.lobe.accumulate(&draw, encoder);
    }

    /// The work of [`Renderer::encode_progressive`]: a frame added where `add(self)` says
    /// so, then the mean resolved into `target` and the truth balls as `encode` draws them.
    fn progressive(
        &mut self,
        scene: &Scene,
        target: Target<'_>,
        encoder: &mut wgpu::CommandEncoder,
        add: impl Fn(&Self) -> bool,
    ) -> Result<()> {
        let size = (target.width, target.height);
        let Some(frames) = self.start_lobe(scene, size) else {
            return self.encode(scene, target, encoder);
        };
        let frame = if frames == 0 || add(self) {
            self.add_lobe_frame(scene, size, frames, encoder)?
        } else {
            self.prepare_frame_at(scene, size, frames)?
        };
        let draw = truth_draw(&self.gpu, &frame);
        let clear = background(scene, target.format);
        self.lobe
            .resolve(&draw, encoder, (target.view, target.format), size, clear);
        if !frame.plan.truth.is_empty() && self.truth_frame(scene, &frame, encoder) {
            let draw = truth_draw(&self.gpu, &frame);
            self.truth
                .resolve(&draw, encoder, target.view, target.format, frame.size);
        }
        Ok(())
    }

    /// Renders `scene` into an `Rgba8Unorm` texture (not sRGB: the transfer curve is
    /// applied in the shader) and reads it back. Into a host's own `*Srgb` target the
    /// renderer writes linear values, which the hardware encodes to the same bytes.
    pub fn render_ldr(&mut self, scene: &Scene, width: u32, height: u32) -> Result<LdrImage> {
        headless::render_ldr(self, scene, width, height)
    }

    /// Renders linear radiance into `Rgba32Float`, or where 32-bit float is not renderable
    /// (GL) its f32 bits into `Rgba32Uint` (`fs_ball_bits`), and reads it back as f32: the
    /// same f32 values on every backend, none clipped to a 16-bit float's range.
    pub fn render_hdr(&mut self, scene: &Scene, width: u32, height: u32) -> Result<HdrImage> {
        headless::render_hdr(self, scene, width, height)
    }

    /// [`Renderer::render_hdr`] averaged over frames `0..frames` of the lobe's samples
    /// (`ibl_method = "lobe"`: the estimate of `frames * ibl_samples` samples a pixel;
    /// `render --ibl-frames`): the sums started again and the frames summed on the GPU
    /// ([`Renderer::accumulate_lobe`], [`Renderer::encode_progressive`]), one read-back.
    /// Errors when `frames` is outside `1..=MAX_IBL_FRAMES`.
    pub fn render_lobe_hdr(
        &mut self,
        scene: &Scene,
        width: u32,
        height: u32,
        frames: u32,
    ) -> Result<HdrImage> {
        headless::render_lobe_hdr(self, scene, (width, height), frames)
    }

    /// The linear radiance of the progressive image [`Renderer::encode_progressive`] holds
    /// for `scene` at `width x height` (as [`Renderer::render_hdr`] reads it back), adding
    /// no frame where the sums hold this scene's: what a viewer shows, for its EXR. A scene
    /// without the lobe is [`Renderer::render_hdr`]'s image.
    pub fn render_progressive_hdr(
        &mut self,
        scene: &Scene,
        width: u32,
        height: u32,
    ) -> Result<HdrImage> {
        headless::render_progressive_hdr(self, scene, (width, height))
    }

    /// [`Renderer::render_ldr`] with the truth balls' image the mean of `spp` estimates a
    /// pixel (the sums started again from zero; the other balls as always).
    pub fn render_truth_ldr(
        &mut self,
        scene: &Scene,
        width: u32,
        height: u32,
        spp: u32,
    ) -> Result<LdrImage> {
        headless::accumulate_frames(self, scene, width, height, spp)?;
        self.render_ldr(scene, width, height)
    }

    /// [`Renderer::render_hdr`] with the truth balls' image the mean of `spp` estimates a
    /// pixel (the sums started again from zero; the other balls as always).
    pub fn render_truth_hdr(
        &mut self,
        scene: &Scene,
        width: u32,
        height: u32,
        spp: u32,
    ) -> Result<HdrImage> {
        headless::accumulate_frames(self, scene, width, height, spp)?;
        self.render_hdr(scene, width, height)
    }

    /// The Monte Carlo of the model on the GPU: `spp` estimates a covered pixel of `scene`
    /// at `width x height` from `seed`, with the CPU estimator's strategies and weights
    /// (`crate::cpu::render_montecarlo`) in f32, and each pixel's standard error.
    /// Errors as the CPU's on a bad `spp` or map, and where the device cannot render to
    /// `Rgba32Float` (GL).
    pub fn render_montecarlo(
        &mut self,
        scene: &Scene,
        (width, height): (u32, u32),
        spp: u32,
        seed: u64,
    ) -> Result<crate::stats::MonteCarloImage> {
        self.render_montecarlo_progressive(scene, (width, height), (spp, seed), |_| true)
    }

    /// [`Renderer::render_montecarlo`] of one [`Part`](crate::stats::Part) of the model:
    /// `Part::Multiple` integrates only the lobe the term adds (the GPU twin of
    /// [`crate::cpu::render_montecarlo_part`]), the reference for a real-time term alone.
    pub fn render_montecarlo_part(
        &mut self,
        scene: &Scene,
        size: (u32, u32),
        (spp, seed): (u32, u64),
        part: crate::stats::Part,
    ) -> Result<crate::stats::MonteCarloImage> {
        self.montecarlo_checked(scene, size, (spp, seed, part), |_| true)
    }

    /// [`Renderer::render_montecarlo`] in passes of [`super::MC_PASS_SAMPLES`] estimates:
    /// after each pass but the last, `keep_going(estimates so far)` may stop the render
    /// (the image then holds the passes done; its `spp` says how many).
    pub fn render_montecarlo_progressive(
        &mut self,
        scene: &Scene,
        (width, height): (u32, u32),
        (spp, seed): (u32, u64),
        keep_going: impl FnMut(u32) -> bool,
    ) -> Result<crate::stats::MonteCarloImage> {
        let whole = crate::stats::Part::Whole;
        self.montecarlo_checked(scene, (width, height), (spp, seed, whole), keep_going)
    }

    /// The checks and error scopes around [`Renderer::montecarlo_passes`].
    fn montecarlo_checked(
        &mut self,
        scene: &Scene,
        (width, height): (u32, u32),
        (spp, seed, part): (u32, u64, crate::stats::Part),
        keep_going: impl FnMut(u32) -> bool,
    ) -> Result<crate::stats::MonteCarloImage> {
        crate::stats::check_montecarlo_inputs(scene, spp)?;
        self.gpu.check_size(width, height)?;
        self.gpu.check()?;
        if !self.truth_supported() {
            return Err(Error::Gpu {
                message: format!(
                    "{} cannot render to Rgba32Float: no Monte Carlo on this device",
                    self.gpu.describe()
                ),
            });
        }
        let scopes = super::Scopes::push(&self.gpu.device);
        let image = self.montecarlo_passes(scene, (width, height), (spp, seed, part), keep_going);
        scopes.pop()?;
        self.gpu.check()?;
        image
    }

    /// The passes of [`Renderer::render_montecarlo_progressive`], within its error scopes.
    fn montecarlo_passes(
        &mut self,
        scene: &Scene,
        size: (u32, u32),
        (spp, seed, part): (u32, u64, crate::stats::Part),
        keep_going: impl FnMut(u32) -> bool,
    ) -> Result<crate::stats::MonteCarloImage> {
        let frame = self.prepare_frame(scene, size.0, size.1)?;
        let device = &self.gpu.device;
        let (group0, group1) = (&self.bindings.layout, &self.environment.layout);
        let pass = self
            .montecarlo
            .get_or_insert_with(|| MonteCarloPass::new(device, group0, group1));
        let mc = McFrame {
            group0: &frame.group0,
            group1: &frame.group1,
            balls: &frame.balls,
            hidden: &frame.hidden,
            geometry: frame.plan.geometry,
            mu_axis: frame.plan.bake.layout.mu_axis,
            variant: frame.plan.truth_variant,
            size,
            part,
        };
        pass.render(&self.gpu, scene, &mc, (spp, seed), keep_going)
    }

    /// Evaluates the tables for `geometry` (baked if needed) on the GPU with the shader's
    /// own reads (`shaders/probe.wgsl`); row-major, row = roughness. Returns the tables
    /// read, for comparison.
    pub fn probe(&mut self, geometry: Geometry, n: u32) -> Result<(Arc<Tables>, Vec<ProbeSample>)> {
        probe::probe(self, geometry, n)
    }

    /// Evaluates the rows `scene`'s plan reads, as its balls read them (`lut_loss_row` at
    /// each row's roughness with no weight on the next row), at `mu = i / (N - 1)`; row-major,
    /// row = the plan's rows in order. Returns the rows read (`None` when the plan reads no
    /// rows: no ball reads E (no term, no environment), or the 2-D table).
    pub fn probe_rows(
        &mut self,
        scene: &Scene,
        n: u32,
    ) -> Result<Option<(Arc<RowSet>, Vec<ProbeSample>)>> {
        probe::probe_rows(self, scene, n)
    }
}

/// What a frame draws with: the plan, the image's size, bind groups 0 and 1, the balls
/// (with those hidden by an identical earlier one) and the map's uniform.
struct Frame {
    plan: Plan,
    size: (u32, u32),
    group0: wgpu::BindGroup,
    group1: wgpu::BindGroup,
    balls: Vec<GpuBall>,
    /// [`hidden_duplicates`] of `balls`.
    hidden: Vec<bool>,
    env_uniform: EnvUniform,
}

/// The per-ball quads of `frame`, grouped by the plan's draws, and each draw's range of
/// them.
fn ball_quads(scene: &Scene, frame: &Frame) -> (Vec<BallInstance>, Vec<std::ops::Range<u32>>) {
    let (w, h) = frame.size;
    let basis = scene.camera.basis(w, h);
    let pad = crate::scene::bounds_pad_px(scene.antialias);
    let mut quads: Vec<BallInstance> = Vec::new();
    let mut ranges = Vec::with_capacity(frame.plan.draws.len());
    for (_, members) in &frame.plan.draws {
        let start = quads.len() as u32;
        quads.extend(
            members
                .iter()
                .filter(|&&k| !frame.hidden[k])
                .filter_map(|&k| {
                    let b = &scene.balls[k];
                    let rect = basis.sphere_bounds(b.center, b.radius, w, h, pad)?;
                    Some(BallInstance {
                        rect: rect.map(|v| v as f32),
                        ball: frame.balls[k],
                    })
                }),
        );
        ranges.push(start..quads.len() as u32);
    }
    (quads, ranges)
}

/// The truth passes' device, groups and compile-time choices for `frame`.
fn truth_draw<'a>(gpu: &'a Gpu, frame: &'a Frame) -> Draw<'a> {
    Draw {
        device: &gpu.device,
        queue: &gpu.queue,
        group0: &frame.group0,
        group1: &frame.group1,
        geometry: frame.plan.geometry,
        mu_axis: frame.plan.bake.layout.mu_axis,
        variant: frame.plan.truth_variant,
    }
}

/// Which balls are hidden by an earlier one of the same centre and radius (as the shader
/// sees them, in f32): such a pair ties at every pixel, where the nearest hit is the lower
/// index's (`cpu::render_radiance`); the depth test would
/// keep whichever quad is drawn first, so the later ball is not drawn at all.
fn hidden_duplicates(balls: &[GpuBall]) -> Vec<bool> {
    let mut seen = std::collections::HashSet::with_capacity(balls.len());
    balls
        .iter()
        // + 0.0 makes -0 and +0 one key.
        .map(|b| !seen.insert(b.center_radius.map(|v| (v + 0.0).to_bits())))
        .collect()
}

/// The clear colour: what the shader would give a pixel that hits no ball (the
/// environment, linear on a float target, its f32 bits on an `Rgba32Uint` one, else
/// through the display transform, decoded to linear on an sRGB target). wgpu clears an integer target with each component
/// `as u32` (Vulkan and GL alike), which keeps a u32 held in an f64 exactly.
fn background(scene: &Scene, format: wgpu::TextureFormat) -> wgpu::Color {
    let env = scene.background_radiance();
    if is_bits(format) {
        let bits = |c: f64| (c as f32).to_bits() as f64;
        return wgpu::Color {
            r: bits(env.x),
            g: bits(env.y),
            b: bits(env.z),
            a: bits(1.0),
        };
    }
    let value = if is_linear(format) {
        env.as_vec3().as_dvec3()
    } else {
        // wgpu clears an sRGB target with a linear colour, which the hardware encodes.
        crate::display::target_value(env, scene.exposure, scene.display(), format.is_srgb())
    };
    wgpu::Color {
        r: value.x,
        g: value.y,
        b: value.z,
        a: 1.0,
    }
}
