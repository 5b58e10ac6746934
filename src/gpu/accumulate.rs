//! The lobe's progressive image on the GPU (`ibl_method = "lobe"`, docs/design/environment.md,
//! "Lighting that follows the lobe"): frame `k` of the lobe's samples is drawn by the ball
//! renderer into an `Rgba32Uint` frame (the bits of linear radiance), added to running sums
//! held on the GPU (`fs_lobe_accumulate` in `accumulate.wgsl`: the bits of f32 sums, the
//! count of frames in alpha, two textures read and written in turn), and the sums' mean
//! resolved into the caller's target (`fs_lobe_resolve`). Nothing is read back per frame.
//!
//! The sums start again from zero whenever what the image depends on changes ([`LobeKey`]:
//! the scene but for its exposure and display transform, the size, the tables and the draw
//! options), so that a changed scene restarts the count at one frame.

use std::collections::HashMap;

use super::pipelines::{self, is_bits, PipelineKey, Shape};
use super::plan::{DrawOptions, Plan};
use super::shaders;
use super::specialise::ParsedProgram;
use super::sums::{self, same_scene, Draw, Sums, SumsSpec};
use crate::lut::{BakeConfig, TableKey};
use crate::scene::Scene;

/// The format of the frame and of the sums: the bits of f32 (renderable on GL, which
/// renders to no 32-bit float format, as on Vulkan).
pub(crate) const LOBE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;

/// [`crate::gpu::Variant::ibl`] of a draw lit by the lobe's samples.
pub(crate) const LOBE_IBL: u8 = 2;

/// What the lobe's sums depend on: the scene (compared by [`same_scene`]: not its exposure
/// or display transform, the sums being linear), the image's size, and the plan's tables,
/// bake settings and draw options.
#[derive(Clone)]
pub(crate) struct LobeKey {
    pub scene: Scene,
    pub size: (u32, u32),
    pub tables: TableKey,
    pub bake: BakeConfig,
    pub options: DrawOptions,
}

impl LobeKey {
    /// The key of `scene` drawn at `size` with `plan` under `options`.
    pub(crate) fn new(scene: &Scene, size: (u32, u32), plan: &Plan, options: DrawOptions) -> Self {
        LobeKey {
            scene: scene.clone(),
            size,
            tables: plan.tables.clone(),
            bake: plan.bake,
            options,
        }
    }

    /// Whether sums kept for `self` hold the image of `other` too.
    fn same(&self, other: &LobeKey) -> bool {
        self.size == other.size
            && self.tables == other.tables
            && self.bake == other.bake
            && self.options == other.options
            && same_scene(&self.scene, &other.scene)
    }
}

/// Which entry point a pipeline of the accumulation runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Role {
    /// `fs_lobe_accumulate` into the sums.
    Accumulate,
    /// `fs_lobe_resolve` into a target.
    Resolve,
}

/// The accumulation's layout (group 2), programs (parsed on first use), pipelines and sums.
pub(crate) struct LobePass {
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    /// Float or display output, and bits output (each made on first use).
    programs: [Option<ParsedProgram>; 2],
    pipelines: HashMap<(Role, PipelineKey), wgpu::RenderPipeline>,
    sums: Option<Held>,
}

/// The key summed, the frame texture's view and the sums (whose bind groups read the
/// frame too).
struct Held {
    key: LobeKey,
    frame: wgpu::TextureView,
    sums: Sums,
}

impl LobePass {
    pub(crate) fn new(
        device: &wgpu::Device,
        group0: &wgpu::BindGroupLayout,
        group1: &wgpu::BindGroupLayout,
    ) -> Self {
        let entry = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Uint,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("lobe sums"),
            entries: &[entry(0), entry(1)],
        });
        let pipeline_layout =
            sums::pipeline_layout(device, "lobe accumulation", [group0, group1, &layout]);
        LobePass {
            layout,
            pipeline_layout,
            programs: [None, None],
            pipelines: HashMap::new(),
            sums: None,
        }
    }

    /// Frames summed so far (`None` when no sums are held).
    pub(crate) fn frames(&self) -> Option<u32> {
        self.sums.as_ref().map(|s| s.sums.frames())
    }

    /// Lobe samples a pixel a frame of the sums held (0 when none are held).
    pub(crate) fn samples_a_frame(&self) -> u32 {
        self.sums.as_ref().map_or(0, |s| s.key.scene.ibl_samples)
    }

    /// Starts the sums again from zero at the next frame.
    pub(crate) fn reset(&mut self) {
        if let Some(s) = &mut self.sums {
            s.sums.reset();
        }
    }

    /// Drops the sums (the latest scene uses no lobe).
    pub(crate) fn forget(&mut self) {
        self.sums = None;
    }

    /// Makes the sums hold `key`'s image: kept where they already do, else started again
    /// from zero (the textures kept where the size is the same). Returns the frames
    /// summed so far.
    pub(crate) fn start(&mut self, device: &wgpu::Device, key: LobeKey) -> u32 {
        match self.sums.take() {
            Some(s) if s.key.same(&key) => self.sums = Some(s),
            Some(mut s) if s.key.size == key.size => {
                s.sums.reset();
                s.key = key;
                self.sums = Some(s);
            }
            _ => self.sums = Some(Held::new(device, &self.layout, key)),
        }
        self.frames().unwrap_or(0)
    }

    /// The view the ball pass draws this frame into (after [`LobePass::start`]).
    pub(crate) fn frame_view(&self) -> Option<&wgpu::TextureView> {
        self.sums.as_ref().map(|s| &s.frame)
    }

    /// Records the addition of the frame drawn into [`LobePass::frame_view`] to the sums.
    pub(crate) fn accumulate(&mut self, draw: &Draw<'_>, encoder: &mut wgpu::CommandEncoder) {
        let pipeline = self.pipeline(draw, Role::Accumulate, LOBE_FORMAT).clone();
        let Some(held) = self.sums.as_mut() else {
            return;
        };
        held.sums.clear_if_empty(encoder);
        // The full-screen triangle writes every pixel: the older sums need no clear.
        let groups = (draw.group0, draw.group1);
        let mut pass = held.sums.next_pass(encoder, groups, wgpu::LoadOp::Load);
        pass.set_pipeline(&pipeline);
        pass.draw(0..3, 0..1);
        drop(pass);
        held.sums.advance();
    }

    /// Records the resolve of the sums' mean into `view` (of `format`) over the `size`
    /// rectangle at its top-left corner, the rest of the attachment cleared to `clear`
    /// (as the ball pass clears it).
    pub(crate) fn resolve(
        &mut self,
        draw: &Draw<'_>,
        encoder: &mut wgpu::CommandEncoder,
        (view, format): (&wgpu::TextureView, wgpu::TextureFormat),
        size: (u32, u32),
        clear: wgpu::Color,
    ) {
        let pipeline = self.pipeline(draw, Role::Resolve, format).clone();
        if let Some(held) = &self.sums {
            let target = (view, wgpu::LoadOp::Clear(clear));
            held.sums.resolve(draw, encoder, &pipeline, target, size);
        }
    }

    /// The pipeline of `role` into `format` for `draw`'s choices, made on first use.
    fn pipeline(
        &mut self,
        draw: &Draw<'_>,
        role: Role,
        format: wgpu::TextureFormat,
    ) -> &wgpu::RenderPipeline {
        let key = PipelineKey {
            format,
            geometry: draw.geometry,
            mu_axis: draw.mu_axis,
            variant: draw.variant,
        };
        // The accumulation writes bits whatever the program; only a resolve into a bits
        // target needs the bits program's output.
        let bits = role == Role::Resolve && is_bits(format);
        let program = self.programs[bits as usize].get_or_insert_with(|| {
            ParsedProgram::new("lobe accumulation", shaders::accumulate_source(bits))
        });
        let layout = &self.pipeline_layout;
        self.pipelines.entry((role, key)).or_insert_with(|| {
            let shape = Shape {
                label: "lobe accumulation",
                vs: shaders::VS_MAIN,
                fs: match role {
                    Role::Accumulate => shaders::FS_LOBE_ACCUMULATE,
                    Role::Resolve => shaders::FS_LOBE_RESOLVE,
                },
                buffers: &[],
                topology: wgpu::PrimitiveTopology::TriangleList,
                depth: None,
            };
            pipelines::create(draw.device, layout, program, key, shape)
        })
    }
}

impl Held {
    fn new(device: &wgpu::Device, layout: &wgpu::BindGroupLayout, key: LobeKey) -> Self {
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let frame = sums::texture(device, "lobe frame", LOBE_FORMAT, key.size, usage)
            .create_view(&Default::default());
        let spec = SumsSpec {
            label: "lobe sums",
            format: LOBE_FORMAT,
            targets: 1,
            size: key.size,
            copy_src: false,
            depth: false,
        };
        let leading = [wgpu::BindingResource::TextureView(&frame)];
        let sums = Sums::new(device, layout, spec, &leading, &[]);
        Held { key, frame, sums }
    }
}
