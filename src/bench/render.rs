//! Rendering: frame time at 1280 x 720 on the adapter in use, with the multiple-scattering
//! term compiled in and out, per preset and table configuration, against the image error
//! relative to the CPU reference renderer evaluating the exact model (precise E and E_avg,
//! [`super::exact`]).
//!
//! Frame time: the median wall time of encoding, submitting and waiting for one frame into
//! a 1280 x 720 `Rgba8Unorm` texture (no readback), after a warm-up frame, frames with and
//! without the term alternating; wall time, not timestamp queries (a CPU rasteriser's
//! timestamps say nothing a wall clock does not). Image error: the frame rendered to
//! linear radiance (`Rgba32Float`), tone-mapped in f64 like the reference, per channel, in
//! units of 1/255 of the display value.

use std::sync::Arc;
use std::time::Instant;

use glam::DVec3;

use super::device;
use super::exact::exact_tables;
use super::plot::{Plot, Series};
use super::table::Table;
use super::{Goal, Sweep};
use crate::cpu;
use crate::error::Result;
use crate::gpu::{Renderer, Target};
use crate::lut::{self, BakeConfig, Tables};
use crate::scene::Scene;

pub const WIDTH: u32 = 1280;
pub const HEIGHT: u32 = 720;

/// A frame's measured cost and error.
pub struct Frame {
    pub ms: f64,
    /// Largest and mean per-channel display error against the exact model, in 1/255.
    pub max_255: f64,
    pub mean_255: f64,
}

/// Display-value error of `gpu` (linear RGBA f32) against `exact` (linear radiance), in
/// 1/255: (max, mean) over every channel of every pixel.
pub fn display_error(gpu: &[f32], exact: &[DVec3], exposure: f64) -> (f64, f64) {
    let mut max: f64 = 0.0;
    let mut sum = 0.0;
    for (px, e) in gpu.chunks_exact(4).zip(exact) {
        for (c, ex) in [e.x, e.y, e.z].into_iter().enumerate() {
            let d = (cpu::tone_map(px[c] as f64, exposure) - cpu::tone_map(ex, exposure)).abs();
            let d = if d.is_nan() { f64::INFINITY } else { d * 255.0 };
            max = max.max(d);
            sum += d;
        }
    }
    (max, sum / (3 * exact.len().max(1)) as f64)
}

/// The exact model's radiance of `scene` at 1280 x 720 (CPU, f64).
pub fn exact_radiance(scene: &Scene, exact: &Tables) -> Vec<DVec3> {
    cpu::render_radiance(scene, exact, WIDTH, HEIGHT)
}

/// Renders `scene` with `tables`, the term compiled in and out, frames alternating between
/// the two so that both see the same machine load: (on, off, ratio), each frame with its
/// median time over `repeats` frames and its display error against `exact` radiance; the
/// ratio is the median over rounds of (on / off) of the two frames of a round, which
/// cancels the drift of a shared machine's load better than a ratio of medians.
pub fn measure_pair(
    renderer: &mut Renderer,
    scene: &Scene,
    tables: Arc<Tables>,
    repeats: usize,
    exact: &[DVec3],
) -> Result<(Frame, Frame, f64)> {
    renderer.set_tables(tables);
    let format = wgpu::TextureFormat::Rgba8Unorm;
    let texture = renderer
        .gpu()
        .device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("bench frame"),
            size: wgpu::Extent3d {
                width: WIDTH,
                height: HEIGHT,
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
    let target = Target {
        view: &view,
        format,
        width: WIDTH,
        height: HEIGHT,
    };
    let mut times = [Vec::new(), Vec::new()];
    // One warm-up frame each (pipeline creation, the driver's shader compile), then
    // alternate, on first in even rounds and off first in odd ones.
    for round in 0..=repeats.max(1) {
        let order = if round % 2 == 0 { [0, 1] } else { [1, 0] };
        for k in order {
            renderer.set_multiple_scattering_term(k == 0);
            let start = Instant::now();
            renderer.render(scene, target)?;
            device::wait(renderer.gpu())?;
            if round > 0 {
                times[k].push(start.elapsed().as_secs_f64() * 1e3);
            }
        }
    }
    // Pairs first: the medians below sort the times.
    let mut ratios: Vec<f64> = times[0].iter().zip(&times[1]).map(|(a, b)| a / b).collect();
    let ratio = median(&mut ratios);
    let mut frames = Vec::new();
    for (k, term) in [true, false].into_iter().enumerate() {
        renderer.set_multiple_scattering_term(term);
        let hdr = renderer.render_hdr(scene, WIDTH, HEIGHT)?;
        let (max_255, mean_255) = display_error(&hdr.rgba, exact, scene.exposure);
        frames.push(Frame {
            ms: median(&mut times[k]),
            max_255,
            mean_255,
        });
    }
    renderer.set_multiple_scattering_term(true);
    let off = frames.pop().expect("two frames");
    let on = frames.pop().expect("two frames");
    Ok((on, off, ratio))
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

/// Tables for a render configuration: `config` with the scene's geometry.
pub fn tables_for(scene: &Scene, config: BakeConfig) -> Arc<Tables> {
    Arc::new(lut::bake(&BakeConfig {
        geometry: scene.effective_geometry(),
        ..config
    }))
}

/// The default scene's camera moved in until one ball fills most of the frame: the
/// term's cost per shaded pixel, undiluted by background.
pub fn close_up() -> Scene {
    let mut scene = Scene::reference();
    scene
        .balls
        .retain(|b| b.multiple_scattering && (b.roughness - 0.55).abs() < 1e-9);
    let centre = scene.balls.first().map_or(DVec3::ZERO, |b| b.center);
    scene.camera.position = centre + DVec3::new(0.0, 0.0, 60.0);
    scene.camera.target = centre;
    scene
}

/// Frame time with the term on and off per scene, preset and tables, against the image
/// error of each (the homework's preset and bake as the peer row).
pub fn render_sweep(renderer: &mut Renderer, quick: bool) -> Result<Sweep> {
    use super::bake::{homework_config, HOMEWORK};
    use crate::lut::{Layout, LayoutKind};
    use crate::scene::Preset;
    let mut t = Table::new(
        "render",
        "Rendering: frame time at 1280x720 with the term on and off against the image error (exact model on the CPU as reference)",
        &["config", "scene", "preset", "tables", "term", "frame_ms", "on_over_off", "err_max_255", "err_mean_255"],
    );
    let repeats = if quick { 9 } else { 41 };
    let reference = Scene::reference();
    let games202 = Scene {
        preset: Preset::Games202,
        ..Scene::reference()
    };
    let default_tables = BakeConfig::default();
    let mut runs: Vec<(&str, &str, Scene, &str, BakeConfig)> = vec![
        (
            HOMEWORK,
            "default",
            games202.clone(),
            "homework",
            homework_config(crate::brdf::Geometry::Schlick),
        ),
        (
            "default",
            "default",
            reference.clone(),
            "default",
            default_tables,
        ),
        ("-", "default", games202.clone(), "default", default_tables),
    ];
    if !quick {
        let layout = |kind| BakeConfig {
            layout: Layout::of_kind(kind),
            ..BakeConfig::default()
        };
        runs.push((
            "-",
            "default",
            reference.clone(),
            "games202 layout; chebyshev bake",
            layout(LayoutKind::Games202),
        ));
        runs.push((
            "-",
            "default",
            reference.clone(),
            "sqrt-mu 64x64",
            layout(LayoutKind::SqrtMu),
        ));
        runs.push(("-", "close-up", close_up(), "default", default_tables));
    }
    let exact = exact_tables(&reference)?;
    let mut exact_images: Vec<(String, Vec<DVec3>)> = Vec::new();
    let series = |label: &str, peer| Series {
        label: label.into(),
        peer,
        points_only: true,
        ..Default::default()
    };
    let mut on_series = series("term on", false);
    let mut off_series = series("term off", false);
    let mut peer = series("homework (term on)", true);
    let mut goals = Vec::new();
    for (label, scene_name, scene, tables_name, config) in runs {
        let key = format!("{scene_name} {}", scene.preset);
        if !exact_images.iter().any(|(k, _)| *k == key) {
            exact_images.push((key.clone(), exact_radiance(&scene, &exact)));
        }
        let image = &exact_images
            .iter()
            .find(|(k, _)| *k == key)
            .expect("added above")
            .1;
        let tables = tables_for(&scene, config);
        let (on, off, ratio) = measure_pair(renderer, &scene, tables, repeats, image)?;
        for (frame, term) in [(&on, "on"), (&off, "off")] {
            t.push(vec![
                label.to_string(),
                scene_name.to_string(),
                scene.preset.to_string(),
                tables_name.to_string(),
                term.to_string(),
                format!("{:.2}", frame.ms),
                if term == "on" {
                    format!("{ratio:.3}")
                } else {
                    "-".into()
                },
                format!("{:.2}", frame.max_255),
                format!("{:.4}", frame.mean_255),
            ]);
        }
        if label == HOMEWORK {
            peer.points.push((on.ms, on.mean_255));
        } else {
            on_series.points.push((on.ms, on.mean_255));
            off_series.points.push((off.ms, off.mean_255));
        }
        if label == "default" {
            goals.push(Goal {
                what:
                    "term's cost: frame time with the term on <= 1.10x with it off (default scene)"
                        .into(),
                figure: format!(
                    "{:.1} ms on, {:.1} ms off: {ratio:.3}x ({})",
                    on.ms,
                    off.ms,
                    renderer.gpu().describe()
                ),
                met: ratio <= 1.10,
            });
        }
    }
    t.note = format!(
        "{} on {}: median of {repeats} frames each, term on and off alternating; wall time of encode, submit and wait (no readback); on_over_off is the median of the on/off ratio of each pair of frames. Error: the frame in linear radiance, tone-mapped like the reference, per channel, in 1/255 of the display value, against the CPU reference renderer with precise E and E_avg (src/bench/exact.rs). 'term off' compiles the term out of the shader (MS_TERM = 0): its error is what dropping the term costs.",
        if quick { "Quick" } else { "Full" },
        renderer.gpu().describe()
    );
    let plot = Plot {
        title: "Render 1280x720: frame time against image error".into(),
        x_label: "frame time (ms, median)".into(),
        y_label: "mean display error (1/255)".into(),
        series: vec![on_series, off_series, peer],
        goals: Vec::new(),
    };
    Ok(Sweep {
        tables: vec![t],
        plots: vec![("render".into(), plot)],
        goals,
    })
}
