// constants.wgsl: the constants and the table-read parameters of the crate's WGSL library
// (constants, brdf, lut: shadeballs::wgsl::KULLA_CONTY). No bindings and no override
// constants: a host program puts the library before its own shader (or imports
// shadeballs::constants with naga_oil) and passes the tables and their LutParams as
// arguments.

#define_import_path shadeballs::constants

const PI: f32 = 3.14159265358979;

// lambda_smith at c = 0 is +infinity in the Rust model; WGSL has no infinity literal and
// fast-math may drop it, so the shader uses this finite stand-in (G becomes ~1e-30, not 0).
const LAMBDA_MAX: f32 = 1e30;

// The constants the Rust side shares: DIV_EPSILON guards divisions whose denominator can
// reach zero at the edge of the domain (grazing angles, E_avg -> 1, F_avg -> 1);
// ROUGHNESS_MIN is the smallest roughness the model evaluates; GAMES202_EDGE_TINT the
// GAMES202 homework's edge tint ("copper"); GEOMETRY_* the `geometry` argument of
// geometry_g and f_micro (in Geometry::ALL order); F_ADD_* the `form` argument of
// f_add_preset; FRESNEL_* the `form` argument of f_dielectric; MU_AXIS_* LutParams.mu_axis; E_AVG_READ_* LutParams.e_avg_read;
// LOSS_AVG_MIN the smallest stored 1 - E_avg the power-law read takes the logarithm of.
// generated from the Rust constants by src/gpu/tests/boundary.rs: do not edit
const DIV_EPSILON: f32 = 1e-12; // brdf::DIV_EPSILON
const ROUGHNESS_MIN: f32 = 0.02; // brdf::ROUGHNESS_MIN
const GAMES202_EDGE_TINT: vec3<f32> = vec3<f32>(0.827, 0.792, 0.678); // brdf::GAMES202_EDGE_TINT
const GEOMETRY_SCHLICK: u32 = 0u; // gpu::shaders::geometry_id(Geometry::Schlick)
const GEOMETRY_SMITH: u32 = 1u; // gpu::shaders::geometry_id(Geometry::Smith)
const GEOMETRY_SMITH_CORRELATED: u32 = 2u; // gpu::shaders::geometry_id(Geometry::SmithCorrelated)
const F_ADD_ACCURATE: u32 = 0u; // gpu::shaders::f_add_form_id(FAvgForm::Accurate)
const F_ADD_GAMES202: u32 = 1u; // gpu::shaders::f_add_form_id(FAvgForm::Games202)
const FRESNEL_EXACT: u32 = 0u; // gpu::shaders::fresnel_id(DielectricFresnel::Exact)
const FRESNEL_SCHLICK: u32 = 1u; // gpu::shaders::fresnel_id(DielectricFresnel::Schlick)
const MU_AXIS_LINEAR: u32 = 0u; // MuAxis::Linear.id()
const MU_AXIS_SQRT: u32 = 1u; // MuAxis::Sqrt.id()
const MU_AXIS_WARPED: u32 = 2u; // MuAxis::Warped.id()
const E_AVG_READ_LINEAR: u32 = 0u; // EAvgRead::Linear.id()
const E_AVG_READ_POWER_LAW: u32 = 1u; // EAvgRead::PowerLaw.id()
const LOSS_AVG_MIN: f32 = 1e-20; // lut::LOSS_AVG_MIN
// end of the generated constants

// How to address and read the tables: src/lut LutParams (Layout::lut_params), 48 bytes in a
// uniform buffer. Texel i of an axis of n texels sits where x * scale + bias = i.
struct LutParams {
    // mu axis: scale and bias; roughness axis: scale and bias (0 for a scene's rows).
    mu_scale: f32,
    mu_bias: f32,
    r_scale: f32,
    r_bias: f32,
    // Texels along mu and roughness.
    mu_size: u32,
    r_size: u32,
    // MU_AXIS_* and E_AVG_READ_*.
    mu_axis: u32,
    e_avg_read: u32,
    // Roughness of the first row.
    r_min: f32,
    padding_a: f32,
    padding_b: f32,
    padding_c: f32,
}
