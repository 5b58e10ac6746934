//! One configuration of the light bench (`bench --only light`, `lab/src/bench/light.rs`:
//! its scene, its GPU Monte Carlo reference at 160x90 with the full run's estimates a
//! pixel, its error measure) for trials of the lobe mode's estimator: the progressive lobe's error
//! after each of the given frame counts of 16 samples, per ball (and, in brackets, the
//! reference's own mean relative standard error there) and the worst of roughness >= 0.3,
//! in seconds instead of the bench's minutes once the reference is kept.
//!
//! ```text
//! cargo run --release -p shadeballs-lab --example light_trial -- MAP MATERIAL FRAMES [--time]
//! cargo run --release -p shadeballs-lab --example light_trial -- studio metal 1,8,16
//! ```
//!
//! MAP is `studio`, `sky` or `sun` (the bench's generated sun map), MATERIAL `metal` or
//! `plastic`, FRAMES a comma-separated list. `--time` also prints the median frame time
//! of the split sum and of the lobe at 16 samples at 1280x720 (7 rounds, in turn). The
//! reference is kept in `target/light_trial/` and read back by later runs: a trial that
//! edits the shaders keeps the same reference, whose model it does not change.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use shadeballs::environment::{Builtin, Environment};
use shadeballs::stats::{median, MonteCarloImage};
use shadeballs_lab::bench::light::{
    ball_errors, frame_times, light_scene, method_image, reference, sun_environment, Family,
    LightMaterial, Method, Settings,
};
use shadeballs_lab::bench::{device, reference_cache};

/// Rounds of timed frames (the bench's full run takes more).
const ROUNDS: usize = 7;

/// The reference's file in `target/light_trial/` ([`reference_cache`]) for the full run's
/// `settings`.
fn cache(map: &str, material: LightMaterial, settings: &Settings) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/light_trial");
    let (w, h) = settings.size;
    dir.join(format!(
        "{map}-{}-{w}x{h}-{}.bin",
        material.name(),
        settings.spp
    ))
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [map, material, frames, ..] = args.as_slice() else {
        bail!("usage: light_trial MAP MATERIAL FRAMES [--time] (e.g. studio metal 1,8,16)");
    };
    let environment = match map.as_str() {
        "studio" => Environment::builtin(Builtin::Studio),
        "sky" => Environment::builtin(Builtin::Sky),
        "sun" => sun_environment(),
        other => bail!("MAP: studio, sky or sun, not {other}"),
    };
    let material = match material.as_str() {
        "metal" => LightMaterial::Metal,
        "plastic" => LightMaterial::Plastic,
        other => bail!("MATERIAL: metal or plastic, not {other}"),
    };
    let frames: Vec<u32> = frames
        .split(',')
        .map(|f| {
            f.parse()
                .with_context(|| format!("FRAMES: {f} is not a count"))
        })
        .collect::<Result<_>>()?;
    // The bench's full run: its error images, reference and timed frames.
    let settings = Settings::new(false);
    let (size, spp) = (settings.size, settings.spp);
    let mut renderer = shadeballs::gpu::Renderer::new(device::open()?);
    renderer.set_multiple_scattering_term(true);
    let base = light_scene(environment, material);
    let path = cache(map, material, &settings);
    // Two estimates a pixel give the reference's shape (coverage, filter) in a moment.
    let shape = MonteCarloImage {
        spp,
        ..reference(&mut renderer, &base, size, 2)?
    };
    let reference = match reference_cache::read(&path, shape) {
        Some(r) => r,
        None => {
            let r = reference(&mut renderer, &base, size, spp)?;
            reference_cache::write(&path, &r);
            r
        }
    };
    if args.iter().any(|a| a == "--time") {
        let split = Method {
            family: Family::SplitSum,
            samples: 0,
            frames: 1,
        };
        let lobe = Method {
            family: Family::Lobe,
            samples: 16,
            frames: 1,
        };
        let scenes = [split, lobe].map(|m| (m.scene(&base), m.options()));
        let (mut times, _) = frame_times(&mut renderer, &scenes, settings.frame, ROUNDS)?;
        println!(
            "{map} {}: split sum {:.1} ms, lobe at 16 samples {:.1} ms a frame ({}x{})",
            material.name(),
            median(&mut times[0]),
            median(&mut times[1]),
            settings.frame.0,
            settings.frame.1
        );
    }
    for count in frames {
        let method = Method {
            family: Family::Progressive,
            samples: 16,
            frames: count,
        };
        let image = method_image(&mut renderer, &base, method, size)?;
        let errors = ball_errors(&method.scene(&base), material, size, &image, &reference)?;
        let worst = errors
            .iter()
            .filter(|e| e.roughness >= 0.3)
            .map(|e| e.mean)
            .fold(0.0, f64::max);
        let balls: Vec<String> = errors
            .iter()
            .map(|e| {
                format!(
                    "{} {:.2}: {:.2} ({:.2})",
                    e.row,
                    e.roughness,
                    100.0 * e.mean,
                    100.0 * e.noise
                )
            })
            .collect();
        println!(
            "{map} {}, {count} frames of 16: worst {:.2} % ({})",
            material.name(),
            100.0 * worst,
            balls.join(", ")
        );
    }
    Ok(())
}
