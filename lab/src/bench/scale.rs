//! Scale: what a frame costs as the work grows, on the planned renderer. Frame time against
//! the number of balls at equal covered pixels (n x n charts whose radius shrinks as n
//! grows), against the resolution (the 16 x 16 chart from 640 x 360 to 3840 x 2160), and
//! against the number of lights; and startup (plan, bake and bind the tables, the first
//! frame's upload and draw) against the number of balls and of distinct roughness values.
//!
//! Frame time as in `render.rs`: the median wall time of encoding, submitting and waiting
//! for one frame into an `Rgba8Unorm` target (no readback); the cases a table compares are
//! measured in interleaved rounds ([`interleaved_frame_ms`]). Beside the times, a model of
//! the work a block rasteriser does ([`block_shades`]): lavapipe's frame time follows it.

use std::time::Instant;

use glam::DVec3;

use super::table::Table;
use super::{device, median, Goal, Sweep};
use crate::plot::{Plot, Series, Style};
use shadeballs::error::Result;
use shadeballs::gpu::{Plan, Renderer, Target};
use shadeballs::lut::{BakeConfig, TableSet};
use shadeballs::scene::{Ball, Camera, Light, Material, Model, Scene};

/// Side of the square the chart's ball centres span, in world units.
const CHART_SPAN: f64 = 400.0;
/// Ball radius as a fraction of the grid spacing.
const RADIUS_OF_SPACING: f64 = 0.4;

/// An `n x n` material chart: metal balls, roughness from 0 to 1 along each row (or
/// cycling through `roughness_values` values), F0 from copper to silver down the columns,
/// every ball with the term, `lights` white directional lights. The balls span the same
/// square whatever `n` (radius `0.4 * CHART_SPAN / n`): about 210,000 pixels covered at
/// 1280 x 720 (23 %), the same for every `n` to within the perspective's few per cent.
pub fn chart(n: u32, lights: usize, roughness_values: Option<u32>) -> Scene {
    let n = n.max(1);
    let spacing = CHART_SPAN / n as f64;
    let radius = RADIUS_OF_SPACING * spacing;
    let copper = DVec3::new(0.955, 0.638, 0.538);
    let silver = DVec3::new(0.972, 0.960, 0.915);
    let mut balls = Vec::with_capacity((n * n) as usize);
    for row in 0..n {
        for col in 0..n {
            let roughness = match roughness_values {
                Some(values) => {
                    let values = values.max(1);
                    ((row * n + col) % values) as f64 / (values - 1).max(1) as f64
                }
                None => col as f64 / (n - 1).max(1) as f64,
            };
            let f0 = copper.lerp(silver, row as f64 / (n - 1).max(1) as f64);
            balls.push(Ball {
                center: DVec3::new(
                    (col as f64 + 0.5) * spacing - 0.5 * CHART_SPAN,
                    0.5 * CHART_SPAN - (row as f64 + 0.5) * spacing,
                    0.0,
                ),
                radius,
                roughness,
                material: Material {
                    f0,
                    ..Material::metal_srgb([0.0; 3])
                },
                model: Model::KullaConty,
                label: None,
            });
        }
    }
    let lights = (0..lights.max(1))
        .map(|k| {
            // Directions spread over the camera's hemisphere.
            let a = k as f64 * 2.399_963; // the golden angle
            let z = 1.0 - 0.5 * (k as f64 + 0.5) / lights.max(1) as f64;
            let s = (1.0 - z * z).sqrt();
            Light::new(
                DVec3::new(s * a.cos(), s * a.sin(), z),
                DVec3::splat(1.0 / lights.max(1) as f64),
            )
        })
        .collect();
    Scene {
        balls,
        lights,
        environment: DVec3::ZERO,
        camera: Camera {
            position: DVec3::new(0.0, 0.0, 520.0),
            target: DVec3::ZERO,
            vfov_deg: 50.0,
            min_aspect: None,
        },
        ..Scene::reference()
    }
}

/// Grid sides of the ball-count series: 1 to 4,096 balls.
const SIDES: [u32; 6] = [1, 4, 8, 16, 32, 64];
const RESOLUTIONS: [(u32, u32); 5] = [
    (640, 360),
    (1280, 720),
    (1920, 1080),
    (2560, 1440),
    (3840, 2160),
];
const LIGHTS: [usize; 5] = [1, 2, 4, 8, 16];

const FORMAT: wgpu::TextureFormat = device::FRAME_FORMAT;

/// One frame of `scene` at `w x h`, waited for: its wall time in ms.
fn frame(
    renderer: &mut Renderer,
    scene: &Scene,
    view: &wgpu::TextureView,
    w: u32,
    h: u32,
) -> Result<f64> {
    let start = Instant::now();
    renderer.render(
        scene,
        Target {
            view,
            format: FORMAT,
            width: w,
            height: h,
        },
    )?;
    device::wait(renderer.gpu())?;
    Ok(start.elapsed().as_secs_f64() * 1e3)
}

/// Frames of each compared case to a round in [`interleaved_frame_ms`], after its warm-up.
pub const FRAMES_A_ROUND: usize = 3;

/// Median frame time (ms) of each `(scene, w, h)` case, measured in rounds that visit
/// every case in turn (one untimed frame, which absorbs a table bind or a depth target
/// made again for the size, then [`FRAMES_A_ROUND`] timed ones), about `repeats` timed
/// frames each: the machine's drift over a sweep falls on every case alike, so the ratios
/// between cases hold where one case after another would not.
pub fn interleaved_frame_ms(
    renderer: &mut Renderer,
    cases: &[(Scene, u32, u32)],
    repeats: usize,
) -> Result<Vec<f64>> {
    let targets: Vec<_> = cases
        .iter()
        .map(|(_, w, h)| device::frame_target(renderer.gpu(), *w, *h))
        .collect();
    let rounds = repeats.max(1).div_ceil(FRAMES_A_ROUND);
    let mut times = vec![Vec::with_capacity(rounds * FRAMES_A_ROUND); cases.len()];
    for _ in 0..rounds {
        for (((scene, w, h), (_texture, view)), times) in cases.iter().zip(&targets).zip(&mut times)
        {
            frame(renderer, scene, view, *w, *h)?;
            for _ in 0..FRAMES_A_ROUND {
                times.push(frame(renderer, scene, view, *w, *h)?);
            }
        }
    }
    Ok(times.iter_mut().map(|t| median(t)).collect())
}

/// The pixels `scene` covers at `w x h`: those whose primary ray hits a ball, tried over
/// each ball's screen-space bounds only.
pub fn covered_pixels(scene: &Scene, w: u32, h: u32) -> usize {
    let basis = scene.camera.basis(w, h);
    let mut hit = vec![false; (w * h) as usize];
    for b in &scene.balls {
        let Some([x0, y0, x1, y1]) = basis.sphere_bounds(b.center, b.radius, w, h, 1.0) else {
            continue;
        };
        let px = |v: f64, n: u32| ((v + 1.0) * 0.5 * n as f64).clamp(0.0, n as f64) as u32;
        let (c0, c1) = (px(x0, w), px(x1, w).saturating_add(1).min(w));
        let (r0, r1) = (
            h - px(y1, h).min(h),
            (h - px(y0, h)).saturating_add(1).min(h),
        );
        for py in r0..r1 {
            for px in c0..c1 {
                let d = basis.ray(px, py, w, h);
                if shadeballs::cpu::intersect_sphere(basis.origin, d, b.center, b.radius) > 0.0 {
                    hit[(py * w + px) as usize] = true;
                }
            }
        }
    }
    hit.iter().filter(|&&c| c).count()
}

/// Side of the pixel blocks lavapipe (llvmpipe) runs the fragment shader over: every pixel
/// of a 4 x 4 block a primitive touches, once per primitive.
pub const LAVAPIPE_BLOCK_PX: u32 = 4;

/// Side of the pixel quads a hardware GPU shades together (2 x 2, for derivatives).
pub const GPU_QUAD_PX: u32 = 2;

/// Fragment work of `scene` at `w x h` on a rasteriser that shades `block x block` pixels
/// together: the shades of the per-ball quads as the renderer draws them (the padded
/// bounds, two triangles split along the diagonal from bottom right to top left; a
/// triangle shades each block holding a pixel centre on its side, the diagonal's on both),
/// and the least any draw of one primitive set per ball can shade: the blocks that hold a
/// pixel the ball covers (its centre ray hits it), each once. Returns (quad shades, floor
/// shades), both in pixels (block shades x block pixels); divide by [`covered_pixels`]
/// for the work per covered pixel.
pub fn block_shades(scene: &Scene, w: u32, h: u32, block: u32) -> (f64, f64) {
    let block = block.max(1);
    let basis = scene.camera.basis(w, h);
    let pad = shadeballs::scene::bounds_pad_px(scene.antialias);
    let (mut quad, mut floor) = (0usize, 0usize);
    for b in &scene.balls {
        let Some([x0, y0, x1, y1]) = basis.sphere_bounds(b.center, b.radius, w, h, pad) else {
            continue;
        };
        // The quad in pixels, y down.
        let (left, right) = ((x0 + 1.0) * 0.5 * w as f64, (x1 + 1.0) * 0.5 * w as f64);
        let (top, bottom) = ((1.0 - y1) * 0.5 * h as f64, (1.0 - y0) * 0.5 * h as f64);
        let blocks = |lo: f64, hi: f64, n: u32| {
            let first = (lo.max(0.0) as u32) / block;
            let last = ((hi.max(0.0) as u32).min(n.saturating_sub(1))) / block;
            first..=last
        };
        for by in blocks(top, bottom, h) {
            for bx in blocks(left, right, w) {
                // Which triangles hold a pixel centre of this block, and whether the ball
                // covers one of its pixels.
                let (mut lower, mut upper, mut hit) = (false, false, false);
                for py in by * block..((by + 1) * block).min(h) {
                    for px in bx * block..((bx + 1) * block).min(w) {
                        let (x, y) = (px as f64 + 0.5, py as f64 + 0.5);
                        if x < left || x > right || y < top || y > bottom {
                            continue;
                        }
                        // u right, v up across the quad: the lower-left triangle is u + v <= 1.
                        let u = (x - left) / (right - left);
                        let v = (bottom - y) / (bottom - top);
                        lower |= u + v <= 1.0;
                        upper |= u + v >= 1.0;
                        if !hit {
                            let d = basis.ray(px, py, w, h);
                            hit = shadeballs::cpu::intersect_sphere(
                                basis.origin,
                                d,
                                b.center,
                                b.radius,
                            ) > 0.0;
                        }
                    }
                }
                quad += lower as usize + upper as usize;
                floor += hit as usize;
            }
        }
    }
    let pixels = |shades: usize| (shades * (block * block) as usize) as f64;
    (pixels(quad), pixels(floor))
}

fn series(label: &str) -> Series {
    Series {
        label: label.into(),
        style: Style::Marked,
        ..Default::default()
    }
}

/// The scale sweep on `renderer` (planned, default options).
pub fn scale_sweep(renderer: &mut Renderer, quick: bool) -> Result<Sweep> {
    renderer.set_draw_options(shadeballs::gpu::DrawOptions::default());
    renderer.set_bake_config(BakeConfig::default());
    let repeats = if quick { 3 } else { 21 };
    let (w, h) = (1280, 720);
    let mut goals = Vec::new();

    // Ball count at equal covered pixels.
    let mut balls_t = Table::new(
        "scale_balls",
        "Scale: frame time at 1280x720 against the number of balls at equal covered pixels (n x n chart, radius shrinking with n)",
        &[
            "balls",
            "radius",
            "covered_pixels",
            "frame_ms",
            "over_16_balls",
            "frame_ms_aa_off",
            "aa_off_over_16_balls",
            "quad_shades_per_px",
            "quad_over_16_balls",
            "floor_shades_per_px",
            "floor_over_16_balls",
            "quad_2x2_shades_per_px",
            "quad_2x2_over_16_balls",
        ],
    );
    let mut by_balls = series("antialiased");
    let mut by_balls_aliased = series("--aa off");
    // Per ball count: frame times antialiased and not, and the block model's shades.
    let mut at = std::collections::HashMap::new();
    let mut cases = Vec::new();
    for n in SIDES {
        let scene = chart(n, 1, None);
        let aliased = Scene {
            antialias: false,
            ..scene.clone()
        };
        cases.push((scene, w, h));
        cases.push((aliased, w, h));
    }
    let times = interleaved_frame_ms(renderer, &cases, repeats)?;
    for (i, n) in SIDES.into_iter().enumerate() {
        let scene = &cases[2 * i].0;
        let (ms, ms_off) = (times[2 * i], times[2 * i + 1]);
        let covered = covered_pixels(scene, w, h);
        let per_covered = |shaded: f64| shaded / covered.max(1) as f64;
        let (quad, floor) = block_shades(scene, w, h, LAVAPIPE_BLOCK_PX);
        let (quad, floor) = (per_covered(quad), per_covered(floor));
        let gpu_quad = per_covered(block_shades(scene, w, h, GPU_QUAD_PX).0);
        at.insert(n * n, (ms, ms_off, quad, floor, gpu_quad));
        by_balls.points.push(((n * n) as f64, ms));
        by_balls_aliased.points.push(((n * n) as f64, ms_off));
        balls_t.push(vec![
            (n * n).to_string(),
            format!("{:.2}", scene.balls[0].radius),
            covered.to_string(),
            format!("{ms:.2}"),
            String::new(),
            format!("{ms_off:.2}"),
            String::new(),
            format!("{quad:.2}"),
            String::new(),
            format!("{floor:.2}"),
            String::new(),
            format!("{gpu_quad:.2}"),
            String::new(),
        ]);
    }
    let base = at[&16];
    // The block model's prediction: 16 balls' antialiased time scaled by the quads' shades.
    let by_balls_model = Series {
        label: "block model".into(),
        style: Style::Dashed,
        points: SIDES
            .iter()
            .map(|n| ((n * n) as f64, base.0 * at[&(n * n)].2 / base.2))
            .collect(),
        ..Default::default()
    };
    for row in &mut balls_t.rows {
        let (ms, ms_off, quad, floor, gpu_quad) = at[&row[0].parse::<u32>().unwrap_or(0)];
        row[4] = format!("{:.3}", ms / base.0);
        row[6] = format!("{:.3}", ms_off / base.1);
        row[8] = format!("{:.3}", quad / base.2);
        row[10] = format!("{:.3}", floor / base.3);
        row[12] = format!("{:.3}", gpu_quad / base.4);
    }
    for (balls, limit) in [(256, 1.3), (4096, 2.0)] {
        let (ms, ms_off, quad, floor, gpu_quad) = at[&balls];
        let ratio = ms / base.0;
        goals.push(Goal {
            what: format!("scale: {balls} balls <= {limit}x the frame time of 16 at equal covered pixels (1280x720)"),
            figure: format!(
                "{ms:.2} ms against {:.2} ms: {ratio:.2}x ({}); --aa off {:.2}x; the block model: the quads {:.2}x, the floor of any per-ball draw {:.2}x; in 2 x 2 quads (a GPU) the quads {:.2}x",
                base.0,
                renderer.gpu().describe(),
                ms_off / base.1,
                quad / base.2,
                floor / base.3,
                gpu_quad / base.4,
            ),
            met: ratio <= limit,
        });
    }

    // The CPU reference renderer at 1280 x 720 (rayon's pool; the same charts).
    let mut cpu_t = Table::new(
        "scale_cpu",
        "Scale: the CPU reference renderer at 1280x720 against the number of balls at equal covered pixels",
        &["balls", "cpu_ms", "over_16_balls"],
    );
    let mut by_balls_cpu = series("CPU reference renderer");
    let cpu_repeats = if quick { 1 } else { 5 };
    let mut cpu_at = std::collections::HashMap::new();
    for n in SIDES {
        let scene = chart(n, 1, None);
        let tables = TableSet::from(shadeballs::lut::bake(&BakeConfig {
            geometry: scene.effective_geometry(),
            ..BakeConfig::default()
        }));
        let (ms, _) = super::median_ms(cpu_repeats, || {
            shadeballs::cpu::render_radiance(
                &scene,
                &shadeballs::prepared::Prepared::new(&scene, &tables),
                w,
                h,
            )
        });
        cpu_at.insert(n * n, ms);
        by_balls_cpu.points.push(((n * n) as f64, ms));
    }
    for n in SIDES {
        let ms = cpu_at[&(n * n)];
        cpu_t.push(vec![
            (n * n).to_string(),
            format!("{ms:.1}"),
            format!("{:.3}", ms / cpu_at[&16]),
        ]);
    }
    let cpu_ratio = cpu_at[&256] / cpu_at[&16];
    goals.push(Goal {
        what:
            "scale: the CPU reference renderer's 256-ball chart <= 2x its 16-ball time (1280x720)"
                .into(),
        figure: format!(
            "{:.1} ms against {:.1} ms: {cpu_ratio:.2}x; 4,096 balls {:.1} ms",
            cpu_at[&256], cpu_at[&16], cpu_at[&4096]
        ),
        met: cpu_ratio <= 2.0,
    });

    // Resolution, the 16 x 16 chart.
    let mut res_t = Table::new(
        "scale_resolution",
        "Scale: frame time of the 16 x 16 chart against the resolution (1 light); the block model's shaded pixels beside the covered ones",
        &[
            "resolution",
            "covered_pixels",
            "frame_ms",
            "ms_per_covered_mpx",
            "over_proportional",
            "quad_shades_per_px",
            "ms_per_shaded_mpx",
            "shaded_over_proportional",
        ],
    );
    let mut by_res = series("against covered pixels");
    let mut by_shaded = series("against pixels shaded (block model)");
    let scene = chart(16, 1, None);
    let mut per_px = Vec::new();
    // The quick run stops at 1920x1080 (2560x1440 and 3840x2160 are 13 of its 16.5 times
    // 1280x720's pixels).
    let resolutions = if quick {
        &RESOLUTIONS[..3]
    } else {
        &RESOLUTIONS[..]
    };
    let cases: Vec<_> = resolutions
        .iter()
        .map(|&(rw, rh)| (scene.clone(), rw, rh))
        .collect();
    let times = interleaved_frame_ms(renderer, &cases, repeats)?;
    for (&(rw, rh), ms) in resolutions.iter().zip(times) {
        let covered = covered_pixels(&scene, rw, rh) as f64;
        let (shaded, _) = block_shades(&scene, rw, rh, LAVAPIPE_BLOCK_PX);
        by_res.points.push((covered, ms));
        by_shaded.points.push((shaded, ms));
        per_px.push(((rw, rh), covered, shaded, ms));
    }
    let reference = per_px.iter().find(|(r, _, _, _)| *r == (1280, 720));
    let (ref_rate, ref_shaded_rate) =
        reference.map_or((f64::NAN, f64::NAN), |(_, c, s, ms)| (ms / c, ms / s));
    let (mut worst, mut worst_shaded): (f64, f64) = (1.0, 1.0);
    for ((rw, rh), covered, shaded, ms) in &per_px {
        let over = ms / covered / ref_rate;
        let over_shaded = ms / shaded / ref_shaded_rate;
        worst = worst.max(over).max(1.0 / over);
        worst_shaded = worst_shaded.max(over_shaded).max(1.0 / over_shaded);
        res_t.push(vec![
            format!("{rw}x{rh}"),
            format!("{covered:.0}"),
            format!("{ms:.2}"),
            format!("{:.2}", ms / covered * 1e6),
            format!("{over:.3}"),
            format!("{:.2}", shaded / covered),
            format!("{:.2}", ms / shaded * 1e6),
            format!("{over_shaded:.3}"),
        ]);
    }
    let (smallest, largest) = (resolutions[0], resolutions[resolutions.len() - 1]);
    goals.push(Goal {
        what: format!(
            "scale: frame time proportional to covered pixels within 1.2x, {}x{} to {}x{} (ms per covered pixel against 1280x720's)",
            smallest.0, smallest.1, largest.0, largest.1
        ),
        figure: format!(
            "worst {worst:.2}x; per pixel the block model shades, worst {worst_shaded:.2}x (scale_resolution.csv)"
        ),
        met: worst <= 1.2,
    });

    // Lights, the 16 x 16 chart at 1280 x 720.
    let mut lights_t = Table::new(
        "scale_lights",
        "Scale: frame time of the 16 x 16 chart at 1280x720 against the number of lights",
        &["lights", "frame_ms", "fit_ms", "over_fit"],
    );
    let mut by_lights = series("16 x 16 chart, 1280x720");
    let mut pts = Vec::new();
    let cases: Vec<_> = LIGHTS.iter().map(|&l| (chart(16, l, None), w, h)).collect();
    let times = interleaved_frame_ms(renderer, &cases, repeats)?;
    for (l, ms) in LIGHTS.into_iter().zip(times) {
        pts.push((l as f64, ms));
        by_lights.points.push((l as f64, ms));
    }
    let (a, b) = line_fit(&pts);
    let mut worst_fit: f64 = 1.0;
    for (l, ms) in &pts {
        let fit = a + b * l;
        worst_fit = worst_fit.max(ms / fit).max(fit / ms);
        lights_t.push(vec![
            format!("{l}"),
            format!("{ms:.2}"),
            format!("{fit:.2}"),
            format!("{:.3}", ms / fit),
        ]);
    }
    goals.push(Goal {
        what: "scale: frame time linear in the number of lights (1 to 16) within 1.2x of a straight line".into(),
        figure: format!("{a:.2} ms + {b:.2} ms a light; worst point {worst_fit:.3}x its fit"),
        met: worst_fit <= 1.2,
    });

    // Startup against ball count and distinct roughness values, a fresh device each.
    let mut start_t = Table::new(
        "scale_startup",
        "Scale: startup at 1280x720 against balls and distinct roughness values (fresh device; pipelines made before timing)",
        &["balls", "roughness_values", "tables", "plan_ms", "bake_bind_ms", "first_frame_ms", "frame_ms"],
    );
    let mut startup_series: Vec<Series> = Vec::new();
    // A fresh device a chart compiles the pipelines again (half a second each on
    // lavapipe): the quick run measures the most roughness values only, at 16, 256 and
    // 4,096 balls.
    let values: &[u32] = if quick { &[64] } else { &[1, 16, 64] };
    let sides: &[u32] = if quick { &[4, 16, 64] } else { &SIDES };
    for &v in values {
        let mut s = series(&format!(
            "plan + bake + first frame, {v} roughness value(s)"
        ));
        for &n in sides {
            let scene = chart(n, 1, Some(v));
            let mut fresh = Renderer::new(device::open()?);
            fresh.prepare(&scene, FORMAT);
            let start = Instant::now();
            std::hint::black_box(Plan::new(
                &scene,
                BakeConfig::default(),
                fresh.draw_options(),
            ));
            let plan_ms = start.elapsed().as_secs_f64() * 1e3;
            let start = Instant::now();
            let tables = plan_tables(fresh.plan_for(&scene));
            let bake_ms = start.elapsed().as_secs_f64() * 1e3;
            let (_texture, view) = device::frame_target(fresh.gpu(), w, h);
            let first = frame(&mut fresh, &scene, &view, w, h)?;
            let steady = frame(&mut fresh, &scene, &view, w, h)?;
            s.points.push(((n * n) as f64, plan_ms + bake_ms + first));
            start_t.push(vec![
                (n * n).to_string(),
                v.min(n * n).to_string(),
                tables,
                format!("{plan_ms:.3}"),
                format!("{bake_ms:.2}"),
                format!("{first:.2}"),
                format!("{steady:.2}"),
            ]);
        }
        startup_series.push(s);
    }

    let plot = |title: &str, x: &str, series: Vec<Series>| Plot {
        title: title.into(),
        x_label: x.into(),
        y_label: "time (ms)".into(),
        series,
        goals: Vec::new(),
    };
    Ok(Sweep {
        tables: vec![balls_t, cpu_t, res_t, lights_t, start_t],
        plots: vec![
            (
                "scale_balls".into(),
                plot(
                    "Frame time against balls at equal covered pixels (1280x720, 1 light)",
                    "balls",
                    vec![by_balls, by_balls_aliased, by_balls_model],
                ),
            ),
            (
                "scale_resolution".into(),
                plot(
                    &format!(
                        "Frame time of the 16 x 16 chart, {}x{} to {}x{} (1 light)",
                        smallest.0, smallest.1, largest.0, largest.1
                    ),
                    "pixels",
                    vec![by_res, by_shaded],
                ),
            ),
            (
                "scale_lights".into(),
                plot("Frame time against lights", "lights", vec![by_lights]),
            ),
            (
                "scale_startup".into(),
                plot(
                    "Startup (plan, bake, first frame) against balls",
                    "balls",
                    startup_series,
                ),
            ),
        ],
        goals,
    })
}

/// The tables a plan binds, in words.
fn plan_tables(plan: &Plan) -> String {
    match &plan.tables {
        TableSet::None => "none".into(),
        TableSet::Full(_) => "2-D table".into(),
        TableSet::Rows(r) => format!("{} rows", r.len()),
    }
}

/// Least-squares line `a + b x` through `pts`.
fn line_fit(pts: &[(f64, f64)]) -> (f64, f64) {
    let n = pts.len() as f64;
    let (sx, sy) = pts.iter().fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
    let (mx, my) = (sx / n, sy / n);
    let sxy: f64 = pts.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = pts.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
    let b = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    (my - b * mx, b)
}
