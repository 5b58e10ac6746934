//! The renderer's WGSL programs and their entry points. Each program is a root module of
//! `shaders/` composed with the modules it imports under its shader defs
//! (`crate::wgsl::PROGRAMS`), at build time (`build.rs`): the ball renderer, the truth,
//! the table probe and the environment prefilter. Variants the entry points share are
//! override constants chosen per pipeline (`overrides_for`); the target's output type
//! (`OUTPUT_BITS`) is a shader def, one module per choice.

#[cfg(test)]
use crate::brdf::FAvgForm;
use crate::brdf::Geometry;
use crate::gpu::Variant;
use crate::lut::MuAxis;
#[cfg(test)]
use crate::wgsl::Program;

/// Vertex entry point of the full-screen draws (one triangle over the viewport: the
/// background, the truth's resolve).
pub(crate) const VS_MAIN: &str = "vs_main";
/// Entry point of the full-screen triangle at the far plane (the background).
pub(crate) const VS_FAR: &str = "vs_far";
/// Vertex entry point of the per-ball draw (one quad per ball over its screen-space
/// bounds).
pub(crate) const VS_BALL: &str = "vs_ball";
/// Fragment entry point of the per-ball draw: the pixel if its nearest hit is the quad's
/// ball.
pub(crate) const FS_BALL: &str = "fs_ball";
/// Fragment entry point of the background draw (the environment map behind the balls).
pub(crate) const FS_BACKGROUND: &str = "fs_background";
/// Fragment entry point of a truth ball's quad in the accumulation pass (`walk.wgsl`).
pub(crate) const FS_TRUTH: &str = "fs_truth";
/// Fragment entry point of another ball's quad in the accumulation pass (depth, zero sum).
pub(crate) const FS_TRUTH_OCCLUDER: &str = "fs_truth_occluder";
/// Fragment entry point of the truth's resolve (the mean of each truth pixel's estimates).
pub(crate) const FS_TRUTH_RESOLVE: &str = "fs_truth_resolve";
/// Fragment entry point of a ball's quad in a Monte Carlo pass (`montecarlo.wgsl`).
pub(crate) const FS_MONTECARLO: &str = "fs_montecarlo";
/// Fragment entry point of the lobe's accumulation: the sums plus this frame
/// (`accumulate.wgsl`).
pub(crate) const FS_LOBE_ACCUMULATE: &str = "fs_lobe_accumulate";
/// Fragment entry point of the lobe's resolve: the mean of the frames summed so far.
pub(crate) const FS_LOBE_RESOLVE: &str = "fs_lobe_resolve";
/// Entry point of the table probe module.
pub(crate) const PROBE_MAIN: &str = "probe_main";
/// Entry point of the probe along a scene's own rows.
pub(crate) const PROBE_ROWS: &str = "probe_rows_main";
/// Entry point of the prefilter's specular layers.
#[cfg(test)]
pub(crate) const SPECULAR_MAIN: &str = "specular_main";
/// Entry point of the prefilter's convolved layers.
#[cfg(test)]
pub(crate) const CONVOLVED_MAIN: &str = "convolved_main";

/// The entry points each program's pipelines use (a test checks that every module a
/// program imports serves one of them).
#[cfg(test)]
pub(crate) fn entry_points(program: &Program) -> &'static [&'static str] {
    match program.root {
        "shadeballs::balls" => &[VS_MAIN, VS_FAR, VS_BALL, FS_BALL, FS_BACKGROUND],
        "shadeballs::walk" => &[
            VS_BALL,
            VS_MAIN,
            FS_TRUTH,
            FS_TRUTH_OCCLUDER,
            FS_TRUTH_RESOLVE,
        ],
        "shadeballs::montecarlo" => &[VS_BALL, FS_MONTECARLO],
        "shadeballs::accumulate" => &[VS_MAIN, FS_LOBE_ACCUMULATE, FS_LOBE_RESOLVE],
        "shadeballs::probe" => &[PROBE_MAIN, PROBE_ROWS],
        "shadeballs::prefilter" => &[SPECULAR_MAIN, CONVOLVED_MAIN],
        "shadeballs::blit" => &["blit_vs", "blit_fs"],
        "shadeballs::difference" => &["difference_vs", "difference_fs"],
        _ => &[],
    }
}

/// The text the build composed for `name` (`NAME.wgsl` in the build's output).
macro_rules! composed {
    ($name:literal) => {
        include_str!(concat!(env!("OUT_DIR"), "/", $name, ".wgsl"))
    };
}

/// The text the build composed for `program`, if it is one of [`crate::wgsl::PROGRAMS`].
#[cfg(test)]
pub(crate) fn source(program: &Program) -> Option<&'static str> {
    Some(match program.name {
        "balls" => composed!("balls"),
        "balls_bits" => composed!("balls_bits"),
        "truth" => composed!("truth"),
        "truth_bits" => composed!("truth_bits"),
        "montecarlo" => composed!("montecarlo"),
        "accumulate" => composed!("accumulate"),
        "accumulate_bits" => composed!("accumulate_bits"),
        "probe" => composed!("probe"),
        "prefilter" => composed!("prefilter"),
        "blit" => composed!("blit"),
        "difference" => composed!("difference"),
        _ => return None,
    })
}

/// The ball renderer (`balls.wgsl` and its imports); `bits`: for an `Rgba32Uint` target
/// (the shader def `OUTPUT_BITS`).
pub(crate) fn balls_source(bits: bool) -> &'static str {
    if bits {
        composed!("balls_bits")
    } else {
        composed!("balls")
    }
}

/// The truth on the GPU (`walk.wgsl`: its accumulation and resolve entry points, and the
/// ball renderer's vertex stages it imports); `bits`: for an `Rgba32Uint` target.
pub(crate) fn truth_source(bits: bool) -> &'static str {
    if bits {
        composed!("truth_bits")
    } else {
        composed!("truth")
    }
}

/// The Monte Carlo of the model (`montecarlo.wgsl` and its imports: the ball renderer's
/// vertex stage, the BRDFs, the coating's functions).
pub(crate) fn montecarlo_source() -> &'static str {
    composed!("montecarlo")
}

/// The lobe's progressive image (`accumulate.wgsl`: its accumulation and resolve, and the
/// screen's vertex stage and output it imports); `bits`: for an `Rgba32Uint` target.
pub(crate) fn accumulate_source(bits: bool) -> &'static str {
    if bits {
        composed!("accumulate_bits")
    } else {
        composed!("accumulate")
    }
}

/// The environment prefilter (compute): `prefilter.wgsl` and its imports (no renderer
/// bindings).
pub(crate) fn prefilter_source() -> &'static str {
    composed!("prefilter")
}

/// The table probe: `probe.wgsl` and its imports.
pub(crate) fn probe_source() -> &'static str {
    composed!("probe")
}

/// The viewer's blit into a GL window (`blit.wgsl`).
pub(crate) fn blit_source() -> &'static str {
    composed!("blit")
}

/// The viewer's difference view (`difference.wgsl`).
pub(crate) fn difference_source() -> &'static str {
    composed!("difference")
}

/// The `geometry` argument of the WGSL `geometry_g` and `f_micro` for `g`, and the value of
/// the renderer's `GEOMETRY` override (its index in `Geometry::ALL`, matching the
/// `GEOMETRY_*` constants of `constants.wgsl`).
pub(crate) fn geometry_id(g: Geometry) -> u32 {
    Geometry::ALL.iter().position(|&x| x == g).unwrap_or(0) as u32
}

/// The `form` argument of the WGSL `f_add_preset` (`F_ADD_*` in `constants.wgsl`).
#[cfg(test)]
pub(crate) fn f_add_form_id(form: FAvgForm) -> u32 {
    match form {
        FAvgForm::Accurate => 0,
        FAvgForm::Games202 => 1,
    }
}

/// The `form` argument of the WGSL `f_dielectric` (`FRESNEL_*` in `constants.wgsl`).
pub(crate) fn fresnel_id(form: crate::brdf::DielectricFresnel) -> u32 {
    match form {
        crate::brdf::DielectricFresnel::Exact => 0,
        crate::brdf::DielectricFresnel::Schlick => 1,
    }
}

/// Pipeline-time constants for every override the modules declare without a default;
/// `mu_axis` is that of the tables the pipeline reads (`MU_AXIS`, `MuAxis::id`).
pub fn overrides(geometry: Geometry, linear: bool, mu_axis: MuAxis) -> [(&'static str, f64); 3] {
    [
        ("GEOMETRY", geometry_id(geometry) as f64),
        ("OUTPUT_LINEAR", if linear { 1.0 } else { 0.0 }),
        ("MU_AXIS", mu_axis.id() as f64),
    ]
}

/// [`overrides`] plus the scene's shader variant (`types.wgsl`): `MS_TERM`
/// ([`crate::gpu::TermMode`]), `HAS_ENVIRONMENT`, `HAS_LIGHTS`, `SUN_LIGHT`, `IBL`, `IBL_SAMPLES`, `AA`,
/// `DOMINANT_DIRECTION`, `BALL_TERM`, `HAS_CLEARCOAT`, `HAS_ANISOTROPY`, `HAS_METAL`,
/// `HAS_DIELECTRIC`, the display
/// transform (`TONE_MAP`, `TRANSFER`), and `SRGB_TARGET` for a target whose format is sRGB
/// (`srgb`: the hardware encodes, so the shader writes linear).
pub(crate) fn overrides_for(
    geometry: Geometry,
    linear: bool,
    mu_axis: MuAxis,
    variant: Variant,
    srgb: bool,
) -> [(&'static str, f64); 20] {
    let [a, b, c] = overrides(geometry, linear, mu_axis);
    let flag = |on: bool| if on { 1.0 } else { 0.0 };
    [
        a,
        b,
        c,
        ("MS_TERM", variant.term as u32 as f64),
        ("HAS_ENVIRONMENT", flag(variant.environment)),
        ("HAS_LIGHTS", flag(variant.lights)),
        ("SUN_LIGHT", flag(variant.sun)),
        ("IBL", variant.ibl as f64),
        ("IBL_SAMPLES", f64::from(variant.ibl_samples.max(1))),
        ("IBL_COSINE_SAMPLES", f64::from(variant.ibl_cosine_samples)),
        ("AA", flag(variant.aa)),
        ("DOMINANT_DIRECTION", flag(variant.dominant)),
        ("BALL_TERM", f64::from(variant.ball_term)),
        ("HAS_CLEARCOAT", flag(variant.clearcoat)),
        ("HAS_ANISOTROPY", flag(variant.anisotropy)),
        ("HAS_METAL", flag(variant.metal)),
        ("HAS_DIELECTRIC", flag(variant.dielectric)),
        ("TONE_MAP", variant.display.tone_map.code() as f64),
        ("TRANSFER", variant.display.transfer.code() as f64),
        ("SRGB_TARGET", flag(srgb)),
    ]
}
