//! What egui draws into the scene image over the balls (`compose.rs`, after the balls and
//! before the panel): the chart's labels (`labels.rs`; in a wipe each side's own, clipped to
//! its side), the wipe's split line, and the difference view's colour bar (`difference.rs`).

use egui::epaint::ClippedShape;

use super::compare::{Compare, View};
use super::{difference, labels};
use crate::scene::Scene;

/// Half the split line's width in pixels (the line covers `split - 1..split + 1`).
pub const SPLIT_HALF_WIDTH_PX: u32 = 1;

/// The shapes over the scene area (the window's left `free_width` points, `window_height`
/// pixels tall) for `scene`, or for its comparison.
pub fn shapes(
    ui: &egui::Ui,
    scene: &Scene,
    compare: Option<&Compare>,
    free_width: f32,
    window_height: u32,
) -> Vec<ClippedShape> {
    let Some(c) = compare else {
        return labels::shapes(ui, scene, free_width, window_height);
    };
    let ppp = ui.ctx().pixels_per_point();
    if !(ppp > 0.0 && free_width > 0.0) || window_height == 0 {
        return Vec::new();
    }
    let width = ((free_width * ppp).floor() as u32).max(1);
    match c.view {
        View::Difference { scale } => {
            difference::colour_bar(ui.painter(), (width, window_height), ppp, scale)
        }
        View::Wipe => {
            let split = c.split_px(width);
            let (left, right) = c.scenes(scene);
            let side = |s: &Scene, x0: u32, x1: u32| {
                let clip = egui::Rect::from_min_max(
                    egui::pos2(x0 as f32 / ppp, 0.0),
                    egui::pos2(x1 as f32 / ppp, window_height as f32 / ppp),
                );
                labels::shapes(ui, s, free_width, window_height)
                    .into_iter()
                    .map(move |mut shape| {
                        shape.clip_rect = shape.clip_rect.intersect(clip);
                        shape
                    })
            };
            let mut out: Vec<ClippedShape> = side(&left, 0, split)
                .chain(side(&right, split, width))
                .collect();
            out.extend(split_line(split, (width, window_height), ppp));
            out
        }
    }
}

/// The wipe's line at pixel column `split` of a `width x height` scene area: light, with a
/// round handle at mid-height (drag it, or anywhere near the line, to move the split).
fn split_line(split: u32, (width, height): (u32, u32), ppp: f32) -> [ClippedShape; 2] {
    let clip = egui::Rect::from_min_size(
        egui::Pos2::ZERO,
        egui::vec2(width as f32 / ppp, height as f32 / ppp),
    );
    let x0 = split.saturating_sub(SPLIT_HALF_WIDTH_PX) as f32 / ppp;
    let x1 = (split + SPLIT_HALF_WIDTH_PX) as f32 / ppp;
    let light = egui::Color32::from_gray(230);
    let line = egui::Shape::rect_filled(
        egui::Rect::from_min_max(egui::pos2(x0, 0.0), egui::pos2(x1, height as f32 / ppp)),
        0.0,
        light,
    );
    let handle = egui::Shape::circle_filled(
        egui::pos2(split as f32 / ppp, 0.5 * height as f32 / ppp),
        6.0 / ppp,
        light,
    );
    [line, handle].map(|shape| ClippedShape {
        clip_rect: clip,
        shape,
        transform_after_tessellation: egui::emath::TSTransform::IDENTITY,
    })
}
