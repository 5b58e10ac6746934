//! The chart's labels in the viewer: laid out by [`crate::labels::layout`] in the same
//! rooms as a PNG's and fitted by `crate::labels::Label::place`, set in egui's own Ubuntu
//! Light: light text over a dark halo, each text and size rasterised once into an image as
//! a PNG's labels are (`labels::label_image`), then drawn as one quad a frame. They are
//! egui shapes of their own, drawn into the scene image right after the balls
//! (`compose.rs`), so that a frame that does not shade the balls again does not draw them
//! either, and the panel is not redrawn for them.

use crate::labels::{self, Labels, MIN_FONT_PX};
use crate::scene::Scene;

/// The smallest font the viewer sets a label in, as a fraction of the layout's size for the
/// image (its height over 45): a label that would have to shrink further to fit its room
/// (columns squeezed together by an orbit, balls shrunk by zooming out) is left out rather
/// than drawn too small to read. A PNG keeps the layout's own rule (down to 8 px).
pub(crate) const READABLE_FRACTION: f32 = labels::READABLE_FRACTION;

/// The smallest font size in pixels the viewer draws a label of layout size `size_px` at.
pub fn readable_px(size_px: f32) -> f32 {
    (READABLE_FRACTION * size_px).max(MIN_FONT_PX)
}

/// `scene`'s labels as egui shapes over the scene area: the window's left `free_width`
/// points, `window_height` pixels tall (the scene image is `floor(free_width * ppp)` pixels
/// wide, as the viewer sizes it). Called inside the frame's `run_ui`, so that the glyphs
/// it lays out reach the font atlas in this frame's texture changes.
pub(crate) fn shapes(
    ui: &egui::Ui,
    scene: &Scene,
    free_width: f32,
    window_height: u32,
) -> Vec<egui::epaint::ClippedShape> {
    let ppp = ui.ctx().pixels_per_point();
    if !(scene.labels && ppp > 0.0 && free_width > 0.0) || window_height == 0 {
        return Vec::new();
    }
    let width = ((free_width * ppp).floor() as u32).max(1);
    let layout = labels::layout(scene, width, window_height);
    paint(ui, &layout, 0, (width, window_height))
}

/// `layout`'s labels (laid out for an image `width x height` pixels) as egui shapes, the
/// image's left edge at pixel column `x0` of the scene area and nothing drawn outside it.
pub(crate) fn paint(
    ui: &egui::Ui,
    layout: &Labels,
    x0: u32,
    (width, height): (u32, u32),
) -> Vec<egui::epaint::ClippedShape> {
    let ppp = ui.ctx().pixels_per_point();
    if ppp.is_nan() || ppp <= 0.0 || width == 0 || height == 0 {
        return Vec::new();
    }
    let shift = x0 as f32;
    let area = egui::Rect::from_min_max(
        egui::pos2(shift / ppp, 0.0),
        egui::pos2((shift + width as f32) / ppp, height as f32 / ppp),
    );
    let ctx = ui.ctx();
    // The same widths as a PNG's labels: the images below are set by the same rasteriser.
    let width_at =
        |text: &str, size_px: f32| labels::text_width(text, size_px).unwrap_or(f32::INFINITY);
    let mut out = Vec::new();
    let lines = layout.iter().flat_map(|label| label.fit(width_at));
    for (label, place) in lines {
        if place.size_px < readable_px(label.size_px) * (1.0 - 1e-4) {
            continue;
        }
        // Whole pixel sizes: each size of a text is an image of its own (label_texture),
        // and a size that followed the rooms as the camera moves would make one every
        // frame. A hair of tolerance keeps a size `place` trimmed by rounding whole.
        let size_px = (place.size_px + 1e-3).floor();
        let Some(image) = label_texture(ctx, &label.text, size_px) else {
            continue;
        };
        // The text box centred where the layout put it, on whole pixels (the image is
        // drawn texel for pixel).
        let centre_x = shift + 0.5 * (place.text.x0 + place.text.x1);
        let centre_y = 0.5 * (place.text.y0 + place.text.y1);
        let [width_px, height_px] = image.handle.size().map(|n| n as f32);
        let margin = image.margin as f32;
        let text_w = width_px - 2.0 * margin;
        let text_h = height_px - 2.0 * margin;
        let x = (centre_x - 0.5 * text_w).round() - margin;
        let y = (centre_y - 0.5 * text_h).round() - margin;
        let rect = egui::Rect::from_min_size(
            egui::pos2(x / ppp, y / ppp),
            egui::vec2(width_px / ppp, height_px / ppp),
        );
        let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
        // Nothing outside the label's outer box (its halo's room), as in a PNG.
        let outer = egui::Rect::from_min_max(
            egui::pos2((shift + place.outer.x0) / ppp, place.outer.y0 / ppp),
            egui::pos2((shift + place.outer.x1) / ppp, place.outer.y1 / ppp),
        );
        out.push(egui::epaint::ClippedShape {
            clip_rect: area.intersect(outer),
            shape: egui::Shape::image(image.handle.id(), rect, uv, egui::Color32::WHITE),
            transform_after_tessellation: egui::emath::TSTransform::IDENTITY,
        });
    }
    out
}

/// The most label images kept (texts times sizes): past it the cache starts again, and
/// egui frees the textures no longer held.
const MAX_LABEL_IMAGES: usize = 256;

/// The label images made so far, by text and whole font size, kept in egui's memory.
#[derive(Clone, Default)]
struct LabelImages(std::collections::HashMap<(String, u32), LabelTexture>);

/// A label's image as a texture: its margin (`labels::LabelImage::margin`) and the handle
/// that keeps the texture alive (and knows its size).
#[derive(Clone)]
struct LabelTexture {
    margin: u32,
    handle: egui::TextureHandle,
}

/// The texture of `text` at `size_px` with its halo (`labels::label_image`), made and
/// uploaded the first time it is asked for; None where the text cannot be set or its image
/// is wider than a texture may be.
fn label_texture(ctx: &egui::Context, text: &str, size_px: f32) -> Option<LabelTexture> {
    let id = egui::Id::unique("shadeballs label images");
    let key = (text.to_string(), size_px as u32);
    // A look-up in place (get_temp would clone the whole cache).
    let found = ctx.data_mut(|d| {
        d.get_temp_mut_or_default::<LabelImages>(id)
            .0
            .get(&key)
            .cloned()
    });
    if found.is_some() {
        return found;
    }
    let image = labels::label_image(text, size_px).ok()?;
    // A text too long for one texture of this device is left out, as one too big for its
    // room is.
    let side = ctx.input(|i| i.max_texture_side);
    if image.width.max(image.height) as usize > side {
        return None;
    }
    let colour = egui::ColorImage::from_rgba_premultiplied(
        [image.width as usize, image.height as usize],
        &image.rgba,
    );
    let name = format!("label {size_px} {text}");
    let handle = ctx.load_texture(name, colour, egui::TextureOptions::NEAREST);
    let texture = LabelTexture {
        margin: image.margin,
        handle,
    };
    ctx.data_mut(|d| {
        let cache = d.get_temp_mut_or_default::<LabelImages>(id);
        if cache.0.len() >= MAX_LABEL_IMAGES {
            cache.0.clear();
        }
        cache.0.insert(key, texture.clone());
    });
    Some(texture)
}
