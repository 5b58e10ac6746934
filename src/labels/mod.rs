//! The labels a shading-ball chart is read with: the roughness under each column of balls,
//! the row's model at the left of each row, and a caption with the preset, the geometry
//! term and the environment.
//!
//! Two halves, so that any drawer uses the same places:
//! - *where* ([`layout`], always built): from a [`Scene`] and the image size, a [`Labels`]
//!   of [`Label`]s, each a text with the room it may take in pixels (never over a ball) and
//!   a preferred font size; `Label::place` shrinks the text to its room, or drops it.
//!   Another picture (a comparison chart) builds its own [`Labels`] by hand.
//! - *drawing*: `draw_labels` (feature `labels`) rasterises them into an RGBA8 image with
//!   `ab_glyph` and the Ubuntu Light font of `epaint_default_fonts`; the viewer paints the
//!   same [`Labels`] with egui. Light text with a dark outline, readable on black and on a
//!   white furnace background.
//!
//! Labels are drawn into PNG pictures only: an `.exr` holds radiance, and text is not.

mod layout;
#[cfg(feature = "labels")]
mod raster;
#[cfg(all(test, feature = "cli"))]
mod tests;

pub use layout::ball_rects;
pub use layout::layout;
pub(crate) use layout::{layout_rows_at, RowSide};
#[cfg(feature = "labels")]
pub use raster::draw_labels;
#[cfg(feature = "labels")]
pub use raster::text_width;
#[cfg(feature = "labels")]
pub use raster::{label_image, LabelImage};

use std::borrow::Cow;

use crate::scene::{Ball, Model, Scene};

/// The preferred font size per pixel of image height: 16 px at 720 (a line is the font's
/// ascent minus its descent, [`Label::size_px`]).
pub(crate) const FONT_PX_PER_HEIGHT: f32 = 1.0 / 45.0;
/// The smallest font drawn: a label that fits its room only smaller is left out.
pub(crate) const MIN_FONT_PX: f32 = 8.0;
/// The fraction of a label's preferred size below which its text is wrapped onto lines
/// of their own where they fit larger ([`Label::fit`]); the viewer draws no label smaller
/// than this fraction at all.
pub const READABLE_FRACTION: f32 = 0.75;
/// The fewest characters a label cut short with an ellipsis keeps ([`Label::ellipsis`]):
/// where fewer fit, it is shrunk whole or left out.
pub(crate) const MIN_SHORTENED_CHARS: usize = 3;
/// The dark outline's width around the glyphs, per pixel of font size.
pub(crate) const OUTLINE_PER_FONT_PX: f32 = 0.07;
/// Free pixels kept around a label's outline (for the glyphs' anti-aliased edges).
pub(crate) const EDGE_PX: f32 = 1.0;
/// The gap between a ball's bounds and its label, per pixel of font size.
pub(crate) const GAP_PER_FONT_PX: f32 = 0.4;

/// How a text sits in its room along one axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Align {
    /// Left (horizontal) or top (vertical).
    Start,
    /// Centred.
    Centre,
    /// Right (horizontal) or bottom (vertical).
    End,
}

/// A rectangle in pixels of the image: `x` right, `y` down, `(0, 0)` the image's top-left
/// corner; pixel `(i, j)` covers `[i, i + 1] x [j, j + 1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    /// Left edge.
    pub x0: f32,
    /// Top edge.
    pub y0: f32,
    /// Right edge.
    pub x1: f32,
    /// Bottom edge.
    pub y1: f32,
}

impl Rect {
    /// Width (zero when empty).
    pub fn width(&self) -> f32 {
        (self.x1 - self.x0).max(0.0)
    }

    /// Height (zero when empty).
    pub fn height(&self) -> f32 {
        (self.y1 - self.y0).max(0.0)
    }

    /// Whether the two rectangles share an area (touching edges do not count).
    pub fn overlaps(&self, other: &Rect) -> bool {
        self.x0 < other.x1 && other.x0 < self.x1 && self.y0 < other.y1 && other.y0 < self.y1
    }

    /// Whether `other` lies inside this rectangle.
    pub fn contains(&self, other: &Rect) -> bool {
        other.x0 >= self.x0 && other.x1 <= self.x1 && other.y0 >= self.y0 && other.y1 <= self.y1
    }
}

/// One line of text and the room it may take.
#[derive(Clone, Debug, PartialEq)]
pub struct Label {
    /// The text (one line).
    pub text: String,
    /// Where the text may go, its outline included: a drawer draws nothing outside it.
    pub room: Rect,
    /// How the text sits in its room: horizontally, vertically.
    pub align: [Align; 2],
    /// The preferred font size in pixels (the height of a line); smaller if the text does
    /// not fit its room (`Label::place`).
    pub size_px: f32,
    /// The same text wrapped, one label a line with its own room (a row's model under its
    /// material): drawn instead of this label where the one line would shrink below
    /// [`READABLE_FRACTION`] of its size and the lines fit larger ([`Label::fit`]). Empty
    /// for a text that does not wrap.
    pub wrapped: Vec<Label>,
    /// Whether a text too long for its room at [`READABLE_FRACTION`] of its size is cut
    /// short with [`crate::scene::ELLIPSIS`] rather than shrunk (a ball's own label).
    pub ellipsis: bool,
}

/// Where a label's text goes once fitted to its room.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// The font size in pixels: the label's, or smaller to fit.
    pub size_px: f32,
    /// The text's own box: its width at that size by one line's height.
    pub text: Rect,
    /// The text's box with the outline and `EDGE_PX` around it: inside the room.
    pub outer: Rect,
}

impl Label {
    /// The font size and boxes of this label's text, given the text's width in pixels at
    /// [`Label::size_px`] (a line's width grows in proportion to its font size). The font
    /// shrinks until the text with its outline fits the room; `None` when that needs a font
    /// under [`MIN_FONT_PX`], or for an empty text or a bad width.
    pub(crate) fn place(&self, width_at_size: f32) -> Option<Placement> {
        if self.text.trim().is_empty()
            || !(width_at_size.is_finite() && width_at_size > 0.0)
            || !(self.size_px.is_finite() && self.size_px > 0.0)
        {
            return None;
        }
        // Outer width at font size s: s (w / size + 2 k) + 2 e; height: s (1 + 2 k) + 2 e.
        let per_px = width_at_size / self.size_px;
        let k = OUTLINE_PER_FONT_PX;
        let fit_w = (self.room.width() - 2.0 * EDGE_PX) / (per_px + 2.0 * k);
        let fit_h = (self.room.height() - 2.0 * EDGE_PX) / (1.0 + 2.0 * k);
        // A hair under the fit, so that rounding never puts the outer box past the room.
        let size = self.size_px.min(fit_w.min(fit_h) * (1.0 - 1e-5));
        // And a hair of tolerance at the smallest size (a room made for it).
        // (NaN, from a room with NaN edges, fails this too.)
        if size.is_nan() || size < MIN_FONT_PX * (1.0 - 1e-4) {
            return None;
        }
        let margin = k * size + EDGE_PX;
        let (w, h) = (per_px * size + 2.0 * margin, size + 2.0 * margin);
        let start = |lo: f32, hi: f32, len: f32, align: Align| match align {
            Align::Start => lo,
            Align::Centre => 0.5 * (lo + hi - len),
            Align::End => hi - len,
        };
        let x0 = start(self.room.x0, self.room.x1, w, self.align[0]);
        let y0 = start(self.room.y0, self.room.y1, h, self.align[1]);
        let outer = Rect {
            x0,
            y0,
            x1: x0 + w,
            y1: y0 + h,
        };
        Some(Placement {
            size_px: size,
            text: Rect {
                x0: x0 + margin,
                y0: y0 + margin,
                x1: x0 + w - margin,
                y1: y0 + h - margin,
            },
            outer,
        })
    }
}

impl Label {
    /// What to draw of this label: its one line, or its [`Label::wrapped`] lines, each
    /// with its placement; `width_at` gives a text's width in pixels at a font size. The
    /// one line wins when it keeps [`READABLE_FRACTION`] of its size, or when the wrapped
    /// lines do not all fit larger; nothing when neither fits.
    ///
    /// A label with [`Label::ellipsis`] keeps the largest size its room's height allows
    /// (at most its own, at least [`READABLE_FRACTION`] of it where the room is tall
    /// enough) and drops characters from its end, adding the ellipsis, until it fits.
    pub fn fit(&self, width_at: impl Fn(&str, f32) -> f32) -> Vec<(Cow<'_, Label>, Placement)> {
        let one = self.place(width_at(&self.text, self.size_px));
        let readable = READABLE_FRACTION * self.size_px * (1.0 - 1e-4);
        if let Some(p) = one {
            if p.size_px >= readable {
                return vec![(Cow::Borrowed(self), p)];
            }
        }
        if self.ellipsis {
            return self.shortened(&width_at, one, readable);
        }
        let lines: Option<Vec<(Cow<'_, Label>, Placement)>> = self
            .wrapped
            .iter()
            .map(|l| {
                l.place(width_at(&l.text, l.size_px))
                    .map(|p| (Cow::Borrowed(l), p))
            })
            .collect();
        match (one, lines) {
            (one, Some(lines))
                if !lines.is_empty()
                    && lines
                        .iter()
                        .all(|(_, p)| one.is_none_or(|o| p.size_px > o.size_px)) =>
            {
                lines
            }
            (Some(p), _) => vec![(Cow::Borrowed(self), p)],
            _ => Vec::new(),
        }
    }

    /// [`Label::fit`] for a label with [`Label::ellipsis`] whose whole text (placed at
    /// `one`) keeps less than `readable` pixels: the longest start of it that, ended with
    /// the ellipsis, keeps the size the room's height allows (capped at `readable`); the
    /// whole text shrunk where no start does.
    fn shortened(
        &self,
        width_at: &impl Fn(&str, f32) -> f32,
        one: Option<Placement>,
        readable: f32,
    ) -> Vec<(Cow<'_, Label>, Placement)> {
        // The size the room's height alone allows: a text of no width.
        let Some(tall) = self.place(f32::MIN_POSITIVE.sqrt()) else {
            return Vec::new();
        };
        let wanted = readable.min(tall.size_px);
        // A start of fewer characters names nothing.
        let ends: Vec<usize> = self
            .text
            .char_indices()
            .map(|(i, _)| i)
            .skip(MIN_SHORTENED_CHARS)
            .collect();
        for &end in ends.iter().rev() {
            let start = self.text[..end].trim_end();
            if start.is_empty() {
                break;
            }
            let text = format!("{start}{}", crate::scene::ELLIPSIS);
            if let Some(p) = self.place(width_at(&text, self.size_px)) {
                if p.size_px >= wanted {
                    let label = Label {
                        text,
                        ..self.clone()
                    };
                    return vec![(Cow::Owned(label), p)];
                }
            }
        }
        one.map(|p| (Cow::Borrowed(self), p)).into_iter().collect()
    }
}

/// A chart's labels, in pixels of one image size.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Labels {
    /// Under each column of balls: its roughness, left to right.
    pub columns: Vec<Label>,
    /// At the left of each row of balls: its model (`row_label`), top to bottom.
    pub rows: Vec<Label>,
    /// The caption line(s): preset, geometry term and environment ([`caption`]).
    pub caption: Vec<Label>,
    /// Under each ball with a label of its own ([`crate::scene::Ball::label`]): that
    /// label, shortened to the ball's column ([`Label::ellipsis`]); such a ball's column
    /// has no roughness label.
    pub balls: Vec<Label>,
}

impl Labels {
    /// Every label: columns, rows, the caption, then the balls' own.
    pub fn iter(&self) -> impl Iterator<Item = &Label> {
        self.columns
            .iter()
            .chain(&self.rows)
            .chain(&self.caption)
            .chain(&self.balls)
    }

    /// Whether there is no label at all.
    #[cfg(test)]
    pub(crate) fn is_empty(&self) -> bool {
        self.iter().next().is_none()
    }
}

/// Between a row label's material and its model: where a row label wraps.
pub(crate) const ROW_LABEL_SEPARATOR: &str = " \u{b7} ";

/// The text at the left of the row a ball heads: what the ball's model is, after its
/// material where it is not all metal (`IOR 1.5 · Kulla-Conty`, `metallic 0.5 ·
/// Kulla-Conty`). The one place that names a row's model.
pub(crate) fn row_label(ball: &Ball) -> String {
    let model = match ball.model {
        Model::None => "no term",
        Model::KullaConty => "Kulla-Conty",
        Model::Turquin => "Turquin",
        Model::FdezAguera => "Fdez-Aguera",
        Model::Truth => "truth",
    };
    let m = &ball.material;
    let label = row_label_isotropic(ball, model);
    if !m.is_anisotropic() {
        return label;
    }
    // An anisotropic lobe says so first, with its rotation where it has one.
    let turned = if m.anisotropy_rotation != 0.0 {
        format!(
            " at {} deg",
            number(m.anisotropy_rotation.to_degrees().round())
        )
    } else {
        String::new()
    };
    format!(
        "anisotropy {}{turned}{ROW_LABEL_SEPARATOR}{label}",
        number(m.anisotropy)
    )
}

/// [`row_label`] without the anisotropy: the clear coat's weight, then the base's.
fn row_label_isotropic(ball: &Ball, model: &str) -> String {
    let m = &ball.material;
    let base = base_label(ball, model);
    if m.clearcoat.is_on() {
        format!(
            "coat {}{ROW_LABEL_SEPARATOR}{base}",
            number(m.clearcoat.weight)
        )
    } else {
        base
    }
}

/// The row label of a ball's material under its clear coat, `model` its model's name.
fn base_label(ball: &Ball, model: &str) -> String {
    let m = &ball.material;
    if !m.has_dielectric() {
        model.to_string()
    } else if m.has_metal() {
        format!(
            "metallic {}{ROW_LABEL_SEPARATOR}{model}",
            number(m.metallic)
        )
    } else {
        format!("IOR {}{ROW_LABEL_SEPARATOR}{model}", number(m.ior))
    }
}

/// The text under a column of balls of these roughness values (top to bottom): `r = 0.15`,
/// or each distinct value in order (`r = 0.15 / 0.35`).
pub fn column_label(roughness: &[f64]) -> String {
    format!("r = {}", distinct_numbers(roughness))
}

/// The text under a column with clear coats: the balls' roughness and the coats'
/// (`r = 0.4 · coat r = 0.1`).
pub(crate) fn column_label_with_coat(roughness: &[f64], coat_roughness: &[f64]) -> String {
    format!(
        "{} \u{b7} coat r = {}",
        column_label(roughness),
        distinct_numbers(coat_roughness)
    )
}

/// Each distinct value in order, joined by ` / `.
fn distinct_numbers(roughness: &[f64]) -> String {
    let mut values: Vec<String> = Vec::new();
    for r in roughness {
        let text = number(*r);
        if !values.contains(&text) {
            values.push(text);
        }
    }
    values.join(" / ")
}

/// The caption: `accurate preset · smith-correlated G · environment · tone mapper ·
/// exposure 1.5` (the tone mapper the scene's display uses), where the environment is `no environment`, `uniform environment 1` (or `uniform environment
/// (r, g, b)`) or the map's name with the term formed under it (`studio map, kulla-conty
/// term`).
pub fn caption(scene: &Scene) -> String {
    let environment = match &scene.environment_map {
        Some(e) => {
            let name = match &e.source {
                crate::environment::Source::Builtin(b) => b.to_string(),
                crate::environment::Source::File(p) => p
                    .file_name()
                    .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into()),
            };
            format!("{name} map")
        }
        None => {
            let c = scene.environment;
            if c == glam::DVec3::ZERO {
                "no environment".to_string()
            } else if c.x == c.y && c.y == c.z {
                format!("uniform environment {}", number(c.x))
            } else {
                format!(
                    "uniform environment ({}, {}, {})",
                    number(c.x),
                    number(c.y),
                    number(c.z)
                )
            }
        }
    };
    let layering = if scene.balls.iter().any(|b| b.material.has_dielectric()) {
        format!(" \u{b7} {} layering", scene.layering)
    } else {
        String::new()
    };
    let layering = if scene.balls.iter().any(|b| b.material.clearcoat.is_on()) {
        format!("{layering} \u{b7} {} coat", scene.coat_form)
    } else {
        layering
    };
    let display = scene.display();
    format!(
        "{} preset \u{b7} {} G{layering} \u{b7} {environment} \u{b7} {} \u{b7} exposure {}",
        scene.preset,
        scene.effective_geometry(),
        display.tone_map.name(),
        number(scene.exposure)
    )
}

/// A number with up to three decimals and no trailing zeros (`0.15`, `0.5`, `1`).
fn number(v: f64) -> String {
    let text = format!("{v:.3}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" {
        "0".to_string()
    } else {
        text.to_string()
    }
}
