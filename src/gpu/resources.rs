//! GPU resources of group 0 (`shaders/bindings.wgsl`): the uniform buffers and the tables,
//! read with `textureLoad` (no filtering feature needed): E as 2x2 blocks in `Rgba32Float`
//! ([`loss_quads`]), E_avg as `R32Float`.

use std::mem::size_of;

use super::uniforms::{Globals, GpuBall, GpuLight};
use crate::lut::{RowSet, Tables};
use crate::scene::{MAX_BALLS, MAX_LIGHTS};

/// Buffers and the layout of group 0; the bind group follows the tables.
pub struct Resources {
    pub layout: wgpu::BindGroupLayout,
    pub globals: wgpu::Buffer,
    pub balls: wgpu::Buffer,
    pub lights: wgpu::Buffer,
    /// Per-ball quads of the planned draw: [`BallInstance`] per ball, grouped by variant.
    pub instances: wgpu::Buffer,
}

/// One ball's quad (`vs_ball` in `balls.wgsl`): its bounds in NDC and its index.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct BallInstance {
    pub rect: [f32; 4],
    pub ball: u32,
}

impl BallInstance {
    /// The vertex layout of [`BallInstance`], one per instance.
    pub const LAYOUT: wgpu::VertexBufferLayout<'static> = wgpu::VertexBufferLayout {
        array_stride: size_of::<BallInstance>() as u64,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &wgpu::vertex_attr_array![0 => Float32x4, 1 => Uint32],
    };
}

/// A uniform buffer, visible to the vertex stage too: the ball renderer's vertex shaders read
/// the loop counts from `globals` for the fragment stage (`loop_counts` in `balls.wgsl`).
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

fn texture_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

fn uniform_buffer(device: &wgpu::Device, label: &str, size: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

impl Resources {
    pub fn new(device: &wgpu::Device) -> Self {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("group 0"),
            entries: &[
                uniform_entry(0),
                uniform_entry(1),
                uniform_entry(2),
                texture_entry(3),
                texture_entry(4),
            ],
        });
        Resources {
            layout,
            globals: uniform_buffer(device, "globals", size_of::<Globals>()),
            balls: uniform_buffer(device, "balls", size_of::<GpuBall>() * MAX_BALLS),
            lights: uniform_buffer(device, "lights", size_of::<GpuLight>() * MAX_LIGHTS),
            instances: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("ball quads"),
                size: (size_of::<BallInstance>() * MAX_BALLS) as u64,
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        }
    }

    /// Uploads `tables` (`1 - E`: mu_size x r_size 2x2 blocks, Rgba32Float; `1 - E_avg` and
    /// row roughness: r_size x 2, R32Float)
    /// and binds them with the buffers.
    pub fn bind_tables(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        tables: &Tables,
    ) -> wgpu::BindGroup {
        let l = tables.layout();
        // Row 0: 1 - E_avg per roughness row; row 1: each row's roughness as the power-law
        // read uses it (`Layout::row_roughness`, computed from the f64 texel coordinate
        // here so the shader does not re-derive it in f32).
        let mut e_avg_rows = tables.stored_loss_avg.clone();
        e_avg_rows.extend((0..l.r_size).map(|j| l.row_roughness(j)));
        self.bind(
            device,
            queue,
            &tables.stored_loss,
            l.mu_size,
            l.r_size,
            &e_avg_rows,
        )
    }

    /// Uploads a scene's rows as a `mu_size x rows` table (the same 2x2 blocks; a ball reads
    /// its row with a zero weight on the next), with each row's `1 - E_avg` and roughness
    /// in the E_avg texture (the renderer passes them per ball; the probe's `probe_rows_main`
    /// reads them).
    pub fn bind_rows(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        rows: &RowSet,
    ) -> wgpu::BindGroup {
        let n = rows.rows.len();
        let mut e_avg_rows: Vec<f32> = rows.rows.iter().map(|r| r.loss_avg).collect();
        e_avg_rows.extend(rows.rows.iter().map(|r| r.key.roughness()));
        let mu_size = rows.layout().mu_size;
        self.bind(device, queue, &rows.stored_loss(), mu_size, n, &e_avg_rows)
    }

    /// No tables: 1 x 1 placeholders, which the planned pipelines of such a scene never read
    /// (the term and the environment compiled out).
    pub fn bind_none(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> wgpu::BindGroup {
        self.bind(device, queue, &[0.0], 1, 1, &[0.0, 0.0])
    }

    fn bind(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        loss: &[f32],
        mu_size: usize,
        r_size: usize,
        e_avg_rows: &[f32],
    ) -> wgpu::BindGroup {
        let e = quad_texture(device, queue, mu_size, r_size, loss);
        let e_avg = r32_texture(device, queue, "1 - E_avg", r_size as u32, 2, e_avg_rows);
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
                    resource: wgpu::BindingResource::TextureView(&e),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::TextureView(&e_avg),
                },
            ],
        })
    }
}

/// A `width x height` table as 2x2 blocks: block (i, j) holds texels (i, j), (i + 1, j),
/// (i, j + 1), (i + 1, j + 1) (clamped at the last column and row), RGBA, so that a
/// bilinear read is one `textureLoad` (`loss_quad` in `lut.wgsl`). Four times the memory of
/// the table: 64 KiB at the default 64 x 64.
pub fn loss_quads(data: &[f32], width: usize, height: usize) -> Vec<f32> {
    let t = |i: usize, j: usize| data[j.min(height - 1) * width + i.min(width - 1)];
    (0..height)
        .flat_map(|j| {
            (0..width).flat_map(move |i| [t(i, j), t(i + 1, j), t(i, j + 1), t(i + 1, j + 1)])
        })
        .collect()
}

/// The E table as an `Rgba32Float` texture of [`loss_quads`].
pub fn quad_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    width: usize,
    height: usize,
    data: &[f32],
) -> wgpu::TextureView {
    let quads = loss_quads(data, width, height);
    let format = wgpu::TextureFormat::Rgba32Float;
    let (width, height) = (width as u32, height as u32);
    f32_texture(
        device,
        queue,
        "1 - E, 2x2 blocks",
        format,
        width,
        height,
        &quads,
    )
}

fn r32_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    width: u32,
    height: u32,
    data: &[f32],
) -> wgpu::TextureView {
    let format = wgpu::TextureFormat::R32Float;
    f32_texture(device, queue, label, format, width, height, data)
}

/// A sampled `width x height` texture of an f32 `format` (R32Float, Rgba32Float) holding
/// `data`, rows packed.
fn f32_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    format: wgpu::TextureFormat,
    width: u32,
    height: u32,
    data: &[f32],
) -> wgpu::TextureView {
    let size = wgpu::Extent3d {
        width,
        height,
        depth_or_array_layers: 1,
    };
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let bytes_per_texel = format.block_copy_size(None).unwrap_or(4);
    queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture: &texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        bytemuck::cast_slice(data),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(width * bytes_per_texel),
            rows_per_image: Some(height),
        },
        size,
    );
    texture.create_view(&wgpu::TextureViewDescriptor::default())
}
