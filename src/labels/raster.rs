//! Labels rasterised into an RGBA8 image (feature `labels`): each line's glyphs are
//! rendered by `ab_glyph` (anti-aliased coverage) from Ubuntu Light, the font egui draws
//! the viewer's text with (`epaint_default_fonts`), into a coverage mask; the mask dilated
//! by the outline's width is blended in dark, then the mask itself in light, both with
//! the "over" operator (Porter and Duff 1984, "Compositing Digital Images") on the 8-bit
//! display values.

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

fn font() -> Result<FontRef<'static>> {
    FontRef::try_from_slice(epaint_default_fonts::UBUNTU_LIGHT).map_err(|e| Error::Invalid {
        what: "font",
        message: format!("the embedded Ubuntu Light font does not parse: {e}"),
    })
}

/// The width in pixels of `text` in one line at font size `size_px` (a line's height:
/// ascent minus descent), kerning included.
pub fn text_width(text: &str, size_px: f32) -> Result<f32> {
    Ok(line(&font()?, text, size_px).1)
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
    let width_at = |text: &str, size: f32| line(&font, text, size).1;
    let mut drawn = 0;
    for label in labels.iter() {
        for (line, place) in label.fit(width_at) {
            if draw(&font, rgba, width, height, &line, place) {
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
    let mut mask = vec![0.0f32; mw * mh];
    let (glyphs, _) = line(font, &label.text, place.size_px);
    // The text box's top-left in mask coordinates.
    let (ox, oy) = (place.text.x0 - x0 as f32, place.text.y0 - y0 as f32);
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
    let radius = (OUTLINE_PER_FONT_PX * place.size_px).round().max(1.0) as usize;
    // A soft dark halo: the glyphs widened by the radius, then blurred by it.
    let outline = blur(&dilate(&mask, mw, mh, radius), mw, mh, radius);
    for my in 0..mh {
        for mx in 0..mw {
            let (t, o) = (mask[my * mw + mx], outline[my * mw + mx]);
            if o <= 0.0 {
                continue;
            }
            let at = 4 * ((y0 as usize + my) * width as usize + x0 as usize + mx);
            let px = &mut rgba[at..at + 4];
            over(px, OUTLINE, OUTLINE_ALPHA * (HALO_GAIN * o).min(1.0));
            over(px, TEXT, (TEXT_GAIN * t).min(1.0));
        }
    }
    true
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
