//! The edits the viewer's panel and keys make to a [`Scene`]: pure functions, so that each
//! is tested without a window. The viewer holds one `Scene` and draws it as the headless
//! renderer would; every control is one of these functions applied to it.

use glam::DVec3;

use crate::scene::{grid_position, Ball, Light, Material, MaterialKind, Scene};
use crate::scene::{REFERENCE_ALBEDO_SRGB, REFERENCE_RADIUS};

/// Most balls per row the panel offers (two rows stay within [`crate::scene::MAX_BALLS`]).
pub const MAX_BALLS_PER_ROW: u32 = 32;

/// The materials the panel offers. Metal F0 values are linear RGB from Real-Time Rendering,
/// 4th ed. (Akenine-Möller et al. 2018), Table 9.2; copper is the homework's sRGB albedo.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MaterialChoice {
    /// Each ball keeps the material its scene gave it.
    AsScene,
    /// The homework's copper: sRGB albedo (0.7216, 0.451, 0.2) decoded with `pow 2.2`.
    Copper,
    /// Gold, F0 (1.000, 0.782, 0.344).
    Gold,
    /// Silver, F0 (0.972, 0.960, 0.915).
    Silver,
    /// Aluminium, F0 (0.913, 0.922, 0.924).
    Aluminium,
    /// F0 = 1: with the furnace on, a ball with the term vanishes into the background.
    White,
    /// A metal of any linear F0.
    Custom([f64; 3]),
}

impl MaterialChoice {
    /// Every choice the panel lists (custom with the homework copper's F0 to start from).
    pub fn all() -> [MaterialChoice; 7] {
        [
            MaterialChoice::AsScene,
            MaterialChoice::Copper,
            MaterialChoice::Gold,
            MaterialChoice::Silver,
            MaterialChoice::Aluminium,
            MaterialChoice::White,
            MaterialChoice::Custom(Material::metal_srgb(REFERENCE_ALBEDO_SRGB).f0.to_array()),
        ]
    }

    /// The choice's label in the panel.
    pub fn name(self) -> &'static str {
        match self {
            MaterialChoice::AsScene => "as in the scene",
            MaterialChoice::Copper => "copper (homework)",
            MaterialChoice::Gold => "gold",
            MaterialChoice::Silver => "silver",
            MaterialChoice::Aluminium => "aluminium",
            MaterialChoice::White => "white (F0 = 1)",
            MaterialChoice::Custom(_) => "custom F0",
        }
    }

    /// The metal this choice names; `None` for [`MaterialChoice::AsScene`].
    pub fn material(self) -> Option<Material> {
        let metal = |f0: [f64; 3]| Material {
            kind: MaterialKind::Metal,
            f0: DVec3::from_array(f0).clamp(DVec3::ZERO, DVec3::ONE),
            diffuse: DVec3::ZERO,
        };
        match self {
            MaterialChoice::AsScene => None,
            MaterialChoice::Copper => Some(Material::metal_srgb(REFERENCE_ALBEDO_SRGB)),
            MaterialChoice::Gold => Some(metal([1.000, 0.782, 0.344])),
            MaterialChoice::Silver => Some(metal([0.972, 0.960, 0.915])),
            MaterialChoice::Aluminium => Some(metal([0.913, 0.922, 0.924])),
            MaterialChoice::White => Some(metal([1.0; 3])),
            MaterialChoice::Custom(f0) => Some(metal(f0)),
        }
    }
}

/// Gives every ball `material`.
pub fn set_material(scene: &mut Scene, material: Material) {
    for ball in &mut scene.balls {
        ball.material = material;
    }
}

/// "As in the scene": ball `i` gets `originals[i]`, the material the scene file gave it
/// (the first of them for balls past its count, a grid's); no change with none.
pub fn restore_materials(scene: &mut Scene, originals: &[Material]) {
    for (i, ball) in scene.balls.iter_mut().enumerate() {
        if let Some(m) = originals.get(i).or(originals.first()) {
            ball.material = *m;
        }
    }
}

/// Rows of balls: indices grouped by the height of their centres, top row first.
pub fn rows(scene: &Scene) -> Vec<Vec<usize>> {
    let mut heights: Vec<f64> = scene.balls.iter().map(|b| b.center.y).collect();
    heights.sort_by(|a, b| b.total_cmp(a));
    heights.dedup();
    heights
        .iter()
        .map(|&y| {
            (0..scene.balls.len())
                .filter(|&i| scene.balls[i].center.y == y)
                .collect()
        })
        .collect()
}

/// Whether every ball of `row` (indices from [`rows`]) has the term.
pub fn row_has_term(scene: &Scene, row: &[usize]) -> bool {
    row.iter().all(|&i| scene.balls[i].multiple_scattering)
}

/// Turns the term on or off for the balls of `row`.
pub fn set_row_term(scene: &mut Scene, row: &[usize], on: bool) {
    for &i in row {
        scene.balls[i].multiple_scattering = on;
    }
}

/// Key M: the term on every ball, or off on every ball if all had it.
pub fn toggle_term(scene: &mut Scene) {
    let on = !scene.balls.iter().all(|b| b.multiple_scattering);
    for ball in &mut scene.balls {
        ball.multiple_scattering = on;
    }
}

/// A grid of two rows: `per_row` balls each, roughness evenly from `low` to `high` along a
/// row, top row with the term; the reference scene's spacing and radius up to five balls,
/// both shrunk in proportion beyond, so that a row is no wider than the reference's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// Balls per row (clamped to `1..=MAX_BALLS_PER_ROW`).
    pub per_row: u32,
    /// Roughness of a row's first ball (column 0, on the right; clamped to `[0, 1]`).
    pub low: f64,
    /// Roughness of a row's last ball (clamped to `[0, 1]`).
    pub high: f64,
}

impl Grid {
    /// The reference scene's grid: five balls, roughness 0.15 to 0.95.
    pub const REFERENCE: Grid = Grid {
        per_row: 5,
        low: 0.15,
        high: 0.95,
    };

    /// The balls of this grid, all made of `material`.
    pub fn balls(&self, material: Material) -> Vec<Ball> {
        let n = self.per_row.clamp(1, MAX_BALLS_PER_ROW);
        // The reference row: centre x = 20, spacing 80, five balls of radius 35, 390 wide.
        let centre_x = grid_position(0, 2).x;
        let reference_spacing = grid_position(0, 0).x - grid_position(0, 1).x;
        let width = |n: f64| (n - 1.0) * reference_spacing + 2.0 * REFERENCE_RADIUS;
        let scale = (width(5.0) / width(n as f64)).min(1.0);
        let spacing = reference_spacing * scale;
        let (low, high) = (self.low.clamp(0.0, 1.0), self.high.clamp(0.0, 1.0));
        (0..2u32)
            .flat_map(|row| {
                (0..n).map(move |col| {
                    let t = if n == 1 {
                        0.0
                    } else {
                        col as f64 / (n - 1) as f64
                    };
                    let offset = (n as f64 - 1.0) / 2.0 - col as f64;
                    Ball {
                        center: DVec3::new(
                            centre_x + spacing * offset,
                            grid_position(row, 0).y,
                            0.0,
                        ),
                        radius: REFERENCE_RADIUS * scale,
                        roughness: low + (high - low) * t,
                        material,
                        multiple_scattering: row == 0,
                    }
                })
            })
            .collect()
    }
}

/// The light the panel edits: a direction by azimuth (about +y, 0 = towards +z, the camera
/// side) and elevation (above the horizon), and a white intensity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightControl {
    /// Angle about +y in degrees, 0 towards +z.
    pub azimuth_deg: f64,
    /// Angle above the horizon in degrees.
    pub elevation_deg: f64,
    /// Radiance of each channel; no light when not positive.
    pub intensity: f64,
}

impl LightControl {
    /// The control describing the scene's first light (zero intensity when it has none).
    pub fn of(scene: &Scene) -> Self {
        match scene.lights.first() {
            Some(light) => {
                let d = light.direction;
                LightControl {
                    azimuth_deg: d.x.atan2(d.z).to_degrees(),
                    elevation_deg: d.y.clamp(-1.0, 1.0).asin().to_degrees(),
                    intensity: light.radiance.max_element(),
                }
            }
            None => LightControl {
                azimuth_deg: 0.0,
                elevation_deg: 0.0,
                intensity: 0.0,
            },
        }
    }

    /// The scene's lights under this control: one white light, or none at zero intensity.
    pub fn lights(&self) -> Vec<Light> {
        // Zero, negative or NaN: no light.
        if self.intensity.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Vec::new();
        }
        let (az, el) = (
            self.azimuth_deg.to_radians(),
            self.elevation_deg.to_radians(),
        );
        let direction = DVec3::new(el.cos() * az.sin(), el.sin(), el.cos() * az.cos());
        vec![Light {
            direction: direction.normalize(),
            radiance: DVec3::splat(self.intensity),
        }]
    }
}

/// The white furnace's environment radiance.
const FURNACE_RADIANCE: DVec3 = DVec3::ONE;

/// The lighting the furnace replaced: the lights and the environment radiance.
pub type SavedLighting = (Vec<Light>, DVec3);

/// Key F and the panel's furnace box: a uniform white environment with the lights off, or
/// back to the lighting in `saved` (which holds it while the furnace is on; no lights and
/// no environment when nothing was saved, as for a scene file that is the furnace).
pub fn set_furnace(scene: &mut Scene, on: bool, saved: &mut Option<SavedLighting>) {
    if on == is_furnace(scene) {
        return;
    }
    if on {
        *saved = Some((std::mem::take(&mut scene.lights), scene.environment));
        scene.environment = FURNACE_RADIANCE;
    } else {
        (scene.lights, scene.environment) = saved.take().unwrap_or_default();
    }
}

/// Whether the scene is the white furnace: the furnace's environment and no lights.
pub fn is_furnace(scene: &Scene) -> bool {
    scene.environment == FURNACE_RADIANCE && scene.lights.is_empty()
}
