//! The renderer's group 0 (`shaders/bindings.wgsl`): its layout, the uniform buffers, the
//! balls' storage buffer and the per-ball quads' vertex buffer; a bind group joins them
//! with the tables ([`GpuTables`], `upload.rs`).

use std::mem::{offset_of, size_of};

use super::ball;
use super::uniforms::{Globals, GpuBall, GpuLight, BALL_MEMBERS};
use super::upload::GpuTables;
use crate::lut::COATING_ROW_LEN;
use crate::scene::{MAX_BALLS, MAX_LIGHTS};

/// Buffers and the layout of group 0; the bind group follows the tables. Cloning shares
/// the buffers (wgpu's handles are references).
#[derive(Clone)]
pub(crate) struct Bindings {
    pub layout: wgpu::BindGroupLayout,
    pub globals: wgpu::Buffer,
    /// Every ball (storage, [`MAX_BALLS`] of them): read by no entry point since the
    /// full-screen path went (`bindings.wgsl` says why it stays).
    pub balls: wgpu::Buffer,
    pub lights: wgpu::Buffer,
    /// Per-ball quads of the planned draw: [`BallInstance`] per ball, grouped by variant.
    pub instances: wgpu::Buffer,
    /// The scene's coating rows (storage, a row for each of up to [`MAX_BALLS`] balls).
    pub coating_rows: wgpu::Buffer,
}

/// One ball's quad (`vs_ball` in `screen.wgsl`): its bounds in NDC and the ball's members,
/// which reach the fragment stage as flat varyings. An instance attribute rather than a
/// read of the balls buffer in the vertex stage: portable to adapters without storage
/// buffers in the vertex stage, and no gather.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct BallInstance {
    pub rect: [f32; 4],
    pub ball: GpuBall,
}

/// The vertex attributes of a [`BallInstance`]: `rect`, then the ball's members packed
/// (`gpu::ball`, generated from [`BALL_MEMBERS`]; `BallIn` of `types.wgsl`).
const ATTRIBUTES: [wgpu::VertexAttribute; 1 + ball::attribute_count(BALL_MEMBERS)] =
    ball::attributes(
        BALL_MEMBERS,
        offset_of!(BallInstance, rect) as u64,
        offset_of!(BallInstance, ball) as u64,
    );

impl BallInstance {
    /// The vertex layout of [`BallInstance`], one per instance (`BallIn` of `types.wgsl`,
    /// `vs_ball`'s input).
    pub(crate) const LAYOUT: wgpu::VertexBufferLayout<'static> = wgpu::VertexBufferLayout {
        array_stride: size_of::<BallInstance>() as u64,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &ATTRIBUTES,
    };
}

/// A uniform buffer, visible to the vertex stage too: the ball renderer's vertex shaders read
/// the loop counts from `globals` for the fragment stage (`loop_counts` in `screen.wgsl`).
fn uniform_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX
            | wgpu::ShaderStages::FRAGMENT
            | wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A read-only storage buffer: the balls (read by no entry point: `bindings.wgsl` says why
/// they stay; the probe's compute stage shares the layout), and the coating rows.
fn storage_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: TABLE_STAGES,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// The stages that read the tables: the ball renderer's fragments, the probe's compute.
const TABLE_STAGES: wgpu::ShaderStages =
    wgpu::ShaderStages::FRAGMENT.union(wgpu::ShaderStages::COMPUTE);

fn uniform_buffer(device: &wgpu::Device, label: &str, size: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

impl Bindings {
    pub(crate) fn new(device: &wgpu::Device) -> Self {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("group 0"),
            entries: &[
                uniform_entry(0),
                storage_entry(1),
                uniform_entry(2),
                GpuTables::layout_entry(3, TABLE_STAGES),
                GpuTables::layout_entry(4, TABLE_STAGES),
                storage_entry(5),
            ],
        });
        Bindings {
            layout,
            globals: uniform_buffer(device, "globals", size_of::<Globals>()),
            balls: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("balls"),
                size: (size_of::<GpuBall>() * MAX_BALLS) as u64,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            lights: uniform_buffer(device, "lights", size_of::<GpuLight>() * MAX_LIGHTS),
            instances: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("ball quads"),
                size: (size_of::<BallInstance>() * MAX_BALLS) as u64,
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            coating_rows: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("coating rows"),
                size: (size_of::<f32>() * COATING_ROW_LEN * MAX_BALLS) as u64,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        }
    }

    /// The bind group of these buffers with `tables`.
    pub(crate) fn bind(&self, device: &wgpu::Device, tables: &GpuTables) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("group 0"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: self.globals.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: self.balls.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: self.lights.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&tables.e),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::TextureView(&tables.e_avg),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: self.coating_rows.as_entire_binding(),
                },
            ],
        })
    }
}

/// A bind group layout of one texture at binding 0, read by the fragment stage with
/// `textureLoad` (unfilterable float, 2-D): the truth's sums, the viewer's blit source.
pub(crate) fn texture_load_layout(device: &wgpu::Device, label: &str) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        }],
    })
}
