//! The side panel: every live setting, and what the last frame cost. Each control edits the
//! viewer's [`Scene`] through [`super::edit`] or the bake settings; the viewer compares
//! before and after to know what to redo.

use glam::DVec3;

use crate::brdf::Geometry;
use crate::display::ToneMap;
use crate::environment::{Background, IblMethod, IblTerm, MAX_IBL_SAMPLES};
use crate::lut::{Layout, LayoutKind};
use crate::scene::{BaseReading, Layering, Material, Preset, Scene, MAX_MAGNITUDE};

use super::compare::{Compare, Side, View, DIFFERENCE_SCALES};
use super::edit::{
    self, EnvironmentChoice, EnvironmentControl, Grid, LightControl, MaterialChoice, SavedLighting,
    MAX_BALLS_PER_ROW,
};

/// The panel's width in points (egui's logical pixels).
pub(crate) const PANEL_WIDTH: f32 = 300.0;
/// Largest table side the panel offers (the bake grows as the square).
pub(crate) const MAX_PANEL_TABLE_SIDE: usize = 512;

/// The panel's own state: choices that are not fields of the scene.
pub(crate) struct Controls {
    pub material: MaterialChoice,
    /// `None` while the balls are the scene's own; a grid once the user asks for one.
    pub grid: Option<Grid>,
    pub light: LightControl,
    /// The scene's lighting while the furnace is on.
    pub saved_lighting: Option<SavedLighting>,
    /// Each ball's material in the scene as loaded ("as in the scene").
    pub scene_materials: Vec<Material>,
    pub layout: LayoutKind,
    pub table_size: (usize, usize),
    /// The environment picker's memory (uniform radiance, map file, built-ins generated).
    pub environment: EnvironmentControl,
    /// The scene file's background colour, if it gave one (offered beside environment
    /// and black).
    pub background_colour: Option<DVec3>,
    /// The map file field's text.
    pub map_path: String,
    /// What the latest map file load said (loaded, or its error).
    pub map_status: Option<String>,
    /// What the panel's buttons asked for this frame (the viewer takes them).
    pub requests: Requests,
    /// The comparison shown (`None`: the scene alone).
    pub compare: Option<Compare>,
    /// The comparison last shown, brought back when the box is ticked again.
    pub last_compare: Compare,
    /// The name field of the screenshot, EXR and save buttons: the file's name without its
    /// extension (empty: a time-stamped name).
    pub file_name: String,
    /// The camera at start, brought back by "reset camera".
    pub home_camera: crate::scene::Camera,
}

impl Controls {
    pub(crate) fn new(scene: &Scene, layout: &Layout, compare: Option<Compare>) -> Self {
        Controls {
            map_path: String::new(),
            map_status: None,
            file_name: String::new(),
            home_camera: scene.camera,
            requests: Requests::default(),
            compare,
            last_compare: compare.unwrap_or(Compare::new(Side::On, Side::Off)),
            material: MaterialChoice::AsScene,
            grid: None,
            light: LightControl::of(scene),
            saved_lighting: None,
            scene_materials: scene.balls.iter().map(|b| b.material).collect(),
            layout: layout.kind,
            table_size: (layout.mu_size, layout.r_size),
            environment: EnvironmentControl::of(scene),
            background_colour: match scene.background {
                Background::Colour(c) => Some(c),
                _ => None,
            },
        }
    }

    /// The table layout these controls ask for.
    pub(crate) fn table_layout(&self) -> Layout {
        Layout::of_kind(self.layout).with_size(self.table_size.0, self.table_size.1)
    }
}

/// The panel's buttons pressed this frame.
#[derive(Default)]
pub(crate) struct Requests {
    /// A PNG screenshot of the window (as key S).
    pub png: bool,
    /// The scene area's linear radiance as an EXR (as key E).
    pub exr: bool,
    /// The scene as a scene file.
    pub save_scene: bool,
}

impl Controls {
    /// The file the buttons write with `extension`: the name field's (an extension typed
    /// in it replaced), else a time-stamped name in the current folder.
    pub(crate) fn file_for(&self, extension: &str) -> std::path::PathBuf {
        let name = self.file_name.trim();
        if name.is_empty() {
            return super::capture::timestamped(extension);
        }
        std::path::Path::new(name).with_extension(extension)
    }
}

/// What the panel reports.
pub(crate) struct Stats {
    /// Median wall time of recent frames, milliseconds.
    pub frame_ms: Option<f64>,
    /// The latest bake's wall time, milliseconds.
    pub bake_ms: Option<f64>,
    /// The latest environment map's upload and prefilter time, milliseconds.
    pub prefilter_ms: Option<f64>,
    pub adapter: String,
    /// What the plan baked and binds (one line), and the rows held in the cache.
    pub plan: String,
    /// The scene area in pixels.
    pub scene_size: (u32, u32),
    /// Estimates a pixel the truth balls' image holds (`None` without truth balls).
    pub truth_samples: Option<u32>,
    /// Lobe samples a pixel the image holds (`None` when no ball uses the lobe).
    pub lobe_samples: Option<u32>,
    /// A comparison's numbers per ball (mean displayed value of each side, their ratio),
    /// measured from the sides' images when the figures were taken.
    pub numbers: Option<Vec<super::compare::BallNumbers>>,
}

/// Shows the panel on the right of `ui`.
pub(crate) fn show(ui: &mut egui::Ui, scene: &mut Scene, controls: &mut Controls, stats: &Stats) {
    egui::Panel::right("settings")
        .exact_size(PANEL_WIDTH)
        .show(ui, |ui| {
            // A solid scroll bar (shown where the panel is taller than the window): egui's
            // floating one fades in and out as the pointer enters and leaves the panel, an
            // animation of several frames for every hover (the idle test's 22 frames grew
            // to 33-41 once the panel outgrew the window).
            ui.spacing_mut().scroll = egui::style::ScrollStyle::solid();
            egui::ScrollArea::vertical().show(ui, |ui| {
                report(ui, stats);
                ui.separator();
                model(ui, scene, controls);
                ui.separator();
                balls(ui, scene, controls);
                ui.separator();
                lighting(ui, scene, controls);
                ui.separator();
                environment(ui, scene, controls);
                ui.separator();
                comparison(ui, controls, stats);
                ui.separator();
                layers(ui, scene);
                ui.separator();
                if ui.button("reset camera").clicked() {
                    scene.camera = controls.home_camera;
                }
                ui.horizontal(|ui| {
                    ui.label("file name");
                    ui.add(
                        egui::TextEdit::singleline(&mut controls.file_name)
                            .hint_text("time-stamped")
                            .desired_width(120.0),
                    );
                });
                ui.horizontal(|ui| {
                    controls.requests.png |= ui.button("screenshot").clicked();
                    controls.requests.exr |= ui.button("EXR").clicked();
                    controls.requests.save_scene |= ui.button("save scene").clicked();
                });
                ui.label("Drag: orbit · wheel: zoom · M: term on all · F: furnace · S: screenshot · E: EXR · Esc: close a menu, quit");
            });
        });
}

fn report(ui: &mut egui::Ui, stats: &Stats) {
    ui.heading("shadeballs");
    let ms = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.1} ms"));
    ui.label(format!("frame {} (median)", ms(stats.frame_ms)));
    ui.label(format!("bake {} (latest change)", ms(stats.bake_ms)));
    if stats.prefilter_ms.is_some() {
        ui.label(format!(
            "environment prefilter {} (latest map)",
            ms(stats.prefilter_ms)
        ));
    }
    ui.label(&stats.plan);
    if let Some(n) = stats.truth_samples {
        ui.label(format!(
            "truth: {n} samples a pixel (accumulating while nothing changes)"
        ));
    }
    if let Some(n) = stats.lobe_samples {
        let state = if n < super::compose::LOBE_SAMPLE_CAP {
            "converging while nothing changes"
        } else {
            "done"
        };
        ui.label(format!("lobe: {n} samples a pixel ({state})"));
    }
    ui.label(format!(
        "scene {}x{} on {}",
        stats.scene_size.0, stats.scene_size.1, stats.adapter
    ));
}

fn model(ui: &mut egui::Ui, scene: &mut Scene, controls: &mut Controls) {
    combo(ui, "preset", &mut scene.preset, &Preset::ALL, |p| p.name());
    let forced = scene.preset.geometry();
    ui.add_enabled_ui(forced.is_none(), |ui| {
        combo(
            ui,
            "geometry term",
            &mut scene.geometry,
            &Geometry::ALL,
            |g| g.name(),
        );
    });
    if let Some(g) = forced {
        ui.label(format!("({} forces {} G)", scene.preset.name(), g.name()));
    }
    combo(
        ui,
        "table layout",
        &mut controls.layout,
        &LayoutKind::ALL,
        |k| k.name(),
    );
    ui.horizontal(|ui| {
        let range = 2..=MAX_PANEL_TABLE_SIDE;
        ui.label("table");
        ui.add(egui::DragValue::new(&mut controls.table_size.0).range(range.clone()));
        ui.label("mu x");
        ui.add(egui::DragValue::new(&mut controls.table_size.1).range(range));
        ui.label("roughness");
    });
    // Only where a ball has a dielectric part: the form weights nothing else.
    if scene.balls.iter().any(|b| b.material.has_dielectric()) {
        combo(
            ui,
            "layering (dielectrics)",
            &mut scene.layering,
            &Layering::ALL,
            |l| l.name(),
        );
        base_reading(ui, scene);
    }
}

/// The base reading's combo box's id salt.
const BASE_READING_ID: &str = "base reading";

/// What a dielectric's base colour means (`base_reading`, as `--base-reading`): the colour
/// a viewer sees or the substrate's albedo under the coating (issue 35). Returns its combo
/// box (its test clicks it).
fn base_reading(ui: &mut egui::Ui, scene: &mut Scene) -> egui::Response {
    let name = |r: BaseReading| match r {
        BaseReading::Apparent => "apparent (as glTF)",
        BaseReading::Substrate => "substrate (under the coating)",
    };
    egui::ComboBox::new(BASE_READING_ID, "base colour reading")
        .selected_text(name(scene.base_reading))
        .show_ui(ui, |ui| {
            for r in BaseReading::ALL {
                ui.selectable_value(&mut scene.base_reading, r, name(r));
            }
        })
        .response
}

fn balls(ui: &mut egui::Ui, scene: &mut Scene, controls: &mut Controls) {
    if controls.grid.is_none() {
        ui.label(format!(
            "the scene's own {} balls; a grid replaces them once these move",
            scene.balls.len()
        ));
    }
    let mut grid = controls.grid.unwrap_or(Grid::REFERENCE);
    let mut changed = ui
        .add(egui::Slider::new(&mut grid.per_row, 1..=MAX_BALLS_PER_ROW).text("balls per row"))
        .changed();
    changed |= ui
        .add(egui::Slider::new(&mut grid.low, 0.0..=1.0).text("roughness from"))
        .changed();
    changed |= ui
        .add(egui::Slider::new(&mut grid.high, 0.0..=1.0).text("roughness to"))
        .changed();
    if changed {
        let material = controls
            .material
            .material()
            .or(scene.balls.first().map(|b| b.material))
            .unwrap_or(crate::scene::Material::metal_gamma22(
                crate::scene::REFERENCE_ALBEDO_SRGB,
            ));
        scene.balls = grid.balls(material);
        controls.grid = Some(grid);
    }
    for (i, row) in edit::rows(scene).iter().enumerate() {
        let mut on = edit::row_has_term(scene, row);
        if ui
            .checkbox(&mut on, format!("row {}: multiple-scattering term", i + 1))
            .changed()
        {
            edit::set_row_term(scene, row, on);
        }
    }
    let before = controls.material;
    egui::ComboBox::from_label("material")
        .selected_text(controls.material.name())
        .show_ui(ui, |ui| {
            for choice in MaterialChoice::all() {
                let selected =
                    std::mem::discriminant(&choice) == std::mem::discriminant(&controls.material);
                if ui.selectable_label(selected, choice.name()).clicked() && !selected {
                    controls.material = choice;
                }
            }
        });
    if let MaterialChoice::Custom(f0) = &mut controls.material {
        let mut rgb = f0.map(|c| c as f32);
        ui.horizontal(|ui| {
            ui.label("F0 (linear)");
            if ui.color_edit_button_rgb(&mut rgb).changed() {
                *f0 = rgb.map(f64::from);
            }
        });
    }
    if let MaterialChoice::MetallicRoughness {
        base_color,
        metallic,
        ior,
    } = &mut controls.material
    {
        let mut srgb = base_color.map(|c| (c * 255.0).round() as u8);
        ui.horizontal(|ui| {
            ui.label("base colour (sRGB)");
            if ui.color_edit_button_srgb(&mut srgb).changed() {
                *base_color = srgb.map(|c| f64::from(c) / 255.0);
            }
        });
        ui.add(egui::Slider::new(metallic, 0.0..=1.0).text("metallic"));
        let (lo, hi) = crate::scene::IOR_RANGE;
        ui.add(egui::Slider::new(ior, lo..=hi).text("IOR"));
    }
    if controls.material != before {
        match controls.material.material() {
            Some(material) => edit::set_material(scene, material),
            None => edit::restore_materials(scene, &controls.scene_materials),
        }
    }
    ui.checkbox(&mut scene.labels, "labels (roughness, row model, caption)");
}

/// The clear coat of every ball (the first ball's shown; moving a slider sets them all)
/// and, with a coat, its form (docs/design/coat.md).
fn clearcoat(ui: &mut egui::Ui, scene: &mut Scene) {
    let Some(first) = scene.balls.first() else {
        return;
    };
    let mut c = first.material.clearcoat;
    let mut changed = ui
        .add(egui::Slider::new(&mut c.weight, 0.0..=1.0).text("clear coat"))
        .changed();
    changed |= ui
        .add(egui::Slider::new(&mut c.roughness, 0.0..=1.0).text("coat roughness"))
        .changed();
    let (lo, hi) = crate::scene::IOR_RANGE;
    changed |= ui
        .add(egui::Slider::new(&mut c.ior, lo..=hi).text("coat IOR"))
        .changed();
    if changed {
        for b in &mut scene.balls {
            b.material.clearcoat = c;
        }
    }
    if scene.balls.iter().any(|b| b.material.clearcoat.is_on()) {
        combo(
            ui,
            "coat form",
            &mut scene.coat_form,
            &crate::scene::CoatForm::ALL,
            |f| f.name(),
        );
    }
}

/// The anisotropy of every ball with metal (docs/design/anisotropy.md): its strength and
/// its rotation from the ball's tangent, as the first such ball has them.
fn anisotropy(ui: &mut egui::Ui, scene: &mut Scene) {
    let Some(first) = scene.balls.iter().find(|b| b.material.has_metal()) else {
        return;
    };
    let (mut strength, mut rotation) = (
        first.material.anisotropy,
        first.material.anisotropy_rotation,
    );
    let pi = std::f64::consts::PI;
    let mut changed = ui
        .add(egui::Slider::new(&mut strength, 0.0..=1.0).text("anisotropy"))
        .changed();
    changed |= ui
        .add(egui::Slider::new(&mut rotation, -pi..=pi).text("rotation (rad)"))
        .changed();
    if changed {
        for b in scene.balls.iter_mut().filter(|b| b.material.has_metal()) {
            b.material = b.material.with_anisotropy(strength, rotation);
        }
    }
}

fn lighting(ui: &mut egui::Ui, scene: &mut Scene, controls: &mut Controls) {
    let mut furnace = edit::is_furnace(scene);
    if ui
        .checkbox(
            &mut furnace,
            "furnace (uniform white environment, lights off)",
        )
        .changed()
    {
        edit::set_furnace(scene, furnace, &mut controls.saved_lighting);
    }
    ui.add_enabled_ui(!furnace, |ui| {
        let light = &mut controls.light;
        let mut changed = ui
            .add(egui::Slider::new(&mut light.azimuth_deg, -180.0..=180.0).text("light azimuth"))
            .changed();
        changed |= ui
            .add(egui::Slider::new(&mut light.elevation_deg, -90.0..=90.0).text("light elevation"))
            .changed();
        changed |= ui
            .add(egui::Slider::new(&mut light.intensity, 0.0..=20.0).text("light intensity"))
            .changed();
        if changed {
            scene.lights = light.lights();
        }
    });
    ui.add(
        egui::Slider::new(&mut scene.exposure, 1e-3..=1e3)
            .logarithmic(true)
            .text("exposure")
            // A scene file's exposure beyond the slider's range stays as it is.
            .clamping(egui::SliderClamping::Edits),
    );
    scene.exposure = scene.exposure.clamp(f64::MIN_POSITIVE, MAX_MAGNITUDE);
    tone_map(ui, scene);
}

/// The tone mapper's dropdown: the scene's (or its preset's), set on the scene once chosen.
fn tone_map(ui: &mut egui::Ui, scene: &mut Scene) {
    let current = scene.display().tone_map;
    let mut choice = current;
    combo(ui, "tone map", &mut choice, &ToneMap::ALL, ToneMap::name);
    if choice != current {
        scene.tone_map = Some(choice);
    }
}

fn environment(ui: &mut egui::Ui, scene: &mut Scene, controls: &mut Controls) {
    ui.label("Environment");
    // The furnace is its own environment: its box turns it off.
    ui.add_enabled_ui(!edit::is_furnace(scene), |ui| {
        let current = EnvironmentChoice::of(scene);
        let mut choice = current;
        let choices = controls.environment.choices();
        combo(
            ui,
            "environment",
            &mut choice,
            &choices,
            EnvironmentChoice::name,
        );
        if choice != current {
            edit::set_environment(scene, choice, &mut controls.environment);
        }
        if let Some(map) = &scene.environment_map {
            let (mut rotation, mut intensity) = (map.rotation_deg, map.intensity);
            let rotated = ui
                .add(
                    egui::Slider::new(&mut rotation, -180.0..=180.0)
                        .text("map rotation")
                        .suffix("°")
                        .clamping(egui::SliderClamping::Edits),
                )
                .changed();
            if rotated {
                edit::set_map_rotation(scene, rotation);
            }
            let scaled = ui
                .add(
                    egui::Slider::new(&mut intensity, 0.0..=10.0)
                        .logarithmic(true)
                        .text("map intensity")
                        .clamping(egui::SliderClamping::Edits),
                )
                .changed();
            if scaled {
                edit::set_map_intensity(scene, intensity);
            }
            // The term of every ball with one (Scene::set_term, as --ibl-term).
            let mut term = scene.term();
            combo(ui, "IBL term", &mut term, &IblTerm::ALL, |t| t.name());
            if term != scene.term() {
                scene.set_term(term);
            }
            let _ = ibl_method(ui, scene);
        }
        let mut backgrounds = vec![Background::Environment, Background::Black];
        backgrounds.extend(controls.background_colour.map(Background::Colour));
        combo(
            ui,
            "background",
            &mut scene.background,
            &backgrounds,
            |b| match b {
                Background::Environment => "environment",
                Background::Black => "black",
                Background::Colour(_) => "colour (as in the scene)",
            },
        );
        ui.horizontal(|ui| {
            ui.label("map file");
            let field = egui::TextEdit::singleline(&mut controls.map_path)
                .hint_text(".hdr/.exr, or drop one")
                .desired_width(150.0);
            let entered =
                ui.add(field).lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
            if ui.button("load").clicked() || entered {
                let path = std::path::PathBuf::from(controls.map_path.trim());
                load_map(scene, controls, &path);
            }
        });
        if let Some(status) = &controls.map_status {
            ui.label(status);
        }
    });
}

/// The IBL method's combo box's id salt.
const IBL_METHOD_ID: &str = "ibl method";

/// How the map lights the metals (split sum or the lobe's samples) and, under the lobe, the
/// samples a pixel each frame adds (`ibl_method`, `ibl_samples`, as `--ibl-method`,
/// `--ibl-samples`). Returns the method's combo box (its test clicks it).
fn ibl_method(ui: &mut egui::Ui, scene: &mut Scene) -> egui::Response {
    let name = |m: IblMethod| match m {
        IblMethod::SplitSum => "split sum",
        IblMethod::Lobe => "lobe (converges while nothing moves)",
    };
    let method = egui::ComboBox::new(IBL_METHOD_ID, "IBL method")
        .selected_text(name(scene.ibl_method))
        .show_ui(ui, |ui| {
            for m in IblMethod::ALL {
                ui.selectable_value(&mut scene.ibl_method, m, name(m));
            }
        })
        .response;
    if scene.ibl_method == IblMethod::Lobe {
        ui.add(
            egui::Slider::new(&mut scene.ibl_samples, 1..=MAX_IBL_SAMPLES)
                .logarithmic(true)
                .text("lobe samples a frame"),
        );
    }
    method
}

/// Loads the map file at `path` ([`edit::load_map_file`]) and says how it went, in the
/// panel and on stderr.
pub(crate) fn load_map(scene: &mut Scene, controls: &mut Controls, path: &std::path::Path) {
    let status = match edit::load_map_file(scene, path, &mut controls.environment) {
        Ok(()) => format!("map: {}", path.display()),
        Err(e) => {
            eprintln!("error: {e}");
            format!("error: {e}")
        }
    };
    controls.map_path = path.display().to_string();
    controls.map_status = Some(status);
}

/// The Layers section: the metal's anisotropy and the clear coat (collapsed unless a
/// ball has one, so the sections above keep their places).
fn layers(ui: &mut egui::Ui, scene: &mut Scene) {
    let any = scene
        .balls
        .iter()
        .any(|b| b.material.is_anisotropic() || b.material.clearcoat.is_on());
    egui::CollapsingHeader::new("Layers (anisotropy, clear coat)")
        .default_open(any)
        .show(ui, |ui| {
            anisotropy(ui, scene);
            clearcoat(ui, scene);
            emission(ui, scene);
        });
}

/// The emission of every ball (linear radiance per channel, at least 0; the first ball's
/// shown, a change sets them all): added to the light the ball reflects
/// (docs/interop.md, "Emission").
fn emission(ui: &mut egui::Ui, scene: &mut Scene) {
    let Some(first) = scene.balls.first() else {
        return;
    };
    let mut e = first.material.emission.to_array();
    let mut changed = false;
    ui.horizontal(|ui| {
        ui.label("emission (linear)");
        for c in &mut e {
            changed |= ui
                .add(
                    egui::DragValue::new(c)
                        .speed(0.01)
                        .range(0.0..=crate::scene::MAX_MAGNITUDE),
                )
                .changed();
        }
    });
    if changed {
        for b in &mut scene.balls {
            b.material.emission = glam::DVec3::from_array(e);
        }
    }
}

/// The Compare section (collapsed unless a comparison was asked for at start): on/off,
/// the two sides, wipe or difference, the split and the difference's scale.
fn comparison(ui: &mut egui::Ui, controls: &mut Controls, stats: &Stats) {
    egui::CollapsingHeader::new("Compare")
        .default_open(controls.compare.is_some())
        .show(ui, |ui| {
            let mut on = controls.compare.is_some();
            ui.checkbox(&mut on, "compare two renderings (drag the split line)");
            let mut c = controls.compare.unwrap_or(controls.last_compare);
            ui.add_enabled_ui(on, |ui| {
                combo(ui, "left (a)", &mut c.left, &Side::ALL, Side::name);
                combo(ui, "right (b)", &mut c.right, &Side::ALL, Side::name);
                #[derive(PartialEq, Clone, Copy)]
                enum Kind {
                    Wipe,
                    SideBySide,
                    Difference,
                }
                let mut kind = match c.view {
                    View::Wipe => Kind::Wipe,
                    View::SideBySide => Kind::SideBySide,
                    View::Difference { .. } => Kind::Difference,
                };
                ui.horizontal(|ui| {
                    ui.radio_value(&mut kind, Kind::Wipe, "wipe");
                    ui.radio_value(&mut kind, Kind::SideBySide, "side by side");
                    ui.radio_value(&mut kind, Kind::Difference, "|a - b|");
                });
                let mut scale = match (c.view, controls.last_compare.view) {
                    (View::Difference { scale }, _) | (_, View::Difference { scale }) => scale,
                    _ => 4,
                };
                if kind == Kind::SideBySide {
                    c.view = View::SideBySide;
                } else if kind == Kind::Difference {
                    egui::ComboBox::from_label("difference scale")
                        .selected_text(format!("x{scale}"))
                        .show_ui(ui, |ui| {
                            for s in DIFFERENCE_SCALES {
                                ui.selectable_value(&mut scale, s, format!("x{s}"));
                            }
                        });
                    c.view = View::Difference { scale };
                } else {
                    c.view = View::Wipe;
                    ui.add(egui::Slider::new(&mut c.split, 0.0..=1.0).text("split"));
                }
                if let (true, Some(numbers)) = (on, &stats.numbers) {
                    ball_numbers(ui, numbers);
                }
            });
            controls.last_compare = c;
            controls.compare = on.then_some(c);
        });
}

/// The comparison's numbers a ball: its roughness, the mean displayed value of A and of B
/// (0 to 1), and A / B.
fn ball_numbers(ui: &mut egui::Ui, numbers: &[super::compare::BallNumbers]) {
    ui.label("mean displayed value a ball (also in a screenshot's .csv):");
    egui::Grid::new("ball numbers")
        .striped(true)
        .show(ui, |ui| {
            for head in ["ball", "r", "A", "B", "A / B"] {
                ui.label(head);
            }
            ui.end_row();
            let cell =
                |v: Option<f64>, digits: usize| v.map_or("-".into(), |v| format!("{v:.digits$}"));
            for n in numbers {
                ui.label(format!("{}", n.index + 1));
                ui.label(format!("{}", n.roughness));
                ui.label(cell(n.mean[0], 3));
                ui.label(cell(n.mean[1], 3));
                ui.label(cell(n.ratio(), 3));
                ui.end_row();
            }
        });
}

fn combo<T: PartialEq + Copy>(
    ui: &mut egui::Ui,
    label: &str,
    value: &mut T,
    all: &[T],
    name: fn(T) -> &'static str,
) {
    egui::ComboBox::from_label(label)
        .selected_text(name(*value))
        .show_ui(ui, |ui| {
            for &choice in all {
                ui.selectable_value(value, choice, name(choice));
            }
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One pass of the IBL method's control over `scene` with `events` in a 400x300
    /// window; returns its combo box's id and rectangle.
    fn pass(
        ctx: &egui::Context,
        scene: &mut Scene,
        events: Vec<egui::Event>,
    ) -> (egui::Id, egui::Rect) {
        pass_of(ctx, scene, events, ibl_method)
    }

    /// One pass of `control` over `scene` with `events` in a 400x300 window; returns its
    /// combo box's id and rectangle.
    fn pass_of(
        ctx: &egui::Context,
        scene: &mut Scene,
        events: Vec<egui::Event>,
        control: fn(&mut egui::Ui, &mut Scene) -> egui::Response,
    ) -> (egui::Id, egui::Rect) {
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(
                egui::Pos2::ZERO,
                egui::vec2(400.0, 300.0),
            )),
            events,
            ..Default::default()
        };
        let mut method = None;
        let _ = ctx.run_ui(input, |ui| method = Some(control(ui, scene)));
        let method = method.expect("the pass ran the control");
        (method.id, method.rect)
    }

    /// A click of the primary button at `at`.
    fn click(at: egui::Pos2) -> Vec<egui::Event> {
        let button = |pressed| egui::Event::PointerButton {
            pos: at,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: Default::default(),
        };
        vec![egui::Event::PointerMoved(at), button(true), button(false)]
    }

    /// The panel's IBL method control: a click on its box opens the list, a click on its
    /// second entry switches the scene to the lobe, on the first back to the split sum.
    #[test]
    fn the_ibl_method_control_switches_the_scene_between_split_sum_and_lobe() {
        let ctx = egui::Context::default();
        let mut scene = Scene::reference();
        let (id, button) = pass(&ctx, &mut scene, Vec::new());
        let pick = |scene: &mut Scene, entry: f32| {
            pass(&ctx, scene, click(button.center()));
            pass(&ctx, scene, Vec::new());
            let list = ctx
                .memory(|m| m.area_rect(id.with("popup")))
                .expect("the list opens");
            // Two entries, one above the other: `entry` 0 or 1.
            let y = list.min.y + (0.25 + 0.5 * entry) * list.height();
            pass(&ctx, scene, click(egui::pos2(list.center().x, y)));
            pass(&ctx, scene, Vec::new());
        };
        assert_eq!(scene.ibl_method, IblMethod::SplitSum);
        pick(&mut scene, 1.0);
        assert_eq!(scene.ibl_method, IblMethod::Lobe);
        pick(&mut scene, 0.0);
        assert_eq!(scene.ibl_method, IblMethod::SplitSum);
    }

    /// The panel's base reading control (issue 35): a click on its box opens the list, a
    /// click on its second entry reads base colours as the substrate's, on the first back
    /// to the apparent colour.
    #[test]
    fn the_base_reading_control_switches_between_apparent_and_substrate() {
        let ctx = egui::Context::default();
        let mut scene = Scene::reference();
        let (id, button) = pass_of(&ctx, &mut scene, Vec::new(), base_reading);
        let pick = |scene: &mut Scene, entry: f32| {
            pass_of(&ctx, scene, click(button.center()), base_reading);
            pass_of(&ctx, scene, Vec::new(), base_reading);
            let list = ctx
                .memory(|m| m.area_rect(id.with("popup")))
                .expect("the list opens");
            let y = list.min.y + (0.25 + 0.5 * entry) * list.height();
            pass_of(
                &ctx,
                scene,
                click(egui::pos2(list.center().x, y)),
                base_reading,
            );
            pass_of(&ctx, scene, Vec::new(), base_reading);
        };
        assert_eq!(scene.base_reading, BaseReading::Apparent);
        pick(&mut scene, 1.0);
        assert_eq!(scene.base_reading, BaseReading::Substrate);
        pick(&mut scene, 0.0);
        assert_eq!(scene.base_reading, BaseReading::Apparent);
    }
}
