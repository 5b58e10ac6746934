//! The README's pictures are what their commands draw now: each line of
//! tests/readme_pictures.txt (`PICTURE: ARGUMENTS`, the commands
//! `bash tests/readme_pictures.sh` runs) is rendered again by the real binary and compared
//! with the committed picture. A picture left behind by a change to the scene, the model,
//! the labels or the shaders fails here; `bash tests/readme_pictures.sh` redraws them.
use std::path::{Path, PathBuf};

use crate::cli::{shadeballs, temp_dir};
use crate::pixels::{difference_image, output_dir};

/// Largest channel difference, in 1/255 steps, that still counts as the same pixel: the
/// commands name Vulkan, and lavapipe draws the same bits run to run (golden.rs), so on
/// the machine that drew the pictures nothing differs; 2 absorbs another Mesa/LLVM's
/// rounding of a last bit (the GPU against the CPU reference differs by up to 1:
/// docs/accuracy.md) twice over.
const SAME_PIXEL_STEPS: u8 = 2;
/// Most pixels that may differ by more than [`SAME_PIXEL_STEPS`]: 0.01 %, the goldens'
/// bound (golden.rs). A changed label ("with term" against "Kulla-Conty") alone moves
/// some 500 pixels of a 960 x 540 picture (0.1 %), a changed scene or model far more.
const MOST_DIFFERENT_FRACTION: f64 = 1e-4;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The (picture, arguments) pairs of tests/readme_pictures.txt.
fn pictures() -> Vec<(String, Vec<String>)> {
    let text = std::fs::read_to_string(root().join("tests/readme_pictures.txt")).unwrap();
    text.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(|l| {
            let (picture, args) = l.split_once(':').expect("PICTURE: ARGUMENTS");
            let args = args.split_whitespace().map(str::to_string).collect();
            (picture.trim().to_string(), args)
        })
        .collect()
}

/// Pixels of two RGBA8 images of the same size whose colour differs by more than
/// [`SAME_PIXEL_STEPS`] in some channel.
fn differing(a: &[u8], b: &[u8]) -> usize {
    a.chunks_exact(4)
        .zip(b.chunks_exact(4))
        .filter(|(x, y)| (0..3).any(|c| x[c].abs_diff(y[c]) > SAME_PIXEL_STEPS))
        .count()
}

fn check(picture: &str, args: &[String], dir: &Path) {
    let out = dir.join(Path::new(picture).file_name().unwrap());
    let mut argv: Vec<&str> = args.iter().map(String::as_str).collect();
    argv.extend(["--out", out.to_str().unwrap()]);
    // Relative scene paths in the list are from the repository root.
    let argv: Vec<String> = argv
        .iter()
        .map(|a| {
            if a.starts_with("assets/") {
                root().join(a).to_string_lossy().into_owned()
            } else {
                a.to_string()
            }
        })
        .collect();
    let argv: Vec<&str> = argv.iter().map(String::as_str).collect();
    let (ok, stderr) = shadeballs(&argv);
    assert!(ok, "{picture}: {stderr}");
    let now = image::open(&out).unwrap().to_rgba8();
    let committed = image::open(root().join(picture))
        .unwrap_or_else(|e| panic!("{picture}: {e}; run bash tests/readme_pictures.sh"))
        .to_rgba8();
    assert_eq!(
        now.dimensions(),
        committed.dimensions(),
        "{picture} has another size than its command draws; run bash tests/readme_pictures.sh"
    );
    let n = differing(now.as_raw(), committed.as_raw());
    let pixels = (now.width() * now.height()) as f64;
    println!("{picture}: {n} pixels differ by more than {SAME_PIXEL_STEPS}/255");
    if n as f64 > MOST_DIFFERENT_FRACTION * pixels {
        let name = Path::new(picture).file_stem().unwrap().to_string_lossy();
        let diff = difference_image(now.as_raw(), committed.as_raw());
        let path = output_dir().join(format!("readme-{name}-difference.png"));
        shadeballs::output::write_png(&path, now.width(), now.height(), diff).unwrap();
        panic!(
            "{picture} is stale: {n} pixels differ from what `shadeballs {}` draws now (see {}); \
             run bash tests/readme_pictures.sh",
            args.join(" "),
            path.display()
        );
    }
}

#[test]
fn readme_pictures_are_what_their_commands_draw() {
    let list = pictures();
    assert!(
        !list.is_empty(),
        "tests/readme_pictures.txt lists no picture"
    );
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let dir = temp_dir("readme-pictures");
    for (picture, args) in &list {
        assert!(
            readme.contains(&format!("]({picture})")),
            "the README does not show {picture}"
        );
        check(picture, args, &dir);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every picture the README shows is in the list, so none is left out of the check above.
/// (docs/viewer.md's window screenshot, assets/viewer.png, is not shown in the README: its
/// panel prints frame times, which no two runs share.)
#[test]
fn every_readme_picture_has_a_command() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let listed: Vec<String> = pictures().into_iter().map(|(p, _)| p).collect();
    for shown in readme
        .split("](")
        .skip(1)
        .filter_map(|s| s.split(')').next())
    {
        if shown.ends_with(".png") {
            assert!(
                listed.iter().any(|p| p == shown),
                "README shows {shown}, which tests/readme_pictures.txt does not list"
            );
        }
    }
}
