//! What egui draws into the scene image over the balls (`compose.rs`, after the balls and
//! before the panel): the chart's labels (`labels.rs`; in a wipe each side's own, clipped to
//! its side, B's row labels at the right), the sides' A/B tags, the wipe's split line or the
//! side-by-side divider, and the difference view's colour bar (`difference.rs`).

use egui::epaint::ClippedShape;

use super::compare::{Compare, Side, View};
use super::{difference, labels};
use crate::labels::{ball_rects, layout_rows_at, Align, Label, Labels, Rect, RowSide};
use crate::scene::Scene;

/// Half the split line's width in pixels (the line covers `split - 1..split + 1`).
pub(crate) const SPLIT_HALF_WIDTH_PX: u32 = 1;

/// The shapes over the scene area (the window's left `free_width` points, `window_height`
/// pixels tall) for `scene`, or for its comparison: each side's labels where the scene has
/// them on, with its tag (`A · on`, `B · off`) and, in a wipe, B's row labels at the right
/// of its chart (its left part is A's); the wipe's split line or the side-by-side
/// divider; the difference's colour bar, off the balls and labels.
pub(crate) fn shapes(
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
    let h = window_height;
    let (a, b) = c.scenes(scene);
    let on = scene.labels;
    let tag = |side: char, s: Side| format!("{side} \u{b7} {}", s.name());
    let clipped = |shapes: Vec<ClippedShape>, x0: u32, x1: u32| {
        let clip = egui::Rect::from_min_max(
            egui::pos2(x0 as f32 / ppp, 0.0),
            egui::pos2(x1 as f32 / ppp, h as f32 / ppp),
        );
        shapes.into_iter().map(move |mut shape| {
            shape.clip_rect = shape.clip_rect.intersect(clip);
            shape
        })
    };
    let mut out: Vec<ClippedShape> = Vec::new();
    match c.view {
        View::Difference { scale } => {
            let mut obstacles: Vec<Rect> = ball_rects(&a, width, h).into_iter().flatten().collect();
            if on {
                let mut layout = crate::labels::layout(&a, width, h);
                let right = layout_rows_at(&b, width, h, RowSide::Right);
                layout.rows.extend(right.rows);
                add_tags(
                    &mut layout,
                    width,
                    h,
                    &obstacles,
                    [
                        Some(format!(
                            "|A - B| \u{b7} A {}, B {}",
                            c.left.name(),
                            c.right.name()
                        )),
                        None,
                    ],
                );
                obstacles.extend(layout.iter().flat_map(rooms));
                out.extend(labels::paint(ui, &layout, 0, (width, h)));
            }
            out.extend(difference::colour_bar(
                ui.painter(),
                (width, h),
                ppp,
                scale,
                &obstacles,
            ));
        }
        View::Wipe => {
            let split = c.split_px(width);
            if on {
                let mut left = crate::labels::layout(&a, width, h);
                let mut right = layout_rows_at(&b, width, h, RowSide::Right);
                let balls: Vec<Rect> = ball_rects(&a, width, h).into_iter().flatten().collect();
                add_tags(&mut left, width, h, &balls, [Some(tag('A', c.left)), None]);
                add_tags(
                    &mut right,
                    width,
                    h,
                    &balls,
                    [None, Some(tag('B', c.right))],
                );
                out.extend(clipped(labels::paint(ui, &left, 0, (width, h)), 0, split));
                out.extend(clipped(
                    labels::paint(ui, &right, 0, (width, h)),
                    split,
                    width,
                ));
            }
            out.extend(split_line(split, (width, h), ppp, true));
        }
        View::SideBySide => {
            let halves = c.halves(width);
            if on {
                for ((x0, w), (s, side, name)) in halves
                    .into_iter()
                    .zip([(&a, c.left, 'A'), (&b, c.right, 'B')])
                {
                    let mut layout = crate::labels::layout(s, w, h);
                    let balls: Vec<Rect> = ball_rects(s, w, h).into_iter().flatten().collect();
                    add_tags(&mut layout, w, h, &balls, [Some(tag(name, side)), None]);
                    out.extend(labels::paint(ui, &layout, x0, (w, h)));
                }
            }
            out.extend(split_line(halves[1].0, (width, h), ppp, false));
        }
    }
    out
}

/// A label's room and its wrapped lines' rooms.
fn rooms(l: &crate::labels::Label) -> impl Iterator<Item = Rect> + '_ {
    std::iter::once(l.room).chain(l.wrapped.iter().map(|w| w.room))
}

/// Adds to `layout` (of a `width x height` image) up to two tags, `tags[0]` at its top-left
/// corner and `tags[1]` at its top-right, each in a room a line tall and up to half the
/// width, off `balls` and the layout's own rooms; a tag with no room at the top goes to the
/// bottom corner, else is left out.
fn add_tags(
    layout: &mut Labels,
    width: u32,
    height: u32,
    balls: &[Rect],
    tags: [Option<String>; 2],
) {
    let (w, h) = (width as f32, height as f32);
    let size = layout
        .iter()
        .map(|l| l.size_px)
        .next()
        .unwrap_or(h * TAG_PX_PER_HEIGHT);
    let line = size * 1.4 + 2.0;
    let margin = 0.5 * size;
    for (k, text) in tags.into_iter().enumerate() {
        let Some(text) = text else { continue };
        let (x0, x1, align) = match k {
            0 => (margin, 0.5 * w, Align::Start),
            _ => (0.5 * w, w - margin, Align::End),
        };
        let taken: Vec<Rect> = balls
            .iter()
            .copied()
            .chain(layout.iter().flat_map(rooms))
            .collect();
        for y0 in [margin, h - margin - line] {
            let room = Rect {
                x0,
                y0,
                x1,
                y1: y0 + line,
            };
            if room.width() > 0.0 && y0 >= 0.0 && !taken.iter().any(|t| room.overlaps(t)) {
                layout.caption.push(Label {
                    text: text.clone(),
                    room,
                    align: [align, Align::Centre],
                    size_px: size,
                    wrapped: Vec::new(),
                    ellipsis: false,
                });
                break;
            }
        }
    }
}

/// A tag's font size per pixel of height where the layout has no label to take it from.
const TAG_PX_PER_HEIGHT: f32 = 1.0 / 45.0;

/// The wipe's line at pixel column `split` of a `width x height` scene area: light, with a
/// round handle at mid-height (drag it, or anywhere near the line, to move the split), or
/// without one (the side-by-side divider).
fn split_line(
    split: u32,
    (width, height): (u32, u32),
    ppp: f32,
    handle: bool,
) -> Vec<ClippedShape> {
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
    let circle = egui::Shape::circle_filled(
        egui::pos2(split as f32 / ppp, 0.5 * height as f32 / ppp),
        6.0 / ppp,
        light,
    );
    let shapes = if handle {
        vec![line, circle]
    } else {
        vec![line]
    };
    shapes
        .into_iter()
        .map(|shape| ClippedShape {
            clip_rect: clip,
            shape,
            transform_after_tessellation: egui::emath::TSTransform::IDENTITY,
        })
        .collect()
}
