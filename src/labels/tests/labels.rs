//! Chart labels (issue 17): where they go (the layout of the reference scene, rooms that no
//! ball reaches into, fuzzed scenes and sizes), how they are drawn (readable on black and
//! on white, nothing outside a room, no panic at any size), and what `render --labels`
//! changes: only label pixels of a `.png`, never a ball's, never an `.exr`.

use crate::labels::{
    self, ball_rects, column_label, draw_labels, layout, row_label, Align, Label, Labels, Rect,
    MIN_FONT_PX,
};

use crate::scene::{self, Camera, Model, Scene};

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
    crate::pixels::check_rooms(&scene, 1280, 720).unwrap();
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
            crate::pixels::check_rooms(&scene, w, h).unwrap();
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

/// The viewer's label image (`label_image`: one line with its halo on a transparent
/// ground, drawn as one quad a frame): as wide as the text plus its margins, transparent
/// along its edges (the halo ends inside the margin), premultiplied (no channel above its
/// opacity), and laid over black and over white as readable as a PNG's label; a size that
/// is not a positive number, or one whose image would be too big, is an error.
#[test]
fn a_label_image_is_the_text_with_its_halo_on_a_transparent_ground() {
    let (text, size) = ("r = 0.35", 16.0);
    let image = labels::label_image(text, size).unwrap();
    let (w, h, m) = (image.width, image.height, image.margin);
    let advance = labels::text_width(text, size).unwrap();
    assert_eq!(w, advance.ceil() as u32 + 2 * m);
    assert_eq!(h, size as u32 + 2 * m);
    assert_eq!(image.rgba.len(), (4 * w * h) as usize);
    let at = |x: u32, y: u32| &image.rgba[(4 * (y * w + x)) as usize..][..4];
    for x in 0..w {
        assert_eq!(at(x, 0)[3], 0, "top edge at {x}");
        assert_eq!(at(x, h - 1)[3], 0, "bottom edge at {x}");
    }
    for y in 0..h {
        assert_eq!(at(0, y)[3], 0, "left edge at {y}");
        assert_eq!(at(w - 1, y)[3], 0, "right edge at {y}");
    }
    for px in image.rgba.chunks_exact(4) {
        assert!(
            px[..3].iter().all(|&c| c <= px[3]),
            "not premultiplied: {px:?}"
        );
    }
    for ground in [0u8, 255] {
        let (mut brightest, mut darkest) = (0u8, 255u8);
        for px in image.rgba.chunks_exact(4) {
            let a = f32::from(px[3]) / 255.0;
            let v = (f32::from(px[0]) + f32::from(ground) * (1.0 - a)).round() as u8;
            if px[3] > 0 {
                brightest = brightest.max(v);
                darkest = darkest.min(v);
            }
        }
        assert!(brightest >= 200, "on {ground}: brightest {brightest}");
        assert!(darkest <= 60, "on {ground}: darkest {darkest}");
    }
    for bad in [0.0, -3.0, f32::NAN, f32::INFINITY, 1e6] {
        assert!(labels::label_image(text, bad).is_err(), "size {bad}");
    }
}
