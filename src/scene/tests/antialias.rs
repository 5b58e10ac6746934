//! Antialiased silhouettes (issue 17; docs/design/antialiasing.md): edge pixels against a
//! supersampled reference, interior pixels against the image without antialiasing, the
//! white furnace's edges, and the GPU against the CPU renderer.

use glam::DVec3;

use crate::cpu;

use crate::display::DisplayTransform;

use crate::gpu::Renderer;

use crate::scene::Scene;

use crate::pixels::{assert_close, compare, output_dir, vulkan};

/// Reference supersampling: the reference is the scene at this many times the width
/// and height, box-filtered in linear radiance.
const SCALE: u32 = 4;

/// What the geometry says about each pixel of a `w x h` image.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    /// The pixel's `SCALE x SCALE` block (the reference's samples) is partly ball, partly
    /// not.
    Edge,
    /// The whole block on one ball, and the centre ray more than 1.5 pixel footprints inside
    /// its silhouette and more than 1.5 from any other ball's.
    Interior,
    /// Anything else (all background, or near a silhouette without a sample across it).
    Other,
}

/// The nearest ball the ray in unit direction `d` from the eye hits, if any (f64).
fn nearest(scene: &Scene, o: DVec3, d: DVec3) -> Option<usize> {
    cpu::nearest_ball(scene, o, d).map(|(_, k)| k)
}

/// Each pixel's [`Kind`], from the f64 rays through the centres of the reference image's
/// pixels (the pixel's `SCALE x SCALE` block).
fn classify(scene: &Scene, w: u32, h: u32) -> Vec<Kind> {
    use rayon::prelude::*;
    let basis = scene.camera.basis(w, h);
    let angle = basis.pixel_angle(w, h);
    let o = basis.origin;
    (0..h)
        .into_par_iter()
        .flat_map_iter(|py| {
            (0..w).map(move |px| {
                // Balls whose silhouette passes near the pixel (within 1.5 footprints).
                let d = basis.ray(px, py, w, h);
                let distance = |b: &crate::scene::Ball| {
                    let oc = o - b.center;
                    let perp = (oc - oc.dot(d) * d).length();
                    (perp - b.radius) / (oc.length() * angle)
                };
                if scene.balls.iter().all(|b| distance(b) > 1.5) {
                    return Kind::Other; // Far from every ball: background.
                }
                let n = SCALE as f64;
                let mut hits = Vec::with_capacity((SCALE * SCALE) as usize);
                for j in 0..SCALE {
                    for i in 0..SCALE {
                        let x = px as f64 + (i as f64 + 0.5) / n;
                        let y = py as f64 + (j as f64 + 0.5) / n;
                        hits.push(nearest(scene, o, basis.ray_at(x, y, w, h)));
                    }
                }
                let any = hits.iter().any(Option::is_some);
                let all = hits.iter().all(Option::is_some);
                if any && !all {
                    return Kind::Edge;
                }
                let inner = hits[0].filter(|&k| {
                    hits.iter().all(|&x| x == Some(k))
                        && scene.balls.iter().enumerate().all(|(i, b)| {
                            let s = distance(b);
                            if i == k {
                                s < -1.5
                            } else {
                                s.abs() > 1.5
                            }
                        })
                });
                if inner.is_some() {
                    Kind::Interior
                } else {
                    Kind::Other
                }
            })
        })
        .collect()
}

/// The reference: `scene` rendered on the GPU at `SCALE` times `w x h` as linear radiance
/// (what `render --out x.exr` writes), box-filtered over each `SCALE x SCALE` block in
/// linear radiance, then exposure, the scene's display transform and 8-bit quantisation
/// (`cpu::to_display_rgba8`, the CPU twin of the shader's).
fn reference(r: &mut Renderer, scene: &Scene, w: u32, h: u32) -> Vec<u8> {
    let (bw, bh) = (w * SCALE, h * SCALE);
    let big = r.render_hdr(scene, bw, bh).unwrap().rgba;
    let mut radiance = vec![DVec3::ZERO; (w * h) as usize];
    for y in 0..bh {
        for x in 0..bw {
            let i = 4 * (y * bw + x) as usize;
            let c = DVec3::new(big[i] as f64, big[i + 1] as f64, big[i + 2] as f64);
            radiance[((y / SCALE) * w + x / SCALE) as usize] += c;
        }
    }
    for c in &mut radiance {
        *c /= (SCALE * SCALE) as f64;
    }
    cpu::to_display_rgba8(&radiance, scene.exposure, scene.display())
}

/// The largest channel difference of pixel `p` between two RGBA8 images, in 1/255.
fn pixel_diff(a: &[u8], b: &[u8], p: usize) -> u8 {
    (0..3)
        .map(|c| a[4 * p + c].abs_diff(b[4 * p + c]))
        .max()
        .unwrap()
}

/// p99 and max of the edge pixels' error against the reference, the error image, and
/// the number of edge pixels; prints them.
fn edge_error(image: &[u8], reference: &[u8], kinds: &[Kind], what: &str) -> (u8, u8, usize) {
    let mut errors: Vec<u8> = (0..kinds.len())
        .filter(|&p| kinds[p] == Kind::Edge)
        .map(|p| pixel_diff(image, reference, p))
        .collect();
    errors.sort_unstable();
    let n = errors.len();
    assert!(n > 0, "{what}: no edge pixels");
    let p99 = errors[((n as f64 * 0.99).ceil() as usize).min(n) - 1];
    let max = errors[n - 1];
    let mean = errors.iter().map(|&e| e as f64).sum::<f64>() / n as f64;
    println!("{what}: {n} edge pixels, error against the reference: p99 {p99}/255, max {max}/255, mean {mean:.2}/255");
    (p99, max, n)
}

/// Writes an image for looking at when a bound fails.
fn save(name: &str, w: u32, h: u32, rgba: Vec<u8>) -> String {
    let path = output_dir().join(name);
    crate::output::write_png(&path, w, h, rgba).unwrap();
    path.display().to_string()
}

/// The goal: at 1280x720, edge pixels within 3/255 (p99) of the reference: the
/// same scene at 4x the width and height (antialiased as by default, so each of its pixels
/// takes the analytic coverage too), box-filtered in linear radiance, tone-mapped and
/// quantised as the PNG is.
///
/// THE GOAL IS NOT MET: measured p99 6/255, max 16/255, mean 0.68/255 (without
/// antialiasing: p99 46, max 53, mean 9.2). The remaining error is the one shading sample
/// of an edge pixel (at the centroid of its covered part) where radiance changes steeply
/// across the pixel (the rims near the terminator), amplified by the tone map's gamma on
/// a black background. The bound below is that measurement (6), held so that it does not
/// grow, not the goal; docs/benchmarks.md, "Antialiasing".
#[test]
fn edges_match_the_supersampled_reference() {
    let (w, h) = (1280, 720);
    let mut r = vulkan();
    let scene = Scene::reference();
    let kinds = classify(&scene, w, h);
    let reference = reference(&mut r, &scene, w, h);
    let image = r.render_ldr(&scene, w, h).unwrap().rgba;
    let off = r
        .render_ldr(
            &Scene {
                antialias: false,
                ..scene.clone()
            },
            w,
            h,
        )
        .unwrap()
        .rgba;
    let (p99_off, max_off, _) = edge_error(&off, &reference, &kinds, "default scene, --aa off");
    let (p99, max, _) = edge_error(&image, &reference, &kinds, "default scene, --aa on");
    // Against a reference without antialiasing of its own (16 point samples a pixel): for
    // comparison only.
    let plain = Scene {
        antialias: false,
        ..scene.clone()
    };
    let reference_plain = self::reference(&mut r, &plain, w, h);
    edge_error(
        &image,
        &reference_plain,
        &kinds,
        "default scene, --aa on against the 4x reference without antialiasing",
    );
    println!("without antialiasing: p99 {p99_off}, max {max_off}; with: p99 {p99}, max {max}");
    if p99 > 6 {
        let a = save("aa-edges-image.png", w, h, image);
        save("aa-edges-reference.png", w, h, reference);
        panic!("edge p99 {p99}/255 > 6/255, the measured figure (max {max}); see {a}");
    }
}

/// The same under the studio environment map (a background that varies along each ray,
/// and bright rims): 640x360 to keep the 4x reference small. The goal is 3/255 at
/// p99; NOT MET: measured p99 6/255, max 12/255, mean 1.29/255 under the homework's
/// display (Reinhard, gamma 2.2), held at 6 (the measured figure, as above). Under the
/// scene's own display since the accurate preset's became Khronos PBR Neutral with the
/// sRGB curve (steeper in the darks the rims pass through): measured p99 8/255, max 20,
/// held at 8.
#[test]
fn edges_match_the_reference_under_an_environment_map() {
    let (w, h) = (640, 360);
    let mut r = vulkan();
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/studio.toml");
    let own = crate::scene::load(&path).unwrap();
    assert!(own.antialias, "antialiasing is on by default");
    let homework = Scene {
        tone_map: Some(DisplayTransform::HOMEWORK.tone_map),
        transfer: Some(DisplayTransform::HOMEWORK.transfer),
        ..own.clone()
    };
    // (scene, what, the measured bound above).
    for (scene, what, bound) in [
        (&homework, "studio, Reinhard + gamma 2.2", 6),
        (&own, "studio, its own display", 8),
    ] {
        let kinds = classify(scene, w, h);
        let reference = reference(&mut r, scene, w, h);
        let image = r.render_ldr(scene, w, h).unwrap().rgba;
        let (p99, max, _) = edge_error(&image, &reference, &kinds, what);
        assert!(
            p99 <= bound,
            "{what}: edge p99 {p99}/255 > {bound}/255 (max {max})"
        );
    }
}

/// Interior pixels (the whole 4x4 block on one ball, more than 1.5 pixels from any
/// silhouette) are those of the image without antialiasing, bit for bit: they take the
/// same single-sample path. Background pixels far from every ball likewise.
#[test]
fn interior_pixels_are_unchanged() {
    let (w, h) = (1280, 720);
    let mut r = vulkan();
    for scene in [Scene::reference(), Scene::furnace()] {
        let kinds = classify(&scene, w, h);
        let on = r.render_ldr(&scene, w, h).unwrap().rgba;
        let off_scene = Scene {
            antialias: false,
            ..scene.clone()
        };
        let off = r.render_ldr(&off_scene, w, h).unwrap().rgba;
        let interior: Vec<usize> = (0..kinds.len())
            .filter(|&p| kinds[p] == Kind::Interior)
            .collect();
        let changed = interior
            .iter()
            .filter(|&&p| pixel_diff(&on, &off, p) != 0)
            .count();
        let edges = kinds.iter().filter(|&&k| k == Kind::Edge).count();
        let all_changed = (0..kinds.len())
            .filter(|&p| pixel_diff(&on, &off, p) != 0)
            .count();
        println!(
            "{} interior pixels, {changed} changed by antialiasing; {edges} edge pixels; \
             {all_changed} pixels changed in all",
            interior.len()
        );
        assert!(interior.len() > 50_000);
        assert_eq!(changed, 0);
        // The linear values too (the bits, on the .exr path).
        let on = r.render_hdr(&scene, w, h).unwrap().rgba;
        let off = r.render_hdr(&off_scene, w, h).unwrap().rgba;
        let changed = interior
            .iter()
            .filter(|&&p| on[4 * p..4 * p + 3] != off[4 * p..4 * p + 3])
            .count();
        assert_eq!(changed, 0, "linear radiance of interior pixels changed");
    }
}

/// The white furnace: a ball with the term vanishes into the background, its edge pixels
/// too (a mix of the ball's radiance, ~1, and the background's, 1). Bound 2/255: the one
/// the furnace test holds the balls' interiors to (`render.rs`).
#[test]
fn furnace_edges_stay_background() {
    let (w, h) = (640, 360);
    let scene = Scene::furnace();
    let kinds = classify(&scene, w, h);
    let image = vulkan().render_ldr(&scene, w, h).unwrap().rgba;
    let bg = crate::display::to_unorm8(crate::display::tone_map(1.0, scene.exposure));
    let basis = scene.camera.basis(w, h);
    let mut worst = 0u8;
    let mut n = 0;
    for (p, _) in kinds.iter().enumerate().filter(|(_, &k)| k == Kind::Edge) {
        let (px, py) = ((p as u32) % w, (p as u32) / w);
        // Edge pixels of the balls with the term (the top row) only: the ball whose
        // silhouette passes nearest the pixel's centre ray (in angle).
        let d = basis.ray(px, py, w, h);
        let near = scene.balls.iter().enumerate().min_by(|(_, a), (_, b)| {
            let off = |x: &&crate::scene::Ball| {
                let oc = basis.origin - x.center;
                ((oc - oc.dot(d) * d).length() - x.radius).abs() / oc.length()
            };
            off(a).total_cmp(&off(b))
        });
        if near.is_some_and(|(_, b)| b.model.has_term()) {
            n += 1;
            worst = worst.max((0..3).map(|c| image[4 * p + c].abs_diff(bg)).max().unwrap());
        }
    }
    println!(
        "furnace: {n} edge pixels of balls with the term, max |pixel - background| {worst}/255"
    );
    assert!(n > 500);
    assert!(worst <= 2, "{worst}");
}

/// The CPU renderer antialiases with the same samples: its image against the GPU's within
/// the GPU-vs-CPU bound (`pixels::assert_close`), default scene and studio map.
/// (`render.rs` compares the default scene and the furnace, on by default, on Vulkan and
/// GL, too.)
#[test]
fn cpu_antialiases_like_the_gpu() {
    let (w, h) = (1280, 720);
    let mut r = vulkan();
    let scene = Scene::reference();
    let (gpu, cpu) = crate::pixels::both(&mut r, &scene, w, h);
    let d = compare(&gpu, &cpu, w);
    assert_close(&d, "Vulkan vs CPU, antialiased, default scene");
    let kinds = classify(&scene, w, h);
    let edge_max = (0..kinds.len())
        .filter(|&p| kinds[p] == Kind::Edge)
        .map(|p| pixel_diff(&gpu, &cpu, p))
        .max()
        .unwrap();
    println!("edge pixels: GPU vs CPU at most {edge_max}/255");
}
