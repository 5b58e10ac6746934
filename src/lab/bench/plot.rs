//! Log-log plots as PNG: one curve per series (a method, a layout), decade grid lines and
//! labels, a legend by colour, dashed goal lines. Drawn with the `image` crate; text with
//! `ab_glyph` from the Hack font embedded in `epaint_default_fonts` (no system fonts, no
//! download).

use std::path::Path;

use ab_glyph::{Font, FontRef, PxScale, ScaleFont};
use image::{Rgb, RgbImage};

use crate::error::{Error, Result};
use crate::output::write_atomic;

const W: u32 = 1000;
const H: u32 = 640;
const LEFT: f64 = 90.0;
const RIGHT: f64 = 290.0;
const TOP: f64 = 50.0;
const BOTTOM: f64 = 70.0;

/// Colours of the series, in order (a colour-blind-safe set: Wong 2011, Nature Methods).
const PALETTE: [[u8; 3]; 7] = [
    [0, 114, 178],
    [213, 94, 0],
    [0, 158, 115],
    [204, 121, 167],
    [230, 159, 0],
    [86, 180, 233],
    [120, 120, 120],
];

/// One curve: points joined in order of x unless `points_only`; `peer` series (the
/// homework's) are black squares, unjoined.
#[derive(Clone, Debug, Default)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub peer: bool,
    pub points_only: bool,
}

/// A log-log plot; `goals` are dashed lines at `(label, Some(x), None)` (vertical) or
/// `(label, None, Some(y))` (horizontal).
#[derive(Clone, Debug, Default)]
pub struct Plot {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    pub goals: Vec<(String, Option<f64>, Option<f64>)>,
}

struct Canvas {
    img: RgbImage,
    font: FontRef<'static>,
}

impl Canvas {
    fn blend(&mut self, x: i64, y: i64, c: [u8; 3], a: f32) {
        if x < 0 || y < 0 || x >= W as i64 || y >= H as i64 || a <= 0.0 {
            return;
        }
        let p = self.img.get_pixel_mut(x as u32, y as u32);
        for (channel, &target) in p.0.iter_mut().zip(&c) {
            *channel = (*channel as f32 * (1.0 - a) + target as f32 * a).round() as u8;
        }
    }

    fn disc(&mut self, cx: f64, cy: f64, r: f64, c: [u8; 3]) {
        let (x0, x1) = ((cx - r - 1.0) as i64, (cx + r + 1.0) as i64);
        let (y0, y1) = ((cy - r - 1.0) as i64, (cy + r + 1.0) as i64);
        for y in y0..=y1 {
            for x in x0..=x1 {
                let d = ((x as f64 + 0.5 - cx).powi(2) + (y as f64 + 0.5 - cy).powi(2)).sqrt();
                self.blend(x, y, c, (r + 0.5 - d).clamp(0.0, 1.0) as f32);
            }
        }
    }

    fn square(&mut self, cx: f64, cy: f64, r: f64, c: [u8; 3]) {
        for y in (cy - r) as i64..=(cy + r) as i64 {
            for x in (cx - r) as i64..=(cx + r) as i64 {
                self.blend(x, y, c, 1.0);
            }
        }
    }

    /// A line of width `2 r`, dashed when `dash` > 0 (dash and gap length in pixels).
    fn line(&mut self, a: (f64, f64), b: (f64, f64), r: f64, c: [u8; 3], dash: f64) {
        let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
        let steps = (len * 2.0).ceil().max(1.0) as usize;
        for s in 0..=steps {
            let t = s as f64 / steps as f64;
            if dash > 0.0 && (t * len / dash) as usize % 2 == 1 {
                continue;
            }
            self.disc(a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t, r, c);
        }
    }

    fn text_width(&self, s: &str, size: f32) -> f64 {
        let f = self.font.as_scaled(PxScale::from(size));
        s.chars().map(|ch| f.h_advance(f.glyph_id(ch)) as f64).sum()
    }

    /// Text with its baseline starting at `(x, y)`.
    fn text(&mut self, s: &str, x: f64, y: f64, size: f32, c: [u8; 3]) {
        let scale = PxScale::from(size);
        let mut pen = x as f32;
        for ch in s.chars() {
            let id = self.font.glyph_id(ch);
            let glyph = id.with_scale_and_position(scale, ab_glyph::point(pen, y as f32));
            pen += self.font.as_scaled(scale).h_advance(id);
            if let Some(outline) = self.font.outline_glyph(glyph) {
                let b = outline.px_bounds();
                let mut cover = Vec::new();
                outline.draw(|gx, gy, a| cover.push((gx, gy, a)));
                for (gx, gy, a) in cover {
                    self.blend(b.min.x as i64 + gx as i64, b.min.y as i64 + gy as i64, c, a);
                }
            }
        }
    }
}

/// A decade's label: plain for 0.01 ... 1000, else `1e-5`.
fn decade_label(k: i32) -> String {
    match k {
        -2..=3 => format!("{}", 10f64.powi(k)),
        _ => format!("1e{k}"),
    }
}

/// Writes `plot` to `path` (PNG).
pub fn write(plot: &Plot, path: &Path) -> Result<()> {
    let font =
        FontRef::try_from_slice(epaint_default_fonts::HACK_REGULAR).map_err(|e| Error::Encode {
            path: path.to_path_buf(),
            message: format!("embedded font: {e}"),
        })?;
    let mut c = Canvas {
        img: RgbImage::from_pixel(W, H, Rgb([255, 255, 255])),
        font,
    };
    let pts = plot.series.iter().flat_map(|s| s.points.iter());
    let finite = |v: f64| v.is_finite() && v > 0.0;
    let xs: Vec<f64> = pts.clone().map(|p| p.0).filter(|&v| finite(v)).collect();
    let ys: Vec<f64> = pts.map(|p| p.1).filter(|&v| finite(v)).collect();
    let goal_x = plot.goals.iter().filter_map(|g| g.1);
    let goal_y = plot.goals.iter().filter_map(|g| g.2);
    let range = |v: Vec<f64>| {
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if !lo.is_finite() {
            return (0, 1);
        }
        // A little room above and below, so that no point sits on the frame.
        let (a, b) = (
            (lo.log10() - 0.1).floor() as i32,
            (hi.log10() + 0.1).ceil() as i32,
        );
        (a, b.max(a + 1))
    };
    let (x0, x1) = range(xs.into_iter().chain(goal_x).collect());
    let (y0, y1) = range(ys.into_iter().chain(goal_y).collect());
    let (pw, ph) = (W as f64 - LEFT - RIGHT, H as f64 - TOP - BOTTOM);
    let px = |x: f64| LEFT + (x.log10() - x0 as f64) / (x1 - x0) as f64 * pw;
    let py = |y: f64| TOP + ph - (y.log10() - y0 as f64) / (y1 - y0) as f64 * ph;
    let grey = [225, 225, 225];
    let ink = [40, 40, 40];
    for k in x0..=x1 {
        let x = px(10f64.powi(k));
        c.line((x, TOP), (x, TOP + ph), 0.5, grey, 0.0);
        let label = decade_label(k);
        let w = c.text_width(&label, 14.0);
        c.text(&label, x - w / 2.0, TOP + ph + 20.0, 14.0, ink);
    }
    for k in y0..=y1 {
        let y = py(10f64.powi(k));
        c.line((LEFT, y), (LEFT + pw, y), 0.5, grey, 0.0);
        let label = decade_label(k);
        let w = c.text_width(&label, 14.0);
        c.text(&label, LEFT - w - 8.0, y + 5.0, 14.0, ink);
    }
    c.line((LEFT, TOP + ph), (LEFT + pw, TOP + ph), 0.8, ink, 0.0);
    c.line((LEFT, TOP), (LEFT, TOP + ph), 0.8, ink, 0.0);
    for (label, gx, gy) in &plot.goals {
        let red = [200, 30, 30];
        if let Some(x) = gx {
            c.line((px(*x), TOP), (px(*x), TOP + ph), 0.8, red, 6.0);
            c.text(label, px(*x) + 4.0, TOP + 14.0, 13.0, red);
        }
        if let Some(y) = gy {
            c.line((LEFT, py(*y)), (LEFT + pw, py(*y)), 0.8, red, 6.0);
            c.text(
                label,
                LEFT + pw - c.text_width(label, 13.0) - 4.0,
                py(*y) - 5.0,
                13.0,
                red,
            );
        }
    }
    let mut colour = PALETTE.iter().cycle();
    for (n, s) in plot.series.iter().enumerate() {
        let col = if s.peer {
            [0, 0, 0]
        } else {
            *colour.next().expect("cycle")
        };
        let mut p: Vec<(f64, f64)> = s
            .points
            .iter()
            .copied()
            .filter(|&(x, y)| finite(x) && finite(y))
            .map(|(x, y)| (px(x), py(y)))
            .collect();
        p.sort_by(|a, b| a.0.total_cmp(&b.0));
        if !s.peer && !s.points_only {
            for w in p.windows(2) {
                c.line(w[0], w[1], 1.2, col, 0.0);
            }
        }
        for &(x, y) in &p {
            if s.peer {
                c.square(x, y, 5.0, col);
            } else {
                c.disc(x, y, 4.0, col);
            }
        }
        let ly = TOP + 10.0 + 24.0 * n as f64;
        let lx = LEFT + pw + 20.0;
        if s.peer {
            c.square(lx + 10.0, ly, 5.0, col);
        } else if s.points_only {
            c.disc(lx + 10.0, ly, 4.0, col);
        } else {
            c.line((lx, ly), (lx + 20.0, ly), 1.2, col, 0.0);
            c.disc(lx + 10.0, ly, 4.0, col);
        }
        c.text(&s.label, lx + 28.0, ly + 5.0, 14.0, ink);
    }
    let tw = c.text_width(&plot.title, 17.0);
    c.text(&plot.title, LEFT + (pw - tw) / 2.0, 22.0, 17.0, ink);
    let xw = c.text_width(&plot.x_label, 15.0);
    c.text(
        &plot.x_label,
        LEFT + (pw - xw) / 2.0,
        H as f64 - 20.0,
        15.0,
        ink,
    );
    c.text(&plot.y_label, 8.0, TOP - 8.0, 15.0, ink);
    let mut png = Vec::new();
    c.img
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .map_err(|e| Error::Encode {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
    write_atomic(path, &png)
}
