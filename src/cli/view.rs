//! `shadeballs view`: the interactive viewer (the [`crate::viewer`] front end).

use super::args::ViewArgs;
use super::guard;
use crate::output::{self, image_kind};
use crate::viewer::compare::{Compare, View};

pub(crate) fn run(args: ViewArgs) -> anyhow::Result<()> {
    if let Some(path) = &args.screenshot {
        output::check_output_path(path)?;
        image_kind(path)?;
    }
    if let Some(path) = &args.save_scene {
        output::check_output_path(path)?;
        if output::extension(path) != "toml" {
            anyhow::bail!("--save-scene '{}' must be a .toml", path.display());
        }
    }
    let compare = args.compare.map(|(a, b)| {
        let mut c = Compare::new(a, b);
        c.split = args.split.unwrap_or(c.split);
        if let Some(scale) = args.difference {
            c.view = View::Difference { scale };
        }
        if args.side_by_side {
            c.view = View::SideBySide;
        }
        c
    });
    super::check_wgpu_backend_env(args.backend)?;
    // Issue 38: no output over an input or the other output; their folders writable.
    let outputs = guard::outputs(&[
        ("--screenshot", args.screenshot.as_deref()),
        ("--save-scene", args.save_scene.as_deref()),
    ]);
    guard::refuse_overlaps(&outputs, &guard::scene_inputs(&args.scene, None))?;
    guard::probe_folders(&outputs)?;
    let scene = args.scene.load()?;
    guard::refuse_overlaps(&outputs, &guard::scene_inputs(&args.scene, Some(&scene)))?;
    // The window: the flags, else the scene's `size` as the scene area beside the panel
    // (its points taken at one pixel a point), else 1280 x 720.
    let panel = crate::viewer::PANEL_WIDTH as u32;
    let (width, height) = super::args::picture_size((args.width, args.height), scene.size, panel);
    guard::check_f32_camera(&scene, width, height)?;
    let report = crate::viewer::run(crate::viewer::ViewOptions {
        scene,
        backend: args.backend,
        size: (width, height),
        frames: args.frames,
        screenshot: args.screenshot,
        save_scene: args.save_scene,
        orbit: args.orbit,
        compare,
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
    if let Some(n) = report.lobe_samples {
        let n = crate::stats::count(n, "sample");
        eprintln!("lobe: {n} a pixel at the last frame");
    }
    Ok(())
}
