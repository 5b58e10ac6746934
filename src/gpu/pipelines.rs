//! The ball renderer's pipelines: one per shader variant and target, created on first use
//! from the program of the target's output (bits or not: the shader def `OUTPUT_BITS`)
//! specialised to the variant's override constants (`types.wgsl`; `specialise.rs`): the
//! per-ball entry points with their instance buffer, and the background's full-screen
//! triangle.

use std::collections::HashMap;

use super::bindings::{BallInstance, Bindings};
use super::plan::{Plan, Variant};
use super::shaders;
use super::specialise::ParsedProgram;
use crate::brdf::Geometry;
use crate::lut::MuAxis;

/// Everything a ball pipeline is compiled for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct PipelineKey {
    /// The target's format (linear, display or bits output: [`is_linear`], [`is_bits`]).
    pub format: wgpu::TextureFormat,
    /// The G of `f_micro` (`GEOMETRY`).
    pub geometry: Geometry,
    /// The mu axis of the tables the pipeline reads (`MU_AXIS`).
    pub mu_axis: MuAxis,
    /// The shader variant (the override constants of `types.wgsl`).
    pub variant: Variant,
}

/// The pipeline key that draws `variant` of `plan` into `format`. The mu axis is the plan's
/// bake layout's: the tables it binds are baked with it (or, pinned by
/// `Renderer::set_tables`, set it), and with no tables nothing reads the axis.
pub(crate) fn pipeline_key(
    plan: &Plan,
    format: wgpu::TextureFormat,
    variant: Variant,
) -> PipelineKey {
    PipelineKey {
        format,
        geometry: plan.geometry,
        mu_axis: plan.bake.layout.mu_axis,
        variant,
    }
}

/// The depth target of the per-ball draw (`Renderer`'s own, sized to each colour target):
/// f32, so that `fs_ball`'s depths (distances scaled by a power of two) keep every bit.
pub(crate) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Whether `format` gets linear radiance rather than display values: float formats, and
/// `Rgba32Uint`, which gets its f32 bits ([`is_bits`]).
pub(crate) fn is_linear(format: wgpu::TextureFormat) -> bool {
    matches!(
        format,
        wgpu::TextureFormat::Rgba32Float
            | wgpu::TextureFormat::Rgba16Float
            | wgpu::TextureFormat::R32Float
    ) || is_bits(format)
}

/// Whether `format` gets the bits of linear radiance as f32 (the modules composed with the
/// shader def `OUTPUT_BITS`): `Rgba32Uint`, the f32 target of backends that render to no 32-bit float format (GL;
/// integer formats are colour-renderable there), read back as f32 by `render_hdr`.
pub(crate) fn is_bits(format: wgpu::TextureFormat) -> bool {
    format == wgpu::TextureFormat::Rgba32Uint
}

/// The ball programs (float or display output, and bits output: each parsed on first use),
/// their pipeline layout and the pipelines made so far.
pub(crate) struct Pipelines {
    programs: [Option<ParsedProgram>; 2],
    /// Whether the programs are specialised per pipeline (always, but in the tests that
    /// compare the two).
    specialise: bool,
    layout: wgpu::PipelineLayout,
    made: HashMap<PipelineKey, wgpu::RenderPipeline>,
    backgrounds: HashMap<PipelineKey, wgpu::RenderPipeline>,
}

impl Pipelines {
    pub(crate) fn new(
        device: &wgpu::Device,
        bindings: &Bindings,
        environment: &wgpu::BindGroupLayout,
    ) -> Self {
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("balls"),
            bind_group_layouts: &[Some(&bindings.layout), Some(environment)],
            immediate_size: 0,
        });
        Pipelines {
            programs: [None, None],
            specialise: true,
            layout,
            made: HashMap::new(),
            backgrounds: HashMap::new(),
        }
    }

    /// The background pipeline (`fs_background`: the environment map behind the balls)
    /// for `format` and `variant`'s map, in the per-ball pass (depth attached, untouched).
    pub(crate) fn background(
        &mut self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        variant: Variant,
        geometry: Geometry,
        mu_axis: MuAxis,
    ) -> &wgpu::RenderPipeline {
        let key = PipelineKey {
            format,
            geometry,
            mu_axis,
            variant,
        };
        let program = program(&mut self.programs, is_bits(format), self.specialise);
        let layout = &self.layout;
        self.backgrounds.entry(key).or_insert_with(|| {
            let shape = Shape {
                label: "background",
                // At the far plane, after the balls: only where no ball wrote its depth
                // (a ball's antialiased edge mixes in the background itself).
                vs: shaders::VS_FAR,
                fs: shaders::FS_BACKGROUND,
                buffers: &[],
                topology: wgpu::PrimitiveTopology::TriangleList,
                depth: Some((false, wgpu::CompareFunction::LessEqual)),
            };
            create(device, layout, program, key, shape)
        })
    }

    /// From now on, pipelines from the whole programs with their constants handed to wgpu
    /// (`false`) or from the programs specialised to them (`true`, the default); drops
    /// what was made.
    #[cfg(test)]
    pub(crate) fn set_specialise(&mut self, on: bool) {
        self.specialise = on;
        self.programs = [None, None];
        self.made.clear();
        self.backgrounds.clear();
    }

    /// The pipeline of `key`, created on first use.
    pub(crate) fn get(&mut self, device: &wgpu::Device, key: PipelineKey) -> &wgpu::RenderPipeline {
        let program = program(&mut self.programs, is_bits(key.format), self.specialise);
        let layout = &self.layout;
        self.made.entry(key).or_insert_with(|| {
            let shape = Shape {
                label: "balls",
                vs: shaders::VS_BALL,
                fs: shaders::FS_BALL,
                buffers: &[Some(BallInstance::LAYOUT)],
                // A quad a ball: one strip of two triangles an instance (4 vertices,
                // not 6).
                topology: wgpu::PrimitiveTopology::TriangleStrip,
                // The quads write each hit's depth (`fs_ball`); the nearest ball stays.
                depth: Some((true, wgpu::CompareFunction::Less)),
            };
            create(device, layout, program, key, shape)
        })
    }
}

/// The ball program for a bits target (`bits`) or another, parsed on first use
/// (`specialise` false: handed to wgpu whole, in the tests).
fn program(
    programs: &mut [Option<ParsedProgram>; 2],
    bits: bool,
    specialise: bool,
) -> &ParsedProgram {
    programs[bits as usize].get_or_insert_with(|| {
        let label = if bits { "balls bits" } else { "balls" };
        let source = shaders::balls_source(bits);
        if specialise {
            ParsedProgram::new(label, source)
        } else {
            ParsedProgram::unspecialised(label, source)
        }
    })
}

/// What differs between the ball module's pipelines: entry points, vertex buffers,
/// topology, and the depth test (`(write, compare)` against [`DEPTH_FORMAT`], or none).
pub(super) struct Shape<'a> {
    pub label: &'a str,
    pub vs: &'a str,
    pub fs: &'a str,
    pub buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    pub topology: wgpu::PrimitiveTopology,
    pub depth: Option<(bool, wgpu::CompareFunction)>,
}

/// A pipeline of `program`'s entry points in `shape`, each specialised to the override
/// constants of `key` (its G, mu axis and variant; linear or bits output for its format,
/// and whether the format is sRGB), into its format.
pub(super) fn create(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    program: &ParsedProgram,
    key: PipelineKey,
    shape: Shape<'_>,
) -> wgpu::RenderPipeline {
    let PipelineKey {
        format,
        geometry,
        mu_axis,
        variant,
        ..
    } = key;
    let constants = shaders::overrides_for(
        geometry,
        is_linear(format),
        mu_axis,
        variant,
        format.is_srgb(),
    );
    let vertex = program.stage(device, naga::ShaderStage::Vertex, shape.vs, &constants);
    let fragment = program.stage(device, naga::ShaderStage::Fragment, shape.fs, &constants);
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(shape.label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module: &vertex.module,
            entry_point: Some(shape.vs),
            compilation_options: vertex.options(),
            buffers: shape.buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology: shape.topology,
            ..Default::default()
        },
        depth_stencil: shape.depth.map(|(write, compare)| wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(write),
            depth_compare: Some(compare),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        }),
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module: &fragment.module,
            entry_point: Some(shape.fs),
            compilation_options: fragment.options(),
            targets: &[Some(wgpu::ColorTargetState {
                format,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}
