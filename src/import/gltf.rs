//! A glTF 2.0 file as a scene (docs/interop.md, "glTF in").
//!
//! Read from each material, exactly: `pbrMetallicRoughness.baseColorFactor` (linear RGB:
//! the ball's base colour, written to a scene file as the sRGB that decodes to it),
//! `metallicFactor`, `roughnessFactor`, `KHR_materials_ior`'s `ior`,
//! `KHR_materials_specular`'s `specularFactor` and `specularColorFactor` (as the
//! specification's dielectric `F0`, whose index the coating takes) and
//! `KHR_materials_emissive_strength` with `emissiveFactor` (their product, the material's
//! `emission`). Textures, alpha and any
//! other extension are notices naming them; an extension in `extensionsRequired` that is not
//! one of [`SUPPORTED_EXTENSIONS`] refuses the file.
//!
//! Placement: a node whose mesh's bounds (its `POSITION` accessors' `min` and `max`, which
//! the specification requires) are a cube, and whose transform (with its parents') only
//! translates and scales uniformly, is a sphere: a ball at the transformed centre of the
//! bounds, of half their side times the scale. The file's first perspective camera is the
//! scene's; without one a camera frames the balls. A file with no such sphere gives a chart
//! of one ball per material. The balls are lit by the built-in studio map; each is labelled
//! with its material's name ([`crate::scene::BallLabel::shortened`]); a chart's labels on.

use std::path::{Path, PathBuf};

use glam::{DMat4, DQuat, DVec3};
use serde_json::{Map, Value};

use super::json::{array, err, index, number, numbers, object, string};
use crate::environment::{Background, Builtin, Environment};
use crate::error::{Error, Result};
use crate::scene::{Ball, Camera, Material, Model, Scene, DEFAULT_IOR, IOR_RANGE, MAX_BALLS};

/// Largest glTF file read (a `.gltf`'s JSON or a whole `.glb`), and largest external buffer
/// read when a position accessor has no bounds.
pub(crate) const MAX_GLTF_BYTES: u64 = 256 << 20;

/// The extensions read (a file may require these).
pub(crate) const SUPPORTED_EXTENSIONS: [&str; 5] = [
    "KHR_materials_ior",
    "KHR_materials_clearcoat",
    "KHR_materials_specular",
    "KHR_materials_emissive_strength",
    "KHR_materials_anisotropy",
];

/// How far a mesh's bounds may be from a cube and still be a sphere: the largest side
/// minus the smallest, over the largest (a tessellated sphere's bounds differ by about the
/// cosine of half its smallest angle step: 1.2e-4 in MetalRoughSpheresNoTextures).
pub(crate) const CUBE_TOLERANCE: f64 = 1e-3;

/// How far a node's transform may be from a translation and a uniform scale, relative to
/// the scale (a rotation of 1e-6 radians moves a ball by a millionth of its distance).
const TRANSFORM_TOLERANCE: f64 = 1e-6;

/// How far a rotation quaternion's length may be from 1 (the specification requires unit
/// quaternions; exporters write them in f32).
const UNIT_TOLERANCE: f64 = 1e-3;

/// Deepest node hierarchy followed: a deeper one (or a cycle) is an error.
const MAX_NODE_DEPTH: usize = 256;

/// The vertical field of view of the camera that frames the balls, in degrees.
const FRAMING_VFOV_DEG: f64 = 30.0;
/// The image aspect the framing camera fits (`render`'s default 1280 x 720).
const FRAMING_ASPECT: f64 = 16.0 / 9.0;
/// Room left around the framed balls, as a factor on the half extent.
const FRAMING_MARGIN: f64 = 1.12;

/// The chart's spacing when the file places no sphere: the showcase's radius and steps.
const CHART_RADIUS: f64 = crate::scene::SHOWCASE_RADIUS;
const CHART_STEP: f64 = crate::scene::SHOWCASE_COLUMN_STEP;
/// The distance between a chart's rows: wider than its columns' by the room of the
/// material's name under each ball (`crate::labels`).
const CHART_ROW_STEP: f64 = CHART_STEP + 20.0;

/// A glTF material's values as the file gives them (defaults filled in), linear.
#[derive(Clone, Debug, PartialEq)]
pub struct GltfMaterial {
    /// Its index in the file's `materials`, `None` for the specification's default
    /// material (a primitive with no `material`).
    pub index: Option<usize>,
    /// Its `name`, else `material N` (`default` for the default material).
    pub name: String,
    /// `baseColorFactor`'s RGB, linear.
    pub base_color: DVec3,
    /// `baseColorFactor`'s alpha.
    pub alpha: f64,
    /// `metallicFactor`.
    pub metallic: f64,
    /// `roughnessFactor`.
    pub roughness: f64,
    /// `KHR_materials_ior`'s `ior` (1.5 without it).
    pub ior: f64,
    /// `KHR_materials_specular`'s `specularFactor` (1 without it).
    pub specular_factor: f64,
    /// `KHR_materials_specular`'s `specularColorFactor` (white without it).
    pub specular_colour: DVec3,
    /// `emissiveFactor`.
    pub emissive: DVec3,
    /// `KHR_materials_emissive_strength`'s `emissiveStrength` (1 without it).
    pub emissive_strength: f64,
    /// `KHR_materials_anisotropy`'s `anisotropyStrength` (0 without it).
    pub anisotropy_strength: f64,
    /// `KHR_materials_anisotropy`'s `anisotropyRotation`, radians (0 without it).
    pub anisotropy_rotation: f64,
    /// `KHR_materials_clearcoat`'s `clearcoatFactor` and `clearcoatRoughnessFactor` (index
    /// 1.5, the extension's; no coat without it).
    pub clearcoat: crate::scene::ClearCoat,
}

impl GltfMaterial {
    /// The specification's default material: white, metallic 1, roughness 1.
    pub(crate) fn default_material() -> Self {
        GltfMaterial {
            index: None,
            name: "default".to_string(),
            base_color: DVec3::ONE,
            alpha: 1.0,
            metallic: 1.0,
            roughness: 1.0,
            ior: DEFAULT_IOR,
            specular_factor: 1.0,
            specular_colour: DVec3::ONE,
            emissive: DVec3::ZERO,
            emissive_strength: 1.0,
            anisotropy_strength: 0.0,
            anisotropy_rotation: 0.0,
            clearcoat: crate::scene::ClearCoat::NONE,
        }
    }

    /// `KHR_materials_specular`'s dielectric `F0`:
    /// `min(((ior - 1) / (ior + 1))^2 specularColorFactor, 1) specularFactor`.
    pub(crate) fn dielectric_f0(&self) -> DVec3 {
        let f0 = crate::brdf::f0_from_ior(self.ior);
        (DVec3::splat(f0) * self.specular_colour).min(DVec3::ONE) * self.specular_factor
    }

    /// Whether `KHR_materials_specular` changes the dielectric (a factor or colour other
    /// than 1).
    pub(crate) fn has_specular(&self) -> bool {
        self.specular_factor != 1.0 || self.specular_colour != DVec3::ONE
    }

    /// The index of the ball's coating: `ior` itself without `KHR_materials_specular`, else
    /// the index whose `F0` is the mean of [`GltfMaterial::dielectric_f0`] (exact for a
    /// grey specular colour).
    pub(crate) fn coating_ior(&self) -> f64 {
        if !self.has_specular() {
            return self.ior;
        }
        let f0 = self.dielectric_f0();
        ior_from_f0((f0.x + f0.y + f0.z) / 3.0)
    }

    /// The emitted radiance the file asks for: `emissiveFactor` times
    /// `emissiveStrength` (linear, as glTF's factors are): the material's `emission`.
    pub fn emission(&self) -> DVec3 {
        self.emissive * self.emissive_strength
    }

    /// The ball's material: the engines' metallic-roughness material of `base_color`,
    /// `metallic` and [`GltfMaterial::coating_ior`], its metal's lobe anisotropic as
    /// `KHR_materials_anisotropy` asks (the rotation brought into `(-pi, pi]`; a material
    /// without metal keeps an isotropic lobe: the import's notice says so).
    pub(crate) fn material(&self) -> Material {
        let m = Material::metallic_roughness(self.base_color, self.metallic, self.coating_ior())
            .with_clearcoat(self.clearcoat);
        let m = Material {
            emission: self.emission(),
            ..m
        };
        if self.anisotropy_strength > 0.0 && m.has_metal() {
            let pi = std::f64::consts::PI;
            let turn = pi - (pi - self.anisotropy_rotation).rem_euclid(2.0 * pi);
            m.with_anisotropy(self.anisotropy_strength, turn)
        } else {
            m
        }
    }
}

/// The index of refraction whose normal-incidence reflectance is `f0`:
/// `(1 + sqrt(F0)) / (1 - sqrt(F0))`, the inverse of `brdf::f0_from_ior`.
pub(crate) fn ior_from_f0(f0: f64) -> f64 {
    let s = f0.clamp(0.0, 1.0).sqrt();
    (1.0 + s) / (1.0 - s).max(crate::brdf::DIV_EPSILON)
}

/// A glTF file read as a scene.
#[derive(Clone, Debug)]
pub struct Imported {
    /// The scene: the balls, the file's camera or one framing them, the studio map.
    pub scene: Scene,
    /// Every material the balls use, and those they do not (the file's order; the
    /// default material last where a primitive has none).
    pub materials: Vec<GltfMaterial>,
    /// Per ball, its material's index in `materials`.
    pub ball_materials: Vec<usize>,
    /// Per ball, the name of the node it stands for (`None` in a chart).
    pub ball_nodes: Vec<Option<String>>,
    /// Whether the balls stand where the file's spheres stand (else a chart).
    pub placed: bool,
    /// Whether the camera is the file's.
    pub camera_from_file: bool,
    /// What was not carried over, one line each (textures, extensions, emission, ...).
    pub notices: Vec<String>,
}

/// Reads the glTF file at `path` (`.gltf` with its buffers beside it, or `.glb`).
pub fn load(path: &Path) -> Result<Imported> {
    let fail = |message: String| Error::Scene {
        path: path.to_path_buf(),
        message,
    };
    let size = std::fs::metadata(path)
        .map_err(|e| fail(format!("cannot read: {e}")))?
        .len();
    if size > MAX_GLTF_BYTES {
        return Err(fail(format!(
            "{size} bytes, more than the {MAX_GLTF_BYTES} a glTF file may have here"
        )));
    }
    let bytes = std::fs::read(path).map_err(|e| fail(format!("cannot read: {e}")))?;
    parse(&bytes, path.parent(), path)
}

/// Reads a glTF file's `bytes` (a `.gltf`'s JSON or a `.glb`), its external buffers
/// relative to `folder`; errors name `path`.
pub(crate) fn parse(bytes: &[u8], folder: Option<&Path>, path: &Path) -> Result<Imported> {
    read(bytes, folder).map_err(|message| Error::Scene {
        path: path.to_path_buf(),
        message: crate::error::one_line(&message),
    })
}

/// The files beside the glTF file at `path` that it names by a relative `uri`: its
/// buffers (which [`load`] reads) and its images (which it does not draw, but which are
/// part of the asset), each with what it is: the inputs an output must not replace
/// (issue 38, finding 2). Empty where the file cannot be read or is not glTF ([`load`]
/// says why then); `data:` URIs name no file.
pub(crate) fn external_files(path: &Path) -> Vec<(&'static str, PathBuf)> {
    if !std::fs::metadata(path).is_ok_and(|m| m.len() <= MAX_GLTF_BYTES) {
        return Vec::new();
    }
    let Ok(bytes) = std::fs::read(path) else {
        return Vec::new();
    };
    let json = if super::glb::is_glb(&bytes) {
        match super::glb::split(&bytes) {
            Ok(glb) => glb.json,
            Err(_) => return Vec::new(),
        }
    } else {
        &bytes[..]
    };
    let Ok(Value::Object(root)) = serde_json::from_slice::<Value>(json) else {
        return Vec::new();
    };
    let folder = path.parent().unwrap_or(Path::new("."));
    let mut files = Vec::new();
    for (key, what) in [("buffers", "buffer"), ("images", "image")] {
        let Some(Value::Array(items)) = root.get(key) else {
            continue;
        };
        for item in items {
            let uri = item.get("uri").and_then(Value::as_str);
            if let Some(uri) = uri.filter(|u| !u.starts_with("data:")) {
                files.push((what, folder.join(percent_decode(uri))));
            }
        }
    }
    files
}

/// Where a buffer's bytes are.
enum BufferData {
    /// In memory (a `.glb`'s BIN chunk or a `data:` URI).
    Bytes(Vec<u8>),
    /// A file beside the glTF file, read only when its bytes are needed.
    File(PathBuf),
}

struct Buffer {
    byte_length: usize,
    data: BufferData,
    uri: String,
}

struct Doc<'a> {
    root: &'a Map<String, Value>,
    buffers: Vec<Buffer>,
    notices: Vec<String>,
    /// Buffers whose file is not beside the glTF file.
    missing: Vec<usize>,
    /// Buffers whose bytes were read (positions without bounds).
    needed: Vec<usize>,
}

fn read(bytes: &[u8], folder: Option<&Path>) -> std::result::Result<Imported, String> {
    let (json, bin) = if super::glb::is_glb(bytes) {
        let glb = super::glb::split(bytes)?;
        (glb.json, glb.bin)
    } else {
        (bytes, None)
    };
    let value: Value = serde_json::from_slice(json).map_err(|e| format!("not glTF JSON: {e}"))?;
    let root = object(&value, "the file")?;
    check_asset(root)?;
    let mut notices = Vec::new();
    check_extensions(root, &mut notices)?;
    let buffers = buffers(root, bin, folder)?;
    let missing = buffers
        .iter()
        .enumerate()
        .filter(|(_, b)| matches!(&b.data, BufferData::File(p) if !p.is_file()))
        .map(|(i, _)| i)
        .collect();
    let mut doc = Doc {
        root,
        buffers,
        notices,
        missing,
        needed: Vec::new(),
    };
    check_buffer_views(&doc)?;
    let mut materials = materials(root, &mut doc.notices)?;
    let placements = placements(&mut doc)?;
    let placed = !placements.spheres.is_empty();
    let default_index = materials.len();
    let material_of = |m: Option<usize>| m.unwrap_or(default_index);
    let mut balls = Vec::new();
    let mut ball_materials = Vec::new();
    let mut ball_nodes = Vec::new();
    if placed {
        if placements.spheres.iter().any(|s| s.material.is_none()) {
            materials.push(GltfMaterial::default_material());
        }
        for s in &placements.spheres {
            let k = material_of(s.material);
            balls.push(ball(&materials[k], s.centre, s.radius));
            ball_materials.push(k);
            ball_nodes.push(Some(s.name.clone()));
        }
        let unused: Vec<&str> = materials
            .iter()
            .enumerate()
            .filter(|(k, _)| !ball_materials.contains(k))
            .map(|(_, m)| m.name.as_str())
            .collect();
        if !unused.is_empty() {
            doc.notices.push(format!(
                "{} material(s) on no sphere, not drawn: {}",
                unused.len(),
                list(&unused)
            ));
        }
    } else {
        if materials.is_empty() {
            return Err("the file has no material and no sphere: nothing to draw".to_string());
        }
        let columns = (materials.len() as f64).sqrt().ceil() as usize;
        let rows = materials.len().div_ceil(columns);
        for (k, m) in materials.iter().enumerate() {
            let (row, col) = (k / columns, k % columns);
            let centre = DVec3::new(
                CHART_STEP * (col as f64 - (columns - 1) as f64 / 2.0),
                -CHART_ROW_STEP * (row as f64 - (rows - 1) as f64 / 2.0),
                0.0,
            );
            balls.push(ball(m, centre, CHART_RADIUS));
            ball_materials.push(k);
            ball_nodes.push(None);
        }
    }
    if balls.len() > MAX_BALLS {
        return Err(format!(
            "{} balls, more than the {MAX_BALLS} a scene may hold",
            balls.len()
        ));
    }
    if !placements.skipped.is_empty() {
        doc.notices.push(format!(
            "{} node(s) not drawn (a mesh whose bounds are no cube, or a transform that is more \
             than a translation and a uniform scale): {}",
            placements.skipped.len(),
            list(
                &placements
                    .skipped
                    .iter()
                    .map(String::as_str)
                    .collect::<Vec<_>>()
            )
        ));
    }
    for &b in &doc.missing {
        if !doc.needed.contains(&b) {
            doc.notices.push(format!(
                "buffer {b} ('{}') is not beside the file; not needed: the import reads only \
                 the accessors' bounds",
                doc.buffers[b].uri
            ));
        }
    }
    let camera_from_file = placements.camera.is_some();
    let camera = match placements.camera {
        Some(c) => c,
        None => frame(&balls),
    };
    for (k, m) in materials.iter().enumerate() {
        if !ball_materials.contains(&k) {
            continue;
        }
        material_notices(m, &mut doc.notices);
    }
    let scene = Scene {
        balls,
        lights: Vec::new(),
        environment: DVec3::ZERO,
        environment_map: Some(Environment::builtin(Builtin::Studio)),
        background: Background::Environment,
        camera,
        exposure: 1.0,
        // Each ball's label is its material's name (`Ball::label`), drawn in a chart; the
        // file's own placement (spheres close together, seen in depth) leaves them no
        // room, so they are there for `--labels` alone.
        labels: !placed,
        tone_map: None,
        transfer: None,
        ..Scene::reference()
    };
    Ok(Imported {
        scene,
        materials,
        ball_materials,
        ball_nodes,
        placed,
        camera_from_file,
        notices: doc.notices,
    })
}

/// The names of `items`, quoted, the first eight and a count of the rest.
fn list(items: &[&str]) -> String {
    const SHOWN: usize = 8;
    let mut s = items
        .iter()
        .take(SHOWN)
        .map(|n| format!("'{n}'"))
        .collect::<Vec<_>>()
        .join(", ");
    if items.len() > SHOWN {
        s.push_str(&format!(" and {} more", items.len() - SHOWN));
    }
    s
}

fn ball(m: &GltfMaterial, centre: DVec3, radius: f64) -> Ball {
    Ball {
        center: centre,
        radius,
        roughness: m.roughness,
        material: m.material(),
        model: Model::KullaConty,
        label: crate::scene::BallLabel::shortened(&m.name),
    }
}

/// What a drawn material loses: its emission's dimming under a clear coat, its specular
/// colour or factor where the coating cannot carry them.
fn material_notices(m: &GltfMaterial, notices: &mut Vec<String>) {
    if m.emission() != DVec3::ZERO && m.clearcoat.is_on() {
        notices.push(format!(
            "material '{}': its emission is drawn undimmed by the clear coat \
             (KHR_materials_clearcoat dims it by the coat's Fresnel)",
            m.name
        ));
    }
    if m.has_specular() && m.metallic < 1.0 {
        let f0 = m.dielectric_f0();
        if f0.x != f0.y || f0.y != f0.z {
            notices.push(format!(
                "material '{}': KHR_materials_specular's F0 {:?} is coloured; the coating takes \
                 its mean (index {})",
                m.name,
                f0.to_array(),
                m.coating_ior()
            ));
        }
        if m.specular_factor != 1.0 {
            notices.push(format!(
                "material '{}': specularFactor {} scales F0 (index {}); the grazing \
                 reflectance stays 1",
                m.name,
                m.specular_factor,
                m.coating_ior()
            ));
        }
    }
    if m.alpha != 1.0 {
        notices.push(format!(
            "material '{}': alpha {} ignored: the balls are opaque",
            m.name, m.alpha
        ));
    }
}

fn check_asset(root: &Map<String, Value>) -> std::result::Result<(), String> {
    let asset = root
        .get("asset")
        .ok_or_else(|| "not a glTF file: no 'asset'".to_string())?;
    let version = object(asset, "asset")?
        .get("version")
        .and_then(Value::as_str)
        .ok_or_else(|| "asset.version is missing".to_string())?;
    if !version.starts_with("2.") {
        return Err(format!("glTF version {version}: only glTF 2.0 is read"));
    }
    Ok(())
}

fn names<'a>(root: &'a Map<String, Value>, key: &str) -> std::result::Result<Vec<&'a str>, String> {
    array(root, key, "the file")?
        .iter()
        .map(|v| {
            v.as_str()
                .ok_or_else(|| err(key, format!("{v} is not a name")))
        })
        .collect()
}

fn check_extensions(
    root: &Map<String, Value>,
    notices: &mut Vec<String>,
) -> std::result::Result<(), String> {
    for name in names(root, "extensionsRequired")? {
        if !SUPPORTED_EXTENSIONS.contains(&name) {
            return Err(format!(
                "the file requires extension {name}, which shadeballs cannot honour (it reads {})",
                SUPPORTED_EXTENSIONS.join(", ")
            ));
        }
    }
    let unmodelled: Vec<&str> = names(root, "extensionsUsed")?
        .into_iter()
        .filter(|n| !SUPPORTED_EXTENSIONS.contains(n))
        .collect();
    if !unmodelled.is_empty() {
        notices.push(format!(
            "extension(s) not modelled, ignored: {}",
            list(&unmodelled)
        ));
    }
    Ok(())
}

/// Percent-decoding of a relative URI's path (`%20` and the like).
fn percent_decode(uri: &str) -> String {
    let b = uri.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let hex = |c: u8| (c as char).to_digit(16);
        if b[i] == b'%' && i + 2 < b.len() {
            if let (Some(h), Some(l)) = (hex(b[i + 1]), hex(b[i + 2])) {
                out.push((h * 16 + l) as u8);
                i += 3;
                continue;
            }
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

fn buffers(
    root: &Map<String, Value>,
    bin: Option<&[u8]>,
    folder: Option<&Path>,
) -> std::result::Result<Vec<Buffer>, String> {
    let mut out = Vec::new();
    for (i, b) in array(root, "buffers", "the file")?.iter().enumerate() {
        let at = format!("buffers[{i}]");
        let b = object(b, &at)?;
        let byte_length =
            number(b, "byteLength", &at, f64::NAN, (1.0, 9.007e15)).and_then(|x| {
                if x.is_nan() {
                    Err(err(&at, "has no byteLength"))
                } else {
                    Ok(x as usize)
                }
            })?;
        let (data, uri) = match string(b, "uri") {
            None => {
                let data =
                    match (i, bin) {
                        (0, Some(bin)) => bin.to_vec(),
                        _ => return Err(err(
                            &at,
                            "has no uri and the file has no .glb BIN chunk for it: its data is \
                             missing",
                        )),
                    };
                (BufferData::Bytes(data), "the BIN chunk".to_string())
            }
            Some(uri) if uri.starts_with("data:") => {
                let payload = uri
                    .split_once(";base64,")
                    .map(|(_, p)| p)
                    .ok_or_else(|| err(&at, "a data: URI that is not base64"))?;
                let data = super::base64::decode(payload)
                    .map_err(|e| err(&at, format!("data: URI: {e}")))?;
                (BufferData::Bytes(data), "a data: URI".to_string())
            }
            Some(uri) => {
                let rel = percent_decode(uri);
                let path = folder.unwrap_or(Path::new(".")).join(&rel);
                (BufferData::File(path), uri.to_string())
            }
        };
        if let BufferData::Bytes(d) = &data {
            if d.len() < byte_length {
                return Err(err(
                    &at,
                    format!(
                        "byteLength {byte_length}, but {uri} holds {} bytes: its data is missing",
                        d.len()
                    ),
                ));
            }
        }
        out.push(Buffer {
            byte_length,
            data,
            uri,
        });
    }
    Ok(out)
}

fn check_buffer_views(doc: &Doc) -> std::result::Result<(), String> {
    for (i, v) in array(doc.root, "bufferViews", "the file")?
        .iter()
        .enumerate()
    {
        let at = format!("bufferViews[{i}]");
        let v = object(v, &at)?;
        let b = index(v, "buffer", &at, ("buffer", doc.buffers.len()))?
            .ok_or_else(|| err(&at, "names no buffer"))?;
        let offset = number(v, "byteOffset", &at, 0.0, (0.0, 9.007e15))? as usize;
        let length = number(v, "byteLength", &at, 0.0, (1.0, 9.007e15))? as usize;
        if offset + length > doc.buffers[b].byte_length {
            return Err(err(
                &at,
                format!(
                    "bytes {offset}..{} lie past buffer {b}'s {} bytes",
                    offset + length,
                    doc.buffers[b].byte_length
                ),
            ));
        }
    }
    Ok(())
}

/// The textures a material's (or an extension's) object names.
const TEXTURE_KEYS: [&str; 11] = [
    "baseColorTexture",
    "metallicRoughnessTexture",
    "normalTexture",
    "occlusionTexture",
    "emissiveTexture",
    "specularTexture",
    "specularColorTexture",
    "anisotropyTexture",
    "clearcoatTexture",
    "clearcoatRoughnessTexture",
    "clearcoatNormalTexture",
];

fn materials(
    root: &Map<String, Value>,
    notices: &mut Vec<String>,
) -> std::result::Result<Vec<GltfMaterial>, String> {
    let mut out = Vec::new();
    for (i, m) in array(root, "materials", "the file")?.iter().enumerate() {
        let at = format!("materials[{i}]");
        let m = object(m, &at)?;
        let name = string(m, "name")
            .filter(|n| !n.is_empty())
            .map_or_else(|| format!("material {i}"), str::to_string);
        let at = format!("{at} ('{name}')");
        let none = Map::new();
        let pbr = match m.get("pbrMetallicRoughness") {
            Some(p) => object(p, &format!("{at}.pbrMetallicRoughness"))?,
            None => &none,
        };
        let pbr_at = format!("{at}.pbrMetallicRoughness");
        let unit = (0.0, 1.0);
        let base = numbers(pbr, "baseColorFactor", &pbr_at, [1.0; 4], unit)?;
        let metallic = number(pbr, "metallicFactor", &pbr_at, 1.0, unit)?;
        let roughness = number(pbr, "roughnessFactor", &pbr_at, 1.0, unit)?;
        let emissive = numbers(m, "emissiveFactor", &at, [0.0; 3], unit)?;
        let mut material = GltfMaterial {
            index: Some(i),
            name: name.clone(),
            base_color: DVec3::new(base[0], base[1], base[2]),
            alpha: base[3],
            metallic,
            roughness,
            ior: DEFAULT_IOR,
            specular_factor: 1.0,
            specular_colour: DVec3::ONE,
            emissive: DVec3::from_array(emissive),
            emissive_strength: 1.0,
            anisotropy_strength: 0.0,
            anisotropy_rotation: 0.0,
            clearcoat: crate::scene::ClearCoat::NONE,
        };
        let mut textures: Vec<&str> = TEXTURE_KEYS
            .iter()
            .copied()
            .filter(|k| pbr.contains_key(*k) || m.contains_key(*k))
            .collect();
        if let Some(mode) = string(m, "alphaMode").filter(|&a| a != "OPAQUE") {
            notices.push(format!(
                "material '{name}': alphaMode {mode} ignored: the balls are opaque"
            ));
        }
        if let Some(ext) = m.get("extensions") {
            let ext_at = format!("{at}.extensions");
            for (key, e) in object(ext, &ext_at)? {
                let e_at = format!("{ext_at}.{key}");
                let e = object(e, &e_at)?;
                match key.as_str() {
                    "KHR_materials_ior" => {
                        material.ior = number(e, "ior", &e_at, DEFAULT_IOR, (1.0, f64::MAX))?;
                    }
                    "KHR_materials_specular" => {
                        material.specular_factor = number(e, "specularFactor", &e_at, 1.0, unit)?;
                        material.specular_colour = DVec3::from_array(numbers(
                            e,
                            "specularColorFactor",
                            &e_at,
                            [1.0; 3],
                            (0.0, f64::MAX),
                        )?);
                    }
                    "KHR_materials_clearcoat" => {
                        material.clearcoat.weight = number(e, "clearcoatFactor", &e_at, 0.0, unit)?;
                        material.clearcoat.roughness =
                            number(e, "clearcoatRoughnessFactor", &e_at, 0.0, unit)?;
                    }
                    "KHR_materials_emissive_strength" => {
                        material.emissive_strength =
                            number(e, "emissiveStrength", &e_at, 1.0, (0.0, f64::MAX))?;
                    }
                    "KHR_materials_anisotropy" => {
                        material.anisotropy_strength =
                            number(e, "anisotropyStrength", &e_at, 0.0, unit)?;
                        material.anisotropy_rotation =
                            number(e, "anisotropyRotation", &e_at, 0.0, (f64::MIN, f64::MAX))?;
                        if material.anisotropy_strength > 0.0 && metallic <= 0.0 {
                            notices.push(format!(
                                "material '{name}': KHR_materials_anisotropy on a material \
                                 without metal not modelled (the anisotropy is the metal \
                                 lobe's), ignored"
                            ));
                        }
                    }
                    other => notices.push(format!(
                        "material '{name}': extension {other} not modelled, ignored"
                    )),
                }
                textures.extend(TEXTURE_KEYS.iter().copied().filter(|k| e.contains_key(*k)));
            }
        }
        if !textures.is_empty() {
            notices.push(format!(
                "material '{name}': texture(s) not read, the factors alone used: {}",
                textures.join(", ")
            ));
        }
        let ior = material.coating_ior();
        if !(IOR_RANGE.0..=IOR_RANGE.1).contains(&ior) {
            let from = if material.has_specular() {
                format!(
                    "KHR_materials_specular's F0 {:?} gives index {ior}",
                    material.dielectric_f0().to_array()
                )
            } else {
                format!("KHR_materials_ior {ior}")
            };
            return Err(format!(
                "{at}: {from}, outside the coating's [{}, {}]",
                IOR_RANGE.0, IOR_RANGE.1
            ));
        }
        out.push(material);
    }
    Ok(out)
}

/// A sphere of the file: a node drawn as a ball.
struct Sphere {
    name: String,
    centre: DVec3,
    radius: f64,
    material: Option<usize>,
}

struct Placements {
    spheres: Vec<Sphere>,
    skipped: Vec<String>,
    camera: Option<Camera>,
}

/// The local transform of node `n`: its `matrix`, or its translation, rotation and scale.
fn local_transform(n: &Map<String, Value>, at: &str) -> std::result::Result<DMat4, String> {
    let any = (f64::MIN, f64::MAX);
    if n.contains_key("matrix") {
        let m = numbers::<16>(n, "matrix", at, [0.0; 16], any)?;
        return Ok(DMat4::from_cols_array(&m));
    }
    let t = numbers(n, "translation", at, [0.0; 3], any)?;
    let r = numbers(n, "rotation", at, [0.0, 0.0, 0.0, 1.0], (-1.0, 1.0))?;
    let s = numbers(n, "scale", at, [1.0; 3], any)?;
    let q = DQuat::from_array(r);
    if (q.length() - 1.0).abs() > UNIT_TOLERANCE {
        return Err(err(
            &format!("{at}.rotation"),
            format!("{r:?} is not a unit quaternion"),
        ));
    }
    Ok(DMat4::from_scale_rotation_translation(
        DVec3::from_array(s),
        q.normalize(),
        DVec3::from_array(t),
    ))
}

/// The uniform scale of `m`'s linear part if it has no rotation, shear or unequal scale.
fn uniform_scale(m: &DMat4) -> Option<f64> {
    let s = m.x_axis.x;
    let linear = [
        m.x_axis.truncate(),
        m.y_axis.truncate(),
        m.z_axis.truncate(),
    ];
    let ok = s > 0.0
        && linear.iter().enumerate().all(|(c, col)| {
            (0..3).all(|r| {
                let expected = if r == c { s } else { 0.0 };
                (col[r] - expected).abs() <= TRANSFORM_TOLERANCE * s
            })
        })
        && m.row(3) == glam::DVec4::new(0.0, 0.0, 0.0, 1.0);
    ok.then_some(s)
}

fn placements(doc: &mut Doc) -> std::result::Result<Placements, String> {
    let root = doc.root;
    let nodes = array(root, "nodes", "the file")?;
    let meshes = array(root, "meshes", "the file")?;
    let cameras = array(root, "cameras", "the file")?;
    let scenes = array(root, "scenes", "the file")?;
    let roots: Vec<usize> = match index(root, "scene", "the file", ("scene", scenes.len()))? {
        Some(s) => scene_roots(&scenes[s], &format!("scenes[{s}]"), nodes.len())?,
        None if !scenes.is_empty() => scene_roots(&scenes[0], "scenes[0]", nodes.len())?,
        None => {
            // No scene: every node no other node lists as a child.
            let mut child = vec![false; nodes.len()];
            for (i, n) in nodes.iter().enumerate() {
                let at = format!("nodes[{i}]");
                for c in array(object(n, &at)?, "children", &at)? {
                    if let Some(c) = c.as_u64().filter(|&c| (c as usize) < nodes.len()) {
                        child[c as usize] = true;
                    }
                }
            }
            (0..nodes.len()).filter(|&i| !child[i]).collect()
        }
    };
    let mut out = Placements {
        spheres: Vec::new(),
        skipped: Vec::new(),
        camera: None,
    };
    let mut camera_node = None;
    let mut stack: Vec<(usize, DMat4, usize)> = roots
        .iter()
        .rev()
        .map(|&r| (r, DMat4::IDENTITY, 0))
        .collect();
    // Per mesh, once: its cube (bounds and material) if it is one.
    let mut mesh_bounds: Vec<Option<Cube>> = vec![None; meshes.len()];
    while let Some((i, parent, depth)) = stack.pop() {
        if depth > MAX_NODE_DEPTH {
            return Err(format!(
                "nodes[{i}]: the node hierarchy is deeper than {MAX_NODE_DEPTH} (a cycle?)"
            ));
        }
        let at = format!("nodes[{i}]");
        let n = object(&nodes[i], &at)?;
        let world = parent * local_transform(n, &at)?;
        for c in array(n, "children", &at)?.iter().rev() {
            let c = c
                .as_u64()
                .filter(|&c| (c as usize) < nodes.len())
                .ok_or_else(|| err(&format!("{at}.children"), format!("{c} is not a node")))?;
            stack.push((c as usize, world, depth + 1));
        }
        let name = string(n, "name")
            .filter(|s| !s.is_empty())
            .map_or_else(|| format!("node {i}"), str::to_string);
        if let Some(c) = index(n, "camera", &at, ("camera", cameras.len()))? {
            if camera_node.is_none() {
                camera_node = Some((c, world, name.clone()));
            }
        }
        let Some(m) = index(n, "mesh", &at, ("mesh", meshes.len()))? else {
            continue;
        };
        if mesh_bounds[m].is_none() {
            mesh_bounds[m] = Some(mesh_cube(doc, &meshes[m], m)?);
        }
        let cube = mesh_bounds[m].flatten();
        match (cube, uniform_scale(&world)) {
            (Some((lo, hi, material)), Some(s)) => out.spheres.push(Sphere {
                name,
                centre: world.transform_point3((lo + hi) * 0.5),
                radius: s * (hi - lo).max_element() * 0.5,
                material,
            }),
            _ => out.skipped.push(name),
        }
    }
    if let Some((c, world, name)) = camera_node {
        out.camera = file_camera(
            &cameras[c],
            c,
            &world,
            &name,
            &out.spheres,
            &mut doc.notices,
        )?;
    }
    Ok(out)
}

fn scene_roots(scene: &Value, at: &str, nodes: usize) -> std::result::Result<Vec<usize>, String> {
    array(object(scene, at)?, "nodes", at)?
        .iter()
        .map(|n| {
            n.as_u64()
                .map(|n| n as usize)
                .filter(|&n| n < nodes)
                .ok_or_else(|| err(&format!("{at}.nodes"), format!("{n} is not a node")))
        })
        .collect()
}

/// A mesh's bounds (least and greatest corner) and its first primitive's material, where
/// the bounds are a cube.
type Cube = Option<(DVec3, DVec3, Option<usize>)>;

/// The bounds of mesh `m` and its first primitive's material if the bounds are a cube.
fn mesh_cube(doc: &mut Doc, mesh: &Value, m: usize) -> std::result::Result<Cube, String> {
    let at = format!("meshes[{m}]");
    let mesh = object(mesh, &at)?;
    let primitives = array(mesh, "primitives", &at)?;
    let materials = array(doc.root, "materials", "the file")?.len();
    let accessors = array(doc.root, "accessors", "the file")?.len();
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    let mut material = None;
    for (p, prim) in primitives.iter().enumerate() {
        let p_at = format!("{at}.primitives[{p}]");
        let prim = object(prim, &p_at)?;
        let mat = index(prim, "material", &p_at, ("material", materials))?;
        if p == 0 {
            material = mat;
        } else if mat != material {
            doc.notices.push(format!(
                "{at}: primitive {p} has another material than primitive 0; the ball takes \
                 primitive 0's"
            ));
        }
        let attributes = object(
            prim.get("attributes")
                .ok_or_else(|| err(&p_at, "has no attributes"))?,
            &format!("{p_at}.attributes"),
        )?;
        let Some(pos) = index(attributes, "POSITION", &p_at, ("accessor", accessors))? else {
            return Ok(None);
        };
        let (a, b) = position_bounds(doc, pos)?;
        lo = lo.min(a);
        hi = hi.max(b);
    }
    if primitives.is_empty() {
        return Ok(None);
    }
    let side = hi - lo;
    let cube = side.min_element() > 0.0
        && side.max_element() - side.min_element() <= CUBE_TOLERANCE * side.max_element();
    Ok(cube.then_some((lo, hi, material)))
}

/// A position accessor's bounds: its `min` and `max`, else read from its buffer.
fn position_bounds(doc: &mut Doc, a: usize) -> std::result::Result<(DVec3, DVec3), String> {
    let at = format!("accessors[{a}]");
    let accessors = array(doc.root, "accessors", "the file")?;
    let acc = object(&accessors[a], &at)?;
    if string(acc, "type") != Some("VEC3") {
        return Err(err(&at, "a POSITION accessor that is not VEC3"));
    }
    let any = (f64::MIN, f64::MAX);
    if acc.contains_key("min") && acc.contains_key("max") {
        let lo = numbers::<3>(acc, "min", &at, [0.0; 3], any)?;
        let hi = numbers::<3>(acc, "max", &at, [0.0; 3], any)?;
        return Ok((DVec3::from_array(lo), DVec3::from_array(hi)));
    }
    // Without bounds (the specification requires them): the positions themselves.
    if acc.get("componentType").and_then(Value::as_u64) != Some(5126) {
        return Err(err(
            &at,
            "POSITION without min/max is read only as floats (componentType 5126)",
        ));
    }
    let count = number(acc, "count", &at, f64::NAN, (1.0, 1e12))?;
    if count.is_nan() {
        return Err(err(&at, "has no count"));
    }
    let views = array(doc.root, "bufferViews", "the file")?;
    let v = index(acc, "bufferView", &at, ("bufferView", views.len()))?
        .ok_or_else(|| err(&at, "POSITION without min/max or bufferView"))?;
    let view = object(&views[v], &format!("bufferViews[{v}]"))?;
    let b = view.get("buffer").and_then(Value::as_u64).unwrap_or(0) as usize;
    let view_offset = view.get("byteOffset").and_then(Value::as_u64).unwrap_or(0) as usize;
    let view_length = view.get("byteLength").and_then(Value::as_u64).unwrap_or(0) as usize;
    let stride = view.get("byteStride").and_then(Value::as_u64).unwrap_or(12) as usize;
    let offset = acc.get("byteOffset").and_then(Value::as_u64).unwrap_or(0) as usize;
    let count = count as usize;
    let end = offset + stride * (count - 1) + 12;
    if stride < 12 || end > view_length {
        return Err(err(
            &at,
            format!("{count} positions do not fit bufferView {v}'s {view_length} bytes"),
        ));
    }
    let data = buffer_bytes(doc, b)?;
    let bytes = &data[view_offset + offset..view_offset + end];
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for k in 0..count {
        let p = &bytes[k * stride..k * stride + 12];
        let f = |i: usize| f32::from_le_bytes([p[i], p[i + 1], p[i + 2], p[i + 3]]) as f64;
        let x = DVec3::new(f(0), f(4), f(8));
        if !x.is_finite() {
            return Err(err(&at, format!("position {k} is not finite")));
        }
        lo = lo.min(x);
        hi = hi.max(x);
    }
    Ok((lo, hi))
}

/// Buffer `b`'s bytes, read from its file if it has one.
fn buffer_bytes(doc: &mut Doc, b: usize) -> std::result::Result<Vec<u8>, String> {
    doc.needed.push(b);
    let buffer = &doc.buffers[b];
    match &buffer.data {
        BufferData::Bytes(d) => Ok(d.clone()),
        BufferData::File(path) => {
            let at = format!("buffers[{b}]");
            let meta = std::fs::metadata(path).map_err(|e| {
                err(
                    &at,
                    format!(
                        "'{}' cannot be read ({e}): the buffer is missing",
                        path.display()
                    ),
                )
            })?;
            if meta.len() > MAX_GLTF_BYTES {
                return Err(err(&at, format!("'{}' is too large", path.display())));
            }
            let data = std::fs::read(path)
                .map_err(|e| err(&at, format!("'{}' cannot be read: {e}", path.display())))?;
            if data.len() < buffer.byte_length {
                return Err(err(
                    &at,
                    format!(
                        "'{}' holds {} bytes, less than its byteLength {}",
                        path.display(),
                        data.len(),
                        buffer.byte_length
                    ),
                ));
            }
            Ok(data)
        }
    }
}

/// The scene's camera from the file's camera `c` at node transform `world`: a perspective
/// camera's position, direction and vertical field of view (its aspect ratio is the
/// render's); `None` (with a notice) where it cannot be carried.
fn file_camera(
    camera: &Value,
    c: usize,
    world: &DMat4,
    node: &str,
    spheres: &[Sphere],
    notices: &mut Vec<String>,
) -> std::result::Result<Option<Camera>, String> {
    let at = format!("cameras[{c}]");
    let cam = object(camera, &at)?;
    if string(cam, "type") != Some("perspective") {
        notices.push(format!(
            "camera {c} (node '{node}') is not perspective: a camera framing the balls is used"
        ));
        return Ok(None);
    }
    let p_at = format!("{at}.perspective");
    let p = object(
        cam.get("perspective")
            .ok_or_else(|| err(&at, "has no perspective"))?,
        &p_at,
    )?;
    let yfov = number(
        p,
        "yfov",
        &p_at,
        f64::NAN,
        (1e-6, std::f64::consts::PI - 1e-6),
    )?;
    if yfov.is_nan() {
        return Err(err(&p_at, "has no yfov"));
    }
    let position = world.transform_point3(DVec3::ZERO);
    let forward = world.transform_vector3(-DVec3::Z).normalize_or_zero();
    let up = world.transform_vector3(DVec3::Y).normalize_or_zero();
    // Look at the balls' centroid's depth along the view (any point on the ray will do).
    let depth = if spheres.is_empty() {
        1.0
    } else {
        let centroid = spheres.iter().map(|s| s.centre).sum::<DVec3>() / spheres.len() as f64;
        (centroid - position)
            .dot(forward)
            .max(1e-9 * (1.0 + position.length()))
    };
    let camera = Camera {
        position,
        target: position + forward * depth,
        vfov_deg: yfov.to_degrees(),
        min_aspect: None,
    };
    if let Some(problem) = camera.problem() {
        notices.push(format!(
            "camera {c} (node '{node}'): {problem}; a camera framing the balls is used"
        ));
        return Ok(None);
    }
    let level_up = forward.cross(DVec3::Y).cross(forward).normalize_or_zero();
    if up.dot(level_up) < 1.0 - 1e-6 {
        notices.push(format!(
            "camera {c} (node '{node}') is rolled: the scene's camera keeps +y up"
        ));
    }
    Ok(Some(camera))
}

/// A camera that frames `balls`: looking from the side (among a few directions around
/// `-z`, the first that hides the fewest balls' centres behind others), level, with
/// [`FRAMING_VFOV_DEG`] and every ball inside a 16:9 frame.
pub(crate) fn frame(balls: &[Ball]) -> Camera {
    let centroid = balls.iter().map(|b| b.center).sum::<DVec3>() / balls.len().max(1) as f64;
    let extent = balls
        .iter()
        .map(|b| (b.center - centroid).length() + b.radius)
        .fold(0.0, f64::max)
        .max(1e-12);
    let tan_half = (FRAMING_VFOV_DEG.to_radians() * 0.5).tan();
    // (yaw about +y, pitch) in degrees: straight on first.
    let directions = [
        (0.0, 0.0),
        (-30.0, 0.0),
        (30.0, 0.0),
        (-30.0, 20.0),
        (30.0, 20.0),
        (-60.0, 20.0),
        (60.0, 20.0),
        (0.0, 35.0),
    ];
    let mut best: Option<(usize, Camera)> = None;
    for (yaw, pitch) in directions {
        let (yaw, pitch) = (f64::to_radians(yaw), f64::to_radians(pitch));
        // The direction from the centroid to the eye.
        let back = DVec3::new(
            yaw.sin() * pitch.cos(),
            pitch.sin(),
            yaw.cos() * pitch.cos(),
        );
        let forward = -back;
        let right = forward.cross(DVec3::Y).normalize();
        let up = right.cross(forward);
        // Half extents seen face on, and the depth of the nearest ball.
        let (mut half_w, mut half_h, mut near) = (0.0f64, 0.0f64, 0.0f64);
        for b in balls {
            let d = b.center - centroid;
            half_w = half_w.max(d.dot(right).abs() + b.radius);
            half_h = half_h.max(d.dot(up).abs() + b.radius);
            near = near.max(d.dot(back) + b.radius);
        }
        let half = (half_h.max(half_w / FRAMING_ASPECT) * FRAMING_MARGIN).max(1e-12);
        let distance = near + half / tan_half;
        let camera = Camera {
            position: centroid + back * distance.max(extent * 1.01),
            target: centroid,
            vfov_deg: FRAMING_VFOV_DEG,
            // Narrower images widen the field of view so the balls stay framed.
            min_aspect: Some(FRAMING_ASPECT),
        };
        let hidden = hidden_centres(balls, camera.position);
        if best.as_ref().is_none_or(|(h, _)| hidden < *h) {
            best = Some((hidden, camera));
        }
        if hidden == 0 {
            break;
        }
    }
    best.map_or_else(Camera::reference, |(_, c)| c)
}

/// How many balls' centres another ball hides from `eye`.
fn hidden_centres(balls: &[Ball], eye: DVec3) -> usize {
    balls
        .iter()
        .enumerate()
        .filter(|(i, b)| {
            let to = b.center - eye;
            let dist = to.length();
            let d = to / dist;
            balls.iter().enumerate().any(|(j, o)| {
                if j == *i {
                    return false;
                }
                let oc = o.center - eye;
                let t = oc.dot(d);
                t > 0.0
                    && t < dist - b.radius
                    && (oc - d * t).length_squared() < o.radius * o.radius
            })
        })
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ior_from_f0_inverts_f0_from_ior() {
        for ior in [1.0, 1.33, 1.5, 2.42, 4.0] {
            let back = ior_from_f0(crate::brdf::f0_from_ior(ior));
            assert!((back - ior).abs() < 1e-12 * ior, "{ior} -> {back}");
        }
    }

    #[test]
    fn external_files_are_the_buffers_and_images_named_beside_the_file() {
        let dir = std::env::temp_dir().join(format!("sb-external-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let json = br#"{"asset": {"version": "2.0"},
            "buffers": [{"byteLength": 4, "uri": "a%20b.bin"},
                        {"byteLength": 4, "uri": "data:application/octet-stream;base64,AAAAAA=="}],
            "images": [{"uri": "t/c.png"}, {"bufferView": 0}]}"#;
        let expected = vec![
            ("buffer", dir.join("a b.bin")),
            ("image", dir.join("t/c.png")),
        ];
        let gltf = dir.join("x.gltf");
        std::fs::write(&gltf, json).unwrap();
        assert_eq!(external_files(&gltf), expected);
        let glb = dir.join("x.glb");
        std::fs::write(&glb, super::super::glb::assemble(json, Some(&[0; 4]))).unwrap();
        assert_eq!(external_files(&glb), expected);
        // Not glTF, or absent: none (the load says why).
        std::fs::write(&gltf, b"{ not json").unwrap();
        assert!(external_files(&gltf).is_empty());
        assert!(external_files(&dir.join("absent.gltf")).is_empty());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn percent_decoding_of_uris() {
        assert_eq!(percent_decode("My%20Model.bin"), "My Model.bin");
        assert_eq!(percent_decode("plain.bin"), "plain.bin");
        assert_eq!(percent_decode("bad%2"), "bad%2");
    }

    #[test]
    fn uniform_scale_refuses_rotation_and_unequal_scale() {
        let t = DMat4::from_scale_rotation_translation(
            DVec3::splat(2.0),
            DQuat::IDENTITY,
            DVec3::new(1.0, 2.0, 3.0),
        );
        assert_eq!(uniform_scale(&t), Some(2.0));
        let r = DMat4::from_rotation_y(0.3);
        assert_eq!(uniform_scale(&r), None);
        let s = DMat4::from_scale(DVec3::new(1.0, 2.0, 1.0));
        assert_eq!(uniform_scale(&s), None);
    }
}
