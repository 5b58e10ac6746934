//! A wgpu program of its own that bakes the Kulla-Conty tables at startup and shades one
//! ball with them: its own device, its own pipeline and WGSL entry points; from shadeballs
//! only the bake, the upload onto this program's device (`GpuTables::upload`) and the WGSL
//! library (`shadeballs::wgsl::KULLA_CONTY`, concatenated before this program's shader).
//!
//! ```text
//! cargo run --release --example bake_at_startup -- --out ball.png [--scene FILE] [--size N]
//! ```
//!
//! The ball, light and camera come from a scene file (default
//! `assets/scenes/one_ball.toml`, read with the library's parser) so that the picture can be
//! held against `shadeballs render` of the same file (tests/suite/example.rs).

use std::path::PathBuf;
use std::time::Instant;

use shadeballs::{BakeConfig, GpuTables};

/// This program's shader: a full-screen triangle, and per pixel a ray against one sphere,
/// shaded with the library's `f_micro`, table reads and multiple-scattering lobe.
const SHADER: &str = r#"
struct View {
    origin: vec4<f32>,
    forward: vec4<f32>,
    // Right and up, scaled by tan(vfov / 2) (and the aspect, for right).
    right: vec4<f32>,
    up: vec4<f32>,
    // width, height, exposure, unused.
    size: vec4<f32>,
    // xyz: centre; w: radius.
    ball: vec4<f32>,
    // xyz: F0; w: roughness.
    f0_roughness: vec4<f32>,
    // xyz: unit direction to the light.
    light_dir: vec4<f32>,
    light_radiance: vec4<f32>,
}

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> lut: LutParams;
@group(0) @binding(2) var e_table: texture_2d<f32>;
@group(0) @binding(3) var e_avg_table: texture_2d<f32>;

@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let x = f32((index << 1u) & 2u) * 2.0 - 1.0;
    let y = f32(index & 2u) * 2.0 - 1.0;
    return vec4<f32>(x, y, 0.0, 1.0);
}

// Nearest positive distance along unit d from o to the sphere (c, r), or -1: the
// discriminant as r^2 - |oc - (oc.d) d|^2, the near root as c / q (no cancellation).
fn hit_sphere(o: vec3<f32>, d: vec3<f32>, center: vec3<f32>, r: f32) -> f32 {
    let oc = o - center;
    let b = dot(oc, d);
    let perp = oc - b * d;
    let disc = r * r - dot(perp, perp);
    if disc < 0.0 {
        return -1.0;
    }
    let q = -b + select(sqrt(disc), -sqrt(disc), b > 0.0);
    if abs(q) < DIV_EPSILON {
        return -1.0;
    }
    let c = dot(oc, oc) - r * r;
    let t0 = min(c / q, q);
    let t1 = max(c / q, q);
    if t0 > 0.0 {
        return t0;
    }
    if t1 > 0.0 {
        return t1;
    }
    return -1.0;
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let ndc_x = 2.0 * frag.x / view.size.x - 1.0;
    let ndc_y = 1.0 - 2.0 * frag.y / view.size.y;
    let o = view.origin.xyz;
    let d = normalize(view.forward.xyz + ndc_x * view.right.xyz + ndc_y * view.up.xyz);
    let t = hit_sphere(o, d, view.ball.xyz, view.ball.w);
    if t < 0.0 {
        return vec4<f32>(0.0, 0.0, 0.0, 1.0);
    }
    let n = normalize(o + t * d - view.ball.xyz);
    let v = -d;
    let l = view.light_dir.xyz;
    let f0 = view.f0_roughness.xyz;
    let roughness = view.f0_roughness.w;
    let mu_o = max(dot(n, v), 0.0);
    let mu_i = dot(n, l);
    var radiance = vec3<f32>(0.0);
    if mu_i > 0.0 && mu_o > 0.0 {
        let h = normalize(v + l);
        // Single scattering: Cook-Torrance with height-correlated Smith G (the G the
        // tables were baked with).
        let fresnel = f_schlick(f0, dot(v, h));
        let single = f_micro(fresnel, mu_o, mu_i, dot(n, h), roughness, GEOMETRY_SMITH_CORRELATED);
        // Multiple scattering: f_add f_ms, from the tables (Kulla & Conty 2017).
        let loss_avg = lut_loss_avg(e_avg_table, lut, roughness);
        let f_add = f_add_preset(F_ADD_ACCURATE, f0, GAMES202_EDGE_TINT, 1.0 - loss_avg);
        let norm = 1.0 / max(PI * loss_avg, DIV_EPSILON);
        let loss_o = lut_loss(e_table, lut, mu_o, roughness);
        let loss_i = lut_loss(e_table, lut, mu_i, roughness);
        let lobe = f_add * f_ms(loss_o, loss_i, norm);
        radiance = (single + lobe) * view.light_radiance.xyz * mu_i;
    }
    // Exposure, Reinhard, gamma 1/2.2: the display transform one_ball.toml names for
    // shadeballs' PNGs (`tone_map = "reinhard"`, `transfer = "gamma-2.2"`).
    let c = max(radiance * view.size.z, vec3<f32>(0.0));
    return vec4<f32>(pow(c / (c + 1.0), vec3<f32>(1.0 / 2.2)), 1.0);
}
"#;

/// `View` of the shader above.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct View {
    origin: [f32; 4],
    forward: [f32; 4],
    right: [f32; 4],
    up: [f32; 4],
    size: [f32; 4],
    ball: [f32; 4],
    f0_roughness: [f32; 4],
    light_dir: [f32; 4],
    light_radiance: [f32; 4],
}

struct Args {
    out: PathBuf,
    scene: PathBuf,
    size: u32,
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args {
        out: PathBuf::from("ball.png"),
        scene: PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/one_ball.toml"),
        size: 256,
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or(format!("{flag} needs a value"));
        match flag.as_str() {
            "--out" => args.out = PathBuf::from(value()?),
            "--scene" => args.scene = PathBuf::from(value()?),
            "--size" => {
                let v = value()?;
                args.size = v
                    .parse()
                    .ok()
                    .filter(|n| (1..=4096).contains(n))
                    .ok_or(format!("--size {v}: expected a whole number in 1..=4096"))?;
            }
            _ => {
                return Err(format!(
                    "unknown flag '{flag}' (usage: --out FILE.png [--scene FILE] [--size N])"
                ))
            }
        }
    }
    Ok(args)
}

/// A line on stdout; a closed pipe (`| head -1`) is not an error worth a panic.
fn say(line: &str) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stdout().lock(), "{line}");
}

fn v4(v: glam::DVec3, w: f64) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, w as f32]
}

fn run(args: &Args) -> Result<(), Box<dyn std::error::Error>> {
    let scene = shadeballs::scene::load(&args.scene)?;
    let (ball, light) = match (scene.balls.first(), scene.lights.first()) {
        (Some(b), Some(l)) => (b, l),
        _ => return Err("the scene needs a ball and a light".into()),
    };

    // This program's own device.
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter =
        pollster::block_on(instance.request_adapter(&Default::default())).map_err(|e| {
            format!("no GPU adapter ({e}); for software Vulkan install mesa-vulkan-drivers")
        })?;
    let (device, queue) = pollster::block_on(adapter.request_device(&Default::default()))?;

    // Startup: bake (the G this program shades with) and upload onto this device.
    let start = Instant::now();
    let tables = shadeballs::bake(&BakeConfig {
        geometry: shadeballs::Geometry::SmithCorrelated,
        ..BakeConfig::default()
    });
    let baked = start.elapsed();
    let gpu_tables = GpuTables::upload(&device, &queue, &tables);
    queue.submit([]);
    device.poll(wgpu::PollType::wait_indefinitely())?;
    let uploaded = start.elapsed() - baked;
    say(&format!(
        "baked the tables ({}x{}) in {:.2} ms, uploaded in {:.2} ms",
        tables.layout().mu_size,
        tables.layout().r_size,
        baked.as_secs_f64() * 1e3,
        uploaded.as_secs_f64() * 1e3
    ));

    let size = args.size;
    let basis = scene.camera.basis(size, size);
    let view = View {
        origin: v4(basis.origin, 1.0),
        forward: v4(basis.forward, 0.0),
        right: v4(basis.right, 0.0),
        up: v4(basis.up, 0.0),
        size: [size as f32, size as f32, scene.exposure as f32, 0.0],
        ball: v4(ball.center, ball.radius),
        f0_roughness: v4(ball.material.f0, ball.roughness),
        light_dir: v4(light.direction, 0.0),
        light_radiance: v4(light.radiance, 0.0),
    };
    let uniform = |label, bytes: &[u8]| {
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: bytes.len() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        queue.write_buffer(&buffer, 0, bytes);
        buffer
    };
    let view_buffer = uniform("view", bytemuck::bytes_of(&view));
    let lut_buffer = uniform("lut params", bytemuck::bytes_of(&gpu_tables.params));

    let buffer_entry = |binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("ball"),
        entries: &[
            buffer_entry(0),
            buffer_entry(1),
            GpuTables::layout_entry(2, wgpu::ShaderStages::FRAGMENT),
            GpuTables::layout_entry(3, wgpu::ShaderStages::FRAGMENT),
        ],
    });
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("ball"),
        layout: &layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: view_buffer.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: lut_buffer.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::TextureView(&gpu_tables.e),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::TextureView(&gpu_tables.e_avg),
            },
        ],
    });

    // The library first, then this program's shader.
    let source = format!("{}\n{SHADER}", shadeballs::wgsl::KULLA_CONTY);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("ball"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let format = wgpu::TextureFormat::Rgba8Unorm;
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("ball"),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("ball"),
        layout: Some(&pipeline_layout),
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
            entry_point: Some("fs_main"),
            compilation_options: Default::default(),
            targets: &[Some(format.into())],
        }),
        multiview_mask: None,
        cache: None,
    });

    // Draw into a texture and read it back (rows padded to 256 bytes).
    let extent = wgpu::Extent3d {
        width: size,
        height: size,
        depth_or_array_layers: 1,
    };
    let target = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("ball"),
        size: extent,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let padded = (size * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
        * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: (padded * size) as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let view = target.create_view(&Default::default());
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("ball"),
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
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
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
    device.poll(wgpu::PollType::wait_indefinitely())?;
    let data = readback.slice(..).get_mapped_range()?;
    let mut rgba = Vec::with_capacity((size * size * 4) as usize);
    for row in data.chunks(padded as usize) {
        rgba.extend_from_slice(&row[..(size * 4) as usize]);
    }
    image::save_buffer(&args.out, &rgba, size, size, image::ColorType::Rgba8)?;
    say(&format!(
        "shaded one ball at {size}x{size} -> {}",
        args.out.display()
    ));
    Ok(())
}

fn main() -> std::process::ExitCode {
    let result = parse_args().map_err(Into::into).and_then(|args| run(&args));
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
