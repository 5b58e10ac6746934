//! The chart's labels over the scene area, painted by egui in the places
//! [`crate::labels::layout`] gives a PNG's (the same rooms, the same fitting by
//! [`crate::labels::Label::place`]), with egui's own Ubuntu Light: light text with a dark
//! outline, the text drawn at eight offsets in dark first.

use crate::labels::{self, OUTLINE_PER_FONT_PX};
use crate::scene::Scene;

/// Paints `scene`'s labels over the scene area: the window's left `free_width` points,
/// `window_height` pixels tall (the scene image is `floor(free_width * ppp)` pixels wide,
/// as the viewer sizes it).
pub fn paint(ui: &egui::Ui, scene: &Scene, free_width: f32, window_height: u32) {
    let ppp = ui.ctx().pixels_per_point();
    if !(ppp > 0.0 && free_width > 0.0) || window_height == 0 {
        return;
    }
    let width = ((free_width * ppp).floor() as u32).max(1);
    let layout = labels::layout(scene, width, window_height);
    let area = egui::Rect::from_min_max(
        egui::Pos2::ZERO,
        egui::pos2(width as f32 / ppp, window_height as f32 / ppp),
    );
    let painter = ui
        .ctx()
        .layer_painter(egui::LayerId::background())
        .with_clip_rect(area);
    let font = |px: f32| egui::FontId::proportional(px / ppp);
    for label in layout.iter() {
        let galley = painter.layout_no_wrap(
            label.text.clone(),
            font(label.size_px),
            egui::Color32::WHITE,
        );
        let Some(place) = label.place(galley.size().x * ppp) else {
            continue;
        };
        let centre = egui::pos2(
            0.5 * (place.text.x0 + place.text.x1) / ppp,
            0.5 * (place.text.y0 + place.text.y1) / ppp,
        );
        let radius = (OUTLINE_PER_FONT_PX * place.size_px).round().max(1.0) / ppp;
        let dark = egui::Color32::from_black_alpha(200);
        for k in 0..8 {
            let angle = k as f32 * std::f32::consts::FRAC_PI_4;
            let offset = egui::vec2(angle.cos(), angle.sin()) * radius;
            painter.text(
                centre + offset,
                egui::Align2::CENTER_CENTER,
                &label.text,
                font(place.size_px),
                dark,
            );
        }
        painter.text(
            centre,
            egui::Align2::CENTER_CENTER,
            &label.text,
            font(place.size_px),
            egui::Color32::from_gray(245),
        );
    }
}
