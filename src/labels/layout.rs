//! Where a scene's labels go: the balls projected with the scene's camera, grouped into
//! columns (balls sharing a screen x) and rows (sharing a screen y), and a room for each
//! label that no ball's bounds reach into.

use super::{
    caption, column_label, row_label, Align, Label, Labels, Rect, EDGE_PX, FONT_PX_PER_HEIGHT,
    GAP_PER_FONT_PX, OUTLINE_PER_FONT_PX, ROW_LABEL_SEPARATOR,
};
use crate::scene::Scene;

/// Pixels added around each ball's exact screen bounds: the renderers' own pad
/// ([`crate::scene::BOUNDS_PAD_PX`], half a pixel) plus the half pixel between a pixel's
/// centre, which decides whether a ball covers it, and its edge. Every pixel a ball covers
/// lies inside its padded bounds.
const BALL_PAD_PX: f64 = 2.0 * crate::scene::BOUNDS_PAD_PX;

/// The smallest preferred font size of a frame whose field of view is widened
/// (`Camera::min_aspect`): the labels shrink with the chart down to this size.
const ZOOMED_FONT_PX: f32 = 10.0;

/// Each ball's screen bounds in pixels of a `width x height` image, padded so that every
/// pixel the ball covers lies inside; `None` for a ball off screen; the whole image for a
/// ball the camera is inside or beside (exact bounds: `crate::scene::CameraBasis::sphere_bounds`).
pub fn ball_rects(scene: &Scene, width: u32, height: u32) -> Vec<Option<Rect>> {
    if width == 0 || height == 0 || scene.camera.problem().is_some() {
        return vec![None; scene.balls.len()];
    }
    let basis = scene.camera.basis(width, height);
    let (w, h) = (width as f64, height as f64);
    scene
        .balls
        .iter()
        .map(|b| {
            let [x0, y0, x1, y1] =
                basis.sphere_bounds(b.center, b.radius, width, height, BALL_PAD_PX)?;
            // NDC (y up) to pixels (y down): x = (ndc + 1) w / 2, y = (1 - ndc) h / 2.
            let rect = Rect {
                x0: ((x0 + 1.0) * 0.5 * w) as f32,
                y0: ((1.0 - y1) * 0.5 * h) as f32,
                x1: ((x1 + 1.0) * 0.5 * w) as f32,
                y1: ((1.0 - y0) * 0.5 * h) as f32,
            };
            (rect.x0.is_finite()
                && rect.y0.is_finite()
                && rect.x1.is_finite()
                && rect.y1.is_finite())
            .then_some(rect)
        })
        .collect()
}

/// A visible ball: its index in the scene and its padded screen bounds.
#[derive(Clone, Copy)]
struct Seen {
    index: usize,
    rect: Rect,
}

impl Seen {
    fn cx(&self) -> f32 {
        0.5 * (self.rect.x0 + self.rect.x1)
    }
    fn cy(&self) -> f32 {
        0.5 * (self.rect.y0 + self.rect.y1)
    }
}

/// Groups balls whose centres lie within half the smaller one's half-size of the group's
/// first centre along an axis (`centre`, `half`): the columns (x) or rows (y) of a chart,
/// which perspective leaves a few pixels apart. Groups come in increasing `centre`.
fn groups(seen: &[Seen], centre: fn(&Seen) -> f32, half: fn(&Seen) -> f32) -> Vec<Vec<Seen>> {
    let mut sorted = seen.to_vec();
    sorted.sort_by(|a, b| centre(a).total_cmp(&centre(b)));
    let mut out: Vec<Vec<Seen>> = Vec::new();
    for s in sorted {
        match out.last_mut() {
            Some(group)
                if (centre(&s) - centre(&group[0])).abs()
                    < 0.5 * half(&s).min(group.iter().map(half).fold(f32::INFINITY, f32::min)) =>
            {
                group.push(s)
            }
            _ => out.push(vec![s]),
        }
    }
    out
}

/// Which side of the chart the row labels go.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum RowSide {
    /// At the left of each row's leftmost ball, right-aligned (every picture's).
    Left,
    /// At the right of its rightmost ball, left-aligned (a comparison's right side, whose
    /// left part is the other side's).
    Right,
}

/// The labels of `scene` in a `width x height` image (whether or not the scene asks for
/// them: `scene.labels` is the caller's to check). Every room lies inside the image and
/// overlaps no ball's padded bounds ([`ball_rects`]) and no other label's room; a label
/// with no room is left out, so a tiny image has none. Row labels at the left.
pub fn layout(scene: &Scene, width: u32, height: u32) -> Labels {
    layout_rows_at(scene, width, height, RowSide::Left)
}

/// As [`layout`], the row labels on the side `rows`.
pub(crate) fn layout_rows_at(scene: &Scene, width: u32, height: u32, rows: RowSide) -> Labels {
    let rects = ball_rects(scene, width, height);
    let seen: Vec<Seen> = rects
        .iter()
        .enumerate()
        .filter_map(|(index, r)| r.map(|rect| Seen { index, rect }))
        .collect();
    let obstacles: Vec<Rect> = seen.iter().map(|s| s.rect).collect();
    let (w, h) = (width as f32, height as f32);
    let image = Rect {
        x0: 0.0,
        y0: 0.0,
        x1: w,
        y1: h,
    };
    // The font follows the chart: smaller where the camera widens its field of view for a
    // narrow image (`Camera::min_aspect`), as the balls are.
    // It keeps a readable size, though (the layout's own where that is smaller: a tiny
    // image has no labels).
    let zoom = scene.camera.zoom_out(width, height) as f32;
    let zoom = if zoom.is_finite() { zoom.max(1.0) } else { 1.0 };
    let size = (h * FONT_PX_PER_HEIGHT / zoom).max((h * FONT_PX_PER_HEIGHT).min(ZOOMED_FONT_PX));
    // One line of text with its outline and edge, and the gap to a ball.
    let line = size * (1.0 + 2.0 * OUTLINE_PER_FONT_PX) + 2.0 * EDGE_PX;
    let gap = size * GAP_PER_FONT_PX;
    let label = |text: String, room: Rect, align: [Align; 2]| Label {
        text,
        room,
        align,
        size_px: size,
        wrapped: Vec::new(),
        ellipsis: false,
    };
    let mut labels = Labels::default();

    // Columns: under the lowest ball, as wide as the gaps to the neighbouring columns allow.
    let columns = groups(&seen, Seen::cx, |s| 0.5 * s.rect.width());
    let centres: Vec<f32> = columns
        .iter()
        .map(|c| c.iter().map(Seen::cx).sum::<f32>() / c.len() as f32)
        .collect();
    for (i, column) in columns.iter().enumerate() {
        let cx = centres[i];
        let left = i.checked_sub(1).map_or(f32::INFINITY, |j| cx - centres[j]);
        let right = centres.get(i + 1).map_or(f32::INFINITY, |c| c - cx);
        let half = 0.5 * left.min(right);
        // Balls with labels of their own: each its label under it, the column no
        // roughness label.
        if column.iter().any(|s| scene.balls[s.index].label.is_some()) {
            for s in column {
                let Some(text) = scene.balls[s.index].label else {
                    continue;
                };
                let mut room = clip(
                    Rect {
                        x0: cx - half,
                        y0: s.rect.y1 + gap,
                        x1: cx + half,
                        y1: s.rect.y1 + gap + line,
                    },
                    &image,
                );
                let others = labels.balls.iter().map(|l| &l.room);
                for o in obstacles.iter().chain(others) {
                    if room.overlaps(o) {
                        if o.y0 > room.y0 {
                            room.y1 = room.y1.min(o.y0);
                        } else if 0.5 * (o.x0 + o.x1) < s.cx() {
                            room.x0 = room.x0.max(o.x1);
                        } else {
                            room.x1 = room.x1.min(o.x0);
                        }
                    }
                }
                labels.balls.push(Label {
                    ellipsis: true,
                    ..label(
                        text.as_str().to_string(),
                        room,
                        [Align::Centre, Align::Start],
                    )
                });
            }
            continue;
        }
        let bottom = column.iter().map(|s| s.rect.y1).fold(f32::MIN, f32::max);
        let mut room = Rect {
            x0: cx - half,
            y0: bottom + gap,
            x1: cx + half,
            y1: bottom + gap + line,
        };
        room = clip(room, &image);
        for o in &obstacles {
            if room.overlaps(o) {
                if o.y0 > room.y0 {
                    room.y1 = room.y1.min(o.y0);
                } else if 0.5 * (o.x0 + o.x1) < cx {
                    room.x0 = room.x0.max(o.x1);
                } else {
                    room.x1 = room.x1.min(o.x0);
                }
            }
        }
        // Centred under the column: as wide on both sides of its centre.
        let half = (cx - room.x0).min(room.x1 - cx).max(0.0);
        room.x0 = cx - half;
        room.x1 = cx + half;
        let mut roughness: Vec<(f32, f64)> = column
            .iter()
            .map(|s| (s.cy(), scene.balls[s.index].roughness))
            .collect();
        roughness.sort_by(|a, b| a.0.total_cmp(&b.0));
        let values: Vec<f64> = roughness.into_iter().map(|(_, r)| r).collect();
        let mut coats: Vec<(f32, f64)> = column
            .iter()
            .map(|s| (s.cy(), scene.balls[s.index].material.clearcoat))
            .filter(|(_, c)| c.is_on())
            .map(|(y, c)| (y, c.roughness))
            .collect();
        coats.sort_by(|a, b| a.0.total_cmp(&b.0));
        let coats: Vec<f64> = coats.into_iter().map(|(_, r)| r).collect();
        let text = if coats.is_empty() {
            column_label(&values)
        } else {
            super::column_label_with_coat(&values, &coats)
        };
        labels
            .columns
            .push(label(text, room, [Align::Centre, Align::Start]));
    }

    // Rows: at the left of the leftmost ball, right-aligned, centred on the row.
    for row in groups(&seen, Seen::cy, |s| 0.5 * s.rect.height()) {
        let texts: Vec<String> = row
            .iter()
            .map(|s| row_label(&scene.balls[s.index]))
            .collect();
        // A row whose balls are of different models has no one name.
        if texts.iter().any(|t| *t != texts[0]) {
            continue;
        }
        let cy = row.iter().map(Seen::cy).sum::<f32>() / row.len() as f32;
        let leftmost = row.iter().map(|s| s.rect.x0).fold(f32::MAX, f32::min);
        let rightmost = row.iter().map(|s| s.rect.x1).fold(f32::MIN, f32::max);
        let (x0, x1) = match rows {
            RowSide::Left => (0.0, leftmost - gap),
            RowSide::Right => (rightmost + gap, w),
        };
        let align = match rows {
            RowSide::Left => [Align::End, Align::Centre],
            RowSide::Right => [Align::Start, Align::Centre],
        };
        // The room between the image's edge (or whatever is in the way) and the row, from
        // y0 to y1.
        let room = |labels: &Labels, y0: f32, y1: f32| {
            let mut room = clip(Rect { x0, y0, x1, y1 }, &image);
            let others = labels
                .columns
                .iter()
                .chain(&labels.rows)
                .chain(&labels.balls)
                .flat_map(|l| std::iter::once(l).chain(&l.wrapped))
                .map(|l| &l.room);
            for o in obstacles.iter().chain(others) {
                if room.overlaps(o) {
                    match rows {
                        RowSide::Left => room.x0 = room.x0.max(o.x1),
                        RowSide::Right => room.x1 = room.x1.min(o.x0),
                    }
                }
            }
            room
        };
        let one = room(&labels, cy - 0.5 * line, cy + 0.5 * line);
        let mut row_label = label(texts[0].clone(), one, align);
        // Wrapped: the model under the material, the lines stacked on the row's centre.
        let parts: Vec<&str> = texts[0].split(ROW_LABEL_SEPARATOR).collect();
        if parts.len() > 1 {
            let top = cy - 0.5 * line * parts.len() as f32;
            row_label.wrapped = parts
                .iter()
                .enumerate()
                .map(|(i, part)| {
                    let y0 = top + line * i as f32;
                    let r = room(&labels, y0, y0 + line);
                    label(part.to_string(), r, align)
                })
                .collect();
            let usable = |l: &Label| l.room.width() > 0.0 && l.room.height() > 0.0;
            if !row_label.wrapped.iter().all(usable) {
                row_label.wrapped.clear();
            }
        }
        labels.rows.push(row_label);
    }

    // The caption: a line at the bottom, else at the top, wherever nothing else is.
    let margin = 0.5 * size;
    let taken: Vec<Rect> = obstacles
        .iter()
        .chain(
            labels
                .iter()
                .flat_map(|l| std::iter::once(l).chain(&l.wrapped))
                .map(|l| &l.room),
        )
        .copied()
        .collect();
    for y0 in [h - margin - line, margin] {
        let room = clip(
            Rect {
                x0: margin,
                y0,
                x1: w - margin,
                y1: y0 + line,
            },
            &image,
        );
        if !taken.iter().any(|t| room.overlaps(t)) {
            labels
                .caption
                .push(label(caption(scene), room, [Align::Centre, Align::Centre]));
            break;
        }
    }
    // Rooms that lost their area to a ball or the image's edge hold no text.
    let usable =
        |l: &Label| (l.room.width() > 0.0 && l.room.height() > 0.0) || !l.wrapped.is_empty();
    labels.columns.retain(usable);
    labels.rows.retain(usable);
    labels.caption.retain(usable);
    labels.balls.retain(usable);
    labels
}

/// `r` cut to the image (an empty rectangle stays empty: its edges may cross).
fn clip(r: Rect, image: &Rect) -> Rect {
    Rect {
        x0: r.x0.max(image.x0),
        y0: r.y0.max(image.y0),
        x1: r.x1.min(image.x1),
        y1: r.y1.min(image.y1),
    }
}
