// types.wgsl: constants, override constants and the uniform layouts shared by every
// entry point. Concatenated first (src/gpu/shaders.rs); naga has no #include.

const PI: f32 = 3.14159265358979;

// Guard for divisions whose denominator can reach zero at the edge of the domain (grazing
// angles, E_avg -> 1, F_avg -> 1): src/brdf DIV_EPSILON, representable in f32.
const DIV_EPSILON: f32 = 1e-12;

// Smallest roughness the model evaluates (src/brdf ROUGHNESS_MIN).
const ROUGHNESS_MIN: f32 = 0.02;

// lambda_smith at c = 0 is +infinity in the Rust model; WGSL has no infinity literal and
// fast-math may drop it, so the shader uses this finite stand-in (G becomes ~1e-30, not 0).
const LAMBDA_MAX: f32 = 1e30;

// The GAMES202 homework's edge tint ("copper"), src/brdf GAMES202_EDGE_TINT.
const GAMES202_EDGE_TINT: vec3<f32> = vec3<f32>(0.827, 0.792, 0.678);

// Sizes of the uniform arrays (src/scene MAX_BALLS, MAX_LIGHTS).
const MAX_BALLS: u32 = 256u;
const MAX_LIGHTS: u32 = 16u;

// Values of the GEOMETRY override (src/brdf Geometry, in Geometry::ALL order).
const GEOMETRY_SCHLICK: u32 = 0u;
const GEOMETRY_SMITH: u32 = 1u;
const GEOMETRY_SMITH_CORRELATED: u32 = 2u;

// Values of the F_ADD_FORM override (src/brdf FAvgForm).
const F_ADD_ACCURATE: u32 = 0u;
const F_ADD_GAMES202: u32 = 1u;

// Values of MU_AXIS (src/lut MuAxis::id).
const MU_AXIS_LINEAR: u32 = 0u;
const MU_AXIS_SQRT: u32 = 1u;
const MU_AXIS_WARPED: u32 = 2u;

// Values of globals.lut_dims.w (src/lut EAvgRead).
const E_AVG_READ_LINEAR: u32 = 0u;
const E_AVG_READ_POWER_LAW: u32 = 1u;

// Smallest stored 1 - E_avg the power-law read takes the logarithm of (src/lut LOSS_AVG_MIN).
const LOSS_AVG_MIN: f32 = 1e-20;

// Pipeline-time choices (PipelineCompilationOptions::constants), folded by the compiler:
// no uniform branches on them.
override GEOMETRY: u32;
override F_ADD_FORM: u32;
// The mu axis of the tables the pipeline reads (MU_AXIS_*): a pipeline-time choice, so the
// read computes its own axis only (a select over all three cost about 1% of a frame with the
// term, README "The term's cost").
override MU_AXIS: u32;
// 1: write linear radiance (float target, for EXR); 0: tone-mapped display value.
override OUTPUT_LINEAR: u32;
// The multiple-scattering term (src/scene/plan.rs TermMode): 0: compiled out (no E read
// for it), the same image as every flag off; 1 (default): a branch on each ball's flag (one
// pipeline for every ball); 2: compiled in for every ball the pipeline draws (the planned
// renderer draws the balls with the term with it, those without with 0).
override MS_TERM: u32 = 1u;
// 1 (default): the uniform environment's part of the shading; 0: compiled out (the scene
// has none). Likewise the directional lights' loop.
override HAS_ENVIRONMENT: u32 = 1u;
override HAS_LIGHTS: u32 = 1u;

// Mirrors src/gpu/uniforms.rs Globals (every member a vec4 for one std140 layout).
struct Globals {
    cam_origin: vec4<f32>,
    cam_forward: vec4<f32>,
    // Right and up scaled by tan(vfov / 2) (times aspect for right): src/scene CameraBasis.
    cam_right: vec4<f32>,
    cam_up: vec4<f32>,
    // rgb: environment radiance (also the background); w: exposure.
    environment: vec4<f32>,
    // width, height (pixels), unused, unused.
    size: vec4<f32>,
    // ball count, light count, unused, unused.
    counts: vec4<u32>,
    // E table read: mu scale, mu bias, roughness scale, roughness bias (Layout::scale_bias).
    lut: vec4<f32>,
    // mu_size, r_size, unused (the mu axis is the MU_AXIS override), E_avg read id.
    lut_dims: vec4<u32>,
    // x: r_min, the roughness of the first row (Layout::r_axis); yzw unused.
    lut_r: vec4<f32>,
}

struct Ball {
    // xyz: centre; w: radius.
    center_radius: vec4<f32>,
    // xyz: linear F0; w: roughness (raw; the BRDF functions clamp it).
    f0_roughness: vec4<f32>,
    // xyz: linear diffuse albedo (dielectric base; 0 for metals); w: 1 with the
    // multiple-scattering term, 0 without.
    diffuse_ms: vec4<f32>,
    // Constant over the ball, formed on the CPU (src/gpu/uniforms.rs balls): xyz: f_add of
    // the preset (f_add_accurate or f_add_games202 of E_avg); w: f_ms_norm of 1 - E_avg at
    // the ball's roughness as read: lut_loss_avg of the 2-D table, or its own row's.
    f_add_ms_norm: vec4<f32>,
    // The roughness half of an E read at the ball's roughness (Tables::lut_row; lut_loss_row
    // in lut.wgsl): first row index, weight of the next row, alpha, unused.
    lut_row: vec4<f32>,
}

struct Light {
    // xyz: unit direction towards the light.
    direction: vec4<f32>,
    // rgb: radiance.
    radiance: vec4<f32>,
}
