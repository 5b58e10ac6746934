//! The default scene of `render` and `view`, the showcase (`Scene::showcase`): balls that
//! stay round and fill the frame, lit by the studio map with no clipped light behind them,
//! a picture bright enough to show (issue 27's goals).

use shadeballs::labels::{ball_rects, layout};

use shadeballs::scene::Scene;

use crate::cli::{shadeballs, temp_dir};

const W: u32 = 1280;

const H: u32 = 720;

/// Mean of every channel of every pixel the default `render` writes must exceed 60/255
/// (issue 27's goal; the homework's scene gives 3.4). The background, where no ball's
/// bounds reach, must show no clipped light: the studio's grey gradient (at most 0.12,
/// times the showcase's exposure 1.5) tone-maps to at most Khronos PBR Neutral's
/// 0.18 - 0.04 = 0.14, sRGB-encoded 105/255, and 160 leaves room for the balls' antialiased
/// edges' glow while any softbox (radiance 4.5 and up: 200/255 and more) fails.
#[test]
fn default_render_is_bright_and_shows_no_clipped_light() {
    let dir = temp_dir("showcase");
    let out = dir.join("default.png");
    let (ok, stderr) = shadeballs(&[
        "render",
        "--backend",
        "vulkan",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let image = image::open(&out).unwrap().to_rgb8();
    assert_eq!(image.dimensions(), (W, H));
    let sum: u64 = image.as_raw().iter().map(|&v| u64::from(v)).sum();
    let mean = sum as f64 / image.as_raw().len() as f64;
    println!("default render: mean pixel {mean:.1}/255");
    assert!(mean > 60.0, "mean pixel {mean:.1}/255");
    let scene = Scene::showcase();
    let rects: Vec<_> = ball_rects(&scene, W, H).into_iter().flatten().collect();
    let labels = layout(&scene, W, H);
    let brightest = image
        .enumerate_pixels()
        .filter(|(x, y, _)| {
            let (x, y) = (*x as f32 + 0.5, *y as f32 + 0.5);
            let inside =
                |r: &shadeballs::labels::Rect| x >= r.x0 && x <= r.x1 && y >= r.y0 && y <= r.y1;
            !rects.iter().any(inside) && !labels.iter().any(|l| inside(&l.room))
        })
        .map(|(_, _, p)| p.0.into_iter().max().unwrap())
        .max()
        .unwrap();
    assert!(brightest < 160, "the background reaches {brightest}/255");
    std::fs::remove_dir_all(&dir).unwrap();
}
