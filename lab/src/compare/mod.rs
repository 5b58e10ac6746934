//! `shadeballs-lab compare`: each model's picture against the truth's (docs/truth.md, "The
//! truth, pictured").
//!
//! One row of balls over the scene's roughness values (its first ball's material, its
//! lights and environment, a camera framing the row) is rendered once per model: `none`,
//! Kulla-Conty under both presets, Turquin, Fdez-Aguera, and Kulla-Conty under each other
//! form the material has ([`rows`]), on the GPU when there is one (else the CPU reference
//! renderer), and the truth by the CPU random walk
//! ([`shadeballs::cpu::render_truth`]). Every row is the same geometry, so a model's image
//! compares with the truth's pixel for pixel ([`image_error`]). Writes `compare.csv`,
//! `compare.png` (the rows stacked, labelled), `heatmaps.png` (each model's relative error,
//! and the truth's own noise as the last row) and `time_vs_error.png` (frame time against
//! image error, a point per model).

pub mod image_error;

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use glam::DVec3;

use crate::plot::{write_plot, Plot, Series, Style};
use image_error::{ball_errors, flip_map, heatmap, BallError};
use shadeballs::cpu::{self, TruthProgress, TruthSettings};
use shadeballs::error::{Error, Result};
use shadeballs::gpu::{Backend, Renderer};
use shadeballs::labels::{self, Align, Label, Labels, Rect};
use shadeballs::lut::{self, BakeConfig, TableSet};
use shadeballs::output::{write_atomic, write_png};
use shadeballs::prepared::Prepared;
use shadeballs::render::{self, Output, Pixels, Request};
use shadeballs::scene::{Ball, Camera, CoatForm, Layering, Model, Preset, Scene};

/// Most columns (distinct roughness values) a comparison draws.
pub const MAX_COLUMNS: usize = 16;
/// World units between ball centres in a row (the reference scene's spacing).
const SPACING: f64 = 80.0;
/// The balls' radius (the reference scene's).
const RADIUS: f64 = 35.0;
/// Camera distance from the row.
const DISTANCE: f64 = 300.0;
/// Full scale of the heatmaps: 20 % relative error is the brightest colour.
pub const HEATMAP_FULL_SCALE: f64 = 0.2;

/// What `shadeballs-lab compare` runs.
#[derive(Clone, Debug)]
pub struct CompareOptions {
    /// The scene whose roughness values, first material, lights and environment are used.
    pub scene: Scene,
    /// Folder for the outputs.
    pub out: PathBuf,
    /// Estimates per pixel of the truth.
    pub spp: u32,
    /// Seed of the truth.
    pub seed: u64,
    /// Pixels per ball: each row is `columns * cell` by `cell`.
    pub cell: u32,
    /// The frame time is measured at this size (the user's scene, every ball the model).
    pub timing_size: (u32, u32),
}

/// One row of the chart: a model under a preset, a layering form and a coat form.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// Its name in the CSV and on the picture.
    pub name: String,
    /// The model.
    pub model: Model,
    /// The preset (and so G and the F_avg form) it is evaluated with.
    pub preset: Preset,
    /// How a dielectric's base sits under its coating (the scene's, except in the rows
    /// of the other forms).
    pub layering: Layering,
    /// How a clear coat weights the base (the scene's, except in the rows of the other
    /// coat forms).
    pub coat_form: CoatForm,
    /// Whether the row draws the material without its anisotropy (the same roughness,
    /// isotropic): what a renderer without glTF's `KHR_materials_anisotropy` draws.
    pub anisotropy_ignored: bool,
}

/// One row's measurements.
#[derive(Clone, Debug)]
pub struct RowResult {
    /// The row.
    pub row: Row,
    /// Per column, the ball's errors against the truth.
    pub errors: Vec<BallError>,
    /// Median frame time in milliseconds (the truth: the whole render's wall time).
    pub frame_ms: f64,
}

/// Everything a comparison measured.
#[derive(Clone, Debug)]
pub struct Comparison {
    /// The roughness of each column.
    pub roughness: Vec<f64>,
    /// The model rows (not the truth).
    pub rows: Vec<RowResult>,
    /// The truth's estimates per pixel and wall time.
    pub truth_spp: u32,
    /// Seconds the truth took.
    pub truth_seconds: f64,
    /// Where the models ran ("GPU: ..." or "CPU reference renderer").
    pub device: String,
    /// Row size in pixels.
    pub size: (u32, u32),
}

impl Comparison {
    /// The headline: the mean over the columns of the `accurate` Kulla-Conty row's mean
    /// relative error, and the truth's mean noise floor over the same balls.
    pub fn headline(&self) -> Option<(f64, f64)> {
        let row = self
            .rows
            .iter()
            .find(|r| r.row.model == Model::KullaConty && r.row.preset == Preset::Accurate)?;
        let n = row.errors.len().max(1) as f64;
        Some((
            row.errors.iter().map(|e| e.mean_rel).sum::<f64>() / n,
            row.errors.iter().map(|e| e.floor_mean).sum::<f64>() / n,
        ))
    }
}

/// The model rows compared with the truth for `scene`: every model under the scene's
/// layering and coat forms; where its first ball (the rows' material) has a dielectric
/// part, Kulla-Conty under each other layering form; where it has a clear coat, Kulla-Conty
/// under each other coat form; where its lobe is anisotropic, Kulla-Conty with the
/// anisotropy ignored.
pub fn rows(scene: &Scene) -> Vec<Row> {
    let layering = scene.layering;
    let coat_form = scene.coat_form;
    let row = |name: &str, model, preset| Row {
        name: name.to_string(),
        model,
        preset,
        layering,
        coat_form,
        anisotropy_ignored: false,
    };
    let mut rows = vec![
        row("none", Model::None, Preset::Accurate),
        row(
            "kulla-conty (accurate)",
            Model::KullaConty,
            Preset::Accurate,
        ),
        row(
            "kulla-conty (games202)",
            Model::KullaConty,
            Preset::Games202,
        ),
        row("turquin", Model::Turquin, Preset::Accurate),
        row("fdez-aguera", Model::FdezAguera, Preset::Accurate),
    ];
    if scene
        .balls
        .first()
        .is_some_and(|b| b.material.has_dielectric())
    {
        for form in Layering::ALL.into_iter().filter(|&f| f != layering) {
            rows.push(Row {
                name: format!("kulla-conty ({form} layering)"),
                layering: form,
                ..row("", Model::KullaConty, Preset::Accurate)
            });
        }
    }
    if scene
        .balls
        .first()
        .is_some_and(|b| b.material.clearcoat.is_on())
    {
        for form in CoatForm::ALL.into_iter().filter(|&f| f != coat_form) {
            rows.push(Row {
                name: format!("kulla-conty ({form} coat)"),
                coat_form: form,
                ..row("", Model::KullaConty, Preset::Accurate)
            });
        }
    }
    if scene
        .balls
        .first()
        .is_some_and(|b| b.material.anisotropy > 0.0)
    {
        rows.push(Row {
            anisotropy_ignored: true,
            ..row(
                "kulla-conty (anisotropy ignored)",
                Model::KullaConty,
                Preset::Accurate,
            )
        });
    }
    rows
}

/// `scene` with its ball `ball` (counted from 0) moved first, so that the rows take its
/// material (`shadeballs-lab compare --ball`); a one-line error where there is no such
/// ball.
pub fn with_rows_material(mut scene: Scene, ball: usize) -> Result<Scene> {
    if ball >= scene.balls.len() {
        return Err(Error::Invalid {
            what: "--ball",
            message: format!(
                "no ball {} (counted from 1) in a scene of {}",
                ball + 1,
                scene.balls.len()
            ),
        });
    }
    let chosen = scene.balls.remove(ball);
    scene.balls.insert(0, chosen);
    Ok(scene)
}

/// `scene`'s balls with their lobes made isotropic where `row` ignores the anisotropy.
fn apply_anisotropy(row: &Row, scene: &mut Scene) {
    if row.anisotropy_ignored {
        for b in &mut scene.balls {
            b.material.anisotropy = 0.0;
        }
    }
}

/// The distinct roughness values of `scene`'s balls, ascending.
pub fn roughness_values(scene: &Scene) -> Vec<f64> {
    let mut r: Vec<f64> = scene.balls.iter().map(|b| b.roughness).collect();
    r.sort_by(f64::total_cmp);
    r.dedup();
    r
}

/// One row of balls: `roughness` left to right, `material` from `scene`'s first ball, every
/// ball `model` under `preset`, lit as `scene`, seen by a camera that frames the row.
pub fn row_scene(scene: &Scene, roughness: &[f64], model: Model, preset: Preset) -> Scene {
    let material = scene.balls[0].material;
    let n = roughness.len();
    let balls = roughness
        .iter()
        .enumerate()
        .map(|(k, &r)| Ball {
            center: DVec3::new((k as f64 - (n as f64 - 1.0) / 2.0) * SPACING, 0.0, 0.0),
            radius: RADIUS,
            roughness: r,
            material,
            model,
            label: None,
        })
        .collect();
    // One ball's spacing fills the image height: tan(vfov / 2) = (SPACING / 2) / DISTANCE.
    let vfov_deg = 2.0 * (0.5 * SPACING / DISTANCE).atan().to_degrees();
    Scene {
        balls,
        camera: Camera {
            position: DVec3::new(0.0, 0.0, DISTANCE),
            target: DVec3::ZERO,
            vfov_deg,
            min_aspect: None,
        },
        preset,
        // One ray through each pixel's centre, as the truth traces: pixel for pixel.
        antialias: false,
        ..scene.clone()
    }
}

/// Renders every row and the truth, measures, and writes the outputs into `options.out`.
/// `renderer`: the GPU, or `None` for the CPU reference renderer.
pub fn run(options: &CompareOptions, mut renderer: Option<&mut Renderer>) -> Result<Comparison> {
    let roughness = roughness_values(&options.scene);
    if roughness.len() > MAX_COLUMNS {
        return Err(Error::Invalid {
            what: "scene",
            message: format!(
                "{} roughness values: compare draws at most {MAX_COLUMNS} columns",
                roughness.len()
            ),
        });
    }
    let cell = options.cell;
    let (w, h) = (cell * roughness.len() as u32, cell);
    std::fs::create_dir_all(&options.out).map_err(|reason| Error::Write {
        path: options.out.clone(),
        reason,
    })?;

    // The truth first: its noise is the floor of every figure.
    let truth_scene = row_scene(&options.scene, &roughness, Model::Truth, Preset::Accurate);
    let truth_tables = TableSet::from(lut::bake(&BakeConfig {
        geometry: truth_scene.effective_geometry(),
        ..Default::default()
    }));
    let started = Instant::now();
    let truth = cpu::render_truth(
        &truth_scene,
        &Prepared::new(&truth_scene, &truth_tables),
        w,
        h,
        TruthSettings {
            spp: options.spp,
            seed: options.seed,
            ..TruthSettings::default()
        },
        |_| true,
    )?;
    let truth_seconds = started.elapsed().as_secs_f64();
    let index = cpu::ball_index_map(&truth_scene, w, h);
    let exposure = options.scene.exposure;
    let truth_ldr = cpu::to_rgba8(&truth.image.mean, exposure);

    let device = match renderer.as_deref() {
        Some(r) => format!("GPU: {}", r.gpu().describe()),
        None => "CPU reference renderer".to_string(),
    };
    let mut results = Vec::new();
    let mut pictures = Vec::new();
    let mut heatmaps = Vec::new();
    for row in rows(&options.scene) {
        let mut scene = Scene {
            layering: row.layering,
            coat_form: row.coat_form,
            ..row_scene(&options.scene, &roughness, row.model, row.preset)
        };
        apply_anisotropy(&row, &mut scene);
        truth.image.compares_with(scene.antialias)?;
        let radiance = radiance(&scene, renderer.as_deref_mut(), w, h)?;
        let ldr = cpu::to_rgba8(&radiance, exposure);
        let flip = flip_map(&truth_ldr, &ldr, w, h);
        let errors = ball_errors(roughness.len(), &index, &radiance, &truth.image, &flip);
        heatmaps.push(heatmap(&index, &radiance, &truth.image, HEATMAP_FULL_SCALE));
        pictures.push(ldr);
        let frame_ms = frame_ms(&options.scene, &row, renderer.as_deref_mut(), options)?;
        results.push(RowResult {
            row,
            errors,
            frame_ms,
        });
    }
    pictures.push(truth_ldr);
    // The truth's own noise as a heatmap on the same scale: the floor each row stands on.
    let noise: Vec<DVec3> = truth
        .image
        .mean
        .iter()
        .zip(&truth.image.std_error)
        .map(|(m, s)| *m + *s)
        .collect();
    heatmaps.push(heatmap(&index, &noise, &truth.image, HEATMAP_FULL_SCALE));

    let comparison = Comparison {
        roughness,
        rows: results,
        truth_spp: truth.image.spp,
        truth_seconds,
        device,
        size: (w, h),
    };
    write_atomic(
        &options.out.join("compare.csv"),
        csv(&comparison).as_bytes(),
    )?;
    let mut names: Vec<String> = comparison.rows.iter().map(|r| r.row.name.clone()).collect();
    names.push(format!("truth ({} spp)", truth.image.spp));
    // The scene's caption without its preset: the rows are under their own.
    let lighting = labels::caption(&options.scene);
    let lighting = lighting
        .split_once(" \u{b7} ")
        .map_or(lighting.as_str(), |(_, rest)| rest)
        .to_string();
    let caption = format!("models against the truth (random walk) \u{b7} {lighting}");
    let (cw, ch, picture) = chart(&pictures, &names, &comparison.roughness, (w, h), &caption)?;
    write_png(&options.out.join("compare.png"), cw, ch, picture)?;
    names.pop();
    names.push("truth's own noise".to_string());
    let caption = format!(
        "relative error against the truth, magma from 0 to {:.0} % \u{b7} {lighting}",
        100.0 * HEATMAP_FULL_SCALE
    );
    let (cw, ch, picture) = chart(&heatmaps, &names, &comparison.roughness, (w, h), &caption)?;
    write_png(&options.out.join("heatmaps.png"), cw, ch, picture)?;
    write_plot(&plot(&comparison), &options.out.join("time_vs_error.png"))?;
    write_atomic(
        &options.out.join("summary.md"),
        summary(&comparison).as_bytes(),
    )?;
    Ok(comparison)
}

/// Pixels left of the rows for their names.
const NAMES_PX: u32 = 190;
/// Pixels above the rows (the caption) and below them (the roughness).
const MARGIN_PX: u32 = 26;
/// The chart's background.
const CHART_GREY: [u8; 4] = [24, 24, 24, 255];

/// The row pictures (`size` each) stacked on a grey canvas with each row's name at its
/// left, each column's roughness under the last row and the caption above; RGBA8.
fn chart(
    pictures: &[Vec<u8>],
    names: &[String],
    roughness: &[f64],
    size: (u32, u32),
    caption: &str,
) -> Result<(u32, u32, Vec<u8>)> {
    let (w, h) = size;
    let width = NAMES_PX + w;
    let height = 2 * MARGIN_PX + h * pictures.len() as u32;
    let mut canvas: Vec<u8> = CHART_GREY.repeat((width * height) as usize);
    for (k, picture) in pictures.iter().enumerate() {
        let top = MARGIN_PX + k as u32 * h;
        for y in 0..h {
            let from = (y * w * 4) as usize;
            let to = (((top + y) * width + NAMES_PX) * 4) as usize;
            canvas[to..to + (w * 4) as usize]
                .copy_from_slice(&picture[from..from + (w * 4) as usize]);
        }
    }
    let size_px = 15.0;
    let label = |text: String, room: Rect, align| Label {
        text,
        room,
        align,
        size_px,
        wrapped: Vec::new(),
        ellipsis: false,
    };
    let cell = w as f32 / roughness.len().max(1) as f32;
    let bottom = (MARGIN_PX + h * pictures.len() as u32) as f32;
    let layout = Labels {
        balls: Vec::new(),
        columns: roughness
            .iter()
            .enumerate()
            .map(|(k, r)| {
                let x0 = NAMES_PX as f32 + k as f32 * cell;
                label(
                    labels::column_label(&[*r]),
                    Rect {
                        x0,
                        y0: bottom,
                        x1: x0 + cell,
                        y1: height as f32,
                    },
                    [Align::Centre, Align::Centre],
                )
            })
            .collect(),
        rows: names
            .iter()
            .enumerate()
            .map(|(k, name)| {
                let y0 = (MARGIN_PX + k as u32 * h) as f32;
                label(
                    name.clone(),
                    Rect {
                        x0: 0.0,
                        y0,
                        x1: NAMES_PX as f32 - 4.0,
                        y1: y0 + h as f32,
                    },
                    [Align::End, Align::Centre],
                )
            })
            .collect(),
        caption: vec![label(
            caption.to_string(),
            Rect {
                x0: 0.0,
                y0: 0.0,
                x1: width as f32,
                y1: MARGIN_PX as f32,
            },
            [Align::Start, Align::Centre],
        )],
    };
    labels::draw_labels(&mut canvas, width, height, &layout)?;
    Ok((width, height, canvas))
}

/// Linear radiance of `scene` on the GPU (its float target) or the CPU reference renderer,
/// by the library's render of any backend (`shadeballs::render`, as `shadeballs render`).
fn radiance(scene: &Scene, renderer: Option<&mut Renderer>, w: u32, h: u32) -> Result<Vec<DVec3>> {
    let request = Request {
        backend: if renderer.is_some() {
            Backend::Auto
        } else {
            Backend::Cpu
        },
        size: (w, h),
        output: Output::Radiance,
        spp: None,
        seed: 0,
        stderr: None,
        ibl_frames: None,
        verbose: false,
    };
    match render::render(renderer, scene, &request, &mut Quiet)?.pixels {
        Pixels::Radiance(radiance) => Ok(radiance),
        _ => Err(Error::Invalid {
            what: "render",
            message: "returned no radiance".to_string(),
        }),
    }
}

/// A render's progress, told to no one (the comparison prints its own summary).
struct Quiet;

impl render::Progress for Quiet {
    fn phase(&mut self, _: &str) {}
    fn line(&mut self, _: &str) {}
    fn stoppable(&mut self, _: bool) {}
    fn keep_going(&mut self) -> bool {
        true
    }
    fn truth_pass(&mut self, _: &TruthProgress, _: u32, _: Option<f64>) -> bool {
        true
    }
    fn truth_done(&mut self, _: &TruthProgress, _: Option<f64>, _: u64) {}
}

/// Frames timed per model (the median is reported).
const TIMED_FRAMES: usize = 7;

/// The median time of a frame of the user's scene with every ball `row`'s model, at the
/// timing size, on the renderer the rows use (the first, untimed frame builds its
/// pipelines).
fn frame_ms(
    scene: &Scene,
    row: &Row,
    renderer: Option<&mut Renderer>,
    options: &CompareOptions,
) -> Result<f64> {
    let mut scene = scene.clone();
    scene.preset = row.preset;
    scene.layering = row.layering;
    scene.coat_form = row.coat_form;
    for b in &mut scene.balls {
        b.model = row.model;
    }
    apply_anisotropy(row, &mut scene);
    let (w, h) = options.timing_size;
    let mut times = Vec::new();
    match renderer {
        Some(r) => {
            r.render_ldr(&scene, w, h)?;
            for _ in 0..TIMED_FRAMES {
                let t = Instant::now();
                r.render_ldr(&scene, w, h)?;
                times.push(t.elapsed().as_secs_f64() * 1e3);
            }
        }
        None => {
            let tables = TableSet::from(lut::bake(&BakeConfig {
                geometry: scene.effective_geometry(),
                ..Default::default()
            }));
            let prepared = Prepared::new(&scene, &tables);
            for _ in 0..3 {
                let t = Instant::now();
                std::hint::black_box(cpu::render_radiance(&scene, &prepared, w, h));
                times.push(t.elapsed().as_secs_f64() * 1e3);
            }
        }
    }
    Ok(shadeballs::stats::median(&mut times))
}

/// `compare.csv`: a line per model and roughness, every figure a number; the verdicts
/// (an error under three times the truth's noise floor is "within noise", else "above
/// noise") and the floors are columns of their own (issue 28: no words in numeric columns).
pub fn csv(c: &Comparison) -> String {
    let mut s = String::from(
        "model,roughness,mean_rel_err,p99_rel_err,flip_mean,frame_ms,\
         truth_rel_stderr_mean,truth_rel_stderr_p99,mean_verdict,p99_verdict\n",
    );
    let verdict = |value: f64, floor: f64| {
        if BallError::within_noise(value, floor) {
            "within noise"
        } else {
            "above noise"
        }
    };
    for r in &c.rows {
        for (e, rough) in r.errors.iter().zip(&c.roughness) {
            let _ = writeln!(
                s,
                "{},{rough},{:.5},{:.5},{:.5},{:.3},{:.5},{:.5},{},{}",
                r.row.name,
                e.mean_rel,
                e.p99_rel,
                e.flip_mean,
                r.frame_ms,
                e.floor_mean,
                e.floor_p99,
                verdict(e.mean_rel, e.floor_mean),
                verdict(e.p99_rel, e.floor_p99),
            );
        }
    }
    s
}

/// Frame time against the mean over the columns of each model's mean relative error.
fn plot(c: &Comparison) -> Plot {
    let series = c
        .rows
        .iter()
        .map(|r| Series {
            label: r.row.name.clone(),
            points: vec![(
                r.frame_ms,
                r.errors.iter().map(|e| e.mean_rel).sum::<f64>() / r.errors.len().max(1) as f64,
            )],
            colour: None,
            style: Style::Points,
        })
        .collect();
    let floor = c.rows.first().map_or(0.0, |r| {
        r.errors.iter().map(|e| e.floor_mean).sum::<f64>() / r.errors.len().max(1) as f64
    });
    Plot {
        title: format!(
            "Image error against the truth ({} spp) and frame time ({})",
            c.truth_spp, c.device
        ),
        x_label: "frame time (ms, median)".into(),
        y_label: "mean relative error over ball pixels".into(),
        series,
        goals: vec![(
            "3 x truth noise".into(),
            None,
            Some(image_error::NOISE_FACTOR * floor),
        )],
    }
}

/// A markdown table of the figures, by model and roughness.
pub fn summary(c: &Comparison) -> String {
    let mut s = format!(
        "# Models against the truth, pictured\n\nRows of {} x {} pixels, truth {} spp ({:.1} s \
         on the CPU); models on the {}. Relative errors of luminance over each ball's pixels \
         (mean / p99), FLIP mean; \"within noise\" is under {} x the truth's own relative \
         standard error.\n\n| model | frame ms |",
        c.size.0,
        c.size.1,
        c.truth_spp,
        c.truth_seconds,
        c.device,
        image_error::NOISE_FACTOR
    );
    for r in &c.roughness {
        let _ = write!(s, " r = {r} |");
    }
    s.push_str("\n|---|---|");
    for _ in &c.roughness {
        s.push_str("---|");
    }
    s.push('\n');
    for r in &c.rows {
        let _ = write!(s, "| {} | {:.2} |", r.row.name, r.frame_ms);
        for e in &r.errors {
            let _ = write!(
                s,
                " {} / {}, FLIP {:.3} |",
                BallError::figure(e.mean_rel, e.floor_mean),
                BallError::figure(e.p99_rel, e.floor_p99),
                e.flip_mean
            );
        }
        s.push('\n');
    }
    if let Some((err, floor)) = c.headline() {
        let _ = writeln!(
            s,
            "\nHeadline: the accurate preset's mean relative image error against the truth is \
             {:.2} % (truth noise floor {:.2} %).",
            100.0 * err,
            100.0 * floor
        );
    }
    s
}
