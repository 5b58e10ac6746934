//! The viewer in a real window: Xvfb (a virtual X server), the binary, and xdotool to send
//! keys, a resize and an unmap/map (what a window manager does on minimise) through the
//! window system. The window's scene area must equal the headless render of the same scene.
//! Also the viewer's pure scene edits (no window).

use std::path::Path;

use std::process::{Child, Command, Output, Stdio};

use std::time::{Duration, Instant};

use glam::DVec3;

use shadeballs::environment::{Builtin, Environment};

use shadeballs::labels;

use shadeballs::scene::Scene;

use shadeballs::viewer::edit;

use shadeballs::viewer::labels::readable_px;

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
/// the scene area (an image a label, drawn by egui) in the rooms of `labels::layout`: each
/// room must differ from the bare render (the labels are there), and the comparison covers
/// every pixel outside the rooms (which the layout keeps off the balls).
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
        // Every label that fits its room (at the PNG font's width, which the viewer's label
        // images are set at) at a readable size is drawn; one that does not is left out.
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

/// A comparison's truth side on GL is what a truth scene on GL is: drawn without the truth
/// balls, with one warning (before, the second renderer, on a host's device, trusted
/// WebGPU's guarantees and failed on a wgpu validation error); a clear-coated truth ball
/// under a light is refused in one line (the coat's walk has no next-event estimation:
/// before, it was drawn without its light).
#[test]
fn truth_the_gpu_cannot_walk_is_said_once() {
    let x = Xvfb::start();
    let dir = temp_dir("view-refused");
    let shot = dir.join("truth-gl.png");
    let args = [
        "--backend",
        "gl",
        "--compare",
        "on,truth",
        "--frames",
        "2",
        "--screenshot",
    ];
    let out = viewer(&x, &args).arg(&shot).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert_eq!(
        stderr.matches("cannot render to Rgba32Float").count(),
        1,
        "{stderr}"
    );
    assert!(!stderr.contains("GPU error") && shot.exists(), "{stderr}");

    let scene = dir.join("coated_truth.toml");
    std::fs::write(
        &scene,
        "[[light]]\ndirection = [0.4, 0.5, 1]\nradiance = [3, 3, 3]\n\n[[ball]]\n\
         position = [0, 0, 0]\nradius = 35\nroughness = 0.6\nmodel = \"truth\"\n\
         material = { base_color = [0.8, 0.1, 0.08], metallic = 0, clearcoat = 1.0 }\n",
    )
    .unwrap();
    let shot = dir.join("coated.png");
    let args = [
        "--scene",
        scene.to_str().unwrap(),
        "--frames",
        "2",
        "--screenshot",
    ];
    let out = viewer(&x, &args).arg(&shot).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "drew: {stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error")).collect();
    assert!(
        errors.len() == 1 && errors[0].contains("clear-coated"),
        "{stderr}"
    );
    assert!(!shot.exists(), "wrote a screenshot: {stderr}");
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

/// The viewer's `--save-scene` after an orbit with a map: `shadeballs render` of the file at
/// the scene area's size draws the screenshot's scene area byte for byte (no labels: the
/// viewer blends each label's image on the GPU, a PNG on the CPU; with labels, every pixel
/// outside their rooms), and its EXR equals the viewer's `--screenshot x.exr` value for
/// value.
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

/// Esc with a menu open (the preset's list, clicked open) closes the menu, not the viewer;
/// so does Esc pressed right after the click, before a frame has opened the menu (on a slow
/// frame both wait for the same one: a clean-clone CI once saw the viewer quit there, its
/// frames taking 1.5 s; the test holds both by stopping the viewer); the next Esc quits.
#[test]
fn escape_closes_an_open_menu_first() {
    let x = Xvfb::start();
    let dir = temp_dir("view-escape");
    let child = viewer(&x, &["--scene", HOMEWORK])
        .current_dir(&dir)
        .spawn()
        .unwrap();
    let pid = child.id();
    let alive = || {
        let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
        let state = stat.rfind(')').and_then(|i| stat[i + 2..].chars().next());
        !matches!(state, None | Some('Z'))
    };
    let (mut alive_with_menu_open, mut alive_before_a_frame) = (None, None);
    // The preset's combo box (the homework scene's panel, 1280x720 at DPI 1).
    let combo = ["mousemove", "--window", "", "1040", "147", "click", "1"];
    drive(&x, child, |id| {
        let mut combo = combo;
        combo[2] = id;
        // A click before the panel is laid out misses it: wait for the first frames to be
        // drawn (the viewer idle), however slow they are (a fixed 2.5 s was once enough).
        until_idle(pid, Duration::from_secs(60));
        x.xdotool(&combo);
        // The menu drawn open.
        until_idle(pid, Duration::from_secs(60));
        x.xdotool(&["windowfocus", "--sync", id, "key", "Escape"]);
        std::thread::sleep(Duration::from_millis(1500));
        alive_with_menu_open = Some(alive());
        // The click and the key wait for the same frame: the viewer is stopped while both
        // are sent (as a slow frame would hold them), then goes on.
        let signal = |name: &str| {
            let status = Command::new("kill")
                .args([name, &pid.to_string()])
                .status()
                .unwrap();
            assert!(status.success(), "kill {name} {pid}");
        };
        signal("-STOP");
        x.xdotool(&[&combo[..], &["key", "Escape"]].concat());
        signal("-CONT");
        std::thread::sleep(Duration::from_millis(1500));
        alive_before_a_frame = Some(alive());
        // A click on the scene area closes a menu left open; then drive's Esc quits.
        x.xdotool(&["mousemove", "--window", id, "300", "300", "click", "1"]);
        std::thread::sleep(Duration::from_millis(1500));
    });
    assert_eq!(
        alive_with_menu_open,
        Some(true),
        "Esc with a menu open quit"
    );
    assert_eq!(
        alive_before_a_frame,
        Some(true),
        "Esc right after a click on the menu quit"
    );
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
    let pid = child.id();
    let stderr = drive(&x, child, |id| {
        // The panel's first frames take a second or two on a slow 2-core machine: a click
        // before the field is laid out misses it, and the path typed after it goes to the
        // window as key presses ('s' takes a screenshot). So the click waits for the first
        // frames to be drawn (the viewer idle), however slow they are.
        until_idle(pid, Duration::from_secs(60));
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
        "68",
    ];
    let child = viewer(&x, &args).current_dir(&dir).spawn().unwrap();
    let pid = child.id();
    let stderr = drive(&x, child, |_| {
        // 16 frames of a 185x68 scene area at 256 samples of each strategy (the lobe
        // mode's multiple importance sampling, issue 37): at 185x270 a frame took 2.5 to
        // 4.4 s on lavapipe (2 loaded cores), a quarter of that here; the test took 27 s
        // at 185x136. Then idle, which the wait sees as the process's CPU time standing
        // still.
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
