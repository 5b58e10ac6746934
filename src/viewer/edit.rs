//! The edits the viewer's panel and keys make to a [`Scene`]: pure functions, so that each
//! is tested without a window. The viewer holds one `Scene` and draws it as the headless
//! renderer would; every control is one of these functions applied to it.

use std::sync::Arc;

use glam::DVec3;

use crate::environment::{Background, Builtin, EnvMap, Environment, Source};

use crate::scene::{grid_position, Ball, Light, Material, Model, Scene};
use crate::scene::{REFERENCE_ALBEDO_SRGB, REFERENCE_RADIUS};

/// Most balls per row the panel offers (two rows stay within [`crate::scene::MAX_BALLS`]).
pub(crate) const MAX_BALLS_PER_ROW: u32 = 32;

/// The materials the panel offers. Metal F0 values are linear RGB from Real-Time Rendering,
/// 4th ed. (Akenine-Möller et al. 2018), Table 9.2; copper is the homework's sRGB albedo.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum MaterialChoice {
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
    /// A red plastic: base colour sRGB (0.8, 0.15, 0.1) under a coating of IOR 1.5.
    Plastic,
    /// Rubber: a near-black base, sRGB (0.05, 0.05, 0.05), under a coating of IOR 1.52
    /// (natural rubber's refractive index, Brandrup & Immergut, Polymer Handbook).
    Rubber,
    /// The engines' material: base colour (sRGB), metallic, IOR.
    MetallicRoughness {
        /// sRGB.
        base_color: [f64; 3],
        /// In [0, 1].
        metallic: f64,
        /// In `scene::IOR_RANGE`.
        ior: f64,
    },
}

impl MaterialChoice {
    /// Every choice the panel lists (custom with the homework copper's F0 to start from).
    pub(crate) fn all() -> [MaterialChoice; 10] {
        [
            MaterialChoice::AsScene,
            MaterialChoice::Copper,
            MaterialChoice::Gold,
            MaterialChoice::Silver,
            MaterialChoice::Aluminium,
            MaterialChoice::White,
            MaterialChoice::Custom(Material::metal_gamma22(REFERENCE_ALBEDO_SRGB).f0.to_array()),
            MaterialChoice::Plastic,
            MaterialChoice::Rubber,
            MaterialChoice::MetallicRoughness {
                base_color: [1.0, 0.847, 0.569],
                metallic: 0.5,
                ior: crate::scene::DEFAULT_IOR,
            },
        ]
    }

    /// The choice's label in the panel.
    pub(crate) fn name(self) -> &'static str {
        match self {
            MaterialChoice::AsScene => "as in the scene",
            MaterialChoice::Copper => "copper (homework)",
            MaterialChoice::Gold => "gold",
            MaterialChoice::Silver => "silver",
            MaterialChoice::Aluminium => "aluminium",
            MaterialChoice::White => "white (F0 = 1)",
            MaterialChoice::Custom(_) => "custom F0",
            MaterialChoice::Plastic => "red plastic (IOR 1.5)",
            MaterialChoice::Rubber => "rubber (IOR 1.52)",
            MaterialChoice::MetallicRoughness { .. } => "base colour, metallic, IOR",
        }
    }

    /// The material this choice names; `None` for [`MaterialChoice::AsScene`].
    pub(crate) fn material(self) -> Option<Material> {
        let metal =
            |f0: [f64; 3]| Material::metal(DVec3::from_array(f0).clamp(DVec3::ZERO, DVec3::ONE));
        match self {
            MaterialChoice::AsScene => None,
            MaterialChoice::Copper => Some(Material::metal_gamma22(REFERENCE_ALBEDO_SRGB)),
            MaterialChoice::Gold => Some(metal([1.000, 0.782, 0.344])),
            MaterialChoice::Silver => Some(metal([0.972, 0.960, 0.915])),
            MaterialChoice::Aluminium => Some(metal([0.913, 0.922, 0.924])),
            MaterialChoice::White => Some(metal([1.0; 3])),
            MaterialChoice::Custom(f0) => Some(metal(f0)),
            MaterialChoice::Plastic => Some(Material::metallic_roughness(
                crate::scene::srgb_decode([0.8, 0.15, 0.1]),
                0.0,
                crate::scene::DEFAULT_IOR,
            )),
            MaterialChoice::Rubber => Some(Material::metallic_roughness(
                crate::scene::srgb_decode([0.05; 3]),
                0.0,
                1.52,
            )),
            MaterialChoice::MetallicRoughness {
                base_color,
                metallic,
                ior,
            } => Some(Material::metallic_roughness(
                crate::scene::srgb_decode(base_color.map(|c| c.clamp(0.0, 1.0))),
                metallic.clamp(0.0, 1.0),
                ior.clamp(crate::scene::IOR_RANGE.0, crate::scene::IOR_RANGE.1),
            )),
        }
    }
}

/// Gives every ball `material`.
pub(crate) fn set_material(scene: &mut Scene, material: Material) {
    for ball in &mut scene.balls {
        ball.material = material;
    }
}

/// "As in the scene": ball `i` gets `originals[i]`, the material the scene file gave it
/// (the first of them for balls past its count, a grid's); no change with none.
pub(crate) fn restore_materials(scene: &mut Scene, originals: &[Material]) {
    for (i, ball) in scene.balls.iter_mut().enumerate() {
        if let Some(m) = originals.get(i).or(originals.first()) {
            ball.material = *m;
        }
    }
}

/// Rows of balls: indices grouped by the height of their centres, top row first.
pub(crate) fn rows(scene: &Scene) -> Vec<Vec<usize>> {
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
pub(crate) fn row_has_term(scene: &Scene, row: &[usize]) -> bool {
    row.iter().all(|&i| scene.balls[i].model.has_term())
}

/// Turns the term on (the scene's, [`Scene::term`]) or off (model `none`) for the balls
/// of `row`; the truth stays the truth.
pub(crate) fn set_row_term(scene: &mut Scene, row: &[usize], on: bool) {
    let model = term_model(scene, on);
    for &i in row {
        if scene.balls[i].model != Model::Truth {
            scene.balls[i].model = model;
        }
    }
}

/// Key M: the term on every ball, or off on every ball if all had it (the truth stays).
pub fn toggle_term(scene: &mut Scene) {
    let on = !scene
        .balls
        .iter()
        .all(|b| b.model.has_term() || b.model == Model::Truth);
    let model = term_model(scene, on);
    for ball in &mut scene.balls {
        if ball.model != Model::Truth {
            ball.model = model;
        }
    }
}

/// The model a ball gets when its term is turned on or off.
fn term_model(scene: &Scene, on: bool) -> Model {
    if on {
        Model::from_term(scene.term())
    } else {
        Model::None
    }
}

/// A grid of two rows: `per_row` balls each, roughness evenly from `low` to `high` along a
/// row, top row with the term; the reference scene's spacing and radius up to five balls,
/// both shrunk in proportion beyond, so that a row is no wider than the reference's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Grid {
    /// Balls per row (clamped to `1..=MAX_BALLS_PER_ROW`).
    pub per_row: u32,
    /// Roughness of a row's first ball (column 0, on the right; clamped to `[0, 1]`).
    pub low: f64,
    /// Roughness of a row's last ball (clamped to `[0, 1]`).
    pub high: f64,
}

impl Grid {
    /// The reference scene's grid: five balls, roughness 0.15 to 0.95.
    pub(crate) const REFERENCE: Grid = Grid {
        per_row: 5,
        low: 0.15,
        high: 0.95,
    };

    /// The balls of this grid, all made of `material`.
    pub(crate) fn balls(&self, material: Material) -> Vec<Ball> {
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
                        model: if row == 0 {
                            Model::KullaConty
                        } else {
                            Model::None
                        },
                        label: None,
                    }
                })
            })
            .collect()
    }
}

/// The light the panel edits: a direction by azimuth (about +y, 0 = towards +z, the camera
/// side) and elevation (above the horizon), and a white intensity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct LightControl {
    /// Angle about +y in degrees, 0 towards +z.
    pub azimuth_deg: f64,
    /// Angle above the horizon in degrees.
    pub elevation_deg: f64,
    /// Radiance of each channel; no light when not positive.
    pub intensity: f64,
}

impl LightControl {
    /// The control describing the scene's first light (zero intensity when it has none).
    pub(crate) fn of(scene: &Scene) -> Self {
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
    pub(crate) fn lights(&self) -> Vec<Light> {
        // Zero, negative or NaN: no light.
        if self.intensity.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Vec::new();
        }
        let (az, el) = (
            self.azimuth_deg.to_radians(),
            self.elevation_deg.to_radians(),
        );
        let direction = DVec3::new(el.cos() * az.sin(), el.sin(), el.cos() * az.cos());
        vec![Light::new(
            direction.normalize(),
            DVec3::splat(self.intensity),
        )]
    }
}

/// The white furnace's environment radiance.
const FURNACE_RADIANCE: DVec3 = DVec3::ONE;

/// The lighting the furnace replaced: the lights, the uniform environment radiance, the
/// environment map and the background.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SavedLighting {
    /// The scene's lights.
    pub lights: Vec<Light>,
    /// The uniform environment radiance.
    pub environment: DVec3,
    /// The environment map (its `Arc` kept: back on, it is not prefiltered again).
    pub environment_map: Option<Environment>,
    /// What the pixels no ball covers showed.
    pub background: Background,
}

impl Default for SavedLighting {
    /// No lights, no environment, no map, the background showing the environment.
    fn default() -> Self {
        SavedLighting {
            lights: Vec::new(),
            environment: DVec3::ZERO,
            environment_map: None,
            background: Background::Environment,
        }
    }
}

/// Key F and the panel's furnace box: a uniform white environment with the lights and any
/// environment map off and the background showing the environment, or back to the
/// lighting in `saved` (which holds it while the furnace is on; no lights, no environment
/// and no map when nothing was saved, as for a scene file that is the furnace).
pub(crate) fn set_furnace(scene: &mut Scene, on: bool, saved: &mut Option<SavedLighting>) {
    if on == is_furnace(scene) {
        return;
    }
    if on {
        *saved = Some(SavedLighting {
            lights: std::mem::take(&mut scene.lights),
            environment: scene.environment,
            environment_map: scene.environment_map.take(),
            background: scene.background,
        });
        scene.environment = FURNACE_RADIANCE;
        scene.background = Background::Environment;
    } else {
        let s = saved.take().unwrap_or_default();
        scene.lights = s.lights;
        scene.environment = s.environment;
        scene.environment_map = s.environment_map;
        scene.background = s.background;
    }
}

/// Whether the scene is the white furnace: the furnace's uniform environment, shown as
/// the background, and no lights and no environment map.
pub(crate) fn is_furnace(scene: &Scene) -> bool {
    scene.environment == FURNACE_RADIANCE
        && scene.lights.is_empty()
        && scene.environment_map.is_none()
        && scene.background == Background::Environment
}

/// The environment picker's choices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum EnvironmentChoice {
    /// No map: the scene's uniform radiance.
    Uniform,
    /// A generated built-in map.
    Builtin(Builtin),
    /// The map file the scene came with.
    File,
}

impl EnvironmentChoice {
    /// What lights `scene` now.
    pub(crate) fn of(scene: &Scene) -> Self {
        match scene.environment_map.as_ref().map(|e| &e.source) {
            None => EnvironmentChoice::Uniform,
            Some(Source::Builtin(b)) => EnvironmentChoice::Builtin(*b),
            Some(Source::File(_)) => EnvironmentChoice::File,
        }
    }

    /// The choice's label in the panel.
    pub(crate) fn name(self) -> &'static str {
        match self {
            EnvironmentChoice::Uniform => "uniform",
            EnvironmentChoice::Builtin(b) => b.name(),
            EnvironmentChoice::File => "file (as loaded)",
        }
    }
}

/// What the environment picker keeps between choices: the scene's uniform radiance, the map
/// file it came with, every built-in generated so far (each generated once, its `Arc` kept so
/// that the renderer knows it again), and the latest map's rotation and intensity (a new
/// choice keeps them).
#[derive(Clone, Debug)]
pub(crate) struct EnvironmentControl {
    /// The uniform radiance "uniform" restores (the scene's as loaded, or as it was when a
    /// map was chosen).
    pub uniform: DVec3,
    /// The map file the scene came with.
    pub file: Option<Environment>,
    /// The built-ins generated so far.
    builtins: Vec<(Builtin, Arc<EnvMap>)>,
    /// Rotation in degrees and intensity of the latest map.
    transform: (f64, f64),
}

impl EnvironmentControl {
    /// The control for `scene` as loaded (a built-in it came with counts as generated).
    pub(crate) fn of(scene: &Scene) -> Self {
        let map = scene.environment_map.as_ref();
        let builtins = match map {
            Some(Environment {
                source: Source::Builtin(b),
                map,
                ..
            }) => vec![(*b, map.clone())],
            _ => Vec::new(),
        };
        EnvironmentControl {
            uniform: scene.environment,
            file: map.filter(|e| matches!(e.source, Source::File(_))).cloned(),
            builtins,
            transform: map.map_or((0.0, 1.0), |e| (e.rotation_deg, e.intensity)),
        }
    }

    /// The choices the picker lists: uniform, the built-ins, and the file if the scene came
    /// with one.
    pub(crate) fn choices(&self) -> Vec<EnvironmentChoice> {
        let mut all = vec![EnvironmentChoice::Uniform];
        all.extend(Builtin::ALL.map(EnvironmentChoice::Builtin));
        if self.file.is_some() {
            all.push(EnvironmentChoice::File);
        }
        all
    }

    /// Built-in `b`'s map: generated on the first call, the same `Arc` after.
    pub(crate) fn builtin_map(&mut self, b: Builtin) -> Arc<EnvMap> {
        if let Some((_, map)) = self.builtins.iter().find(|(c, _)| *c == b) {
            return map.clone();
        }
        let map = Environment::builtin(b).map;
        self.builtins.push((b, map.clone()));
        map
    }

    /// How many built-ins have been generated.
    #[cfg(test)]
    pub(crate) fn builtins_generated(&self) -> usize {
        self.builtins.len()
    }
}

/// The picker: lights `scene` with `choice`. A map keeps the latest map's rotation and
/// intensity and zeroes the uniform radiance (kept in `control` for "uniform" to restore,
/// as a scene file with a map leaves it black); "uniform" removes the map. Choosing what is
/// already shown, or the file when the scene came with none, changes nothing.
pub(crate) fn set_environment(
    scene: &mut Scene,
    choice: EnvironmentChoice,
    control: &mut EnvironmentControl,
) {
    if choice == EnvironmentChoice::of(scene) {
        return;
    }
    let (source, map) = match choice {
        EnvironmentChoice::Uniform => {
            if let Some(e) = scene.environment_map.take() {
                control.transform = (e.rotation_deg, e.intensity);
            }
            scene.environment = control.uniform;
            return;
        }
        EnvironmentChoice::Builtin(b) => (Source::Builtin(b), control.builtin_map(b)),
        EnvironmentChoice::File => match &control.file {
            Some(file) => (file.source.clone(), file.map.clone()),
            None => return,
        },
    };
    match &scene.environment_map {
        Some(e) => control.transform = (e.rotation_deg, e.intensity),
        None => control.uniform = scene.environment,
    }
    scene.environment = DVec3::ZERO;
    scene.environment_map = Some(Environment {
        source,
        map,
        rotation_deg: control.transform.0,
        intensity: control.transform.1,
    });
}

/// The panel's map file field and a file dropped on the window: loads the `.hdr` or
/// `.exr` at `path` and lights `scene` with it, as the picker's "file (as loaded)" (which
/// it becomes from then on), with the latest map's rotation and intensity. An error (a
/// missing or bad file, or the furnace on: it has no map) leaves everything as it was.
pub(crate) fn load_map_file(
    scene: &mut Scene,
    path: &std::path::Path,
    control: &mut EnvironmentControl,
) -> crate::Result<()> {
    if is_furnace(scene) {
        return Err(crate::Error::Invalid {
            what: "environment",
            message: "the furnace is on: turn it off to light the balls with a map".into(),
        });
    }
    let loaded = Environment::from_file(path)?;
    if EnvironmentChoice::of(scene) == EnvironmentChoice::File {
        if let Some(e) = &mut scene.environment_map {
            e.source = loaded.source.clone();
            e.map = loaded.map.clone();
        }
        control.file = Some(loaded);
        return Ok(());
    }
    control.file = Some(loaded);
    set_environment(scene, EnvironmentChoice::File, control);
    Ok(())
}

/// Turns the scene's environment map (if any) to `degrees` about `+y`; the map itself is
/// kept (the same `Arc`: nothing is prefiltered again).
pub(crate) fn set_map_rotation(scene: &mut Scene, degrees: f64) {
    if let Some(e) = &mut scene.environment_map {
        e.rotation_deg = degrees;
    }
}

/// Scales the scene's environment map (if any) by `intensity` (negative or NaN: 0); the map
/// itself is kept.
pub(crate) fn set_map_intensity(scene: &mut Scene, intensity: f64) {
    if let Some(e) = &mut scene.environment_map {
        // At most what keeps the map within the scene's bound on radiance (issue 38, 1).
        e.intensity = intensity
            .max(0.0)
            .min(crate::environment::max_map_intensity(e.map.peak()));
    }
}
