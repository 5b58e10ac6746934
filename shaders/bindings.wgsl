// bindings.wgsl: group 0, shared by the ball renderer and the table probe
// (src/gpu/bindings.rs creates the matching layout).

#define_import_path shadeballs::bindings
#import shadeballs::constants::LutParams
#import shadeballs::types::{Globals, Ball, Light, EnvUniform, MAX_LIGHTS, MU_AXIS}

@group(0) @binding(0) var<uniform> globals: Globals;
// Every ball (a storage buffer: MAX_BALLS balls of 112 bytes exceed the 64 KiB a uniform
// binding may hold). No entry point reads it since the full-screen path went (the per-ball
// quads carry their ball in the instance buffer, vs_ball); it still declares struct Ball's
// buffer layout, which src/gpu/tests/boundary.rs compares with the Rust side.
@group(0) @binding(1) var<storage, read> balls: array<Ball>;
@group(0) @binding(2) var<uniform> lights: array<Light, MAX_LIGHTS>;
// 1 - E(mu, roughness) (Tables::stored_loss) as 2x2 blocks (lut.wgsl says how).
@group(0) @binding(3) var e_table: texture_2d<f32>;
// 1 - E_avg(roughness) (Tables::stored_loss_avg) and each row's roughness (lut.wgsl).
@group(0) @binding(4) var e_avg_table: texture_2d<f32>;
// The scene's coating rows (lut::coating CoatingRows, COATING_ROW_LEN values each): a ball's
// dielectric single scattering E_F(mu) (coating_albedo in coating.wgsl). A storage buffer,
// written with the balls: it changes with the scene, not with the tables.
@group(0) @binding(5) var<storage, read> coating_rows: array<f32>;
// The set of the map's prefiltered layers the ball being shaded reads (env_specular's
// `layer_set`): 1 where the ball takes the map's sun as a light (fs_ball sets it from its vertex
// stage's counts.x, vs_ball), else 0.
var<private> env_layer_set: u32;

// Group 1: the environment map, prefiltered (src/gpu/environment.rs). Stand-ins of one
// texel when the scene has none (IBL = 0 compiles the reads out).
@group(1) @binding(0) var<uniform> env: EnvUniform;
// The map and its mip chain (Rgba16Float).
@group(1) @binding(1) var env_radiance: texture_2d<f32>;
// SPECULAR_LEVELS GGX-prefiltered layers (env_specular).
@group(1) @binding(2) var env_specular_layers: texture_2d_array<f32>;
// Irradiance, then the Kulla-Conty kernel layers (env_irradiance, env_multiple).
@group(1) @binding(3) var env_convolved: texture_2d_array<f32>;
// The split sum's bias B as 2x2 blocks (Rgba32Float, split_sum_bias).
@group(1) @binding(4) var env_split_sum: texture_2d<f32>;
@group(1) @binding(5) var env_sampler: sampler;
// The map's luminance tables for the lobe mode's map samples (lighting.wgsl
// luminance_sample; src/environment/sampler.rs LuminanceCdf::gpu_words): texels across and
// down (0 and 0 where the map has none, or the scene does not use the lobe), then the
// marginal (H values), each row's CDF (W H), each texel's probability (W H), the marginal's
// guide (guide_buckets(H) + 1) and each row's (H (guide_buckets(W) + 1)).
@group(1) @binding(6) var<storage, read> env_cdf: array<f32>;

// The bound tables' read parameters, with the pipeline's MU_AXIS for the axis: a constant,
// so the compiler keeps only that axis's arithmetic (a select over all three cost about 1 %
// of a frame with the term; docs/benchmarks.md, "The term's cost").
fn lut_params() -> LutParams {
    var p = globals.lut;
    p.mu_axis = MU_AXIS;
    return p;
}
