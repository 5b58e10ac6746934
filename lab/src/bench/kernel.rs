//! The compiled kernel the lookup sweep times (`lookup.rs`): its shader (the common files
//! and `lookup.wgsl`), its entry points ([`Filter`]), and the pipeline, bind groups and
//! buffers for up to [`INVOCATIONS`] invocations, with one timed dispatch.

use super::device::{self, buffer, entry, loss_texture, texture};
use shadeballs::error::{Error, Result};
use shadeballs::gpu::{shaders, uniforms, Gpu};
use shadeballs::lut::Tables;

/// Invocations of a timed dispatch.
pub const INVOCATIONS: u32 = 1 << 16;

/// How the read filters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    /// No read: the loop's own cost.
    None,
    /// `lut_loss`: one `textureLoad` of a 2x2 block and three lerps in f32 (the renderer's
    /// read).
    Manual,
    /// One `textureSampleLevel` with a linear, clamp-to-edge sampler.
    Hardware,
}

impl Filter {
    pub fn name(self) -> &'static str {
        match self {
            Filter::None => "none",
            Filter::Manual => "manual",
            Filter::Hardware => "hardware",
        }
    }

    pub fn entry_point(self) -> &'static str {
        match self {
            Filter::None => "lookup_none",
            Filter::Manual => "lookup_manual",
            Filter::Hardware => "lookup_filtered",
        }
    }
}

/// The lookup module: `lookup.wgsl` and the crate's modules it imports.
pub fn lookup_source() -> std::result::Result<String, shadeballs::wgsl::ComposeError> {
    let root = include_str!("lookup.wgsl");
    shadeballs::wgsl::compose("lookup.wgsl", root, &[]).map(|c| c.source)
}

/// A compiled lookup pipeline with its bind groups and buffers (for up to
/// [`INVOCATIONS`] invocations).
pub struct Kernel {
    pipeline: wgpu::ComputePipeline,
    group0: wgpu::BindGroup,
    group1: wgpu::BindGroup,
    params: wgpu::Buffer,
    out: wgpu::Buffer,
    readback: wgpu::Buffer,
}

impl Kernel {
    pub fn new(gpu: &Gpu, tables: &Tables, filter: Filter) -> Result<Self> {
        let device = &gpu.device;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let globals = uniforms::Globals {
            lut: tables.layout().lut_params(),
            ..bytemuck::Zeroable::zeroed()
        };
        let globals_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("bench globals"),
            size: std::mem::size_of::<uniforms::Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        gpu.queue
            .write_buffer(&globals_buffer, 0, bytemuck::bytes_of(&globals));
        // e_table: the renderer's 2x2 blocks; filtered_table: one texel each, in the storage
        // format, for the sampler.
        let quads = shadeballs::gpu::GpuTables::upload(device, &gpu.queue, tables).e;
        let view = loss_texture(gpu, tables);
        let layout0 = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("bench group 0"),
            entries: &[
                entry(0, buffer(wgpu::BufferBindingType::Uniform)),
                entry(3, texture(false)),
            ],
        });
        let group0 = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("bench group 0"),
            layout: &layout0,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: globals_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&quads),
                },
            ],
        });
        let hardware = filter == Filter::Hardware;
        let mut entries1 = vec![entry(0, buffer(wgpu::BufferBindingType::Uniform))];
        if hardware {
            entries1.push(entry(1, texture(true)));
            entries1.push(entry(
                2,
                wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
            ));
        }
        entries1.push(entry(
            3,
            buffer(wgpu::BufferBindingType::Storage { read_only: false }),
        ));
        let layout1 = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("bench group 1"),
            entries: &entries1,
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("bench lookup"),
            bind_group_layouts: &[Some(&layout0), Some(&layout1)],
            immediate_size: 0,
        });
        let source = lookup_source().map_err(|e| Error::Gpu {
            message: e.to_string(),
        })?;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("bench lookup"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let constants = shaders::overrides(tables.config.geometry, false, tables.layout().mu_axis);
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("bench lookup"),
            layout: Some(&layout),
            module: &module,
            entry_point: Some(filter.entry_point()),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: &constants,
                ..Default::default()
            },
            cache: None,
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("bilinear, clamp to edge"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("lookup params"),
            size: 16,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let size = INVOCATIONS as u64 * 4;
        let out = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("lookup out"),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("lookup readback"),
            size,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut entries = vec![wgpu::BindGroupEntry {
            binding: 0,
            resource: params.as_entire_binding(),
        }];
        if hardware {
            entries.push(wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(&view),
            });
            entries.push(wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::Sampler(&sampler),
            });
        }
        entries.push(wgpu::BindGroupEntry {
            binding: 3,
            resource: out.as_entire_binding(),
        });
        let group1 = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("lookup group 1"),
            layout: &layout1,
            entries: &entries,
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(Error::Gpu {
                message: e.to_string(),
            });
        }
        Ok(Kernel {
            pipeline,
            group0,
            group1,
            params,
            out,
            readback,
        })
    }

    /// One dispatch of `n` (at most [`INVOCATIONS`]) invocations with `reads` reads each;
    /// waits for it and, when `read_back`, returns each invocation's sum.
    pub fn run(&self, gpu: &Gpu, reads: u32, n: u32, read_back: bool) -> Result<Vec<f32>> {
        let n = n.min(INVOCATIONS);
        gpu.queue
            .write_buffer(&self.params, 0, bytemuck::cast_slice(&[reads, n, 0, 0]));
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.group0, &[]);
            pass.set_bind_group(1, &self.group1, &[]);
            pass.dispatch_workgroups(n.div_ceil(64), 1, 1);
        }
        let size = n as u64 * 4;
        if read_back {
            encoder.copy_buffer_to_buffer(&self.out, 0, &self.readback, 0, size);
        }
        gpu.queue.submit([encoder.finish()]);
        device::wait(gpu)?;
        if !read_back {
            return Ok(Vec::new());
        }
        let bytes = device::read(gpu, &self.readback, size)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }
}
