//! Line plots as PNG, drawn pixel by pixel with the `image` crate and the embedded bitmap
//! font: a figure is a grid of panels sharing one legend.

use image::{Rgb, RgbImage};

use super::font::{draw_text, text_height, text_width};

/// One curve.
#[derive(Clone, Debug)]
pub struct Series {
    pub label: String,
    pub color: [u8; 3],
    pub dashed: bool,
    pub points: Vec<(f64, f64)>,
}

/// One set of axes (the figure's title says what y is).
#[derive(Clone, Debug, Default)]
pub struct Panel {
    pub title: String,
    pub x_label: String,
    pub series: Vec<Series>,
    /// Include y = 0 in the range (error plots).
    pub with_zero: bool,
}

/// Panels in rows of `cols`, a title and a legend.
#[derive(Clone, Debug, Default)]
pub struct Figure {
    pub title: String,
    pub cols: usize,
    pub panels: Vec<Panel>,
}

const PANEL_W: u32 = 460;
const PANEL_H: u32 = 320;
const LEFT: u32 = 86;
const RIGHT: u32 = 16;
const TOP: u32 = 30;
const BOTTOM: u32 = 52;
const SCALE: u32 = 2;
const BLACK: [u8; 3] = [0, 0, 0];
const GRID: [u8; 3] = [225, 225, 225];

/// Step of about `range / 5` rounded to 1, 2 or 5 times a power of ten.
fn nice_step(range: f64) -> f64 {
    let raw = (range / 5.0).max(1e-300);
    let p = 10f64.powf(raw.log10().floor());
    let m = raw / p;
    p * if m < 1.5 {
        1.0
    } else if m < 3.5 {
        2.0
    } else if m < 7.5 {
        5.0
    } else {
        10.0
    }
}

fn label(v: f64, step: f64) -> String {
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    let s = format!("{v:.decimals$}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// Draws into an image with clipping and simple alpha blending.
struct Canvas {
    img: RgbImage,
}

impl Canvas {
    fn blend(&mut self, x: i64, y: i64, c: [u8; 3], a: f64) {
        if x < 0 || y < 0 || x >= self.img.width() as i64 || y >= self.img.height() as i64 {
            return;
        }
        let p = self.img.get_pixel_mut(x as u32, y as u32);
        for (dst, src) in p.0.iter_mut().zip(c) {
            *dst = (*dst as f64 * (1.0 - a) + src as f64 * a).round() as u8;
        }
    }

    fn text(&mut self, s: &str, x: i64, y: i64, c: [u8; 3]) {
        let mut pts = Vec::new();
        draw_text(s, x, y, SCALE, |px, py| pts.push((px, py)));
        for (px, py) in pts {
            self.blend(px, py, c, 1.0);
        }
    }

    fn hline(&mut self, x0: i64, x1: i64, y: i64, c: [u8; 3]) {
        for x in x0..=x1 {
            self.blend(x, y, c, 1.0);
        }
    }

    fn vline(&mut self, x: i64, y0: i64, y1: i64, c: [u8; 3]) {
        for y in y0..=y1 {
            self.blend(x, y, c, 1.0);
        }
    }

    /// A 2.5-pixel-wide anti-aliased segment, clipped to `clip` (x0, y0, x1, y1); dashed
    /// segments skip every other 8 pixels of `phase` (the running length).
    fn segment(
        &mut self,
        a: (f64, f64),
        b: (f64, f64),
        c: [u8; 3],
        clip: [f64; 4],
        dash: Option<&mut f64>,
    ) {
        let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
        let steps = (len * 2.0).ceil().max(1.0) as usize;
        let mut phase = dash.as_ref().map(|p| **p);
        for k in 0..=steps {
            let t = k as f64 / steps as f64;
            let (x, y) = (a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t);
            if let Some(p) = phase {
                if (p + len * t) % 16.0 >= 8.0 {
                    continue;
                }
            }
            if x < clip[0] || x > clip[2] || y < clip[1] || y > clip[3] {
                continue;
            }
            for dy in -2..=2 {
                for dx in -2..=2 {
                    let (px, py) = (x.round() as i64 + dx, y.round() as i64 + dy);
                    let d = ((px as f64 - x).powi(2) + (py as f64 - y).powi(2)).sqrt();
                    let cov = (1.75 - d).clamp(0.0, 1.0);
                    if cov > 0.0 {
                        self.blend(px, py, c, cov * 0.6);
                    }
                }
            }
        }
        if let (Some(p), Some(out)) = (phase.as_mut(), dash) {
            *out = *p + len;
        }
    }
}

/// The data range of a panel, padded by 5 %.
fn ranges(panel: &Panel) -> ([f64; 2], [f64; 2]) {
    let pts = panel
        .series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|p| p.0.is_finite() && p.1.is_finite());
    let (mut x, mut y) = ([f64::MAX, f64::MIN], [f64::MAX, f64::MIN]);
    for p in pts {
        x = [x[0].min(p.0), x[1].max(p.0)];
        y = [y[0].min(p.1), y[1].max(p.1)];
    }
    if x[0] > x[1] {
        return ([0.0, 1.0], [0.0, 1.0]);
    }
    if panel.with_zero {
        y = [y[0].min(0.0), y[1].max(0.0)];
    }
    let pad = |r: [f64; 2]| {
        let w = (r[1] - r[0]).max(1e-9 * r[1].abs().max(1.0));
        [r[0] - 0.05 * w, r[1] + 0.05 * w]
    };
    (if x[1] > x[0] { x } else { pad(x) }, pad(y))
}

fn draw_panel(cv: &mut Canvas, panel: &Panel, ox: i64, oy: i64) {
    let (x0, y0) = (ox + LEFT as i64, oy + TOP as i64);
    let (x1, y1) = (
        ox + (PANEL_W - RIGHT) as i64,
        oy + (PANEL_H - BOTTOM) as i64,
    );
    let ([xa, xb], [ya, yb]) = ranges(panel);
    let px = |x: f64| x0 as f64 + (x - xa) / (xb - xa) * (x1 - x0) as f64;
    let py = |y: f64| y1 as f64 - (y - ya) / (yb - ya) * (y1 - y0) as f64;
    let th = text_height(SCALE) as i64;
    // Grid and tick labels.
    let (sx, sy) = (nice_step(xb - xa), nice_step(yb - ya));
    let mut t = (xa / sx).ceil() * sx;
    while t <= xb + 1e-12 {
        let x = px(t).round() as i64;
        cv.vline(x, y0, y1, GRID);
        let s = label(t, sx);
        cv.text(&s, x - text_width(&s, SCALE) as i64 / 2, y1 + 6, BLACK);
        t += sx;
    }
    let mut t = (ya / sy).ceil() * sy;
    while t <= yb + 1e-12 {
        let y = py(t).round() as i64;
        cv.hline(x0, x1, y, GRID);
        let s = label(t, sy);
        cv.text(&s, x0 - 6 - text_width(&s, SCALE) as i64, y - th / 2, BLACK);
        t += sy;
    }
    // Frame, titles.
    cv.hline(x0, x1, y0, BLACK);
    cv.hline(x0, x1, y1, BLACK);
    cv.vline(x0, y0, y1, BLACK);
    cv.vline(x1, y0, y1, BLACK);
    let w = text_width(&panel.title, SCALE) as i64;
    cv.text(&panel.title, (x0 + x1) / 2 - w / 2, oy + 8, BLACK);
    let w = text_width(&panel.x_label, SCALE) as i64;
    cv.text(&panel.x_label, (x0 + x1) / 2 - w / 2, y1 + 12 + th, BLACK);
    // Curves.
    let clip = [x0 as f64, y0 as f64, x1 as f64, y1 as f64];
    for s in &panel.series {
        let mut phase = 0.0;
        let pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .filter(|p| p.0.is_finite() && p.1.is_finite())
            .map(|p| (px(p.0), py(p.1)))
            .collect();
        for w in pts.windows(2) {
            let dash = s.dashed.then_some(&mut phase);
            cv.segment(w[0], w[1], s.color, clip, dash);
        }
    }
}

/// Renders `fig` to an RGB image.
pub fn render(fig: &Figure) -> RgbImage {
    let cols = fig.cols.max(1);
    let rows = fig.panels.len().div_ceil(cols).max(1);
    // Legend: every distinct label in order of first appearance.
    let mut legend: Vec<(&str, [u8; 3], bool)> = Vec::new();
    for s in fig.panels.iter().flat_map(|p| &p.series) {
        if !legend.iter().any(|l| l.0 == s.label) {
            legend.push((&s.label, s.color, s.dashed));
        }
    }
    let width = cols as u32 * PANEL_W;
    let entry_w = |l: &str| 40 + text_width(l, SCALE) + 24;
    let mut legend_rows = 1;
    let mut x = 10;
    for l in &legend {
        if x + entry_w(l.0) > width {
            legend_rows += 1;
            x = 10;
        }
        x += entry_w(l.0);
    }
    let header = 40 + legend_rows * 26;
    let mut cv = Canvas {
        img: RgbImage::from_pixel(width, header + rows as u32 * PANEL_H, Rgb([255; 3])),
    };
    cv.text(&fig.title, 10, 10, BLACK);
    let (mut x, mut y) = (10i64, 40i64);
    for l in &legend {
        if x + entry_w(l.0) as i64 > width as i64 {
            x = 10;
            y += 26;
        }
        let mid = (y + 7) as f64;
        let mut phase = 0.0;
        let clip = [0.0, 0.0, width as f64, header as f64];
        let dash = l.2.then_some(&mut phase);
        cv.segment((x as f64, mid), (x as f64 + 30.0, mid), l.1, clip, dash);
        cv.text(l.0, x + 40, y, BLACK);
        x += entry_w(l.0) as i64;
    }
    for (k, panel) in fig.panels.iter().enumerate() {
        let (r, c) = (k / cols, k % cols);
        draw_panel(
            &mut cv,
            panel,
            (c as u32 * PANEL_W) as i64,
            (header + r as u32 * PANEL_H) as i64,
        );
    }
    cv.img
}
