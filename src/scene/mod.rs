//! The scene: balls, lights, environment, camera and the render settings
//! (docs/design/model.md and docs/design/reference-scene.md), its TOML file format, and its
//! validation. Knows nothing of wgpu.
//!
//! Conventions: world units are arbitrary (the reference scene uses the homework's), `+y`
//! is up, colours are linear RGB unless a field says sRGB, light directions point from the
//! surface towards the light.

mod ball_label;
mod camera;
mod clearcoat;
#[cfg(feature = "scene-files")]
mod file;
mod material;
mod model;
mod preset;
mod reading;
mod showcase;
#[cfg(all(test, feature = "cli"))]
mod tests;
#[cfg(feature = "scene-files")]
mod values;

use glam::DVec3;

pub(crate) use ball_label::BallLabel;
pub use ball_label::ELLIPSIS;
pub use ball_label::MAX_BALL_LABEL_BYTES;
pub use camera::bounds_pad_px;
pub use camera::Camera;
pub(crate) use camera::{CameraBasis, AA_EDGE_PX, BOUNDS_PAD_PX};
pub use clearcoat::ClearCoat;
pub use clearcoat::CoatForm;
pub(crate) use clearcoat::DEFAULT_CLEARCOAT_IOR;
#[cfg(feature = "scene-files")]
pub use file::load;
#[cfg(feature = "scene-files")]
pub use file::parse;
#[cfg(feature = "scene-files")]
pub use file::MAX_SCENE_BYTES;
pub use material::gamma22_decode;
pub use material::srgb_decode;
pub use material::Layering;
pub use material::Material;
pub use material::DEFAULT_IOR;
pub(crate) use material::IOR_RANGE;
pub use model::Model;
pub use preset::Preset;
pub use reading::BaseReading;
pub(crate) use showcase::{SHOWCASE_COLUMN_STEP, SHOWCASE_RADIUS};

use crate::brdf::Geometry;
use crate::display::{DisplayTransform, ToneMap, Transfer};
use crate::environment::{Background, Environment, IblMethod, IblTerm, DEFAULT_IBL_SAMPLES};

/// Most balls a scene may hold: a 64 x 64 chart. The GPU keeps them in a storage buffer
/// X; a frame's
/// cost follows the pixels the balls cover, not their number (docs/reliability.md,
/// "Limits").
pub const MAX_BALLS: usize = 4096;

/// Most directional lights a scene may hold.
pub const MAX_LIGHTS: usize = 16;

/// Largest magnitude of any number in a scene file (coordinates, radii, radiances,
/// exposure). The GPU works in f32 (largest value 3.4e38), where a "finite" f64 such as
/// 1e300 is infinite. Within this bound no pixel can overflow: the BRDF times the cosine
/// peaks near `1 / (2 pi alpha^3) = 2.5e9` at the roughness clamp (D up to
/// `1 / (pi alpha^2)`, `G / (4 mu_o)` up to `1 / (2 alpha)`), so 16 lights of radiance 1e12
/// under an exposure of 1e12 stay below 1e35, and squared distances below 1e25.
pub const MAX_MAGNITUDE: f64 = 1e12;

// A map's radiance is held to the same bound (`environment::check_map_radiance`).
const _: () = assert!(MAX_MAGNITUDE == crate::environment::MAX_MAP_RADIANCE);

pub(crate) use crate::error::{short_number, short_numbers};

/// Spacing of `grid = [row, col]` placements: the reference scene's layout
/// (docs/design/reference-scene.md, "The balls, the light and the camera"): column 0 at x =
/// 180, each column 80 to the left; row 0 at y = +60, each row 120 lower; z = 0.
pub(crate) fn grid_position(row: u32, col: u32) -> DVec3 {
    DVec3::new(180.0 - 80.0 * col as f64, 60.0 - 120.0 * row as f64, 0.0)
}

/// One exact sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ball {
    /// Centre, in world units.
    pub center: DVec3,
    /// Radius, in world units.
    pub radius: f64,
    /// In `[0, 1]`; the model clamps it to `[ROUGHNESS_MIN, 1]` when shading.
    pub roughness: f64,
    /// What the ball is made of.
    pub material: Material,
    /// The BRDF model it is shaded with.
    pub model: Model,
    /// Its own label, drawn under it where the scene's labels are on (an imported
    /// material's name); `None` for the chart's labels alone.
    pub label: Option<BallLabel>,
}

impl Ball {
    /// The roughness every isotropic part of the ball's shading reads
    /// (`Material::shading_roughness`): `roughness`, or an anisotropic lobe's isotropic
    /// equivalent.
    pub fn shading_roughness(&self) -> f64 {
        self.material.shading_roughness(self.roughness)
    }
}

/// A directional light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// Unit vector from the surface towards the light.
    pub direction: DVec3,
    /// Linear RGB radiance; a point it lights reflects `f_r * radiance * mu_i`.
    pub radiance: DVec3,
}

impl Light {
    /// A light towards unit `direction`, of `radiance`.
    pub fn new(direction: DVec3, radiance: DVec3) -> Self {
        Light {
            direction,
            radiance,
        }
    }
}

/// Point lights a map's sun is shaded as ([`SunLight::lights`]).
pub const SUN_POINTS: usize = 4;

/// A map's sun as lights ([`Scene::sun_light`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunLight {
    /// The sun's disc as [`SUN_POINTS`] point lights, each a quarter of its irradiance
    /// times the map's intensity, at `R / sqrt 2` from its centre (`R` its angular
    /// radius) a quarter turn apart: the four-point rule of a uniform disc, exact for
    /// every polynomial of degree 3 over it, so that a lobe sees the disc's second moment
    /// (Stroud 1971, "Approximate Calculation of Multiple Integrals", formula S2 3-1).
    /// The Monte Carlo and the walk never see the sun as lights: they read the map.
    pub lights: [Light; SUN_POINTS],
    /// The roughness from which a ball takes it ([`crate::environment::Sun::roughness_min`]),
    /// in f32 as the GPU's vertex stage compares it.
    pub roughness_min: f32,
}

impl SunLight {
    /// Whether `ball` takes the sun as a light (and reads the layers without it): every
    /// lobe that reads the prefiltered layers at least [`SunLight::roughness_min`] rough,
    /// compared in f32 as `sun_takes` in `screen.wgsl`.
    pub fn takes(&self, ball: &Ball) -> bool {
        let coat = &ball.material.clearcoat;
        ball.shading_roughness() as f32 >= self.roughness_min
            && (!coat.is_on() || coat.roughness as f32 >= self.roughness_min)
    }
}

/// A scene and its render settings.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The balls (at most [`MAX_BALLS`]: the renderers draw no more).
    pub balls: Vec<Ball>,
    /// The directional lights (at most [`MAX_LIGHTS`]: the GPU renderer uses no more).
    pub lights: Vec<Light>,
    /// Uniform environment radiance (the white furnace when 1 and `F0 = 1`); also the
    /// background.
    pub environment: DVec3,
    /// An environment map lighting the balls, added to the uniform `environment` (which a
    /// scene with a map leaves black).
    pub environment_map: Option<Environment>,
    /// What the pixels no ball covers show.
    pub background: Background,
    /// The camera the image is seen through.
    pub camera: Camera,
    /// Multiplies radiance before tone mapping.
    pub exposure: f64,
    /// The `F_avg` and `f_add` forms the multiple-scattering term uses (and, for
    /// `games202`, G).
    pub preset: Preset,
    /// The G the `accurate` preset uses (`games202` always uses schlick); default
    /// height-correlated Smith.
    pub geometry: Geometry,
    /// How every dielectric's base is weighted under its coating.
    pub layering: Layering,
    /// How every clear coat weights the ball under it (`coat_form`, `--coat-form`).
    pub coat_form: CoatForm,
    /// What every dielectric's `base_color` means: the colour a viewer sees (default) or
    /// the substrate's albedo under the coating (`base_reading`, `--base-reading`).
    pub base_reading: BaseReading,
    /// Whether the chart's labels (roughness under each column, the row's model, a
    /// caption) are drawn into PNG pictures and the viewer (`crate::labels`); the
    /// renderers themselves never draw them. On in the built-in scenes, off by default in
    /// a scene file.
    pub labels: bool,
    /// Antialiased silhouettes (default on): a pixel a ball's silhouette crosses mixes the
    /// ball and the background by the fraction of it the ball covers, computed analytically,
    /// in linear radiance (docs/design/antialiasing.md); off, one ray through each pixel's
    /// centre.
    pub antialias: bool,
    /// The tone mapper of PNG pictures and the window (`tone_map` in a scene file,
    /// `--tone-map`); `None`: the preset's ([`Preset::tone_map`]). EXR output is linear
    /// radiance, before exposure and tone mapping.
    pub tone_map: Option<ToneMap>,
    /// The transfer curve (`transfer` in a scene file); `None`: the preset's
    /// ([`Preset::transfer`]).
    pub transfer: Option<Transfer>,
    /// How the balls are lit by the environment map (`ibl_method`, `--ibl-method`):
    /// the split sum (default) or samples of each ball's lobe.
    pub ibl_method: IblMethod,
    /// Lobe samples a pixel a frame under [`IblMethod::Lobe`] (`ibl_samples`,
    /// `--ibl-samples`), in `1..=MAX_IBL_SAMPLES`.
    pub ibl_samples: u32,
    /// The picture's size in pixels the scene asks for (`size = [width, height]` in a scene
    /// file; a saved viewer scene writes its scene area's): `render`'s image and the
    /// viewer's scene area where `--width` and `--height` are not given. `None`: the
    /// commands' defaults. The renderers draw at the target's size, whatever this says.
    pub size: Option<(u32, u32)>,
}

/// The largest width or height of a picture in pixels (`--width`, `--height`, a scene
/// file's `size`): a device with a smaller largest texture refuses more.
pub(crate) const MAX_IMAGE_SIDE: u32 = 16384;

/// The reference scene's copper, a display colour the homework decodes with `pow 2.2`
/// ([`Material::metal_gamma22`]; docs/design/reference-scene.md, "The balls, the light and
/// the camera").
pub(crate) const REFERENCE_ALBEDO_SRGB: [f64; 3] = [0.7216, 0.451, 0.2];
/// Roughness per column of the reference scene (column 0 at x = 180).
pub const REFERENCE_ROUGHNESS: [f64; 5] = [0.15, 0.35, 0.55, 0.75, 0.95];
/// The reference scene's ball radius.
pub(crate) const REFERENCE_RADIUS: f64 = 35.0;

impl Scene {
    /// The homework's scene (docs/design/reference-scene.md, "The balls, the light and the
    /// camera"): two rows of five copper-coloured metal balls, top row with the
    /// multiple-scattering term, one white light from +z.
    pub fn reference() -> Self {
        Scene {
            balls: two_rows(Material::metal_gamma22(REFERENCE_ALBEDO_SRGB)),
            lights: vec![Light::new(DVec3::Z, DVec3::ONE)],
            environment: DVec3::ZERO,
            environment_map: None,
            background: Background::Environment,
            camera: Camera::reference(),
            exposure: 1.0,
            preset: Preset::Accurate,
            // The G closest to real multiple scattering (docs/truth.md, "How close to the truth").
            geometry: Geometry::SmithCorrelated,
            layering: Layering::default(),
            coat_form: CoatForm::default(),
            base_reading: BaseReading::default(),
            labels: true,
            antialias: true,
            // The homework's display: Reinhard and gamma 1/2.2, whichever the preset.
            tone_map: Some(DisplayTransform::HOMEWORK.tone_map),
            transfer: Some(DisplayTransform::HOMEWORK.transfer),
            ibl_method: IblMethod::SplitSum,
            ibl_samples: DEFAULT_IBL_SAMPLES,
            size: None,
        }
    }

    /// The white furnace (docs/design/reference-scene.md, "The white furnace"): the same
    /// balls with `F0 = 1`, no lights, a uniform white environment. With the term on, the
    /// balls vanish into the background.
    pub fn furnace() -> Self {
        let white = Material::metal(DVec3::ONE);
        Scene {
            balls: two_rows(white),
            lights: Vec::new(),
            environment: DVec3::ONE,
            ..Scene::reference()
        }
    }

    /// The fixed part of the background's radiance: the uniform environment under
    /// [`Background::Environment`] (plus the map along each ray where the scene has one),
    /// black, or the colour.
    pub(crate) fn background_radiance(&self) -> DVec3 {
        match self.background {
            Background::Environment => self.environment,
            Background::Black => DVec3::ZERO,
            Background::Colour(c) => c,
        }
    }

    /// What a pixel that misses every ball shows along unit direction `d`: the uniform
    /// environment plus the map (the background's), black, or the background's colour.
    pub(crate) fn background_along(&self, d: DVec3) -> DVec3 {
        match self.background {
            Background::Environment => {
                let map = self
                    .environment_map
                    .as_ref()
                    .map_or(DVec3::ZERO, |m| m.radiance(d));
                self.environment + map
            }
            Background::Black => DVec3::ZERO,
            Background::Colour(c) => c,
        }
    }

    /// The lobe mode's samples of each strategy a pixel a frame (the GPU's `IBL_SAMPLES`):
    /// `ibl_samples` within `1..=MAX_IBL_SAMPLES`.
    pub(crate) fn lobe_sample_count(&self) -> u32 {
        self.ibl_samples
            .clamp(1, crate::environment::MAX_IBL_SAMPLES)
    }

    /// The lobe mode's cosine samples a pixel a frame under this scene's map
    /// ([`crate::environment::lobe::cosine_samples`] of [`Self::lobe_sample_count`]; all of
    /// them without a map).
    pub(crate) fn cosine_samples(&self) -> u32 {
        let count = self.lobe_sample_count();
        let below_mean = self
            .environment_map
            .as_ref()
            .map_or(1.0, |e| e.map.light_below_mean());
        crate::environment::lobe::cosine_samples(count, below_mean)
    }

    /// Whether pixels that miss every ball show the environment map.
    pub(crate) fn background_shows_map(&self) -> bool {
        self.environment_map.is_some() && self.background == Background::Environment
    }

    /// The map's sun as the split sum shades it ([`crate::environment::Sun`]): lights
    /// after the scene's own, for the balls it [`SunLight::takes`]. None without a map, a
    /// sun, the split sum, or room in the lights' array ([`MAX_LIGHTS`]).
    pub fn sun_light(&self) -> Option<SunLight> {
        if self.ibl_method != crate::environment::IblMethod::SplitSum
            || self.lights.len() + SUN_POINTS > MAX_LIGHTS
        {
            return None;
        }
        let environment = self.environment_map.as_ref()?;
        let sun = environment.map.sun()?;
        let centre = environment.from_map(sun.direction);
        let radiance = sun.irradiance * environment.intensity / SUN_POINTS as f64;
        let (u, w) = centre.any_orthonormal_pair();
        // On the plane tangent at the centre, `tan(R / sqrt 2)` out: the disc's radius
        // is a few degrees at most (environment::sun::SUN_MAX_RADIUS).
        let offset = (sun.radius * std::f64::consts::FRAC_1_SQRT_2).tan();
        let lights =
            [u, w, -u, -w].map(|t| Light::new((centre + offset * t).normalize(), radiance));
        Some(SunLight {
            lights,
            roughness_min: sun.roughness_min() as f32,
        })
    }

    /// Gives every ball with a real-time term (`kulla-conty`, `turquin` or `fdez-aguera`)
    /// the term `term` (`--ibl-term`; the scene file's `ibl_term` is the term of the balls
    /// that name none).
    pub fn set_term(&mut self, term: IblTerm) {
        for b in &mut self.balls {
            if b.model.has_term() {
                b.model = Model::from_term(term);
            }
        }
    }

    /// The scene with [`Scene::set_term`] applied.
    #[cfg(test)]
    pub(crate) fn with_term(mut self, term: IblTerm) -> Self {
        self.set_term(term);
        self
    }

    /// The term of the first ball with one (what the viewer's picker shows), else
    /// Kulla-Conty.
    pub fn term(&self) -> IblTerm {
        self.balls
            .iter()
            .find_map(|b| b.model.term())
            .unwrap_or(IblTerm::KullaConty)
    }

    /// The key of ball `b`'s coating row (`lut::coating`); `None` for an all-metal ball.
    pub fn coating_key(&self, b: &Ball) -> Option<crate::lut::CoatingKey> {
        b.material.has_dielectric().then(|| {
            crate::lut::CoatingKey::new(
                b.shading_roughness(),
                b.material.ior,
                self.preset.dielectric_fresnel(),
                self.effective_geometry(),
            )
        })
    }

    /// Whether any ball is the random-walk truth.
    pub(crate) fn has_truth(&self) -> bool {
        self.balls.iter().any(|b| b.model == Model::Truth)
    }

    /// A clear coat's truth is walked under uniform light and maps only: next-event
    /// estimation through the coat to a directional light is not written
    /// (docs/design/coat.md), so a clear-coated ball walked (a truth ball, or every ball
    /// where `every_ball`) under the scene's lights is refused, by the CPU's truth and the
    /// GPU's alike, rather than drawn without its lights.
    pub(crate) fn check_clearcoat_truth_lights(&self, every_ball: bool) -> crate::Result<()> {
        let coated_walk = self
            .balls
            .iter()
            .take(MAX_BALLS)
            .filter(|b| every_ball || b.model == Model::Truth)
            .any(|b| b.material.clearcoat.is_on());
        if coated_walk && !self.lights.is_empty() {
            return Err(crate::Error::Invalid {
                what: "truth",
                message: "the truth of a clear-coated ball is walked under the environment \
                          alone: remove the scene's lights (a coat's walk has no next-event \
                          estimation)"
                    .into(),
            });
        }
        Ok(())
    }

    /// The display transform: the scene's tone mapper and transfer curve, each the
    /// preset's where the scene names none.
    pub fn display(&self) -> DisplayTransform {
        DisplayTransform {
            tone_map: self.tone_map.unwrap_or(self.preset.tone_map()),
            transfer: self.transfer.unwrap_or(self.preset.transfer()),
        }
    }

    /// The G the tables and the shader use: the preset's, or `self.geometry` for
    /// `accurate`.
    pub fn effective_geometry(&self) -> Geometry {
        self.preset.geometry().unwrap_or(self.geometry)
    }
}

fn two_rows(material: Material) -> Vec<Ball> {
    term_rows(material, REFERENCE_RADIUS, grid_position)
}

/// The chart's two rows of `material` balls of `radius` over [`REFERENCE_ROUGHNESS`], the
/// top row (0) with the Kulla-Conty term, the bottom one without, ball `(row, col)` at
/// `position(row, col)`.
pub(crate) fn term_rows(
    material: Material,
    radius: f64,
    position: impl Fn(u32, u32) -> DVec3 + Copy,
) -> Vec<Ball> {
    (0..2u32)
        .flat_map(|row| {
            REFERENCE_ROUGHNESS
                .iter()
                .enumerate()
                .map(move |(col, &roughness)| Ball {
                    center: position(row, col as u32),
                    radius,
                    roughness,
                    material,
                    model: if row == 0 {
                        Model::KullaConty
                    } else {
                        Model::None
                    },
                    label: None,
                })
        })
        .collect()
}
