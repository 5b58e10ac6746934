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
    pub const ALL: [Side; 7] = [
        Side::Scene,
        Side::On,
        Side::Off,
        Side::KullaConty,
        Side::Turquin,
        Side::FdezAguera,
        Side::Truth,
    ];

    /// The name the command line and the panel use.
    pub fn name(self) -> &'static str {
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
pub const DIFFERENCE_SCALES: [u32; 7] = [1, 2, 4, 8, 16, 32, 64];

/// How the two sides are shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// Left of the split the left side, right of it the right side.
    Wipe,
    /// `|left - right|` of the displayed values (the largest channel's), times `scale`,
    /// in the colour ramp of `difference.rs`, with a colour bar.
    Difference {
        /// One of [`DIFFERENCE_SCALES`].
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
    pub fn scenes(&self, scene: &Scene) -> (Scene, Scene) {
        (self.left.apply(scene), self.right.apply(scene))
    }

    /// The first column right of the split in a scene area `width` pixels wide: columns
    /// `0..split_px` show the left side, `split_px..width` the right one.
    pub fn split_px(&self, width: u32) -> u32 {
        let split = if self.split.is_nan() { 0.5 } else { self.split };
        (split.clamp(0.0, 1.0) * width as f64).round() as u32
    }

    /// The split that puts the line at pixel column `x` of a scene area `width` wide.
    pub fn split_at(x: f64, width: u32) -> f64 {
        (x / width.max(1) as f64).clamp(0.0, 1.0)
    }

    /// Whether the comparison has truth balls on either side (they accumulate).
    pub fn has_truth(&self, scene: &Scene) -> bool {
        let (a, b) = self.scenes(scene);
        a.has_truth() || b.has_truth()
    }
}

/// `--compare A,B`: two side names separated by a comma.
pub fn parse_sides(s: &str) -> Result<(Side, Side), String> {
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
