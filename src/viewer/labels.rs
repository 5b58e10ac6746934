//! The chart's labels in the viewer: laid out by [`crate::labels::layout`] in the same
//! rooms as a PNG's and fitted by `crate::labels::Label::place`, set in egui's own Ubuntu
//! Light: light text over a dark outline (the text drawn at eight offsets in dark first).
//! They are egui shapes of their own, drawn into the scene image right after the balls
//! (`compose.rs`), so that a frame that does not shade the balls again does not draw them
//! either, and the panel is not redrawn for them.

use crate::labels::{self, Labels, MIN_FONT_PX, OUTLINE_PER_FONT_PX};
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
    let painter = ui.painter();
    let font = |px: f32| egui::FontId::proportional(px / ppp);
    let light = egui::Color32::from_gray(245);
    let dark = egui::Color32::from_black_alpha(200);
    let mut out = Vec::new();
    let width_at = |text: &str, size_px: f32| {
        painter
            .layout_no_wrap(text.to_string(), font(size_px), light)
            .size()
            .x
            * ppp
    };
    let lines = layout.iter().flat_map(|label| label.fit(width_at));
    for (label, place) in lines {
        if place.size_px < readable_px(label.size_px) * (1.0 - 1e-4) {
            continue;
        }
        let centre = egui::pos2(
            (shift + 0.5 * (place.text.x0 + place.text.x1)) / ppp,
            0.5 * (place.text.y0 + place.text.y1) / ppp,
        );
        // Whole pixel sizes: egui keeps each size's glyphs in its font atlas, and a size
        // that followed the rooms as the camera moves would add glyphs every frame (the
        // atlas, and so the panel, would change every frame). A hair of tolerance keeps a
        // size `place` trimmed by rounding whole.
        let size_px = (place.size_px + 1e-3).floor();
        let radius = (OUTLINE_PER_FONT_PX * size_px).round().max(1.0) / ppp;
        let mut add = |offset: egui::Vec2, colour: egui::Color32| {
            let galley = painter.layout_no_wrap(label.text.clone(), font(size_px), colour);
            // On whole pixels: the glyphs' sub-pixel positions (and so the font atlas)
            // stay the same as the labels move with the camera.
            let min = ((centre + offset - 0.5 * galley.size()) * ppp).round() / ppp;
            out.push(egui::epaint::ClippedShape {
                clip_rect: area,
                shape: egui::Shape::galley(min, galley, colour),
                transform_after_tessellation: egui::emath::TSTransform::IDENTITY,
            });
        };
        for k in 0..8 {
            let angle = k as f32 * std::f32::consts::FRAC_PI_4;
            add(egui::vec2(angle.cos(), angle.sin()) * radius, dark);
        }
        add(egui::Vec2::ZERO, light);
    }
    out
}
