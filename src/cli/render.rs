//! `shadeballs render`: the scene to a `.png` or `.exr`, on the GPU or, without a GPU driver,
//! the CPU reference renderer; one line on stderr with the time of each phase.

use std::fmt::Write as _;
use std::time::Instant;

use super::args::RenderArgs;
use super::{guard, interrupt, progress};
use crate::cpu;
use crate::environment::ChainOn;
use crate::error::{Error, Result};
use crate::gpu::{Backend, Gpu, Renderer};
use crate::labels;
use crate::lut::{self, BakeConfig};
use crate::memory;
use crate::output::{self, image_kind, write_exr, write_png, ImageKind};
use crate::scene::Scene;

/// The GPU renderer of `backend`, or `None` for the CPU: a CPU backend, or `auto` with no
/// adapter (with a warning). The lab's `compare` opens its models' renderer the same way.
/// `montecarlo` tries `auto`'s adapters, and falls back to the CPU estimator with a notice
/// where there is none or it cannot render to `Rgba32Float`.
pub fn open(backend: Backend) -> Result<Option<Renderer>> {
    let (renderer, notice) = open_quietly(backend)?;
    if let Some(notice) = notice {
        eprintln!("{notice}");
    }
    Ok(renderer)
}

/// [`open`], with the fallback's warning or notice returned rather than printed (`run`
/// opens the device beside reading the scene and prints it only once the scene is read,
/// so a bad scene file still gets one line).
fn open_quietly(backend: Backend) -> Result<(Option<Renderer>, Option<String>)> {
    let tried = if backend == Backend::Montecarlo {
        Backend::Auto
    } else {
        backend
    };
    let Some(backends) = tried.wgpu_backends() else {
        return Ok((None, None));
    };
    let renderer = match Gpu::new(backends) {
        Ok(gpu) => Renderer::new(gpu),
        Err(e @ Error::NoAdapter { .. }) if backend == Backend::Auto => {
            let warning = format!("warning: {e}; falling back to the CPU reference renderer");
            return Ok((None, Some(warning)));
        }
        Err(e @ Error::NoAdapter { .. }) if backend == Backend::Montecarlo => {
            let notice = format!("notice: {e}; the Monte Carlo backend runs on the CPU");
            return Ok((None, Some(notice)));
        }
        Err(e) => return Err(e),
    };
    if backend == Backend::Montecarlo && !renderer.truth_supported() {
        let notice = format!(
            "notice: {} cannot render to Rgba32Float; the Monte Carlo backend runs on the CPU",
            renderer.gpu().describe()
        );
        return Ok((None, Some(notice)));
    }
    Ok((Some(renderer), None))
}

pub fn run(args: RenderArgs) -> anyhow::Result<()> {
    let start = Instant::now();
    let mut phases = Phases(start, String::new());
    let kind = image_kind(&args.out)?;
    let sidecar = check_before_the_work(&args, kind)?;
    // Issue 38: no output over an input or another output; every output's folder writable.
    let outputs = guard::outputs(&[
        ("--out", Some(args.out.as_path())),
        ("the standard-error sidecar", sidecar.as_deref()),
    ]);
    guard::refuse_overlaps(&outputs, &guard::scene_inputs(&args.scene, None))?;
    guard::probe_folders(&outputs)?;
    let (scene, renderer) = scene_beside_the_device(&args, &mut phases)?;
    guard::refuse_overlaps(&outputs, &guard::scene_inputs(&args.scene, Some(&scene)))?;
    let on_gpu = renderer.is_some() && args.backend != Backend::Montecarlo;
    if let Some(notice) = guard::ibl_frames_ignored(args.ibl_frames, on_gpu, &scene) {
        eprintln!("{notice}");
    }
    let geometry = scene.effective_geometry();
    let (w, h) = (args.width, args.height);
    let (device, truth_spp) = match renderer {
        Some(mut renderer) if args.backend == Backend::Montecarlo => {
            render_montecarlo_on_gpu(&mut renderer, &scene, &args, kind, &mut phases)?
        }
        Some(mut renderer) => (
            render_on_gpu(&mut renderer, &scene, &args, kind, &mut phases)?,
            None,
        ),
        None => render_on_cpu(&scene, &args, kind, sidecar.as_deref(), &mut phases)?,
    };
    phases.mark("encode");
    eprintln!(
        "rendered {w}x{h} ({} preset, {geometry} G) on {device} in {:.1} ms ({}) -> {}",
        scene.preset,
        start.elapsed().as_secs_f64() * 1e3,
        phases.1.trim_end_matches(", "),
        args.out.display()
    );
    // A truth or GPU Monte Carlo render Ctrl-C stopped has written what it had: the command
    // still fails, with the signal's status.
    if let (Some(signal), Some(spp)) = (interrupt::stop_requested(), truth_spp) {
        return Err(interrupt::Interrupted {
            signal,
            spp,
            out: args.out.clone(),
        }
        .into());
    }
    Ok(())
}

/// The scene, read (and its map generated or loaded, and its mip chain built where a GPU
/// will prepare it) on this thread while the device opens on another
/// ([`open`]'s fallback notice printed once the scene is read); phases `scene`, `mip chain`
/// and `device` (what is left of the opening then).
fn scene_beside_the_device(
    args: &RenderArgs,
    phases: &mut Phases,
) -> anyhow::Result<(Scene, Option<Renderer>)> {
    let backend = args.backend;
    let opening = std::thread::spawn(move || open_quietly(backend));
    let loaded = args.scene.load();
    // Reading the scene can wait (a FIFO, a slow disk): its own phase, not the device's.
    phases.mark("scene");
    // The map's mip chain, where a GPU will prepare it (and it fits in memory; else the
    // renderer says so).
    let ahead = match &loaded {
        Ok(scene) if backend.wgpu_backends().is_some() => scene
            .environment_map
            .as_ref()
            .filter(|e| {
                e.map
                    .check_chain_memory(crate::environment::ChainOn::Gpu)
                    .is_ok()
            })
            .map(|e| (e.map.clone(), crate::environment::MipChain::new(&e.map))),
        _ => None,
    };
    if ahead.is_some() {
        phases.mark("mip chain");
    }
    // Joined before any error returns: the process never exits under a device still opening.
    let opened = opening.join();
    let mut scene = loaded?;
    if backend == Backend::Truth {
        // Every ball is the walk's (and its label says so).
        for b in &mut scene.balls {
            b.model = crate::scene::Model::Truth;
        }
    }
    let (mut renderer, notice) =
        opened.map_err(|_| anyhow::anyhow!("opening the GPU device panicked"))??;
    if let Some(notice) = notice {
        eprintln!("{notice}");
    }
    if let (Some(r), Some((map, chain))) = (renderer.as_mut(), ahead) {
        r.offer_mip_chain(map, chain);
    }
    phases.mark("device");
    Ok((scene, renderer))
}

/// What can be refused before any work (issue 28, 4): the output path, the truth's
/// sidecar path (returned for an `.exr` of `--backend truth`) and its `--spp 1`, the
/// `WGPU_BACKEND` variable; an ignored `--stderr` is warned of.
fn check_before_the_work(args: &RenderArgs, kind: ImageKind) -> Result<Option<std::path::PathBuf>> {
    output::check_output_path(&args.out)?;
    let sidecar =
        (args.backend == Backend::Truth && kind == ImageKind::Exr).then(|| stderr_path(&args.out));
    if let Some(path) = &sidecar {
        output::check_output_path(path)?;
        if args.spp == Some(1) {
            return Err(Error::Invalid {
                what: "samples per pixel",
                message: format!(
                    "--spp 1: one estimate a pixel has no standard error for {} \
                     (use --spp 2 or more, or a .png)",
                    path.display()
                ),
            });
        }
    }
    super::check_wgpu_backend_env(args.backend)?;
    if args.stderr.is_some() && args.backend != Backend::Truth {
        eprintln!(
            "warning: --stderr is ignored: only --backend truth stops at a standard error \
             (--backend {} runs --spp samples)",
            args.backend
        );
    }
    Ok(sidecar)
}

/// The render on the GPU (plan, bake, the map's prefilter, the truth's frames, the
/// pipeline, the frame, labels, the file); the device's description.
fn render_on_gpu(
    renderer: &mut Renderer,
    scene: &Scene,
    args: &RenderArgs,
    kind: ImageKind,
    phases: &mut Phases,
) -> Result<String> {
    let (w, h) = (args.width, args.height);
    let pixels = u64::from(w) * u64::from(h);
    renderer.gpu().check_size(w, h)?;
    guard::check_f32_camera(scene, w, h)?;
    let lobe_frames = args.ibl_frames.unwrap_or(1);
    let lobe = lobe_frames > 1
        && scene.ibl_method == crate::environment::IblMethod::Lobe
        && scene.environment_map.is_some();
    let per_pixel = if lobe {
        // The mean is read back as f32 whatever the file, besides the lobe's sums.
        gpu_bytes_per_pixel(ImageKind::Exr) + LOBE_BYTES_PER_PIXEL
    } else {
        gpu_bytes_per_pixel(kind)
    };
    memory::check(
        &format!("a {w}x{h} {} on the GPU", kind_name(kind)),
        pixels * per_pixel,
    )?;
    let plan = renderer.plan_for(scene);
    if args.verbose {
        eprintln!("plan: {}", plan.to_string().replace('\n', "\n      "));
    }
    phases.mark("bake");
    if scene.environment_map.is_some() {
        // Mip chain, split-sum table and the GPU's prefiltering of the map.
        renderer.prepare_environment(scene)?;
        phases.mark("prefilter");
    }
    if scene.has_truth() {
        let spp = args.spp.unwrap_or(DEFAULT_SPP);
        accumulate_gpu_truth(renderer, scene, w, h, spp)?;
        phases.mark("truth");
    }
    if lobe {
        // The mean of the frames in linear radiance, then the display transform (a PNG).
        let t = Instant::now();
        let image = renderer.render_lobe_hdr(scene, w, h, lobe_frames)?;
        eprintln!(
            "lobe: {} of {} at {w}x{h} in {:.1} ms",
            crate::stats::count(lobe_frames, "frame"),
            crate::stats::count(scene.ibl_samples, "sample"),
            t.elapsed().as_secs_f64() * 1e3
        );
        phases.mark("render");
        match kind {
            ImageKind::Png => {
                let display = scene.display();
                let mut rgba: Vec<u8> = image
                    .rgba
                    .chunks_exact(4)
                    .flat_map(|p| {
                        let radiance = glam::Vec3::new(p[0], p[1], p[2]).as_dvec3();
                        crate::display::to_rgba8_pixel(radiance, scene.exposure, display)
                    })
                    .collect();
                draw_labels(scene, args, &mut rgba, phases)?;
                write_png(&args.out, w, h, rgba)?
            }
            ImageKind::Exr => write_exr(&args.out, w, h, image.rgba)?,
        }
        return Ok(renderer.gpu().describe());
    }
    match kind {
        ImageKind::Png => {
            renderer.prepare(scene, wgpu::TextureFormat::Rgba8Unorm);
            phases.mark("pipeline");
            let mut rgba = renderer.render_ldr(scene, w, h)?.rgba;
            phases.mark("render");
            draw_labels(scene, args, &mut rgba, phases)?;
            write_png(&args.out, w, h, rgba)?
        }
        ImageKind::Exr => {
            // The pipeline is created at the first draw (its float format is
            // chosen there): "render" includes it.
            let image = renderer.render_hdr(scene, w, h)?;
            phases.mark("render");
            write_exr(&args.out, w, h, image.rgba)?
        }
    }
    Ok(renderer.gpu().describe())
}

/// `--backend montecarlo` on the GPU: the estimator's passes (Ctrl-C stops after one, the
/// image then holds the passes done), its summary line, labels and the file; the device's
/// description, and the samples a pixel where a signal stopped it.
fn render_montecarlo_on_gpu(
    renderer: &mut Renderer,
    scene: &Scene,
    args: &RenderArgs,
    kind: ImageKind,
    phases: &mut Phases,
) -> Result<(String, Option<u32>)> {
    let (w, h) = (args.width, args.height);
    renderer.gpu().check_size(w, h)?;
    guard::check_f32_camera(scene, w, h)?;
    // Four Rgba32Float textures and two read-backs on the device; mean, error and coverage
    // on the host.
    memory::check(
        &format!("a {w}x{h} {} by the GPU's Monte Carlo", kind_name(kind)),
        u64::from(w) * u64::from(h) * (6 * 16 + MONTECARLO_BYTES_PER_PIXEL + 24),
    )?;
    if scene.environment_map.is_some() {
        renderer.prepare_environment(scene)?;
        phases.mark("prefilter");
    }
    if scene.antialias {
        eprintln!(
            "notice: montecarlo on the GPU traces one ray through each pixel's centre (no \
             antialiasing); --backend montecarlo-cpu antialiases silhouettes as the real-time \
             renderers do"
        );
    }
    let spp = args.spp.unwrap_or(DEFAULT_SPP);
    let started = Instant::now();
    let stoppable = interrupt::Stoppable::start();
    let image = renderer.render_montecarlo_progressive(scene, (w, h), (spp, args.seed), |_| {
        interrupt::stop_requested().is_none()
    })?;
    drop(stoppable);
    phases.mark("render");
    montecarlo_summary(&image, args.seed, started);
    // The samples a pixel in the file, complete or stopped (issue 38, 7), as the truth's.
    let note = samples_note("Monte Carlo on the GPU", image.spp);
    match kind {
        ImageKind::Png => {
            let mut rgba = cpu::to_display_rgba8(&image.mean, scene.exposure, scene.display());
            drop(image.mean);
            draw_labels(scene, args, &mut rgba, phases)?;
            output::write_png_noted(&args.out, w, h, rgba, &note)?
        }
        ImageKind::Exr => {
            let rgba = cpu::to_rgba_f32(&image.mean);
            output::stage_exr_noted(&args.out, w, h, rgba, &note)?.commit()?
        }
    }
    let stopped = interrupt::stop_requested().map(|_| image.spp);
    Ok((
        format!("GPU Monte Carlo, {}", renderer.gpu().describe()),
        stopped,
    ))
}

/// The Monte Carlo backends' line on stderr: samples, seed, time, noise.
fn montecarlo_summary(image: &cpu::MonteCarloImage, seed: u64, started: Instant) {
    let noise = image
        .mean_relative_std_error()
        .map_or("n/a".to_string(), |r| format!("{:.3} %", 100.0 * r));
    eprintln!(
        "montecarlo: {} spp, seed {seed}, {:.1} ms, mean relative standard error over \
         ball pixels {noise}",
        image.spp,
        started.elapsed().as_secs_f64() * 1e3
    );
}

/// The render on the CPU: the reference renderer, the Monte Carlo backend or the truth (its
/// `sidecar` of standard errors written with the image, both or neither); the renderer's
/// name, and the truth's samples a pixel.
fn render_on_cpu(
    scene: &Scene,
    args: &RenderArgs,
    kind: ImageKind,
    sidecar: Option<&std::path::Path>,
    phases: &mut Phases,
) -> Result<(String, Option<u32>)> {
    let (w, h) = (args.width, args.height);
    let pixels = u64::from(w) * u64::from(h);
    let geometry = scene.effective_geometry();
    check_cpu_size(w, h)?;
    let montecarlo = matches!(args.backend, Backend::Montecarlo | Backend::MontecarloCpu);
    let truth = args.backend == Backend::Truth;
    // The Monte Carlo image also keeps a standard error and a coverage flag per pixel
    // (the truth also its running sums per covered pixel: counted as twice that).
    let extra = if truth {
        2 * MONTECARLO_BYTES_PER_PIXEL
    } else if montecarlo {
        MONTECARLO_BYTES_PER_PIXEL
    } else {
        0
    };
    memory::check_on_cpu(
        &format!("a {w}x{h} {} on the CPU", kind_name(kind)),
        pixels * (cpu_bytes_per_pixel(kind) + extra),
    )?;
    if let Some(environment) = scene
        .environment_map
        .as_ref()
        .filter(|_| !montecarlo && !truth)
    {
        // The Monte Carlo backends read the map itself; the others its mip chain.
        environment.map.check_chain_memory(ChainOn::Cpu)?;
    }
    if args.verbose {
        eprintln!("plan: the CPU reference renderer reads the 2-D table; no pipelines");
    }
    let tables = lut::TableSet::from(lut::bake(&BakeConfig {
        geometry,
        ..Default::default()
    }));
    phases.mark("bake");
    let (radiance, walked) = cpu_radiance(scene, &tables, args, phases)?;
    let spp = walked.as_ref().map(|(_, spp)| *spp);
    // The samples a pixel of a progressive backend, in the file (issue 38, 7).
    let note = match spp {
        Some(spp) => Some(truth_note(spp)),
        None => montecarlo
            .then(|| samples_note("Monte Carlo on the CPU", args.spp.unwrap_or(DEFAULT_SPP))),
    };
    // The radiance (24 bytes a pixel) is dropped before the encoder starts.
    match kind {
        ImageKind::Png => {
            let mut rgba = cpu::to_display_rgba8(&radiance, scene.exposure, scene.display());
            drop(radiance);
            draw_labels(scene, args, &mut rgba, phases)?;
            match &note {
                Some(note) => output::write_png_noted(&args.out, w, h, rgba, note)?,
                None => write_png(&args.out, w, h, rgba)?,
            }
        }
        ImageKind::Exr => {
            let rgba = cpu::to_rgba_f32(&radiance);
            drop(radiance);
            match (sidecar, walked) {
                (Some(path), Some((std_error, spp))) if spp >= 2 => {
                    // Both written, then both renamed: a failed write leaves the old
                    // pair (issue 28, 4).
                    let note = truth_note(spp);
                    let side = cpu::to_rgba_f32(&std_error);
                    let side = output::stage_exr_noted(path, w, h, side, &note)?;
                    let image = output::stage_exr_noted(&args.out, w, h, rgba, &note)?;
                    output::commit_all(vec![side, image])?;
                    eprintln!("per-pixel standard error -> {}", path.display());
                }
                (Some(path), Some((_, spp))) => {
                    // Stopped after the first pass: one estimate a pixel has no error.
                    let note = truth_note(spp);
                    output::stage_exr_noted(&args.out, w, h, rgba, &note)?.commit()?;
                    eprintln!(
                        "{} not written: one estimate a pixel has no standard error",
                        path.display()
                    );
                }
                _ => match &note {
                    Some(note) => output::stage_exr_noted(&args.out, w, h, rgba, note)?.commit()?,
                    None => write_exr(&args.out, w, h, rgba)?,
                },
            }
        }
    }
    let name = if truth {
        "CPU truth (random walk)"
    } else if montecarlo {
        "CPU Monte Carlo reference"
    } else {
        "CPU reference renderer"
    };
    Ok((name.to_string(), spp))
}

/// The text a truth PNG carries (its `Comment`): the samples a pixel, and the signal that
/// stopped the render early, if one did.
fn truth_note(spp: u32) -> String {
    samples_note("truth (random walk)", spp)
}

/// The text a progressive backend's file carries (a PNG's `Comment`, an EXR's `comment`):
/// what rendered it, the samples a pixel, and the signal that stopped it early, if one did.
fn samples_note(what: &str, spp: u32) -> String {
    let stopped = interrupt::stop_requested().map_or(String::new(), |s| {
        format!(", interrupted by {}", interrupt::signal_name(s))
    });
    format!("shadeballs {what}: {spp} spp{stopped}")
}

/// The CPU's radiance, and the truth's per-pixel standard error with its samples a pixel.
type CpuRadiance = (Vec<glam::DVec3>, Option<(Vec<glam::DVec3>, u32)>);

/// The CPU's radiance of `scene` by the backend `args` names, and the truth's per-pixel
/// standard error and samples a pixel.
fn cpu_radiance(
    scene: &Scene,
    tables: &lut::TableSet,
    args: &RenderArgs,
    phases: &mut Phases,
) -> Result<CpuRadiance> {
    let (w, h) = (args.width, args.height);
    let montecarlo = matches!(args.backend, Backend::Montecarlo | Backend::MontecarloCpu);
    let truth = args.backend == Backend::Truth;
    if truth {
        let image = render_truth(scene, tables, args)?;
        phases.mark("render");
        let spp = image.image.spp;
        return Ok((image.image.mean, Some((image.image.std_error, spp))));
    }
    let radiance = if montecarlo {
        let started = Instant::now();
        let spp = args.spp.unwrap_or(DEFAULT_SPP);
        let image = cpu::render_montecarlo(scene, tables, w, h, spp, args.seed)?;
        phases.mark("render");
        montecarlo_summary(&image, args.seed, started);
        image.mean
    } else if scene.has_truth() {
        // Truth balls by the walk, the others by the reference renderer.
        let settings = cpu::TruthSettings {
            spp: args.spp.unwrap_or(DEFAULT_SPP),
            seed: args.seed,
            ..Default::default()
        };
        let radiance = cpu::render_radiance_with_truth(scene, tables, w, h, settings)?;
        phases.mark("render");
        radiance
    } else {
        let radiance = cpu::render_radiance(scene, tables, w, h);
        phases.mark("render");
        radiance
    };
    Ok((radiance, None))
}

/// Samples per pixel of the Monte Carlo backends without `--spp` (and of the truth without
/// `--stderr`).
const DEFAULT_SPP: u32 = 64;

/// `--backend truth`: the render with its progress on stderr (`progress`: a bar with the
/// time left, redrawn in place on a terminal, else a line a pass), stopped after a pass by
/// Ctrl-C (`interrupt`), and a summary of every ball's mean and its standard error.
fn render_truth(
    scene: &crate::scene::Scene,
    e: &lut::TableSet,
    args: &RenderArgs,
) -> Result<cpu::TruthImage> {
    use std::io::IsTerminal as _;
    let settings = cpu::TruthSettings {
        spp: args.spp.unwrap_or(if args.stderr.is_some() {
            cpu::montecarlo::MAX_SPP
        } else {
            DEFAULT_SPP
        }),
        stderr: args.stderr,
        seed: args.seed,
        max_order: u32::MAX,
        every_ball: true,
    };
    let terminal = std::io::stderr().is_terminal();
    let line = |p: &cpu::TruthProgress, terminal| {
        progress::line(p, settings.spp, settings.stderr, terminal)
    };
    // A bar redrawn in place on a terminal, else a line a pass (the curve of the error
    // against time, docs/truth.md). Ctrl-C stops after the pass (`interrupt`): the image
    // then holds the passes done.
    let stoppable = interrupt::Stoppable::start();
    let image = cpu::render_truth(scene, e, args.width, args.height, settings, |p| {
        if terminal {
            eprint!("\r{}   ", line(p, true));
        } else {
            eprintln!("{}", line(p, false));
        }
        interrupt::stop_requested().is_none()
    })?;
    drop(stoppable);
    if terminal {
        eprintln!();
    }
    if let Some(last) = image.passes.last() {
        let target = settings
            .stderr
            .map_or(String::new(), |s| format!(" (target {:.3} %)", 100.0 * s));
        eprintln!(
            "{}{target}, seed {}",
            progress::summary(last),
            settings.seed
        );
        if let (Some(target), Some(worst)) = (settings.stderr, last.worst_stderr) {
            if worst > target {
                eprintln!(
                    "warning: the target standard error {:.3} % was not reached: {:.3} % at \
                     the cap of {} spp (raise --spp, up to {})",
                    100.0 * target,
                    100.0 * worst,
                    last.spp,
                    cpu::montecarlo::MAX_SPP
                );
            }
        }
    }
    if image.balls.iter().all(|b| b.relative_std_error().is_none()) {
        eprintln!(
            "warning: no ball covers a pixel of the {}x{} image: the walk has nothing to \
             estimate (the background is exact), so it stopped at {}",
            args.width,
            args.height,
            crate::stats::count(image.image.spp, "sample")
        );
    }
    // One estimate a pixel gives no standard error (issue 28, 5): say so, not "+- 0 %".
    let one = image.image.spp < 2;
    for (k, b) in image.balls.iter().enumerate() {
        if let Some(rel) = b.relative_std_error() {
            let error = if one {
                "(no standard error from one estimate a pixel)".to_string()
            } else {
                format!("+- {:.3} %", 100.0 * rel)
            };
            eprintln!(
                "  ball {k}: mean radiance [{:.5}, {:.5}, {:.5}] {error}",
                b.mean.x, b.mean.y, b.mean.z,
            );
        }
    }
    Ok(image)
}

/// A GPU render of a scene with truth balls: `spp - 1` frames of their estimates, each
/// waited for and timed (the draw that writes the image adds the last), and a line on
/// stderr with the median frame time (docs/benchmarks.md, "GPU truth").
fn accumulate_gpu_truth(
    renderer: &mut Renderer,
    scene: &crate::scene::Scene,
    w: u32,
    h: u32,
    spp: u32,
) -> Result<()> {
    if !(1..=crate::gpu::MAX_TRUTH_SPP).contains(&spp) {
        return Err(Error::Invalid {
            what: "samples per pixel",
            message: format!(
                "{spp}: must be in 1..={} on the GPU",
                crate::gpu::MAX_TRUTH_SPP
            ),
        });
    }
    renderer.reset_truth();
    let mut times = Vec::new();
    for _ in 1..spp {
        let t = Instant::now();
        renderer.accumulate_truth(scene, w, h)?;
        let _ = renderer
            .gpu()
            .device
            .poll(wgpu::PollType::wait_indefinitely());
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    let median = times.get(times.len() / 2).copied();
    let rate = median.map_or("n/a".to_string(), |m| {
        format!(
            "median {:.1} ms a frame ({:.1} frames/s)",
            m * 1e3,
            1.0 / m.max(1e-9)
        )
    });
    // With one frame the draw that writes the image is the only one: nothing to time.
    if !times.is_empty() {
        eprintln!(
            "gpu truth: {spp} spp at {w}x{h}, {rate} over {} frames",
            times.len()
        );
    }
    Ok(())
}

/// The sidecar of a truth `.exr`: `NAME.stderr.exr` beside `NAME.exr`.
pub fn stderr_path(out: &std::path::Path) -> std::path::PathBuf {
    let stem = out
        .file_stem()
        .map_or_else(Default::default, |s| s.to_os_string());
    let mut name = stem;
    name.push(".stderr.exr");
    out.with_file_name(name)
}

/// The chart's labels over a picture's display pixels, when the scene asks for them (a
/// `.png` only: an `.exr` holds radiance).
/// An explicit `--labels` that draws nothing says so (issue 28, 10).
fn draw_labels(
    scene: &Scene,
    args: &RenderArgs,
    rgba: &mut [u8],
    phases: &mut Phases,
) -> Result<()> {
    let (w, h) = (args.width, args.height);
    if scene.labels {
        let drawn = labels::draw_labels(rgba, w, h, &labels::layout(scene, w, h))?;
        phases.mark("labels");
        if drawn == 0 && args.scene.labels {
            eprintln!(
                "warning: --labels drew nothing: no label fits a {w}x{h} image at a font of \
                 at least {} px (a larger image has room)",
                labels::MIN_FONT_PX
            );
        }
    }
    Ok(())
}

/// Wall time per phase since the previous mark, for the one-line report ("name 12.3 ms,
/// ..."; "encode" is the image file's encoding and write). For people: nothing parses it.
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

fn kind_name(kind: ImageKind) -> &'static str {
    match kind {
        ImageKind::Png => ".png",
        ImageKind::Exr => ".exr",
    }
}

/// Peak bytes a pixel on the CPU path: the radiance (3 f64) twice (rayon collects it in
/// pieces, then into one vector: measured under `ulimit -v`, issue 38, 8, where the GPU's
/// margin no longer hides it), then the pixels for the encoder (RGBA8 or RGBA f32) made
/// from it.
fn cpu_bytes_per_pixel(kind: ImageKind) -> u64 {
    match kind {
        ImageKind::Png => 2 * 24 + 4,
        ImageKind::Exr => 2 * 24 + 16,
    }
}

/// Bytes a pixel the Monte Carlo image adds to the CPU path's: the collected per-pixel
/// results (mean, standard error, coverage: 56 bytes) split into the image's three vectors
/// (49 bytes).
const MONTECARLO_BYTES_PER_PIXEL: u64 = 56 + 49;

/// Bytes a pixel the lobe's progressive image holds on the GPU besides the target
/// (counted, not measured): its `Rgba32Uint` frame and two sums, 16 bytes each, and the
/// ball pass's f32 depth.
const LOBE_BYTES_PER_PIXEL: u64 = 3 * 16 + 4;

/// Peak bytes a pixel on the GPU path, measured on lavapipe (where the GPU's memory is the
/// host's): the frame, the read-back buffer, its mapped copy and the unpadded image, each
/// 4 (RGBA8) or 16 (RGBA f32) bytes.
fn gpu_bytes_per_pixel(kind: ImageKind) -> u64 {
    match kind {
        ImageKind::Png => 4 * 4,
        ImageKind::Exr => 4 * 16,
    }
}
