//! The viewer's comparisons: the scene drawn twice, each time with its balls' models edited
//! ([`Side`]), shown side by side across a draggable split (the wipe) or as their
//! difference, scaled, in a colour ramp ([`View::Difference`], `difference.rs`). Pure: the
//! edits and the split's pixel are tested without a window.

use crate::scene::{Model, Scene};

/// What one side of a comparison shows: the scene with its balls' models edited.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// The scene as it is.
    Scene,
    /// Every ball's multiple-scattering term on (the scene's term, [`Scene::term`]).
    On,
    /// Every ball's term off (model `none`).
    Off,
    /// Every ball Kulla-Conty.
    KullaConty,
    /// Every ball Turquin.
    Turquin,
    /// Every ball Fdez-Aguera.
    FdezAguera,
    /// Every ball the random-walk truth (accumulating while nothing changes; Vulkan).
    Truth,
}

impl Side {
    /// Every side, in the order the help and the panel list them.
    pub(crate) const ALL: [Side; 7] = [
        Side::Scene,
        Side::On,
        Side::Off,
        Side::KullaConty,
        Side::Turquin,
        Side::FdezAguera,
        Side::Truth,
    ];

    /// The name the command line and the panel use.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Side::Scene => "scene",
            Side::On => "on",
            Side::Off => "off",
            Side::KullaConty => "kulla-conty",
            Side::Turquin => "turquin",
            Side::FdezAguera => "fdez-aguera",
            Side::Truth => "truth",
        }
    }

    /// `scene` as this side shows it: the models edited, everything else kept. `on`, `off`
    /// and the terms leave truth balls the truth; `truth` makes every ball the truth.
    pub fn apply(self, scene: &Scene) -> Scene {
        let model = match self {
            Side::Scene => return scene.clone(),
            Side::On => Model::from_term(scene.term()),
            Side::Off => Model::None,
            Side::KullaConty => Model::KullaConty,
            Side::Turquin => Model::Turquin,
            Side::FdezAguera => Model::FdezAguera,
            Side::Truth => Model::Truth,
        };
        let mut out = scene.clone();
        for ball in &mut out.balls {
            if ball.model != Model::Truth || model == Model::Truth {
                ball.model = model;
            }
        }
        out
    }
}

crate::named_enum!(Side, "comparison side");

/// The difference view's scales: `|a - b|` of the displayed values times this, clamped to 1.
pub(crate) const DIFFERENCE_SCALES: [u32; 7] = [1, 2, 4, 8, 16, 32, 64];

/// How the two sides are shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// Left of the split the left side, right of it the right side.
    Wipe,
    /// Each side whole, in its own half of the scene area: A in the left half, B in the
    /// right ([`Compare::halves`]); the split is not used.
    SideBySide,
    /// `|left - right|` of the displayed values (the largest channel's), times `scale`,
    /// in the colour ramp of `difference.rs`, with a colour bar.
    Difference {
        /// One of `DIFFERENCE_SCALES`.
        scale: u32,
    },
}

/// A comparison: two sides, the split's place and the view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Compare {
    /// Shown left of the split (the difference's `a`).
    pub left: Side,
    /// Shown right of the split (the difference's `b`).
    pub right: Side,
    /// The split's place across the scene area, in `[0, 1]`.
    pub split: f64,
    /// Wipe or difference.
    pub view: View,
}

impl Compare {
    /// The wipe of `left` and `right` split at the middle.
    pub fn new(left: Side, right: Side) -> Self {
        Compare {
            left,
            right,
            split: 0.5,
            view: View::Wipe,
        }
    }

    /// The two scenes the comparison draws from `scene`.
    pub(crate) fn scenes(&self, scene: &Scene) -> (Scene, Scene) {
        (self.left.apply(scene), self.right.apply(scene))
    }

    /// The first column right of the split in a scene area `width` pixels wide: columns
    /// `0..split_px` show the left side, `split_px..width` the right one.
    pub fn split_px(&self, width: u32) -> u32 {
        let split = if self.split.is_nan() { 0.5 } else { self.split };
        (split.clamp(0.0, 1.0) * width as f64).round() as u32
    }

    /// The split that puts the line at pixel column `x` of a scene area `width` wide.
    pub(crate) fn split_at(x: f64, width: u32) -> f64 {
        (x / width.max(1) as f64).clamp(0.0, 1.0)
    }

    /// Where each side is drawn across a scene area `width` wide, as `(x0, width)` in
    /// pixels, and the width each side is rendered at: side by side, the left half
    /// (`width / 2`) and the rest; otherwise both sides are rendered over the whole area
    /// (the wipe and the difference take their pixels from both at the same places).
    pub fn halves(&self, width: u32) -> [(u32, u32); 2] {
        match self.view {
            View::SideBySide => {
                let left = (width / 2).max(1);
                [(0, left), (left, width.saturating_sub(left).max(1))]
            }
            _ => [(0, width), (0, width)],
        }
    }
}

/// `--compare A,B`: two side names separated by a comma.
pub(crate) fn parse_sides(s: &str) -> Result<(Side, Side), String> {
    let names: Vec<&str> = Side::ALL.iter().map(|s| s.name()).collect();
    let fail = || {
        format!(
            "'{s}' is not two sides A,B (each one of {})",
            names.join(", ")
        )
    };
    let (a, b) = s.split_once(',').ok_or_else(fail)?;
    let side = |t: &str| t.trim().parse::<Side>().map_err(|_| fail());
    Ok((side(a)?, side(b)?))
}

/// One ball's numbers in a comparison: the mean displayed value of its pixels on each
/// side (0 to 1, the average of the three channels after tone mapping and the transfer
/// curve, as the window shows them) and their ratio `a / b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct BallNumbers {
    /// The ball's index in the scene.
    pub index: usize,
    /// Its roughness.
    pub roughness: f64,
    /// Mean displayed value on side A, and on side B (`None` where the ball shows no
    /// pixel on that side).
    pub mean: [Option<f64>; 2],
}

impl BallNumbers {
    /// `a / b`, where both are known and `b` is not 0.
    pub(crate) fn ratio(&self) -> Option<f64> {
        match self.mean {
            [Some(a), Some(b)] if b > 0.0 => Some(a / b),
            _ => None,
        }
    }
}

/// The mean displayed value of each ball's pixels in `rgba` (RGBA8, `width x height`,
/// row 0 at the top) drawn from `scene`: a pixel counts for the ball its centre's primary
/// ray meets first, so antialiased edges are left out only where the ray misses. `None`
/// for a ball with no pixel.
pub(crate) fn ball_means(scene: &Scene, rgba: &[u8], width: u32, height: u32) -> Vec<Option<f64>> {
    let mut sums = vec![(0.0f64, 0u64); scene.balls.len()];
    if scene.camera.problem().is_some() || rgba.len() != 4 * width as usize * height as usize {
        return vec![None; scene.balls.len()];
    }
    let basis = scene.camera.basis(width, height);
    let rects = crate::labels::ball_rects(scene, width, height);
    for (i, ball) in scene.balls.iter().enumerate() {
        let Some(r) = rects[i] else { continue };
        let (x0, x1) = (r.x0.max(0.0) as u32, (r.x1.ceil() as u32).min(width));
        let (y0, y1) = (r.y0.max(0.0) as u32, (r.y1.ceil() as u32).min(height));
        for y in y0..y1 {
            for x in x0..x1 {
                let d = basis.ray(x, y, width, height);
                let Some(t) = hit(basis.origin, d, ball.center, ball.radius) else {
                    continue;
                };
                // Another ball in front of this one takes the pixel.
                let nearer = scene.balls.iter().enumerate().any(|(j, o)| {
                    j != i && hit(basis.origin, d, o.center, o.radius).is_some_and(|u| u < t)
                });
                if nearer {
                    continue;
                }
                let p = 4 * (y as usize * width as usize + x as usize);
                let v = (rgba[p] as f64 + rgba[p + 1] as f64 + rgba[p + 2] as f64) / (3.0 * 255.0);
                sums[i].0 += v;
                sums[i].1 += 1;
            }
        }
    }
    sums.into_iter()
        .map(|(s, n)| (n > 0).then(|| s / n as f64))
        .collect()
}

/// The nearest positive distance along the unit ray `(o, d)` to the sphere `(c, r)`.
fn hit(o: glam::DVec3, d: glam::DVec3, c: glam::DVec3, r: f64) -> Option<f64> {
    let oc = o - c;
    let b = oc.dot(d);
    let disc = r * r - (oc - b * d).length_squared();
    if disc < 0.0 {
        return None;
    }
    let root = disc.sqrt();
    [-b - root, -b + root].into_iter().find(|t| *t > 0.0)
}

/// Each ball's numbers from the two sides' images (`a` and `b`, RGBA8 of `sizes[0]` and
/// `sizes[1]`), drawn from the comparison `c` of `scene`.
pub(crate) fn numbers(
    c: &Compare,
    scene: &Scene,
    (a, b): (&[u8], &[u8]),
    sizes: [(u32, u32); 2],
) -> Vec<BallNumbers> {
    let (sa, sb) = c.scenes(scene);
    let ma = ball_means(&sa, a, sizes[0].0, sizes[0].1);
    let mb = ball_means(&sb, b, sizes[1].0, sizes[1].1);
    scene
        .balls
        .iter()
        .enumerate()
        .map(|(index, ball)| BallNumbers {
            index,
            roughness: ball.roughness,
            mean: [ma[index], mb[index]],
        })
        .collect()
}

/// The numbers as CSV, a header and a line a ball: `ball,x,y,roughness,a,b,mean_a,mean_b,
/// ratio` (the sides' names, empty cells where a value is unknown).
pub(crate) fn numbers_csv(c: &Compare, scene: &Scene, numbers: &[BallNumbers]) -> String {
    let mut out = String::from("ball,x,y,roughness,a,b,mean_a,mean_b,ratio_a_over_b\n");
    let cell = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.6}"));
    for n in numbers {
        let ball = &scene.balls[n.index];
        out.push_str(&format!(
            "{},{},{},{},{},{},{},{},{}\n",
            n.index + 1,
            ball.center.x,
            ball.center.y,
            n.roughness,
            c.left.name(),
            c.right.name(),
            cell(n.mean[0]),
            cell(n.mean[1]),
            cell(n.ratio()),
        ));
    }
    out
}
