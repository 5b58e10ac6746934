//! What one orbiting frame of a scene costs headless, without a window: each scene drawn
//! by its own `Renderer` into a 980x720 `Bgra8UnormSrgb` target (the viewer's scene area
//! at its default window and the swapchain's format on lavapipe), the camera turned about
//! its target by the viewer's `--orbit` step before every frame, the scenes alternating
//! frame by frame; per scene, the median wall time of a frame (encode, submit, wait) and
//! the process's CPU time a frame (all threads: lavapipe's shading), which a machine
//! loaded by other work inflates less than the wall time. Issue 39's profile of the
//! default view against the homework's (docs/viewer.md, "Frame times").
//!
//! ```text
//! cargo run --release --example frame_cost --features scene-files -- FRAMES SCENE[,black][,noaa][,sky][,lobe] ...
//! ```
//!
//! `,black`: the background black (no map drawn behind the balls); `,noaa`: antialiasing off;
//! `,sky`: the built-in sky in place of the scene's map; `,lobe`: the map lights the balls
//! by the lobe mode (`ibl_method = "lobe"`, the scene's `ibl_samples`) instead of the split
//! sum.

use std::time::Instant;

use shadeballs::environment::{Background, Builtin, Environment, IblMethod};
use shadeballs::{wgpu, Renderer, Target};

/// The viewer's `--orbit` turn a frame, radians (`viewer::ORBIT_STEP`).
const ORBIT_STEP: f64 = 0.02;

#[repr(C)]
struct Timespec {
    seconds: i64,
    nanoseconds: i64,
}

extern "C" {
    fn clock_gettime(clock: i32, t: *mut Timespec) -> i32;
}

/// The process's CPU time, all threads, in milliseconds (`CLOCK_PROCESS_CPUTIME_ID`).
fn cpu_ms() -> f64 {
    const CLOCK_PROCESS_CPUTIME_ID: i32 = 2;
    let mut t = Timespec {
        seconds: 0,
        nanoseconds: 0,
    };
    // SAFETY: `t` is a valid, writable timespec for the call.
    unsafe { clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &mut t) };
    t.seconds as f64 * 1e3 + t.nanoseconds as f64 * 1e-6
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: frame_cost FRAMES SCENE[,black][,noaa][,sky][,lobe] ...";
    let frames: usize = args.get(1).ok_or(usage)?.parse()?;
    if args.len() < 3 || frames < 4 {
        return Err(format!("{usage} (FRAMES at least 4)").into());
    }
    let gpu = shadeballs::Gpu::new(wgpu::Backends::VULKAN)?;
    let (device, queue) = (&gpu.device, &gpu.queue);
    let (width, height, format) = (980, 720, wgpu::TextureFormat::Bgra8UnormSrgb);
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("frame"),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    let mut runs = Vec::new();
    for spec in &args[2..] {
        let mut parts = spec.split(',');
        let path = parts.next().unwrap_or_default();
        let mut scene = shadeballs::scene::load(std::path::Path::new(path))?;
        for part in parts {
            match part {
                "black" => scene.background = Background::Black,
                "noaa" => scene.antialias = false,
                "sky" => scene.environment_map = Some(Environment::builtin(Builtin::Sky)),
                "lobe" => scene.ibl_method = IblMethod::Lobe,
                _ => return Err(format!("{spec}: unknown modifier {part}").into()),
            }
        }
        let renderer = Renderer::from_device(device, queue);
        runs.push((spec.clone(), scene, renderer, Vec::new(), 0.0));
    }
    for frame in 0..frames {
        for (_, scene, renderer, walls, cpu) in runs.iter_mut() {
            // The camera about its target, turned about +y (viewer::orbit::orbit's yaw).
            let c = &mut scene.camera;
            let offset = c.position - c.target;
            let (s, k) = ORBIT_STEP.sin_cos();
            let turned = shadeballs::glam::DVec3::new(
                k * offset.x + s * offset.z,
                offset.y,
                -s * offset.x + k * offset.z,
            );
            c.position = c.target + turned;
            let (start, cpu_start) = (Instant::now(), cpu_ms());
            let mut encoder = device.create_command_encoder(&Default::default());
            let target = Target {
                view: &view,
                format,
                width,
                height,
            };
            renderer.encode(scene, target, &mut encoder)?;
            queue.submit([encoder.finish()]);
            let _ = device.poll(wgpu::PollType::wait_indefinitely());
            // The first frames bake, prefilter and compile: not counted.
            if frame >= 3 {
                walls.push(start.elapsed().as_secs_f64() * 1e3);
                *cpu += cpu_ms() - cpu_start;
            }
        }
    }
    for (name, _, _, walls, cpu) in &mut runs {
        walls.sort_by(f64::total_cmp);
        let n = walls.len();
        println!(
            "{name}: median frame {:.1} ms wall, {:.1} ms CPU a frame ({n} frames)",
            walls[n / 2],
            *cpu / n as f64
        );
    }
    Ok(())
}
