//! The clear coat (docs/design/coat.md): its scene keys, the GPU against its CPU twin, the
//! white furnace with the engines' forms as negative controls, the walk's laws, and every
//! form against the truth.

/// A bad `--coat-form` is one line and writes nothing; the flag is read; both Monte Carlo
/// backends shade a coat.
#[test]
fn clearcoat_forms_and_backends_on_the_command_line() {
    let dir = crate::cli::temp_dir("clearcoat-refused");
    let png = dir.join("x.png");
    let png = png.to_str().unwrap();
    let scene = crate::cli_render::scene_file("clearcoat.toml");
    let (ok, stderr) = crate::cli::shadeballs(&[
        "render",
        "--scene",
        &scene,
        "--out",
        png,
        "--width",
        "64",
        "--height",
        "36",
        "--coat-form",
        "matte",
    ]);
    assert!(!ok, "--coat-form matte should fail");
    assert!(stderr.contains("coat form"), "{stderr}");
    assert!(
        !stderr.contains("panicked") && stderr.trim().lines().count() == 1,
        "{stderr}"
    );
    assert!(
        !std::path::Path::new(png).exists(),
        "--coat-form matte wrote {png}"
    );
    let mut all = vec![
        "render", "--scene", &scene, "--out", png, "--width", "64", "--height", "36",
    ];
    all.extend(["--coat-form", "gltf"]);
    let (ok, stderr) = crate::cli::shadeballs(&all);
    assert!(ok && std::path::Path::new(png).exists(), "{stderr}");
    // The Monte Carlo estimators shade a coat, the CPU's and the GPU's.
    for backend in ["montecarlo-cpu", "montecarlo"] {
        std::fs::remove_file(png).unwrap();
        let mut all = vec![
            "render", "--scene", &scene, "--out", png, "--width", "32", "--height", "18",
        ];
        all.extend(["--backend", backend, "--spp", "2"]);
        let (ok, stderr) = crate::cli::shadeballs(&all);
        assert!(
            ok && std::path::Path::new(png).exists(),
            "{backend}: {stderr}"
        );
    }
}

/// glTF's `KHR_materials_clearcoat`: `clearcoatFactor` and `clearcoatRoughnessFactor` carried
/// into the scene (and through its file exactly), its textures named in a notice.
#[test]
fn gltf_clearcoat_imports() {
    let dir = crate::cli::temp_dir("gltf-clearcoat");
    let doc = serde_json::json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_materials_clearcoat"],
        "materials": [
            {"name": "car paint",
             "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.05, 0.02, 1.0],
                                      "metallicFactor": 0.3, "roughnessFactor": 0.5},
             "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 0.75,
                                                        "clearcoatRoughnessFactor": 0.125,
                                                        "clearcoatTexture": {"index": 0}}}},
            {"name": "bare",
             "pbrMetallicRoughness": {"metallicFactor": 1.0, "roughnessFactor": 0.3},
             "extensions": {"KHR_materials_clearcoat": {}}}
        ]
    });
    let file = dir.join("coat.gltf");
    std::fs::write(&file, serde_json::to_string(&doc).unwrap()).unwrap();
    let out = dir.join("coat.toml");
    let (ok, stderr) = crate::cli::shadeballs(&[
        "import",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert!(stderr.contains("clearcoatTexture"), "no notice: {stderr}");
    assert!(
        !stderr.contains("KHR_materials_clearcoat not modelled"),
        "{stderr}"
    );
    let scene = shadeballs::scene::load(&out).unwrap();
    let c = scene.balls[0].material.clearcoat;
    assert_eq!((c.weight, c.roughness, c.ior), (0.75, 0.125, 1.5));
    assert!(
        !scene.balls[1].material.clearcoat.is_on(),
        "factor 0 by default"
    );
    let imported = shadeballs::import::load(&file).unwrap();
    assert_eq!(scene.balls, imported.scene.balls);
}
