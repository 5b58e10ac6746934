//! The command line's flags: what `shadeballs bake`, `bench`, `environment`, `render`,
//! `probe`, `truth` and `view` accept, and the parsers of their values. The binary (`src/main.rs`) only adds the subcommand
//! names around these; they live in the library so that tests parse argv in-process with
//! exactly the binary's rules (`clap::Args::augment_args` and `FromArgMatches`), and fuzz
//! them without starting a process per case. Values are checked here, so a bad flag is one
//! clear line from clap before any work starts. The values a named flag accepts come from
//! its enum (`ALL` and `name()`, through `value_enum!`): help text never lists them by hand.

use std::path::PathBuf;

use clap::error::ErrorKind;

use crate::brdf::Geometry;
use crate::display::ToneMap;
use crate::environment::{Background, Builtin, Environment, IblMethod, IblTerm};
use crate::gpu::Backend;
use crate::lut::{self, LayoutKind, Method, PointSet, Storage};
use crate::scene::{Layering, Preset};

/// Implements [`clap::ValueEnum`] for enums with `ALL` and `name()` (the names `FromStr`
/// parses, see `named_enum!`): clap parses the flag, prints `[possible values: ...]` in
/// `--help` and names the choices when a value is wrong. A variant added to `ALL` is a new
/// value without any change here. (The impls live in the command line, so the library
/// builds without clap.)
macro_rules! value_enum {
    ($($ty:ty),+ $(,)?) => {$(
        impl clap::ValueEnum for $ty {
            fn value_variants<'a>() -> &'a [Self] {
                &<$ty>::ALL
            }
            fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
                Some(clap::builder::PossibleValue::new(self.name()))
            }
        }
    )+};
}

value_enum!(
    Geometry,
    Method,
    PointSet,
    LayoutKind,
    Storage,
    Preset,
    Backend,
    IblTerm,
    IblMethod,
    Builtin,
    BackgroundArg,
    OnOff,
    Layering,
    ToneMap,
);

/// `--aa`: a switch spelled `on` or `off`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum OnOff {
    /// On.
    On,
    /// Off.
    Off,
}

impl OnOff {
    /// Every value, in the order the help lists them.
    pub(crate) const ALL: [OnOff; 2] = [OnOff::On, OnOff::Off];

    /// The name the command line uses.
    pub(crate) fn name(self) -> &'static str {
        match self {
            OnOff::On => "on",
            OnOff::Off => "off",
        }
    }

    /// Whether it is on.
    pub(crate) fn is_on(self) -> bool {
        self == OnOff::On
    }
}

/// `--background`: what the pixels no ball covers show.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum BackgroundArg {
    /// The environment along the pixel's ray.
    Environment,
    /// Black.
    Black,
}

impl BackgroundArg {
    /// Every value, in the order the help lists them.
    pub(crate) const ALL: [BackgroundArg; 2] = [BackgroundArg::Environment, BackgroundArg::Black];

    /// The name the command line uses.
    pub(crate) fn name(self) -> &'static str {
        match self {
            BackgroundArg::Environment => "environment",
            BackgroundArg::Black => "black",
        }
    }

    /// The scene's background it stands for.
    pub(crate) fn background(self) -> Background {
        match self {
            BackgroundArg::Environment => Background::Environment,
            BackgroundArg::Black => Background::Black,
        }
    }
}

/// The help of `--environment`, naming the built-ins from [`Builtin::ALL`].
fn environment_help() -> String {
    let names: Vec<_> = Builtin::ALL.iter().map(|b| b.name()).collect();
    format!(
        "Light the balls with this environment map instead of the scene's environment: a \
         built-in ({}) or an equirectangular .hdr/.exr file (not turned, intensity 1; the \
         uniform radiance is set to black)",
        names.join(", ")
    )
}

/// Flags of `shadeballs bake`.
#[derive(clap::Args)]
pub struct BakeArgs {
    /// Output file: .csv (one row per texel), .exr (f32), .png (16 bit), or .ktx2: the
    /// texture the shader reads (R = 1 - E, G = 1 - E_avg of the row; the layout in its
    /// key/value block), in the --storage format: f32 R32G32_SFLOAT, f16 R16G16_SFLOAT,
    /// unorm8 R8G8_UNORM; or .h / .glsl: C / GLSL float arrays of 1 - E and 1 - E_avg as
    /// stored, their layout in a comment.
    #[arg(long)]
    pub out: PathBuf,
    /// Table size: N (N x N) or MUxR (mu texels x roughness texels). Default: the layout's.
    #[arg(long, value_parser = parse_size, allow_negative_numbers = true)]
    pub size: Option<(usize, usize)>,
    /// Masking-shadowing term.
    #[arg(long, default_value_t = Geometry::Schlick)]
    pub geometry: Geometry,
    /// Estimator of E(mu, roughness).
    #[arg(long, default_value_t = lut::DEFAULT_METHOD)]
    pub method: Method,
    /// Samples per texel (Monte Carlo) or Gauss-Legendre nodes per segment (quadrature).
    #[arg(long, default_value_t = lut::DEFAULT_SAMPLES as u32, value_parser = clap::value_parser!(u32).range(1..=1_000_000), allow_negative_numbers = true)]
    pub samples: u32,
    /// Point set for the Monte Carlo methods.
    #[arg(long, default_value_t = PointSet::Sobol)]
    pub points: PointSet,
    /// Table layout (games202: the homework's; uniform: for engines, read by a plain bilinear
    /// texture sample at uv = (mu (N-1)/N + 0.5/N, r (M-1)/M + 0.5/M); 128x128 by default,
    /// --size 2304x112 for 1e-3 everywhere at roughness >= 0.1: docs/accuracy.md).
    #[arg(long, default_value_t = LayoutKind::Warped)]
    pub layout: LayoutKind,
    /// Storage format the GPU will read (default: the layout's).
    #[arg(long)]
    pub storage: Option<Storage>,
}

/// The scene to draw, and the command line's overrides of it (`render` and `view`).
#[derive(clap::Args)]
pub struct SceneArgs {
    /// Scene file (TOML), or a glTF file (.gltf, .glb: its materials, as `shadeballs
    /// import` reads them); default: the showcase (assets/scenes/default.toml; the
    /// homework's scene is assets/scenes/homework.toml).
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Model preset: which Fresnel average and f_add form (default: the scene's, else
    /// accurate).
    #[arg(long)]
    pub preset: Option<Preset>,
    /// Masking-shadowing term for the accurate preset (default: the scene's; the built-in
    /// scenes use smith-correlated).
    #[arg(long)]
    pub geometry: Option<Geometry>,
    /// How every dielectric's base sits under its coating (default: the scene's, else
    /// physical, the form closest to the random walk; docs/design/materials.md).
    #[arg(long)]
    pub layering: Option<Layering>,
    /// How every clear coat weights the ball under it: physical (the coat's own lobe and
    /// term, the base through it both ways, internal reflections summed), filament or
    /// gltf (the engines', for comparison). Default: the scene's `coat_form`, else
    /// physical (docs/design/coat.md).
    #[arg(long, value_name = "physical|filament|gltf")]
    pub coat_form: Option<crate::scene::CoatForm>,
    /// What a dielectric's base colour means: apparent (the colour a viewer sees, as glTF,
    /// OpenPBR and Blender read it) or substrate (the albedo under the coating). Default:
    /// the scene's `base_reading`, else apparent.
    #[arg(long, value_name = "apparent|substrate")]
    pub(crate) base_reading: Option<crate::scene::BaseReading>,
    /// A built-in environment name or a .hdr/.exr path (the help names the built-ins).
    #[arg(long, value_name = "NAME|FILE", help = environment_help())]
    pub environment: Option<String>,
    /// The multiple-scattering term of every ball that has one (its model: default the
    /// scene's, else kulla-conty).
    #[arg(long)]
    pub ibl_term: Option<IblTerm>,
    /// How the environment map lights the balls: split-sum (one prefiltered read a pixel)
    /// or lobe (--ibl-samples samples a pixel a frame of each ball's own lobe, of the
    /// cosine and of the map's brightness, combined by multiple importance sampling, each
    /// read at the map's full resolution). Default: the scene's `ibl_method`, else
    /// split-sum.
    #[arg(long)]
    pub ibl_method: Option<IblMethod>,
    /// Lobe samples a pixel a frame under --ibl-method lobe, 1..=256 (default: the
    /// scene's `ibl_samples`, else 16).
    #[arg(long, allow_negative_numbers = true,
          value_parser = clap::value_parser!(u32).range(1..=i64::from(crate::environment::MAX_IBL_SAMPLES)))]
    pub ibl_samples: Option<u32>,
    /// What the pixels no ball covers show (default: the scene's, else environment).
    #[arg(long)]
    pub(crate) background: Option<BackgroundArg>,
    /// Draw the chart's labels: the roughness under each column, the row's model at its
    /// left, a caption line (preset, G, environment); into a .png (never an .exr) and the
    /// viewer. Default: the scene's `labels` (on in the built-in scenes).
    #[arg(long, overrides_with = "no_labels")]
    pub labels: bool,
    /// Draw no labels (the opposite of --labels; the last one given wins).
    #[arg(long, overrides_with = "labels")]
    pub no_labels: bool,
    /// Antialiased silhouettes: a pixel a ball's edge crosses mixes ball and background by
    /// the fraction it covers, in linear radiance, on the GPU, the CPU and montecarlo
    /// (default: the scene's, else on; off: one ray through each pixel's centre, as the
    /// truth always traces).
    #[arg(long, value_name = "on|off")]
    pub(crate) aa: Option<OnOff>,
    /// Tone mapper of .png pictures and the window (default: the scene's `tone_map`, else
    /// the preset's: accurate khronos-neutral with the sRGB curve, games202 reinhard with
    /// gamma 2.2). An .exr stays linear radiance, before exposure and tone mapping.
    #[arg(long)]
    pub tone_map: Option<ToneMap>,
}

impl SceneArgs {
    /// The scene file's scene (or the showcase, `render`'s and `view`'s default), with the
    /// overrides applied.
    pub(crate) fn load(&self) -> crate::Result<crate::scene::Scene> {
        self.load_or(crate::scene::Scene::showcase)
    }

    /// The scene file's scene (or `default()` when no `--scene` is given), with the
    /// overrides applied.
    pub fn load_or(
        &self,
        default: fn() -> crate::scene::Scene,
    ) -> crate::Result<crate::scene::Scene> {
        let mut scene = match &self.scene {
            // A glTF file: its materials and spheres (`shadeballs import`'s scene).
            Some(path) if crate::import::is_gltf(path) => {
                let imported = crate::import::load(path)?;
                super::print_import_notices(&imported);
                imported.scene
            }
            Some(path) => crate::scene::load(path)?,
            None => default(),
        };
        scene.preset = self.preset.unwrap_or(scene.preset);
        scene.geometry = self.geometry.unwrap_or(scene.geometry);
        scene.layering = self.layering.unwrap_or(scene.layering);
        scene.coat_form = self.coat_form.unwrap_or(scene.coat_form);
        scene.base_reading = self.base_reading.unwrap_or(scene.base_reading);
        if let Some(name) = &self.environment {
            scene.environment_map = Some(Environment::named(name)?);
            scene.environment = glam::DVec3::ZERO;
        }
        if let Some(term) = self.ibl_term {
            scene.set_term(term);
        }
        scene.ibl_method = self.ibl_method.unwrap_or(scene.ibl_method);
        scene.ibl_samples = self.ibl_samples.unwrap_or(scene.ibl_samples);
        if let Some(b) = self.background {
            scene.background = b.background();
        }
        if self.labels || self.no_labels {
            scene.labels = self.labels;
        }
        if let Some(aa) = self.aa {
            scene.antialias = aa.is_on();
        }
        if let Some(t) = self.tone_map {
            scene.tone_map = Some(t);
        }
        if let Some(warning) = ignored_geometry(scene.preset, self.geometry) {
            eprintln!("warning: {warning}");
        }
        let black_map = scene.environment_map.as_ref().is_none_or(|e| e.is_black());
        if scene.lights.iter().all(|l| l.radiance == glam::DVec3::ZERO)
            && scene.environment == glam::DVec3::ZERO
            && black_map
        {
            let map = match &scene.environment_map {
                Some(e) if e.intensity == 0.0 => " (the map's intensity is 0)",
                Some(_) => " (the map is black)",
                None => "",
            };
            eprintln!(
                "warning: the scene has no light and a black environment{map}: the balls are \
                 black (add a [[light]] or an [environment])"
            );
        }
        Ok(scene)
    }
}

/// The warning for a `--geometry` the preset does not use (games202 always uses schlick).
pub(crate) fn ignored_geometry(preset: Preset, geometry: Option<Geometry>) -> Option<String> {
    let (Some(fixed), Some(asked)) = (preset.geometry(), geometry) else {
        return None;
    };
    (fixed != asked).then(|| {
        format!("--geometry {asked} is ignored: the {preset} preset always uses {fixed} G")
    })
}

/// Flags of `shadeballs render`.
#[derive(clap::Args)]
pub struct RenderArgs {
    /// The scene and its overrides.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Image width in pixels, 1..=16384 (a device with a smaller largest texture refuses
    /// more). Default: the scene's `size`, else 1280.
    #[arg(long, value_parser = parse_side, allow_negative_numbers = true)]
    pub width: Option<u32>,
    /// Image height in pixels, 1..=16384. Default: the scene's `size`, else 720.
    #[arg(long, value_parser = parse_side, allow_negative_numbers = true)]
    pub height: Option<u32>,
    /// .png (tone-mapped, 8 bit: --tone-map) or .exr (linear radiance: no exposure, tone
    /// map or transfer curve).
    #[arg(long, default_value = "shading_balls.png")]
    pub out: PathBuf,
    /// Where to render: a GPU backend (auto: any adapter, else the CPU), the CPU
    /// reference renderer, the Monte Carlo reference (montecarlo: the model integrated
    /// against the lights and the environment by importance sampling, on the GPU where
    /// auto finds an adapter that renders to Rgba32Float, else on the CPU with a notice;
    /// Ctrl-C stops the GPU's after a pass; montecarlo-cpu: on the CPU always), or the
    /// truth (every ball shaded with the random walk of Heitz et al. 2016, on the CPU: a bar
    /// with the time left on a terminal; Ctrl-C stops it after a pass and writes what it
    /// has, exit status 130).
    #[arg(long, default_value_t = Backend::Auto)]
    pub backend: Backend,
    /// Samples per pixel of --backend montecarlo, montecarlo-cpu and truth, 1..=65536; on a GPU backend,
    /// the frames accumulated for balls with model = "truth", 1..=1024 (otherwise
    /// ignored). Default 64; for truth with --stderr, the cap (default 65536).
    #[arg(long, allow_negative_numbers = true,
          value_parser = clap::value_parser!(u32).range(1..=i64::from(crate::cpu::montecarlo::MAX_SPP)))]
    pub spp: Option<u32>,
    /// --backend truth stops once every ball's mean radiance has this relative standard
    /// error: a fraction (0.005) or a percentage (0.5%), from 0.01% to 100%.
    #[arg(long, value_parser = parse_stderr, allow_negative_numbers = true)]
    pub stderr: Option<f64>,
    /// Random seed of --backend montecarlo and truth (ignored by other backends): the same
    /// seed gives the same image on any number of threads.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    pub seed: u64,
    /// Frames of --ibl-method lobe accumulated into the image on a GPU backend, 1..=4096
    /// (default 1): frame k takes the lobe samples k N .. (k + 1) N of each pixel's
    /// sequence, N = --ibl-samples, and the image is their mean.
    #[arg(long, allow_negative_numbers = true,
          value_parser = clap::value_parser!(u32).range(1..=i64::from(crate::environment::lobe::MAX_IBL_FRAMES)))]
    pub ibl_frames: Option<u32>,
    /// Print the plan (tables baked, pipelines, what each draws) on stderr before rendering.
    #[arg(long)]
    pub verbose: bool,
}

/// Flags of `shadeballs environment`.
#[derive(clap::Args)]
pub(crate) struct EnvironmentArgs {
    /// The built-in to write.
    #[arg(long)]
    pub name: Builtin,
    /// Output file: .exr (f32), .hdr (Radiance RGBE, about 1 % precision) or .png (a
    /// preview to look at: tone-mapped like render's PNGs, not a map to load).
    #[arg(long)]
    pub out: PathBuf,
    /// Width in texels: even, 2..=8192 (the height is half).
    #[arg(long, default_value_t = crate::environment::builtin::DEFAULT_BUILTIN_WIDTH,
          value_parser = parse_map_width, allow_negative_numbers = true)]
    pub width: u32,
}

/// `environment --width`: an even whole number in `2..=MAX_BUILTIN_WIDTH`.
pub(crate) fn parse_map_width(s: &str) -> Result<u32, String> {
    let max = crate::environment::builtin::MAX_BUILTIN_WIDTH;
    let n: i64 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a whole number"))?;
    if !(2..=i64::from(max)).contains(&n) || n % 2 != 0 {
        return Err(format!(
            "{n}: the width must be even and in 2..={max} (the height is half)"
        ));
    }
    Ok(n as u32)
}

/// Flags of `shadeballs probe`.
#[derive(clap::Args)]
pub struct ProbeArgs {
    /// CSV output (a .csv file): roughness,mu,E,E_avg.
    #[arg(long)]
    pub out: PathBuf,
    /// Grid side N, 2..=1024 (mu = i/(N-1), roughness = j/(N-1)).
    #[arg(long, default_value_t = 65, allow_negative_numbers = true,
          value_parser = clap::value_parser!(u32).range(2..=i64::from(crate::gpu::MAX_PROBE_GRID)))]
    pub grid: u32,
    /// Model preset: which Fresnel average and f_add form.
    #[arg(long, default_value_t = Preset::Accurate)]
    pub preset: Preset,
    /// Masking-shadowing term for the accurate preset (default schlick; games202 always
    /// uses schlick).
    #[arg(long)]
    pub geometry: Option<Geometry>,
    /// GPU backend: auto, vulkan or gl (the probe runs on the GPU; there is no cpu).
    #[arg(long, default_value_t = Backend::Auto, value_parser = parse_gpu_backend)]
    pub backend: Backend,
    /// Probe along this scene's own rows (one per roughness its plan bakes; mu = i/(N-1))
    /// instead of the N x N grid of the 2-D table; `--preset` and `--geometry` then come
    /// from the scene.
    #[arg(long)]
    pub scene: Option<PathBuf>,
}

/// Flags of `shadeballs view`.
#[derive(clap::Args)]
pub(crate) struct ViewArgs {
    /// The scene and its overrides.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Window width in pixels, 1..=16384, as for `render` (the panel takes 300 points on the
    /// right). Default: the scene's `size` (its scene area) and the panel, else 1280.
    #[arg(long, value_parser = parse_side, allow_negative_numbers = true)]
    pub width: Option<u32>,
    /// Window height in pixels, 1..=16384. Default: the scene's `size`, else 720.
    #[arg(long, value_parser = parse_side, allow_negative_numbers = true)]
    pub height: Option<u32>,
    /// Draw this many frames back to back, print their median times and exit.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1_000_000), allow_negative_numbers = true)]
    pub frames: Option<u32>,
    /// With --frames: save the window's last frame to this .png, or the scene area's
    /// linear radiance (before exposure and tone mapping, as render's) to this .exr.
    #[arg(long, requires = "frames")]
    pub screenshot: Option<PathBuf>,
    /// With --frames: after the last frame, save the scene as a scene file (.toml) that
    /// `shadeballs render` draws as the viewer's scene area (the size is in its first line).
    #[arg(long, requires = "frames")]
    pub save_scene: Option<PathBuf>,
    /// With --frames: turn the camera a little every frame (to measure frame times while
    /// orbiting).
    #[arg(long, requires = "frames")]
    pub orbit: bool,
    /// Compare two renderings of the scene, A left of a split and B right of it: each
    /// scene (as it is), on (every ball's term on), off (every term off), a model
    /// (kulla-conty, turquin, fdez-aguera) or truth; e.g. --compare on,off.
    #[arg(long, value_name = "A,B", value_parser = crate::viewer::compare::parse_sides)]
    pub compare: Option<(crate::viewer::compare::Side, crate::viewer::compare::Side)>,
    /// With --compare: the split's place across the scene area, 0..=1 (default 0.5).
    #[arg(long, requires = "compare", value_parser = parse_split, allow_negative_numbers = true)]
    pub split: Option<f64>,
    /// With --compare: show |A - B| of the displayed values times this scale (1, 2, 4, 8,
    /// 16, 32 or 64) in a colour ramp with a colour bar, instead of the wipe.
    #[arg(long, requires = "compare", value_parser = parse_difference_scale,
          allow_negative_numbers = true)]
    pub difference: Option<u32>,
    /// With --compare: A and B whole, each in its own half of the scene area, instead of
    /// the wipe (a screenshot's .csv beside it holds each ball's mean on both sides).
    #[arg(long, requires = "compare", conflicts_with_all = ["difference", "split"])]
    pub side_by_side: bool,
    /// GPU backend (the viewer needs a GPU).
    #[arg(long, default_value_t = Backend::Auto, value_parser = view_backend_parser())]
    pub backend: Backend,
}

/// `view --backend`: the GPU backends alone (auto, vulkan, gl), so that `view --help`
/// lists what the viewer takes, not render's CPU renderers.
pub(crate) fn view_backend_parser() -> impl clap::builder::TypedValueParser<Value = Backend> {
    let names = [Backend::Auto, Backend::Vulkan, Backend::Gl].map(Backend::name);
    use clap::builder::TypedValueParser as _;
    clap::builder::PossibleValuesParser::new(names).try_map(|s| s.parse::<Backend>())
}

/// `view --split`: a number in `[0, 1]`.
pub(crate) fn parse_split(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if (0.0..=1.0).contains(&v) => Ok(v),
        _ => Err(format!("'{s}' is not a split in 0..=1")),
    }
}

/// `view --difference`: one of [`crate::viewer::compare::DIFFERENCE_SCALES`].
pub(crate) fn parse_difference_scale(s: &str) -> Result<u32, String> {
    let scales = crate::viewer::compare::DIFFERENCE_SCALES;
    match s.trim().parse::<u32>() {
        Ok(v) if scales.contains(&v) => Ok(v),
        _ => Err(format!(
            "'{s}' is not a difference scale: use one of {scales:?}"
        )),
    }
}

/// Largest table side accepted (wgpu's guaranteed 2-D texture limit is 8192).
pub(crate) const MAX_TABLE_SIDE: usize = 8192;

/// `--size`: `N` or `MUxR`, each side a whole number in `2..=MAX_TABLE_SIDE`.
pub(crate) fn parse_size(s: &str) -> Result<(usize, usize), String> {
    let one = |t: &str| -> Result<usize, String> {
        let n: usize = t
            .trim()
            .parse()
            .map_err(|_| format!("'{t}' is not a whole number"))?;
        if !(2..=MAX_TABLE_SIDE).contains(&n) {
            return Err(format!("{n} is outside 2..={MAX_TABLE_SIDE}"));
        }
        Ok(n)
    };
    match s.split_once(['x', 'X']) {
        Some((a, b)) => Ok((one(a)?, one(b)?)),
        None => one(s).map(|n| (n, n)),
    }
}

/// Largest image or window side `render` and `view` accept: lavapipe's and most GPUs'
/// largest 2-D texture (the scene file's `size` keeps to the same).
pub(crate) use crate::scene::MAX_IMAGE_SIDE;

/// The size `render` draws (or `view`'s window, `panel` pixels added to the width of a
/// scene's `size`): each of `--width`/`--height` given, else the scene's `size`, else
/// 1280 x 720.
pub(crate) fn picture_size(
    (width, height): (Option<u32>, Option<u32>),
    scene: Option<(u32, u32)>,
    panel: u32,
) -> (u32, u32) {
    let (w, h) = scene.map_or((1280, 720), |(w, h)| {
        (w.saturating_add(panel).min(MAX_IMAGE_SIDE), h)
    });
    (width.unwrap_or(w), height.unwrap_or(h))
}

/// `--width` / `--height` of `render` and `view`: a whole number in
/// `1..=MAX_IMAGE_SIDE` (one rule for both; the device's own limit is checked when it is
/// open).
pub(crate) fn parse_side(s: &str) -> Result<u32, String> {
    let n: i64 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a whole number"))?;
    if !(1..=i64::from(MAX_IMAGE_SIDE)).contains(&n) {
        return Err(format!(
            "{n}: the image size must be in 1..={MAX_IMAGE_SIDE}"
        ));
    }
    Ok(n as u32)
}

/// `--stderr`: a fraction (`0.005`) or a percentage (`0.5%`) in `[MIN_STDERR, 1]`.
pub(crate) fn parse_stderr(s: &str) -> Result<f64, String> {
    let (number, scale) = match s.trim().strip_suffix('%') {
        Some(p) => (p.trim(), 0.01),
        None => (s.trim(), 1.0),
    };
    let min = crate::cpu::truth::MIN_STDERR;
    match number.parse::<f64>() {
        Ok(v) if (min..=1.0).contains(&(v * scale)) => Ok(v * scale),
        _ => Err(format!(
            "'{s}' is not a relative standard error in {min}..=1 (a fraction: 0.005, or a \
             percentage: 0.5%)"
        )),
    }
}

/// `probe --backend`: a GPU backend (the probe runs the shader's own reads on the GPU).
pub(crate) fn parse_gpu_backend(s: &str) -> Result<Backend, String> {
    match s.parse::<Backend>() {
        Ok(Backend::Cpu | Backend::Montecarlo | Backend::MontecarloCpu | Backend::Truth) => {
            Err("the probe runs on the GPU: use auto, vulkan or gl".to_string())
        }
        Ok(b) => Ok(b),
        Err(_) => Err(format!("'{s}' is not a backend: use auto, vulkan or gl")),
    }
}

/// What the front end prints for a clap error: `None` for `--help`, `--version` and a
/// missing subcommand (clap prints those itself, in full); otherwise one line: clap's
/// paragraphs but the usage block, joined, with a pointer to `--help` instead of it.
pub fn one_line_error(e: &clap::Error) -> Option<String> {
    if !e.use_stderr() || e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
        return None;
    }
    let rendered = e.render().to_string();
    let kept: Vec<String> = rendered
        .split("\n\n")
        .map(crate::error::one_line)
        .filter(|p| !p.is_empty() && !p.starts_with("Usage:") && !p.starts_with("For more"))
        .collect();
    let line = kept.join("; ");
    let line = if line.starts_with("error:") {
        line
    } else {
        format!("error: {line}")
    };
    Some(format!("{line} (see --help)"))
}
