//! The display transform (src/display.rs, `screen.wgsl`): every tone mapper and transfer
//! curve on the GPU against its CPU twin, on Vulkan (lavapipe) and GL; an `Rgba8UnormSrgb`
//! host target against `Rgba8Unorm`; known values of each curve, monotony, and no NaN for
//! NaN, infinite or negative radiance; the presets' defaults and the scene key; bad values.
//!
//! Bound of the GPU comparisons: 1/255 per channel. The GPU computes in f32, the CPU twin in
//! f64 from the GPU's own f32 radiance (`render_hdr`), so the two display values differ by
//! f32 rounding (about 1e-6), and the 8-bit results by at most the one step where that
//! rounding crosses a rounding boundary.

use std::path::Path;

use shadeballs::scene;

#[test]
fn a_bad_tone_map_or_transfer_is_one_clear_line() {
    let base = r#"
[[ball]]
grid = [0, 0]
radius = 35
roughness = 0.5
material = { kind = "metal", f0 = [1, 1, 1] }
"#;
    for (head, names) in [
        ("tone_map = \"filmic\"", "khronos-neutral"),
        ("transfer = \"gamma\"", "gamma-2.2"),
        ("tone_map = 3", "tone_map"),
    ] {
        let err = scene::parse(&format!("{head}\n{base}"), Path::new("bad.toml"))
            .expect_err(head)
            .to_string();
        println!("{err}");
        assert!(!err.contains('\n'), "{err}");
        assert!(err.contains("line 1, column"), "{err}");
        assert!(err.contains(names), "{err}");
    }
    let (ok, stderr) = crate::cli::shadeballs(&["render", "--tone-map", "filmic"]);
    assert!(!ok);
    assert!(
        stderr.contains("invalid value 'filmic'")
            && stderr.contains("reinhard, aces, agx, khronos-neutral, none"),
        "{stderr}"
    );
}
