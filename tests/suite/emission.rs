//! Emission through the command line (docs/interop.md, "Emission"): a bad value is one
//! line and no picture. The backends' and the key's tests sit beside the scene's code
//! (src/scene/tests/emission.rs).

use crate::cli::{shadeballs, temp_dir};

/// Bad emission values: one line each, at the value's line, and `render` writes nothing.
#[test]
fn bad_emission_is_refused_in_one_line() {
    let ball = |emission: &str| {
        format!(
            "[[ball]]\ngrid = [0, 0]\nradius = 35\nroughness = 0.5\nmaterial = {{ base_color = \
             [0.5, 0.5, 0.5], emission = {emission} }}\n"
        )
    };
    let parse = |text: &str| shadeballs::scene::parse(text, std::path::Path::new("e.toml"));
    for (emission, says) in [
        ("[-1, 0, 0]", "has a negative channel"),
        ("[nan, 0, 0]", "has a NaN or infinite component"),
        ("[0, inf, 0]", "has a NaN or infinite component"),
        ("[0, 0, -inf]", "has a NaN or infinite component"),
        ("[1e300, 0, 0]", "beyond"),
        ("[1, 2]", "3"),
        ("\"bright\"", "emission"),
    ] {
        let err = parse(&ball(emission)).unwrap_err().to_string();
        assert!(err.contains(says), "{emission}: {err}");
        assert!(err.contains("line 5"), "{emission}: {err}");
        assert_eq!(err.lines().count(), 1, "{emission}: {err}");
    }
    // Through the command line: one line, no picture.
    let dir = temp_dir("glow-bad");
    let scene = dir.join("bad.toml");
    std::fs::write(&scene, ball("[-0.5, 0, 0]")).unwrap();
    let png = dir.join("out.png");
    let (ok, stderr) = shadeballs(&[
        "render",
        "--backend",
        "cpu",
        "--scene",
        scene.to_str().unwrap(),
        "--width",
        "32",
        "--height",
        "18",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(stderr.contains("negative channel"), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(!png.exists());
    let _ = std::fs::remove_dir_all(&dir);
}
