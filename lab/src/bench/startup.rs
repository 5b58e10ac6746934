//! Startup: process start to the first PNG written, split into device, bake, pipeline,
//! render (draw and readback) and encode (PNG encoding and write).
//!
//! The process row runs `shadeballs render` as a child process, as a user does, and takes
//! only the wall time from spawn to exit (the child's stderr is for people, not parsed
//! here). The in-process rows time each phase with the library's own calls, with a fresh
//! device each time, for the default bake and for the homework's bake (its lut-gen run at
//! startup: the peer row).

use std::path::Path;
use std::process::Command;
use std::time::Instant;

use super::device;
use shadeballs::error::{Error, Result};
use shadeballs::gpu::Renderer;
use shadeballs::lut::{self, BakeConfig};
use shadeballs::output::write_png;
use shadeballs::scene::Scene;

/// Phase names, in order (the names `shadeballs render` reports too).
pub const PHASES: [&str; 5] = ["device", "bake", "pipeline", "render", "encode"];

/// One startup: the total and each phase, in ms.
#[derive(Clone, Debug)]
pub struct Startup {
    pub total_ms: f64,
    pub phases_ms: [f64; 5],
}

/// The homework's scene file (`Scene::reference()`, what the in-process rows draw): the
/// process row renders it too, not `render`'s default showcase, whose environment map
/// adds its prefiltering.
const HOMEWORK_TOML: &str = include_str!("../../../assets/scenes/homework.toml");

/// The same balls under the built-in studio map (`assets/scenes/studio.toml`): the first
/// PNG with a map, whose preparation (mip chain, prefiltering) the homework's lacks.
const STUDIO_TOML: &str = include_str!("../../../assets/scenes/studio.toml");

/// A scene the process rows render: its name and its file's text.
pub type SceneFile = (&'static str, &'static str);

/// The homework scene ([`HOMEWORK_TOML`]).
pub const HOMEWORK_SCENE: SceneFile = ("homework", HOMEWORK_TOML);

/// The studio scene ([`STUDIO_TOML`]).
pub const STUDIO_SCENE: SceneFile = ("studio", STUDIO_TOML);

/// Runs `exe render --scene DIR/NAME.toml --out DIR/startup.png` once: its wall time from
/// spawn to exit, in ms.
pub fn process(exe: &Path, dir: &Path, (name, text): SceneFile) -> Result<f64> {
    let out = dir.join("startup.png");
    let scene = dir.join(format!("{name}.toml"));
    shadeballs::output::write_atomic(&scene, text.as_bytes())?;
    let start = Instant::now();
    let result = Command::new(exe)
        .arg("render")
        .arg("--scene")
        .arg(&scene)
        .arg("--out")
        .arg(&out)
        .output();
    let total_ms = start.elapsed().as_secs_f64() * 1e3;
    // The scene file is the run's own: gone whether or not the child started.
    let _ = std::fs::remove_file(&scene);
    let result = result.map_err(|e| Error::Invalid {
        what: "startup run",
        message: format!("cannot run '{}': {e}", exe.display()),
    })?;
    if result.status.success() && out.exists() {
        Ok(total_ms)
    } else {
        Err(Error::Invalid {
            what: "startup run",
            message: format!(
                "'{} render' failed: {}",
                exe.display(),
                String::from_utf8_lossy(&result.stderr).trim()
            ),
        })
    }
}

/// The same phases in this process: a fresh device, `bake`, the pipeline, one frame of the
/// default scene with readback, and the PNG written to `dir`.
pub fn in_process(bake: &BakeConfig, dir: &Path) -> Result<Startup> {
    let scene = Scene::reference();
    let (w, h) = (1280, 720);
    let start = Instant::now();
    let mut marks = [0.0; 5];
    let mut last = start;
    let mut mark = |k: usize| {
        let now = Instant::now();
        marks[k] = (now - last).as_secs_f64() * 1e3;
        last = now;
    };
    let mut renderer = Renderer::new(device::open()?);
    mark(0);
    renderer.set_tables(std::sync::Arc::new(lut::bake(bake)));
    mark(1);
    renderer.prepare(&scene, wgpu::TextureFormat::Rgba8Unorm);
    mark(2);
    let image = renderer.render_ldr(&scene, w, h)?;
    mark(3);
    write_png(&dir.join("startup-in-process.png"), w, h, image.rgba)?;
    mark(4);
    Ok(Startup {
        total_ms: start.elapsed().as_secs_f64() * 1e3,
        phases_ms: marks,
    })
}

/// Per-column medians of `runs`.
pub fn median(runs: &[Startup]) -> Startup {
    let med =
        |f: &dyn Fn(&Startup) -> f64| super::median(&mut runs.iter().map(f).collect::<Vec<_>>());
    let mut phases_ms = [0.0; 5];
    for (k, p) in phases_ms.iter_mut().enumerate() {
        *p = med(&|s: &Startup| s.phases_ms[k]);
    }
    Startup {
        total_ms: med(&|s: &Startup| s.total_ms),
        phases_ms,
    }
}

/// The startup table: the process (median of `runs` runs of `exe`), and the same phases in
/// this process with the default bake and with the homework's bake (peer). The images go to
/// a scratch folder under the system's temp folder, removed afterwards.
pub fn startup_sweep(exe: &Path, quick: bool) -> Result<super::Sweep> {
    let dir = std::env::temp_dir().join(format!("shadeballs-startup-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|reason| Error::Write {
        path: dir.clone(),
        reason,
    })?;
    let sweep = startup_runs(exe, &dir, quick);
    let _ = std::fs::remove_dir_all(&dir);
    sweep
}

fn startup_runs(exe: &Path, dir: &Path, quick: bool) -> Result<super::Sweep> {
    use super::bake::{homework_config, HOMEWORK};
    use super::table::Table;
    use super::Goal;
    // Process runs (alternating pairs) and in-process runs; the quick run's figures are
    // each of one run, not a median.
    let (runs, in_process_runs) = if quick { (1, 1) } else { (7, 7) };
    let mut columns = vec!["config", "how", "total_ms"];
    columns.extend(PHASES.iter().map(|p| match *p {
        "device" => "device_ms",
        "bake" => "bake_ms",
        "pipeline" => "pipeline_ms",
        "render" => "render_ms",
        _ => "encode_ms",
    }));
    columns.push("bake_share");
    let mut t = Table::new(
        "startup",
        "Startup: process start to the first PNG written (default scene, 1280x720)",
        &columns,
    );
    let row = |label: &str, how: &str, s: &Startup| {
        let mut r = vec![
            label.to_string(),
            how.to_string(),
            format!("{:.1}", s.total_ms),
        ];
        r.extend(s.phases_ms.iter().map(|p| format!("{p:.1}")));
        r.push(format!("{:.1}%", 100.0 * s.phases_ms[1] / s.total_ms));
        r
    };
    // The homework and the studio alternate, so a change of the machine's load falls on
    // both alike.
    let (mut process_runs, mut studio_runs) = (Vec::new(), Vec::new());
    for _ in 0..runs {
        process_runs.push(process(exe, dir, HOMEWORK_SCENE)?);
        studio_runs.push(process(exe, dir, STUDIO_SCENE)?);
    }
    let worst = process_runs.iter().copied().fold(0.0, f64::max);
    let process_ms = super::median(&mut process_runs);
    let studio_ms = super::median(&mut studio_runs);
    let hw = (0..in_process_runs)
        .map(|_| in_process(&homework_config(shadeballs::brdf::Geometry::Schlick), dir))
        .collect::<Result<Vec<_>>>()?;
    t.push(row(HOMEWORK, "in process", &median(&hw)));
    let mut process_row = vec![
        "default".to_string(),
        "process (shadeballs render)".to_string(),
        format!("{process_ms:.1}"),
    ];
    process_row.extend(["-"; 6].map(String::from));
    t.push(process_row);
    let mut studio_row = vec![
        "studio map".to_string(),
        "process (shadeballs render)".to_string(),
        format!("{studio_ms:.1}"),
    ];
    studio_row.extend(["-"; 6].map(String::from));
    t.push(studio_row);
    let ours = median(
        &(0..in_process_runs)
            .map(|_| in_process(&BakeConfig::default(), dir))
            .collect::<Result<Vec<_>>>()?,
    );
    t.push(row("default", "in process", &ours));
    t.note = format!(
        "Medians of {runs} run(s) of each process, {in_process_runs} of each in process. 'process': `shadeballs render` spawned by the bench (the homework's scene file, or the same balls under the studio map, alternating), total = spawn to exit as this process sees it (its slowest run: {worst:.0} ms; a new shader compiles on the first run after a build, Mesa's disk cache serves later runs). 'in process': the phases, timed with the library's calls, with a fresh device per run."
    );
    let goal = Goal {
        what: "startup to the first PNG <= 1 s, the bake a small share".into(),
        figure: format!(
            "{process_ms:.0} ms (bake {:.1} ms, {:.1}% in process)",
            ours.phases_ms[1],
            100.0 * ours.phases_ms[1] / ours.total_ms
        ),
        met: process_ms <= 1000.0 && ours.phases_ms[1] <= 0.1 * ours.total_ms,
    };
    let ratio = studio_ms / process_ms;
    let map_goal = Goal {
        what: "the first PNG with the studio map at most 2x the first PNG without".into(),
        figure: format!("{studio_ms:.0} ms against {process_ms:.0} ms: {ratio:.2}x"),
        met: ratio <= 2.0,
    };
    Ok(super::Sweep {
        tables: vec![t],
        plots: Vec::new(),
        goals: vec![goal, map_goal],
    })
}
