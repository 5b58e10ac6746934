//! Scene files: the shipped ones equal the built-in scenes; every malformed file is an
//! error that names the file, the line and the column.
use std::path::{Path, PathBuf};

use shadeballs::brdf::Geometry;
use shadeballs::scene::{self, Preset, Scene};

fn asset(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/scenes")
        .join(name)
}

const BALL: &str = "[[ball]]\ngrid = [0, 0]\nradius = 35\nroughness = 0.5\nmaterial = { kind = \"metal\", f0 = [1, 1, 1] }\n";

/// Parses `text` as `bad.toml` and returns the error message, asserting it names the file,
/// a line and a column.
fn error_of(text: &str) -> String {
    let err = scene::parse(text, Path::new("bad.toml")).expect_err("the scene should be rejected");
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
