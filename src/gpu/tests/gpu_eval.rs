//! Evaluates the WGSL BRDF functions (`shaders/brdf.wgsl`) and table reads
//! (`shaders/lut.wgsl`) on the GPU at given inputs, with a compute entry point appended to
//! the renderer's own shader files: the f32 side of the f32-versus-f64 comparisons and the
//! GPU edge grid in `gpu_stress.rs`. Each output has an f64 counterpart in [`cpu`], the same
//! functions of `src/brdf` at the same (f32) inputs.

use crate::brdf::{self, Geometry};
use crate::gpu::{shaders, uniforms, Renderer};
use crate::lut::Tables;
use wgpu::util::DeviceExt;

/// Inputs per sample: mu_o, mu_i, n.h, v.h, roughness, F0, loss_o, loss_i, loss_avg, F_avg,
/// E_avg, and the (mu, roughness) of a table read.
pub(crate) const INPUTS: usize = 13;

/// Names of the outputs per sample, in order (`eval_main` below).
pub(crate) const OUTPUTS: [&str; 19] = [
    "roughness_clamped",
    "alpha_from_roughness",
    "d_ggx",
    "g1_schlick",
    "g1_smith",
    "lambda_smith",
    "g_schlick",
    "g_smith",
    "g_smith_correlated",
    "f_schlick",
    "f_avg_schlick",
    "f_avg_games202",
    "f_ms",
    "f_add_accurate",
    "f_add_games202",
    "f_micro",
    "lut_loss",
    "lut_loss_avg",
    "f_r",
];

const STRIDE_OUT: usize = 20;

const ENTRY: &str = r#"
#import shadeballs::constants
#import shadeballs::brdf
#import shadeballs::lut
#import shadeballs::types
#import shadeballs::bindings

@group(1) @binding(0) var<storage, read> eval_in: array<f32>;
@group(1) @binding(1) var<storage, read_write> eval_out: array<f32>;

@compute @workgroup_size(64)
fn eval_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x;
    if k >= arrayLength(&eval_in) / 13u {
        return;
    }
    let i = k * 13u;
    let mu_o = eval_in[i];
    let mu_i = eval_in[i + 1u];
    let n_dot_h = eval_in[i + 2u];
    let v_dot_h = eval_in[i + 3u];
    let r = eval_in[i + 4u];
    let f0 = vec3<f32>(eval_in[i + 5u]);
    let alpha = alpha_from_roughness(r);
    let o = k * 20u;
    eval_out[o] = roughness_clamped(r);
    eval_out[o + 1u] = alpha;
    eval_out[o + 2u] = d_ggx(n_dot_h, alpha);
    eval_out[o + 3u] = g1_schlick(mu_o, alpha / 2.0);
    eval_out[o + 4u] = g1_smith(mu_o, alpha);
    eval_out[o + 5u] = lambda_smith(mu_o, alpha);
    eval_out[o + 6u] = g_schlick(mu_o, mu_i, r);
    eval_out[o + 7u] = g_smith(mu_o, mu_i, r);
    eval_out[o + 8u] = g_smith_correlated(mu_o, mu_i, r);
    let fresnel = f_schlick(f0, v_dot_h);
    eval_out[o + 9u] = fresnel.x;
    eval_out[o + 10u] = f_avg_schlick(f0).x;
    // The homework's fit with F0 as both reflectivity and edge tint.
    eval_out[o + 11u] = f_avg_games202(f0, f0).x;
    eval_out[o + 12u] = f_ms(eval_in[i + 6u], eval_in[i + 7u], eval_in[i + 8u]);
    eval_out[o + 13u] = f_add_accurate(vec3<f32>(eval_in[i + 9u]), eval_in[i + 10u]).x;
    eval_out[o + 14u] = f_add_games202(vec3<f32>(eval_in[i + 9u]), eval_in[i + 10u]).x;
    let spec = f_micro(fresnel, mu_o, mu_i, n_dot_h, r, GEOMETRY).x;
    eval_out[o + 15u] = spec;
    eval_out[o + 16u] = lut_loss(e_table, lut_params(), eval_in[i + 11u], eval_in[i + 12u]);
    eval_out[o + 17u] = lut_loss_avg(e_avg_table, lut_params(), eval_in[i + 12u]);
    // The lighting.wgsl combination for one light: f_micro + f_add f_ms, tables read.
    let loss_avg = lut_loss_avg(e_avg_table, lut_params(), r);
    // The normalisation as src/brdf f_ms_norm forms it (per ball on the CPU in the renderer).
    let norm = 1.0 / max(PI * loss_avg, DIV_EPSILON);
    let lobe = f_ms(lut_loss(e_table, lut_params(), mu_o, r), lut_loss(e_table, lut_params(), mu_i, r), norm);
    eval_out[o + 18u] = spec + (f_add_accurate(f_avg_schlick(f0), 1.0 - loss_avg) * lobe).x;
}
"#;

/// Largest batch of samples per dispatch (keeps each storage binding under 64 MiB).
const CHUNK: usize = 1 << 18;

/// The outputs of [`OUTPUTS`] for every sample of `inputs` (`INPUTS` floats each), with the
/// G of `geometry` in `f_micro` and `f_r`, and `tables` behind the table reads.
pub(crate) fn evaluate(
    r: &Renderer,
    tables: &Tables,
    geometry: Geometry,
    inputs: &[f32],
) -> Vec<[f32; 19]> {
    let (device, queue) = (&r.gpu().device, &r.gpu().queue);
    let source = crate::wgsl::compose("eval", ENTRY, &[])
        .expect("the eval module composes")
        .source;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("eval"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let constants = shaders::overrides(geometry, true, tables.layout().mu_axis);
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("eval"),
        layout: None,
        module: &module,
        entry_point: Some("eval_main"),
        compilation_options: wgpu::PipelineCompilationOptions {
            constants: &constants,
            ..Default::default()
        },
        cache: None,
    });
    let group0 = table_group(device, queue, &pipeline, tables);
    let mut out = Vec::with_capacity(inputs.len() / INPUTS);
    for chunk in inputs.chunks(CHUNK * INPUTS) {
        let n = chunk.len() / INPUTS;
        let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("eval in"),
            contents: bytemuck::cast_slice(chunk),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let size = (n * STRIDE_OUT * 4) as u64;
        let output = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("eval out"),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("eval readback"),
            size,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let group1 = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("eval io"),
            layout: &pipeline.get_bind_group_layout(1),
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: input.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: output.as_entire_binding(),
                },
            ],
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &group0, &[]);
            pass.set_bind_group(1, &group1, &[]);
            pass.dispatch_workgroups(n.div_ceil(64) as u32, 1, 1);
        }
        encoder.copy_buffer_to_buffer(&output, 0, &readback, 0, size);
        queue.submit([encoder.finish()]);
        let bytes = crate::gpu::readback::read_buffer(device, &readback).unwrap();
        let values: Vec<f32> = bytemuck::pod_collect_to_vec(&bytes);
        out.extend(values.chunks_exact(STRIDE_OUT).map(|v| {
            let mut row = [0.0; 19];
            row.copy_from_slice(&v[..19]);
            row
        }));
    }
    r.gpu().check().expect("the device reported an error");
    out
}

/// Group 0 as `bindings.wgsl` declares it, for the table reads: the table uniforms, the E
/// table in 2x2 blocks and the R32Float E_avg rows, as `GpuTables::upload` makes them.
fn table_group(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    pipeline: &wgpu::ComputePipeline,
    tables: &Tables,
) -> wgpu::BindGroup {
    // The tables as the renderer and any host upload them (the facade's GpuTables).
    let gpu_tables = crate::GpuTables::upload(device, queue, tables);
    let globals = uniforms::Globals {
        lut: gpu_tables.params,
        ..bytemuck::Zeroable::zeroed()
    };
    let globals = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("eval globals"),
        contents: bytemuck::bytes_of(&globals),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let (e, e_avg) = (&gpu_tables.e, &gpu_tables.e_avg);
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("eval tables"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: globals.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::TextureView(e),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: wgpu::BindingResource::TextureView(e_avg),
            },
        ],
    })
}

/// The f64 counterparts of [`OUTPUTS`] at the same inputs (`src/brdf`; the table reads are
/// the CPU model of the shader's, `Tables::lut_loss`, itself f32).
pub(crate) fn cpu(tables: &Tables, geometry: Geometry, x: &[f32]) -> [f64; 19] {
    let f = |k: usize| x[k] as f64;
    let (mu_o, mu_i, n_dot_h, v_dot_h, r, f0) = (f(0), f(1), f(2), f(3), f(4), f(5));
    let alpha = brdf::alpha_from_roughness(r);
    let fresnel = brdf::f_schlick(f0, v_dot_h);
    let spec = brdf::f_micro(fresnel, mu_o, mu_i, n_dot_h, r, geometry);
    let rf = x[4];
    let loss_avg = tables.lut_loss_avg(rf) as f64;
    let lobe = brdf::f_ms(
        tables.lut_loss(x[0], rf) as f64,
        tables.lut_loss(x[1], rf) as f64,
        brdf::f_ms_norm(loss_avg),
    );
    [
        brdf::roughness_clamped(r),
        alpha,
        brdf::d_ggx(n_dot_h, alpha),
        brdf::g1_schlick(mu_o, alpha / 2.0),
        brdf::g1_smith(mu_o, alpha),
        brdf::lambda_smith(mu_o, alpha),
        brdf::g_schlick(mu_o, mu_i, r),
        brdf::g_smith(mu_o, mu_i, r),
        brdf::g_smith_correlated(mu_o, mu_i, r),
        fresnel,
        brdf::f_avg_schlick(f0),
        brdf::f_avg_games202(f0, f0),
        brdf::f_ms(f(6), f(7), f(8)),
        brdf::f_add_accurate(f(9), f(10)),
        brdf::f_add_games202(f(9), f(10)),
        spec,
        tables.lut_loss(x[11], x[12]) as f64,
        tables.lut_loss_avg(x[12]) as f64,
        spec + brdf::f_add_accurate(brdf::f_avg_schlick(f0), 1.0 - loss_avg) * lobe,
    ]
}
