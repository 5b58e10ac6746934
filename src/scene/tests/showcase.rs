//! The default scene of `render` and `view`, the showcase (`Scene::showcase`): balls that
//! stay round and fill the frame, lit by the studio map with no clipped light behind them,
//! a picture bright enough to show (issue 27's goals).

use crate::labels::{ball_rects, layout, text_width, READABLE_FRACTION};

use crate::scene::Scene;

const W: u32 = 1280;

const H: u32 = 720;

/// Most a ball's screen bounds may be wider than high (or higher than wide): the outer
/// balls sit 9.8 degrees off the axis, where a pinhole stretches them by 1.5 % (the
/// showcase camera's docs); 3 % leaves room for the bounds' pad of a pixel a side. The
/// homework's camera stretches its outer balls by over 20 %.
const MOST_STRETCH: f32 = 0.03;

#[test]
fn showcase_balls_are_round_and_fill_the_frame() {
    let scene = Scene::showcase();
    let rects: Vec<_> = ball_rects(&scene, W, H)
        .into_iter()
        .map(|r| r.expect("every ball in frame"))
        .collect();
    for r in &rects {
        let stretch = r.width() / r.height() - 1.0;
        assert!(
            stretch.abs() < MOST_STRETCH,
            "ball {r:?} stretched {stretch}"
        );
    }
    // Filling the frame: the balls span more than 65 % of the width (the homework's
    // middle 60 %: issue 27; the showcase's 67 %, capped by the viewer's narrower scene
    // area below), inside the image.
    let left = rects.iter().map(|r| r.x0).fold(f32::MAX, f32::min);
    let right = rects.iter().map(|r| r.x1).fold(f32::MIN, f32::max);
    assert!(left > 0.0 && right < W as f32, "{left}..{right}");
    assert!(right - left > 0.65 * W as f32, "{left}..{right}");
    // The viewer's scene area (980 x 720 beside its 300-point panel) holds every ball and
    // both row labels.
    let viewer = layout(&scene, 980, 720);
    assert!(ball_rects(&scene, 980, 720)
        .iter()
        .all(|r| r.is_some_and(|r| r.x0 > 0.0 && r.x1 < 980.0)));
    assert_eq!(viewer.rows.len(), 2);
    // Both axes labelled: a roughness under each of the 5 columns, a model at each row.
    let labels = layout(&scene, W, H);
    assert_eq!(labels.columns.len(), 5);
    assert_eq!(labels.rows.len(), 2);
    let rows: Vec<&str> = labels.rows.iter().map(|l| l.text.as_str()).collect();
    assert_eq!(rows, ["Kulla-Conty", "no term"]);
    assert!(scene.environment_map.is_some() && scene.lights.is_empty());
}

/// The default chart frames itself at any aspect (issue 39's goal): at 800x800, 1024x768,
/// 720x1280 and 1920x600 (and 16:9), every one of the ten balls lies whole inside the
/// frame, and both row labels and the five roughness labels fit their rooms at a readable
/// size (the viewer's floor, [`READABLE_FRACTION`] of the layout's size, with the PNG's
/// font). The camera keeps 1.4:1's horizontal field of view in a narrower frame
/// (`Camera::min_aspect`), and the labels' font follows the chart's scale.
#[test]
fn default_chart_fits_any_aspect_with_its_labels() {
    let scene = Scene::showcase();
    for (w, h) in [
        (800u32, 800u32),
        (1024, 768),
        (720, 1280),
        (1920, 600),
        (W, H),
    ] {
        let rects = ball_rects(&scene, w, h);
        assert_eq!(rects.len(), 10);
        for r in &rects {
            let r = r.unwrap_or_else(|| panic!("{w}x{h}: a ball out of frame"));
            assert!(
                r.x0 > 0.0 && r.y0 > 0.0 && r.x1 < w as f32 && r.y1 < h as f32,
                "{w}x{h}: ball {r:?} cut by the frame"
            );
        }
        let labels = layout(&scene, w, h);
        let rows: Vec<&str> = labels.rows.iter().map(|l| l.text.as_str()).collect();
        assert_eq!(rows, ["Kulla-Conty", "no term"], "{w}x{h}");
        assert_eq!(labels.columns.len(), 5, "{w}x{h}");
        for l in labels.rows.iter().chain(&labels.columns) {
            let fitted = l.fit(|t, s| text_width(t, s).unwrap());
            assert!(!fitted.is_empty(), "{w}x{h}: {:?} left out", l.text);
            for (line, p) in fitted {
                assert!(
                    p.size_px >= READABLE_FRACTION * line.size_px * (1.0 - 1e-4),
                    "{w}x{h}: {:?} at {} px of {}",
                    line.text,
                    p.size_px,
                    line.size_px
                );
            }
        }
        println!(
            "{w}x{h}: font {:.1} px, row labels at {:?}",
            labels.rows[0].size_px,
            labels.rows.iter().map(|l| l.room).collect::<Vec<_>>()
        );
    }
}

/// A row label too long for the room at the chart's left (a base colour + metallic + IOR
/// material's "metallic 0.5 · Kulla-Conty" in the viewer's 980x720 scene area at 1280x720)
/// wraps onto two lines, the material over the model, rather than vanishing.
#[test]
fn long_row_labels_wrap_rather_than_vanish() {
    let mut scene = Scene::showcase();
    for b in &mut scene.balls {
        b.material = crate::scene::Material {
            metallic: 0.5,
            ..b.material
        };
    }
    for (w, h) in [(980u32, 720u32), (800, 800), (W, H)] {
        let labels = layout(&scene, w, h);
        assert_eq!(labels.rows.len(), 2, "{w}x{h}");
        for l in &labels.rows {
            let fitted = l.fit(|t, s| text_width(t, s).unwrap());
            let texts: Vec<&str> = fitted.iter().map(|(l, _)| l.text.as_str()).collect();
            println!("{w}x{h}: {texts:?}");
            assert!(!fitted.is_empty(), "{w}x{h}: {:?} left out", l.text);
            assert!(fitted
                .iter()
                .all(|(l, p)| p.size_px >= READABLE_FRACTION * l.size_px * (1.0 - 1e-4)));
        }
    }
}
