// environment.wgsl: reading a prefiltered environment map (src/environment,
// docs/design/environment.md, "Shading under a map (image-based lighting)"). Library
// functions: no bindings; the textures, the sampler and the split-sum table are arguments.
// Each has a CPU twin of the same name in src/environment or src/lut.

#define_import_path shadeballs::environment
#import shadeballs::constants::{PI, ROUGHNESS_MIN, DIV_EPSILON}
#import shadeballs::brdf::d_ggx

// SPECULAR_LEVELS and CONVOLVED_LEVELS: layers of the prefiltered textures;
// SPLIT_SUM_SIZE: texels of the split-sum bias table along each axis; SOBOL_MASK_*,
// LOBE_LOD_BIAS, LOBE_SIN_MIN: the lobe's sequence and mip levels (lobe_sobol_point,
// lobe_lod).
// generated from the Rust constants by src/gpu/tests/boundary.rs: do not edit
const SPECULAR_LEVELS: u32 = 7u; // environment::prefilter::SPECULAR_LEVELS
const CONVOLVED_LEVELS: u32 = 9u; // environment::prefilter::CONVOLVED_LEVELS
const SPLIT_SUM_SIZE: u32 = 32u; // lut::SPLIT_SUM_SIZE
const SOBOL_MASK_0: u32 = 2863311530u; // environment::lobe::SOBOL_MASKS[0]
const SOBOL_MASK_1: u32 = 3435973836u; // environment::lobe::SOBOL_MASKS[1]
const SOBOL_MASK_2: u32 = 4042322160u; // environment::lobe::SOBOL_MASKS[2]
const SOBOL_MASK_3: u32 = 4278255360u; // environment::lobe::SOBOL_MASKS[3]
const SOBOL_MASK_4: u32 = 4294901760u; // environment::lobe::SOBOL_MASKS[4]
const LOBE_LOD_BIAS: f32 = 0.0; // environment::lobe::LOBE_LOD_BIAS
const LOBE_SIN_MIN: f32 = 0.0001; // environment::prefilter::POLE_SIN_MIN
// end of the generated constants

// (u, v) of unit direction d: u = atan2(x, -z) / 2 pi + 1/2, v = acos(y) / pi (+y up; the
// convention of src/environment).
fn direction_to_uv(d: vec3<f32>) -> vec2<f32> {
    let u = atan2(d.x, -d.z) / (2.0 * PI) + 0.5;
    let v = acos(clamp(d.y, -1.0, 1.0)) / PI;
    return vec2<f32>(u, v);
}

// The unit direction at (u, v) (direction_to_uv's inverse).
fn uv_to_direction(uv: vec2<f32>) -> vec3<f32> {
    let phi = (uv.x - 0.5) * 2.0 * PI;
    let theta = uv.y * PI;
    return vec3<f32>(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
}

// A world direction in the map's frame: turned about +y by the angle whose (cos, sin) is
// `rotation` (Environment::to_map: cos and sin of -rotation_deg).
fn env_to_map(d: vec3<f32>, rotation: vec2<f32>) -> vec3<f32> {
    let c = rotation.x;
    let s = rotation.y;
    return vec3<f32>(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
}

// The mip level specular layer `layer` is stored at, in a texture of `levels` levels
// (src/environment/prefilter.rs specular_mip says why).
fn specular_mip(layer: u32, levels: u32) -> u32 {
    let m = select(select(2u, 1u, layer == 2u), 0u, layer < 2u);
    return min(m, levels - 1u);
}

// The prefiltered specular radiance about map-frame direction r at `roughness` from layer
// set `layer_set` (0: the map; 1: the map without its sun, for the balls that take it as a light,
// src/environment/sun.rs): linear between the two layers around it, each read at its own
// mip level (Prefiltered::specular).
fn env_specular(tex: texture_2d_array<f32>, samp: sampler, r: vec3<f32>, roughness: f32, layer_set: u32) -> vec3<f32> {
    let uv = direction_to_uv(r);
    let s = clamp(roughness, 0.0, 1.0) * f32(SPECULAR_LEVELS - 1u);
    let k0 = min(u32(floor(s)), SPECULAR_LEVELS - 2u);
    let f = s - f32(k0);
    let levels = textureNumLevels(tex);
    let first = layer_set * SPECULAR_LEVELS;
    let a = textureSampleLevel(tex, samp, uv, first + k0, f32(specular_mip(k0, levels))).rgb;
    let b = textureSampleLevel(tex, samp, uv, first + k0 + 1u, f32(specular_mip(k0 + 1u, levels))).rgb;
    return mix(a, b, f);
}

// Irradiance about map-frame normal n over pi from layer set `layer_set` (Prefiltered::irradiance):
// the set's layer 0.
fn env_irradiance(tex: texture_2d_array<f32>, samp: sampler, n: vec3<f32>, layer_set: u32) -> vec3<f32> {
    return textureSampleLevel(tex, samp, direction_to_uv(n), layer_set * (CONVOLVED_LEVELS + 1u), 0.0).rgb;
}

// int (1 - E(mu_i)) mu_i L dw_i / (pi (1 - E_avg)) about map-frame normal n at `roughness`
// from layer set `layer_set` (Prefiltered::multiple): the set's layers 1..=CONVOLVED_LEVELS,
// linear between the two around it.
fn env_multiple(tex: texture_2d_array<f32>, samp: sampler, n: vec3<f32>, roughness: f32, layer_set: u32) -> vec3<f32> {
    let uv = direction_to_uv(n);
    let s = clamp(roughness, 0.0, 1.0) * f32(CONVOLVED_LEVELS - 1u);
    let k0 = min(u32(floor(s)), CONVOLVED_LEVELS - 2u);
    let f = s - f32(k0);
    let first = layer_set * (CONVOLVED_LEVELS + 1u);
    let a = textureSampleLevel(tex, samp, uv, first + k0 + 1u, 0.0).rgb;
    let b = textureSampleLevel(tex, samp, uv, first + k0 + 2u, 0.0).rgb;
    return mix(a, b, f);
}

// The direction the prefiltered specular is read along for a ball of `roughness` at
// normal n with mirror direction r: r bent towards n as the lobe widens (Lagarde & de
// Rousiers 2014, "Moving Frostbite to Physically Based Rendering", section 4.9.3: the
// lobe of a rough surface, clipped by its horizon, leans towards the normal; the split
// sum centres it on r). specular_direction in src/environment/prefilter.rs.
fn specular_direction(n: vec3<f32>, r: vec3<f32>, roughness: f32) -> vec3<f32> {
    let a = clamp(roughness, ROUGHNESS_MIN, 1.0);
    return normalize(mix(n, r, dominant_weight(a * a)));
}

// The weight of the mirror direction against the normal in specular_direction for a lobe
// of GGX alpha in [0, 1] (the same source's fit).
fn dominant_weight(alpha: f32) -> f32 {
    let smoothness = 1.0 - alpha;
    return smoothness * (sqrt(smoothness) + alpha);
}

// specular_direction for an anisotropic lobe of (alpha_t, alpha_b) along the unit tangent
// t and bitangent b, read at the level `roughness` (the lobe's equal solid angle, or the
// wider one under a clear coat, which scales both alphas alike): r's component along each axis leans
// towards n by that axis's own weight, so that the read follows the lobe along its rough
// axis (docs/design/anisotropy.md, "The split sum's direction"); equal alphas give
// specular_direction.
fn specular_direction_aniso(n: vec3<f32>, r: vec3<f32>, t: vec3<f32>, b: vec3<f32>, alpha_t: f32, alpha_b: f32, roughness: f32) -> vec3<f32> {
    let a = clamp(roughness, ROUGHNESS_MIN, 1.0);
    let alpha = a * a;
    let scale = alpha / max(sqrt(alpha_t * alpha_b), DIV_EPSILON);
    let w = dominant_weight(alpha);
    let w_t = dominant_weight(min(alpha_t * scale, 1.0));
    let w_b = dominant_weight(min(alpha_b * scale, 1.0));
    return normalize((1.0 - w + w * dot(r, n)) * n + w_t * dot(r, t) * t + w_b * dot(r, b) * b);
}

// The split sum's bias B(mu, roughness) (SplitSum::bias_at): bilinear between the texels
// of the table whose texel (i, j) holds mu = i / (N - 1), roughness = j / (N - 1), stored
// as 2x2 blocks (Rgba32Float: block (i, j) holds texels (i, j), (i + 1, j), (i, j + 1),
// (i + 1, j + 1), as the E table, lut.wgsl), so the read is one load, not four.
fn split_sum_bias(table: texture_2d<f32>, mu: f32, roughness: f32) -> f32 {
    let n = SPLIT_SUM_SIZE;
    let x = clamp(mu, 0.0, 1.0) * f32(n - 1u);
    let y = clamp(roughness, 0.0, 1.0) * f32(n - 1u);
    let i0 = min(u32(x), n - 2u);
    let j0 = min(u32(y), n - 2u);
    let fx = x - f32(i0);
    let fy = y - f32(j0);
    let q = textureLoad(table, vec2<u32>(i0, j0), 0);
    let top = q.x + (q.y - q.x) * fx;
    let bottom = q.z + (q.w - q.z) * fx;
    return top + (bottom - top) * fy;
}

// The split sum's second factor per channel, F0 A + B with A = E - B (src/lut/split_sum.rs):
// `e_o` from the E table, so F0 = 1 gives E exactly.
fn split_sum_scale(f0: vec3<f32>, e_o: f32, bias: f32) -> vec3<f32> {
    return f0 * e_o + (1.0 - f0) * bias;
}

// Lighting that follows the lobe (IBL = 2; docs/design/environment.md, "Lighting that
// follows the lobe"): the sequence of a pixel's samples, the visible normals they pick and
// the mip level each reads (the frame, the visible normals and their density: sampling.wgsl).
// CPU twins of the same names in src/environment/lobe.rs (the sequence, the level).

// PCG's hash of one 32-bit value (Jarzynski & Olano 2020, "Hash Functions for GPU
// Rendering", JCGT 9(3)).
fn lobe_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// The per-pixel scramble of the sequence (the seeds of lobe_sobol_point's Owen scrambling).
fn pixel_scramble(pixel: vec2<u32>) -> vec2<u32> {
    let a = lobe_hash(pixel.x ^ lobe_hash(pixel.y));
    return vec2<u32>(a, lobe_hash(a ^ 0x9e3779b9u));
}

// The scramble of strategy k's points in a pixel (the lobe mode's multiple importance
// sampling: 0 the visible normals', 1 the cosine's, 2 and 3 the map's texel and its
// position in it): `scramble` itself for k = 0, else each coordinate plus k times an odd
// constant, hashed, so the strategies' point sets are shifted independently.
fn strategy_scramble(scramble: vec2<u32>, k: u32) -> vec2<u32> {
    if k == 0u {
        return scramble;
    }
    return vec2<u32>(lobe_hash(scramble.x + k * 0x68bc21ebu), lobe_hash(scramble.y + k * 0x02e5be93u));
}

// Point i of the 2-D Sobol sequence in fixed point (sobol_2d in src/environment/lobe.rs): x
// the radical inverse of i, y its image under the Pascal matrix mod 2 (Sobol's second
// dimension) in five subset steps; a (0, 2)-sequence, every aligned block of 2^m indices a
// (0, m, 2)-net.
fn sobol_2d(i: u32) -> vec2<u32> {
    let x = reverseBits(i);
    var y = x;
    y ^= (y << 1u) & SOBOL_MASK_0;
    y ^= (y << 2u) & SOBOL_MASK_1;
    y ^= (y << 4u) & SOBOL_MASK_2;
    y ^= (y << 8u) & SOBOL_MASK_3;
    y ^= (y << 16u) & SOBOL_MASK_4;
    return vec2<u32>(x, y);
}

// Laine and Karras's permutation (Burley 2020, "Practical Hash-based Owen Scrambling"):
// each bit flipped by a hash of the bits below it and `seed`.
fn laine_karras_permutation(x_in: u32, seed: u32) -> u32 {
    var x = x_in + seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

// Owen's nested uniform scramble of a fixed-point coordinate (nested_uniform_scramble):
// each bit, from the top, flipped by a hash of the bits above it; nets stay nets.
fn nested_uniform_scramble(x: u32, seed: u32) -> u32 {
    return reverseBits(laine_karras_permutation(reverseBits(x), seed));
}

// Point i of the pixel's sequence in [0, 1)^2 (lobe_sobol_point): the Sobol point, each
// coordinate Owen-scrambled by its word of `scramble`; the 24 high bits (exact in f32).
fn lobe_sobol_point(i: u32, scramble: vec2<u32>) -> vec2<f32> {
    let p = sobol_2d(i);
    let x = nested_uniform_scramble(p.x, scramble.x);
    let y = nested_uniform_scramble(p.y, scramble.y);
    return vec2<f32>(f32(x >> 8u), f32(y >> 8u)) * (1.0 / 16777216.0);
}

// Sample j of a frame whose first index is `first`: point first + j of the pixel's Sobol
// sequence (lobe_frame_point), so every frame of 2^m samples is a net, and so are the
// first 2^k frames together. No branch on `first`, which comes from the uniform buffer:
// lavapipe compiles a fragment shader again at every bind when its control flow depends on
// a uniform value (tests/suite/uniform_flow.rs).
fn lobe_frame_point(first: u32, j: u32, scramble: vec2<u32>) -> vec2<f32> {
    return lobe_sobol_point(first + j, scramble);
}

// The mip level a lobe sample of density `pdf` reads among `count` samples (filtered
// importance sampling, Colbert & Krivanek 2007): 0.5 log2(Omega_s / Omega_p) + the bias,
// Omega_s = 1 / (count pdf), Omega_p the base level's texel about map-frame d
// (2 pi^2 sin(theta) / (w h), size = (w, h)), clamped to [0, max_level].
fn lobe_lod(pdf: f32, count: f32, d: vec3<f32>, size: vec2<f32>, max_level: f32) -> f32 {
    let sin_theta = max(sqrt(max(1.0 - d.y * d.y, 0.0)), LOBE_SIN_MIN);
    let omega_p = 2.0 * PI * PI * sin_theta / (size.x * size.y);
    let omega_s = 1.0 / max(count * pdf, DIV_EPSILON);
    return clamp(0.5 * log2(omega_s / omega_p) + LOBE_LOD_BIAS, 0.0, max_level);
}
