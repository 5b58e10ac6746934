//! The ball renderer: plans each scene ([`Plan`]: which tables, which shader variants),
//! bakes and binds what the plan needs ([`TableCache`]), and draws into any colour target:
//! each ball's quad over its screen-space bounds with its variant's pipeline
//! ([`Pipelines`]), the background a clear (`balls.wgsl`). A window reuses
//! [`Renderer::render`] with its surface view; a host program hands its own device
//! ([`Renderer::from_device`]).

use std::sync::Arc;
use std::time::{Duration, Instant};

use super::accumulate::LobePass;
use super::bindings::Bindings;
use super::context::Gpu;
use super::depth::DepthTarget;
use super::map_cache::PrefilteredMaps;
use super::montecarlo::MonteCarloPass;
use super::pipelines::{pipeline_key, Pipelines};
use super::plan::{DrawOptions, Plan, TablePolicy};
use super::sums::SUM_FORMAT;
use super::table_cache::TableCache;
use super::truth::TruthPass;
use crate::brdf::Geometry;
use crate::error::{Error, Result};
use crate::lut::{BakeConfig, TableSet, Tables};
use crate::prepared::{CoatingCache, Prepared};
use crate::scene::Scene;

// The renderer's rooms, each an `impl Renderer` block: a frame's preparation, the balls'
// pass, the progressive images (the truth's and the lobe's sums), the headless renders
// (and the Monte Carlo), the table probe.
mod ball_pass;
mod frame;
pub(super) mod headless;
pub(super) mod probe;
mod progressive;

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
    /// The view's format (linear radiance where `crate::gpu::is_linear`, else tone-mapped).
    pub format: wgpu::TextureFormat,
    /// Width of the image in pixels, from the texture's left edge.
    pub width: u32,
    /// Height of the image in pixels, from the texture's top edge.
    pub height: u32,
}

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
    /// Every coating row baked so far, by key (`lut::coating`), and the latest scene
    /// prepared with the tables bound for it.
    coating_cache: CoatingCache,
    prepared: Prepared,
    /// The frame of the lobe's samples the next draw takes ([`Renderer::set_lobe_frame`]).
    lobe_frame: u32,
    /// The lobe's progressive image (`accumulate.wgsl`, `accumulate.rs`).
    lobe: LobePass,
    /// Most lobe samples a pixel [`Renderer::encode_progressive`] sums before it only
    /// resolves ([`Renderer::set_lobe_sample_cap`]).
    lobe_cap: Option<u32>,
}

impl Renderer {
    /// A renderer on `gpu` (its own device: [`Gpu::new`]; or a host's: `Gpu::from_device`).
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
            coating_cache: CoatingCache::new(),
            prepared: Prepared::default(),
            environment,
            truth,
            lobe_frame: 0,
            lobe,
            lobe_cap: None,
            montecarlo: None,
        }
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

    /// Which frame of the lobe's samples the next draws take under `ibl_method = "lobe"`:
    /// frame k reads the sample indices `k N .. (k + 1) N` of each pixel's sequence (`N`
    /// the scene's `ibl_samples`), so the mean of frames `0..K` is the estimate of `K N`
    /// samples (what `render --ibl-frames` and a progressive viewer accumulate). 0 until set.
    pub fn set_lobe_frame(&mut self, frame: u32) {
        self.lobe_frame = frame;
    }

    /// The frame of the lobe's samples the next draw takes.
    #[cfg(test)]
    pub(crate) fn lobe_frame(&self) -> u32 {
        self.lobe_frame
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
        // The scene prepared with the tables bound: the coating rows its dielectrics read,
        // baked where not yet cached, and each ball's coating.
        let (rows_before, start) = (self.coating_cache.len(), Instant::now());
        let tables = self.bound_tables();
        self.prepared = Prepared::with_cache(scene, &tables, &mut self.coating_cache);
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

    /// Whether the ball pipelines are made from programs specialised to their constants
    /// (the default) or from the whole programs (the tests' control).
    #[cfg(test)]
    pub(crate) fn set_specialise(&mut self, on: bool) {
        self.pipelines.set_specialise(on);
    }

    /// The plan of the latest scene planned or drawn.
    pub(crate) fn plan(&self) -> Option<&Plan> {
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
    pub(crate) fn bake_config(&self) -> BakeConfig {
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
    pub(crate) fn last_prefilter_time(&self) -> Option<Duration> {
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
    /// that very map (the same `Arc`); a preparation of any other map builds its own. The
    /// map's sun is found on it here: planning, which comes before the map's preparation
    /// (`Renderer::prepare`), asks for it, and would otherwise build a chain of its own.
    pub(crate) fn offer_mip_chain(
        &mut self,
        map: Arc<crate::environment::EnvMap>,
        chain: crate::environment::MipChain,
    ) {
        map.sun_of_chain(&chain);
        self.environment.offer_chain(map, chain);
    }

    /// Rows in the memory cache.
    pub(crate) fn cached_rows(&self) -> usize {
        self.tables.cached_rows()
    }

    /// Draws `scene` into `target` and submits. Truth balls (`model = "truth"`) are path
    /// traced: each draw of an unchanged scene at the same size adds one estimate a pixel
    /// to their sums and shows the mean (`Renderer::truth_samples`).
    pub fn render(&mut self, scene: &Scene, target: Target<'_>) -> Result<()> {
        self.gpu.check()?;
        self.check_truth_supported(scene)?;
        self.submit_scoped(|r, encoder| r.encode(scene, target, encoder))
    }

    /// Runs `work` within error scopes (validation and out of memory: [`super::Scopes`]),
    /// so that what it raises is returned; the device is checked before and after. The
    /// one place the renderer pushes them.
    fn scoped<T>(&mut self, work: impl FnOnce(&mut Self) -> Result<T>) -> Result<T> {
        self.gpu.check()?;
        let scopes = super::Scopes::push(&self.gpu.device);
        let out = work(self);
        scopes.pop()?;
        let out = out?;
        self.gpu.check()?;
        Ok(out)
    }

    /// [`Renderer::scoped`] with a command encoder, submitted after `work` records.
    fn submit_scoped<T>(
        &mut self,
        work: impl FnOnce(&mut Self, &mut wgpu::CommandEncoder) -> Result<T>,
    ) -> Result<T> {
        self.scoped(|r| {
            let mut encoder = r.gpu.device.create_command_encoder(&Default::default());
            let out = work(r, &mut encoder);
            r.gpu.queue.submit([encoder.finish()]);
            out
        })
    }

    /// Whether this device can accumulate the truth: it renders to `Rgba32Float` (GL
    /// does not).
    pub fn truth_supported(&self) -> bool {
        self.gpu.renderable(SUM_FORMAT)
    }

    /// [`Error::TruthUnsupported`] if `scene` has truth balls and this device cannot
    /// accumulate them; [`Error::Invalid`] if a truth ball is clear-coated under the
    /// scene's lights (walk.wgsl's coat walk, as the CPU's, has no next-event estimation:
    /// it would be drawn without its lights).
    pub(crate) fn check_truth_supported(&self, scene: &Scene) -> Result<()> {
        if scene.has_truth() && !self.truth_supported() {
            return Err(Error::TruthUnsupported {
                device: self.gpu.describe(),
            });
        }
        scene.check_clearcoat_truth_lights(false)
    }
}
