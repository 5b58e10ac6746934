//! The lab's plots as PNG, drawn with `plotters` on its bitmap backend: log-log charts for
//! the bench ([`Plot`], legend on the right) and grids of linear panels under one title and
//! one legend for the truth study ([`Figure`]); both go through the same chart, legend and
//! series code. Log axes are drawn on the decimal logarithm of the data with one labelled
//! grid line a decade and faint lines at 2..9 times it. Text is set in the Ubuntu Light
//! font embedded in `epaint_default_fonts`, registered with plotters' `ab_glyph` text (no
//! system fonts, no download). That text places each glyph without its left side bearing
//! (letters sit a pixel tight; a proportional font shows it far less than the monospace
//! Hack) and a little high (see `centre_fix`).

use std::error::Error as StdError;
use std::path::Path;
use std::sync::OnceLock;

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use shadeballs::error::{Error, Result};
use shadeballs::output::write_image;

/// Colours of the series without a colour of their own, in order (a colour-blind-safe set:
/// Wong 2011, Nature Methods).
const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(120, 120, 120),
];
const INK: RGBColor = RGBColor(40, 40, 40);
const GRID: RGBColor = RGBColor(222, 222, 222);
const MINOR: RGBColor = RGBColor(242, 242, 242);
const GOAL: RGBColor = RGBColor(200, 30, 30);
/// The name the embedded font is registered under.
const FONT: &str = "ubuntu-light";

/// How a series is drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Style {
    /// Points joined in order of x, each marked with a disc.
    #[default]
    Marked,
    /// Points joined in order of x.
    Line,
    /// Points joined in order of x by a dashed line.
    Dashed,
    /// Discs, unjoined.
    Points,
    /// The homework's (a peer's) points: black squares, unjoined.
    Peer,
}

/// One series; `colour` `None` takes the next colour of the palette (peers are black).
#[derive(Clone, Debug, Default)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub colour: Option<[u8; 3]>,
    pub style: Style,
}

/// A log-log chart with its legend on the right; `goals` are dashed lines at
/// `(label, Some(x), None)` (vertical) or `(label, None, Some(y))` (horizontal).
#[derive(Clone, Debug, Default)]
pub struct Plot {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    pub goals: Vec<(String, Option<f64>, Option<f64>)>,
}

/// One set of linear axes of a [`Figure`] (the figure's title says what y is).
#[derive(Clone, Debug, Default)]
pub struct Panel {
    pub title: String,
    pub x_label: String,
    pub series: Vec<Series>,
    /// Include y = 0 in the range (error plots).
    pub with_zero: bool,
}

/// Panels in rows of `cols` under a title and one legend (each label once).
#[derive(Clone, Debug, Default)]
pub struct Figure {
    pub title: String,
    pub cols: usize,
    pub panels: Vec<Panel>,
}

/// The size of a [`Plot`] in pixels, and where its legend starts.
const PLOT_W: u32 = 1000;
const PLOT_H: u32 = 640;
const PLOT_LEGEND_X: u32 = 720;
/// The size of one panel of a [`Figure`].
const PANEL_W: u32 = 460;
const PANEL_H: u32 = 320;
/// A legend row's height and the length of its sample line.
const ROW: i32 = 26;
const SAMPLE: i32 = 30;

type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;
/// What drawing returns (plotters' errors, boxed).
type Drawing<T> = std::result::Result<T, Box<dyn StdError>>;
type Drawn = Drawing<()>;

/// Text sizes and margins of a chart, in pixels.
struct Look {
    title: u32,
    tick: u32,
    desc: u32,
    x_area: u32,
    y_area: u32,
    margin: u32,
}

const PLOT_LOOK: Look = Look {
    title: 21,
    tick: 16,
    desc: 17,
    x_area: 64,
    y_area: 80,
    margin: 14,
};
const PANEL_LOOK: Look = Look {
    title: 17,
    tick: 15,
    desc: 16,
    x_area: 46,
    y_area: 58,
    margin: 10,
};
/// The legend's text size.
const LEGEND: u32 = 17;

fn font(size: u32, colour: &RGBColor) -> TextStyle<'static> {
    (FONT, size).into_font().color(colour)
}

/// How far to move text anchored at its vertical centre down so that it looks centred:
/// plotters' `ab_glyph` text sits about a fifth of its size above that anchor.
fn centre_fix(size: u32) -> i32 {
    (size as f64 * 0.2).round() as i32
}

/// A decade's label: plain for 0.01 ... 1000, else `1e-5`.
fn decade_label(k: i32) -> String {
    match k {
        -2..=3 => format!("{}", 10f64.powi(k)),
        _ => format!("1e{k}"),
    }
}

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

/// `v` with as many decimals as `step` needs (no "-0.0").
fn tick_label(v: f64, step: f64) -> String {
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    let s = format!("{v:.decimals$}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// The smallest and largest of `values`, if any.
fn span(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    values.into_iter().fold(None, |acc, v| match acc {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    })
}

/// One axis in chart coordinates (the decimal logarithm of the data on a log axis), with
/// its labelled grid lines as plotters' bold key points and the faint ones as its light
/// key points.
#[derive(Clone, Copy, Debug)]
struct Axis {
    lo: f64,
    hi: f64,
    log: bool,
    step: f64,
}

impl Axis {
    /// Whole decades around the positive finite `values`, with a little room each side so
    /// that no point sits on the frame.
    fn log(values: impl IntoIterator<Item = f64>) -> Axis {
        let logs = values
            .into_iter()
            .filter(|v| v.is_finite() && *v > 0.0)
            .map(f64::log10);
        let (lo, hi) = match span(logs) {
            Some((lo, hi)) => ((lo - 0.1).floor(), (hi + 0.1).ceil()),
            None => (0.0, 1.0),
        };
        Axis {
            lo,
            hi: hi.max(lo + 1.0),
            log: true,
            step: 1.0,
        }
    }

    /// The range of the finite `values` (with 0 if `with_zero`), padded by 5 % if `pad` or
    /// if it is a single value.
    fn linear(values: impl IntoIterator<Item = f64>, with_zero: bool, pad: bool) -> Axis {
        let finite = values.into_iter().filter(|v| v.is_finite());
        let (mut lo, mut hi) = span(finite).unwrap_or((0.0, 1.0));
        if with_zero {
            (lo, hi) = (lo.min(0.0), hi.max(0.0));
        }
        if pad || hi <= lo {
            let w = (hi - lo).max(1e-9 * hi.abs().max(1.0));
            (lo, hi) = (lo - 0.05 * w, hi + 0.05 * w);
        }
        Axis {
            lo,
            hi,
            log: false,
            step: nice_step(hi - lo),
        }
    }

    /// `v` in chart coordinates; `None` if it cannot be drawn.
    fn to_chart(self, v: f64) -> Option<f64> {
        if self.log {
            (v.is_finite() && v > 0.0).then(|| v.log10())
        } else {
            v.is_finite().then_some(v)
        }
    }

    /// The labelled grid lines.
    fn ticks(self) -> Vec<f64> {
        let first = (self.lo / self.step - 1e-9).ceil() as i64;
        let last = (self.hi / self.step + 1e-9).floor() as i64;
        (first..=last).map(|k| k as f64 * self.step).collect()
    }

    /// The faint grid lines: 2..9 times each decade on a log axis.
    fn minor(self) -> Vec<f64> {
        if !self.log {
            return Vec::new();
        }
        let decades = self.lo as i64..self.hi as i64;
        decades
            .flat_map(|k| (2..10).map(move |m| k as f64 + (m as f64).log10()))
            .collect()
    }

    fn label(self, v: f64) -> String {
        if self.log {
            decade_label(v.round() as i32)
        } else {
            tick_label(v, self.step)
        }
    }
}

impl Ranged for Axis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, v: &f64, (a, b): (i32, i32)) -> i32 {
        let t = (v - self.lo) / (self.hi - self.lo);
        a + ((b - a) as f64 * t + 1e-3).floor() as i32
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.minor()
        } else {
            self.ticks()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.lo..self.hi
    }
}

/// A legend entry: each label once, in order of first appearance, with the colour every
/// series of that label is drawn in.
struct Entry<'a> {
    label: &'a str,
    colour: RGBColor,
    style: Style,
}

fn entries<'a>(series: impl IntoIterator<Item = &'a Series>) -> Vec<Entry<'a>> {
    let mut palette = PALETTE.iter().cycle();
    let mut out: Vec<Entry> = Vec::new();
    for s in series {
        if out.iter().any(|e| e.label == s.label) {
            continue;
        }
        let colour = match (s.colour, s.style) {
            (Some([r, g, b]), _) => RGBColor(r, g, b),
            (None, Style::Peer) => BLACK,
            (None, _) => *palette.next().expect("cycle"),
        };
        out.push(Entry {
            label: &s.label,
            colour,
            style: s.style,
        });
    }
    out
}

fn colour_of(entries: &[Entry], s: &Series) -> RGBColor {
    entries
        .iter()
        .find(|e| e.label == s.label)
        .map_or(INK, |e| e.colour)
}

/// What one chart shows.
struct Chart<'a> {
    title: &'a str,
    x_label: &'a str,
    y_label: &'a str,
    x: Axis,
    y: Axis,
    series: &'a [Series],
    goals: &'a [(String, Option<f64>, Option<f64>)],
    look: &'a Look,
}

fn draw_chart(area: &Area, c: &Chart, entries: &[Entry]) -> Drawn {
    let look = c.look;
    let mut builder = ChartBuilder::on(area);
    builder
        .margin(look.margin)
        .x_label_area_size(look.x_area)
        .y_label_area_size(look.y_area);
    if !c.title.is_empty() {
        builder.caption(c.title, font(look.title, &INK));
    }
    let mut chart = builder.build_cartesian_2d(c.x, c.y)?;
    let (x_label, y_label) = (|v: &f64| c.x.label(*v), |v: &f64| c.y.label(*v));
    let mut mesh = chart.configure_mesh();
    mesh.x_label_formatter(&x_label)
        .y_label_formatter(&y_label)
        .label_style(font(look.tick, &INK))
        .axis_desc_style(font(look.desc, &INK))
        .bold_line_style(GRID.stroke_width(1))
        .light_line_style(MINOR.stroke_width(1))
        .axis_style(INK.stroke_width(1))
        .y_label_offset(centre_fix(look.tick))
        .x_desc(c.x_label);
    if !c.y_label.is_empty() {
        mesh.y_desc(c.y_label);
    }
    mesh.draw()?;
    let (x, y) = (c.x, c.y);
    let frame = [(x.lo, y.lo), (x.hi, y.hi)];
    chart.draw_series([Rectangle::new(frame, INK.stroke_width(1))])?;
    for (label, gx, gy) in c.goals {
        let line = GOAL.stroke_width(2);
        let text = font(15, &GOAL);
        if let Some(gx) = gx.and_then(|v| x.to_chart(v)) {
            let ends = [(gx, y.lo), (gx, y.hi)];
            chart.draw_series(DashedLineSeries::new(ends, 7, 5, line))?;
            let at = EmptyElement::at((gx, y.hi)) + Text::new(label.clone(), (5, 6), text.clone());
            chart.draw_series([at])?;
        }
        if let Some(gy) = gy.and_then(|v| y.to_chart(v)) {
            let ends = [(x.lo, gy), (x.hi, gy)];
            chart.draw_series(DashedLineSeries::new(ends, 7, 5, line))?;
            let style = text.pos(Pos::new(HPos::Right, VPos::Bottom));
            let at = EmptyElement::at((x.hi, gy)) + Text::new(label.clone(), (-5, -4), style);
            chart.draw_series([at])?;
        }
    }
    for s in c.series {
        let colour = colour_of(entries, s);
        let mut pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .filter_map(|&(px, py)| Some((x.to_chart(px)?, y.to_chart(py)?)))
            .collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let line = colour.stroke_width(2);
        match s.style {
            Style::Marked | Style::Line => {
                chart.draw_series(LineSeries::new(pts.iter().copied(), line))?;
            }
            Style::Dashed => {
                chart.draw_series(DashedLineSeries::new(pts.iter().copied(), 8, 6, line))?;
            }
            Style::Points | Style::Peer => {}
        }
        match s.style {
            Style::Marked | Style::Points => {
                let disc = |&p: &(f64, f64)| Circle::new(p, 4, colour.filled());
                chart.draw_series(pts.iter().map(disc))?;
            }
            Style::Peer => {
                let square = |&p: &(f64, f64)| {
                    EmptyElement::at(p) + Rectangle::new([(-5, -5), (5, 5)], colour.filled())
                };
                chart.draw_series(pts.iter().map(square))?;
            }
            Style::Line | Style::Dashed => {}
        }
    }
    Ok(())
}

/// The width of a legend entry in pixels.
fn entry_width(e: &Entry, size: u32) -> Drawing<i32> {
    let (w, _) = (FONT, size).into_font().box_size(e.label)?;
    Ok(SAMPLE + 8 + w as i32 + 24)
}

/// Where each entry goes, rows of at most `width` pixels (one entry a row if `width` is
/// 0), relative to the legend's top left; and the number of rows.
fn legend_layout(entries: &[Entry], size: u32, width: i32) -> Drawing<(Vec<(i32, i32)>, i32)> {
    let (mut x, mut row) = (0, 0);
    let mut at = Vec::new();
    for (n, e) in entries.iter().enumerate() {
        let w = entry_width(e, size)?;
        if n > 0 && (width == 0 || x + w > width) {
            (x, row) = (0, row + 1);
        }
        at.push((x, row * ROW));
        x += w;
    }
    Ok((at, row + 1))
}

/// Draws `entries` at `origin` (the top left of the first row).
fn draw_legend(area: &Area, entries: &[Entry], at: &[(i32, i32)], origin: (i32, i32)) -> Drawn {
    for (e, &(dx, dy)) in entries.iter().zip(at) {
        let (x, y) = (origin.0 + dx, origin.1 + dy + ROW / 2);
        let line = e.colour.stroke_width(2);
        let mid = (x + SAMPLE / 2, y);
        match e.style {
            Style::Marked | Style::Line => {
                area.draw(&PathElement::new([(x, y), (x + SAMPLE, y)], line))?;
            }
            Style::Dashed => {
                let ends = [(x, y), (x + SAMPLE, y)];
                area.draw(&DashedPathElement::new(ends, 8, 6, line))?;
            }
            Style::Points | Style::Peer => {}
        }
        match e.style {
            Style::Marked | Style::Points => {
                area.draw(&Circle::new(mid, 4, e.colour.filled()))?;
            }
            Style::Peer => {
                let (cx, cy) = mid;
                let corners = [(cx - 5, cy - 5), (cx + 5, cy + 5)];
                area.draw(&Rectangle::new(corners, e.colour.filled()))?;
            }
            Style::Line | Style::Dashed => {}
        }
        let style = font(LEGEND, &INK).pos(Pos::new(HPos::Left, VPos::Center));
        let at = (x + SAMPLE + 8, y + centre_fix(LEGEND));
        area.draw(&Text::new(e.label, at, style))?;
    }
    Ok(())
}

fn fail(path: &Path, message: String) -> Error {
    Error::Encode {
        path: path.to_path_buf(),
        message,
    }
}

/// Registers the embedded font with plotters (once), also as the family that plotters
/// asks for by default; before any text is measured or drawn.
fn register_font(path: &Path) -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = REGISTERED.get_or_init(|| {
        [FONT, "sans-serif"].iter().all(|name| {
            let bytes = epaint_default_fonts::UBUNTU_LIGHT;
            plotters::style::register_font(name, FontStyle::Normal, bytes).is_ok()
        })
    });
    match ok {
        true => Ok(()),
        false => Err(fail(path, "the embedded font could not be read".into())),
    }
}

/// Draws a `w` x `h` white image with `draw` and writes it to `path` as PNG.
fn render(path: &Path, (w, h): (u32, u32), draw: impl FnOnce(&Area) -> Drawn) -> Result<()> {
    register_font(path)?;
    let fail = |message: String| fail(path, message);
    let mut buf = vec![255u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        draw(&root).map_err(|e| fail(e.to_string()))?;
        root.present().map_err(|e| fail(e.to_string()))?;
    }
    let img = image::RgbImage::from_raw(w, h, buf).expect("buffer of w x h RGB pixels");
    write_image(
        path,
        &image::DynamicImage::ImageRgb8(img),
        image::ImageFormat::Png,
    )
}

/// Writes `plot` to `path` (PNG, 1000 x 640).
pub fn write_plot(plot: &Plot, path: &Path) -> Result<()> {
    let entries = entries(&plot.series);
    let pts = || plot.series.iter().flat_map(|s| s.points.iter());
    let chart = Chart {
        title: &plot.title,
        x_label: &plot.x_label,
        y_label: &plot.y_label,
        x: Axis::log(
            pts()
                .map(|p| p.0)
                .chain(plot.goals.iter().filter_map(|g| g.1)),
        ),
        y: Axis::log(
            pts()
                .map(|p| p.1)
                .chain(plot.goals.iter().filter_map(|g| g.2)),
        ),
        series: &plot.series,
        goals: &plot.goals,
        look: &PLOT_LOOK,
    };
    render(path, (PLOT_W, PLOT_H), |root| {
        let (left, right) = root.split_horizontally(PLOT_LEGEND_X);
        draw_chart(&left, &chart, &entries)?;
        let (at, _) = legend_layout(&entries, LEGEND, 0)?;
        draw_legend(&right, &entries, &at, (10, 46))
    })
}

/// Writes `fig` to `path` (PNG, 460 x 320 pixels a panel under the title and legend).
pub fn write_figure(fig: &Figure, path: &Path) -> Result<()> {
    let cols = fig.cols.max(1);
    let rows = fig.panels.len().div_ceil(cols).max(1);
    let entries = entries(fig.panels.iter().flat_map(|p| &p.series));
    let width = cols as u32 * PANEL_W;
    register_font(path)?;
    let (at, legend_rows) = legend_layout(&entries, LEGEND, width as i32 - 20)
        .map_err(|e| fail(path, e.to_string()))?;
    let header = 44 + legend_rows as u32 * ROW as u32 + 6;
    let size = (width, header + rows as u32 * PANEL_H);
    render(path, size, |root| {
        root.draw(&Text::new(fig.title.as_str(), (10, 10), font(21, &INK)))?;
        draw_legend(root, &entries, &at, (10, 40))?;
        let (_, body) = root.split_vertically(header);
        for (area, panel) in body.split_evenly((rows, cols)).iter().zip(&fig.panels) {
            let pts = || panel.series.iter().flat_map(|s| s.points.iter());
            let chart = Chart {
                title: &panel.title,
                x_label: &panel.x_label,
                y_label: "",
                x: Axis::linear(pts().map(|p| p.0), false, false),
                y: Axis::linear(pts().map(|p| p.1), panel.with_zero, true),
                series: &panel.series,
                goals: &[],
                look: &PANEL_LOOK,
            };
            draw_chart(area, &chart, &entries)?;
        }
        Ok(())
    })
}
