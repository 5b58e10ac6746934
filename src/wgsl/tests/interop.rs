//! The BRDF out (docs/interop.md): `export-shader` writes the ball shading through naga's
//! back ends (its GLSL passes glslangValidator), `bake --out tables.h|.glsl` writes the
//! tables as C / GLSL arrays that compile and hold the bake's values exactly.

/// The exported program's `fs_ball`, run on lavapipe through wgpu with the uniforms
/// docs/interop.md describes, shades each pixel as the crate's CPU renderer shades the
/// same ball (`cpu::shade`: one light and a uniform environment), for a plastic, a metal
/// and a half-metal, under both readings.
#[test]
fn the_exported_fragment_shades_as_the_renderer() {
    use crate::prepared::{CoatingConstants, Prepared};
    use crate::scene::{Ball, BaseReading, Light, Material, Model, Scene};
    use glam::DVec3;
    const SIZE: u32 = 32;
    let gpu = match crate::gpu::Gpu::new(wgpu::Backends::VULKAN) {
        Ok(gpu) => gpu,
        Err(e) => panic!(
            "GPU test cannot run: {e}. Install lavapipe: apt-get install -y \
             --no-install-recommends mesa-vulkan-drivers libvulkan1"
        ),
    };
    let (device, queue) = (&gpu.device, &gpu.queue);
    let tables = crate::bake(&crate::BakeConfig {
        geometry: crate::Geometry::SmithCorrelated,
        ..Default::default()
    });
    let gpu_tables = crate::GpuTables::upload(device, queue, &tables);
    let e = crate::lut::TableSet::full(tables.clone());
    // The program as exported, and a full-screen triangle to run it.
    let source = format!(
        "{}\n@vertex fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {{\n    \
         return vec4<f32>(f32((i << 1u) & 2u) * 2.0 - 1.0, f32(i & 2u) * 2.0 - 1.0, 0.0, 1.0);\n}}\n",
        crate::wgsl::export::ball_program()
    );
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("exported ball"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let format = wgpu::TextureFormat::Rgba32Float;
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("exported ball"),
        layout: None,
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: Default::default(),
        depth_stencil: None,
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs_ball"),
            compilation_options: Default::default(),
            targets: &[Some(format.into())],
        }),
        multiview_mask: None,
        cache: None,
    });
    let light = DVec3::new(0.3, 0.5, 0.8).normalize();
    let radiance = DVec3::new(2.0, 1.8, 1.5);
    let environment = DVec3::new(0.25, 0.3, 0.35);
    let cases = [
        (
            "orange plastic",
            Material::metallic_roughness(DVec3::new(0.8, 0.3, 0.1), 0.0, 1.5),
            0.5,
        ),
        (
            "gold",
            Material::metallic_roughness(DVec3::new(1.0, 0.78, 0.34), 1.0, 1.5),
            0.3,
        ),
        (
            "half metal",
            Material::metallic_roughness(DVec3::new(0.2, 0.5, 0.9), 0.5, 1.33),
            0.8,
        ),
    ];
    let mut worst = 0.0f64;
    for reading in BaseReading::ALL {
        for (name, material, roughness) in cases {
            let ball = Ball {
                center: DVec3::ZERO,
                radius: 1.0,
                roughness,
                material,
                model: Model::KullaConty,
                label: None,
            };
            let scene = Scene {
                balls: vec![ball],
                lights: vec![Light::new(light, radiance)],
                environment,
                base_reading: reading,
                ..Scene::reference()
            };
            let prepared = Prepared::new(&scene, &e);
            let rows = prepared.coating_rows();
            let key = crate::lut::CoatingKey::new(
                roughness,
                material.ior,
                crate::brdf::DielectricFresnel::Exact,
                crate::Geometry::SmithCorrelated,
            );
            // An all-metal ball has no row in the scene's (the shader mixes it out).
            let row = rows
                .row(&key)
                .copied()
                .unwrap_or_else(|| crate::lut::coating_row(&Default::default(), &key));
            let c = CoatingConstants::of_ball(&scene, &ball, &e, rows).unwrap_or_default();
            // BallUniforms: LutParams, then six vec4s.
            let mut uniforms: Vec<u8> = bytemuck::bytes_of(&gpu_tables.params).to_vec();
            let apparent = if reading == BaseReading::Apparent {
                1.0
            } else {
                0.0
            };
            let m = material.f0;
            let f_avg = crate::brdf::f_avg_dielectric(material.ior);
            for v in [
                [m.x, m.y, m.z, material.metallic],
                [roughness, material.ior, f_avg, c.e_spec_avg],
                [light.x, light.y, light.z, 0.0],
                [radiance.x, radiance.y, radiance.z, 0.0],
                [environment.x, environment.y, environment.z, apparent],
                [f64::from(SIZE), f64::from(SIZE), 0.0, 0.0],
            ] {
                for x in v {
                    uniforms.extend_from_slice(&(x as f32).to_le_bytes());
                }
            }
            let buffer = |label: &str, bytes: &[u8]| {
                let b = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: bytes.len() as u64,
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                queue.write_buffer(&b, 0, bytes);
                b
            };
            let ball_buffer = buffer("ball", &uniforms);
            let row_buffer = buffer("row", bytemuck::cast_slice(&row));
            let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("exported ball"),
                layout: &pipeline.get_bind_group_layout(0),
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: ball_buffer.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(&gpu_tables.e),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::TextureView(&gpu_tables.e_avg),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: row_buffer.as_entire_binding(),
                    },
                ],
            });
            let rgba = draw(device, queue, &pipeline, &bind, SIZE);
            // Every pixel inside the ball against the CPU at its normal.
            let radius = 0.45 * f64::from(SIZE);
            let form = scene.preset.f_avg_form();
            let geometry = scene.effective_geometry();
            let mut inside = 0;
            for py in 0..SIZE {
                for px in 0..SIZE {
                    let p = DVec3::new(
                        (f64::from(px) + 0.5 - 0.5 * f64::from(SIZE)) / radius,
                        -(f64::from(py) + 0.5 - 0.5 * f64::from(SIZE)) / radius,
                        0.0,
                    );
                    let r2 = p.length_squared();
                    if r2 >= 0.95 {
                        continue;
                    }
                    inside += 1;
                    let n = DVec3::new(p.x, p.y, (1.0 - r2).sqrt());
                    let cpu = crate::cpu::shade(&scene, &ball, n, DVec3::Z, &e, form, geometry);
                    let k = 4 * (py * SIZE + px) as usize;
                    let gpu = DVec3::new(rgba[k] as f64, rgba[k + 1] as f64, rgba[k + 2] as f64);
                    let rel = ((gpu - cpu).abs() / (cpu.abs() + 1e-3)).max_element();
                    worst = worst.max(rel);
                    assert!(
                        rel < 2e-3,
                        "{name}, {reading}: pixel ({px}, {py}) GPU {gpu:?} against CPU {cpu:?}"
                    );
                }
            }
            assert!(inside > 400, "{inside} pixels inside");
        }
    }
    println!("the exported fragment against cpu::shade: worst relative difference {worst:.2e}");
}

/// Runs `pipeline` over a `size x size` Rgba32Float target: its f32 values.
fn draw(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    pipeline: &wgpu::RenderPipeline,
    bind: &wgpu::BindGroup,
    size: u32,
) -> Vec<f32> {
    let extent = wgpu::Extent3d {
        width: size,
        height: size,
        depth_or_array_layers: 1,
    };
    let target = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("exported ball"),
        size: extent,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba32Float,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let row_bytes = size * 16;
    let padded =
        row_bytes.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: u64::from(padded * size),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let view = target.create_view(&Default::default());
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("exported ball"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            ..Default::default()
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, bind, &[]);
        pass.draw(0..3, 0..1);
    }
    encoder.copy_texture_to_buffer(
        target.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &readback,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(size),
            },
        },
        extent,
    );
    queue.submit([encoder.finish()]);
    readback.slice(..).map_async(wgpu::MapMode::Read, |_| {});
    device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    let data = readback.slice(..).get_mapped_range().unwrap();
    let mut out = Vec::with_capacity((size * size * 4) as usize);
    for row in data.chunks(padded as usize) {
        out.extend_from_slice(bytemuck::cast_slice::<u8, f32>(&row[..row_bytes as usize]));
    }
    out
}
