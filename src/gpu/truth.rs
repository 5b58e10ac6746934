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
//! changes ([`same_scene`]). The sums, their bind groups and the resolve are `sums.rs`'s.

use std::collections::HashMap;

use super::bindings::BallInstance;
use super::pipelines::{self, is_bits, PipelineKey, Shape};
use super::plan::Variant;
use super::shaders;
use super::specialise::ParsedProgram;
use super::sums::{self, same_scene, Draw, Sums, SumsSpec, QUAD_PAD_PX, SUM_FORMAT};
use super::uniforms::GpuBall;
use crate::brdf::Geometry;
use crate::lut::MuAxis;
use crate::scene::{Model, Scene, MAX_BALLS};

/// What a truth pipeline is compiled for: G, mu axis, variant, and the entry point's role.
type Key = (Geometry, MuAxis, Variant, Role);

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Role {
    /// `fs_truth` into the sums.
    Truth,
    /// `fs_truth_occluder` into the sums.
    Occluder,
    /// `fs_truth_resolve` into a target of this format (from the bits program for a bits
    /// target).
    Resolve(wgpu::TextureFormat),
}

/// The truth's layout (group 2), programs (float or display output, and bits output: each
/// parsed on first use), pipelines, quads and the running sums.
pub(crate) struct TruthPass {
    layout: wgpu::BindGroupLayout,
    programs: [Option<ParsedProgram>; 2],
    pipeline_layout: wgpu::PipelineLayout,
    pipelines: HashMap<Key, wgpu::RenderPipeline>,
    /// The accumulation pass's quads: the truth balls', then the others'.
    instances: wgpu::Buffer,
    /// The scene (map compared by identity: [`same_scene`]) summed, and its sums (with a
    /// depth target).
    sums: Option<(Scene, Sums)>,
}

/// The accumulation pass's quads of `scene` at `size`: the truth balls', then the other
/// balls' (they hide what is behind them), each over its bounds without the antialiasing
/// pad (the walk traces one ray through each pixel's centre); `hidden` balls (by an
/// identical earlier one) are left out.
pub(crate) fn quads(
    scene: &Scene,
    balls: &[GpuBall],
    hidden: &[bool],
    size: (u32, u32),
) -> (Vec<BallInstance>, Vec<BallInstance>) {
    let members = |truth: bool| {
        let all = scene.balls.iter().enumerate();
        all.filter(move |(_, b)| (b.model == Model::Truth) == truth)
            .map(|(k, _)| k)
    };
    let quads = |truth| sums::quads(scene, (balls, hidden), size, QUAD_PAD_PX, members(truth));
    (quads(true), quads(false))
}

impl TruthPass {
    pub(crate) fn new(
        device: &wgpu::Device,
        group0: &wgpu::BindGroupLayout,
        group1: &wgpu::BindGroupLayout,
    ) -> Self {
        let layout = super::bindings::texture_load_layout(device, "truth sums");
        TruthPass {
            pipeline_layout: sums::pipeline_layout(device, "truth", [group0, group1, &layout]),
            layout,
            programs: [None, None],
            pipelines: HashMap::new(),
            instances: sums::quad_buffer(device, "truth quads"),
            sums: None,
        }
    }

    /// Estimates per truth pixel of the latest accumulation (`None` before any).
    pub(crate) fn frames(&self) -> Option<u32> {
        self.sums.as_ref().map(|(_, s)| s.frames())
    }

    /// Starts the sums again from zero at the next frame.
    pub(crate) fn reset(&mut self) {
        if let Some((_, s)) = &mut self.sums {
            s.reset();
        }
    }

    /// Records one frame of estimates for `scene` at `size`: `truth` are the truth balls'
    /// quads, `others` the other balls' (they hide what is behind them). Restarts the sums
    /// if the scene or the size changed.
    pub(crate) fn accumulate(
        &mut self,
        draw: &Draw<'_>,
        encoder: &mut wgpu::CommandEncoder,
        scene: &Scene,
        size: (u32, u32),
        quads: (&[BallInstance], &[BallInstance]),
    ) {
        let (truth, others) = quads;
        let fresh = match self.sums.take() {
            Some((held, s)) if s.size() == size && same_scene(&held, scene) => (held, s),
            Some((_, mut s)) if s.size() == size => {
                s.reset();
                (scene.clone(), s)
            }
            _ => {
                let spec = SumsSpec {
                    label: "truth sums",
                    format: SUM_FORMAT,
                    targets: 1,
                    size,
                    copy_src: false,
                    depth: true,
                };
                let s = Sums::new(draw.device, &self.layout, spec, &[], &[]);
                (scene.clone(), s)
            }
        };
        self.sums = Some(fresh);
        let truth_pipeline = self.pipeline(draw, Role::Truth).clone();
        let occluder_pipeline = self.pipeline(draw, Role::Occluder).clone();
        let mut all = truth.to_vec();
        all.extend_from_slice(others);
        all.truncate(MAX_BALLS);
        if !all.is_empty() {
            draw.queue
                .write_buffer(&self.instances, 0, bytemuck::cast_slice(&all));
        }
        let (_, sums) = self.sums.as_mut().expect("made above");
        sums.clear_if_empty(encoder);
        let zero = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
        let mut pass = sums.next_pass(encoder, (draw.group0, draw.group1), zero);
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
        sums.advance();
    }

    /// Records the resolve of the latest sums into `view` (of `format`), over the
    /// `size` rectangle at its top-left corner, keeping what is drawn there elsewhere.
    pub(crate) fn resolve(
        &mut self,
        draw: &Draw<'_>,
        encoder: &mut wgpu::CommandEncoder,
        view: &wgpu::TextureView,
        format: wgpu::TextureFormat,
        size: (u32, u32),
    ) {
        let pipeline = self.pipeline(draw, Role::Resolve(format)).clone();
        if let Some((_, sums)) = &self.sums {
            sums.resolve(draw, encoder, &pipeline, (view, wgpu::LoadOp::Load), size);
        }
    }

    /// The pipeline of `role` for `draw`'s choices, created on first use.
    fn pipeline(&mut self, draw: &Draw<'_>, role: Role) -> &wgpu::RenderPipeline {
        let key = (draw.geometry, draw.mu_axis, draw.variant, role);
        let bits = matches!(role, Role::Resolve(f) if is_bits(f));
        let program = self.programs[bits as usize].get_or_insert_with(|| {
            ParsedProgram::new(
                if bits { "truth bits" } else { "truth" },
                shaders::truth_source(bits),
            )
        });
        let layout = &self.pipeline_layout;
        self.pipelines
            .entry(key)
            .or_insert_with(|| create(draw, layout, program, role))
    }
}

/// A truth pipeline: the per-ball quads into the sums (with the depth test) for
/// [`Role::Truth`] and [`Role::Occluder`], the full-screen triangle into a target for
/// [`Role::Resolve`].
fn create(
    draw: &Draw<'_>,
    layout: &wgpu::PipelineLayout,
    program: &ParsedProgram,
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
    pipelines::create(draw.device, layout, program, key, shape)
}
