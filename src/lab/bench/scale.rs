//! Scale: what a frame costs as the work grows, on the planned renderer. Frame time against
//! the number of balls at equal covered pixels (n x n charts whose radius shrinks as n
//! grows), against the resolution (the 16 x 16 chart from 640 x 360 to 3840 x 2160), and
//! against the number of lights; and startup (plan, bake and bind the tables, the first
//! frame's upload and draw) against the number of balls and of distinct roughness values.
//!
//! Frame time as in `render.rs`: the median wall time of encoding, submitting and waiting
//! for one frame into an `Rgba8Unorm` target (no readback), after a warm-up frame.

use std::time::Instant;

use glam::DVec3;

use super::table::Table;
use super::{device, median, Goal, Sweep};
use crate::error::Result;
use crate::gpu::{Plan, Renderer, Target};
use crate::lab::plot::{Plot, Series, Style};
use crate::lut::BakeConfig;
use crate::scene::{Ball, Camera, Light, Material, Model, Scene};

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
            });
        }
    }
    let lights = (0..lights.max(1))
        .map(|k| {
            // Directions spread over the camera's hemisphere.
            let a = k as f64 * 2.399_963; // the golden angle
            let z = 1.0 - 0.5 * (k as f64 + 0.5) / lights.max(1) as f64;
            let s = (1.0 - z * z).sqrt();
            Light {
                direction: DVec3::new(s * a.cos(), s * a.sin(), z),
                radiance: DVec3::splat(1.0 / lights.max(1) as f64),
            }
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

/// Median frame time (ms) of `scene` at `w x h` over `repeats` frames after a warm-up one.
pub fn frame_ms(
    renderer: &mut Renderer,
    scene: &Scene,
    w: u32,
    h: u32,
    repeats: usize,
) -> Result<f64> {
    let (_texture, view) = device::frame_target(renderer.gpu(), w, h);
    frame(renderer, scene, &view, w, h)?;
    let mut times = Vec::with_capacity(repeats);
    for _ in 0..repeats.max(1) {
        times.push(frame(renderer, scene, &view, w, h)?);
    }
    Ok(median(&mut times))
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
                if crate::cpu::intersect_sphere(basis.origin, d, b.center, b.radius) > 0.0 {
                    hit[(py * w + px) as usize] = true;
                }
            }
        }
    }
    hit.iter().filter(|&&c| c).count()
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
    renderer.set_draw_options(crate::gpu::DrawOptions::default());
    renderer.set_bake_config(BakeConfig::default());
    let repeats = if quick { 5 } else { 21 };
    let (w, h) = (1280, 720);
    let mut goals = Vec::new();

    // Ball count at equal covered pixels.
    let mut balls_t = Table::new(
        "scale_balls",
        "Scale: frame time at 1280x720 against the number of balls at equal covered pixels (n x n chart, radius shrinking with n)",
        &["balls", "radius", "covered_pixels", "frame_ms", "over_16_balls"],
    );
    let mut by_balls = series("frame time (1280x720, 1 light)");
    let mut at = std::collections::HashMap::new();
    for n in SIDES {
        let scene = chart(n, 1, None);
        let covered = covered_pixels(&scene, w, h);
        let ms = frame_ms(renderer, &scene, w, h, repeats)?;
        at.insert(n * n, ms);
        by_balls.points.push(((n * n) as f64, ms));
        balls_t.push(vec![
            (n * n).to_string(),
            format!("{:.2}", scene.balls[0].radius),
            covered.to_string(),
            format!("{ms:.2}"),
            String::new(),
        ]);
    }
    let base = at[&16];
    for row in &mut balls_t.rows {
        let ms: f64 = row[3].parse().unwrap_or(f64::NAN);
        row[4] = format!("{:.3}", ms / base);
    }
    for (balls, limit) in [(256, 1.3), (4096, 2.0)] {
        let ratio = at[&balls] / base;
        goals.push(Goal {
            what: format!("scale: {balls} balls <= {limit}x the frame time of 16 at equal covered pixels (1280x720)"),
            figure: format!("{:.2} ms against {:.2} ms: {ratio:.2}x ({})", at[&balls], base, renderer.gpu().describe()),
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
        let tables = crate::lut::bake(&BakeConfig {
            geometry: scene.effective_geometry(),
            ..BakeConfig::default()
        });
        let (ms, _) = super::median_ms(cpu_repeats, || {
            crate::cpu::render_radiance(&scene, &tables, w, h)
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
        "Scale: frame time of the 16 x 16 chart against the resolution (1 light)",
        &[
            "resolution",
            "covered_pixels",
            "frame_ms",
            "ms_per_covered_mpx",
            "over_proportional",
        ],
    );
    let mut by_res = series("16 x 16 chart, 1 light");
    let scene = chart(16, 1, None);
    let mut per_px = Vec::new();
    for (rw, rh) in RESOLUTIONS {
        // Covered pixels scale with the area; count them at 1280 x 720 and scale, except
        // where counting is cheap.
        let covered = if rw * rh <= 1280 * 720 {
            covered_pixels(&scene, rw, rh) as f64
        } else {
            covered_pixels(&scene, 1280, 720) as f64 * (rw * rh) as f64 / (1280.0 * 720.0)
        };
        let ms = frame_ms(renderer, &scene, rw, rh, repeats)?;
        by_res.points.push((covered, ms));
        per_px.push(((rw, rh), covered, ms));
    }
    let ref_rate = per_px
        .iter()
        .find(|(r, _, _)| *r == (1280, 720))
        .map_or(f64::NAN, |(_, c, ms)| ms / c);
    let mut worst: f64 = 1.0;
    for ((rw, rh), covered, ms) in &per_px {
        let over = ms / covered / ref_rate;
        worst = worst.max(over).max(1.0 / over);
        res_t.push(vec![
            format!("{rw}x{rh}"),
            format!("{covered:.0}"),
            format!("{ms:.2}"),
            format!("{:.2}", ms / covered * 1e6),
            format!("{over:.3}"),
        ]);
    }
    goals.push(Goal {
        what: "scale: frame time proportional to covered pixels within 1.2x, 640x360 to 3840x2160 (ms per covered pixel against 1280x720's)".into(),
        figure: format!("worst {worst:.2}x (scale_resolution.csv)"),
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
    for l in LIGHTS {
        let ms = frame_ms(renderer, &chart(16, l, None), w, h, repeats)?;
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
    let values: &[u32] = if quick { &[1, 64] } else { &[1, 16, 64] };
    for &v in values {
        let mut s = series(&format!(
            "plan + bake + first frame, {v} roughness value(s)"
        ));
        for n in SIDES {
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
                    "Frame time against balls at equal covered pixels",
                    "balls",
                    vec![by_balls],
                ),
            ),
            (
                "scale_resolution".into(),
                plot(
                    "Frame time against covered pixels (640x360 to 3840x2160)",
                    "covered pixels",
                    vec![by_res],
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
        crate::gpu::TablePlan::None => "none".into(),
        crate::gpu::TablePlan::Full => "2-D table".into(),
        crate::gpu::TablePlan::Rows(r) => format!("{} rows", r.len()),
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
