//! The truth renderer (`cpu::render_truth`, `render --backend truth`): checks that can fail
//! against independent references. The walk limited to one event is the single-scattering
//! model (`none`, as the Monte Carlo backend integrates it); a white furnace ball is the
//! background; the truth is brighter than `none` on every rough ball; a seed gives one
//! image; the stopping rule stops; bad settings are refused in one line.
use glam::DVec3;
use shadeballs::brdf::Geometry;
use shadeballs::cpu::{self, render_montecarlo, render_truth, TruthSettings};
use shadeballs::lut::TableSet;
use shadeballs::lut::{self, BakeConfig, Tables};
use shadeballs::scene::{Model, Scene};

use crate::cli::{interrupt, shadeballs, temp_dir};

/// Small images with many estimates: each ball still covers about 250 pixels.
const W: u32 = 160;
const H: u32 = 90;

/// Four standard errors: a correct estimate lands outside with probability 6e-5 per
/// comparison (normal tails; the ball means average hundreds of pixels).
const SIGMAS: f64 = 4.0;

fn tables(scene: &Scene) -> Tables {
    lut::bake(&BakeConfig {
        geometry: scene.effective_geometry(),
        ..Default::default()
    })
}

fn with_model(mut scene: Scene, model: Model) -> Scene {
    for b in &mut scene.balls {
        b.model = model;
    }
    scene
}

fn settings(spp: u32, max_order: u32) -> TruthSettings {
    TruthSettings {
        spp,
        stderr: None,
        seed: 3,
        max_order,
        every_ball: true,
    }
}

/// Per ball: the mean of the pixels whose nearest hit is the ball, and the standard error
/// of that mean, from any Monte Carlo image (per channel).
fn ball_means(scene: &Scene, image: &cpu::MonteCarloImage) -> Vec<(DVec3, DVec3)> {
    let index = cpu::ball_index_map(scene, image.width, image.height);
    let mut sums = vec![(0.0, DVec3::ZERO, DVec3::ZERO); scene.balls.len()];
    for (k, ball) in index.iter().enumerate() {
        if let Some(i) = *ball {
            sums[i].0 += 1.0;
            sums[i].1 += image.mean[k];
            sums[i].2 += image.std_error[k] * image.std_error[k];
        }
    }
    sums.into_iter()
        .map(|(n, sum, var): (f64, DVec3, DVec3)| (sum / n, var.powf(0.5) / n))
        .collect()
}

/// The reference balls under the reference light and a uniform environment (both parts of
/// the fixed single scattering and the walk's two estimators run), one ray through each
/// pixel's centre: the truth's pixel filter, which the Monte Carlo backend it is held
/// against then shares (like with like).
fn lit_scene() -> Scene {
    Scene {
        environment: DVec3::splat(0.3),
        antialias: false,
        ..Scene::reference()
    }
}

#[test]
fn one_event_walk_is_the_single_scattering_model() {
    let scene = lit_scene();
    let t = tables(&scene);
    let e = TableSet::full(t.clone());
    let truth = render_truth(
        &scene,
        &shadeballs::prepared::Prepared::new(&scene, &e),
        W,
        H,
        settings(4, 1),
        |_| true,
    )
    .unwrap();
    // The none model with the walk's own G, integrated by the Monte Carlo backend.
    let none = Scene {
        geometry: Geometry::SmithCorrelated,
        ..with_model(scene.clone(), Model::None)
    };
    let mc = render_montecarlo(
        &none,
        &shadeballs::prepared::Prepared::new(&none, &e),
        W,
        H,
        256,
        11,
    )
    .unwrap();
    let a = ball_means(&scene, &truth.image);
    let b = ball_means(&scene, &mc);
    for (k, ((ma, sa), (mb, sb))) in a.iter().zip(&b).enumerate() {
        for c in 0..3 {
            let bound = SIGMAS * (sa[c] * sa[c] + sb[c] * sb[c]).sqrt() + 1e-6 * mb[c];
            assert!(
                (ma[c] - mb[c]).abs() <= bound,
                "ball {k} channel {c}: one-event truth {} against none {} (bound {bound})",
                ma[c],
                mb[c]
            );
        }
    }
}

#[test]
fn white_furnace_truth_ball_is_the_background() {
    let scene = with_model(Scene::furnace(), Model::Truth);
    let t = tables(&scene);
    let truth = render_truth(
        &scene,
        &shadeballs::prepared::Prepared::new(&scene, &TableSet::full(t.clone())),
        W,
        H,
        settings(32, u32::MAX),
        |_| true,
    )
    .unwrap();
    for (k, b) in truth.balls.iter().enumerate() {
        let (m, s) = (b.mean.x, b.std_error.x);
        assert!(b.pixels > 100, "ball {k}: {} pixels", b.pixels);
        // The walk conserves energy with F = 1: what is not reflected at one event goes on.
        // A floor of 2e-3 for the single scattering's table (linear in mu between 129 nodes).
        assert!(
            (m - 1.0).abs() <= SIGMAS * s + 2e-3,
            "ball {k} (roughness {}): {m} +- {s}, not 1",
            scene.balls[k].roughness
        );
    }
    // Control: the same furnace without the walk's higher orders loses energy at roughness
    // 0.95 (E about 0.6), so the check above can fail.
    let single = render_truth(
        &scene,
        &shadeballs::prepared::Prepared::new(&scene, &TableSet::full(t.clone())),
        W,
        H,
        settings(2, 1),
        |_| true,
    )
    .unwrap();
    assert!(single.balls[4].mean.x < 0.9, "{:?}", single.balls[4]);
}

#[test]
fn truth_is_brighter_than_none_on_every_rough_ball() {
    let scene = lit_scene();
    let t = tables(&scene);
    let e = TableSet::full(t.clone());
    let truth = render_truth(
        &scene,
        &shadeballs::prepared::Prepared::new(&scene, &e),
        W,
        H,
        settings(64, u32::MAX),
        |_| true,
    )
    .unwrap();
    let none = Scene {
        geometry: Geometry::SmithCorrelated,
        ..with_model(scene.clone(), Model::None)
    };
    // Integrated exactly (the real-time renderers approximate the uniform environment's
    // single scattering by F_avg E, which can exceed the exact value).
    let image = render_montecarlo(
        &none,
        &shadeballs::prepared::Prepared::new(&none, &e),
        W,
        H,
        256,
        5,
    )
    .unwrap();
    let none_means = ball_means(&scene, &image);
    for (k, (b, (m_none, s_none))) in truth.balls.iter().zip(&none_means).enumerate() {
        let r = scene.balls[k].roughness;
        if r < 0.3 {
            continue;
        }
        let lum = |v: DVec3| v.dot(DVec3::new(0.2126, 0.7152, 0.0722));
        assert!(
            lum(b.mean) > lum(*m_none) + SIGMAS * lum(b.std_error + *s_none),
            "ball {k} (roughness {r}): truth {} +- {} not above none {} +- {}",
            lum(b.mean),
            lum(b.std_error),
            lum(*m_none),
            lum(*s_none)
        );
    }
}

#[test]
fn a_seed_gives_one_image_and_the_stopping_rule_stops() {
    let scene = with_model(Scene::reference(), Model::Truth);
    let t = tables(&scene);
    let e = TableSet::full(t.clone());
    let a = render_truth(
        &scene,
        &shadeballs::prepared::Prepared::new(&scene, &e),
        64,
        36,
        settings(4, u32::MAX),
        |_| true,
    )
    .unwrap();
    let b = render_truth(
        &scene,
        &shadeballs::prepared::Prepared::new(&scene, &e),
        64,
        36,
        settings(4, u32::MAX),
        |_| true,
    )
    .unwrap();
    assert_eq!(a.image, b.image);
    let c = render_truth(
        &scene,
        &shadeballs::prepared::Prepared::new(&scene, &e),
        64,
        36,
        TruthSettings {
            seed: 4,
            ..settings(4, u32::MAX)
        },
        |_| true,
    )
    .unwrap();
    assert_ne!(a.image.mean, c.image.mean);
    // A loose target stops long before the cap, and the last pass met it.
    let loose = TruthSettings {
        stderr: Some(0.05),
        ..settings(4096, u32::MAX)
    };
    let d = render_truth(
        &scene,
        &shadeballs::prepared::Prepared::new(&scene, &e),
        64,
        36,
        loose,
        |_| true,
    )
    .unwrap();
    assert!(d.image.spp < 64, "{} spp", d.image.spp);
    let last = d.passes.last().unwrap();
    assert!(last.worst_stderr.unwrap() <= 0.05, "{last:?}");
    // The callback stops it: one pass only.
    let e2 = render_truth(
        &scene,
        &shadeballs::prepared::Prepared::new(&scene, &e),
        64,
        36,
        settings(64, u32::MAX),
        |_| false,
    )
    .unwrap();
    assert_eq!(e2.image.spp, 1);
}

#[test]
fn bad_truth_settings_are_refused() {
    let scene = Scene::reference();
    let t = tables(&scene);
    let e = TableSet::full(t.clone());
    // The library states the fact (what and its range); the command line adds the flag
    // (`render_backend_truth_writes_radiance_and_standard_error`).
    for (s, needle) in [
        (
            settings(0, u32::MAX),
            "samples per pixel: 0: must be in 1..=65536",
        ),
        (
            settings(1 << 20, u32::MAX),
            "samples per pixel: 1048576: must be in 1..=65536",
        ),
        (settings(4, 0), "at least one event"),
        (
            TruthSettings {
                stderr: Some(0.0),
                ..settings(4, u32::MAX)
            },
            "standard error: 0: must be in",
        ),
    ] {
        let err = render_truth(
            &scene,
            &shadeballs::prepared::Prepared::new(&scene, &e),
            8,
            8,
            s,
            |_| true,
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains(needle), "{s:?}: {err}");
    }
}

#[test]
fn render_backend_truth_writes_radiance_and_standard_error() {
    let dir = temp_dir("truth_render");
    let out = dir.join("truth.exr");
    let (ok, stderr) = shadeballs(&[
        "render",
        "--backend",
        "truth",
        "--width",
        "64",
        "--height",
        "36",
        "--stderr",
        "2%",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert!(
        out.exists() && dir.join("truth.stderr.exr").exists(),
        "{stderr}"
    );
    assert!(stderr.contains("worst ball standard error"), "{stderr}");
    let entries: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert_eq!(entries.len(), 2, "temporary files left: {entries:?}");
    for (args, needle) in [
        (vec!["--spp", "0"], "--spp"),
        (vec!["--stderr", "0"], "relative standard error"),
        (vec!["--stderr", "150%"], "relative standard error"),
        (vec!["--stderr", "abc"], "relative standard error"),
    ] {
        let mut all = vec!["render", "--backend", "truth", "--out", "x.exr"];
        all.extend(args.iter().copied());
        let (ok, stderr) = shadeballs(&all);
        assert!(!ok && stderr.contains(needle), "{args:?}: {stderr}");
    }
}

#[test]
fn a_bogus_model_lists_the_names() {
    let text = "[[ball]]\ngrid = [0, 0]\nradius = 35\nroughness = 0.5\nmodel = \"bogus\"\n\
                material = { kind = \"metal\", albedo = [0.9, 0.6, 0.2] }\n";
    let err = shadeballs::scene::parse(text, std::path::Path::new("s.toml"))
        .unwrap_err()
        .to_string();
    for name in [
        "none",
        "kulla-conty",
        "turquin",
        "fdez-aguera",
        "truth",
        "line 5",
    ] {
        assert!(err.contains(name), "{err}");
    }
    let both = text.replace(
        "model = \"bogus\"",
        "model = \"none\"\nmultiple_scattering = true",
    );
    let err = shadeballs::scene::parse(&both, std::path::Path::new("s.toml"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("not both"), "{err}");
    let ok = text.replace("bogus", "turquin");
    let s = shadeballs::scene::parse(&ok, std::path::Path::new("s.toml")).unwrap();
    assert_eq!(s.balls[0].model, Model::Turquin);
}

/// Ctrl-C during a truth render (issue 27, 4): the render stops after its pass, writes the
/// image and its standard errors with the samples a pixel in each file and in the message,
/// and exits with 130 (128 + SIGINT), leaving no temporary file.
#[test]
fn ctrl_c_during_a_truth_render_writes_what_it_has() {
    use std::process::{Command, Stdio};
    use std::time::{Duration, Instant};
    let dir = temp_dir("truth_interrupted");
    let out = dir.join("truth.exr");
    let mut child = Command::new(env!("CARGO_BIN_EXE_shadeballs"))
        .args([
            "render",
            "--backend",
            "truth",
            "--spp",
            "65536",
            "--width",
            "320",
            "--height",
            "180",
            "--out",
            out.to_str().unwrap(),
        ])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Well inside the render (65536 estimates a pixel take minutes).
    let start = Instant::now();
    std::thread::sleep(Duration::from_millis(700));
    assert!(child.try_wait().unwrap().is_none(), "finished early");
    let stderr = interrupt(child, "INT", 130);
    // 30 s: a pass of 16 estimates a pixel at 320x180 takes well under a second here.
    assert!(start.elapsed() < Duration::from_secs(30));
    let spp = crate::truth_progress::interrupted_spp(&stderr);
    assert!(spp >= 1, "{stderr}");
    let image = image::open(&out).unwrap().to_rgba32f();
    assert_eq!(image.dimensions(), (320, 180));
    assert!(image.as_raw().iter().all(|v| v.is_finite()));
    let note = format!("{spp} spp, interrupted by SIGINT");
    let bytes = std::fs::read(&out).unwrap();
    assert!(
        bytes.windows(note.len()).any(|w| w == note.as_bytes()),
        "the EXR's comment does not say {note:?}"
    );
    let mut left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    // The sidecar too, but for a render stopped at one estimate a pixel.
    let expected = if spp >= 2 {
        vec!["truth.exr", "truth.stderr.exr"]
    } else {
        vec!["truth.exr"]
    };
    assert_eq!(left, expected, "{stderr}");
}
