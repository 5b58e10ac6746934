//! Cost against error for light (issue 26): each way the map lights the balls, its frame
//! time at 1280x720 against its whole image's error, the curve of `light.png`.
//!
//! Methods: the split sum read along the dominant direction (the renderer's), the split
//! sum read along the plain mirror direction (`DrawOptions::dominant_direction` off), the
//! lobe mode at N = 1, 2, 4, ..., 64 samples a pixel in one frame, and the progressive lobe
//! mode: frames `0..k` of [`DEFAULT_IBL_SAMPLES`] samples each averaged
//! ([`Renderer::render_lobe_hdr`]), k = 1, 2, 4, ...
//!
//! Error: each method's GPU image (linear, one ray through each pixel's centre) against
//! the GPU Monte Carlo of the same model ([`Renderer::render_montecarlo`], also centre
//! rays: like with like, checked by [`errors_by_roughness`]), per ball the mean relative
//! error of luminance over its pixels (the ibl bench's measure and function, given one row
//! of balls at a time), with the Monte Carlo's own mean relative standard error beside it. Balls: the ibl bench's metals ([`ibl_scene`], copper over white) and
//! plastics (the same layout, red IOR 1.5 over blue IOR 1.33 of `assets/scenes/plastic.toml`),
//! every ball with the Kulla-Conty term, under `studio` and `sky`, and in the full run
//! under issue 37's sun map ([`sun_environment`]).
//!
//! Cost: the median wall time of a 1280x720 frame (320x180 in the quick run), each
//! submitted and waited for, the methods' frames in turn within each round (the first
//! method of a round rotating), and the median over rounds of the ratio to the split sum's
//! frame of the same round. The progressive image after k frames costs k lobe frames of its
//! N (the frame index changes a uniform, not the work).

use std::sync::Arc;

use glam::{DVec2, DVec3};

use super::ibl::{errors_by_roughness, ibl_scene, linear};
use super::table::{sci, Table};
use super::{device, median, Goal, Sweep};
use crate::plot::{Plot, Series, Style};
use shadeballs::environment::{
    uv_to_direction, Builtin, EnvMap, Environment, IblMethod, IblTerm, Source, DEFAULT_IBL_SAMPLES,
};
use shadeballs::error::{Error, Result};
use shadeballs::gpu::{DrawOptions, Renderer, Target};
use shadeballs::lut::BakeConfig;
use shadeballs::scene::{srgb_decode, Material, Scene};
use shadeballs::stats::{MonteCarloImage, MAX_SPP};

/// Lobe samples a pixel of the one-frame lobe rows.
pub const LOBE_SAMPLES: [u32; 7] = [1, 2, 4, 8, 16, 32, 64];
/// The frame size the cost is measured at (the quick run's is smaller).
pub const FRAME_SIZE: (u32, u32) = (1280, 720);
/// The Monte Carlo reference's seed.
const MC_SEED: u64 = 7;
/// The Monte Carlo's noise counts as well under an error when at most this fraction of it
/// (a fifth: the mean absolute error it adds to a noiseless image's is about 0.8 times
/// its standard error, so a fifth moves a measured error by at most about a sixth).
pub const NOISE_FRACTION: f64 = 0.2;

/// Issue 37's sun: its radiance (every channel) ...
pub const SUN_RADIANCE: f32 = 1e4;
/// ... over this share of the sphere (a cap 3.6 degrees in radius).
pub const SUN_SHARE: f64 = 1e-3;
/// The sun map's width (the built-ins' default; the height is half).
const SUN_MAP_WIDTH: u32 = 1024;

/// Issue 37's sun map, generated: a dim bluish sky (0.2 at the nadir to 1 at the zenith, in
/// blue) and a sun of [`SUN_RADIANCE`] over the texels whose centres lie in a cap of
/// [`SUN_SHARE`] of the sphere, up and to the left behind the bench's camera (that of
/// `Scene::reference`), so every ball's lobe catches it on its visible face. Most of the
/// map's light comes from about 330 of its 524,288 texels, as in a clear day's HDRI. Its
/// source reads `sun` in messages (it is made in memory, read from no file).
pub fn sun_environment() -> Environment {
    let (w, h) = (SUN_MAP_WIDTH, SUN_MAP_WIDTH / 2);
    let sun = DVec3::new(-0.45, 0.55, 0.7).normalize();
    // A cap of solid angle 2 pi (1 - cos) = 4 pi SUN_SHARE.
    let cos_cap = 1.0 - 2.0 * SUN_SHARE;
    let texels = (0..w * h)
        .map(|k| {
            let uv = DVec2::new(
                (f64::from(k % w) + 0.5) / f64::from(w),
                (f64::from(k / w) + 0.5) / f64::from(h),
            );
            let d = uv_to_direction(uv);
            if d.dot(sun) >= cos_cap {
                return [SUN_RADIANCE; 3];
            }
            let s = (0.6 + 0.4 * d.y) as f32;
            [0.8 * s, 0.9 * s, s]
        })
        .collect();
    Environment {
        source: Source::File("sun".into()),
        map: Arc::new(EnvMap::new(w, h, texels).expect("a valid generated map")),
        rotation_deg: 0.0,
        intensity: 1.0,
    }
}

/// How a method lights the balls.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    /// One prefiltered read along the dominant direction.
    SplitSum,
    /// One prefiltered read along the plain mirror direction.
    SplitSumMirror,
    /// `samples` of the lobe in one frame.
    Lobe,
    /// `frames` frames of `samples` lobe samples, averaged.
    Progressive,
}

impl Family {
    /// Whether the family is one of the split sum's (one read, no samples).
    pub fn is_split_sum(self) -> bool {
        matches!(self, Family::SplitSum | Family::SplitSumMirror)
    }

    pub fn name(self) -> &'static str {
        match self {
            Family::SplitSum => "split-sum",
            Family::SplitSumMirror => "split-sum-mirror",
            Family::Lobe => "lobe",
            Family::Progressive => "lobe-progressive",
        }
    }
}

/// The balls' material.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightMaterial {
    /// The ibl bench's copper row over a white metal row.
    Metal,
    /// Red plastic (IOR 1.5) over blue plastic (IOR 1.33).
    Plastic,
}

impl LightMaterial {
    pub const ALL: [LightMaterial; 2] = [LightMaterial::Metal, LightMaterial::Plastic];

    pub fn name(self) -> &'static str {
        match self {
            LightMaterial::Metal => "metal",
            LightMaterial::Plastic => "plastic",
        }
    }

    /// The names of the top and the bottom row's balls.
    pub fn rows(self) -> [&'static str; 2] {
        match self {
            LightMaterial::Metal => ["copper", "white"],
            LightMaterial::Plastic => ["red", "blue"],
        }
    }
}

/// `scene` with the balls of one row alone, top row first: the pixels of the other row then
/// hit no ball and count in no error (the rows do not overlap on screen).
pub fn row_scenes(scene: &Scene) -> [Scene; 2] {
    let top = top_row(scene);
    let row = |on_top: bool| {
        let mut s = scene.clone();
        s.balls.retain(|b| (b.center.y == top) == on_top);
        s
    };
    [row(true), row(false)]
}

/// The height of the top row's centres.
fn top_row(scene: &Scene) -> f64 {
    scene
        .balls
        .iter()
        .map(|b| b.center.y)
        .fold(f64::NEG_INFINITY, f64::max)
}

/// One ball's error against the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BallError {
    /// The ball's row (its material's [`LightMaterial::rows`]).
    pub row: &'static str,
    pub roughness: f64,
    /// Mean and 99th percentile of the relative error of luminance over its pixels.
    pub mean: f64,
    pub p99: f64,
    /// The reference's mean relative standard error over the same pixels.
    pub noise: f64,
}

/// One method: its family, lobe samples a frame (0 for the split sum) and frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Method {
    pub family: Family,
    pub samples: u32,
    pub frames: u32,
}

impl Method {
    /// `base` lit by this method.
    pub fn scene(&self, base: &Scene) -> Scene {
        let mut scene = base.clone();
        if self.family.is_split_sum() {
            scene.ibl_method = IblMethod::SplitSum;
        } else {
            scene.ibl_method = IblMethod::Lobe;
            scene.ibl_samples = self.samples;
        }
        scene
    }

    /// The renderer's options for this method: the split sum's read along the mirror
    /// direction for [`Family::SplitSumMirror`].
    pub fn options(&self) -> DrawOptions {
        DrawOptions {
            dominant_direction: self.family != Family::SplitSumMirror,
            ..DrawOptions::default()
        }
    }
}

/// The methods measured: the split sum along the dominant and along the mirror
/// direction, the lobe at each of `lobe_samples` (the full run: [`LOBE_SAMPLES`]), the
/// progressive lobe after each of `frames`.
pub fn methods(lobe_samples: &[u32], frames: &[u32]) -> Vec<Method> {
    let split = |family| Method {
        family,
        samples: 0,
        frames: 1,
    };
    let mut out = vec![split(Family::SplitSum), split(Family::SplitSumMirror)];
    out.extend(lobe_samples.iter().map(|&samples| Method {
        family: Family::Lobe,
        samples,
        frames: 1,
    }));
    out.extend(frames.iter().map(|&frames| Method {
        family: Family::Progressive,
        samples: DEFAULT_IBL_SAMPLES,
        frames,
    }));
    out
}

/// The measured balls under `environment`: the ibl bench's metals, or the same layout in
/// plastics (top row red IOR 1.5, bottom row blue IOR 1.33, `assets/scenes/plastic.toml`'s
/// colours as its `base_color` keys decode them), every ball with the Kulla-Conty term,
/// one ray through each pixel's centre.
pub fn light_scene(environment: Environment, material: LightMaterial) -> Scene {
    let mut scene = ibl_scene(environment, IblTerm::KullaConty);
    if material == LightMaterial::Plastic {
        let red = Material::dielectric(srgb_decode([0.85, 0.15, 0.1]), 1.5);
        let blue = Material::dielectric(srgb_decode([0.2, 0.45, 0.85]), 1.33);
        let top = top_row(&scene);
        for b in scene.balls.iter_mut() {
            b.material = if b.center.y == top { red } else { blue };
        }
    }
    scene
}

/// `method`'s linear image of `base` at `size` (the progressive one through
/// [`Renderer::render_lobe_hdr`]).
pub fn method_image(
    renderer: &mut Renderer,
    base: &Scene,
    method: Method,
    (w, h): (u32, u32),
) -> Result<Vec<DVec3>> {
    let scene = method.scene(base);
    renderer.set_draw_options(method.options());
    let image = if method.family == Family::Progressive {
        renderer.render_lobe_hdr(&scene, w, h, method.frames)
    } else {
        renderer.set_lobe_frame(0);
        renderer.render_hdr(&scene, w, h)
    };
    renderer.set_draw_options(DrawOptions::default());
    Ok(linear(&image?.rgba))
}

/// The Monte Carlo of `scene`'s model on the GPU: `spp` estimates a pixel at `size`. Above
/// [`MAX_SPP`] (one render's limit), `spp` is split into equal renders of seeds
/// [`MC_SEED`], `MC_SEED + 1`, ..., pooled ([`pool`]); it must then divide evenly.
pub fn reference(
    renderer: &mut Renderer,
    scene: &Scene,
    size: (u32, u32),
    spp: u32,
) -> Result<MonteCarloImage> {
    let runs = spp.div_ceil(MAX_SPP).max(1);
    if !spp.is_multiple_of(runs) {
        return Err(Error::Invalid {
            what: "reference samples per pixel",
            message: format!("{spp}: above {MAX_SPP}, a multiple of {runs} renders"),
        });
    }
    let images = (0..runs)
        .map(|k| renderer.render_montecarlo(scene, size, spp / runs, MC_SEED + u64::from(k)))
        .collect::<Result<Vec<_>>>()?;
    pool(&images)
}

/// Independent Monte Carlo images of one scene (same size, coverage and pixel filter, the
/// same estimates a pixel) as one: per pixel the mean of their means and the standard error
/// of that mean, `sqrt(sum of se^2) / n`.
pub fn pool(images: &[MonteCarloImage]) -> Result<MonteCarloImage> {
    let [first, rest @ ..] = images else {
        return Err(Error::Invalid {
            what: "Monte Carlo images to pool",
            message: "none".into(),
        });
    };
    if rest.iter().any(|i| {
        (i.width, i.height, i.spp, i.antialias)
            != (first.width, first.height, first.spp, first.antialias)
            || i.covered != first.covered
    }) {
        return Err(Error::Invalid {
            what: "Monte Carlo images to pool",
            message: "their sizes, coverage, filters or estimates a pixel differ".into(),
        });
    }
    let n = images.len() as f64;
    let pixels = first.mean.len();
    let mean = (0..pixels)
        .map(|p| images.iter().map(|i| i.mean[p]).sum::<DVec3>() / n)
        .collect();
    let std_error = (0..pixels)
        .map(|p| {
            let sum: DVec3 = images.iter().map(|i| i.std_error[p] * i.std_error[p]).sum();
            DVec3::new(sum.x.sqrt(), sum.y.sqrt(), sum.z.sqrt()) / n
        })
        .collect();
    Ok(MonteCarloImage {
        spp: first.spp * images.len() as u32,
        mean,
        std_error,
        ..first.clone()
    })
}

/// Frames of each of `scenes` (drawn with its options) at `(w, h)`, in turn, `repeats` rounds after a warm-up
/// round (pipelines, the driver's compile, the map's preparation), round `r` starting at
/// scene `r mod n`: per scene its frame times (ms), and per scene the median over rounds of
/// its time over scene 0's of the same round.
pub fn frame_times(
    renderer: &mut Renderer,
    scenes: &[(Scene, DrawOptions)],
    (w, h): (u32, u32),
    repeats: usize,
) -> Result<(Vec<Vec<f64>>, Vec<f64>)> {
    let (_texture, view) = device::frame_target(renderer.gpu(), w, h);
    let target = Target {
        view: &view,
        format: device::FRAME_FORMAT,
        width: w,
        height: h,
    };
    renderer.set_lobe_frame(0);
    let n = scenes.len();
    let mut times = vec![Vec::new(); n];
    for round in 0..=repeats.max(1) {
        for j in 0..n {
            let k = (round + j) % n;
            renderer.set_draw_options(scenes[k].1);
            let start = std::time::Instant::now();
            renderer.render(&scenes[k].0, target)?;
            device::wait(renderer.gpu())?;
            if round > 0 {
                times[k].push(start.elapsed().as_secs_f64() * 1e3);
            }
        }
    }
    renderer.set_draw_options(DrawOptions::default());
    let ratios = times
        .iter()
        .map(|t| {
            let mut r: Vec<f64> = t.iter().zip(&times[0]).map(|(a, b)| a / b).collect();
            median(&mut r)
        })
        .collect();
    Ok((times, ratios))
}

/// The sizes, samples and repeats of a run.
#[derive(Clone, Debug)]
pub struct Settings {
    /// The error images' size.
    pub size: (u32, u32),
    /// The Monte Carlo reference's estimates a pixel.
    pub spp: u32,
    /// The timed frames' size.
    pub frame: (u32, u32),
    /// Rounds of timed frames.
    pub repeats: usize,
    /// The lobe rows' sample counts.
    pub lobe_samples: Vec<u32>,
    /// The progressive rows' frame counts.
    pub frames: Vec<u32>,
    /// Whether the sun map is measured beside the studio and the sky.
    pub sun: bool,
}

impl Settings {
    pub fn new(quick: bool) -> Self {
        if quick {
            // Seconds, inside `bench --quick`'s minute: a sixteenth of the full run's
            // frame (the lobe's multiple importance sampling at N = 64 costs seconds a
            // frame at 640x360), one timed round, and the lobe at three sample counts
            // (each count is a pipeline of its own to compile, for the timed frames and
            // the error images: 0.3 s each, the first time, on lavapipe).
            Settings {
                size: (64, 36),
                spp: 1024,
                frame: (320, 180),
                repeats: 1,
                lobe_samples: vec![1, DEFAULT_IBL_SAMPLES, 64],
                frames: vec![1, 4],
                // The sun map is the full run's: the quick run checks the sweep's shape
                // and convergence, which the two built-ins show.
                sun: false,
            }
        } else {
            // The reference's mean relative standard error goes as 1 / sqrt(spp): under
            // the studio 0.62 % at 16384 estimates and 0.45 % at 32768 in runs of this
            // bench, above a fifth (NOISE_FRACTION) of the progressive lobe's error after
            // 16 frames (about 1 %). Four renders of MAX_SPP (pooled: `reference`) bring
            // it near 0.18 %, at about 90 s a reference on lavapipe.
            Settings {
                size: (160, 90),
                spp: 4 * MAX_SPP,
                frame: FRAME_SIZE,
                repeats: 11,
                lobe_samples: LOBE_SAMPLES.to_vec(),
                frames: vec![1, 2, 4, 8, 16, 32, 64],
                sun: true,
            }
        }
    }
}

/// One measured method of one configuration.
#[derive(Clone, Debug)]
pub struct Measured {
    pub method: Method,
    /// Per ball, top row first.
    pub errors: Vec<BallError>,
    /// Median frame time (ms) of one frame of the method's scene.
    pub frame_ms: f64,
    /// The image's cost over the split sum's frame (k frames for the progressive rows).
    pub ratio: f64,
}

impl Measured {
    /// The worst mean relative error over the balls of roughness `>= min_roughness`.
    pub fn worst(&self, min_roughness: f64) -> f64 {
        self.errors
            .iter()
            .filter(|e| e.roughness >= min_roughness)
            .map(|e| e.mean)
            .fold(0.0, f64::max)
    }

    /// The reference's noise over the worst ball's error (roughness `>= min_roughness`):
    /// above [`NOISE_FRACTION`], the row's error is partly the reference's.
    pub fn noise_over_error(&self, min_roughness: f64) -> f64 {
        self.errors
            .iter()
            .filter(|e| e.roughness >= min_roughness)
            .max_by(|a, b| a.mean.total_cmp(&b.mean))
            .map_or(f64::NAN, |e| e.noise / e.mean)
    }

    /// The reference's mean relative standard error over every ball.
    pub fn noise(&self) -> f64 {
        let n = self.errors.len().max(1) as f64;
        self.errors.iter().map(|e| e.noise).sum::<f64>() / n
    }

    /// The image's cost in ms (k frames for the progressive rows).
    pub fn image_ms(&self) -> f64 {
        self.frame_ms * f64::from(self.method.frames)
    }
}

/// Every method of `settings` on `base`: errors against one Monte Carlo reference and the
/// frame times of the same run.
pub fn measure(
    renderer: &mut Renderer,
    base: &Scene,
    material: LightMaterial,
    settings: &Settings,
) -> Result<(Vec<Measured>, MonteCarloImage)> {
    let reference = reference(renderer, base, settings.size, settings.spp)?;
    let methods = methods(&settings.lobe_samples, &settings.frames);
    // One timed scene per distinct frame (the progressive rows time the lobe's frame).
    let timed: Vec<Method> = methods
        .iter()
        .filter(|m| m.family != Family::Progressive)
        .copied()
        .collect();
    let scenes: Vec<(Scene, DrawOptions)> =
        timed.iter().map(|m| (m.scene(base), m.options())).collect();
    let (mut times, ratios) = frame_times(renderer, &scenes, settings.frame, settings.repeats)?;
    let mut out = Vec::new();
    for method in methods {
        let (w, h) = settings.size;
        let image = method_image(renderer, base, method, (w, h))?;
        let errors = ball_errors(&method.scene(base), material, (w, h), &image, &reference)?;
        let per_frame = Method {
            family: Family::Lobe,
            frames: 1,
            ..method
        };
        let k = timed
            .iter()
            .position(|m| *m == method || (method.family == Family::Progressive && *m == per_frame))
            .expect("every method's frame is timed");
        out.push(Measured {
            method,
            errors,
            frame_ms: median(&mut times[k]),
            ratio: ratios[k] * f64::from(method.frames),
        });
    }
    Ok((out, reference))
}

/// Each ball's error of `image` (of `scene`, at `size`) against `reference`, one row of
/// balls at a time through [`errors_by_roughness`].
pub fn ball_errors(
    scene: &Scene,
    material: LightMaterial,
    (w, h): (u32, u32),
    image: &[DVec3],
    reference: &MonteCarloImage,
) -> Result<Vec<BallError>> {
    let all = (f64::NEG_INFINITY, f64::INFINITY);
    let mut out = Vec::new();
    for (row, row_scene) in material.rows().into_iter().zip(row_scenes(scene)) {
        for (roughness, mean, p99, noise) in
            errors_by_roughness(&row_scene, w, h, image, reference, all)?
        {
            out.push(BallError {
                row,
                roughness,
                mean,
                p99,
                noise,
            });
        }
    }
    Ok(out)
}

fn method_cells(m: &Method) -> [String; 3] {
    let samples = if m.family.is_split_sum() {
        "-".to_string()
    } else {
        m.samples.to_string()
    };
    [m.family.name().to_string(), samples, m.frames.to_string()]
}

/// The two tables of the sweep: per roughness (`light.csv`) and the curve (`light_cost.csv`).
fn tables(settings: &Settings) -> (Table, Table) {
    let (w, h) = settings.size;
    let (fw, fh) = settings.frame;
    let errors = Table::new(
        "light",
        &format!(
            "Light: each method's whole image against the GPU Monte Carlo of the same model ({w}x{h}, {} spp, centre rays on both sides; relative error of luminance over each ball's pixels)",
            settings.spp
        ),
        &[
            "environment",
            "material",
            "method",
            "samples",
            "frames",
            "ball",
            "roughness",
            "mean_rel_err",
            "p99_rel_err",
            "mc_rel_std_err",
        ],
    );
    let cost = Table::new(
        "light_cost",
        &format!(
            "Light: cost against error ({fw}x{fh} frames in turn, median; ratio: the image's cost over the split sum's frame, median over rounds; errors: the worst ball's mean relative error, of roughness >= 0.3 and of all; the reference's mean relative standard error over every ball; noise_over_err: the reference's noise over the worst ball's error at roughness >= 0.3, above 0.2 the row's error is partly the reference's)"
        ),
        &[
            "environment",
            "material",
            "method",
            "samples",
            "frames",
            "frame_ms",
            "image_ms",
            "ratio",
            "worst_err_r03",
            "worst_err_all",
            "mc_rel_std_err",
            "noise_over_err",
        ],
    );
    (errors, cost)
}

/// Adds `measured` of one configuration to the tables.
fn push_rows(errors: &mut Table, cost: &mut Table, config: [&str; 2], measured: &[Measured]) {
    for m in measured {
        let [family, samples, frames] = method_cells(&m.method);
        for e in &m.errors {
            errors.push(vec![
                config[0].into(),
                config[1].into(),
                family.clone(),
                samples.clone(),
                frames.clone(),
                e.row.into(),
                format!("{}", e.roughness),
                sci(e.mean),
                sci(e.p99),
                sci(e.noise),
            ]);
        }
        cost.push(vec![
            config[0].into(),
            config[1].into(),
            family,
            samples,
            frames,
            format!("{:.2}", m.frame_ms),
            format!("{:.2}", m.image_ms()),
            format!("{:.3}", m.ratio),
            sci(m.worst(0.3)),
            sci(m.worst(0.0)),
            sci(m.noise()),
            format!("{:.3}", m.noise_over_error(0.3)),
        ]);
    }
}

/// The curve's series of one configuration: one per family, x the cost ratio, y the worst
/// error at roughness >= 0.3; metals marked, plastics dashed, a colour per family.
fn curve_series(material: LightMaterial, measured: &[Measured]) -> Vec<Series> {
    let split_colour = match material {
        LightMaterial::Metal => [0, 0, 0],
        LightMaterial::Plastic => [150, 150, 150],
    };
    let families = [
        (Family::SplitSum, split_colour),
        (Family::SplitSumMirror, [0, 158, 115]),
        (Family::Lobe, [0, 114, 178]),
        (Family::Progressive, [213, 94, 0]),
    ];
    families
        .iter()
        .map(|&(family, colour)| Series {
            label: format!("{}, {}", material.name(), family.name()),
            points: measured
                .iter()
                .filter(|m| m.method.family == family)
                .map(|m| (m.ratio, m.worst(0.3).max(1e-6)))
                .collect(),
            colour: Some(colour),
            style: match (family, material) {
                (Family::SplitSum | Family::SplitSumMirror, _) => Style::Points,
                (_, LightMaterial::Metal) => Style::Marked,
                (_, LightMaterial::Plastic) => Style::Dashed,
            },
        })
        .collect()
}

/// The cheapest lobe or progressive row whose worst error at roughness >= 0.3 is within the
/// split sum's, as a sentence.
fn break_even(config: &str, measured: &[Measured]) -> String {
    let Some(split_row) = measured
        .iter()
        .find(|m| m.method.family == Family::SplitSum)
    else {
        return format!("{config}: no split-sum row");
    };
    let split = split_row.worst(0.3);
    // The same errors to the last digit: the same image.
    let sampled = |m: &&Measured| !m.method.family.is_split_sum();
    if measured
        .iter()
        .filter(sampled)
        .all(|m| m.errors == split_row.errors)
    {
        return format!(
            "{config}: split sum {:.2} %; every lobe row's image is the split sum's (the same errors): the lobe mode does not shade this material on this commit",
            100.0 * split
        );
    }
    let best = measured
        .iter()
        .filter(|m| sampled(m) && m.worst(0.3) <= split)
        .min_by(|a, b| a.ratio.total_cmp(&b.ratio));
    match best {
        Some(m) => format!(
            "{config}: split sum {:.2} %; the cheapest lobe row within it: {} N = {} x {} frames, {:.2} % at {:.2}x",
            100.0 * split,
            m.method.family.name(),
            m.method.samples,
            m.method.frames,
            100.0 * m.worst(0.3),
            m.ratio
        ),
        None => format!(
            "{config}: split sum {:.2} %; no lobe row measured within it",
            100.0 * split
        ),
    }
}

/// The light sweep on `renderer`.
pub fn light_sweep(renderer: &mut Renderer, quick: bool) -> Result<Sweep> {
    renderer.set_draw_options(shadeballs::gpu::DrawOptions::default());
    renderer.set_bake_config(BakeConfig::default());
    renderer.set_multiple_scattering_term(true);
    let settings = Settings::new(quick);
    let (mut errors, mut cost) = tables(&settings);
    let mut plots = Vec::new();
    let mut notes = Vec::new();
    let mut checks = Checks {
        frame: settings.frame,
        ..Checks::default()
    };
    let mut maps = vec![
        Environment::builtin(Builtin::Studio),
        Environment::builtin(Builtin::Sky),
    ];
    if settings.sun {
        maps.push(sun_environment());
    }
    for environment in maps {
        let map = environment.source.to_string();
        let mut series = Vec::new();
        let mut noise = 0.0f64;
        for material in LightMaterial::ALL {
            let base = light_scene(environment.clone(), material);
            let (measured, _) = measure(renderer, &base, material, &settings)?;
            let config = [map.as_str(), material.name()];
            push_rows(&mut errors, &mut cost, config, &measured);
            notes.push(break_even(
                &format!("{map}, {}", material.name()),
                &measured,
            ));
            checks.add(
                &format!("{map} {}", material.name()),
                &map,
                material,
                &measured,
            );
            series.extend(curve_series(material, &measured));
            noise = measured.iter().map(Measured::noise).fold(noise, f64::max);
        }
        plots.push((
            format!("light_{map}"),
            Plot {
                title: format!("Light under {map}: cost against error (GPU Monte Carlo reference)"),
                x_label: format!(
                    "cost over the split sum's frame ({}x{})",
                    settings.frame.0, settings.frame.1
                ),
                y_label: "worst ball's mean relative error, roughness >= 0.3".into(),
                series,
                // Errors near this line are partly the reference's (noise_over_err).
                goals: vec![(
                    format!("reference's noise ({:.2} %)", 100.0 * noise),
                    None,
                    Some(noise),
                )],
            },
        ));
    }
    cost.note = notes.join("\n\n");
    Ok(Sweep {
        tables: vec![errors, cost],
        plots,
        goals: checks.goals(),
    })
}

/// Issue 37's one-frame goal: the lobe within this error ...
pub const ONE_FRAME_ERROR: f64 = 0.03;
/// ... at at most this cost over the split sum's frame.
pub const ONE_FRAME_COST: f64 = 4.0;
/// Issue 37's progressive goal: within this error ...
pub const PROGRESSIVE_ERROR: f64 = 0.01;
/// ... in at most this many milliseconds of frames (at 1280x720).
pub const PROGRESSIVE_MS: f64 = 2000.0;
/// The maps issue 37's goals name.
const GOAL_MAPS: [&str; 2] = ["studio", "sky"];

/// The sweep's checks, over every configuration.
#[derive(Default)]
struct Checks {
    /// The timed frames' size.
    frame: (u32, u32),
    /// Under the goals' maps, per configuration: the one-frame lobe row of the lowest error
    /// at roughness >= 0.3 within [`ONE_FRAME_COST`], and the progressive row of the lowest
    /// within [`PROGRESSIVE_MS`].
    one_frame: Vec<(String, Option<Measured>)>,
    progressive: Vec<(String, Option<Measured>)>,
    /// Rows measured, and those whose error is partly the reference's noise.
    rows: usize,
    noise_bound: Vec<String>,
    /// Metals: (lobe N = 1, lobe N = 64) worst errors at roughness >= 0.3.
    lobe_ends: Vec<(f64, f64)>,
    /// Metals: (first, last) progressive worst errors.
    progressive_ends: Vec<(f64, f64)>,
}

impl Checks {
    fn add(&mut self, config: &str, map: &str, material: LightMaterial, measured: &[Measured]) {
        self.rows += measured.len();
        if GOAL_MAPS.contains(&map) {
            // The row of the lowest error among `family`'s rows that `fits`.
            let lowest = |family: Family, fits: fn(&Measured) -> bool| {
                measured
                    .iter()
                    .filter(|m| m.method.family == family && fits(m))
                    .min_by(|a, b| a.worst(0.3).total_cmp(&b.worst(0.3)))
                    .cloned()
            };
            self.one_frame.push((
                config.to_string(),
                lowest(Family::Lobe, |m| m.ratio <= ONE_FRAME_COST),
            ));
            self.progressive.push((
                config.to_string(),
                lowest(Family::Progressive, |m| m.image_ms() <= PROGRESSIVE_MS),
            ));
        }
        for m in measured {
            let ratio = m.noise_over_error(0.3);
            if ratio.is_nan() || ratio > NOISE_FRACTION {
                let [family, samples, frames] = method_cells(&m.method);
                self.noise_bound.push(format!(
                    "{config} {family} N {samples} x {frames} ({ratio:.2})"
                ));
            }
        }
        if material != LightMaterial::Metal {
            return;
        }
        let ends = |family: Family| {
            let rows: Vec<f64> = measured
                .iter()
                .filter(|m| m.method.family == family)
                .map(|m| m.worst(0.3))
                .collect();
            (
                rows.first().copied().unwrap_or(f64::NAN),
                rows.last().copied().unwrap_or(f64::NAN),
            )
        };
        self.lobe_ends.push(ends(Family::Lobe));
        self.progressive_ends.push(ends(Family::Progressive));
    }

    fn goals(&self) -> Vec<Goal> {
        let pct = |v: &[(f64, f64)]| {
            v.iter()
                .map(|(a, b)| format!("{:.2} -> {:.2} %", 100.0 * a, 100.0 * b))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let falls = |v: &[(f64, f64)]| !v.is_empty() && v.iter().all(|(a, b)| b < a);
        let (fw, fh) = self.frame;
        // Each configuration's lowest error within the cost, against the goal's error.
        let within =
            |rows: &[(String, Option<Measured>)], goal: f64, what: &dyn Fn(&Measured) -> String| {
                let figure = rows
                    .iter()
                    .map(|(config, best)| match best {
                        Some(m) => format!("{config} {:.2} % ({})", 100.0 * m.worst(0.3), what(m)),
                        None => format!("{config}: no row within the cost"),
                    })
                    .collect::<Vec<_>>()
                    .join(", ");
                let met = !rows.is_empty()
                    && rows
                        .iter()
                        .all(|(_, best)| best.as_ref().is_some_and(|m| m.worst(0.3) <= goal));
                (figure, met)
            };
        let (one_frame, one_frame_met) = within(&self.one_frame, ONE_FRAME_ERROR, &|m| {
            format!("N = {}, {:.2}x", m.method.samples, m.ratio)
        });
        let (progressive, progressive_met) = within(&self.progressive, PROGRESSIVE_ERROR, &|m| {
            format!("{} frames, {:.2} s", m.method.frames, m.image_ms() / 1e3)
        });
        vec![
            Goal {
                what: format!(
                    "light (issue 37): one frame of the lobe within {} % at at most {ONE_FRAME_COST}x the split sum's frame ({fw}x{fh}), the worst ball of roughness >= 0.3, metals and plastics, studio and sky (each: the lowest error within the cost)",
                    100.0 * ONE_FRAME_ERROR
                ),
                figure: one_frame,
                met: one_frame_met,
            },
            Goal {
                what: format!(
                    "light (issue 37): the progressive lobe within {} % in at most {} s of {fw}x{fh} frames, metals and plastics, studio and sky (each: the lowest error within the time)",
                    100.0 * PROGRESSIVE_ERROR,
                    PROGRESSIVE_MS / 1e3
                ),
                figure: progressive,
                met: progressive_met,
            },
            Goal {
                what: format!("light: the Monte Carlo reference's noise at most {NOISE_FRACTION} of each row's error (the worst ball's at roughness >= 0.3: mean relative standard error over mean relative error)"),
                figure: if self.noise_bound.is_empty() {
                    format!("all {} rows (light_cost.csv)", self.rows)
                } else {
                    format!(
                        "{} of {} rows; not: {} (light_cost.csv, noise_over_err)",
                        self.rows - self.noise_bound.len(),
                        self.rows,
                        self.noise_bound.join(", ")
                    )
                },
                met: self.noise_bound.is_empty(),
            },
            Goal {
                what: "light: the lobe's error falls from N = 1 to N = 64 (metals, every map, worst at roughness >= 0.3)".into(),
                figure: pct(&self.lobe_ends),
                met: falls(&self.lobe_ends),
            },
            Goal {
                what: "light: the progressive lobe's error falls from its first frame count to its last (metals)".into(),
                figure: pct(&self.progressive_ends),
                met: falls(&self.progressive_ends),
            },
        ]
    }
}
