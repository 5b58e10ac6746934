//! `shadeballs render`: the scene to a `.png` or `.exr`, on the GPU or, without a GPU driver,
//! the CPU reference renderer; one line on stderr with the time of each phase.

use std::fmt::Write as _;
use std::time::Instant;

use super::args::RenderArgs;
use super::{guard, interrupt, progress};
use crate::cpu::TruthProgress;
use crate::error::{Error, Result};
use crate::gpu::{Backend, Renderer};
use crate::labels;
use crate::output::{self, image_kind, write_exr, write_png, ImageKind};
use crate::render::{self as dispatch, Output, Pixels, Request};
use crate::scene::Scene;

pub(crate) fn run(args: RenderArgs) -> anyhow::Result<()> {
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
    let (w, h) = image_size(&args, &scene);
    let (device, truth_spp) =
        render_and_write(renderer, &scene, &args, kind, sidecar, &mut phases)?;
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
    let opening = std::thread::Builder::new()
        .name("device".into())
        .spawn(move || dispatch::open(backend))
        .unwrap_or_else(|e| super::process::cannot_start("the thread that opens the device", e));
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

/// `scene` rendered as `args` ask ([`dispatch::render`]; Ctrl-C stops a truth or a GPU
/// Monte Carlo after a pass), labelled and written (a truth's `sidecar` of standard errors
/// with the image, both or neither); where it ran, and the samples a pixel of a render a
/// stop may cut short.
fn render_and_write(
    mut renderer: Option<Renderer>,
    scene: &Scene,
    args: &RenderArgs,
    kind: ImageKind,
    sidecar: Option<std::path::PathBuf>,
    phases: &mut Phases,
) -> Result<(String, Option<u32>)> {
    let (w, h) = image_size(args, scene);
    let request = Request {
        backend: args.backend,
        size: (w, h),
        output: if kind == ImageKind::Exr {
            Output::Linear
        } else {
            Output::Display
        },
        spp: args.spp,
        seed: args.seed,
        stderr: args.stderr,
        ibl_frames: args.ibl_frames,
        verbose: args.verbose,
    };
    let mut told = Told {
        phases: &mut *phases,
        stoppable: None,
        terminal: std::io::IsTerminal::is_terminal(&std::io::stderr()),
    };
    if let Some(r) = &renderer {
        // The GPU's f32 camera (issue 38, 4), checked where the size is.
        r.gpu().check_size(w, h)?;
        guard::check_f32_camera(scene, w, h)?;
    }
    let rendered = dispatch::render(renderer.as_mut(), scene, &request, &mut told)?;
    let truth = args.backend == Backend::Truth;
    // The samples a pixel of a progressive backend, in the file (issue 38, 7).
    let note = rendered.sampled.map(|(what, spp)| samples_note(what, spp));
    let linear = match rendered.pixels {
        Pixels::Display(mut rgba) => {
            draw_labels(scene, args, &mut rgba, phases)?;
            match &note {
                Some(note) => output::write_png_noted(&args.out, w, h, rgba, note)?,
                None => write_png(&args.out, w, h, rgba)?,
            }
            None
        }
        Pixels::Linear(rgba) => Some(rgba),
        // Not asked for here: written as the f32 an `.exr` holds.
        Pixels::Radiance(radiance) => Some(crate::cpu::to_rgba_f32(&radiance)),
    };
    if let Some(rgba) = linear {
        match (sidecar, rendered.std_error, rendered.spp, &note) {
            (Some(path), Some(side), Some(spp), Some(note)) if spp >= 2 => {
                // Both written, then both renamed: a failed write leaves the old pair
                // (issue 28, 4).
                let side = output::stage_exr_noted(&path, w, h, side, note)?;
                let image = output::stage_exr_noted(&args.out, w, h, rgba, note)?;
                output::commit_all(vec![side, image])?;
                eprintln!("per-pixel standard error -> {}", path.display());
            }
            (Some(path), _, _, Some(note)) if truth => {
                // Stopped after the first pass: one estimate a pixel has no error.
                output::stage_exr_noted(&args.out, w, h, rgba, note)?.commit()?;
                eprintln!(
                    "{} not written: one estimate a pixel has no standard error",
                    path.display()
                );
            }
            (_, _, _, Some(note)) => {
                output::stage_exr_noted(&args.out, w, h, rgba, note)?.commit()?
            }
            _ => write_exr(&args.out, w, h, rgba)?,
        }
    }
    let stopped = rendered
        .spp
        .filter(|_| interrupt::stop_requested().is_some() || truth);
    Ok((rendered.device, stopped))
}

/// What `render` shows while the library renders: the phases' times, lines on stderr, the
/// truth's progress (a bar on a terminal, else a line a pass), and Ctrl-C's stop after a
/// pass.
struct Told<'a> {
    phases: &'a mut Phases,
    stoppable: Option<interrupt::Stoppable>,
    terminal: bool,
}

impl dispatch::Progress for Told<'_> {
    fn phase(&mut self, name: &str) {
        self.phases.mark(name);
    }

    fn line(&mut self, text: &str) {
        eprintln!("{text}");
    }

    fn stoppable(&mut self, on: bool) {
        self.stoppable = on.then(interrupt::Stoppable::start);
    }

    fn keep_going(&mut self) -> bool {
        interrupt::stop_requested().is_none()
    }

    fn truth_pass(&mut self, pass: &TruthProgress, spp: u32, stderr: Option<f64>) -> bool {
        // A bar redrawn in place on a terminal, else a line a pass (the curve of the error
        // against time, docs/truth.md).
        if self.terminal {
            eprint!("\r{}   ", progress::line(pass, spp, stderr, true));
        } else {
            eprintln!("{}", progress::line(pass, spp, stderr, false));
        }
        interrupt::stop_requested().is_none()
    }

    fn truth_done(&mut self, last: &TruthProgress, stderr: Option<f64>, seed: u64) {
        if self.terminal {
            eprintln!();
        }
        let target = stderr.map_or(String::new(), |s| format!(" (target {:.3} %)", 100.0 * s));
        eprintln!("{}{target}, seed {seed}", progress::summary(last));
    }
}

/// The text a progressive backend's file carries (a PNG's `Comment`, an EXR's `comment`):
/// what rendered it, the samples a pixel, and the signal that stopped it early, if one did.
fn samples_note(what: &str, spp: u32) -> String {
    let stopped = interrupt::stop_requested().map_or(String::new(), |s| {
        format!(", interrupted by {}", interrupt::signal_name(s))
    });
    format!("shadeballs {what}: {spp} spp{stopped}")
}

/// The sidecar of a truth `.exr`: `NAME.stderr.exr` beside `NAME.exr`.
pub(crate) fn stderr_path(out: &std::path::Path) -> std::path::PathBuf {
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
    let (w, h) = image_size(args, scene);
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

/// The image's size: `--width` and `--height` where given, else the scene's `size`, else
/// 1280 x 720 (`args::picture_size`).
fn image_size(args: &RenderArgs, scene: &Scene) -> (u32, u32) {
    super::args::picture_size((args.width, args.height), scene.size, 0)
}
