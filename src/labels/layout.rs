//! Where a scene's labels go: the balls projected with the scene's camera, grouped into
//! columns (balls sharing a screen x) and rows (sharing a screen y), and a room for each
//! label that no ball's bounds reach into.

use super::{
    caption, column_label, row_label, Align, Label, Labels, Rect, EDGE_PX, FONT_PX_PER_HEIGHT,
    GAP_PER_FONT_PX, OUTLINE_PER_FONT_PX,
};
use crate::scene::Scene;

/// Pixels added around each ball's exact screen bounds: the renderers' own pad
/// ([`crate::scene::BOUNDS_PAD_PX`], half a pixel) plus the half pixel between a pixel's
/// centre, which decides whether a ball covers it, and its edge. Every pixel a ball covers
/// lies inside its padded bounds.
const BALL_PAD_PX: f64 = 2.0 * crate::scene::BOUNDS_PAD_PX;

/// Each ball's screen bounds in pixels of a `width x height` image, padded so that every
/// pixel the ball covers lies inside; `None` for a ball off screen; the whole image for a
/// ball the camera is inside or beside (exact bounds: [`crate::scene::CameraBasis::sphere_bounds`]).
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

/// The labels of `scene` in a `width x height` image (whether or not the scene asks for
/// them: `scene.labels` is the caller's to check). Every room lies inside the image and
/// overlaps no ball's padded bounds ([`ball_rects`]) and no other label's room; a label
/// with no room is left out, so a tiny image has none.
pub fn layout(scene: &Scene, width: u32, height: u32) -> Labels {
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
    let size = h * FONT_PX_PER_HEIGHT;
    // One line of text with its outline and edge, and the gap to a ball.
    let line = size * (1.0 + 2.0 * OUTLINE_PER_FONT_PX) + 2.0 * EDGE_PX;
    let gap = size * GAP_PER_FONT_PX;
    let label = |text: String, room: Rect, align: [Align; 2]| Label {
        text,
        room,
        align,
        size_px: size,
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
        labels.columns.push(label(
            column_label(&values),
            room,
            [Align::Centre, Align::Start],
        ));
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
        let mut room = clip(
            Rect {
                x0: 0.0,
                y0: cy - 0.5 * line,
                x1: leftmost - gap,
                y1: cy + 0.5 * line,
            },
            &image,
        );
        let others = labels.columns.iter().chain(&labels.rows).map(|l| &l.room);
        for o in obstacles.iter().chain(others) {
            if room.overlaps(o) {
                room.x0 = room.x0.max(o.x1);
            }
        }
        labels
            .rows
            .push(label(texts[0].clone(), room, [Align::End, Align::Centre]));
    }

    // The caption: a line at the bottom, else at the top, wherever nothing else is.
    let margin = 0.5 * size;
    let taken: Vec<Rect> = obstacles
        .iter()
        .chain(labels.iter().map(|l| &l.room))
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
    let usable = |l: &Label| l.room.width() > 0.0 && l.room.height() > 0.0;
    labels.columns.retain(usable);
    labels.rows.retain(usable);
    labels.caption.retain(usable);
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
