//! Lighting that follows the lobe against the split sum (docs/design/environment.md,
//! "Lighting that follows the lobe"): each method's whole image against the CPU Monte Carlo
//! of the same model (`cpu::render_montecarlo`), both without antialiasing, and its frame
//! time at 1280x720 on the first Vulkan adapter (lavapipe here).
//!
//! The balls are the lab's IBL balls (`bench --only ibl`: the reference scene's copper row
//! over a white metal row, F0 0.95, every ball with the Kulla-Conty term, lit by the map
//! alone) under `studio` and `sky`. Per method: the worst over the balls of roughness >=
//! 0.3 of the mean relative error of luminance over a ball's pixels, the Monte Carlo's own
//! mean relative standard error beside it; the median frame time of `--repeats` frames.
//! Then the progressive image: frames of `--progressive-samples` samples accumulated until
//! the worst error is within 1 %, and what those frames cost at 1280x720. The same for
//! plastics (every ball a dielectric of IOR 1.5 with the term; `--plastics` for them alone).
//!
//! ```text
//! cargo run --release -p shadeballs-lab --example lobe_sweep [-- --width 160 --height 90 --spp 8192 --repeats 11]
//! cargo run --release -p shadeballs-lab --example lobe_sweep -- --study [--frames 32] [--progressive] [--only NAME]
//! ```
//!
//! `--study` measures, on the CPU, each candidate estimator's bias and noise instead
//! (`lobe/study.rs`). The Monte Carlo references are kept in `target/lobe_sweep/` and read
//! back by later runs of the same size and sample count.

#[path = "lobe/study.rs"]
mod study;

use std::time::Instant;

use glam::DVec3;
use shadeballs::cpu::{self, MonteCarloImage};
use shadeballs::environment::{Builtin, Environment, IblMethod, IblTerm};
use shadeballs::gpu::{Gpu, Renderer, Target};
use shadeballs::lut::{self, BakeConfig, TableSet};
use shadeballs::scene::{Material, Model, Scene};
use shadeballs_lab::bench::reference_cache;

/// Rec. 709 luminance.
const LUMINANCE: DVec3 = DVec3::new(0.2126, 0.7152, 0.0722);
/// Reference pixels darker than this are left out of relative errors (the lab's floor).
const LUMINANCE_FLOOR: f64 = 1e-4;

fn flag(name: &str) -> bool {
    std::env::args().any(|a| a == name)
}

fn arg(name: &str, default: u32) -> u32 {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .map_or(default, |v| v.parse().expect("a whole number"))
}

/// The lab's IBL balls under `environment`, no antialiasing.
fn scene(environment: Environment) -> Scene {
    let mut scene = Scene::reference();
    for b in scene.balls.iter_mut() {
        if !b.model.has_term() {
            b.material = Material::metal(DVec3::splat(0.95));
        }
        b.model = Model::from_term(IblTerm::KullaConty);
    }
    Scene {
        lights: Vec::new(),
        environment: DVec3::ZERO,
        environment_map: Some(environment),
        antialias: false,
        ..scene
    }
}

/// A scene of the sweep's balls under a map.
type BallsUnder = fn(Environment) -> Scene;

/// The plastics under `environment`: the metals' scene with every ball a dielectric of IOR
/// 1.5 (a red base on the top row, a light grey one below), each with the Kulla-Conty term.
fn plastics(environment: Environment) -> Scene {
    let mut s = scene(environment);
    for (k, b) in s.balls.iter_mut().enumerate() {
        let base = if k < 5 {
            DVec3::new(0.6, 0.1, 0.1)
        } else {
            DVec3::splat(0.8)
        };
        b.material = Material::dielectric(base, 1.5);
    }
    s
}

/// The worst over the balls of roughness >= 0.3 of the mean relative luminance error of
/// `image` against `mc` over the ball's pixels, and the Monte Carlo's mean relative
/// standard error over the same pixels.
fn worst_error(
    scene: &Scene,
    size: (u32, u32),
    image: &[DVec3],
    mc: &MonteCarloImage,
) -> (f64, f64) {
    let (w, h) = size;
    let basis = scene.camera.basis(w, h);
    let mut per_ball = vec![(0.0, 0.0, 0usize); scene.balls.len()];
    for py in 0..h {
        for px in 0..w {
            let d = basis.ray(px, py, w, h);
            let hit = cpu::nearest_ball(scene, basis.origin, d);
            let Some((_, k)) = hit else { continue };
            let i = (py * w + px) as usize;
            let y_ref = mc.mean[i].dot(LUMINANCE);
            if y_ref < LUMINANCE_FLOOR {
                continue;
            }
            let e = &mut per_ball[k];
            e.0 += (image[i].dot(LUMINANCE) - y_ref).abs() / y_ref;
            e.1 += mc.std_error[i].dot(LUMINANCE) / y_ref;
            e.2 += 1;
        }
    }
    let mut worst = (0.0f64, 0.0f64);
    for (b, (err, noise, n)) in scene.balls.iter().zip(per_ball) {
        if b.roughness >= 0.3 && n > 0 && err / n as f64 > worst.0 {
            worst = (err / n as f64, noise / n as f64);
        }
    }
    worst
}

fn linear(rgba: &[f32]) -> Vec<DVec3> {
    rgba.chunks_exact(4)
        .map(|p| DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64))
        .collect()
}

/// The median wall time (ms) of `repeats` frames of `scene` at 1280x720, each waited for.
fn frame_ms(renderer: &mut Renderer, scene: &Scene, repeats: u32) -> f64 {
    let (w, h) = (1280, 720);
    let device = renderer.gpu().device.clone();
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("frame"),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8Unorm,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    let target = Target {
        view: &view,
        format: wgpu::TextureFormat::Rgba8Unorm,
        width: w,
        height: h,
    };
    let mut times = Vec::new();
    // The first frame compiles the pipeline and prepares the map: not timed.
    for k in 0..=repeats {
        let start = Instant::now();
        renderer.render(scene, target).expect("a frame");
        let _ = device.poll(wgpu::PollType::wait_indefinitely());
        if k > 0 {
            times.push(start.elapsed().as_secs_f64() * 1e3);
        }
    }
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// The CPU Monte Carlo of `scene` (seed 7), read from `target/lobe_sweep/` where an
/// earlier run of the same map, size and sample count left it, else rendered and kept.
fn reference(
    scene: &Scene,
    e: &TableSet,
    name: &str,
    (w, h): (u32, u32),
    spp: u32,
) -> shadeballs::Result<MonteCarloImage> {
    let path =
        std::path::Path::new("target/lobe_sweep").join(format!("mc-{name}-{w}x{h}-{spp}.bin"));
    let pixels = (w * h) as usize;
    let shape = MonteCarloImage {
        width: w,
        height: h,
        spp,
        mean: Vec::new(),
        std_error: Vec::new(),
        covered: vec![true; pixels],
        antialias: scene.antialias,
    };
    if let Some(mc) = reference_cache::read(&path, shape) {
        return Ok(mc);
    }
    let mc = cpu::render_montecarlo(
        scene,
        &shadeballs::prepared::Prepared::new(scene, e),
        w,
        h,
        spp,
        7,
    )?;
    reference_cache::write(&path, &mc);
    Ok(mc)
}

/// `--study`: each candidate's one-frame error, bias and noise (`lobe/study.rs`).
fn run_study((w, h): (u32, u32), spp: u32) -> shadeballs::Result<()> {
    let frames = arg("--frames", 32);
    let only: Option<String> = std::env::args().skip_while(|a| a != "--only").nth(1);
    println!(
        "study at {w}x{h}, {frames} frames a variant, against the CPU Monte Carlo of {spp} spp"
    );
    println!("environment | variant | samples | one frame | bias | noise | worst ball: (bias, noise) by n.v <0.25, <0.5, >=0.5");
    for builtin in [Builtin::Studio, Builtin::Sky] {
        let environment = Environment::builtin(builtin);
        let s = scene(environment.clone());
        let tables = lut::bake(&BakeConfig {
            geometry: s.effective_geometry(),
            ..BakeConfig::default()
        });
        let ibl = cpu::CpuEnvironment::new(&environment, &tables, true);
        let e = TableSet::full(tables);
        let mc = reference(&s, &e, builtin.name(), (w, h), spp)?;
        let setup = study::Setup {
            scene: &s,
            environment: &environment,
            e: &e,
            ibl: &ibl,
            mc: &mc,
            size: (w, h),
        };
        println!(
            "{builtin} | split sum | - | {:.2} % | | |",
            100.0 * study::split_sum_error(&setup)
        );
        if flag("--progressive") {
            for variant in study::progressive_candidates() {
                for frames in [1, 4, 16, 64] {
                    let e = study::progressive(&setup, &variant, 16, frames);
                    println!(
                        "{builtin} | {} progressive | {frames} x 16 | {:.2} % | | |",
                        variant.name,
                        100.0 * e
                    );
                }
            }
            continue;
        }
        for (variant, n) in study::candidates() {
            if only.as_deref().is_some_and(|o| !variant.name.contains(o)) {
                continue;
            }
            let f = study::measure(&setup, &variant, n, frames);
            let by: Vec<String> = f
                .by_mu
                .iter()
                .map(|(b, s)| format!("({:.1}, {:.1})", 100.0 * b, 100.0 * s))
                .collect();
            println!(
                "{builtin} | {} | {n} | {:.2} % | {:.2} % | {:.2} % | ball {}: {}",
                variant.name,
                100.0 * f.frame,
                100.0 * f.bias,
                100.0 * f.noise,
                f.worst_ball,
                by.join(" ")
            );
        }
    }
    Ok(())
}

fn main() -> shadeballs::Result<()> {
    let (w, h) = (arg("--width", 160), arg("--height", 90));
    let spp = arg("--spp", 8192);
    if flag("--study") {
        return run_study((w, h), spp);
    }
    let mut renderer = Renderer::new(Gpu::new(wgpu::Backends::VULKAN)?);
    println!(
        "{}; errors at {w}x{h} against Monte Carlo of {spp} spp",
        renderer.gpu().describe()
    );
    println!("balls, environment | method | samples | worst mean rel err (r >= 0.3) | mc rel std err | frame ms (1280x720)");
    let kinds: [(&str, BallsUnder); 2] = [("metals", scene), ("plastics", plastics)];
    for (kind, make) in kinds {
        if flag("--plastics") && kind == "metals" {
            continue;
        }
        for builtin in [Builtin::Studio, Builtin::Sky] {
            sweep(
                &mut renderer,
                make(Environment::builtin(builtin)),
                (kind, builtin),
                (w, h),
                spp,
            )?;
        }
    }
    Ok(())
}

/// The sweep's rows for `s` (`kind` its balls, under `builtin`).
fn sweep(
    renderer: &mut Renderer,
    mut s: Scene,
    (kind, builtin): (&str, Builtin),
    (w, h): (u32, u32),
    spp: u32,
) -> shadeballs::Result<()> {
    let repeats = arg("--repeats", 11);
    let progressive = arg("--progressive-samples", 16);
    {
        let tables = lut::bake(&BakeConfig {
            geometry: s.effective_geometry(),
            ..BakeConfig::default()
        });
        let e = TableSet::full(tables);
        let name = match kind {
            "metals" => builtin.name().to_string(),
            _ => format!("{kind}-{builtin}"),
        };
        let mc = reference(&s, &e, &name, (w, h), spp)?;
        let row =
            |s: &Scene, label: &str, samples: String, r: &mut Renderer| -> shadeballs::Result<()> {
                let image = linear(&r.render_hdr(s, w, h)?.rgba);
                let (err, noise) = worst_error(s, (w, h), &image, &mc);
                let ms = frame_ms(r, s, repeats);
                println!(
                    "{kind}, {builtin} | {label} | {samples} | {:.2} % | {:.2} % | {ms:.1}",
                    err * 100.0,
                    noise * 100.0
                );
                Ok(())
            };
        s.ibl_method = IblMethod::SplitSum;
        row(&s, "split-sum", "-".into(), renderer)?;
        s.ibl_method = IblMethod::Lobe;
        for n in [1, 2, 4, 8, 16, 32, 64] {
            s.ibl_samples = n;
            row(&s, "lobe", n.to_string(), renderer)?;
        }
        // Progressive: frames of `progressive` samples until within 1 %.
        s.ibl_samples = progressive;
        let per_frame = frame_ms(renderer, &s, repeats);
        let mut frames = 1;
        loop {
            let image = linear(&renderer.render_lobe_hdr(&s, w, h, frames)?.rgba);
            let (err, _) = worst_error(&s, (w, h), &image, &mc);
            println!("{kind}, {builtin} | lobe progressive | {frames} x {progressive} | {:.2} % | | {:.0} ms for {frames} frames", err * 100.0, per_frame * frames as f64);
            if err <= 0.01 || frames >= 256 {
                break;
            }
            frames *= 2;
        }
    }
    Ok(())
}
