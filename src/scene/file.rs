//! The scene file format (TOML) and its validation.
//!
//! ```toml
//! preset = "accurate"          # optional: accurate | games202
//! geometry = "smith-correlated" # optional: schlick | smith | smith-correlated (default)
//! layering = "physical"        # optional: how a dielectric's base sits under its coating:
//!                              #   constant | gltf | view-only | reciprocal | physical (default)
//! coat_form = "physical"       # optional: how a clear coat weights the ball under it:
//!                              #   physical (default) | filament | gltf
//! base_reading = "apparent"    # optional: what a dielectric's base colour means: apparent
//!                              #   (default: the colour a viewer sees, as glTF) | substrate
//! exposure = 1.0               # optional, > 0
//! background = "environment"   # optional: environment (default) | black | [r, g, b]
//! ibl_term = "kulla-conty"     # optional: turquin | fdez-aguera | kulla-conty (default):
//!                              #   the model of balls that name none
//! ibl_method = "split-sum"     # optional: split-sum (default) | lobe: how the map lights
//!                              #   the balls (lobe: samples of each ball's own lobe; metals)
//! ibl_samples = 16             # optional, 1..=256: lobe samples a pixel a frame (default 16)
//! labels = true                # optional, default false: roughness, row model and a
//!                              #   caption drawn into PNG pictures and the viewer
//! antialias = true             # optional: antialiased silhouettes (default true)
//! size = [980, 720]            # optional: the picture's width and height in pixels, each
//!                              #   1..=16384: render's image, the viewer's scene area (the
//!                              #   window is that and the panel); --width/--height win
//! tone_map = "khronos-neutral" # optional: reinhard | aces | agx | khronos-neutral | none
//!                              #   (default: the preset's: accurate khronos-neutral,
//!                              #   games202 reinhard); PNGs and the window, not EXR
//! transfer = "srgb"            # optional: srgb | gamma-2.2 (default: the preset's:
//!                              #   accurate srgb, games202 gamma-2.2)
//! [camera]                     # optional: the reference camera
//! position = [0, 80, 300]
//! target = [0, 0, 0]
//! vfov_deg = 75
//! [environment]                # optional: black. Exactly one of radiance, map, builtin:
//! radiance = [1, 1, 1]         #   uniform linear radiance, or
//! # map = "studio.hdr"         #   an equirectangular .hdr/.exr, relative to this file, or
//! # builtin = "studio"         #   studio | sky | white (generated, 1024 x 512)
//! rotation_deg = 0             # optional: turns the map about +y
//! intensity = 1                # optional, >= 0: multiplies the radiance or the map
//! [[light]]                    # up to MAX_LIGHTS
//! direction = [0, 0, 1]        # towards the light; normalised on load
//! radiance = [1, 1, 1]
//! [[ball]]                     # at least one (up to MAX_BALLS)
//! grid = [0, 0]                # [row, col] (see `grid_position`), or position = [x, y, z]
//! radius = 35
//! roughness = 0.15             # in [0, 1]
//! model = "kulla-conty"       # optional: none | kulla-conty | turquin | fdez-aguera | truth
//!                              # (default: the scene's ibl_term, kulla-conty unless set);
//! # multiple_scattering = true #   shorthand: true = that default, false = "none"
//! label = "Gold"               # optional: one line, at most MAX_BALL_LABEL_BYTES bytes,
//!                              # drawn under the ball where `labels` is on
//! material = { kind = "metal", albedo = [0.7216, 0.451, 0.2] }   # pow 2.2 (the homework's);
//!                              # or f0 = [...] (linear)
//! # material = { base_color = [0.8, 0.3, 0.1], metallic = 0.5, ior = 1.5 }
//! #   the engines' material: base_color sRGB (the sRGB curve; or base_color_linear,
//! #   linear), metallic in [0, 1]
//! #   (default 0), ior in [1, 4] (default 1.5); or the shorthand
//! #   { kind = "dielectric", albedo = [...], ior = 1.5 } (albedo required, as a
//! #   metal's; a grey f0 for the ior)
//! # material = { base_color = [...], metallic = 1, anisotropy = 0.8, anisotropy_rotation = 0 }
//! #   any material with metal: its lobe's anisotropy in [0, 1] (glTF's
//! #   KHR_materials_anisotropy), turned by anisotropy_rotation radians from the tangent
//! #   around +y (docs/design/anisotropy.md)
//! # Any material takes a clear coat: clearcoat = 0.5 (weight in [0, 1], default 0),
//! #   clearcoat_roughness = 0.1 (in [0, 1], default 0), clearcoat_ior = 1.5 (in [1, 4])
//! ```
//!
//! Value checks (ranges, NaN, zero directions) run inside deserialisation, so toml reports
//! them with the line and column of the value; checks across fields report the line and
//! column of their table. A map that cannot be loaded is an error naming the map, its
//! reason, and the line and column of its `map` key.

use std::ops::Range;
use std::path::Path;

use glam::DVec3;
use serde::Deserialize;
use toml::Spanned;

use super::values::{
    Anisotropy, AnisotropyRotation, BackgroundValue, Colour, Direction, Finite, Finite3, Fov, Grid,
    IblSamples, ImageSize, Ior, Metallic, Named, NonNegative, Positive, Radiance, Roughness, Unit,
};
use super::{
    grid_position, srgb_decode, Ball, Camera, Layering, Light, Material, Model, Scene, DEFAULT_IOR,
    MAX_BALLS, MAX_LIGHTS,
};
use crate::brdf::Geometry;
use crate::display::{ToneMap, Transfer};
use crate::environment::{self, Builtin, Environment, IblMethod, IblTerm, Source};
use crate::error::{Error, Result};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    preset: Option<Named<super::Preset>>,
    geometry: Option<Named<Geometry>>,
    layering: Option<Named<Layering>>,
    coat_form: Option<Named<super::CoatForm>>,
    base_reading: Option<Named<super::BaseReading>>,
    exposure: Option<Positive>,
    antialias: Option<bool>,
    background: Option<BackgroundValue>,
    ibl_term: Option<Named<IblTerm>>,
    ibl_method: Option<Named<IblMethod>>,
    ibl_samples: Option<IblSamples>,
    tone_map: Option<Named<ToneMap>>,
    transfer: Option<Named<Transfer>>,
    #[serde(default)]
    labels: bool,
    size: Option<ImageSize>,
    camera: Option<Spanned<CameraFile>>,
    environment: Option<Spanned<EnvironmentFile>>,
    #[serde(default)]
    light: Vec<Spanned<LightFile>>,
    #[serde(default)]
    ball: Vec<Spanned<BallFile>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraFile {
    position: Finite3,
    target: Finite3,
    vfov_deg: Fov,
    min_aspect: Option<Finite>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct EnvironmentFile {
    radiance: Option<Radiance>,
    map: Option<Spanned<String>>,
    builtin: Option<Named<Builtin>>,
    rotation_deg: Option<Finite>,
    intensity: Option<NonNegative>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LightFile {
    direction: Direction,
    radiance: Radiance,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BallFile {
    position: Option<Finite3>,
    grid: Option<Grid>,
    radius: Positive,
    roughness: Roughness,
    multiple_scattering: Option<bool>,
    model: Option<Named<Model>>,
    label: Option<Spanned<String>>,
    material: Spanned<MaterialFile>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "lowercase")]
enum KindFile {
    Metal,
    Dielectric,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialFile {
    /// The shorthands: a metal (`albedo` or `f0`) or a dielectric (`albedo`, `ior` or a
    /// grey `f0`).
    kind: Option<KindFile>,
    /// sRGB colour (decoded with pow 2.2, the homework's): a metal's F0 or a dielectric's
    /// base.
    albedo: Option<Colour>,
    /// Linear F0: a metal's (instead of albedo), or a dielectric's (grey: it gives the IOR).
    f0: Option<Colour>,
    /// The engines' metallic-roughness material: sRGB colour (the sRGB curve), the metal's
    /// F0 and the dielectric's base.
    base_color: Option<Colour>,
    /// `base_color` given linear (what `shadeballs import` writes where no sRGB value
    /// decodes to a glTF file's linear colour exactly).
    base_color_linear: Option<Colour>,
    /// With `base_color`: in [0, 1], default 0.
    metallic: Option<Metallic>,
    /// The dielectric's index of refraction (default 1.5).
    ior: Option<Ior>,
    /// The metal lobe's anisotropy in [0, 1] (default 0; docs/design/anisotropy.md).
    anisotropy: Option<Anisotropy>,
    /// Its rotation from the ball's tangent, radians (default 0).
    anisotropy_rotation: Option<AnisotropyRotation>,
    /// The clear coat's weight in [0, 1] (default 0: none).
    clearcoat: Option<Unit>,
    /// The clear coat's roughness in [0, 1] (default 0).
    clearcoat_roughness: Option<Roughness>,
    /// The clear coat's index of refraction (default 1.5).
    clearcoat_ior: Option<Ior>,
    /// Linear radiance the surface emits, `[r, g, b]`, each finite and at least 0
    /// (default 0: none; glTF's `emissiveFactor` x `emissiveStrength`).
    emission: Option<Radiance>,
}

/// Reads and parses the scene file at `path`.
pub fn load(path: &Path) -> Result<Scene> {
    use std::io::Read;
    let err = |message: String| Error::Scene {
        path: path.to_path_buf(),
        message,
    };
    // Read at most one byte past the limit: `/dev/zero` or a stray huge file is an error,
    // not an endless read.
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(MAX_SCENE_BYTES + 1).read_to_end(&mut bytes))
        .map_err(|e| err(e.to_string()))?;
    if bytes.len() as u64 > MAX_SCENE_BYTES {
        return Err(err(format!(
            "larger than {MAX_SCENE_BYTES} bytes, the limit for a scene file \
             ({MAX_BALLS} balls and {MAX_LIGHTS} lights, each written out in full)"
        )));
    }
    let text = String::from_utf8(bytes).map_err(|e| {
        let valid = e.utf8_error().valid_up_to();
        let bytes = e.as_bytes();
        // The text up to the bad byte is valid, so the line and column count in it.
        let before = std::str::from_utf8(&bytes[..valid]).unwrap_or_default();
        err(at(
            before,
            valid..valid,
            &format!("not UTF-8 text (byte 0x{:02x})", bytes[valid]),
        ))
    })?;
    parse(&text, path)
}

/// Bytes a `[[ball]]` table may take in a scene file: the longest legal ball, every number
/// written with 17 digits and an exponent, is about 350 bytes; the rest is room for
/// comments and indentation.
pub(crate) const SCENE_BYTES_PER_BALL: u64 = 1024;
/// Bytes a `[[light]]` table may take (the longest legal one is about 130 bytes).
pub(crate) const SCENE_BYTES_PER_LIGHT: u64 = 512;
/// Bytes for the rest: the top-level keys, `[camera]`, `[environment]`, comments.
pub(crate) const SCENE_BYTES_OTHER: u64 = 64 * 1024;

/// Largest scene file read (`load`): the largest legal scene, [`MAX_BALLS`] balls and
/// [`MAX_LIGHTS`] lights written out in full, so that a huge file is refused before toml
/// parses it (a 16 MiB file used to take 1.3 GB to parse before its error).
pub const MAX_SCENE_BYTES: u64 = SCENE_BYTES_OTHER
    + MAX_BALLS as u64 * SCENE_BYTES_PER_BALL
    + MAX_LIGHTS as u64 * SCENE_BYTES_PER_LIGHT;

/// Parses scene text; `path` names the file in errors, and its folder is where a relative
/// `map` path is read from.
pub fn parse(text: &str, path: &Path) -> Result<Scene> {
    let err = |message: String| Error::Scene {
        path: path.to_path_buf(),
        message,
    };
    // Too many `[[ball]]` or `[[light]]` headers are counted before toml builds anything
    // (100,000 balls used to take 600 MB before their error), at the first one too many.
    for (header, max, what) in [
        ("[[ball]]", MAX_BALLS, "balls"),
        ("[[light]]", MAX_LIGHTS, "lights"),
    ] {
        let mut offset = 0;
        let extra = text
            .split_inclusive('\n')
            .map(|line| {
                let start = offset;
                offset += line.len();
                (start, line)
            })
            .filter(|(_, line)| line.trim_start().starts_with(header))
            .nth(max);
        if let Some((start, _)) = extra {
            return Err(err(at(
                text,
                start..start,
                &format!("more than {max} {what}"),
            )));
        }
    }
    // toml's own rendering spans several lines (a source snippet); the line and column
    // of its span, then its message, make the one line the front end prints.
    let file: SceneFile = toml::from_str(text).map_err(|e| {
        let message = crate::error::one_line(e.message());
        err(match e.span() {
            Some(span) => {
                let message = match key_before(text, span.start) {
                    Some(key) if !message.starts_with(key) => format!("{key}: {message}"),
                    _ => message,
                };
                at(text, span, &message)
            }
            None => message,
        })
    })?;
    build(file, path).map_err(|(span, msg)| err(at(text, span, &msg)))
}

/// The key whose value starts at byte `start` of `text` (`radius` in `radius = 0`, `f0` in
/// `material = { kind = "metal", f0 = [2, 1, 1] }`), so that a value's error names it.
fn key_before(text: &str, start: usize) -> Option<&str> {
    let mut start = start.min(text.len());
    while !text.is_char_boundary(start) {
        start -= 1;
    }
    let line_start = text[..start].rfind('\n').map_or(0, |i| i + 1);
    let before = text[line_start..start]
        .trim_end()
        .strip_suffix('=')?
        .trim_end();
    let is_key = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
    // Every byte of the key is ASCII, so its length in bytes is its length in chars.
    let len = before.chars().rev().take_while(|&c| is_key(c)).count();
    let key = &before[before.len() - len..];
    (!key.is_empty()).then_some(key)
}

/// "line L, column C: message" for the byte offset `span.start` of `text`.
fn at(text: &str, span: Range<usize>, message: &str) -> String {
    // A span inside a multi-byte character (never seen; fuzzed in the tests) counts from
    // that character's start.
    let mut start = span.start.min(text.len());
    while !text.is_char_boundary(start) {
        start -= 1;
    }
    let before = &text[..start];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    format!("line {line}, column {column}: {message}")
}

type Spanned2<T> = std::result::Result<T, (Range<usize>, String)>;

fn build(file: SceneFile, path: &Path) -> Spanned2<Scene> {
    let reference = Scene::reference();
    let (tone_map, transfer) = display(&file);
    let camera = match file.camera {
        None => reference.camera,
        Some(c) => {
            let span = c.span();
            let c = c.into_inner();
            let camera = Camera {
                position: c.position.0,
                target: c.target.0,
                vfov_deg: c.vfov_deg.0,
                min_aspect: c.min_aspect.map(|a| a.0),
            };
            if let Some(problem) = camera.problem() {
                return Err((span, problem.to_string()));
            }
            camera
        }
    };
    if file.ball.is_empty() {
        return Err((
            0..0,
            "the scene has no balls (add a [[ball]] table)".to_string(),
        ));
    }
    if file.ball.len() > MAX_BALLS {
        let span = file.ball[MAX_BALLS].span();
        return Err((span, format!("more than {MAX_BALLS} balls")));
    }
    if file.light.len() > MAX_LIGHTS {
        let span = file.light[MAX_LIGHTS].span();
        return Err((span, format!("more than {MAX_LIGHTS} lights")));
    }
    let term = file.ibl_term.map_or(IblTerm::KullaConty, |t| t.0);
    let balls = file
        .ball
        .into_iter()
        .map(|b| ball(b, term))
        .collect::<Spanned2<Vec<_>>>()?;
    let lights = file
        .light
        .into_iter()
        .map(|l| Light::new(l.get_ref().direction.0, l.get_ref().radiance.0))
        .collect();
    let (environment, environment_map) = match file.environment {
        None => (DVec3::ZERO, None),
        Some(e) => environment(e, path)?,
    };
    Ok(Scene {
        balls,
        lights,
        environment,
        environment_map,
        background: file.background.map_or(reference.background, |b| b.0),
        camera,
        exposure: file.exposure.map_or(1.0, |e| e.0),
        preset: file.preset.map_or(reference.preset, |p| p.0),
        geometry: file.geometry.map_or(reference.geometry, |g| g.0),
        layering: file.layering.map_or(reference.layering, |l| l.0),
        coat_form: file.coat_form.map_or(reference.coat_form, |f| f.0),
        base_reading: file.base_reading.map_or(reference.base_reading, |r| r.0),
        labels: file.labels,
        antialias: file.antialias.unwrap_or(reference.antialias),
        tone_map,
        transfer,
        ibl_method: file.ibl_method.map_or(reference.ibl_method, |m| m.0),
        ibl_samples: file.ibl_samples.map_or(reference.ibl_samples, |n| n.0),
        size: file.size.map(|s| s.0),
    })
}

/// `tone_map` and `transfer`: each `None` (the preset's) where the file names none.
fn display(file: &SceneFile) -> (Option<ToneMap>, Option<Transfer>) {
    (
        file.tone_map.as_ref().map(|t| t.0),
        file.transfer.as_ref().map(|t| t.0),
    )
}

/// The folder a scene file's relative paths start from: the file's own.
fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new(""),
    }
}

/// `[environment]`: the uniform radiance, or the map it names (loaded or generated).
fn environment(e: Spanned<EnvironmentFile>, path: &Path) -> Spanned2<(DVec3, Option<Environment>)> {
    let span = e.span();
    let e = e.into_inner();
    let intensity = e.intensity.map_or(1.0, |i| i.0);
    let rotation_deg = e.rotation_deg.map_or(0.0, |r| r.0);
    let (source, map) = match (e.radiance, e.map, e.builtin) {
        (Some(r), None, None) => return Ok((r.0 * intensity, None)),
        (None, Some(file), None) => {
            let map_span = file.span();
            let file = folder_of(path).join(file.into_inner());
            let (map, _stats) =
                environment::load(&file).map_err(|e| (map_span.clone(), e.to_string()))?;
            environment::check_map_radiance(map.peak(), intensity).map_err(|e| {
                let e = format!("the map '{}': {e}", file.display());
                (map_span, e)
            })?;
            (Source::File(file), map)
        }
        (None, None, Some(b)) => (
            Source::Builtin(b.0),
            b.0.generate(environment::builtin::DEFAULT_BUILTIN_WIDTH),
        ),
        _ => {
            return Err((
                span,
                "[environment] needs exactly one of `radiance` (uniform), `map` (a .hdr or \
                 .exr file) or `builtin` (a generated map)"
                    .to_string(),
            ))
        }
    };
    Ok((
        DVec3::ZERO,
        Some(Environment {
            source,
            map: std::sync::Arc::new(map),
            rotation_deg,
            intensity,
        }),
    ))
}

/// One `[[ball]]`; `term` is the model of a ball that names none (or says
/// `multiple_scattering = true`): the scene's `ibl_term`.
fn ball(b: Spanned<BallFile>, term: IblTerm) -> Spanned2<Ball> {
    let span = b.span();
    let b = b.into_inner();
    let center = match (b.position, b.grid) {
        (Some(p), None) => p.0,
        (None, Some(Grid([row, col]))) => grid_position(row, col),
        _ => {
            return Err((
                span,
                "a ball needs exactly one of `position` or `grid`".to_string(),
            ))
        }
    };
    let model = match (b.model, b.multiple_scattering) {
        (Some(m), None) => m.0,
        (None, Some(false)) => Model::None,
        (None, Some(true) | None) => Model::from_term(term),
        (Some(_), Some(_)) => {
            return Err((
                span,
                "a ball takes `model` or its shorthand `multiple_scattering`, not both".to_string(),
            ))
        }
    };
    let label = match b.label {
        Some(l) => {
            let span = l.span();
            Some(super::BallLabel::new(l.get_ref()).map_err(|e| (span, e))?)
        }
        None => None,
    };
    let material = material(b.material)?;
    Ok(Ball {
        center,
        radius: b.radius.0,
        roughness: b.roughness.0,
        material,
        model,
        label,
    })
}

fn material(m: Spanned<MaterialFile>) -> Spanned2<Material> {
    let span = m.span();
    let anisotropy = m.get_ref().anisotropy.map_or(0.0, |a| a.0);
    let rotation = m.get_ref().anisotropy_rotation.map_or(0.0, |r| r.0);
    let material = material_isotropic(m)?;
    if anisotropy > 0.0 && !material.has_metal() {
        return Err((
            span,
            "`anisotropy` is the metal lobe's: a material without metal (metallic 0) takes \
             none"
                .to_string(),
        ));
    }
    Ok(material.with_anisotropy(anisotropy, rotation))
}

fn material_isotropic(m: Spanned<MaterialFile>) -> Spanned2<Material> {
    let span = m.span();
    let m = m.into_inner();
    let clearcoat = super::ClearCoat {
        weight: m.clearcoat.map_or(0.0, |w| w.0),
        roughness: m.clearcoat_roughness.map_or(0.0, |r| r.0),
        ior: m
            .clearcoat_ior
            .map_or(super::DEFAULT_CLEARCOAT_IOR, |i| i.0),
    };
    let emission = m.emission.map_or(glam::DVec3::ZERO, |e| e.0);
    let material = material_base(Spanned::new(span.clone(), m))?;
    Ok(Material {
        clearcoat,
        emission,
        ..material
    })
}

fn material_base(m: Spanned<MaterialFile>) -> Spanned2<Material> {
    let span = m.span();
    let m = m.into_inner();
    let fail = |message: &str| Err((span.clone(), message.to_string()));
    let ior = m.ior.map(|i| i.0);
    let base_color = match (m.base_color, m.base_color_linear) {
        (Some(_), Some(_)) => {
            return fail("a material takes `base_color` (sRGB) or `base_color_linear`, not both")
        }
        (Some(b), None) => Some(srgb_decode(b.0.to_array())),
        (None, linear) => linear.map(|b| b.0),
    };
    match (m.kind, base_color) {
        (Some(_), Some(_)) => fail("a material takes `kind` or `base_color`, not both"),
        (None, None) => fail(
            "a material needs `base_color` (with `metallic` and `ior`) or a `kind` \
             (metal or dielectric)",
        ),
        (None, Some(base)) => {
            if m.albedo.is_some() || m.f0.is_some() {
                return fail("`base_color` takes no `albedo` or `f0`");
            }
            Ok(Material::metallic_roughness(
                base,
                m.metallic.map_or(0.0, |x| x.0),
                ior.unwrap_or(DEFAULT_IOR),
            ))
        }
        (Some(_), None) if m.metallic.is_some() => {
            fail("`metallic` goes with `base_color`: a `kind` is all metal or all dielectric")
        }
        (Some(KindFile::Metal), None) => match (m.albedo, m.f0, ior) {
            (_, _, Some(_)) => fail("a metal takes no `ior` (its F0 is `albedo` or `f0`)"),
            (Some(a), None, None) => Ok(Material::metal_gamma22(a.0.to_array())),
            (None, Some(f0), None) => Ok(Material::metal(f0.0)),
            _ => fail(
                "a metal needs exactly one of `albedo` (the homework's gamma 2.2) or `f0` \
                 (linear)",
            ),
        },
        (Some(KindFile::Dielectric), None) => {
            let ior = match (m.f0, ior) {
                (Some(_), Some(_)) => return fail("a dielectric takes `ior` or `f0`, not both"),
                (Some(f0), None) => ior_from_f0(f0.0).map_err(|e| (span.clone(), e))?,
                (None, ior) => ior.unwrap_or(DEFAULT_IOR),
            };
            // A dielectric needs its base colour, as a metal its F0 (issue 38, 9: it got a
            // black base silently).
            let Some(albedo) = m.albedo else {
                return fail(
                    "a dielectric needs `albedo` (its sRGB base colour; [0, 0, 0] for a black \
                     base, a clear coat over nothing)",
                );
            };
            let diffuse = super::gamma22_decode(albedo.0.to_array());
            Ok(Material::dielectric(diffuse, ior))
        }
    }
}

/// The IOR of a dielectric's grey `f0`: `(1 + sqrt F0) / (1 - sqrt F0)`, the inverse of
/// `brdf::f0_from_ior`.
fn ior_from_f0(f0: DVec3) -> std::result::Result<f64, String> {
    if f0.max_element() - f0.min_element() > 1e-9 {
        return Err(format!(
            "a dielectric's f0 must be grey (one index of refraction), not {}; give `ior`",
            super::short_numbers(&f0.to_array())
        ));
    }
    let r = f0.x.sqrt();
    let (lo, hi) = super::IOR_RANGE;
    let f0_range = || {
        let f0_of = |ior: f64| ((ior - 1.0) / (ior + 1.0)).powi(2);
        format!("give f0 in [{:.4}, {:.4}]", f0_of(lo), f0_of(hi))
    };
    // F0 = 1 (or more) is a perfect mirror: no index of refraction gives it (issue 38, 9:
    // it printed "ior 2000000000000.000").
    if r >= 1.0 - crate::brdf::DIV_EPSILON {
        return Err(format!(
            "a dielectric's f0 {} is a perfect mirror, which no ior gives ({}; a mirror is \
             a metal's f0 = [1, 1, 1])",
            super::short_number(f0.x),
            f0_range()
        ));
    }
    let ior = (1.0 + r) / (1.0 - r);
    if !(lo..=hi).contains(&ior) {
        return Err(format!(
            "a dielectric's f0 {} gives ior {}, outside [{lo}, {hi}] ({})",
            super::short_number(f0.x),
            super::short_number((ior * 1e3).round() / 1e3),
            f0_range()
        ));
    }
    Ok(ior)
}

#[cfg(all(test, feature = "scene-files"))]
mod tests {
    //! Scene files: the shipped ones equal the built-in scenes; every malformed file is an
    //! error that names the file, the line and the column.
    //!
    //! (Feature `scene-files`: the parser they test.)

    use std::path::{Path, PathBuf};

    use crate::brdf::Geometry;
    use crate::scene::{self, Preset, Scene};

    fn asset(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("assets/scenes")
            .join(name)
    }

    const BALL: &str = "[[ball]]\ngrid = [0, 0]\nradius = 35\nroughness = 0.5\nmaterial = { kind = \"metal\", f0 = [1, 1, 1] }\n";

    /// Parses `text` as `bad.toml` and returns the error message, asserting it names the file,
    /// a line and a column.
    fn error_of(text: &str) -> String {
        let err =
            scene::parse(text, Path::new("bad.toml")).expect_err("the scene should be rejected");
        let msg = err.to_string();
        println!("{msg}\n---");
        assert!(
            msg.contains("bad.toml"),
            "message does not name the file: {msg}"
        );
        assert!(
            msg.contains("line") && msg.contains("column"),
            "message has no line/column: {msg}"
        );
        msg
    }

    #[test]
    fn shipped_scenes_equal_the_built_in_ones() {
        assert_eq!(
            scene::load(&asset("homework.toml")).unwrap(),
            Scene::reference()
        );
        assert_eq!(
            scene::load(&asset("furnace.toml")).unwrap(),
            Scene::furnace()
        );
        assert_eq!(
            scene::load(&asset("default.toml")).unwrap(),
            Scene::showcase()
        );
    }

    /// `size = [width, height]` is the picture's size; a side out of `1..=16384`, a
    /// fraction or a third number is a one-line error at the value.
    #[test]
    fn size_key_is_the_pictures_size() {
        let scene = scene::parse(&format!("size = [980, 720]\n{BALL}"), Path::new("s.toml"));
        assert_eq!(scene.unwrap().size, Some((980, 720)));
        let scene = scene::parse(BALL, Path::new("s.toml")).unwrap();
        assert_eq!(scene.size, None);
        for (bad, says) in [
            ("[0, 720]", "1..=16384"),
            ("[16385, 720]", "1..=16384"),
            ("[-5, 720]", "1..=16384"),
            ("[980, 720, 1]", "[width, height]"),
            ("[980.5, 720]", ""),
        ] {
            let msg = error_of(&format!("size = {bad}\n{BALL}"));
            assert!(msg.contains(says) && !msg.contains('\n'), "{bad}: {msg}");
        }
    }

    #[test]
    fn valid_file_with_every_field() {
        let text = r#"
    preset = "games202"
    geometry = "smith-correlated"
    exposure = 2.0
    [camera]
    position = [0, 0, 10]
    target = [0, 0, 0]
    vfov_deg = 40
    [environment]
    radiance = [0.5, 0.5, 0.5]
    [[light]]
    direction = [0, 0, 2]
    radiance = [3, 3, 3]
    [[ball]]
    position = [1, 2, 3]
    radius = 1.5
    roughness = 0
    multiple_scattering = false
    material = { kind = "dielectric", albedo = [0.5, 0.5, 0.5] }
    "#;
        let s = scene::parse(text, Path::new("ok.toml")).unwrap();
        assert_eq!(s.preset, Preset::Games202);
        assert_eq!(s.geometry, Geometry::SmithCorrelated);
        assert_eq!(
            s.effective_geometry(),
            Geometry::Schlick,
            "games202 forces schlick G"
        );
        assert_eq!(
            s.lights[0].direction,
            glam::DVec3::Z,
            "directions are normalised"
        );
        assert_eq!(s.balls.len(), 1);
        assert_eq!(s.balls[0].material.ior, scene::DEFAULT_IOR);
        assert_eq!(s.balls[0].material.metallic, 0.0);
        assert!(!s.balls[0].model.has_term());
    }

    #[test]
    fn unknown_key() {
        let msg = error_of(&format!("{BALL}colour = 3\n"));
        assert!(msg.contains("colour"), "{msg}");
    }

    #[test]
    fn wrong_type() {
        error_of("[[ball]]\ngrid = [0, 0]\nradius = \"big\"\nroughness = 0.5\nmaterial = { kind = \"metal\", f0 = [1, 1, 1] }\n");
    }

    #[test]
    fn truncated() {
        error_of(&BALL[..BALL.len() - 20]);
    }

    #[test]
    fn empty() {
        let msg = error_of("");
        assert!(msg.contains("no balls"), "{msg}");
    }

    #[test]
    fn roughness_out_of_range() {
        let msg = error_of(&BALL.replace("roughness = 0.5", "roughness = 1.5"));
        assert!(msg.contains("line 4"), "roughness is on line 4: {msg}");
        assert!(msg.contains("outside [0, 1]"), "{msg}");
    }

    #[test]
    fn negative_radius_nan_and_zero_direction() {
        error_of(&BALL.replace("radius = 35", "radius = -1"));
        error_of(&BALL.replace("roughness = 0.5", "roughness = nan"));
        let msg = error_of(&format!(
            "{BALL}[[light]]\ndirection = [0, 0, 0]\nradiance = [1, 1, 1]\n"
        ));
        assert!(msg.contains("zero"), "{msg}");
    }

    #[test]
    fn cross_field_errors_have_positions() {
        let msg = error_of(&BALL.replace("grid = [0, 0]", "grid = [0, 0]\nposition = [0, 0, 0]"));
        assert!(msg.contains("exactly one of `position` or `grid`"), "{msg}");
        let msg = error_of(&format!(
            "[camera]\nposition = [0, 5, 0]\ntarget = [0, 0, 0]\nvfov_deg = 60\n{BALL}"
        ));
        assert!(msg.contains("line 1"), "{msg}");
        error_of(&BALL.replace("f0 = [1, 1, 1]", "f0 = [1, 1, 1], albedo = [1, 1, 1]"));
    }

    #[test]
    fn missing_file_names_it() {
        let err = scene::load(Path::new("/nonexistent/scene.toml"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("/nonexistent/scene.toml"), "{err}");
    }
}
