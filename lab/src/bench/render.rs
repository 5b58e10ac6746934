//! Rendering: how a frame at 1280 x 720 is timed on the adapter in use, with the
//! multiple-scattering term compiled in and out (or two scenes alternating), and its
//! image error relative to the CPU reference renderer evaluating the exact model (precise
//! E and E_avg, [`super::exact`]); the sweep itself is `render_sweep.rs`.
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

use super::{device, median};
use shadeballs::error::Result;
use shadeballs::gpu::DrawOptions;
use shadeballs::gpu::{Renderer, Target};
use shadeballs::lut::{self, BakeConfig, TableSet, Tables};
use shadeballs::scene::Scene;
use shadeballs::{cpu, display};

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
            let d =
                (display::tone_map(px[c] as f64, exposure) - display::tone_map(ex, exposure)).abs();
            let d = if d.is_nan() { f64::INFINITY } else { d * 255.0 };
            max = max.max(d);
            sum += d;
        }
    }
    (max, sum / (3 * exact.len().max(1)) as f64)
}

/// The exact model's radiance of `scene` at 1280 x 720 (CPU, f64).
pub fn exact_radiance(scene: &Scene, exact: &TableSet) -> Vec<DVec3> {
    cpu::render_radiance(
        scene,
        &shadeballs::prepared::Prepared::new(scene, exact),
        WIDTH,
        HEIGHT,
    )
}

/// Renders `scene` as `setup` says, the term compiled in and out, frames alternating between
/// the two so that both see the same machine load: (on, off, ratio), each frame with its
/// median time over `repeats` frames and its display error against `exact` radiance; the
/// ratio is the median over rounds of (on / off) of the two frames of a round, which
/// cancels the drift of a shared machine's load better than a ratio of medians.
pub fn measure_pair(
    renderer: &mut Renderer,
    scene: &Scene,
    setup: Setup,
    repeats: usize,
    exact: &[DVec3],
) -> Result<(Frame, Frame, f64)> {
    setup.apply(renderer);
    let (mut times, ratio) = alternate(renderer, [scene, scene], repeats, |r, k| {
        r.set_multiple_scattering_term(k == 0)
    })?;
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

/// How a measured run gets its tables and draws.
#[derive(Clone)]
pub enum Setup {
    /// These tables whatever the plan (`Renderer::set_tables`), drawn with these options.
    Table(Arc<Tables>, DrawOptions),
    /// Planned with this bake config and these options.
    Planned(BakeConfig, DrawOptions),
}

impl Setup {
    pub fn apply(&self, renderer: &mut Renderer) {
        match self {
            Setup::Table(t, o) => {
                renderer.set_draw_options(*o);
                renderer.set_tables(t.clone());
            }
            Setup::Planned(c, o) => {
                renderer.set_draw_options(*o);
                renderer.set_bake_config(*c);
            }
        }
    }
}

const FORMAT: wgpu::TextureFormat = device::FRAME_FORMAT;

/// Frames of `scenes[k]` into the bench's target with the two settings `set(renderer, k)`
/// makes (k = 0, 1) alternating, `repeats` of each after one warm-up frame each (pipeline
/// creation, the driver's shader compile), 0 first in even rounds and 1 first in odd ones:
/// the times (ms) per setting, and the median over rounds of the ratio time 0 / time 1.
pub fn alternate(
    renderer: &mut Renderer,
    scenes: [&Scene; 2],
    repeats: usize,
    mut set: impl FnMut(&mut Renderer, usize),
) -> Result<([Vec<f64>; 2], f64)> {
    let (_texture, view) = device::frame_target(renderer.gpu(), WIDTH, HEIGHT);
    let target = Target {
        view: &view,
        format: FORMAT,
        width: WIDTH,
        height: HEIGHT,
    };
    let mut times = [Vec::new(), Vec::new()];
    for round in 0..=repeats.max(1) {
        let order = if round % 2 == 0 { [0, 1] } else { [1, 0] };
        for k in order {
            set(renderer, k);
            let start = Instant::now();
            renderer.render(scenes[k], target)?;
            device::wait(renderer.gpu())?;
            if round > 0 {
                times[k].push(start.elapsed().as_secs_f64() * 1e3);
            }
        }
    }
    let mut ratios: Vec<f64> = times[0].iter().zip(&times[1]).map(|(a, b)| a / b).collect();
    Ok((times, median(&mut ratios)))
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
        .retain(|b| b.model.has_term() && (b.roughness - 0.55).abs() < 1e-9);
    let centre = scene.balls.first().map_or(DVec3::ZERO, |b| b.center);
    scene.camera.position = centre + DVec3::new(0.0, 0.0, 60.0);
    scene.camera.target = centre;
    scene
}
