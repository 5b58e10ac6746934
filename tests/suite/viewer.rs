//! The viewer in a real window: Xvfb (a virtual X server), the binary, and xdotool to send
//! keys, a resize and an unmap/map (what a window manager does on minimise) through the
//! window system. The window's scene area must equal the headless render of the same scene.
//! Also the viewer's pure scene edits (no window).

use std::path::Path;
use std::process::{Child, Command, Output, Stdio};
use std::sync::Arc;
use std::time::{Duration, Instant};

use glam::DVec3;
use shadeballs::environment::{Background, Builtin, Environment, IblTerm, Source};
use shadeballs::labels;
use shadeballs::scene::{Camera, Scene};
use shadeballs::viewer::edit::{
    self, EnvironmentChoice, EnvironmentControl, Grid, LightControl, MaterialChoice,
};
use shadeballs::viewer::labels::readable_px;
use shadeballs::viewer::orbit;

use crate::cli::temp_dir;
use crate::pixels::{assert_close, compare, vulkan};

/// A private X server, killed when dropped.
pub struct Xvfb {
    child: Child,
    display: String,
}

impl Xvfb {
    pub fn start() -> Xvfb {
        // `-displayfd 1`: Xvfb picks a free display number and writes it to its stdout
        // once it accepts connections (tests run in parallel, each with its own server).
        let mut child = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "1600x1000x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap_or_else(|e| {
                panic!("viewer test cannot run: Xvfb: {e}. Install it: apt-get install -y xvfb")
            });
        let mut line = String::new();
        let stdout = child.stdout.take().unwrap();
        std::io::BufRead::read_line(&mut std::io::BufReader::new(stdout), &mut line).unwrap();
        let n: u32 = line
            .trim()
            .parse()
            .unwrap_or_else(|_| panic!("Xvfb did not report its display (said {line:?})"));
        Xvfb {
            child,
            display: format!(":{n}"),
        }
    }

    pub fn command(&self, program: &str) -> Command {
        let mut c = Command::new(program);
        c.env("DISPLAY", &self.display)
            .env_remove("WAYLAND_DISPLAY");
        c
    }

    /// `xdotool args...`, which must succeed.
    pub fn xdotool(&self, args: &[&str]) -> String {
        let out = self
            .command("xdotool")
            .args(args)
            .output()
            .unwrap_or_else(|e| {
                panic!(
                    "viewer test cannot run: xdotool: {e}. Install it: apt-get install -y xdotool"
                )
            });
        assert!(
            out.status.success(),
            "xdotool {args:?} failed: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).trim().to_string()
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Waits for `child` at most `limit`; kills it and fails if it runs longer.
pub fn wait(mut child: Child, limit: Duration) -> Output {
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            let out = child.wait_with_output().unwrap();
            panic!(
                "the viewer did not exit within {limit:?}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    child.wait_with_output().unwrap()
}

/// Waits until the process `pid` is idle: its CPU time, all threads together
/// (`/proc/PID/stat`'s utime and stime, in clock ticks of 10 ms), grows by under
/// `IDLE_TICKS` in each of two seconds in a row. Panics after `limit`.
fn until_idle(pid: u32, limit: Duration) {
    const IDLE_TICKS: u64 = 5;
    let cpu_ticks = || -> u64 {
        let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap();
        // The fields after the command name's closing parenthesis start at the 3rd
        // (state): utime and stime, the 14th and 15th, are the 12th and 13th of these.
        let fields: Vec<&str> = stat[stat.rfind(')').unwrap() + 1..]
            .split_whitespace()
            .collect();
        fields[11].parse::<u64>().unwrap() + fields[12].parse::<u64>().unwrap()
    };
    let start = Instant::now();
    let (mut last, mut quiet) = (cpu_ticks(), 0);
    while quiet < 2 {
        assert!(
            start.elapsed() < limit,
            "the viewer was still busy after {limit:?}"
        );
        std::thread::sleep(Duration::from_secs(1));
        let now = cpu_ticks();
        quiet = if now - last < IDLE_TICKS {
            quiet + 1
        } else {
            0
        };
        last = now;
    }
}

/// The scene area's size the viewer reports with its screenshot ("scene area WxH").
fn scene_area(stderr: &str) -> (u32, u32) {
    let at = stderr
        .find("(scene area ")
        .unwrap_or_else(|| panic!("no scene area in: {stderr}"));
    let size = stderr[at + 12..].split_whitespace().next().unwrap();
    let (w, h) = size.split_once('x').unwrap();
    (w.parse().unwrap(), h.parse().unwrap())
}

/// The top-left `w x h` of an RGBA8 image `width` wide.
fn crop(rgba: &[u8], width: u32, (w, h): (u32, u32)) -> Vec<u8> {
    (0..h as usize)
        .flat_map(|y| {
            let start = 4 * y * width as usize;
            rgba[start..start + 4 * w as usize].iter().copied()
        })
        .collect()
}

/// Asserts the screenshot's scene area equals the headless render of `scene` (on Vulkan).
/// A Vulkan window is the same shader on the same adapter into an 8-bit unorm target (BGRA
/// for the window, RGBA headless) and agrees exactly; a GL window is another driver, 6 of
/// 705,600 pixels off by 1/255 when measured. The bound is the render issue's GPU-vs-CPU
/// bound (`assert_close`).
///
/// With the scene's labels on (the built-in scene's default), the viewer paints them over
/// the scene area with egui in the rooms of `labels::layout`: each room must differ from
/// the bare render (the labels are there), and the comparison covers every pixel outside
/// the rooms (which the layout keeps off the balls).
fn assert_scene_matches(shot: &Path, stderr: &str, scene: &Scene, what: &str) {
    let image = image::open(shot).unwrap().to_rgba8();
    let area = scene_area(stderr);
    let mut window = crop(image.as_raw(), image.width(), area);
    let mut headless = vulkan().render_ldr(scene, area.0, area.1).unwrap().rgba;
    if scene.labels {
        let layout = labels::layout(scene, area.0, area.1);
        let mut changed = vec![0usize; layout.iter().count()];
        for (i, (a, b)) in window
            .chunks_exact_mut(4)
            .zip(headless.chunks_exact_mut(4))
            .enumerate()
        {
            let (x, y) = ((i as u32 % area.0) as f32, (i as u32 / area.0) as f32);
            // A label's room, or the room of one of its wrapped lines.
            let room = layout.iter().position(|l| {
                std::iter::once(l).chain(&l.wrapped).any(|l| {
                    let r = &l.room;
                    x + 1.0 > r.x0 && x < r.x1 && y + 1.0 > r.y0 && y < r.y1
                })
            });
            if let Some(k) = room {
                changed[k] += (a != b) as usize;
                a.copy_from_slice(b);
            }
        }
        println!("{what}: pixels the labels changed, per label: {changed:?}");
        // Every label that fits its room (at the PNG font's width: egui's Ubuntu Light is
        // the same font) at a readable size is drawn; one that does not is left out.
        let fits: Vec<bool> = layout
            .iter()
            .map(|l| {
                let fitted = l.fit(|t, s| labels::text_width(t, s).unwrap());
                !fitted.is_empty()
                    && fitted
                        .iter()
                        .all(|(l, p)| p.size_px >= readable_px(l.size_px))
            })
            .collect();
        assert!(fits.iter().any(|&f| f), "{what}: no label fits");
        for ((l, n), fit) in layout.iter().zip(&changed).zip(fits) {
            assert!(
                !fit || *n >= 20,
                "{what}: {:?} missing: {changed:?}",
                l.text
            );
            assert!(fit || *n == 0, "{what}: {:?} drawn too small", l.text);
        }
    }
    assert_close(&compare(&window, &headless, area.0), what);
}

/// The homework's scene file (`Scene::reference()`): the viewer tests' scene where they
/// compare against it or click its panel.
const HOMEWORK: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/homework.toml");

fn viewer(x: &Xvfb, args: &[&str]) -> Command {
    let mut c = x.command(env!("CARGO_BIN_EXE_shadeballs"));
    c.arg("view").args(args);
    c.stdout(Stdio::piped()).stderr(Stdio::piped());
    c
}

/// On Vulkan (the frame image copied into the window) and on GL (drawn into it: GL
/// surfaces cannot be copied into).
#[test]
fn window_scene_area_equals_the_headless_render() {
    let x = Xvfb::start();
    let dir = temp_dir("view-shot");
    for backend in ["vulkan", "gl"] {
        let shot = dir.join(format!("view-{backend}.png"));
        let args = ["--frames", "3", "--backend", backend, "--screenshot"];
        let out = viewer(&x, &args).arg(&shot).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "viewer on {backend} failed: {stderr}");
        let image = image::open(&shot).unwrap();
        assert_eq!((image.width(), image.height()), (1280, 720), "{stderr}");
        let what = format!("window on {backend} vs headless on Vulkan");
        // The default scene: the showcase.
        assert_scene_matches(&shot, &stderr, &Scene::showcase(), &what);
    }
}

/// The default chart in windows narrower than 16:9 (issue 39): the scene area beside the
/// panel holds all ten balls whole, and its labels are drawn where the layout puts them,
/// the rest equal to the headless render of the scene area.
#[test]
fn default_chart_fits_the_scene_area_beside_the_panel() {
    let x = Xvfb::start();
    let dir = temp_dir("view-aspect");
    for (w, h) in [(1024u32, 768u32), (800, 800)] {
        let shot = dir.join(format!("view-{w}x{h}.png"));
        let (ws, hs) = (w.to_string(), h.to_string());
        let args = [
            "--frames",
            "2",
            "--backend",
            "vulkan",
            "--width",
            &ws,
            "--height",
            &hs,
            "--screenshot",
        ];
        let out = viewer(&x, &args).arg(&shot).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "viewer at {w}x{h} failed: {stderr}");
        let (aw, ah) = scene_area(&stderr);
        let scene = Scene::showcase();
        for r in labels::ball_rects(&scene, aw, ah) {
            let r = r.unwrap_or_else(|| panic!("{aw}x{ah}: a ball out of frame"));
            assert!(
                r.x0 > 0.0 && r.y0 > 0.0 && r.x1 < aw as f32 && r.y1 < ah as f32,
                "{aw}x{ah}: ball {r:?} cut by the frame"
            );
        }
        assert_eq!(labels::layout(&scene, aw, ah).rows.len(), 2);
        let what = format!("window {w}x{h} (scene area {aw}x{ah})");
        assert_scene_matches(&shot, &stderr, &scene, &what);
    }
}

/// `view --environment studio`: the window draws the map (prefiltered on the GPU at the
/// first frame) and its scene area equals the headless render of the same scene.
#[test]
fn window_with_an_environment_map_equals_the_headless_render() {
    let x = Xvfb::start();
    let dir = temp_dir("view-env");
    let shot = dir.join("view-studio.png");
    let args = [
        "--scene",
        HOMEWORK,
        "--environment",
        "studio",
        "--frames",
        "3",
        "--screenshot",
    ];
    let out = viewer(&x, &args).arg(&shot).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "viewer with studio failed: {stderr}");
    assert!(!stderr.contains("error"), "{stderr}");
    let image = image::open(&shot).unwrap();
    assert_eq!((image.width(), image.height()), (1280, 720), "{stderr}");
    // The environment section fits in the panel's 300 points.
    assert_eq!(scene_area(&stderr), (980, 720), "{stderr}");
    let mut scene = Scene::reference();
    scene.environment_map = Some(Environment::builtin(Builtin::Studio));
    scene.environment = DVec3::ZERO;
    assert_scene_matches(&shot, &stderr, &scene, "window with studio vs headless");
}

/// Key M, a resize and an unmap/map (the minimise of a window manager; X11 has no 0x0
/// window) at a fractional DPI scale (1.5: the panel's 300 points are 450 pixels), then
/// key S: the viewer goes on, and its screenshot is the resized window showing the scene
/// with the term on every ball. Interactive, so no frame count can run out before the
/// events arrive.
#[test]
fn keys_resize_and_unmap_through_the_window_system() {
    let x = Xvfb::start();
    let dir = temp_dir("view-events");
    let child = viewer(&x, &["--scene", HOMEWORK])
        .current_dir(&dir)
        .env("WINIT_X11_SCALE_FACTOR", "1.5")
        .spawn()
        .unwrap();
    let stderr = drive(&x, child, |id| {
        x.xdotool(&["windowsize", "--sync", id, "960", "540"]);
        // XTEST input to the focused window, as a real keyboard's (not a sent event).
        x.xdotool(&["windowfocus", "--sync", id, "key", "m"]);
        x.xdotool(&["windowunmap", "--sync", id]);
        std::thread::sleep(Duration::from_millis(300));
        x.xdotool(&["windowmap", "--sync", id]);
        x.xdotool(&["windowfocus", "--sync", id, "key", "s"]);
        let start = Instant::now();
        while pngs(&dir).is_empty() && start.elapsed() < Duration::from_secs(30) {
            std::thread::sleep(Duration::from_millis(100));
        }
    });
    let shots = pngs(&dir);
    assert_eq!(shots.len(), 1, "{shots:?}: {stderr}");
    let image = image::open(&shots[0]).unwrap();
    assert_eq!((image.width(), image.height()), (960, 540), "{stderr}");
    assert_eq!(scene_area(&stderr), (960 - 450, 540), "{stderr}");
    let mut scene = Scene::reference();
    edit::toggle_term(&mut scene);
    assert!(scene.balls.iter().all(|b| b.model.has_term()));
    assert_scene_matches(
        &shots[0],
        &stderr,
        &scene,
        "resized window (M pressed) vs headless",
    );
}

/// Finds the viewer's window, runs `events` on it (given its id), presses Esc and waits for
/// the viewer to exit; returns what it printed, failing with it if anything went wrong.
fn drive(x: &Xvfb, child: Child, events: impl FnOnce(&str)) -> String {
    let sent = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let id = x.xdotool(&["search", "--sync", "--name", "^shadeballs$"]);
        let id = id.lines().next().unwrap().to_string();
        events(&id);
        x.xdotool(&["windowfocus", "--sync", &id, "key", "Escape"]);
    }));
    let out = wait(child, Duration::from_secs(60));
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        sent.is_ok(),
        "sending the events failed; the viewer said: {stderr}"
    );
    assert!(out.status.success(), "viewer failed: {stderr}");
    stderr
}

/// The PNG files in `dir`.
fn pngs(dir: &Path) -> Vec<std::path::PathBuf> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .collect()
}

/// The number after `key` in the viewer's report ("viewed 12 frames (1 shading ...").
fn reported(stderr: &str, key: &str) -> u64 {
    let at = stderr
        .find(key)
        .unwrap_or_else(|| panic!("no '{key}' in: {stderr}"));
    stderr[at + key.len()..]
        .split(|c: char| !c.is_ascii_digit())
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

/// Interactive: nothing is drawn while nothing happens, hovering the panel redraws only the
/// panel, a drag in the scene area orbits (shades the balls again), and S saves a
/// screenshot without shading them again; Esc quits.
#[test]
fn idle_draws_nothing_and_only_the_scene_area_orbits() {
    let x = Xvfb::start();
    let dir = temp_dir("view-idle");
    // The homework scene's panel, which the hover points and the frame bound were chosen
    // on (22 frames). The showcase (a map: one more panel line and the environment
    // section) took 26 to 29 frames, 32 once under the full suite's load; why it takes
    // more is not established.
    let child = viewer(&x, &["--scene", HOMEWORK])
        .current_dir(&dir)
        .spawn()
        .unwrap();
    let stderr = drive(&x, child, |id| {
        // Idle for 1.5 s: at 20-60 frames a second, continuous redrawing would show.
        std::thread::sleep(Duration::from_millis(1500));
        for (px, py) in [(1100, 200), (1150, 300), (1200, 400)] {
            let (px, py) = (px.to_string(), py.to_string());
            x.xdotool(&["mousemove", "--window", id, &px, &py]);
            std::thread::sleep(Duration::from_millis(100));
        }
        x.xdotool(&["mousemove", "--window", id, "300", "300", "mousedown", "1"]);
        x.xdotool(&["mousemove", "--window", id, "360", "320", "mouseup", "1"]);
        std::thread::sleep(Duration::from_millis(300));
        x.xdotool(&["windowfocus", "--sync", id, "key", "s"]);
        std::thread::sleep(Duration::from_millis(300));
    });
    let frames = reported(&stderr, "viewed ");
    let shaded = reported(&stderr, "frames (");
    println!("idle, hover, drag and S: {frames} frames, the balls shaded {shaded} times");
    // First frame, the drag's one or two, and egui's own follow-ups per event (hover,
    // focus, key): well under what 1.5 s of continuous drawing would give.
    assert!(frames <= 30, "{frames} frames while idle: {stderr}");
    assert!(
        (2..=3).contains(&shaded),
        "balls shaded {shaded} times: {stderr}"
    );
    assert_eq!(pngs(&dir).len(), 1, "S wrote no screenshot: {stderr}");
}

/// CPU time (user + system) the process `pid` has used, in clock ticks (Linux
/// `/proc/PID/stat` fields 14 and 15, counted after the command name's closing parenthesis).
fn cpu_ticks(pid: u32) -> u64 {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap();
    let fields: Vec<&str> = stat[stat.rfind(')').unwrap() + 2..].split(' ').collect();
    fields[11].parse::<u64>().unwrap() + fields[12].parse::<u64>().unwrap()
}

/// A focused text field (the table size, clicked) makes egui ask for a redraw at its
/// cursor's next blink: the viewer wakes for it, draws, and waits again. It once kept a
/// reached deadline and woke at once forever: a whole core spent while nothing was drawn.
#[test]
fn a_blinking_cursor_redraws_without_spinning() {
    let x = Xvfb::start();
    let dir = temp_dir("view-blink");
    let child = viewer(&x, &["--scene", HOMEWORK])
        .current_dir(&dir)
        .spawn()
        .unwrap();
    let pid = child.id();
    let mut ticks = 0;
    let stderr = drive(&x, child, |id| {
        std::thread::sleep(Duration::from_millis(500));
        // The table's mu size field, left of "mu x" (the homework scene's panel, 1280x720 at
        // DPI 1: a scene with a map has one more line above it).
        x.xdotool(&[
            "windowfocus",
            "--sync",
            id,
            "mousemove",
            "--window",
            id,
            "1045",
            "216",
        ]);
        x.xdotool(&["mousedown", "1"]);
        std::thread::sleep(Duration::from_millis(200));
        x.xdotool(&["mouseup", "1"]);
        std::thread::sleep(Duration::from_millis(500));
        let before = cpu_ticks(pid);
        std::thread::sleep(Duration::from_secs(2));
        ticks = cpu_ticks(pid) - before;
        // Esc in a text field leaves the field (egui has the keyboard); the next one quits.
        x.xdotool(&["windowfocus", "--sync", id, "key", "Escape"]);
        std::thread::sleep(Duration::from_millis(200));
    });
    println!("2 s with a blinking cursor: {ticks} clock ticks (Linux's 100 a second)");
    // Blinking: about four panel frames of ~15 ms (7 ticks in 3 s measured); spinning: a
    // core for the whole 2 s (200 ticks).
    assert!(
        ticks >= 1,
        "no redraw while the cursor blinks: {ticks} ticks; {stderr}"
    );
    assert!(
        ticks <= 60,
        "the viewer spins while idle: {ticks} ticks in 2 s; {stderr}"
    );
}

/// With no display the viewer fails in one line that points to `shadeballs render`.
#[test]
fn no_display_points_to_render() {
    let out = Command::new(env!("CARGO_BIN_EXE_shadeballs"))
        .arg("view")
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "view without a display succeeded");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("cannot open a window") && stderr.contains("`shadeballs render`"),
        "{stderr}"
    );
}

#[test]
fn orbit_keeps_a_valid_camera_and_zoom_stays_in_range() {
    let home = Camera::reference();
    let d0 = (home.position - home.target).length();
    let mut c = home;
    for _ in 0..1000 {
        c = orbit::orbit(&c, 0.37, 0.11);
        assert!(c.problem().is_none(), "{c:?}");
        let d = (c.position - c.target).length();
        assert!(
            (d - d0).abs() < 1e-9 * d0,
            "orbit changed the distance: {d}"
        );
    }
    let pitch = ((c.position - c.target).y / d0).asin().to_degrees();
    assert!(pitch <= orbit::MAX_PITCH_DEG + 1e-9, "{pitch}");
    for lines in [1e3, -1e3] {
        let z = orbit::zoom(&home, lines, d0);
        let d = (z.position - z.target).length();
        assert!(
            d >= d0 * orbit::ZOOM_RANGE.0 * (1.0 - 1e-12)
                && d <= d0 * orbit::ZOOM_RANGE.1 * (1.0 + 1e-12),
            "{d}"
        );
    }
}

#[test]
fn reference_grid_and_light_controls_reproduce_the_reference_scene() {
    let reference = Scene::reference();
    let material = reference.balls[0].material;
    let grid = Grid::REFERENCE.balls(material);
    assert_eq!(grid.len(), reference.balls.len());
    for (a, b) in grid.iter().zip(&reference.balls) {
        assert!((a.center - b.center).length() < 1e-12, "{a:?} {b:?}");
        assert!((a.roughness - b.roughness).abs() < 1e-12);
        assert_eq!(a.radius, b.radius);
        assert_eq!(a.model.has_term(), b.model.has_term());
    }
    let lights = LightControl::of(&reference).lights();
    assert_eq!(lights.len(), 1);
    assert!((lights[0].direction - reference.lights[0].direction).length() < 1e-12);
    assert_eq!(lights[0].radiance, reference.lights[0].radiance);
    // Many balls: still two rows, the row (edge to edge) no wider than the reference's.
    let wide = Grid {
        per_row: 32,
        low: 0.0,
        high: 1.0,
    }
    .balls(material);
    assert_eq!(wide.len(), 64);
    let span = |bs: &[shadeballs::scene::Ball]| {
        let right = bs.iter().map(|b| b.center.x + b.radius);
        let left = bs.iter().map(|b| b.center.x - b.radius);
        right.fold(f64::MIN, f64::max) - left.fold(f64::MAX, f64::min)
    };
    assert!(span(&wide) <= span(&reference.balls) + 1e-9);
    assert_eq!(wide[0].roughness, 0.0);
    assert_eq!(wide[31].roughness, 1.0);
}

#[test]
fn term_rows_furnace_and_materials_edit_the_scene() {
    let mut scene = Scene::reference();
    let rows = edit::rows(&scene);
    assert_eq!(rows.len(), 2);
    assert!(edit::row_has_term(&scene, &rows[0]) && !edit::row_has_term(&scene, &rows[1]));
    edit::set_row_term(&mut scene, &rows[1], true);
    assert!(scene.balls.iter().all(|b| b.model.has_term()));
    edit::toggle_term(&mut scene);
    assert!(scene.balls.iter().all(|b| !b.model.has_term()));
    edit::toggle_term(&mut scene);
    assert!(scene.balls.iter().all(|b| b.model.has_term()));

    let mut saved = None;
    edit::set_furnace(&mut scene, true, &mut saved);
    assert!(edit::is_furnace(&scene) && scene.lights.is_empty());
    edit::set_furnace(&mut scene, true, &mut saved);
    assert_eq!(
        saved.as_ref().map(|s| s.lights.len()),
        Some(1),
        "turning it on twice must not lose the lights"
    );
    edit::set_furnace(&mut scene, false, &mut saved);
    assert!(!edit::is_furnace(&scene));
    assert_eq!(scene.lights, Scene::reference().lights);
    assert_eq!(scene.environment, DVec3::ZERO);
    // A coloured environment with lights is not the furnace, and comes back whole.
    let sky = DVec3::new(0.2, 0.3, 0.5);
    scene.environment = sky;
    assert!(!edit::is_furnace(&scene));
    edit::set_furnace(&mut scene, true, &mut saved);
    assert!(edit::is_furnace(&scene));
    edit::set_furnace(&mut scene, false, &mut saved);
    assert_eq!(scene.environment, sky);
    assert_eq!(scene.lights, Scene::reference().lights);
    // The furnace scene file turned off: no lights to restore, a black environment.
    let mut furnace = Scene::furnace();
    assert!(edit::is_furnace(&furnace));
    edit::set_furnace(&mut furnace, false, &mut None);
    assert!(furnace.lights.is_empty() && furnace.environment == DVec3::ZERO);

    assert_eq!(MaterialChoice::AsScene.material(), None);
    let originals: Vec<_> = scene.balls.iter().map(|b| b.material).collect();
    let white = MaterialChoice::White.material().unwrap();
    edit::set_material(&mut scene, white);
    assert!(scene.balls.iter().all(|b| b.material == white));
    edit::restore_materials(&mut scene, &originals);
    assert!(scene
        .balls
        .iter()
        .zip(&originals)
        .all(|(b, m)| b.material == *m));
    edit::set_material(&mut scene, white);
    let wild = MaterialChoice::Custom([2.0, -1.0, 0.5]).material().unwrap();
    assert_eq!(
        wild.f0.to_array(),
        [1.0, 0.0, 0.5],
        "F0 is clamped to [0, 1]"
    );
    assert_eq!(
        MaterialChoice::Copper.material().unwrap(),
        Scene::reference().balls[0].material
    );
}

/// The panel's environment picker: a built-in replaces the uniform radiance (kept for
/// "uniform" to restore), is generated once however often it is chosen, and keeps the
/// latest map's rotation and intensity; rotation and intensity edits keep the map's `Arc`
/// (the renderer knows a map by it: nothing is prefiltered again).
#[test]
fn environment_picker_switches_maps_and_keeps_them() {
    let mut scene = Scene::reference();
    let sky = DVec3::new(0.2, 0.3, 0.5);
    scene.environment = sky;
    let mut control = EnvironmentControl::of(&scene);
    assert_eq!(EnvironmentChoice::of(&scene), EnvironmentChoice::Uniform);
    assert_eq!(
        control.choices(),
        [
            EnvironmentChoice::Uniform,
            EnvironmentChoice::Builtin(Builtin::Studio),
            EnvironmentChoice::Builtin(Builtin::Sky),
            EnvironmentChoice::Builtin(Builtin::White),
        ],
        "no file without a scene map file"
    );
    // Nothing to pick without a file: no change.
    edit::set_environment(&mut scene, EnvironmentChoice::File, &mut control);
    assert!(scene.environment_map.is_none() && scene.environment == sky);

    let studio = EnvironmentChoice::Builtin(Builtin::Studio);
    edit::set_environment(&mut scene, studio, &mut control);
    let map = scene.environment_map.clone().expect("studio chosen");
    assert_eq!(map.source, Source::Builtin(Builtin::Studio));
    assert_eq!((map.rotation_deg, map.intensity), (0.0, 1.0));
    assert_eq!(scene.environment, DVec3::ZERO);
    assert_eq!(EnvironmentChoice::of(&scene), studio);
    assert_eq!(
        *map.map,
        Builtin::Studio.generate(shadeballs::environment::builtin::DEFAULT_BUILTIN_WIDTH)
    );
    assert_eq!(scene.lights, Scene::reference().lights, "lights untouched");

    // Rotation and intensity change those fields alone, and keep the same map.
    let before = scene.clone();
    edit::set_map_rotation(&mut scene, -90.0);
    edit::set_map_intensity(&mut scene, 2.5);
    let e = scene.environment_map.as_ref().unwrap();
    assert!(
        Arc::ptr_eq(&e.map, &map.map),
        "rotation or intensity replaced the map"
    );
    assert_eq!((e.rotation_deg, e.intensity), (-90.0, 2.5));
    assert_eq!(e.source, map.source);
    let mut same = scene.clone();
    same.environment_map = before.environment_map.clone();
    assert_eq!(
        same, before,
        "only the map's rotation and intensity changed"
    );
    edit::set_map_intensity(&mut scene, -1.0);
    assert_eq!(scene.environment_map.as_ref().unwrap().intensity, 0.0);
    edit::set_map_intensity(&mut scene, 2.5);

    // Sky, then studio again: the first studio's map, turned and scaled as last set.
    edit::set_environment(
        &mut scene,
        EnvironmentChoice::Builtin(Builtin::Sky),
        &mut control,
    );
    let e = scene.environment_map.as_ref().unwrap();
    assert_eq!(e.source, Source::Builtin(Builtin::Sky));
    assert_eq!((e.rotation_deg, e.intensity), (-90.0, 2.5));
    edit::set_environment(&mut scene, studio, &mut control);
    assert!(Arc::ptr_eq(
        &scene.environment_map.as_ref().unwrap().map,
        &map.map
    ));
    assert_eq!(control.builtins_generated(), 2, "studio generated once");
    assert!(Arc::ptr_eq(&control.builtin_map(Builtin::Studio), &map.map));

    // Back to uniform: the scene's radiance, no map; studio again keeps its transform.
    edit::set_environment(&mut scene, EnvironmentChoice::Uniform, &mut control);
    assert!(scene.environment_map.is_none());
    assert_eq!(scene.environment, sky);
    edit::set_environment(&mut scene, studio, &mut control);
    let e = scene.environment_map.as_ref().unwrap();
    assert!(Arc::ptr_eq(&e.map, &map.map));
    assert_eq!((e.rotation_deg, e.intensity), (-90.0, 2.5));
    edit::set_environment(&mut scene, EnvironmentChoice::Uniform, &mut control);
    assert_eq!(scene.environment, sky);
    assert_eq!(control.builtins_generated(), 2);

    // A scene that came with a built-in: the picker starts from it, its map counts as
    // generated (chosen again, the same Arc).
    let mut scene = Scene::reference();
    scene.environment_map = Some(Environment::builtin(Builtin::White));
    let loaded = scene.environment_map.clone().unwrap();
    let mut control = EnvironmentControl::of(&scene);
    assert_eq!(
        EnvironmentChoice::of(&scene),
        EnvironmentChoice::Builtin(Builtin::White)
    );
    edit::set_environment(&mut scene, EnvironmentChoice::Uniform, &mut control);
    edit::set_environment(
        &mut scene,
        EnvironmentChoice::Builtin(Builtin::White),
        &mut control,
    );
    assert!(Arc::ptr_eq(
        &scene.environment_map.as_ref().unwrap().map,
        &loaded.map
    ));
    assert_eq!(control.builtins_generated(), 1);
}

/// A scene that came with a map file lists "file (as loaded)", which brings back that very
/// map (its Arc) after a built-in; "uniform" gives the scene's uniform radiance (black for
/// a scene with a map).
#[test]
fn environment_picker_offers_the_scene_map_file() {
    let dir = temp_dir("view-env-file");
    let path = dir.join("tiny.hdr");
    let map = Builtin::Sky.generate(32);
    shadeballs::environment::save(&map, &path).unwrap();
    let mut scene = Scene::reference();
    let file = Environment {
        rotation_deg: 30.0,
        intensity: 0.5,
        ..Environment::from_file(&path).unwrap()
    };
    scene.environment_map = Some(file.clone());
    let mut control = EnvironmentControl::of(&scene);
    assert_eq!(EnvironmentChoice::of(&scene), EnvironmentChoice::File);
    assert_eq!(control.choices().last(), Some(&EnvironmentChoice::File));
    assert_eq!(EnvironmentChoice::File.name(), "file (as loaded)");
    edit::set_environment(
        &mut scene,
        EnvironmentChoice::Builtin(Builtin::Sky),
        &mut control,
    );
    let e = scene.environment_map.as_ref().unwrap();
    assert_eq!((e.rotation_deg, e.intensity), (30.0, 0.5));
    edit::set_environment(&mut scene, EnvironmentChoice::File, &mut control);
    let e = scene.environment_map.as_ref().unwrap();
    assert_eq!(e.source, file.source);
    assert!(Arc::ptr_eq(&e.map, &file.map));
    edit::set_environment(&mut scene, EnvironmentChoice::Uniform, &mut control);
    assert!(scene.environment_map.is_none() && scene.environment == DVec3::ZERO);
}

/// The furnace with a map: on, the map, lights and a black background are put away (a
/// uniform white environment shown as the background); off, they come back as they were,
/// the map the same Arc (not prefiltered again).
#[test]
fn furnace_round_trips_a_scene_with_a_map() {
    let mut scene = Scene::reference();
    scene.environment_map = Some(Environment {
        rotation_deg: 45.0,
        intensity: 3.0,
        ..Environment::builtin(Builtin::Studio)
    });
    scene.background = Background::Black;
    scene.set_term(IblTerm::Turquin);
    let original = scene.clone();
    let mut saved = None;
    assert!(!edit::is_furnace(&scene));
    edit::set_furnace(&mut scene, true, &mut saved);
    assert!(edit::is_furnace(&scene));
    assert!(scene.environment_map.is_none() && scene.lights.is_empty());
    assert_eq!(scene.environment, DVec3::ONE);
    assert_eq!(scene.background, Background::Environment);
    edit::set_furnace(&mut scene, true, &mut saved);
    assert!(
        saved.as_ref().unwrap().environment_map.is_some(),
        "on twice kept the map"
    );
    edit::set_furnace(&mut scene, false, &mut saved);
    assert_eq!(scene, original);
    assert!(Arc::ptr_eq(
        &scene.environment_map.as_ref().unwrap().map,
        &original.environment_map.as_ref().unwrap().map
    ));
    assert!(saved.is_none());
    // A uniform white environment with a map is not the furnace, nor one with a black
    // background.
    let mut white_map = original.clone();
    white_map.lights.clear();
    white_map.environment = DVec3::ONE;
    white_map.background = Background::Environment;
    assert!(!edit::is_furnace(&white_map));
    white_map.environment_map = None;
    assert!(edit::is_furnace(&white_map));
    white_map.background = Background::Black;
    assert!(!edit::is_furnace(&white_map));
}

/// The blit that stands in for a copy where the window cannot be copied into (GL) gives the
/// window the frame image's exact bytes.
#[test]
fn blit_is_an_exact_copy() {
    use shadeballs::gpu::readback::Readback;
    use shadeballs::viewer::blit::Blit;
    let r = vulkan();
    let (device, queue) = (&r.gpu().device, &r.gpu().queue);
    let format = wgpu::TextureFormat::Bgra8Unorm;
    let (w, h) = (67u32, 45u32);
    let texture = |usage| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: None,
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    };
    let from = texture(wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST);
    let to = texture(wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC);
    // Every byte value, in a pattern that differs per texel and channel.
    let bytes: Vec<u8> = (0..w * h * 4).map(|i| (i * 37 % 256) as u8).collect();
    queue.write_texture(
        from.as_image_copy(),
        &bytes,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(4 * w),
            rows_per_image: Some(h),
        },
        from.size(),
    );
    let mut encoder = device.create_command_encoder(&Default::default());
    let view = to.create_view(&Default::default());
    Blit::new(device, format).encode(device, &mut encoder, &from, &view);
    let readback = Readback::new(device, format, (w, h)).unwrap();
    readback.record(&mut encoder, &to);
    queue.submit([encoder.finish()]);
    assert!(
        readback.read(device).unwrap() == bytes,
        "the blit changed the bytes"
    );
}

/// Truth balls keep accumulating in the window: every frame of an unchanged scene shades
/// the balls again, adding an estimate a pixel (a scene without them shades them once:
/// `idle_draws_nothing_and_only_the_scene_area_orbits`).
#[test]
fn truth_balls_accumulate_while_nothing_changes() {
    let x = Xvfb::start();
    let dir = temp_dir("view-truth");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/models_and_truth.toml");
    let shot = dir.join("truth.png");
    let args = [
        "--frames",
        "12",
        "--scene",
        scene.to_str().unwrap(),
        "--screenshot",
    ];
    let out = viewer(&x, &args).arg(&shot).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let shaded = reported(&stderr, "frames (");
    assert_eq!(
        shaded, 12,
        "balls shaded {shaded} times in 12 frames: {stderr}"
    );
    assert!(shot.exists(), "{stderr}");
}

/// The screenshot's scene area (RGBA8) and its size.
fn scene_pixels(shot: &Path, stderr: &str) -> (Vec<u8>, (u32, u32)) {
    let image = image::open(shot).unwrap().to_rgba8();
    let area = scene_area(stderr);
    (crop(image.as_raw(), image.width(), area), area)
}

/// Pixel `(x, y)` of an RGBA8 image `width` wide.
fn pixel(rgba: &[u8], width: u32, (x, y): (u32, u32)) -> [u8; 4] {
    let i = 4 * (y * width + x) as usize;
    rgba[i..i + 4].try_into().unwrap()
}

/// The wipe: left of the split the headless render of the left side (every term on),
/// right of it the right side's (every term off), at the same pixels; the split line
/// between them. A Vulkan window and the headless render agree exactly
/// (`window_scene_area_equals_the_headless_render`: 0 pixels differ), so every pixel off
/// the line must be equal.
#[test]
fn wipe_shows_each_side_at_its_own_pixels() {
    use shadeballs::viewer::compare::{Compare, Side};
    let x = Xvfb::start();
    let dir = temp_dir("view-wipe");
    let shot = dir.join("wipe.png");
    let args = [
        "--scene",
        HOMEWORK,
        "--no-labels",
        "--compare",
        "on,off",
        "--split",
        "0.4",
        "--frames",
        "3",
        "--backend",
        "vulkan",
        "--screenshot",
    ];
    let out = viewer(&x, &args).arg(&shot).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let (window, (w, h)) = scene_pixels(&shot, &stderr);
    let mut scene = Scene::reference();
    scene.labels = false;
    let on = vulkan()
        .render_ldr(&Side::On.apply(&scene), w, h)
        .unwrap()
        .rgba;
    let off = vulkan()
        .render_ldr(&Side::Off.apply(&scene), w, h)
        .unwrap()
        .rgba;
    assert!(on != off, "the term changes the picture");
    let split = Compare {
        split: 0.4,
        ..Compare::new(Side::On, Side::Off)
    }
    .split_px(w);
    assert_eq!(split, (0.4 * w as f64).round() as u32);
    let mut differ = [0usize; 2];
    for yy in 0..h {
        for xx in 0..w {
            // The line (2 px) and its round handle (6 px radius) lie within 8 px of it.
            if xx.abs_diff(split) <= 8 {
                continue;
            }
            let side = if xx < split { &on } else { &off };
            let k = (xx >= split) as usize;
            differ[k] += (pixel(&window, w, (xx, yy)) != pixel(side, w, (xx, yy))) as usize;
        }
    }
    assert_eq!(
        differ,
        [0, 0],
        "pixels off their side's render (left, right)"
    );
    // The line itself: light grey over the black background, at the top row.
    assert_eq!(pixel(&window, w, (split, 0)), [230, 230, 230, 255]);
}

/// Side by side (issue 39): A whole in the left half of the scene area and B in the right,
/// each equal to the headless render of its side at its half's size outside its labels'
/// rooms and tags; the screenshot's .csv holds every ball's mean on both sides, the term's
/// side brighter on the roughest balls.
#[test]
fn side_by_side_shows_both_charts_whole_with_numbers_a_ball() {
    use shadeballs::viewer::compare::{Compare, Side, View};
    let x = Xvfb::start();
    let dir = temp_dir("view-side-by-side");
    let shot = dir.join("sides.png");
    let args = [
        "--compare",
        "on,off",
        "--side-by-side",
        "--no-labels",
        "--frames",
        "3",
        "--backend",
        "vulkan",
        "--screenshot",
    ];
    let out = viewer(&x, &args).arg(&shot).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let (window, (w, h)) = scene_pixels(&shot, &stderr);
    let mut scene = Scene::showcase();
    scene.labels = false;
    let c = Compare {
        view: View::SideBySide,
        ..Compare::new(Side::On, Side::Off)
    };
    let halves = c.halves(w);
    for ((x0, hw), side) in halves.into_iter().zip([Side::On, Side::Off]) {
        let s = side.apply(&scene);
        // Every ball whole in its half.
        for r in labels::ball_rects(&s, hw, h) {
            let r = r.expect("a ball out of its half");
            assert!(r.x0 > 0.0 && r.x1 < hw as f32, "{side:?}: {r:?} cut");
        }
        let want = vulkan().render_ldr(&s, hw, h).unwrap().rgba;
        let mut differ = 0;
        for yy in 0..h {
            for xx in 0..hw {
                // The divider (2 px) around the right half's first column.
                if (x0 + xx).abs_diff(halves[1].0) <= 1 {
                    continue;
                }
                differ += (pixel(&window, w, (x0 + xx, yy)) != pixel(&want, hw, (xx, yy))) as usize;
            }
        }
        assert_eq!(
            differ, 0,
            "{side:?}'s half ({x0}, {hw} wide): {differ} pixels differ from its headless render"
        );
    }
    let csv = std::fs::read_to_string(shot.with_extension("csv")).expect("the numbers' .csv");
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines[0],
        "ball,x,y,roughness,a,b,mean_a,mean_b,ratio_a_over_b"
    );
    assert_eq!(lines.len(), 11, "{csv}");
    for line in &lines[1..] {
        let cells: Vec<&str> = line.split(',').collect();
        let (a, b, ratio): (f64, f64, f64) = (
            cells[6].parse().unwrap(),
            cells[7].parse().unwrap(),
            cells[8].parse().unwrap(),
        );
        assert!(a > 0.0 && b > 0.0 && (ratio - a / b).abs() < 1e-5, "{line}");
        // The term adds energy: on the roughest balls A (on) is brighter than B (off).
        if cells[3] == "0.95" {
            assert!(ratio > 1.02, "{line}");
        }
    }
    println!("{csv}");
}

/// The difference view: of two identical sides, the ramp's zero colour (black) wherever
/// the colour bar's legend is not, the bar itself the ramp from 1 (top) to 0 (bottom); of
/// the term on against off, the CPU mirror of the shader's pixel applied to the two
/// headless renders.
#[test]
fn difference_view_is_the_scaled_difference_with_a_colour_bar() {
    use shadeballs::viewer::compare::Side;
    use shadeballs::viewer::difference::{colour_bar_rect, colour_bar_row, difference_pixel};
    let x = Xvfb::start();
    let dir = temp_dir("view-difference");
    let base = ["--scene", HOMEWORK, "--no-labels", "--frames", "3"];
    let run = |compare: &str, scale: &str, name: &str| {
        let shot = dir.join(name);
        let out = viewer(&x, &base)
            .args(["--compare", compare, "--difference", scale, "--screenshot"])
            .arg(&shot)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "{stderr}");
        scene_pixels(&shot, &stderr)
    };
    let (same, (w, h)) = run("scene,scene", "16", "same.png");
    // The bar goes where it and its legend meet no ball (the scene's labels are off).
    let mut homework = Scene::reference();
    homework.labels = false;
    let balls: Vec<labels::Rect> = labels::ball_rects(&homework, w, h)
        .into_iter()
        .flatten()
        .collect();
    let (x0, y0, x1, y1) = colour_bar_rect(w, h, &balls);
    // The legend: the bar, its title above it and its numbers left of it (13 px text).
    let legend = |xx: u32, yy: u32| xx + 80 >= x0 && xx < x1 + 8 && yy + 40 >= y0 && yy < y1 + 8;
    let zone = labels::Rect {
        x0: x0.saturating_sub(80) as f32,
        y0: y0.saturating_sub(40) as f32,
        x1: (x1 + 8) as f32,
        y1: (y1 + 8) as f32,
    };
    assert!(
        !balls.iter().any(|b| b.overlaps(&zone)),
        "the colour bar's legend {zone:?} over a ball"
    );
    let mut not_zero = 0;
    for yy in 0..h {
        for xx in 0..w {
            let p = pixel(&same, w, (xx, yy));
            not_zero += (!legend(xx, yy) && p != [0, 0, 0, 255]) as usize;
        }
    }
    assert_eq!(not_zero, 0, "pixels off the zero colour in |a - a|");
    let mid = (x0 + x1) / 2;
    for row in [0, (y1 - y0) / 2, y1 - y0 - 1] {
        let got = pixel(&same, w, (mid, y0 + row));
        let want = colour_bar_row(row, y1 - y0);
        // egui draws the bar's rectangles in its own colour path: 1/255 of rounding.
        for c in 0..3 {
            assert!(
                got[c].abs_diff(want[c]) <= 1,
                "colour bar row {row}: {got:?}, want {want:?}"
            );
        }
    }

    let (diff, _) = run("on,off", "4", "on-off.png");
    let mut scene = Scene::reference();
    scene.labels = false;
    let on = vulkan()
        .render_ldr(&Side::On.apply(&scene), w, h)
        .unwrap()
        .rgba;
    let off = vulkan()
        .render_ldr(&Side::Off.apply(&scene), w, h)
        .unwrap()
        .rgba;
    let (mut far, mut lit) = (0, 0);
    for yy in 0..h {
        for xx in 0..w {
            if legend(xx, yy) {
                continue;
            }
            let want = difference_pixel(pixel(&on, w, (xx, yy)), pixel(&off, w, (xx, yy)), 4);
            let got = pixel(&diff, w, (xx, yy));
            lit += (want != [0, 0, 0, 255]) as usize;
            // The GPU's f32 of a unorm byte and its rounding to a byte: 1/255.
            far += (0..3).any(|c| got[c].abs_diff(want[c]) > 1) as usize;
        }
    }
    println!("difference x4 of on and off: {lit} pixels not zero");
    assert!(lit > 10_000, "the term's difference shows: {lit} pixels");
    assert_eq!(far, 0, "pixels more than 1/255 off the mirror");
}

/// The saved scene file loads back as the very scene saved: the built-in and shipped
/// scenes, and scenes the panel makes (an orbited camera, the light control's direction, the
/// engines' material, a custom metal, a background colour). A scene file cannot hold a
/// uniform radiance and a map at once: that is an error, not a file of another scene.
#[test]
fn saved_scene_text_loads_back_as_the_same_scene() {
    use shadeballs::viewer::save::scene_toml;
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes");
    let mut scenes = vec![Scene::reference(), Scene::showcase(), Scene::furnace()];
    for name in [
        "plastic.toml",
        "metallic_roughness.toml",
        "models_and_truth.toml",
    ] {
        scenes.push(shadeballs::scene::load(&assets.join(name)).unwrap());
    }
    let mut edited = Scene::showcase();
    edited.camera = orbit::orbit(&edited.camera, 0.37, 0.11);
    edited.lights = LightControl {
        azimuth_deg: 33.3,
        elevation_deg: 21.7,
        intensity: 2.5,
    }
    .lights();
    edited.exposure = 0.37;
    edited.ibl_method = shadeballs::environment::IblMethod::Lobe;
    edited.ibl_samples = 7;
    edited.background = Background::Colour(DVec3::new(0.1, 0.2, 0.3));
    edit::set_material(
        &mut edited,
        MaterialChoice::MetallicRoughness {
            base_color: [0.3, 0.6, 0.9],
            metallic: 0.4,
            ior: 1.7,
        }
        .material()
        .unwrap(),
    );
    edited.balls[0].material = MaterialChoice::Custom([0.9, 0.5, 0.1]).material().unwrap();
    edited.balls[1].material = MaterialChoice::Plastic.material().unwrap();
    edited.balls[2].material = MaterialChoice::Rubber.material().unwrap();
    scenes.push(edited);
    for (i, scene) in scenes.iter().enumerate() {
        let text = scene_toml(scene, (640, 360)).unwrap_or_else(|e| panic!("scene {i}: {e}"));
        let back = shadeballs::scene::parse(&text, Path::new("saved.toml"))
            .unwrap_or_else(|e| panic!("scene {i}: {e}\n{text}"));
        // The scene area's size travels as the `size` key (issue 39), not only a comment.
        let sized = Scene {
            size: Some((640, 360)),
            ..scene.clone()
        };
        assert!(back == sized, "scene {i} came back another:\n{text}");
    }
    let mut both = Scene::reference();
    both.environment = DVec3::splat(0.5);
    both.environment_map = Some(Environment::builtin(Builtin::Sky));
    let e = scene_toml(&both, (640, 360)).unwrap_err();
    assert!(e.contains("uniform radiance and a map"), "{e}");
}

/// The viewer's `--save-scene` after an orbit with a map: `shadeballs render` of the file at
/// the scene area's size draws the screenshot's scene area byte for byte (no labels: the
/// viewer sets them with egui, a PNG with ab_glyph; with labels, every pixel outside their
/// rooms), and its EXR equals the viewer's `--screenshot x.exr` value for value.
#[test]
fn saved_scene_renders_the_viewers_picture() {
    let x = Xvfb::start();
    let dir = temp_dir("view-save");
    let run = |labels: &str, name: &str, shot: &str| {
        let (toml, shot) = (dir.join(name), dir.join(shot));
        let args = [
            "--scene",
            HOMEWORK,
            "--environment",
            "studio",
            labels,
            "--frames",
            "4",
            "--orbit",
            "--backend",
            "vulkan",
        ];
        let out = viewer(&x, &args)
            .arg("--save-scene")
            .arg(&toml)
            .arg("--screenshot")
            .arg(&shot)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "{stderr}");
        (toml, shot, stderr)
    };
    // No --width/--height: the saved `size` key gives the scene area's size (issue 39).
    let render = |toml: &Path, _area: (u32, u32), out: &Path| {
        let out = Command::new(env!("CARGO_BIN_EXE_shadeballs"))
            .args(["render", "--backend", "vulkan", "--scene"])
            .arg(toml)
            .arg("--out")
            .arg(out)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    let (toml, shot, stderr) = run("--no-labels", "bare.toml", "bare.png");
    let (window, area) = scene_pixels(&shot, &stderr);
    let rendered = dir.join("bare-render.png");
    render(&toml, area, &rendered);
    let rendered = image::open(&rendered).unwrap().to_rgba8();
    assert_eq!(
        rendered.dimensions(),
        area,
        "render drew another size than `size`"
    );
    let rendered = rendered.into_raw();
    assert!(
        rendered == window,
        "render of the saved scene differs: {}",
        { compare(&window, &rendered, area.0).report("saved scene") }
    );
    // `view` of the saved scene opens a window of that scene area beside the panel.
    let again = dir.join("again.png");
    let out = viewer(&x, &["--scene", toml.to_str().unwrap(), "--frames", "1"])
        .arg("--screenshot")
        .arg(&again)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{stderr}");
    assert_eq!(scene_pixels(&again, &stderr).1, area, "{stderr}");

    let (_, exr, stderr) = run("--no-labels", "bare2.toml", "bare.exr");
    assert!(stderr.contains("linear radiance"), "{stderr}");
    let rendered = dir.join("bare-render.exr");
    render(&toml, area, &rendered);
    let a = image::open(&exr).unwrap().to_rgba32f();
    let b = image::open(&rendered).unwrap().to_rgba32f();
    assert_eq!(a.dimensions(), area);
    assert!(
        a.as_raw() == b.as_raw(),
        "the viewer's EXR differs from render's"
    );

    let (toml, shot, stderr) = run("--labels", "labelled.toml", "labelled.png");
    let (window, area) = scene_pixels(&shot, &stderr);
    let rendered = dir.join("labelled-render.png");
    render(&toml, area, &rendered);
    let rendered = image::open(&rendered).unwrap().to_rgba8().into_raw();
    let scene = shadeballs::scene::load(&toml).unwrap();
    assert!(scene.labels);
    let layout = labels::layout(&scene, area.0, area.1);
    let (mut outside, mut differ) = (0, 0);
    for (i, (a, b)) in window
        .chunks_exact(4)
        .zip(rendered.chunks_exact(4))
        .enumerate()
    {
        let (px, py) = ((i as u32 % area.0) as f32, (i as u32 / area.0) as f32);
        let in_room = layout.iter().any(|l| {
            let r = &l.room;
            px + 1.0 > r.x0 && px < r.x1 && py + 1.0 > r.y0 && py < r.y1
        });
        if !in_room {
            outside += 1;
            differ += (a != b) as usize;
        }
    }
    println!("labelled: {differ} of {outside} pixels outside the labels' rooms differ");
    assert_eq!(differ, 0, "render of the saved labelled scene");
}

/// `view --help` offers the viewer's backends alone; `render --help` still all of them.
#[test]
fn view_help_lists_only_the_viewers_backends() {
    let help = |sub: &str| {
        let out = Command::new(env!("CARGO_BIN_EXE_shadeballs"))
            .args([sub, "--help"])
            .output()
            .unwrap();
        assert!(out.status.success());
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let view = help("view");
    assert!(
        view.contains("[default: auto] [possible values: auto, vulkan, gl]"),
        "{view}"
    );
    for other in ["cpu", "montecarlo"] {
        assert!(!view.contains(&format!(", {other}")), "{other} in: {view}");
    }
    for flag in ["--compare <A,B>", "--split", "--difference", "--save-scene"] {
        assert!(view.contains(flag), "{flag} missing: {view}");
    }
    assert!(help("render").contains("cpu"));
    let out = Command::new(env!("CARGO_BIN_EXE_shadeballs"))
        .args(["view", "--backend", "cpu"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains("vulkan"),
        "{stderr}"
    );
}

/// The comparison's sides edit the models alone, the split's column is rounded and
/// clamped, and `--compare`'s value is two names.
#[test]
fn comparison_sides_and_split() {
    use shadeballs::scene::Model;
    use shadeballs::viewer::compare::{parse_sides, Compare, Side};
    let scene = shadeballs::scene::load(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/models_and_truth.toml"),
    )
    .unwrap();
    assert!(scene.balls.iter().any(|b| b.model == Model::Truth));
    assert_eq!(Side::Scene.apply(&scene), scene);
    for (side, model) in [
        (Side::Off, Model::None),
        (Side::Turquin, Model::Turquin),
        (Side::On, Model::from_term(scene.term())),
    ] {
        let s = side.apply(&scene);
        for (a, b) in s.balls.iter().zip(&scene.balls) {
            let want = if b.model == Model::Truth {
                Model::Truth
            } else {
                model
            };
            assert_eq!(a.model, want, "{side}");
            assert_eq!((a.center, a.material), (b.center, b.material));
        }
        assert_eq!(s.lights, scene.lights);
    }
    assert!(Side::Truth
        .apply(&scene)
        .balls
        .iter()
        .all(|b| b.model == Model::Truth));
    let mut c = Compare::new(Side::On, Side::Off);
    assert_eq!(c.split_px(981), 491);
    c.split = 7.0;
    assert_eq!(c.split_px(980), 980);
    c.split = f64::NAN;
    assert_eq!(c.split_px(980), 490);
    assert_eq!(Compare::split_at(-5.0, 980), 0.0);
    assert_eq!(parse_sides(" on , truth"), Ok((Side::On, Side::Truth)));
    for bad in ["on", "on,", "on,gold", ""] {
        let e = parse_sides(bad).unwrap_err();
        assert!(e.contains("scene, on, off"), "{bad}: {e}");
    }
}

/// `shaders/difference.wgsl` parses and validates, and its ramp's CPU mirror starts at
/// black and ends at its last stop.
#[test]
fn difference_shader_validates_and_its_ramp_spans_black_to_pale_yellow() {
    use shadeballs::viewer::difference::{difference_colour, difference_pixel};
    let source = include_str!("../../shaders/difference.wgsl");
    let module = naga::front::wgsl::parse_str(source).unwrap();
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .unwrap();
    assert!(source.contains("fn difference_colour("));
    assert_eq!(difference_colour(-1.0), [0.0; 3]);
    assert_eq!(difference_colour(0.0), [0.0; 3]);
    assert_eq!(difference_colour(5.0), [1.0, 1.0, 0.75]);
    assert_eq!(
        difference_pixel([9, 9, 9, 255], [9, 9, 9, 255], 64),
        [0, 0, 0, 255]
    );
    assert_eq!(
        difference_pixel([255, 0, 0, 255], [0, 0, 0, 255], 1),
        [255, 255, 191, 255]
    );
}

/// Esc with a menu open (the preset's list, clicked open) closes the menu, not the viewer;
/// the next Esc quits.
#[test]
fn escape_closes_an_open_menu_first() {
    let x = Xvfb::start();
    let dir = temp_dir("view-escape");
    let child = viewer(&x, &["--scene", HOMEWORK])
        .current_dir(&dir)
        .spawn()
        .unwrap();
    let pid = child.id();
    let state = || {
        let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
        stat.rfind(')').and_then(|i| stat[i + 2..].chars().next())
    };
    let mut alive_after_escape = None;
    drive(&x, child, |id| {
        std::thread::sleep(Duration::from_millis(500));
        // The preset's combo box (the homework scene's panel, 1280x720 at DPI 1).
        x.xdotool(&["mousemove", "--window", id, "1040", "147", "click", "1"]);
        std::thread::sleep(Duration::from_millis(500));
        x.xdotool(&["windowfocus", "--sync", id, "key", "Escape"]);
        std::thread::sleep(Duration::from_millis(700));
        alive_after_escape = Some(!matches!(state(), None | Some('Z')));
    });
    assert_eq!(alive_after_escape, Some(true), "Esc with a menu open quit");
}

/// After an orbit that squeezes the columns together, every label the viewer draws is still
/// set at a readable size: the light text's height in each label's room (measured in the
/// screenshot, the rooms from the layout of the scene the viewer saved) is at least the
/// readable fraction of the layout's size times the text's ink height at its size.
#[test]
fn labels_keep_a_readable_size_after_an_orbit() {
    let x = Xvfb::start();
    let dir = temp_dir("view-label-size");
    let (shot, toml) = (dir.join("orbit.png"), dir.join("orbit.toml"));
    let args = [
        "--scene",
        HOMEWORK,
        "--frames",
        "50",
        "--orbit",
        "--screenshot",
    ];
    let out = viewer(&x, &args)
        .arg(&shot)
        .arg("--save-scene")
        .arg(&toml)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let (window, (w, h)) = scene_pixels(&shot, &stderr);
    let scene = shadeballs::scene::load(&toml).unwrap();
    let layout = labels::layout(&scene, w, h);
    let mut heights = Vec::new();
    for l in layout.iter() {
        let r = &l.room;
        // The text is grey 245 over a dark outline: its pixels are the near-white ones.
        let rows: Vec<u32> = (r.y0.max(0.0) as u32..(r.y1.ceil() as u32).min(h))
            .filter(|&y| {
                (r.x0.max(0.0) as u32..(r.x1.ceil() as u32).min(w))
                    .any(|x| pixel(&window, w, (x, y))[..3].iter().all(|&c| c >= 200))
            })
            .collect();
        if let (Some(top), Some(bottom)) = (rows.first(), rows.last()) {
            heights.push((l.text.clone(), bottom - top + 1, l.size_px));
        }
    }
    println!("after the orbit, label ink heights (text, px, layout size): {heights:?}");
    assert!(!heights.is_empty(), "no label drawn after the orbit");
    for (text, ink, size) in &heights {
        // Ubuntu Light's digits and capitals stand about 0.7 of the font size (0.69 at 16
        // px measured here before the orbit); a label at the readable floor stands
        // 0.7 * 0.75 of the layout's size, one at 8 px in a 720 px window 0.35 of it.
        assert!(
            *ink as f32 >= 0.7 * readable_px(*size) - 1.0,
            "{text:?} is {ink} px tall (layout size {size} px)"
        );
    }
}

/// The panel's map file field (and a file dropped on the window) loads a map as the
/// picker's file choice, keeping the latest map's rotation and intensity; a second file
/// replaces it; a missing file, or the furnace on, is an error that changes nothing.
#[test]
fn a_map_file_loads_from_the_panel() {
    let dir = temp_dir("view-map-file");
    let (sky, studio) = (dir.join("sky.hdr"), dir.join("studio.exr"));
    shadeballs::environment::save(&Builtin::Sky.generate(32), &sky).unwrap();
    shadeballs::environment::save(&Builtin::Studio.generate(32), &studio).unwrap();
    let mut scene = Scene::reference();
    let mut control = EnvironmentControl::of(&scene);
    edit::set_environment(
        &mut scene,
        EnvironmentChoice::Builtin(Builtin::White),
        &mut control,
    );
    edit::set_map_rotation(&mut scene, 40.0);
    edit::load_map_file(&mut scene, &sky, &mut control).unwrap();
    let e = scene.environment_map.clone().unwrap();
    assert_eq!(e.source, Source::File(sky.clone()));
    assert_eq!((e.rotation_deg, e.intensity), (40.0, 1.0));
    assert_eq!(EnvironmentChoice::of(&scene), EnvironmentChoice::File);
    assert_eq!(control.choices().last(), Some(&EnvironmentChoice::File));
    assert_eq!(
        *e.map,
        Environment::from_file(&sky).unwrap().map.as_ref().clone()
    );
    edit::load_map_file(&mut scene, &studio, &mut control).unwrap();
    let e2 = scene.environment_map.clone().unwrap();
    assert_eq!(e2.source, Source::File(studio.clone()));
    assert_eq!(e2.rotation_deg, 40.0);
    assert!(!Arc::ptr_eq(&e.map, &e2.map));
    let before = scene.clone();
    let err = edit::load_map_file(&mut scene, &dir.join("missing.hdr"), &mut control);
    assert!(err.unwrap_err().to_string().contains("missing.hdr"));
    assert_eq!(scene, before);
    let mut furnace = Scene::furnace();
    let mut control = EnvironmentControl::of(&furnace);
    let err = edit::load_map_file(&mut furnace, &sky, &mut control);
    assert!(err.unwrap_err().to_string().contains("furnace"));
    assert!(furnace.environment_map.is_none());
}

/// In a window: a map file typed into the panel's field and entered lights the balls; the
/// screenshot's scene area is the headless render of the scene with that map.
#[test]
fn a_map_file_typed_into_the_panel_lights_the_window() {
    let x = Xvfb::start();
    let dir = temp_dir("view-map-typed");
    let map = dir.join("sky.hdr");
    shadeballs::environment::save(&Builtin::Sky.generate(64), &map).unwrap();
    let child = viewer(&x, &["--scene", HOMEWORK])
        .current_dir(&dir)
        .spawn()
        .unwrap();
    let stderr = drive(&x, child, |id| {
        std::thread::sleep(Duration::from_millis(500));
        // The map file field (the homework scene's panel, 1280x720 at DPI 1: below the
        // background's combo box).
        x.xdotool(&[
            "windowfocus",
            "--sync",
            id,
            "mousemove",
            "--window",
            id,
            "1118",
            "672",
            "click",
            "1",
        ]);
        std::thread::sleep(Duration::from_millis(300));
        x.xdotool(&["type", "--delay", "5", map.to_str().unwrap()]);
        x.xdotool(&["key", "Return"]);
        std::thread::sleep(Duration::from_millis(1500));
        // A click lower in the panel (the Compare header: it only opens) takes the
        // keyboard from the field, if it kept it.
        x.xdotool(&["mousemove", "--window", id, "1200", "712", "click", "1"]);
        std::thread::sleep(Duration::from_millis(300));
        x.xdotool(&["windowfocus", "--sync", id, "key", "s"]);
        let start = Instant::now();
        while pngs(&dir).is_empty() && start.elapsed() < Duration::from_secs(30) {
            std::thread::sleep(Duration::from_millis(100));
        }
    });
    let shots = pngs(&dir);
    assert_eq!(shots.len(), 1, "{shots:?}: {stderr}");
    let mut scene = Scene::reference();
    scene.environment_map = Some(Environment::from_file(&map).unwrap());
    scene.environment = DVec3::ZERO;
    assert_scene_matches(&shots[0], &stderr, &scene, "map typed into the panel");
}

/// A comparison keeps the idle behaviour (nothing drawn while nothing happens: both sides
/// shaded once), and a drag that starts on the split line moves the split to where it ends
/// instead of orbiting.
#[test]
fn a_comparison_idles_and_its_split_follows_a_drag() {
    let x = Xvfb::start();
    let dir = temp_dir("view-compare-drag");
    let args = ["--scene", HOMEWORK, "--no-labels", "--compare", "on,off"];
    let child = viewer(&x, &args).current_dir(&dir).spawn().unwrap();
    let stderr = drive(&x, child, |id| {
        // Idle for 1.5 s: at 5-60 frames a second, continuous redrawing would show.
        std::thread::sleep(Duration::from_millis(1500));
        // The split starts at 0.5 of the 980 px scene area: column 490.
        x.xdotool(&["mousemove", "--window", id, "491", "100", "mousedown", "1"]);
        x.xdotool(&["mousemove", "--window", id, "400", "100"]);
        x.xdotool(&["mousemove", "--window", id, "300", "100", "mouseup", "1"]);
        std::thread::sleep(Duration::from_millis(500));
        x.xdotool(&["windowfocus", "--sync", id, "key", "s"]);
        let start = Instant::now();
        while pngs(&dir).is_empty() && start.elapsed() < Duration::from_secs(30) {
            std::thread::sleep(Duration::from_millis(100));
        }
    });
    let frames = reported(&stderr, "viewed ");
    let shaded = reported(&stderr, "frames (");
    println!("compare: idle, drag and S: {frames} frames, the balls shaded {shaded} times");
    // As `idle_draws_nothing_and_only_the_scene_area_orbits`: the first frame, the drag's
    // two or three and egui's follow-ups, well under 1.5 s of continuous drawing.
    assert!(frames <= 30, "{frames} frames: {stderr}");
    assert!((2..=4).contains(&shaded), "shaded {shaded} times: {stderr}");
    let shots = pngs(&dir);
    assert_eq!(shots.len(), 1, "{stderr}");
    let (window, (w, _)) = scene_pixels(&shots[0], &stderr);
    let line = [230, 230, 230, 255];
    assert_eq!(pixel(&window, w, (300, 0)), line, "the split moved to 300");
    assert_ne!(pixel(&window, w, (490, 0)), line, "the split left 490");
    // The camera did not orbit: left of the split is the `on` render's top-left pixel.
    let mut scene = Scene::reference();
    scene.labels = false;
    let on = vulkan()
        .render_ldr(&shadeballs::viewer::compare::Side::On.apply(&scene), w, 720)
        .unwrap()
        .rgba;
    assert_eq!(
        &window[..4 * 250],
        &on[..4 * 250],
        "the first row's left part"
    );
}

/// `view --ibl-method lobe`: every frame of an unchanged scene shades the balls again and
/// adds `--ibl-samples` samples a pixel (the report's count grows with the frames; the
/// first frame may be drawn before the panel settles the scene area, which starts the
/// count again), an orbit restarts it every frame (one frame's samples), and the picture
/// differs from the split sum's.
#[test]
fn lobe_converges_while_nothing_moves_and_restarts_after_an_orbit() {
    let x = Xvfb::start();
    let dir = temp_dir("view-lobe");
    let run = |method: &str, extra: &[&str]| {
        let shot = dir.join(format!("lobe-{method}-{}.png", extra.len()));
        let mut args = vec!["--environment", "sky", "--ibl-method", method];
        args.extend(["--ibl-samples", "4", "--frames", "6"]);
        args.extend(["--width", "640", "--height", "360"]);
        args.extend(extra);
        args.push("--screenshot");
        let out = viewer(&x, &args).arg(&shot).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "{stderr}");
        (stderr, shot)
    };
    let (still, still_shot) = run("lobe", &[]);
    assert_eq!(reported(&still, "frames ("), 6, "{still}");
    let n = reported(&still, "lobe: ");
    // 6 frames of 4, or 5 where the first frame's scene area differed.
    assert!(
        (20..=24).contains(&n),
        "{n} samples after 6 frames: {still}"
    );
    let (orbit, _) = run("lobe", &["--orbit"]);
    assert_eq!(reported(&orbit, "lobe: "), 4, "{orbit}");
    let (split, split_shot) = run("split-sum", &[]);
    assert!(!split.contains("lobe: "), "{split}");
    let (lobe_pixels, _) = scene_pixels(&still_shot, &still);
    let (split_pixels, _) = scene_pixels(&split_shot, &split);
    assert_ne!(
        lobe_pixels, split_pixels,
        "the lobe's picture is the split sum's"
    );
}

/// The lobe's image stops converging at the viewer's cap (4096 samples a pixel, 16 frames
/// of 256) and the viewer then goes idle, as without the lobe
/// (`idle_draws_nothing_and_only_the_scene_area_orbits`).
#[test]
fn lobe_stops_at_its_cap_and_the_viewer_goes_idle() {
    let x = Xvfb::start();
    let dir = temp_dir("view-lobe-cap");
    let args = [
        "--environment",
        "sky",
        "--ibl-method",
        "lobe",
        "--ibl-samples",
        "256",
        "--width",
        "480",
        "--height",
        "136",
    ];
    let child = viewer(&x, &args).current_dir(&dir).spawn().unwrap();
    let pid = child.id();
    let stderr = drive(&x, child, |_| {
        // 16 frames of a 185x136 scene area at 256 samples of each strategy (the lobe
        // mode's multiple importance sampling, issue 37): at 185x270 a frame took 2.5 to
        // 4.4 s on lavapipe (2 loaded cores), half that here, about 20 to 35 s to the cap;
        // then idle, which the wait sees as the process's CPU time standing still.
        until_idle(pid, Duration::from_secs(240));
    });
    assert_eq!(reported(&stderr, "lobe: "), 4096, "{stderr}");
    let frames = reported(&stderr, "viewed ");
    let shaded = reported(&stderr, "frames (");
    println!("lobe to its cap, then idle: {frames} frames, the balls shaded {shaded} times");
    // 16 frames to the cap (17 where the first frame's scene area differed), one more for
    // the panel's final count, and egui's few follow-ups: far under 15 s of redrawing.
    assert!(
        (16..=17).contains(&shaded),
        "balls shaded {shaded} times: {stderr}"
    );
    assert!(frames <= 30, "{frames} frames: {stderr}");
}
