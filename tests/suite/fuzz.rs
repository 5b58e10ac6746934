//! Fuzzing the scene parser (issue 6; the command line: `cli_fuzz.rs`), with proptest
//! generators in place of cargo-fuzz (which needs a nightly toolchain): structured scene
//! files with valid, edge and wrong values; the same mutated at random; truncated at
//! random; garbage text and bytes; deep nesting. Every case runs under `catch_unwind` and
//! is counted. An accepted scene must hold only values the renderers can take, and renders
//! finite on the CPU and the GPU; a rejected one gets a one-line message naming the file.
//! Runs are seeded and bounded (a few seconds in release mode).

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::sync::Mutex;

use proptest::prelude::*;
use shadeballs::scene::{self, Scene, MAX_BALLS, MAX_LIGHTS, MAX_MAGNITUDE};

use crate::props::run;
use crate::scene_gen::{garbage, mutated, scene_text, truncated};

/// Outcomes of the parser over the fuzzed files.
#[derive(Default, Debug)]
struct Tally {
    files: usize,
    accepted: usize,
    rejected: usize,
    panics: usize,
    /// Accepted scenes rendered on the CPU (8 x 8) and the GPU (8 x 8), and their pixels
    /// that were not finite and non-negative.
    rendered: usize,
    bad_pixels: usize,
    /// Parsed scenes kept for the GPU pass (one device for all).
    to_render: Vec<Scene>,
}

/// Everything a renderer relies on in an accepted scene.
fn check_accepted(s: &Scene) -> Result<(), String> {
    let finite = |v: glam::DVec3| v.is_finite() && v.abs().max_element() <= MAX_MAGNITUDE;
    if s.balls.is_empty() || s.balls.len() > MAX_BALLS || s.lights.len() > MAX_LIGHTS {
        return Err(format!(
            "{} balls, {} lights",
            s.balls.len(),
            s.lights.len()
        ));
    }
    if s.camera.problem().is_some() || !finite(s.camera.position) || !finite(s.camera.target) {
        return Err(format!("camera {:?}", s.camera));
    }
    if !(s.exposure > 0.0 && s.exposure <= MAX_MAGNITUDE && finite(s.environment)) {
        return Err(format!(
            "exposure {} environment {}",
            s.exposure, s.environment
        ));
    }
    for b in &s.balls {
        let ok = finite(b.center)
            && b.radius > 0.0
            && b.radius <= MAX_MAGNITUDE
            && (0.0..=1.0).contains(&b.roughness)
            && b.material.f0.min_element() >= 0.0
            && b.material.f0.max_element() <= 1.0
            && b.material.diffuse.min_element() >= 0.0
            && b.material.diffuse.max_element() <= 1.0;
        if !ok {
            return Err(format!("ball {b:?}"));
        }
    }
    for l in &s.lights {
        if (l.direction.length() - 1.0).abs() > 1e-12
            || !finite(l.radiance)
            || l.radiance.min_element() < 0.0
        {
            return Err(format!("light {l:?}"));
        }
    }
    Ok(())
}

fn parse_one(text: &str, tally: &Mutex<Tally>) -> Result<(), TestCaseError> {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        scene::parse(text, Path::new("fuzz.toml"))
    }));
    let mut t = tally.lock().unwrap();
    t.files += 1;
    match outcome {
        Err(_) => {
            t.panics += 1;
            Err(TestCaseError::fail(format!(
                "the parser panicked on {text:?}"
            )))
        }
        Ok(Err(e)) => {
            t.rejected += 1;
            let msg = e.to_string();
            prop_assert!(
                !msg.contains('\n') && msg.contains("fuzz.toml"),
                "{msg:?} for {text:?}"
            );
            Ok(())
        }
        Ok(Ok(s)) => {
            t.accepted += 1;
            if let Err(why) = check_accepted(&s) {
                return Err(TestCaseError::fail(format!(
                    "accepted a bad scene ({why}) from {text:?}"
                )));
            }
            if t.to_render.len() < 400 {
                t.to_render.push(s);
            }
            Ok(())
        }
    }
}

#[test]
fn fuzzed_scene_files_never_panic_and_are_accepted_only_when_valid() {
    let tally = Mutex::new(Tally::default());
    run(5000, scene_text(), |text| parse_one(&text, &tally));
    run(3000, mutated(), |text| parse_one(&text, &tally));
    run(1500, truncated(), |text| parse_one(&text, &tally));
    run(1500, garbage(), |text| parse_one(&text, &tally));
    // Deep nesting (arrays, inline tables), very long lines, a huge scene.
    let deep =
        |open: &str, close: &str, n: usize| format!("a = {}1{}", open.repeat(n), close.repeat(n));
    let long = format!("[[ball]]\ngrid = [0, 0]\nradius = 1\nroughness = 0.{}\nmaterial = {{ kind = \"metal\", f0 = [1, 1, 1] }}\n", "5".repeat(100_000));
    let many = "[[ball]]\ngrid = [0, 0]\nradius = 1\nroughness = 0.5\nmaterial = { kind = \"metal\", f0 = [1, 1, 1] }\n".repeat(MAX_BALLS + 1);
    for text in [
        deep("[", "]", 100),
        deep("[", "]", 100_000),
        deep("{ b = ", " }", 100_000),
        long,
        many,
    ] {
        parse_one(&text, &tally).unwrap();
    }
    let mut t = tally.into_inner().unwrap();
    // Accepted scenes render finite and non-negative on the CPU reference renderer.
    let tables: Vec<_> = shadeballs::brdf::Geometry::ALL
        .iter()
        .map(|&geometry| {
            shadeballs::lut::bake(&shadeballs::lut::BakeConfig {
                geometry,
                ..Default::default()
            })
        })
        .collect();
    for s in &t.to_render {
        let g = s.effective_geometry();
        let k = shadeballs::brdf::Geometry::ALL
            .iter()
            .position(|&x| x == g)
            .unwrap();
        let radiance = shadeballs::cpu::render_radiance(
            s,
            &shadeballs::prepared::Prepared::new(s, &tables[k].clone().into()),
            8,
            8,
        );
        t.bad_pixels += radiance
            .iter()
            .filter(|c| !(c.is_finite() && c.min_element() >= 0.0))
            .count();
        t.rendered += 1;
    }
    // And on the GPU.
    let mut r = crate::pixels::vulkan();
    for s in &t.to_render {
        let image = r.render_hdr(s, 8, 8).expect("an accepted scene renders");
        t.bad_pixels += image
            .rgba
            .iter()
            .filter(|v| !(v.is_finite() && **v >= 0.0))
            .count();
    }
    println!(
        "fuzzed scene files: {} parsed, {} accepted, {} rejected with a one-line message, {} panics; \
         {} accepted scenes rendered on the CPU and the GPU, {} non-finite or negative pixel values",
        t.files, t.accepted, t.rejected, t.panics, t.rendered, t.bad_pixels
    );
    assert!(
        t.files >= 10_000 && t.panics == 0 && t.bad_pixels == 0,
        "{t:?}"
    );
    assert!(
        t.accepted >= 500 && t.rejected >= 5000,
        "the generators drifted: {t:?}"
    );
}

/// Scene files that cannot be read: not UTF-8, a folder, missing, endless.
#[test]
fn unreadable_scene_files_are_one_line_errors() {
    let dir = crate::cli::temp_dir("fuzz-load");
    let bad = dir.join("latin1.toml");
    std::fs::write(&bad, b"[[ball]]\nradius = 1 # \xe9t\xe9\n").unwrap();
    for path in [
        bad.as_path(),
        dir.as_path(),
        Path::new("/nonexistent/scene.toml"),
        Path::new("/dev/zero"),
    ] {
        let msg = scene::load(path).unwrap_err().to_string();
        println!("{msg}");
        assert!(
            !msg.contains('\n') && msg.contains(&*path.to_string_lossy()),
            "{msg}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
