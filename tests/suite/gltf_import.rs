//! glTF in (docs/interop.md, "glTF in"): `shadeballs import` and `render --scene
//! FILE.gltf` carry every value over exactly, place Khronos' MetalRoughSpheresNoTextures
//! where the file puts its spheres, and refuse bad files with one line, writing nothing.

use std::path::{Path, PathBuf};

use glam::DVec3;
use serde_json::{json, Value};
use shadeballs::import::{self, GltfMaterial};

use crate::cli::{shadeballs, temp_dir};

fn metal_rough_spheres() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("assets/gltf/MetalRoughSpheresNoTextures/MetalRoughSpheresNoTextures.gltf")
}

fn write_json(dir: &Path, name: &str, doc: &Value) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, serde_json::to_vec_pretty(doc).unwrap()).unwrap();
    path
}

/// A `.glb` of `json` and `bin` (the specification's layout, written here independently
/// of the library's reader).
fn glb(json: &Value, bin: &[u8]) -> Vec<u8> {
    let mut j = serde_json::to_vec(json).unwrap();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut b = bin.to_vec();
    while !b.len().is_multiple_of(4) {
        b.push(0);
    }
    let total = 12 + 8 + j.len() + 8 + b.len();
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(j.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&j);
    out.extend_from_slice(&(b.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&b);
    out
}

#[test]
fn metal_rough_spheres_places_98_balls_at_its_node_translations() {
    let path = metal_rough_spheres();
    let imported = import::load(&path).unwrap();
    assert!(imported.placed && !imported.camera_from_file);
    assert_eq!(imported.scene.balls.len(), 98);
    // Each ball carries its material's name, drawn with --labels alone: the file's own
    // placement leaves no room under its spheres.
    assert!(!imported.scene.labels);
    for (b, &k) in imported.scene.balls.iter().zip(&imported.ball_materials) {
        assert_eq!(
            b.label.map(|l| l.to_string()),
            Some(imported.materials[k].name.clone())
        );
    }
    // The expectation from the file's JSON read here: every node with a mesh below 98 (the
    // spheres; 98..102 are the text labels), at its translation (its parents have none)
    // plus the centre of accessor 0's bounds, radius half its side.
    let doc: Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    let acc = &doc["accessors"][0];
    let v3 = |v: &Value| {
        DVec3::new(
            v[0].as_f64().unwrap(),
            v[1].as_f64().unwrap(),
            v[2].as_f64().unwrap(),
        )
    };
    let (lo, hi) = (v3(&acc["min"]), v3(&acc["max"]));
    let mut expected = Vec::new();
    for node in doc["nodes"].as_array().unwrap() {
        let Some(mesh) = node["mesh"].as_u64().filter(|&m| m < 98) else {
            continue;
        };
        let t = node.get("translation").map_or(DVec3::ZERO, v3);
        let material = doc["meshes"][mesh as usize]["primitives"][0]["material"]
            .as_u64()
            .unwrap() as usize;
        expected.push((
            node["name"].as_str().unwrap().to_string(),
            t + (lo + hi) * 0.5,
            material,
        ));
    }
    assert_eq!(expected.len(), 98);
    // Two 7 x 7 grids: grey at z = 0, gold at z = -0.003.
    let zs: std::collections::BTreeSet<i64> = expected
        .iter()
        .map(|(_, c, _)| (c.z * 1e4).round() as i64)
        .collect();
    assert_eq!(zs.len(), 2);
    for (k, (b, (name, centre, material))) in imported.scene.balls.iter().zip(&expected).enumerate()
    {
        assert_eq!(imported.ball_nodes[k].as_deref(), Some(name.as_str()));
        assert_eq!(b.center, *centre, "ball {k} ({name})");
        assert_eq!(b.radius, (hi - lo).max_element() * 0.5);
        let m = &doc["materials"][*material]["pbrMetallicRoughness"];
        let base = &m["baseColorFactor"];
        assert_eq!(b.material.f0, v3(base), "{name}");
        assert_eq!(b.material.diffuse, v3(base), "{name}");
        assert_eq!(b.material.metallic, m["metallicFactor"].as_f64().unwrap());
        assert_eq!(b.roughness, m["roughnessFactor"].as_f64().unwrap());
        assert_eq!(b.material.ior, 1.5);
    }
    // The labels' meshes are no spheres, the buffer is not shipped: both said.
    let notices = imported.notices.join("\n");
    assert!(
        notices.contains("'Metal'") && notices.contains("not drawn"),
        "{notices}"
    );
    assert!(
        notices.contains("MetalRoughSpheresNoTextures.bin"),
        "{notices}"
    );
    // Every ball in the frame of the camera that frames them.
    let basis = imported.scene.camera.basis(1280, 720);
    for b in &imported.scene.balls {
        let d = b.center - basis.origin;
        let z = d.dot(basis.forward);
        let x = d.dot(basis.right) / basis.right.length_squared() / z;
        let y = d.dot(basis.up) / basis.up.length_squared() / z;
        assert!(
            z > 0.0 && x.abs() < 1.0 && y.abs() < 1.0,
            "{:?} out of frame",
            b.center
        );
    }
}

#[test]
fn metal_rough_spheres_renders_from_its_file() {
    let dir = temp_dir("gltf-render");
    let exr = dir.join("spheres.exr");
    let (ok, stderr) = shadeballs(&[
        "render",
        "--scene",
        metal_rough_spheres().to_str().unwrap(),
        "--backend",
        "cpu",
        "--width",
        "192",
        "--height",
        "108",
        "--out",
        exr.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert!(stderr.contains("notice: "), "{stderr}");
    assert!(exr.exists());
}

/// A file of four materials, one per extension, a texture and an unknown extension, no
/// mesh: a chart of four balls.
fn several_materials() -> Value {
    json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_materials_ior", "KHR_materials_specular",
                           "KHR_materials_emissive_strength", "KHR_materials_sheen"],
        "materials": [
            {"name": "orange plastic",
             "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.3, 0.1, 1.0],
                                      "metallicFactor": 0.0, "roughnessFactor": 0.35}},
            {"name": "glass-like",
             "pbrMetallicRoughness": {"baseColorFactor": [0.123456789, 0.5, 0.987654321, 1.0],
                                      "metallicFactor": 0.25, "roughnessFactor": 0.1,
                                      "baseColorTexture": {"index": 0}},
             "extensions": {"KHR_materials_ior": {"ior": 1.33}}},
            {"name": "grey specular",
             "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.2, 0.2, 1.0],
                                      "metallicFactor": 0.0, "roughnessFactor": 0.6},
             "extensions": {"KHR_materials_specular": {"specularFactor": 0.5,
                                                       "specularColorFactor": [1.5, 1.5, 1.5]},
                            "KHR_materials_ior": {"ior": 1.6}}},
            {"name": "lamp",
             "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 1.0],
                                      "metallicFactor": 1.0, "roughnessFactor": 0.9},
             "emissiveFactor": [1.0, 0.5, 0.25],
             "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0},
                            "KHR_materials_sheen": {}}}
        ]
    })
}

#[test]
fn import_carries_every_value_over_exactly() {
    let dir = temp_dir("gltf-import");
    let file = write_json(&dir, "materials.gltf", &several_materials());
    let out = dir.join("materials.toml");
    let (ok, stderr) = shadeballs(&[
        "import",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    for named in ["baseColorTexture", "KHR_materials_sheen", "specularFactor"] {
        assert!(stderr.contains(named), "no notice of {named}: {stderr}");
    }
    // Emission is drawn now: no notice of it.
    assert!(!stderr.contains("emission"), "{stderr}");
    let text = std::fs::read_to_string(&out).unwrap();
    for name in ["orange plastic", "glass-like", "grey specular", "lamp"] {
        assert!(text.contains(&format!("# Material '{name}'")), "{text}");
    }
    let imported = import::load(&file).unwrap();
    assert!(!imported.placed);
    let m: &[GltfMaterial] = &imported.materials;
    // The file's values, as read by the import.
    assert_eq!(m[0].base_color, DVec3::new(0.8, 0.3, 0.1));
    assert_eq!(m[1].ior, 1.33);
    assert_eq!(
        (m[2].specular_factor, m[2].specular_colour),
        (0.5, DVec3::splat(1.5))
    );
    assert_eq!(m[3].emission(), DVec3::new(4.0, 2.0, 1.0));
    // The scene file loads back to the same balls, value for value; the render reads the
    // same scene from the glTF file directly.
    let scene = shadeballs::scene::load(&out).unwrap();
    assert_eq!(scene.balls, imported.scene.balls);
    for (b, g) in scene.balls.iter().zip(m) {
        assert_eq!(b.material.f0, g.base_color, "{}", g.name);
        assert_eq!(b.material.diffuse, g.base_color, "{}", g.name);
        assert_eq!(b.material.metallic, g.metallic, "{}", g.name);
        assert_eq!(b.roughness, g.roughness, "{}", g.name);
    }
    assert_eq!(scene.balls[0].material.ior, 1.5);
    assert_eq!(scene.balls[1].material.ior, 1.33);
    // emissiveFactor x emissiveStrength, the `emission` key; none elsewhere.
    assert_eq!(scene.balls[3].material.emission, DVec3::new(4.0, 2.0, 1.0));
    assert!(scene.balls[..3]
        .iter()
        .all(|b| b.material.emission == DVec3::ZERO));
    // KHR_materials_specular: F0 = min(((1.6 - 1) / 2.6)^2 x 1.5, 1) x 0.5, the coating's.
    let f0 = ((0.6f64 / 2.6).powi(2) * 1.5).min(1.0) * 0.5;
    let coating_f0 = shadeballs::brdf::f0_from_ior(scene.balls[2].material.ior);
    assert!(
        (coating_f0 - f0).abs() <= 1e-15,
        "{coating_f0} against {f0}"
    );
}

/// An RGBA8 PNG's pixels and width.
fn png(path: &Path) -> (Vec<u8>, u32) {
    let img = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8();
    (img.as_raw().clone(), img.width())
}

/// Each ball is labelled with its material's name: in the scene file `import` writes
/// (`label = "..."`, labels on), and in the picture `render --scene FILE.gltf` draws, whose
/// pixels change with `--no-labels` inside the names' rooms under the balls (each room
/// some), nowhere else but the caption's.
#[test]
fn material_names_are_the_balls_labels() {
    let dir = temp_dir("gltf-labels");
    let file = write_json(&dir, "materials.gltf", &several_materials());
    let names = ["orange plastic", "glass-like", "grey specular", "lamp"];
    let out = dir.join("materials.toml");
    let (ok, stderr) = shadeballs(&[
        "import",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("\nlabels = true\n"), "{text}");
    for name in names {
        assert!(text.contains(&format!("\nlabel = \"{name}\"\n")), "{text}");
    }
    let scene = shadeballs::scene::load(&out).unwrap();
    let labels: Vec<&str> = scene
        .balls
        .iter()
        .map(|b| b.label.as_ref().map_or("", |l| l.as_str()))
        .collect();
    assert_eq!(labels, names);
    // The smallest font drawn (8 px) at a 360-pixel height.
    let (w, h) = (640u32, 360u32);
    let layout = shadeballs::labels::layout(&scene, w, h);
    let mut texts: Vec<&str> = layout.balls.iter().map(|l| l.text.as_str()).collect();
    texts.sort();
    let mut sorted = names.to_vec();
    sorted.sort();
    assert_eq!(texts, sorted, "one label under each ball");
    assert!(layout.columns.is_empty(), "{:?}", layout.columns);
    let size = ["--width", &w.to_string(), "--height", &h.to_string()].map(String::from);
    let mut flags: Vec<&str> = vec!["render", "--scene", file.to_str().unwrap()];
    flags.extend(["--backend", "cpu", "--spp", "1"]);
    flags.extend(size.iter().map(String::as_str));
    let on = dir.join("on.png");
    let off = dir.join("off.png");
    let (ok, stderr) = shadeballs(&[&flags[..], &["--out", on.to_str().unwrap()]].concat());
    assert!(ok, "{stderr}");
    let (ok, stderr) =
        shadeballs(&[&flags[..], &["--no-labels", "--out", off.to_str().unwrap()]].concat());
    assert!(ok, "{stderr}");
    let ((a, aw), (b, _)) = (png(&on), png(&off));
    assert_eq!(aw, w);
    let mut per_ball = vec![0usize; layout.balls.len()];
    let mut elsewhere = 0;
    for (i, (p, q)) in a.chunks_exact(4).zip(b.chunks_exact(4)).enumerate() {
        if p == q {
            continue;
        }
        let (x, y) = ((i as u32 % w) as f32 + 0.5, (i as u32 / w) as f32 + 0.5);
        let at = |r: &shadeballs::labels::Rect| x > r.x0 && x < r.x1 && y > r.y0 && y < r.y1;
        match layout.balls.iter().position(|l| at(&l.room)) {
            Some(k) => per_ball[k] += 1,
            None => {
                assert!(
                    layout.iter().any(|l| at(&l.room)),
                    "({x}, {y}) changed outside the rooms"
                );
                elsewhere += 1;
            }
        }
    }
    println!("changed pixels per name {per_ball:?}, in other labels {elsewhere}");
    assert!(per_ball.iter().all(|&n| n >= 20), "{per_ball:?}");
}

#[test]
fn a_glb_places_its_spheres_from_positions_in_its_bin_chunk() {
    // One mesh of eight corners of a cube of side 2 (no min/max: read from the BIN chunk),
    // drawn twice: translated, and scaled by 3.
    let corners: Vec<u8> = (0..8)
        .flat_map(|k| {
            [k & 1, (k >> 1) & 1, (k >> 2) & 1].map(|b| if b == 1 { 1.0f32 } else { -1.0 })
        })
        .flat_map(f32::to_le_bytes)
        .collect();
    let doc = json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": corners.len()}],
        "bufferViews": [{"buffer": 0, "byteLength": corners.len()}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3"}],
        "materials": [{"name": "gold", "pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.8, 0.3, 1.0]}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
        "nodes": [{"mesh": 0, "translation": [5.0, 0.0, -2.0], "name": "a"},
                  {"mesh": 0, "scale": [3.0, 3.0, 3.0], "name": "b"},
                  {"mesh": 0, "scale": [1.0, 2.0, 1.0], "name": "squashed"}],
        "scenes": [{"nodes": [0, 1, 2]}]
    });
    let dir = temp_dir("gltf-glb");
    let path = dir.join("cube.glb");
    std::fs::write(&path, glb(&doc, &corners)).unwrap();
    let imported = import::load(&path).unwrap();
    let balls = &imported.scene.balls;
    assert_eq!(balls.len(), 2, "{:?}", imported.notices);
    assert_eq!(
        (balls[0].center, balls[0].radius),
        (DVec3::new(5.0, 0.0, -2.0), 1.0)
    );
    assert_eq!((balls[1].center, balls[1].radius), (DVec3::ZERO, 3.0));
    // glTF's defaults: metallic 1, roughness 1.
    assert_eq!((balls[0].material.metallic, balls[0].roughness), (1.0, 1.0));
    assert!(
        imported.notices.iter().any(|n| n.contains("'squashed'")),
        "{:?}",
        imported.notices
    );
}

#[test]
fn bad_gltf_files_fail_with_one_line_and_write_nothing() {
    let dir = temp_dir("gltf-bad");
    let mut range = several_materials();
    range["materials"][0]["pbrMetallicRoughness"]["metallicFactor"] = json!(1.5);
    let mut colour = several_materials();
    colour["materials"][1]["pbrMetallicRoughness"]["baseColorFactor"] = json!([0.5, 0.5, 2.0, 1.0]);
    let mut ior = several_materials();
    ior["materials"][1]["extensions"]["KHR_materials_ior"]["ior"] = json!(5.0);
    let mut required = several_materials();
    required["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
    let missing_buffer = json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": 96, "uri": "absent.bin"}],
        "bufferViews": [{"buffer": 0, "byteLength": 96}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}]
    });
    let mut no_buffer = missing_buffer.clone();
    no_buffer["bufferViews"][0]["buffer"] = json!(3);
    let good_glb = glb(&several_materials(), &[0; 8]);
    let mut broken_glb = good_glb.clone();
    let bin_header = good_glb.len() - 8 - 8;
    broken_glb[bin_header..bin_header + 4].copy_from_slice(&4096u32.to_le_bytes());
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "malformed.gltf",
            b"{\"asset\": {\"version\": \"2.0\"}, ".to_vec(),
            "not glTF JSON",
        ),
        (
            "range.gltf",
            serde_json::to_vec(&range).unwrap(),
            "metallicFactor: 1.5 is outside [0, 1]",
        ),
        (
            "colour.gltf",
            serde_json::to_vec(&colour).unwrap(),
            "baseColorFactor[2]: 2 is outside",
        ),
        (
            "ior.gltf",
            serde_json::to_vec(&ior).unwrap(),
            "outside the coating's [1, 4]",
        ),
        (
            "required.gltf",
            serde_json::to_vec(&required).unwrap(),
            "requires extension KHR_draco_mesh_compression",
        ),
        (
            "missing.gltf",
            serde_json::to_vec(&missing_buffer).unwrap(),
            "absent.bin",
        ),
        (
            "nobuffer.gltf",
            serde_json::to_vec(&no_buffer).unwrap(),
            "refers to buffer 3",
        ),
        ("broken.glb", broken_glb, ".glb chunk 1"),
        (
            "truncated.glb",
            good_glb[..good_glb.len() - 4].to_vec(),
            "header says",
        ),
    ];
    // The good .glb imports (the check above breaks only what it says).
    std::fs::write(dir.join("good.glb"), &good_glb).unwrap();
    assert!(import::load(&dir.join("good.glb")).is_ok());
    for (name, bytes, expected) in cases {
        let file = dir.join(name);
        std::fs::write(&file, bytes).unwrap();
        let out = dir.join(format!("{name}.toml"));
        let png = dir.join(format!("{name}.png"));
        let (ok, stderr) = shadeballs(&[
            "import",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(!ok, "{name} imported");
        assert!(stderr.contains(expected), "{name}: {stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{name}: {stderr}");
        assert!(!out.exists(), "{name}: a scene was written");
        let (ok, stderr) = shadeballs(&[
            "render",
            "--scene",
            file.to_str().unwrap(),
            "--backend",
            "cpu",
            "--width",
            "32",
            "--height",
            "18",
            "--out",
            png.to_str().unwrap(),
        ]);
        assert!(!ok && stderr.contains(expected), "{name}: {stderr}");
        assert!(!png.exists(), "{name}: a picture was written");
    }
    // Nothing else was left in the folder (no temporary file).
    let left: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !(n.ends_with(".gltf") || n.ends_with(".glb")))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}
