//! Chart labels (issue 17): where they go (the layout of the reference scene, rooms that no
//! ball reaches into, fuzzed scenes and sizes), how they are drawn (readable on black and
//! on white, nothing outside a room, no panic at any size), and what `render --labels`
//! changes: only label pixels of a `.png`, never a ball's, never an `.exr`.

use std::path::{Path, PathBuf};

use proptest::prelude::*;

use shadeballs::labels::{self, ball_rects, draw_labels, layout, Rect};

use shadeballs::scene::{self, Scene};

use crate::cli::{shadeballs, temp_dir};

use crate::props::run;

/// Scene files: `labels` parses in every build, defaults to off, and a wrong type is a
/// one-line error with its line and column.
#[test]
fn scene_key_labels() {
    let ball = "[[ball]]\ngrid = [0, 0]\nradius = 35\nroughness = 0.5\n\
                material = { kind = \"metal\", f0 = [1, 1, 1] }\n";
    let parse = |text: &str| scene::parse(text, Path::new("s.toml"));
    assert!(!parse(ball).unwrap().labels);
    assert!(parse(&format!("labels = true\n{ball}")).unwrap().labels);
    let e = parse(&format!("exposure = 1\nlabels = \"yes\"\n{ball}"))
        .unwrap_err()
        .to_string();
    println!("{e}");
    assert!(
        e.contains("s.toml") && e.contains("line 2, column 10") && e.contains("labels"),
        "{e}"
    );
    assert!(!e.contains('\n'));
    assert!(Scene::reference().labels && Scene::furnace().labels);
}

/// A ball's `label` key: its text under the ball (the column's roughness label then
/// gone), shortened with an ellipsis to the column where it is too long; blank, multi-line
/// or over-long text is a one-line error with its line.
#[test]
fn ball_label_key_is_drawn_under_its_ball_and_shortened_to_its_column() {
    let ball = |label: &str, col: u32| {
        format!(
            "[[ball]]\ngrid = [0, {col}]\nradius = 35\nroughness = 0.5\nlabel = {label}\n\
             material = {{ kind = \"metal\", f0 = [1, 1, 1] }}\n"
        )
    };
    let parse = |text: &str| scene::parse(text, Path::new("s.toml"));
    let long = "a material name far too long for the column it stands in";
    let text = format!(
        "labels = true\n{}{}[[ball]]\ngrid = [0, 2]\nradius = 35\nroughness = 0.5\n\
         material = {{ kind = \"metal\", f0 = [1, 1, 1] }}\n",
        ball("\"gold\"", 0),
        ball(&format!("\"{long}\""), 1)
    );
    let s = parse(&text).unwrap();
    assert_eq!(s.balls[0].label.unwrap().as_str(), "gold");
    assert!(s.balls[2].label.is_none());
    let (w, h) = (1280, 720);
    crate::pixels::check_rooms(&s, w, h).unwrap();
    let l = layout(&s, w, h);
    assert_eq!(l.balls.len(), 2);
    assert_eq!(
        l.columns.len(),
        1,
        "the unlabelled ball's column keeps its own"
    );
    let width_at = |t: &str, size: f32| labels::text_width(t, size).unwrap();
    let mut fitted: Vec<_> = l.balls.iter().flat_map(|b| b.fit(width_at)).collect();
    assert_eq!(fitted.len(), 2);
    // Grid column 0 is the rightmost: its label comes last, left to right.
    fitted.reverse();
    let (gold, gold_at) = &fitted[0];
    assert_eq!(gold.text, "gold");
    assert!(
        gold_at.size_px >= gold.size_px * (1.0 - 1e-4),
        "{gold_at:?}"
    );
    let (short, at) = &fitted[1];
    println!("{:?} at {} px in {:?}", short.text, at.size_px, short.room);
    assert!(short.text.ends_with(scene::ELLIPSIS), "{}", short.text);
    assert!(long.starts_with(short.text.trim_end_matches(scene::ELLIPSIS)));
    assert!(short.text.chars().count() > 3, "{}", short.text);
    assert!(at.size_px >= labels::READABLE_FRACTION * short.size_px * (1.0 - 1e-4));
    assert!(short.room.contains(&at.outer));
    // Drawn: pixels change under each labelled ball.
    let mut rgba = vec![0u8; (w * h * 4) as usize];
    assert_eq!(draw_labels(&mut rgba, w, h, &l).unwrap(), l.iter().count());
    for bad in [
        "\"\"".to_string(),
        "\"two\\nlines\"".to_string(),
        format!("\"{}\"", "x".repeat(scene::MAX_BALL_LABEL_BYTES + 1)),
        "3".to_string(),
    ] {
        let e = parse(&format!("labels = true\n{}", ball(&bad, 0)))
            .unwrap_err()
            .to_string();
        println!("{e}");
        assert!(!e.contains('\n') && e.contains("line 6"), "{e}");
    }
}

/// Accepted fuzzed scene files lay out and draw at several sizes without panicking, and
/// their rooms keep the layout's promises.
#[test]
fn fuzzed_scenes_lay_out_and_draw_without_panics() {
    run(300, crate::scene_gen::scene_text(), |text| {
        let Ok(scene) = scene::parse(&text, Path::new("fuzz.toml")) else {
            return Ok(());
        };
        for (w, h) in [(9, 5), (400, 400), (1280, 720)] {
            if let Err(e) = crate::pixels::check_rooms(&scene, w, h) {
                return Err(TestCaseError::fail(format!("{e} for {text:?}")));
            }
            let mut rgba = vec![0u8; 4 * w as usize * h as usize];
            draw_labels(&mut rgba, w, h, &layout(&scene, w, h)).unwrap();
        }
        Ok(())
    });
}

/// An RGBA8 PNG's pixels and size.
fn png(path: &Path) -> (Vec<u8>, u32, u32) {
    let img = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8();
    let (w, h) = img.dimensions();
    (img.into_raw(), w, h)
}

/// `shadeballs render` with `extra` flags to `dir/name`; the output's path.
fn render(dir: &Path, name: &str, extra: &[&str]) -> PathBuf {
    let out = dir.join(name);
    let mut args = vec!["render", "--out", out.to_str().unwrap()];
    args.extend(extra);
    let (ok, stderr) = shadeballs(&args);
    assert!(ok, "{args:?}: {stderr}");
    out
}

/// A labelled picture differs from the unlabelled one only inside the label rooms (never
/// inside a ball's bounds), and differs under every column, at each row and in the
/// caption; on the GPU, the CPU reference renderer and the Monte Carlo backend.
#[test]
fn labelled_png_differs_only_in_label_rooms() {
    let dir = temp_dir("labels-png");
    let scene = Scene::reference();
    for (backend, w, h) in [
        ("vulkan", 1280u32, 720u32),
        ("cpu", 640, 360),
        ("montecarlo", 640, 360),
    ] {
        let size = ["--width", &w.to_string(), "--height", &h.to_string()].map(String::from);
        let homework = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/homework.toml");
        let mut flags: Vec<&str> = vec!["--backend", backend, "--spp", "1", "--scene", homework];
        flags.extend(size.iter().map(String::as_str));
        // The homework's scene file has labels on; --no-labels turns them off.
        let on = render(&dir, &format!("{backend}-on.png"), &flags);
        let off = render(
            &dir,
            &format!("{backend}-off.png"),
            &[&flags[..], &["--no-labels"]].concat(),
        );
        let (a, aw, ah) = png(&on);
        let (b, ..) = png(&off);
        assert_eq!((aw, ah), (w, h));
        let l = layout(&scene, w, h);
        assert_eq!((l.columns.len(), l.rows.len(), l.caption.len()), (5, 2, 1));
        let balls: Vec<Rect> = ball_rects(&scene, w, h).into_iter().flatten().collect();
        let mut in_room = vec![0usize; l.iter().count()];
        for (i, (p, q)) in a.chunks_exact(4).zip(b.chunks_exact(4)).enumerate() {
            if p == q {
                continue;
            }
            let (x, y) = ((i as u32 % w) as f32 + 0.5, (i as u32 / w) as f32 + 0.5);
            let at = |r: &Rect| x > r.x0 && x < r.x1 && y > r.y0 && y < r.y1;
            assert!(
                !balls.iter().any(at),
                "{backend}: ball pixel ({x}, {y}) changed"
            );
            let room = l.iter().position(|label| at(&label.room));
            let k =
                room.unwrap_or_else(|| panic!("{backend}: ({x}, {y}) changed outside the rooms"));
            in_room[k] += 1;
        }
        println!("{backend} {w}x{h}: changed pixels per label {in_room:?}");
        assert!(in_room.iter().all(|&n| n >= 20), "{backend}: {in_room:?}");
    }
}

/// `--labels` turns them on for a scene file without them; an `.exr` is the same with or
/// without.
#[test]
fn labels_flag_and_exr() {
    let dir = temp_dir("labels-flag");
    let one = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/one_ball.toml");
    let base = [
        "--scene",
        one,
        "--backend",
        "vulkan",
        "--width",
        "640",
        "--height",
        "360",
    ];
    let (plain, ..) = png(&render(&dir, "plain.png", &base));
    let (labelled, ..) = png(&render(
        &dir,
        "labelled.png",
        &[&base[..], &["--labels"]].concat(),
    ));
    assert_ne!(plain, labelled, "--labels drew nothing");
    // The last of --labels / --no-labels wins.
    let (off, ..) = png(&render(
        &dir,
        "off.png",
        &[&base[..], &["--labels", "--no-labels"]].concat(),
    ));
    assert_eq!(plain, off);
    let exr = |name: &str, extra: &[&str]| {
        let path = render(&dir, name, &[&base[..], extra].concat());
        image::open(path).unwrap().into_rgba32f().into_raw()
    };
    assert_eq!(
        exr("plain.exr", &["--no-labels"]),
        exr("labelled.exr", &["--labels"])
    );
}
