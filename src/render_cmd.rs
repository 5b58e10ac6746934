//! The `render` and `probe` subcommands: parse flags, call the scene, GPU and CPU layers,
//! report on stderr.

use std::fmt::Write as _;
use std::time::Instant;

use shadeballs::cli::{ProbeArgs, RenderArgs, ViewArgs};
use shadeballs::error::{Error, Result};
use shadeballs::gpu::{Backend, Gpu, Renderer};
use shadeballs::image_out::{image_kind, write_exr, write_png, ImageKind};
use shadeballs::lut::{self, BakeConfig};
use shadeballs::scene;
use shadeballs::{cpu, output};

fn open(backend: Backend) -> Result<Option<Renderer>> {
    let Some(backends) = backend.wgpu_backends() else {
        return Ok(None);
    };
    match Gpu::new(backends) {
        Ok(gpu) => Ok(Some(Renderer::new(gpu))),
        Err(e @ Error::NoAdapter { .. }) if backend == Backend::Auto => {
            eprintln!("warning: {e}; falling back to the CPU reference renderer");
            Ok(None)
        }
        Err(e) => Err(e),
    }
}

pub fn render(args: RenderArgs) -> anyhow::Result<()> {
    let start = Instant::now();
    let mut phases = Phases(start, String::new());
    let kind = image_kind(&args.out)?;
    output::check_output_path(&args.out)?;
    let scene = args.scene.load()?;
    let geometry = scene.effective_geometry();
    let (w, h) = (args.width, args.height);
    let renderer = open(args.backend)?;
    phases.mark("device");
    let device = match renderer {
        Some(mut renderer) => {
            renderer.gpu().check_size(w, h)?;
            let plan = renderer.plan_for(&scene);
            if args.verbose {
                eprintln!("plan: {}", plan.to_string().replace('\n', "\n      "));
            }
            phases.mark("bake");
            match kind {
                ImageKind::Png => {
                    renderer.prepare(&scene, wgpu::TextureFormat::Rgba8Unorm);
                    phases.mark("pipeline");
                    let image = renderer.render_ldr(&scene, w, h)?;
                    phases.mark("render");
                    write_png(&args.out, w, h, image.rgba)?
                }
                ImageKind::Exr => {
                    // The pipeline is created at the first draw (its float format is
                    // chosen there): "render" includes it.
                    let image = renderer.render_hdr(&scene, w, h)?;
                    phases.mark("render");
                    write_exr(&args.out, w, h, image.rgba)?
                }
            }
            renderer.gpu().describe()
        }
        None => {
            check_cpu_size(w, h)?;
            if args.verbose {
                eprintln!("plan: the CPU reference renderer reads the 2-D table; no pipelines");
            }
            let tables = lut::bake(&BakeConfig {
                geometry,
                ..Default::default()
            });
            phases.mark("bake");
            let radiance = cpu::render_radiance(&scene, &tables, w, h);
            phases.mark("render");
            match kind {
                ImageKind::Png => {
                    write_png(&args.out, w, h, cpu::to_rgba8(&radiance, scene.exposure))?
                }
                ImageKind::Exr => write_exr(&args.out, w, h, cpu::to_rgba_f32(&radiance))?,
            }
            "CPU reference renderer".to_string()
        }
    };
    phases.mark("encode");
    eprintln!(
        "rendered {w}x{h} ({} preset, {geometry} G) on {device} in {:.1} ms ({}) -> {}",
        scene.preset,
        start.elapsed().as_secs_f64() * 1e3,
        phases.1.trim_end_matches(", "),
        args.out.display()
    );
    Ok(())
}

/// Wall time per phase since the previous mark, for the one-line report (`shadeballs
/// bench` parses it: "name 12.3 ms, ..."; "encode" is the image file's encoding and write).
struct Phases(Instant, String);

impl Phases {
    fn mark(&mut self, name: &str) {
        let now = Instant::now();
        let _ = write!(
            self.1,
            "{name} {:.1} ms, ",
            (now - self.0).as_secs_f64() * 1e3
        );
        self.0 = now;
    }
}

/// The CPU renderer's size limit: the same 16384 a GPU texture has on lavapipe.
fn check_cpu_size(w: u32, h: u32) -> Result<()> {
    const MAX: u32 = 16384;
    if w > MAX || h > MAX {
        return Err(Error::Invalid {
            what: "image size",
            message: format!("{w}x{h}: each side must be in 1..={MAX}"),
        });
    }
    Ok(())
}

pub fn probe(args: ProbeArgs) -> anyhow::Result<()> {
    output::check_output_path(&args.out)?;
    // The probe needs a GPU: no CPU fallback (and no warning announcing one).
    let backend = if args.backend == Backend::Cpu {
        Backend::Vulkan
    } else {
        args.backend
    };
    let backends = backend.wgpu_backends().unwrap_or(wgpu::Backends::VULKAN);
    let mut renderer = match Gpu::new(backends) {
        Ok(gpu) => Renderer::new(gpu),
        Err(Error::NoAdapter { message, .. }) => anyhow::bail!(
            "the probe runs on the GPU and no adapter was found ({message}); \
             for software Vulkan install the package mesa-vulkan-drivers"
        ),
        Err(e) => return Err(e.into()),
    };
    let (geometry, samples, what) = match &args.scene {
        Some(path) => {
            let scene = scene::load(path)?;
            let geometry = scene.effective_geometry();
            let Some((rows, samples)) = renderer.probe_rows(&scene, args.grid)? else {
                anyhow::bail!(
                    "{}: the scene's plan bakes no rows (no ball reads E, or more roughness \
                     values than rows are planned for); probe without --scene",
                    path.display()
                );
            };
            (
                geometry,
                samples,
                format!("{}x{} rows", args.grid, rows.rows.len()),
            )
        }
        None => {
            let geometry = args.preset.geometry().unwrap_or(args.geometry);
            let (_, samples) = renderer.probe(geometry, args.grid)?;
            (geometry, samples, format!("{}x{}", args.grid, args.grid))
        }
    };
    let mut csv = String::from("roughness,mu,E,E_avg\n");
    for s in &samples {
        let _ = writeln!(csv, "{},{},{},{}", s.roughness, s.mu, s.e, s.e_avg);
    }
    output::write_atomic(&args.out, csv.as_bytes())?;
    eprintln!(
        "probed {what} ({} G) on {} -> {}",
        geometry,
        renderer.gpu().describe(),
        args.out.display()
    );
    Ok(())
}

pub fn view(args: ViewArgs) -> anyhow::Result<()> {
    if let Some(path) = &args.screenshot {
        output::check_output_path(path)?;
        if image_kind(path)? != ImageKind::Png {
            anyhow::bail!("--screenshot '{}' must be a .png", path.display());
        }
    }
    let scene = args.scene.load()?;
    let report = shadeballs::viewer::run(shadeballs::viewer::ViewOptions {
        scene,
        backend: args.backend,
        size: (args.width, args.height),
        frames: args.frames,
        screenshot: args.screenshot,
        orbit: args.orbit,
    })?;
    let ms = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.1} ms"));
    let fps = report
        .interval_ms
        .map_or("-".to_string(), |v| format!("{:.1}", 1e3 / v));
    eprintln!(
        "viewed {} frames ({} shading the balls, {} drawing the panel) at {}x{} (scene area \
         {}x{}) on {}: median frame interval {} ({fps} fps), median draw {}",
        report.frames,
        report.scene_draws,
        report.panel_draws,
        report.window.0,
        report.window.1,
        report.scene.0,
        report.scene.1,
        report.adapter,
        ms(report.interval_ms),
        ms(report.draw_ms),
    );
    Ok(())
}
