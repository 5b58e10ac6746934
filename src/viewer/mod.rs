//! The interactive viewer (`shadeballs view`): a winit window showing the scene the headless
//! renderer draws, through the same [`crate::gpu::Renderer::encode`], with an egui panel
//! on the right to change it live.
//!
//! `App` is winit's application (its events, keys and mouse in `events`); `state::State`
//! holds the GPU resources and `compose` the cached images a frame is made of; [`edit`] and
//! `orbit` are the pure scene edits the controls make. Nothing is drawn while nothing
//! changes (winit waits for events), except in `--frames` mode, which
//! draws the given number of frames back to back, saves the window and exits.

pub(crate) mod blit;
mod capture;
mod clock;
pub mod compare;
mod compose;
pub mod difference;
pub mod edit;
mod events;
pub mod labels;
pub(crate) mod orbit;
mod overlay;
mod panel;

pub(crate) use panel::PANEL_WIDTH;
pub(crate) mod save;
mod state;
#[cfg(all(test, feature = "cli"))]
mod tests;
#[cfg(test)]
pub(crate) use state::surface_format;

use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop, OwnedDisplayHandle};
use winit::window::Window;

use crate::error::{Error, Result};
use crate::gpu::Backend;
use crate::output::{write_png, ImageKind};
use crate::scene::Scene;
use clock::FrameClock;
use compose::Overlay;
use panel::{Controls, Stats};
use state::{Frame, State};

/// Camera turn per frame in `--orbit` mode, radians (a full turn in about 300 frames).
pub(crate) const ORBIT_STEP: f64 = 0.02;
/// How often the panel's figures are updated (each update draws the panel again).
const STATS_PERIOD: Duration = Duration::from_millis(500);

/// What `shadeballs view` was asked for.
pub(crate) struct ViewOptions {
    /// The scene shown first (the panel edits it).
    pub scene: Scene,
    /// The GPU backend to open (not [`Backend::Cpu`]: the viewer needs a GPU).
    pub backend: Backend,
    /// The window's inner size in pixels.
    pub size: (u32, u32),
    /// Draw this many frames, save `screenshot` if given, and exit.
    pub frames: Option<u32>,
    /// With `frames`: the PNG the window's last frame is saved to, or the EXR the scene
    /// area's linear radiance is.
    pub screenshot: Option<PathBuf>,
    /// With `frames`: the scene file the scene is saved to after the last frame.
    pub save_scene: Option<PathBuf>,
    /// Turn the camera by [`ORBIT_STEP`] every frame (to measure frame times while orbiting).
    pub orbit: bool,
    /// The comparison shown first (`--compare`, `--split`, `--difference`); the panel's
    /// Compare section edits it.
    pub compare: Option<compare::Compare>,
}

/// What a `--frames` run measured.
pub(crate) struct Report {
    /// Frames drawn.
    pub frames: u32,
    /// How many of the frames shaded the balls (the others reused the last image of them).
    pub scene_draws: u64,
    /// How many of the frames drew the panel (the others reused the last image of it).
    pub panel_draws: u64,
    /// The window's inner size in pixels.
    pub window: (u32, u32),
    /// The scene area: the top-left `width x height` of the window.
    pub scene: (u32, u32),
    /// The adapter drawn with ([`crate::gpu::Gpu::describe`]).
    pub adapter: String,
    /// Median wall time between the starts of consecutive frames (what the user sees).
    pub interval_ms: Option<f64>,
    /// Median wall time of drawing a frame (acquire, encode, GPU, present).
    pub draw_ms: Option<f64>,
    /// Lobe samples a pixel the last frame's image held (`None` when no ball uses the
    /// lobe).
    pub lobe_samples: Option<u32>,
}

/// Opens the window and runs until it is closed (or `--frames` are drawn).
pub(crate) fn run(options: ViewOptions) -> Result<Report> {
    let Some(backends) = options.backend.wgpu_backends() else {
        return Err(Error::Invalid {
            what: "backend",
            message: "the viewer draws with the GPU; `shadeballs render --backend cpu` \
                      renders with the CPU reference renderer"
                .into(),
        });
    };
    let event_loop = EventLoop::new().map_err(display_error)?;
    event_loop.set_control_flow(ControlFlow::Wait);
    let mut app = App::new(options, backends, event_loop.owned_display_handle());
    event_loop.run_app(&mut app).map_err(display_error)?;
    app.finish()
}

struct App {
    options: ViewOptions,
    backends: wgpu::Backends,
    display: OwnedDisplayHandle,
    state: Option<State>,
    egui_ctx: egui::Context,
    egui_winit: Option<egui_winit::State>,
    scene: Scene,
    controls: Controls,
    /// The camera's distance to its target at start (zoom limits are relative to it).
    home_distance: f64,
    cursor: (f64, f64),
    /// Where the left button went down in the scene area, while it is held.
    drag: Option<(f64, f64)>,
    /// Whether the left button went down on the wipe's split line, while it is held.
    split_drag: bool,
    /// Whether the left button went down on the panel since egui last ran: a click on a
    /// combo box that opens its menu only at the next frame.
    panel_press_undrawn: bool,
    scene_width: u32,
    frames_drawn: u32,
    clock: FrameClock,
    /// The figures the panel shows, and when they were taken.
    stats: Option<(Instant, Stats)>,
    /// egui's shapes and scale of the last frame (the panel is drawn again only when they
    /// change).
    last_shapes: (Vec<egui::epaint::ClippedShape>, f32),
    /// Where the next frame's pixels go (key S, or the last `--frames` frame).
    screenshot: Option<PathBuf>,
    /// The EXR and scene file the next frame writes (key E, the panel's buttons, the last
    /// `--frames` frame).
    pending: capture::Pending,
    /// The scene and comparison of the last frame shown: where a refused edit goes back to.
    last_drawn: Option<(Scene, Option<compare::Compare>)>,
    error: Option<Error>,
}

impl App {
    fn new(options: ViewOptions, backends: wgpu::Backends, display: OwnedDisplayHandle) -> Self {
        let scene = options.scene.clone();
        let home_distance = (scene.camera.position - scene.camera.target).length();
        App {
            controls: Controls::new(
                &scene,
                &crate::lut::BakeConfig::default().layout,
                options.compare,
            ),
            options,
            backends,
            display,
            state: None,
            egui_ctx: egui::Context::default(),
            egui_winit: None,
            scene,
            home_distance,
            cursor: (0.0, 0.0),
            drag: None,
            split_drag: false,
            panel_press_undrawn: false,
            scene_width: 1,
            frames_drawn: 0,
            clock: FrameClock::default(),
            stats: None,
            last_shapes: (Vec::new(), 0.0),
            screenshot: None,
            pending: capture::Pending::default(),
            last_drawn: None,
            error: None,
        }
    }

    fn finish(self) -> Result<Report> {
        if let Some(e) = self.error {
            return Err(e);
        }
        let state = self.state.as_ref();
        Ok(Report {
            frames: self.frames_drawn,
            scene_draws: state.map_or(0, |s| s.draws().0),
            panel_draws: state.map_or(0, |s| s.draws().1),
            window: state.map_or((0, 0), State::size),
            scene: (self.scene_width, state.map_or(0, |s| s.size().1)),
            adapter: state.map_or_else(String::new, |s| s.renderer.gpu().describe()),
            interval_ms: self.clock.interval_ms(),
            draw_ms: self.clock.draw_ms(),
            lobe_samples: state.and_then(|s| s.renderer.lobe_samples()),
        })
    }

    /// Stops the event loop with `e` as the run's result.
    fn fail(&mut self, event_loop: &ActiveEventLoop, e: Error) {
        self.error.get_or_insert(e);
        event_loop.exit();
    }

    /// A draw that failed with `e`. In a window, a scene the renderer refuses (an edit in
    /// the panel, such as a clear coat on a truth ball under lights) is reported and the
    /// viewer goes back to the scene and comparison it last showed; anything else, a
    /// `--frames` run's failure or the first frame's, ends the run.
    fn draw_failed(&mut self, event_loop: &ActiveEventLoop, e: Error) {
        let refused = matches!(e, Error::Invalid { .. } | Error::TruthUnsupported { .. });
        match self.last_drawn.clone() {
            Some((scene, compare)) if refused && self.options.frames.is_none() => {
                eprintln!("error: {e} (back to the last scene drawn)");
                self.scene = scene;
                self.controls.compare = compare;
                self.request_redraw();
            }
            _ => self.fail(event_loop, e),
        }
    }

    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let (w, h) = self.options.size;
        let attributes = Window::default_attributes()
            .with_title("shadeballs")
            .with_inner_size(winit::dpi::PhysicalSize::new(w, h));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .map_err(display_error)?,
        );
        let mut desc = wgpu::InstanceDescriptor::new_with_display_handle_from_env(Box::new(
            self.display.clone(),
        ));
        desc.backends = self.backends;
        let instance = wgpu::Instance::new(desc);
        let state = State::new(instance, self.backends, window.clone())?;
        let max_side = state
            .renderer
            .gpu()
            .device
            .limits()
            .max_texture_dimension_2d;
        self.egui_winit = Some(egui_winit::State::new(
            self.egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(max_side as usize),
        ));
        self.state = Some(state);
        window.request_redraw();
        Ok(())
    }

    fn request_redraw(&self) {
        if let Some(state) = &self.state {
            state.window.request_redraw();
        }
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        let (Some(state), Some(egui_winit)) = (&mut self.state, &mut self.egui_winit) else {
            return;
        };
        let start = Instant::now();
        if self.options.orbit {
            self.scene.camera = orbit::orbit(&self.scene.camera, ORBIT_STEP, 0.0);
        }
        // The panel: edits the scene and the bake settings; reports the last frames.
        let stats = refresh_stats(
            &mut self.stats,
            state,
            &mut self.clock,
            (&self.scene, self.controls.compare.as_ref()),
            self.scene_width,
            start,
        );
        let input = egui_winit.take_egui_input(&state.window);
        self.panel_press_undrawn = false;
        let (scene, controls) = (&mut self.scene, &mut self.controls);
        let mut free_width = 0.0;
        let mut label_shapes = Vec::new();
        let window_height = state.size().1;
        let output = self.egui_ctx.run_ui(input, |ui| {
            panel::show(ui, scene, controls, stats);
            free_width = ui.available_rect_before_wrap().max.x;
            let compare = controls.compare.as_ref();
            label_shapes = overlay::shapes(ui, scene, compare, free_width, window_height);
        });
        egui_winit.handle_platform_output(&state.window, output.platform_output);
        take_requests(
            &mut self.controls,
            &mut self.screenshot,
            &mut self.pending,
            self.options.save_scene.as_deref(),
        );
        let ppp = output.pixels_per_point;
        let (width, height) = state.size();
        self.scene_width = ((free_width * ppp).floor() as u32).clamp(1, width.max(1));
        let mut bake = state.renderer.bake_config();
        bake.layout = self.controls.table_layout();
        state.renderer.set_bake_config(bake);
        let overlay = overlay(
            &self.egui_ctx,
            state,
            &mut self.last_shapes,
            self.scene_width,
            (output.shapes, output.textures_delta, ppp),
            label_shapes,
        );
        let last = self.options.frames == Some(self.frames_drawn + 1);
        if last {
            self.pending.scene = self.options.save_scene.clone();
            match self.options.screenshot.clone() {
                Some(p) if crate::output::image_kind(&p).ok() == Some(ImageKind::Exr) => {
                    self.pending.exr = Some(p)
                }
                Some(p) if self.screenshot.is_none() => self.screenshot = Some(p),
                _ => {}
            }
        }
        let capture = self.screenshot.is_some();
        let scene = (&self.scene, self.controls.compare.as_ref());
        match state.draw(scene, self.scene_width, &overlay, capture) {
            Ok(Frame::Shown(pixels)) => {
                self.clock.shown(start);
                self.frames_drawn += 1;
                self.last_drawn = Some((self.scene.clone(), self.controls.compare));
                if let (Some(path), Some(rgba)) = (self.screenshot.take(), pixels) {
                    if let Err(e) = self.write_screenshot(&path, (width, height), rgba) {
                        return self.fail(event_loop, e);
                    }
                    if let Err(e) = self.write_numbers(&path) {
                        return self.fail(event_loop, e);
                    }
                }
                if let Err(e) = self.write_pending() {
                    return self.fail(event_loop, e);
                }
                if last {
                    event_loop.exit();
                }
            }
            // Not shown: the next frame must draw the panel whatever egui says then.
            Ok(Frame::Skipped) => self.last_shapes = (Vec::new(), 0.0),
            Ok(Frame::Retry) => {
                self.last_shapes = (Vec::new(), 0.0);
                self.request_redraw();
            }
            Err(e) => self.draw_failed(event_loop, e),
        }
        let delay = output
            .viewport_output
            .get(&egui::ViewportId::ROOT)
            .map_or(Duration::MAX, |v| v.repaint_delay);
        self.schedule_next(event_loop, delay);
    }

    /// Writes the frame's `rgba` pixels of `size` to `path`. A failure is the run's only
    /// where `--screenshot` is what the run was for (`--frames`); in a window (S) it is
    /// reported and the viewer goes on.
    fn write_screenshot(
        &self,
        path: &std::path::Path,
        size: (u32, u32),
        rgba: Vec<u8>,
    ) -> Result<()> {
        let (width, height) = size;
        match write_png(path, width, height, rgba) {
            Ok(()) => eprintln!(
                "screenshot {width}x{height} (scene area {}x{height} at the top left) -> {}",
                self.scene_width,
                path.display()
            ),
            Err(e) if self.options.frames.is_some() => return Err(e),
            Err(e) => eprintln!("error: {e}"),
        }
        Ok(())
    }

    /// Beside a screenshot taken while comparing, the comparison's numbers a ball as CSV
    /// (`NAME.csv` beside `NAME.png`). A failure is the run's only in `--frames` mode.
    fn write_numbers(&self, shot: &std::path::Path) -> Result<()> {
        let (Some(state), Some(c)) = (&self.state, self.controls.compare.as_ref()) else {
            return Ok(());
        };
        let written = state
            .ball_numbers(&self.scene, c, self.scene_width)
            .and_then(|numbers| {
                let Some(numbers) = numbers else {
                    return Ok(None);
                };
                let csv = compare::numbers_csv(c, &self.scene, &numbers);
                let path = shot.with_extension("csv");
                crate::output::write_atomic(&path, csv.as_bytes())?;
                Ok(Some(path))
            });
        match written {
            Ok(Some(path)) => eprintln!("ball numbers (A, B, A / B) -> {}", path.display()),
            Ok(None) => {}
            Err(e) if self.options.frames.is_some() => return Err(e),
            Err(e) => eprintln!("error: {e}"),
        }
        Ok(())
    }

    /// Interactive: a frame was drawn because something changed; egui may ask for another
    /// (an animation) after `delay`, and truth balls keep accumulating while nothing changes
    /// (each draw of an unchanged scene adds an estimate a pixel), up to the headless cap,
    /// as the lobe's image does (`ibl_samples` a draw, up to [`compose::LOBE_SAMPLE_CAP`]).
    fn schedule_next(&mut self, event_loop: &ActiveEventLoop, delay: Duration) {
        let compare = self.controls.compare.as_ref();
        let accumulating = self.state.as_ref().is_some_and(|s| {
            s.truth_accumulating(&self.scene, compare) || s.lobe_converging(compare)
        });
        // The panel shows the count of the frame before: once more after the last frame
        // added, so that it shows the final count.
        let stale_count = self
            .stats
            .as_ref()
            .zip(self.state.as_ref())
            .is_some_and(|((_, stats), state)| stats.lobe_samples != state.renderer.lobe_samples());
        // A deadline is kept until it is reached (`new_events`) or replaced.
        if delay.is_zero() || accumulating || stale_count {
            self.request_redraw();
        } else {
            event_loop.set_control_flow(match Instant::now().checked_add(delay) {
                Some(when) => ControlFlow::WaitUntil(when),
                None => ControlFlow::Wait,
            });
        }
    }
}

/// The panel's buttons (screenshot, EXR, save scene) as the keys' requests: into the
/// screenshot and the files the next frame writes, named by the panel's file name field
/// (else time-stamped; a scene file to `--save-scene`'s path where given and the field is
/// empty).
fn take_requests(
    controls: &mut Controls,
    screenshot: &mut Option<PathBuf>,
    pending: &mut capture::Pending,
    save_scene: Option<&std::path::Path>,
) {
    let requests = std::mem::take(&mut controls.requests);
    if requests.png {
        *screenshot = Some(controls.file_for("png"));
    }
    if requests.exr {
        pending.exr = Some(controls.file_for("exr"));
    }
    if requests.save_scene {
        let path = match save_scene {
            Some(p) if controls.file_name.trim().is_empty() => p.to_path_buf(),
            _ => controls.file_for("toml"),
        };
        pending.scene = Some(path);
    }
}

/// The egui part of a frame ([`Overlay`]) from egui's `shapes`, `textures` and
/// pixels-per-point: whether anything changed since `last` (replaced by these shapes),
/// whether it all lies right of the scene area (its left edge, in pixels, past
/// `scene_width` unless a popup reaches over), the panel tessellated only when the frame
/// image's panel is redrawn (compose.rs), and the chart's labels.
fn overlay(
    ctx: &egui::Context,
    state: &State,
    last: &mut (Vec<egui::epaint::ClippedShape>, f32),
    scene_width: u32,
    (shapes, textures, ppp): (Vec<egui::epaint::ClippedShape>, egui::TexturesDelta, f32),
    label_shapes: Vec<egui::epaint::ClippedShape>,
) -> Overlay {
    let left = shapes
        .iter()
        .map(|s| s.shape.visual_bounding_rect().intersect(s.clip_rect).min.x)
        .filter(|x| x.is_finite())
        .fold(f32::INFINITY, f32::min);
    let changed = shapes != last.0 || ppp != last.1 || !textures.is_empty();
    *last = (shapes.clone(), ppp);
    let panel_only = left * ppp >= scene_width as f32 - 1.0;
    let primitives = if state.panel_due(changed, panel_only) {
        ctx.tessellate(shapes, ppp)
    } else {
        Vec::new()
    };
    Overlay {
        labels: ctx.tessellate(label_shapes, ppp),
        primitives,
        textures,
        pixels_per_point: ppp,
        changed,
        panel_only,
    }
}

/// The panel's readouts: kept while they are fresh (the clock settled, within
/// [`STATS_PERIOD`], the same bake, map preparation, scene area and no accumulating truth),
/// else measured again at `now`.
fn refresh_stats<'a>(
    held: &'a mut Option<(Instant, Stats)>,
    state: &State,
    clock: &mut FrameClock,
    (scene, compare): (&Scene, Option<&compare::Compare>),
    scene_width: u32,
    now: Instant,
) -> &'a Stats {
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    let bake_ms = state.renderer.last_bake_time().map(ms);
    let prefilter_ms = state.renderer.last_prefilter_time().map(ms);
    let scene_size = (scene_width, state.size().1);
    let fresh = clock.settled()
        && held.as_ref().is_some_and(|(at, s)| {
            at.elapsed() < STATS_PERIOD
                && s.bake_ms == bake_ms
                && s.prefilter_ms == prefilter_ms
                && s.scene_size == scene_size
                && s.truth_samples.is_none()
                && s.lobe_samples == state.renderer.lobe_samples()
                && s.numbers.is_some() == compare.is_some()
        });
    if !fresh {
        let stats = Stats {
            frame_ms: clock.recent_draw_ms(),
            bake_ms,
            prefilter_ms,
            adapter: state.renderer.gpu().describe(),
            plan: plan_summary(&state.renderer),
            scene_size,
            truth_samples: if scene.has_truth() {
                state.renderer.truth_samples()
            } else {
                None
            },
            lobe_samples: state.renderer.lobe_samples(),
            // Read back only while comparing; a failed read shows no numbers.
            numbers: compare.and_then(|c| state.ball_numbers(scene, c, scene_width).ok().flatten()),
        };
        *held = Some((now, stats));
    }
    &held.as_ref().expect("set above").1
}

/// winit's error without the "os error at <its source file>:<line>: " it starts with.
fn display_error(e: impl std::fmt::Display) -> Error {
    let message = e.to_string();
    let message = match message.strip_prefix("os error at ") {
        Some(rest) => rest
            .split_once(": ")
            .map_or(rest, |(_, cause)| cause)
            .to_string(),
        None => message,
    };
    Error::Display { message }
}

/// The plan in a few words, shorter than its `Display` (`render --verbose`), which lists
/// every row's roughness: what is baked and bound, and the rows kept in memory.
fn plan_summary(renderer: &crate::gpu::Renderer) -> String {
    use crate::lut::TableSet;
    let Some(plan) = renderer.plan() else {
        return "tables: not planned yet".into();
    };
    let layout = &plan.bake.layout;
    let tables = match &plan.tables {
        TableSet::None => "tables: none (no ball reads E)".to_string(),
        TableSet::Rows(rows) => format!(
            "tables: {} exact rows of {} along mu",
            rows.len(),
            layout.mu_size
        ),
        TableSet::Full(_) => format!("tables: {}x{} table", layout.mu_size, layout.r_size),
    };
    format!("{tables}; {} rows cached", renderer.cached_rows())
}
