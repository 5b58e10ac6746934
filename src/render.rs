//! A scene rendered by any backend (`render --backend`, the lab's `compare`): the device
//! opened with its fallbacks and their notices ([`open`]), then the image on the GPU, the
//! CPU reference renderer, the Monte Carlo (on the GPU, else the CPU with a notice) or the
//! truth, as display pixels or linear radiance ([`render`]). What a front end shows while
//! it runs (the phases, the summary lines, the truth's progress, a stop after a pass) goes
//! through [`Progress`]; it writes the file itself.

use std::time::Instant;

use glam::DVec3;

use crate::cpu::{self, TruthImage, TruthProgress};
use crate::environment::{ChainOn, IblMethod};
use crate::error::{Error, Result};
use crate::gpu::{Backend, Gpu, Renderer};
use crate::lut::{self, BakeConfig};
use crate::memory;
use crate::prepared::Prepared;
use crate::scene::Scene;

/// Samples per pixel of the Monte Carlo backends without `spp` (and of the truth without a
/// target standard error).
pub(crate) const DEFAULT_SPP: u32 = 64;

/// The GPU renderer of `backend`, or `None` for the CPU: a CPU backend, or `auto` with no
/// adapter; with the warning or notice of a fallback, for the front end to print.
/// `montecarlo` tries `auto`'s adapters, and falls back to the CPU estimator with a notice
/// where there is none or it cannot render to `Rgba32Float`.
pub fn open(backend: Backend) -> Result<(Option<Renderer>, Option<String>)> {
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

/// What to render: the backend, the size, display pixels or linear radiance, and the
/// sampled backends' settings.
#[derive(Clone, Debug)]
pub struct Request {
    /// The backend the device was opened for ([`open`]).
    pub backend: Backend,
    /// Width and height in pixels.
    pub size: (u32, u32),
    /// Display pixels (a `.png`), linear radiance in f32 (an `.exr`) or in full.
    pub output: Output,
    /// Samples a pixel of the Monte Carlo, the truth and the truth balls (default
    /// `DEFAULT_SPP`).
    pub spp: Option<u32>,
    /// The sampled backends' seed.
    pub seed: u64,
    /// The truth's target standard error.
    pub stderr: Option<f64>,
    /// Frames of the lobe's samples averaged on the GPU.
    pub ibl_frames: Option<u32>,
    /// Say the plan.
    pub verbose: bool,
}

/// What a render returns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// Display pixels ([`Pixels::Display`]).
    Display,
    /// Linear radiance in f32 ([`Pixels::Linear`]).
    Linear,
    /// Linear radiance as the renderer has it ([`Pixels::Radiance`]: the CPU's f64, the
    /// GPU's f32 widened), for a measurement.
    Radiance,
}

impl Request {
    /// Whether the pixels are linear radiance.
    fn linear(&self) -> bool {
        self.output != Output::Display
    }
}

/// The picture's pixels, row-major from the top.
pub enum Pixels {
    /// RGBA8 display values (tone-mapped and encoded).
    Display(Vec<u8>),
    /// RGBA f32 linear radiance.
    Linear(Vec<f32>),
    /// Linear radiance ([`Output::Radiance`]).
    Radiance(Vec<DVec3>),
}

/// A rendered picture: its pixels, where it was drawn, and for a render a stop may cut
/// short (the GPU's Monte Carlo, the truth) its samples a pixel; the truth's per-pixel
/// standard error (RGBA f32) beside an `.exr`.
pub struct Rendered {
    /// The pixels.
    pub pixels: Pixels,
    /// The device or renderer, for people.
    pub device: String,
    /// Samples a pixel of a render a stop may cut short.
    pub spp: Option<u32>,
    /// The truth's per-pixel standard error, RGBA f32 (linear requests only).
    pub std_error: Option<Vec<f32>>,
    /// What a progressive backend (the Monte Carlo, the truth) rendered with, and its
    /// samples a pixel: the note its file carries.
    pub sampled: Option<(&'static str, u32)>,
}

/// What a front end is told while a render runs.
pub trait Progress {
    /// A phase of the work ended (`bake`, `render`, ...), to time it.
    fn phase(&mut self, name: &str);
    /// A line for people (a summary, a notice).
    fn line(&mut self, text: &str);
    /// A render a stop may cut short starts (`true`) or ends (`false`).
    fn stoppable(&mut self, on: bool);
    /// After a pass of such a render: whether to go on.
    fn keep_going(&mut self) -> bool;
    /// After a pass of the truth (capped at `spp`, with the target `stderr`): whether to
    /// go on.
    fn truth_pass(&mut self, pass: &TruthProgress, spp: u32, stderr: Option<f64>) -> bool;
    /// The truth's last pass, with its target `stderr` and `seed`.
    fn truth_done(&mut self, last: &TruthProgress, stderr: Option<f64>, seed: u64);
}

/// Renders `scene` as `request` asks on `renderer` (the GPU, or `None` for the CPU
/// backends), telling `progress`.
pub fn render(
    renderer: Option<&mut Renderer>,
    scene: &Scene,
    request: &Request,
    progress: &mut dyn Progress,
) -> Result<Rendered> {
    check_clearcoat(scene, request.backend, renderer.is_some())?;
    match renderer {
        Some(renderer) if request.backend == Backend::Montecarlo => {
            montecarlo_on_gpu(renderer, scene, request, progress)
        }
        Some(renderer) => on_gpu(renderer, scene, request, progress),
        None => on_cpu(scene, request, progress),
    }
}

/// What the GPU does not draw: a clear-coated truth ball under directional lights (the
/// coat's walk in walk.wgsl has no next-event estimation, as the CPU truth's: `cpu::truth`
/// refuses it too, and so does `Renderer::render`; here before any work is done).
fn check_clearcoat(scene: &Scene, backend: Backend, gpu: bool) -> Result<()> {
    if gpu && backend != Backend::Truth {
        scene.check_clearcoat_truth_lights(false)?;
    }
    Ok(())
}

/// The noun of a picture file, for messages.
fn kind_name(linear: bool) -> &'static str {
    if linear {
        ".exr"
    } else {
        ".png"
    }
}

/// The render on the GPU (plan, bake, the map's prefilter, the truth's frames, the
/// pipeline, the frame).
fn on_gpu(
    renderer: &mut Renderer,
    scene: &Scene,
    request: &Request,
    progress: &mut dyn Progress,
) -> Result<Rendered> {
    let (w, h) = request.size;
    let pixels = u64::from(w) * u64::from(h);
    renderer.gpu().check_size(w, h)?;
    let lobe_frames = request.ibl_frames.unwrap_or(1);
    let lobe =
        lobe_frames > 1 && scene.ibl_method == IblMethod::Lobe && scene.environment_map.is_some();
    let per_pixel = if lobe {
        // The mean is read back as f32 whatever the file, besides the lobe's sums.
        gpu_bytes_per_pixel(true) + LOBE_BYTES_PER_PIXEL
    } else {
        gpu_bytes_per_pixel(request.linear())
    };
    memory::check(
        &format!("a {w}x{h} {} on the GPU", kind_name(request.linear())),
        pixels * per_pixel,
    )?;
    let plan = renderer.plan_for(scene);
    if request.verbose {
        let plan = plan.to_string().replace('\n', "\n      ");
        progress.line(&format!("plan: {plan}"));
    }
    progress.phase("bake");
    if scene.environment_map.is_some() {
        // Mip chain, split-sum table and the GPU's prefiltering of the map.
        renderer.prepare_environment(scene)?;
        progress.phase("prefilter");
    }
    if scene.has_truth() {
        let spp = request.spp.unwrap_or(DEFAULT_SPP);
        accumulate_gpu_truth(renderer, scene, (w, h), spp, progress)?;
        progress.phase("truth");
    }
    let pixels = if lobe {
        // The mean of the frames in linear radiance, then the display transform (a PNG).
        let t = Instant::now();
        let image = renderer.render_lobe_hdr(scene, w, h, lobe_frames)?;
        progress.line(&format!(
            "lobe: {} of {} at {w}x{h} in {:.1} ms",
            crate::stats::count(lobe_frames, "frame"),
            crate::stats::count(scene.ibl_samples, "sample"),
            t.elapsed().as_secs_f64() * 1e3
        ));
        progress.phase("render");
        if request.linear() {
            linear_pixels(request.output, image.rgba)
        } else {
            let display = scene.display();
            Pixels::Display(
                image
                    .rgba
                    .chunks_exact(4)
                    .flat_map(|p| {
                        let radiance = glam::Vec3::new(p[0], p[1], p[2]).as_dvec3();
                        crate::display::to_rgba8_pixel(radiance, scene.exposure, display)
                    })
                    .collect(),
            )
        }
    } else if request.linear() {
        // The pipeline is created at the first draw (its float format is chosen there):
        // "render" includes it.
        let image = renderer.render_hdr(scene, w, h)?;
        progress.phase("render");
        linear_pixels(request.output, image.rgba)
    } else {
        renderer.prepare(scene, wgpu::TextureFormat::Rgba8Unorm);
        progress.phase("pipeline");
        let rgba = renderer.render_ldr(scene, w, h)?.rgba;
        progress.phase("render");
        Pixels::Display(rgba)
    };
    Ok(Rendered {
        pixels,
        device: renderer.gpu().describe(),
        spp: None,
        std_error: None,
        sampled: None,
    })
}

/// The Monte Carlo on the GPU: its passes (a stop after one leaves the passes done) and
/// its summary line.
fn montecarlo_on_gpu(
    renderer: &mut Renderer,
    scene: &Scene,
    request: &Request,
    progress: &mut dyn Progress,
) -> Result<Rendered> {
    let (w, h) = request.size;
    renderer.gpu().check_size(w, h)?;
    // Four Rgba32Float textures and two read-backs on the device; mean, error and coverage
    // on the host.
    memory::check(
        &format!(
            "a {w}x{h} {} by the GPU's Monte Carlo",
            kind_name(request.linear())
        ),
        u64::from(w) * u64::from(h) * (6 * 16 + MONTECARLO_BYTES_PER_PIXEL + 24),
    )?;
    if scene.environment_map.is_some() {
        renderer.prepare_environment(scene)?;
        progress.phase("prefilter");
    }
    let spp = request.spp.unwrap_or(DEFAULT_SPP);
    let started = Instant::now();
    progress.stoppable(true);
    let image = renderer.render_montecarlo_progressive(scene, (w, h), (spp, request.seed), |_| {
        progress.keep_going()
    });
    progress.stoppable(false);
    let image = image?;
    progress.phase("render");
    progress.line(&montecarlo_summary(&image, request.seed, started));
    Ok(Rendered {
        pixels: pixels_of(scene, request.output, image.mean),
        device: format!("GPU Monte Carlo, {}", renderer.gpu().describe()),
        spp: Some(image.spp),
        std_error: None,
        sampled: Some(("Monte Carlo on the GPU", image.spp)),
    })
}

/// `radiance` as the request's pixels.
fn pixels_of(scene: &Scene, output: Output, radiance: Vec<DVec3>) -> Pixels {
    match output {
        Output::Radiance => Pixels::Radiance(radiance),
        Output::Linear => Pixels::Linear(cpu::to_rgba_f32(&radiance)),
        Output::Display => Pixels::Display(cpu::to_display_rgba8(
            &radiance,
            scene.exposure,
            scene.display(),
        )),
    }
}

/// The GPU's RGBA f32 radiance as the request's linear pixels.
fn linear_pixels(output: Output, rgba: Vec<f32>) -> Pixels {
    match output {
        Output::Radiance => Pixels::Radiance(
            rgba.chunks_exact(4)
                .map(|p| DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2])))
                .collect(),
        ),
        _ => Pixels::Linear(rgba),
    }
}

/// The Monte Carlo backends' line: samples, seed, time, noise.
fn montecarlo_summary(image: &cpu::MonteCarloImage, seed: u64, started: Instant) -> String {
    let noise = image
        .mean_relative_std_error()
        .map_or("n/a".to_string(), |r| format!("{:.3} %", 100.0 * r));
    format!(
        "montecarlo: {} spp, seed {seed}, {:.1} ms, mean relative standard error over \
         ball pixels {noise}",
        image.spp,
        started.elapsed().as_secs_f64() * 1e3
    )
}

/// The render on the CPU: the reference renderer, the Monte Carlo backend or the truth (its
/// per-pixel standard error with the image).
fn on_cpu(scene: &Scene, request: &Request, progress: &mut dyn Progress) -> Result<Rendered> {
    let (w, h) = request.size;
    let pixels = u64::from(w) * u64::from(h);
    let geometry = scene.effective_geometry();
    check_cpu_size(w, h)?;
    let montecarlo = matches!(
        request.backend,
        Backend::Montecarlo | Backend::MontecarloCpu
    );
    let truth = request.backend == Backend::Truth;
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
        &format!("a {w}x{h} {} on the CPU", kind_name(request.linear())),
        pixels * (cpu_bytes_per_pixel(request.linear()) + extra),
    )?;
    if let Some(environment) = scene
        .environment_map
        .as_ref()
        .filter(|_| !montecarlo && !truth)
    {
        // The Monte Carlo backends read the map itself; the others its mip chain.
        environment.map.check_chain_memory(ChainOn::Cpu)?;
    }
    if request.verbose {
        progress.line("plan: the CPU reference renderer reads the 2-D table; no pipelines");
    }
    // The tables, the coating rows and each ball's coating, prepared once for the render.
    let tables = lut::TableSet::from(lut::bake(&BakeConfig {
        geometry,
        ..Default::default()
    }));
    let prepared = Prepared::new(scene, &tables);
    progress.phase("bake");
    let name = if truth {
        "CPU truth (random walk)"
    } else if montecarlo {
        "CPU Monte Carlo reference"
    } else {
        "CPU reference renderer"
    };
    if truth {
        let image = render_truth(scene, &prepared, request, progress)?.image;
        progress.phase("render");
        let std_error = request.linear().then(|| cpu::to_rgba_f32(&image.std_error));
        // The radiance (24 bytes a pixel) is dropped before the encoder starts.
        return Ok(Rendered {
            pixels: pixels_of(scene, request.output, image.mean),
            device: name.to_string(),
            spp: Some(image.spp),
            std_error,
            sampled: Some(("truth (random walk)", image.spp)),
        });
    }
    let radiance = if montecarlo {
        let started = Instant::now();
        let spp = request.spp.unwrap_or(DEFAULT_SPP);
        let image = cpu::render_montecarlo(scene, &prepared, w, h, spp, request.seed)?;
        progress.phase("render");
        progress.line(&montecarlo_summary(&image, request.seed, started));
        image.mean
    } else if scene.has_truth() {
        // Truth balls by the walk, the others by the reference renderer.
        let settings = cpu::TruthSettings {
            spp: request.spp.unwrap_or(DEFAULT_SPP),
            seed: request.seed,
            ..Default::default()
        };
        let radiance = cpu::render_radiance_with_truth(scene, &prepared, w, h, settings)?;
        progress.phase("render");
        radiance
    } else {
        let radiance = cpu::render_radiance(scene, &prepared, w, h);
        progress.phase("render");
        radiance
    };
    let sampled = montecarlo.then(|| {
        let spp = request.spp.unwrap_or(DEFAULT_SPP);
        ("Monte Carlo on the CPU", spp)
    });
    Ok(Rendered {
        pixels: pixels_of(scene, request.output, radiance),
        device: name.to_string(),
        spp: None,
        std_error: None,
        sampled,
    })
}

/// The truth on the CPU, its passes told to `progress` (which may stop it after one), and
/// a summary of every ball's mean and its standard error.
fn render_truth(
    scene: &Scene,
    prepared: &Prepared,
    request: &Request,
    progress: &mut dyn Progress,
) -> Result<TruthImage> {
    let settings = cpu::TruthSettings {
        spp: request.spp.unwrap_or(if request.stderr.is_some() {
            cpu::montecarlo::MAX_SPP
        } else {
            DEFAULT_SPP
        }),
        stderr: request.stderr,
        seed: request.seed,
        max_order: u32::MAX,
        every_ball: true,
    };
    let (w, h) = request.size;
    progress.stoppable(true);
    let image = cpu::render_truth(scene, prepared, w, h, settings, |p| {
        progress.truth_pass(p, settings.spp, settings.stderr)
    });
    progress.stoppable(false);
    let image = image?;
    if let Some(last) = image.passes.last() {
        progress.truth_done(last, settings.stderr, settings.seed);
        if let (Some(target), Some(worst)) = (settings.stderr, last.worst_stderr) {
            if worst > target {
                progress.line(&format!(
                    "warning: the target standard error {:.3} % was not reached: {:.3} % at \
                     the cap of {} spp (raise --spp, up to {})",
                    100.0 * target,
                    100.0 * worst,
                    last.spp,
                    cpu::montecarlo::MAX_SPP
                ));
            }
        }
    }
    if image.balls.iter().all(|b| b.relative_std_error().is_none()) {
        progress.line(&format!(
            "warning: no ball covers a pixel of the {w}x{h} image: the walk has nothing to \
             estimate (the background is exact), so it stopped at {}",
            crate::stats::count(image.image.spp, "sample")
        ));
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
            progress.line(&format!(
                "  ball {k}: mean radiance [{:.5}, {:.5}, {:.5}] {error}",
                b.mean.x, b.mean.y, b.mean.z,
            ));
        }
    }
    Ok(image)
}

/// A GPU render of a scene with truth balls: `spp - 1` frames of their estimates, each
/// waited for and timed (the draw that writes the image adds the last), and a line with
/// the median frame time (docs/benchmarks.md, "GPU truth").
fn accumulate_gpu_truth(
    renderer: &mut Renderer,
    scene: &Scene,
    (w, h): (u32, u32),
    spp: u32,
    progress: &mut dyn Progress,
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
        progress.line(&format!(
            "gpu truth: {spp} spp at {w}x{h}, {rate} over {} frames",
            times.len()
        ));
    }
    Ok(())
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

/// Peak bytes a pixel on the CPU path: the radiance (3 f64) twice (rayon collects it in
/// pieces, then into one vector: measured under `ulimit -v`, issue 38, 8, where the GPU's
/// margin no longer hides it), then the pixels for the encoder (RGBA8 or RGBA f32) made
/// from it.
fn cpu_bytes_per_pixel(linear: bool) -> u64 {
    if linear {
        2 * 24 + 16
    } else {
        2 * 24 + 4
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
fn gpu_bytes_per_pixel(linear: bool) -> u64 {
    if linear {
        4 * 16
    } else {
        4 * 4
    }
}
