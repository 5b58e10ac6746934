//! Chart labels (issue 17): where they go (the layout of the reference scene, rooms that no
//! ball reaches into, fuzzed scenes and sizes), how they are drawn (readable on black and
//! on white, nothing outside a room, no panic at any size), and what `render --labels`
//! changes: only label pixels of a `.png`, never a ball's, never an `.exr`.

use std::path::{Path, PathBuf};

use proptest::prelude::*;
use shadeballs::labels::{
    self, ball_rects, column_label, draw_labels, layout, row_label, Align, Label, Labels, Rect,
    MIN_FONT_PX,
};
use shadeballs::scene::{self, Camera, Model, Scene};

use crate::cli::{shadeballs, temp_dir};
use crate::props::run;

/// Checks the layout's promises for `scene` at `w x h`: every room inside the image, off
/// every ball's padded bounds and off every other room.
fn check_rooms(scene: &Scene, w: u32, h: u32) -> Result<(), String> {
    let l = layout(scene, w, h);
    let balls: Vec<Rect> = ball_rects(scene, w, h).into_iter().flatten().collect();
    let image = Rect {
        x0: 0.0,
        y0: 0.0,
        x1: w as f32,
        y1: h as f32,
    };
    // Each label with its wrapped lines (alternatives to it, so they may share its room),
    // tagged by the label they belong to.
    let all: Vec<(usize, &Label)> = l
        .iter()
        .enumerate()
        .flat_map(|(k, label)| {
            std::iter::once((k, label)).chain(label.wrapped.iter().map(move |w| (k, w)))
        })
        .collect();
    for (i, (k, label)) in all.iter().enumerate() {
        let r = &label.room;
        // A label whose one line found no room may still be drawn wrapped.
        let empty_but_wrapped =
            (r.width() == 0.0 || r.height() == 0.0) && !label.wrapped.is_empty();
        let fine = image.contains(r) && r.width() > 0.0 && r.height() > 0.0;
        if !(fine || empty_but_wrapped) {
            return Err(format!("{w}x{h}: room {r:?} of {:?}", label.text));
        }
        if let Some(b) = balls.iter().find(|b| b.overlaps(r)) {
            return Err(format!(
                "{w}x{h}: {:?} in {r:?} over ball {b:?}",
                label.text
            ));
        }
        if let Some((_, o)) = all[i + 1..]
            .iter()
            .find(|(j, o)| j != k && o.room.overlaps(r))
        {
            return Err(format!("{w}x{h}: {:?} over {:?}", label.text, o.text));
        }
    }
    Ok(())
}

#[test]
fn reference_layout_has_five_roughness_columns_two_rows_and_a_caption() {
    let scene = Scene::reference();
    let l = layout(&scene, 1280, 720);
    let columns: Vec<&str> = l.columns.iter().map(|c| c.text.as_str()).collect();
    // Roughness grows right to left (docs/design/reference-scene.md, "The balls, the light
    // and the camera"): left to right 0.95 first.
    assert_eq!(
        columns,
        ["r = 0.95", "r = 0.75", "r = 0.55", "r = 0.35", "r = 0.15"]
    );
    let rows: Vec<&str> = l.rows.iter().map(|r| r.text.as_str()).collect();
    assert_eq!(rows, ["Kulla-Conty", "no term"]);
    assert_eq!(l.caption.len(), 1);
    assert_eq!(
        l.caption[0].text,
        "accurate preset \u{b7} smith-correlated G \u{b7} no environment \u{b7} reinhard \u{b7} \
         exposure 1"
    );
    // Columns left to right, under the balls; rows top to bottom, left of them.
    let rects: Vec<Rect> = ball_rects(&scene, 1280, 720)
        .into_iter()
        .flatten()
        .collect();
    assert_eq!(rects.len(), 10);
    let lowest = rects.iter().map(|r| r.y1).fold(0.0, f32::max);
    // Balls 0-4 are the top row, 5-9 the bottom one.
    let leftmost = |row: &[Rect]| row.iter().map(|r| r.x0).fold(f32::MAX, f32::min);
    for pair in l.columns.windows(2) {
        assert!(pair[0].room.x1 <= pair[1].room.x0, "{pair:?}");
    }
    assert!(l.columns.iter().all(|c| c.room.y0 >= lowest));
    assert!(l.rows[0].room.y1 <= l.rows[1].room.y0);
    assert!(l.rows[0].room.x1 <= leftmost(&rects[..5]));
    assert!(l.rows[1].room.x1 <= leftmost(&rects[5..]));
    // A sensible size at 1280x720, in proportion to the height.
    assert!(l.iter().all(|x| (14.0..=18.0).contains(&x.size_px)));
    let big = layout(&scene, 2560, 1440);
    assert_eq!(big.columns.len(), 5);
    assert!((big.columns[0].size_px - 2.0 * l.columns[0].size_px).abs() < 1e-3);
    check_rooms(&scene, 1280, 720).unwrap();
}

#[test]
fn row_and_column_texts() {
    let mut ball = Scene::reference().balls[0];
    assert_eq!(row_label(&ball), "Kulla-Conty");
    for (model, text) in [
        (Model::None, "no term"),
        (Model::Turquin, "Turquin"),
        (Model::FdezAguera, "Fdez-Aguera"),
        (Model::Truth, "truth"),
    ] {
        ball.model = model;
        assert_eq!(row_label(&ball), text);
    }
    assert_eq!(column_label(&[0.5]), "r = 0.5");
    assert_eq!(column_label(&[1.0, 1.0]), "r = 1");
    assert_eq!(column_label(&[0.15, 0.35, 0.15]), "r = 0.15 / 0.35");
    let mut s = Scene::reference();
    s.preset = scene::Preset::Games202;
    s.environment = glam::DVec3::ONE;
    assert!(labels::caption(&s).starts_with("games202 preset \u{b7} schlick G"));
    assert!(
        labels::caption(&s).ends_with("uniform environment 1 \u{b7} reinhard \u{b7} exposure 1")
    );
}

/// A tight camera: the balls fill the picture. Labels that have no room are left out
/// rather than drawn over a ball; tiny and huge images lay out without panicking.
#[test]
fn tight_cameras_tiny_and_huge_images_keep_labels_off_the_balls() {
    let mut tight = Scene::reference();
    tight.camera = Camera {
        position: glam::DVec3::new(20.0, 0.0, 160.0),
        target: glam::DVec3::new(20.0, 0.0, 0.0),
        vfov_deg: 75.0,
        min_aspect: None,
    };
    let mut inside = Scene::reference();
    inside.camera.position = glam::DVec3::new(180.0, 60.0, 10.0);
    inside.camera.target = glam::DVec3::new(180.0, 60.0, -10.0);
    for scene in [Scene::reference(), tight.clone(), inside.clone()] {
        for (w, h) in [
            (1, 1),
            (16, 16),
            (64, 36),
            (320, 180),
            (1280, 720),
            (4000, 300),
            (300, 4000),
            (16384, 16384),
        ] {
            check_rooms(&scene, w, h).unwrap();
        }
    }
    // At 16x16 nothing fits: the image is left as it was.
    let l = layout(&Scene::reference(), 16, 16);
    let mut rgba = vec![7u8; 16 * 16 * 4];
    draw_labels(&mut rgba, 16, 16, &l).unwrap();
    assert!(rgba.iter().all(|&v| v == 7));
    let mut one = vec![0u8; 4];
    draw_labels(&mut one, 1, 1, &layout(&Scene::reference(), 1, 1)).unwrap();
    // Inside a ball, it covers the whole picture: no label at all.
    assert!(layout(&inside, 1280, 720).is_empty());
    // A wrong buffer is an error, not a panic.
    let e = draw_labels(&mut [0u8; 10], 16, 16, &l)
        .unwrap_err()
        .to_string();
    assert!(e.contains("1024 bytes, not 10"), "{e}");
}

/// `Label::place` shrinks a text to its room, and gives up under the smallest size.
#[test]
fn place_shrinks_to_the_room_or_leaves_the_label_out() {
    let label = |width: f32| Label {
        text: "r = 0.15".into(),
        room: Rect {
            x0: 10.0,
            y0: 20.0,
            x1: 10.0 + width,
            y1: 60.0,
        },
        align: [Align::Centre, Align::Start],
        size_px: 16.0,
        wrapped: Vec::new(),
        ellipsis: false,
    };
    let p = label(200.0).place(60.0).unwrap();
    assert_eq!(p.size_px, 16.0);
    assert!(label(200.0).room.contains(&p.outer) && p.outer.contains(&p.text));
    assert!((p.text.width() - 60.0).abs() < 1e-3);
    let p = label(40.0).place(60.0).unwrap();
    assert!(p.size_px < 16.0 && p.size_px >= MIN_FONT_PX);
    assert!(label(40.0).room.contains(&p.outer));
    assert!(label(20.0).place(60.0).is_none());
    assert!(label(200.0).place(f32::NAN).is_none());
}

/// The drawn text is light on black, has dark edges on white, and stays in its room.
#[test]
fn text_is_readable_on_black_and_on_white_and_stays_in_its_room() {
    let (w, h) = (200u32, 60u32);
    let room = Rect {
        x0: 20.0,
        y0: 10.0,
        x1: 180.0,
        y1: 50.0,
    };
    let labels = Labels {
        caption: vec![Label {
            text: "with term".into(),
            room,
            align: [Align::Centre, Align::Centre],
            size_px: 18.0,
            wrapped: Vec::new(),
            ellipsis: false,
        }],
        ..Labels::default()
    };
    for background in [0u8, 255] {
        let mut rgba: Vec<u8> = (0..w * h)
            .flat_map(|_| [background, background, background, 255])
            .collect();
        draw_labels(&mut rgba, w, h, &labels).unwrap();
        let (mut brightest, mut darkest, mut outside) = (0u8, 255u8, 0usize);
        for (i, px) in rgba.chunks_exact(4).enumerate() {
            let (x, y) = ((i as u32 % w) as f32, (i as u32 / w) as f32);
            let inside = x >= room.x0 && x + 1.0 <= room.x1 && y >= room.y0 && y + 1.0 <= room.y1;
            if px[..3] != [background; 3] {
                outside += !inside as usize;
                brightest = brightest.max(px[0]);
                darkest = darkest.min(px[0]);
            }
            assert_eq!(px[3], 255);
        }
        assert_eq!(
            outside, 0,
            "pixels changed outside the room on {background}"
        );
        assert!(brightest >= 200, "on {background}: brightest {brightest}");
        assert!(darkest <= 60, "on {background}: darkest {darkest}");
    }
}

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
    check_rooms(&s, w, h).unwrap();
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
            if let Err(e) = check_rooms(&scene, w, h) {
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
