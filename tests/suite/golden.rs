//! Golden images (assets/golden/): the Vulkan (lavapipe) rendering of the default scene in
//! both presets and of the furnace, compared per pixel.
//!
//! Bound: every channel within 1/255 of the golden and at most 0.01 % of pixels different
//! at all. Lavapipe's output is bit-identical run to run, debug or release, any thread
//! count (docs/design/machine.md, "Determinism"), so on the machine that wrote the goldens
//! the difference is 0; the slack absorbs a different Mesa/LLVM rounding a last bit. A
//! changed model or table layout moves far more pixels and fails.
//!
//! The goldens are rendered with antialiasing off (`Scene::antialias = false`, `--aa
//! off`): they are the images of before antialiasing, unchanged, which `--aa off` must
//! still give; `antialias.rs` tests the antialiased edges against a supersampled
//! reference and the interiors against these.
//!
//! On failure, `-actual` and `-difference` PNGs go to target/test-output/. Goldens are
//! rewritten only with `SHADEBALLS_UPDATE_GOLDENS=1`; a missing golden fails otherwise.
use std::path::PathBuf;

use shadeballs::output::write_png;
use shadeballs::scene::{Preset, Scene};

use crate::pixels::{compare, difference_image, output_dir, vulkan};

const W: u32 = 640;
const H: u32 = 360;

fn golden(name: &str, scene: &Scene) {
    let scene = &Scene {
        antialias: false,
        ..scene.clone()
    };
    let actual = vulkan().render_ldr(scene, W, H).unwrap().rgba;
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("assets/golden")
        .join(format!("{name}.png"));
    if std::env::var("SHADEBALLS_UPDATE_GOLDENS").is_ok_and(|v| v == "1") {
        write_png(&path, W, H, actual).unwrap();
        println!("updated {}", path.display());
        return;
    }
    let expected = match image::open(&path) {
        Ok(img) => img.to_rgba8(),
        Err(e) => panic!(
            "golden {} missing or unreadable ({e}); run with SHADEBALLS_UPDATE_GOLDENS=1 to create it",
            path.display()
        ),
    };
    assert_eq!(
        expected.dimensions(),
        (W, H),
        "golden {} has another size",
        path.display()
    );
    let d = compare(&actual, expected.as_raw(), W);
    let report = d.report(&format!("golden {name}"));
    println!("{report}");
    let differing = d.pixels - compare_exact(&actual, expected.as_raw());
    if d.max > 1 || differing as f64 > 1e-4 * d.pixels as f64 {
        let dir = output_dir();
        let diff = difference_image(&actual, expected.as_raw());
        write_png(&dir.join(format!("{name}-actual.png")), W, H, actual).unwrap();
        write_png(&dir.join(format!("{name}-difference.png")), W, H, diff).unwrap();
        panic!("{report}; {differing} pixels differ; see {}", dir.display());
    }
}

/// Pixels equal in every colour channel.
fn compare_exact(a: &[u8], b: &[u8]) -> usize {
    a.chunks_exact(4)
        .zip(b.chunks_exact(4))
        .filter(|(x, y)| x[..3] == y[..3])
        .count()
}

#[test]
fn golden_default_accurate() {
    golden("default-accurate", &Scene::reference());
}

#[test]
fn golden_default_games202() {
    golden(
        "default-games202",
        &Scene {
            preset: Preset::Games202,
            ..Scene::reference()
        },
    );
}

#[test]
fn golden_furnace() {
    golden("furnace", &Scene::furnace());
}
