// constants.wgsl: the constants and the table-read parameters of the crate's WGSL library
// (constants, brdf, lut: shadeballs::wgsl::KULLA_CONTY). No bindings and no override
// constants: a host program concatenates the library before its own shader and passes
// the tables and their LutParams as arguments.

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

// Geometry ids, the `geometry` argument of geometry_g and f_micro (src/brdf Geometry, in
// Geometry::ALL order).
const GEOMETRY_SCHLICK: u32 = 0u;
const GEOMETRY_SMITH: u32 = 1u;
const GEOMETRY_SMITH_CORRELATED: u32 = 2u;

// f_add forms, the `form` argument of f_add_preset (src/brdf FAvgForm).
const F_ADD_ACCURATE: u32 = 0u;
const F_ADD_GAMES202: u32 = 1u;

// Mu axes, LutParams.mu_axis (src/lut MuAxis::id).
const MU_AXIS_LINEAR: u32 = 0u;
const MU_AXIS_SQRT: u32 = 1u;
const MU_AXIS_WARPED: u32 = 2u;

// E_avg reads, LutParams.e_avg_read (src/lut EAvgRead::id).
const E_AVG_READ_LINEAR: u32 = 0u;
const E_AVG_READ_POWER_LAW: u32 = 1u;

// Smallest stored 1 - E_avg the power-law read takes the logarithm of (src/lut LOSS_AVG_MIN).
const LOSS_AVG_MIN: f32 = 1e-20;

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
    padding0: f32,
    padding1: f32,
    padding2: f32,
}
