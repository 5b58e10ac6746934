//! The WGSL sources and how they are combined. naga has no `#include`, so each module is
//! the concatenation of the role files in one fixed order: the library (constants, BRDF
//! terms, table reads: [`crate::wgsl::KULLA_CONTY`], no bindings), the renderer's types and
//! bindings, then the entry points.

use crate::brdf::{FAvgForm, Geometry};
use crate::gpu::Variant;
use crate::lut::MuAxis;

/// The library's files (`crate::wgsl::KULLA_CONTY` is their concatenation), then the
/// renderer's types and bindings: every module starts with these, by file name.
pub const COMMON: [(&str, &str); 6] = [
    (
        "constants.wgsl",
        include_str!("../../shaders/constants.wgsl"),
    ),
    ("brdf.wgsl", include_str!("../../shaders/brdf.wgsl")),
    ("lut.wgsl", include_str!("../../shaders/lut.wgsl")),
    (
        "environment.wgsl",
        include_str!("../../shaders/environment.wgsl"),
    ),
    ("types.wgsl", include_str!("../../shaders/types.wgsl")),
    ("bindings.wgsl", include_str!("../../shaders/bindings.wgsl")),
];
const LIGHTING: &str = include_str!("../../shaders/lighting.wgsl");
const BALLS: &str = include_str!("../../shaders/balls.wgsl");
const WALK: &str = include_str!("../../shaders/walk.wgsl");
const PROBE: &str = include_str!("../../shaders/probe.wgsl");
const PREFILTER: &str = include_str!("../../shaders/prefilter.wgsl");

/// Vertex entry point of the ball renderer module's full-screen draw (one triangle over
/// the viewport).
pub const VS_MAIN: &str = "vs_main";
/// Fragment entry point of the full-screen draw: every pixel's radiance, background included.
pub const FS_MAIN: &str = "fs_main";
/// Vertex entry point of the per-ball draw (one quad per ball over its screen-space bounds).
pub const VS_BALL: &str = "vs_ball";
/// Fragment entry point of the per-ball draw: the pixel if its nearest hit is the quad's ball.
pub const FS_BALL: &str = "fs_ball";
/// `FS_MAIN` for an `Rgba32Uint` target: the bits of linear radiance (`output_bits`).
pub const FS_MAIN_BITS: &str = "fs_main_bits";
/// `FS_BALL` for an `Rgba32Uint` target: the bits of linear radiance (`output_bits`).
pub const FS_BALL_BITS: &str = "fs_ball_bits";
/// Fragment entry point of the background draw (the environment map behind the balls).
pub const FS_BACKGROUND: &str = "fs_background";
/// `FS_BACKGROUND` for an `Rgba32Uint` target.
pub const FS_BACKGROUND_BITS: &str = "fs_background_bits";
/// Fragment entry point of a truth ball's quad in the accumulation pass (`walk.wgsl`).
pub const FS_TRUTH: &str = "fs_truth";
/// Fragment entry point of another ball's quad in the accumulation pass (depth, zero sum).
pub const FS_TRUTH_OCCLUDER: &str = "fs_truth_occluder";
/// Fragment entry point of the truth's resolve (the mean of each truth pixel's estimates).
pub const FS_TRUTH_RESOLVE: &str = "fs_truth_resolve";
/// `FS_TRUTH_RESOLVE` for an `Rgba32Uint` target.
pub const FS_TRUTH_RESOLVE_BITS: &str = "fs_truth_resolve_bits";
/// Entry point of the table probe module.
pub const PROBE_MAIN: &str = "probe_main";
/// Entry point of the probe along a scene's own rows.
pub const PROBE_ROWS: &str = "probe_rows_main";

fn concat(parts: &[&str]) -> String {
    let common = COMMON.iter().map(|(_, src)| *src);
    common
        .chain(parts.iter().copied())
        .collect::<Vec<_>>()
        .join("\n")
}

/// The ball renderer: common files, `lighting.wgsl`, `balls.wgsl`, `walk.wgsl` (the truth
/// on the GPU: its accumulation and resolve entry points).
pub fn balls_source() -> String {
    concat(&[LIGHTING, BALLS, WALK])
}

/// The environment prefilter (compute): `constants.wgsl`, `brdf.wgsl`, `environment.wgsl`,
/// `prefilter.wgsl` (no renderer bindings).
pub fn prefilter_source() -> String {
    [COMMON[0].1, COMMON[1].1, COMMON[3].1, PREFILTER].join("\n")
}

/// The table probe: common files, `probe.wgsl`.
pub fn probe_source() -> String {
    concat(&[PROBE])
}

/// The `geometry` argument of the WGSL `geometry_g` and `f_micro` for `g`, and the value of
/// the renderer's `GEOMETRY` override (its index in `Geometry::ALL`, matching the
/// `GEOMETRY_*` constants of `constants.wgsl`).
pub fn geometry_id(g: Geometry) -> u32 {
    Geometry::ALL.iter().position(|&x| x == g).unwrap_or(0) as u32
}

/// The `form` argument of the WGSL `f_add_preset` (`F_ADD_*` in `constants.wgsl`).
pub fn f_add_form_id(form: FAvgForm) -> u32 {
    match form {
        FAvgForm::Accurate => 0,
        FAvgForm::Games202 => 1,
    }
}

/// Pipeline-time constants for every override the modules declare without a default;
/// `mu_axis` is that of the tables the pipeline reads (`MU_AXIS`, [`MuAxis::id`]).
pub fn overrides(geometry: Geometry, linear: bool, mu_axis: MuAxis) -> [(&'static str, f64); 3] {
    [
        ("GEOMETRY", geometry_id(geometry) as f64),
        ("OUTPUT_LINEAR", if linear { 1.0 } else { 0.0 }),
        ("MU_AXIS", mu_axis.id() as f64),
    ]
}

/// [`overrides`] plus the scene's shader variant (`types.wgsl`): `MS_TERM`
/// ([`crate::gpu::TermMode`]), `HAS_ENVIRONMENT`, `HAS_LIGHTS`, `IBL`, `AA`.
pub fn overrides_for(
    geometry: Geometry,
    linear: bool,
    mu_axis: MuAxis,
    variant: Variant,
) -> [(&'static str, f64); 8] {
    let [a, b, c] = overrides(geometry, linear, mu_axis);
    let flag = |on: bool| if on { 1.0 } else { 0.0 };
    [
        a,
        b,
        c,
        ("MS_TERM", variant.term as u32 as f64),
        ("HAS_ENVIRONMENT", flag(variant.environment)),
        ("HAS_LIGHTS", flag(variant.lights)),
        ("IBL", variant.ibl as f64),
        ("AA", flag(variant.aa)),
    ]
}
