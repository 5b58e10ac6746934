//! The table probe: what the shader's `lut_e` / `lut_e_avg` return on an N x N grid, or
//! what `lut_loss_row` returns along a scene's own rows, computed on the GPU by
//! `shaders/probe.wgsl` (the same WGSL functions the renderer uses).

use std::sync::Arc;

use super::Renderer;
use crate::brdf::Geometry;
use crate::error::{Error, Result};
use crate::gpu::readback::read_buffer;
use crate::gpu::shaders;
use crate::lut::{RowSet, TableSet, Tables};
use crate::scene::Scene;

/// Largest probe grid side (N^2 / 64 workgroups must fit one dispatch dimension, 65535).
pub(crate) const MAX_PROBE_GRID: u32 = 1024;

/// One probe sample: `mu = i / (N - 1)`, `roughness = j / (N - 1)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeSample {
    /// Roughness of the read: `j / (N - 1)`, or the row's (clamped) along a scene's rows.
    pub roughness: f32,
    /// mu of the read (cos of the angle to the normal): `i / (N - 1)`.
    pub mu: f32,
    /// E as the shader reads it at `(mu, roughness)`.
    pub e: f32,
    /// E_avg as the shader reads it at `roughness` (a scene's row: the row's own).
    pub e_avg: f32,
}

impl Renderer {
    /// Evaluates the tables for `geometry` (baked if needed) on the GPU with the shader's
    /// own reads (`shaders/probe.wgsl`); row-major, row = roughness. Returns the tables
    /// read, for comparison.
    pub fn probe(&mut self, geometry: Geometry, n: u32) -> Result<(Arc<Tables>, Vec<ProbeSample>)> {
        check_grid(n)?;
        self.gpu.check()?;
        let tables = self.tables_for(geometry);
        let read = TableSet::Full(tables.clone());
        let values = self.dispatch(&read, geometry, [n, 0, 0, 0], n * n, shaders::PROBE_MAIN)?;
        let last = (n - 1) as f32;
        let samples = (0..n * n)
            .map(|k| ProbeSample {
                roughness: (k / n) as f32 / last,
                mu: (k % n) as f32 / last,
                e: values[2 * k as usize],
                e_avg: values[2 * k as usize + 1],
            })
            .collect();
        Ok((tables, samples))
    }

    /// Evaluates the rows `scene`'s plan reads, as its balls read them (`lut_loss_row` at
    /// each row's roughness with no weight on the next row), at `mu = i / (N - 1)`;
    /// row-major, row = the plan's rows in order. Returns the rows read (`None` when the
    /// plan reads no rows: no ball reads E (no term, no environment), or the 2-D table).
    pub(crate) fn probe_rows(
        &mut self,
        scene: &Scene,
        n: u32,
    ) -> Result<Option<(Arc<RowSet>, Vec<ProbeSample>)>> {
        check_grid(n)?;
        self.gpu.check()?;
        let plan = self.plan_for(scene);
        let (geometry, planned_rows) = (plan.geometry, !plan.rows().is_empty());
        let read = self.bound_tables();
        if !planned_rows {
            // What is bound then is an earlier scene's (kept: this plan reads nothing).
            return Ok(None);
        }
        let TableSet::Rows(rows) = &read else {
            return Ok(None);
        };
        let k = rows.rows.len() as u32;
        let values = self.dispatch(&read, geometry, [n, k, 0, 0], n * k, shaders::PROBE_ROWS)?;
        let last = (n - 1) as f32;
        let samples = (0..n * k)
            .map(|s| ProbeSample {
                roughness: rows.rows[(s / n) as usize].key.roughness(),
                mu: (s % n) as f32 / last,
                e: values[2 * s as usize],
                e_avg: values[2 * s as usize + 1],
            })
            .collect();
        Ok(Some((rows.clone(), samples)))
    }

    /// Runs `entry` of the probe module over `count` samples with the bound tables (`read`
    /// gives their uniforms) and the grid uniform `grid`: two f32 per sample.
    fn dispatch(
        &mut self,
        read: &TableSet,
        geometry: Geometry,
        grid_value: [u32; 4],
        count: u32,
        entry_point: &str,
    ) -> Result<Vec<f32>> {
        let (device, queue) = (self.gpu.device.clone(), self.gpu.queue.clone());
        let bind = self
            .tables
            .bound()
            .expect("tables bound above")
            .bind
            .clone();
        let globals = crate::gpu::uniforms::Globals {
            lut: read.lut_params(),
            ..bytemuck::Zeroable::zeroed()
        };
        let buffer = |label, size, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        use wgpu::BufferUsages as U;
        let out_size = u64::from(count) * 8;
        let readback = self.scoped(|r| {
            queue.write_buffer(&r.bindings.globals, 0, bytemuck::bytes_of(&globals));
            let grid = buffer("probe grid", 16, U::UNIFORM | U::COPY_DST);
            queue.write_buffer(&grid, 0, bytemuck::cast_slice(&grid_value));
            let out = buffer("probe out", out_size, U::STORAGE | U::COPY_SRC);
            let readback = buffer("probe readback", out_size, U::COPY_DST | U::MAP_READ);
            let (pipeline, group1) = probe_pipeline(
                &device,
                &r.bindings.layout,
                (&grid, &out),
                shaders::overrides(geometry, false, read.mu_axis()),
                entry_point,
            );
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_compute_pass(&Default::default());
                pass.set_pipeline(&pipeline);
                pass.set_bind_group(0, &bind, &[]);
                pass.set_bind_group(1, &group1, &[]);
                pass.dispatch_workgroups(count.div_ceil(64), 1, 1);
            }
            encoder.copy_buffer_to_buffer(&out, 0, &readback, 0, out_size);
            queue.submit([encoder.finish()]);
            Ok(readback)
        })?;
        let values = read_buffer(&device, &readback);
        self.gpu.check()?;
        Ok(bytemuck::pod_collect_to_vec(&values?))
    }
}

/// The probe's compute pipeline for `entry_point` with the override `constants`, over
/// group 0 (`layout0`, the renderer's) and its own group 1 (the grid uniform and the output
/// storage buffer), and that group bound to `grid` and `out`.
fn probe_pipeline(
    device: &wgpu::Device,
    layout0: &wgpu::BindGroupLayout,
    (grid, out): (&wgpu::Buffer, &wgpu::Buffer),
    constants: [(&str, f64); 3],
    entry_point: &str,
) -> (wgpu::ComputePipeline, wgpu::BindGroup) {
    let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let layout1 = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("probe"),
        entries: &[
            entry(0, wgpu::BufferBindingType::Uniform),
            entry(1, wgpu::BufferBindingType::Storage { read_only: false }),
        ],
    });
    let group1 = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("probe"),
        layout: &layout1,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: grid.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: out.as_entire_binding(),
            },
        ],
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("probe"),
        bind_group_layouts: &[Some(layout0), Some(&layout1)],
        immediate_size: 0,
    });
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("probe"),
        source: wgpu::ShaderSource::Wgsl(shaders::probe_source().into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("probe"),
        layout: Some(&layout),
        module: &module,
        entry_point: Some(entry_point),
        compilation_options: wgpu::PipelineCompilationOptions {
            constants: &constants,
            ..Default::default()
        },
        cache: None,
    });
    (pipeline, group1)
}

fn check_grid(n: u32) -> Result<()> {
    if !(2..=MAX_PROBE_GRID).contains(&n) {
        return Err(Error::Invalid {
            what: "probe grid",
            message: format!("{n} is outside 2..={MAX_PROBE_GRID}"),
        });
    }
    Ok(())
}
