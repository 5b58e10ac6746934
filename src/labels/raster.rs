//! Labels rasterised into an RGBA8 image (feature `labels`): each line's glyphs are
//! rendered by `ab_glyph` (anti-aliased coverage) from Ubuntu Light, the font egui draws
//! the viewer's text with (`epaint_default_fonts`), into a coverage mask; the mask dilated
//! by the outline's width is blended in dark, then the mask itself in light, both with
//! the "over" operator (Porter and Duff 1984, "Compositing Digital Images") on the 8-bit
//! display values.

use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, PxScale, ScaleFont};

use super::{Label, Labels, OUTLINE_PER_FONT_PX};
use crate::error::{Error, Result};

/// The text's colour (display values).
const TEXT: [f32; 3] = [245.0, 245.0, 245.0];
/// The outline's colour and opacity.
const OUTLINE: [f32; 3] = [0.0, 0.0, 0.0];
const OUTLINE_ALPHA: f32 = 0.9;
/// The halo's opacity grows faster than its blurred coverage, so that it stays dark right
/// around the glyphs and fades beyond them.
const HALO_GAIN: f32 = 1.5;
/// The text's coverage is strengthened a little: Ubuntu Light's strokes are thin.
const TEXT_GAIN: f32 = 1.3;

/// The embedded Ubuntu Light, parsed once: the viewer measures and sets its labels every
/// frame, and a parse of the font's tables each time would be work done over and over.
fn font() -> Result<&'static FontRef<'static>> {
    static FONT: OnceLock<std::result::Result<FontRef<'static>, String>> = OnceLock::new();
    FONT.get_or_init(|| {
        FontRef::try_from_slice(epaint_default_fonts::UBUNTU_LIGHT).map_err(|e| e.to_string())
    })
    .as_ref()
    .map_err(|e| Error::Invalid {
        what: "font",
        message: format!("the embedded Ubuntu Light font does not parse: {e}"),
    })
}

/// The width in pixels of `text` in one line at font size `size_px` (a line's height:
/// ascent minus descent), kerning included.
pub fn text_width(text: &str, size_px: f32) -> Result<f32> {
    Ok(line(font()?, text, size_px).1)
}

/// The glyphs of `text` laid out on one line at `size_px`, the baseline at the ascent (so
/// the line's top is at 0), and the line's advance width.
fn line(font: &FontRef<'_>, text: &str, size_px: f32) -> (Vec<ab_glyph::Glyph>, f32) {
    let scale = PxScale::from(size_px);
    let scaled = font.as_scaled(scale);
    let mut x = 0.0;
    let mut previous = None;
    let mut glyphs = Vec::new();
    for c in text.chars().filter(|c| !c.is_control()) {
        let id = scaled.glyph_id(c);
        if let Some(p) = previous {
            x += scaled.kern(p, id);
        }
        glyphs.push(id.with_scale_and_position(scale, ab_glyph::point(x, scaled.ascent())));
        x += scaled.h_advance(id);
        previous = Some(id);
    }
    (glyphs, x)
}

/// Draws `labels` into `rgba`, a `width x height` RGBA8 image (rows top to bottom), each
/// label fitted to its room (`Label::place`) and nothing drawn outside its room: the
/// number drawn. An error for a buffer of the wrong length; labels that do not fit are
/// left out.
pub fn draw_labels(rgba: &mut [u8], width: u32, height: u32, labels: &Labels) -> Result<usize> {
    let expected = 4 * width as usize * height as usize;
    if rgba.len() != expected {
        return Err(Error::Invalid {
            what: "labels",
            message: format!(
                "an RGBA8 image of {width}x{height} has {expected} bytes, not {}",
                rgba.len()
            ),
        });
    }
    let font = font()?;
    let width_at = |text: &str, size: f32| line(font, text, size).1;
    let mut drawn = 0;
    for label in labels.iter() {
        for (line, place) in label.fit(width_at) {
            if draw(font, rgba, width, height, &line, place) {
                drawn += 1;
            }
        }
    }
    Ok(drawn)
}

/// Draws `label` at `place` (its [`Label::place`]); false when no pixel is inside.
fn draw(
    font: &FontRef<'_>,
    rgba: &mut [u8],
    width: u32,
    height: u32,
    label: &Label,
    place: super::Placement,
) -> bool {
    // The pixels wholly inside the outer box (and the image): the mask covers them.
    let x0 = place.outer.x0.ceil().max(0.0) as i64;
    let y0 = place.outer.y0.ceil().max(0.0) as i64;
    let x1 = (place.outer.x1.floor() as i64).min(i64::from(width));
    let y1 = (place.outer.y1.floor() as i64).min(i64::from(height));
    if x1 <= x0 || y1 <= y0 {
        return false;
    }
    let (mw, mh) = ((x1 - x0) as usize, (y1 - y0) as usize);
    // The text box's top-left in mask coordinates.
    let origin = (place.text.x0 - x0 as f32, place.text.y0 - y0 as f32);
    let mask = coverage(font, &label.text, place.size_px, origin, (mw, mh));
    let outline = halo(&mask, (mw, mh), place.size_px);
    for my in 0..mh {
        for mx in 0..mw {
            let at = 4 * ((y0 as usize + my) * width as usize + x0 as usize + mx);
            let i = my * mw + mx;
            blend(&mut rgba[at..at + 4], mask[i], outline[i]);
        }
    }
    true
}

/// One line of label text with its halo on a transparent ground, as the viewer draws each
/// label (one image a text and size, one quad a frame, instead of the glyphs nine times):
/// premultiplied RGBA8, `width x height` pixels, the text box `margin` pixels in from each
/// edge (the halo's reach).
#[derive(Clone, Debug)]
pub struct LabelImage {
    /// Pixels across.
    pub width: u32,
    /// Pixels down.
    pub height: u32,
    /// Pixels from each edge to the text box.
    pub margin: u32,
    /// Premultiplied RGBA8 display values, rows top to bottom.
    pub rgba: Vec<u8>,
}

/// The most pixels a label's image may have ([`label_image`]): a line of a thousand
/// characters at 64 px is about 3 million.
const MAX_LABEL_IMAGE_PIXELS: f32 = 16_777_216.0;

/// `text` on one line at `size_px` with its halo ([`LabelImage`]): the same mask, halo and
/// blending as a PNG's labels ([`draw_labels`]), over transparent black, so that the RGBA
/// holds colours already multiplied by their opacity.
pub fn label_image(text: &str, size_px: f32) -> Result<LabelImage> {
    if !(size_px.is_finite() && size_px > 0.0) {
        return Err(Error::Invalid {
            what: "label",
            message: format!("a font size of {size_px} px"),
        });
    }
    let font = font()?;
    let advance = line(font, text, size_px).1;
    let margin = 2 * outline_radius(size_px) + 1;
    let (w, h) = (
        advance.ceil() + 2.0 * margin as f32,
        size_px.ceil() + 2.0 * margin as f32,
    );
    if w * h > MAX_LABEL_IMAGE_PIXELS {
        return Err(Error::Invalid {
            what: "label",
            message: format!("{text:?} at {size_px} px needs an image of {w} x {h} pixels"),
        });
    }
    let (w, h) = (w as usize, h as usize);
    let origin = (margin as f32, margin as f32);
    let mask = coverage(font, text, size_px, origin, (w, h));
    let outline = halo(&mask, (w, h), size_px);
    let mut rgba = vec![0u8; 4 * w * h];
    for (i, px) in rgba.chunks_exact_mut(4).enumerate() {
        blend(px, mask[i], outline[i]);
    }
    Ok(LabelImage {
        width: w as u32,
        height: h as u32,
        margin: margin as u32,
        rgba,
    })
}

/// The glyphs' coverage of `text` at `size_px` in a `mw x mh` mask, the text box's top-left
/// at `origin` (mask pixels); glyphs outside are cut.
fn coverage(
    font: &FontRef<'_>,
    text: &str,
    size_px: f32,
    (ox, oy): (f32, f32),
    (mw, mh): (usize, usize),
) -> Vec<f32> {
    let mut mask = vec![0.0f32; mw * mh];
    let (glyphs, _) = line(font, text, size_px);
    for mut glyph in glyphs {
        glyph.position.x += ox;
        glyph.position.y += oy;
        let Some(outlined) = font.outline_glyph(glyph) else {
            continue;
        };
        // Whole pixels: the sub-pixel position is in the coverage.
        let b = outlined.px_bounds();
        outlined.draw(|gx, gy, coverage| {
            let mx = b.min.x as i64 + i64::from(gx);
            let my = b.min.y as i64 + i64::from(gy);
            if (0..mw as i64).contains(&mx) && (0..mh as i64).contains(&my) {
                let m = &mut mask[my as usize * mw + mx as usize];
                *m = (*m + coverage).min(1.0);
            }
        });
    }
    mask
}

/// The outline's width in whole pixels at font size `size_px` (at least one).
fn outline_radius(size_px: f32) -> usize {
    (OUTLINE_PER_FONT_PX * size_px).round().max(1.0) as usize
}

/// A soft dark halo around `mask`: the glyphs widened by the outline's radius, then
/// blurred by it.
fn halo(mask: &[f32], (w, h): (usize, usize), size_px: f32) -> Vec<f32> {
    let radius = outline_radius(size_px);
    blur(&dilate(mask, w, h, radius), w, h, radius)
}

/// The halo of coverage `o` in dark, then the text of coverage `t` in light, over the pixel.
fn blend(px: &mut [u8], t: f32, o: f32) {
    if o <= 0.0 {
        return;
    }
    over(px, OUTLINE, OUTLINE_ALPHA * (HALO_GAIN * o).min(1.0));
    over(px, TEXT, (TEXT_GAIN * t).min(1.0));
}

/// `colour` with opacity `alpha` over the pixel (display values; alpha composited too).
fn over(px: &mut [u8], colour: [f32; 3], alpha: f32) {
    let a = alpha.clamp(0.0, 1.0);
    if a <= 0.0 {
        return;
    }
    for c in 0..3 {
        let v = colour[c] * a + f32::from(px[c]) * (1.0 - a);
        px[c] = v.round().clamp(0.0, 255.0) as u8;
    }
    let v = 255.0 * a + f32::from(px[3]) * (1.0 - a);
    px[3] = v.round().clamp(0.0, 255.0) as u8;
}

/// The largest value within `radius` along x, then along y: a square dilation in time
/// independent of the radius (van Herk 1992, "A fast algorithm for local minimum and
/// maximum filters on rectangular and octagonal kernels"; Gil and Werman 1993).
fn dilate(mask: &[f32], w: usize, h: usize, radius: usize) -> Vec<f32> {
    separable(mask, w, h, radius, max_filter)
}

/// The mean within `radius` along x, then along y (a box blur; the window cut at the
/// image's ends, so an edge keeps its level).
fn blur(mask: &[f32], w: usize, h: usize, radius: usize) -> Vec<f32> {
    separable(mask, w, h, radius, box_filter)
}

/// A 1-D filter of the given radius applied to every row of a `w x h` image, then to every
/// column of the result.
fn separable(
    mask: &[f32],
    w: usize,
    h: usize,
    radius: usize,
    filter: fn(&[f32], &mut [f32], usize),
) -> Vec<f32> {
    let mut rows = vec![0.0; w * h];
    for y in 0..h {
        filter(
            &mask[y * w..(y + 1) * w],
            &mut rows[y * w..(y + 1) * w],
            radius,
        );
    }
    let mut out = vec![0.0; w * h];
    let mut column = vec![0.0; h];
    let mut filtered = vec![0.0; h];
    for x in 0..w {
        for y in 0..h {
            column[y] = rows[y * w + x];
        }
        filter(&column, &mut filtered, radius);
        for y in 0..h {
            out[y * w + x] = filtered[y];
        }
    }
    out
}

/// `out[i] = mean(input[i - r ..= i + r])` over the part of the window inside, from a
/// running sum.
fn box_filter(input: &[f32], out: &mut [f32], r: usize) {
    let n = input.len();
    let mut prefix = vec![0.0f64; n + 1];
    for i in 0..n {
        prefix[i + 1] = prefix[i] + f64::from(input[i]);
    }
    for (i, o) in out.iter_mut().enumerate() {
        let lo = i.saturating_sub(r);
        let hi = (i + r + 1).min(n);
        *o = ((prefix[hi] - prefix[lo]) / (hi - lo) as f64) as f32;
    }
}

/// `out[i] = max(input[i - r ..= i + r])` (the window cut at the ends), by van Herk's
/// blocks of `2 r + 1`: a running maximum forwards and backwards within each block, so
/// that any window is the backward maximum at its start and the forward one at its end.
fn max_filter(input: &[f32], out: &mut [f32], r: usize) {
    let n = input.len();
    if n == 0 {
        return;
    }
    let k = 2 * r + 1;
    let mut forward = vec![0.0f32; n];
    let mut backward = vec![0.0f32; n];
    for i in 0..n {
        forward[i] = if i % k == 0 {
            input[i]
        } else {
            forward[i - 1].max(input[i])
        };
    }
    for i in (0..n).rev() {
        backward[i] = if i % k == k - 1 || i == n - 1 {
            input[i]
        } else {
            backward[i + 1].max(input[i])
        };
    }
    for (i, o) in out.iter_mut().enumerate() {
        let lo = i.saturating_sub(r);
        let hi = (i + r).min(n - 1);
        // [lo, hi] spans at most two blocks: the end of lo's and the start of hi's.
        *o = if lo / k == hi / k {
            input[lo..=hi].iter().copied().fold(0.0, f32::max)
        } else {
            backward[lo].max(forward[hi])
        };
    }
}
