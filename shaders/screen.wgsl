// screen.wgsl: what the ball renderer (balls.wgsl) and the truth (walk.wgsl) share on
// screen: the vertex stages (the full-screen triangle, the per-ball quads), the primary
// rays, the ray-sphere intersection, the depth of a hit, and the colour a fragment writes
// (the display transform, or the bits of linear radiance under the shader def OUTPUT_BITS).
// The display transform's functions mirror src/display.rs name for name.

#define_import_path shadeballs::screen
#import shadeballs::constants::DIV_EPSILON
#import shadeballs::types::{BallIn, BallOut, ball_out, ball_of, MAX_BALLS, MAX_LIGHTS, OUTPUT_LINEAR, TONE_MAP, TRANSFER, SRGB_TARGET, SUN_LIGHT, SUN_POINTS}
#import shadeballs::types::{TONE_MAP_ACES, TONE_MAP_AGX, TONE_MAP_KHRONOS_NEUTRAL, TONE_MAP_REINHARD, TRANSFER_SRGB}
#import shadeballs::bindings::globals

struct VsOut {
    @builtin(position) position: vec4<f32>,
    // globals.counts.xy (balls, lights), passed through the vertex stage: see loop_counts.
    @location(1) @interpolate(flat) counts: vec2<u32>,
}

// The ball and light counts the fragment loops run to, clamped to the array sizes. Read in
// the vertex stage and handed to the fragment stage as a flat varying, never read from the
// uniform buffer by the fragment stage itself: lavapipe (Mesa 22.3) inlines uniform-buffer
// values that decide a loop's exit into the fragment shader and compiles that shader again
// each time the pipeline is bound (about 2 ms a bind with Mesa's disk cache answering), so
// every frame that bound the term's pipeline paid a compile (docs/benchmarks.md, "The term's cost").
fn loop_counts() -> vec2<u32> {
    return min(globals.counts.xy, vec2<u32>(MAX_BALLS, MAX_LIGHTS));
}

// The triangle (-1,-1), (3,-1), (-1,3) covers the whole viewport.
@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> VsOut {
    let x = f32((index << 1u) & 2u) * 2.0 - 1.0;
    let y = f32(index & 2u) * 2.0 - 1.0;
    var out: VsOut;
    out.position = vec4<f32>(x, y, 0.0, 1.0);
    out.counts = loop_counts();
    return out;
}

// The same triangle at the far plane (depth 1): the background, drawn after the balls with
// a depth test, shades only the pixels no ball wrote (src/gpu/pipelines.rs).
@vertex
fn vs_far(@builtin(vertex_index) index: u32) -> VsOut {
    let x = f32((index << 1u) & 2u) * 2.0 - 1.0;
    let y = f32(index & 2u) * 2.0 - 1.0;
    var out: VsOut;
    out.position = vec4<f32>(x, y, 1.0, 1.0);
    out.counts = loop_counts();
    return out;
}

// Nearest positive distance along unit direction d from o to sphere (c, r), or -1.
// The discriminant is r^2 - |oc - (oc.d) d|^2 (no cancellation of two large squares), and
// the near root is c / q with q = -b + sqrt(disc) (Press et al., Numerical Recipes 5.6;
// Haines et al., Ray Tracing Gems, ch. 7).
fn intersect_sphere(o: vec3<f32>, d: vec3<f32>, center: vec3<f32>, r: f32) -> f32 {
    let oc = o - center;
    let b = dot(oc, d);
    let perp = oc - b * d;
    let disc = r * r - dot(perp, perp);
    if disc < 0.0 {
        return -1.0;
    }
    let q = -b + select(sqrt(disc), -sqrt(disc), b > 0.0);
    if abs(q) < DIV_EPSILON {
        return -1.0;
    }
    let c = dot(oc, oc) - r * r;
    let t0 = min(c / q, q);
    let t1 = max(c / q, q);
    if t0 > 0.0 {
        return t0;
    }
    if t1 > 0.0 {
        return t1;
    }
    return -1.0;
}

// The primary ray through pixel position `frag` (pixel centres at +0.5): origin, unit
// direction.
fn primary_ray(frag: vec2<f32>) -> array<vec3<f32>, 2> {
    let ndc_x = 2.0 * frag.x / globals.size.x - 1.0;
    let ndc_y = 1.0 - 2.0 * frag.y / globals.size.y;
    let o = globals.cam_origin.xyz;
    let d = normalize(globals.cam_forward.xyz + ndc_x * globals.cam_right.xyz + ndc_y * globals.cam_up.xyz);
    return array<vec3<f32>, 2>(o, d);
}

// The colour a fragment writes: f32 on a float or display target; with the shader def
// OUTPUT_BITS (the modules of an `Rgba32Uint` target, src/gpu/shaders.rs), the bits of
// linear radiance as u32: GL renders to no 32-bit float format, and the read-back
// reinterprets the bits as f32 (src/gpu/headless.rs render_hdr), so `.exr` keeps f32
// there too.
#ifdef OUTPUT_BITS
alias Colour = vec4<u32>;

// The bits of linear radiance (and alpha 1). Compiled with OUTPUT_LINEAR = 1.
fn output_value(radiance: vec3<f32>) -> Colour {
    return bitcast<vec4<u32>>(vec4<f32>(radiance, 1.0));
}
#else
alias Colour = vec4<f32>;

// The target's value of linear radiance: itself on a float target, else through the
// display transform (target_value: decoded to linear on an sRGB target, SRGB_TARGET).
fn output_value(radiance: vec3<f32>) -> Colour {
    if OUTPUT_LINEAR == 1u {
        return vec4<f32>(radiance, 1.0);
    }
    return vec4<f32>(target_value(radiance, globals.environment.w), 1.0);
}
#endif

// The unit normal along p (hit point minus centre), or facing the eye when |p| is at most
// DIV_EPSILON, where normalize would give NaN (p = 0) or overflow (a subnormal |p|^2): a
// ball far smaller than its distance from the camera, whose hit point is lost in the f32
// rounding of the ray (src/cpu surface_normal).
fn surface_normal(p: vec3<f32>, d: vec3<f32>) -> vec3<f32> {
    if dot(p, p) > DIV_EPSILON * DIV_EPSILON {
        return normalize(p);
    }
    return -d;
}

// One corner of a ball's quad per vertex (a triangle strip, vertices 0..4): `rect` is its
// bounds in NDC, [x0, y0, x1, y1], the other attributes the ball's members (BallIn and
// ball_out in types.wgsl, generated; src/gpu/renderer.rs, one instance per ball).
@vertex
fn vs_ball(@builtin(vertex_index) index: u32, in: BallIn) -> BallOut {
    // Corners (0,0) (1,0) (0,1) (1,1): the index's bits.
    let cx = f32(index & 1u);
    let cy = f32((index >> 1u) & 1u);
    let rect = in.rect;
    let position = vec4<f32>(mix(rect.x, rect.z, cx), mix(rect.y, rect.w, cy), 0.0, 1.0);
    var counts = vec2<u32>(0u, loop_counts().y);
    if SUN_LIGHT == 1u {
        // The map's sun is SUN_POINTS lights after the scene's (src/scene SunLight): a
        // ball that takes it loops over them too and reads the layers without it (set 1).
        let b = ball_of(ball_out(in, position, counts));
        if sun_takes(b.roughness, b.clearcoat, b.clearcoat_roughness, globals.size.z) {
            counts = vec2<u32>(1u, counts.y + SUN_POINTS);
        }
    }
    return ball_out(in, position, counts);
}

// Whether a ball of `roughness` (its shading roughness) under a coat of weight `coat` and
// roughness `coat_roughness` takes the map's sun as a light: every lobe that reads the
// prefiltered layers at least `roughness_min` rough (SunLight::takes).
fn sun_takes(roughness: f32, coat: f32, coat_roughness: f32, roughness_min: f32) -> bool {
    return roughness >= roughness_min && (coat <= 0.0 || coat_roughness >= roughness_min);
}

// The depth of a hit at distance t > 0: t scaled by the power of two DEPTH_SCALE, which is
// exact in f32 (no two distances the f32 ray tells apart share a depth), so the depth
// test (less) keeps the nearest hit, as the CPU renderer does. Every distance in a valid scene
// is below 2^43 (coordinates and radii within MAX_MAGNITUDE = 1e12 of src/scene: at most
// 2 sqrt(3) 1e12 + 1e12 = 4.5e12), so depths stay in [0, 1).
const DEPTH_SCALE: f32 = 5.684341886080802e-14; // 2^-44

// The display transform (src/display.rs, whose functions these mirror in f32; each curve's
// source is cited there): exposure, the tone mapper TONE_MAP, the transfer curve TRANSFER,
// each an override chosen per pipeline (the scene's display, src/gpu/plan.rs Variant).

// The curves' constants: the largest exposed radiance taken, the floor of the divisors,
// AgX's encoded range and its log floor.
// generated from the Rust constants by src/gpu/tests/boundary.rs: do not edit
const MAX_DISPLAY_RADIANCE: f32 = 1000000.0; // display::MAX_DISPLAY_RADIANCE
const DISPLAY_EPSILON: f32 = 1e-9; // display::DISPLAY_EPSILON
const AGX_MIN_EV: f32 = -12.47393; // display::AGX_MIN_EV
const AGX_MAX_EV: f32 = 4.026069; // display::AGX_MAX_EV
const AGX_LOG_FLOOR: f32 = 1e-10; // display::AGX_LOG_FLOOR
// end of the generated constants

// What the target holds for linear radiance: the encoded display value, or on an sRGB
// target (SRGB_TARGET = 1: the hardware encodes what the shader writes) that value decoded
// with the sRGB curve; under the sRGB transfer curve, the tone-mapped value itself.
fn target_value(radiance: vec3<f32>, exposure: f32) -> vec3<f32> {
    let mapped = apply_tone_map(exposed(radiance, exposure));
    if SRGB_TARGET == 0u {
        return encode_transfer(mapped);
    }
    if TRANSFER == TRANSFER_SRGB {
        return mapped;
    }
    let v = encode_transfer(mapped);
    return vec3<f32>(decode_srgb(v.x), decode_srgb(v.y), decode_srgb(v.z));
}

// radiance * exposure clamped to [0, MAX_DISPLAY_RADIANCE], NaN to 0.
fn exposed(radiance: vec3<f32>, exposure: f32) -> vec3<f32> {
    let c = radiance * exposure;
    let finite = select(c, vec3<f32>(0.0), c != c);
    return clamp(finite, vec3<f32>(0.0), vec3<f32>(MAX_DISPLAY_RADIANCE));
}

// Exposed radiance through the tone mapper TONE_MAP, clamped to [0, 1].
fn apply_tone_map(c: vec3<f32>) -> vec3<f32> {
    var mapped = c;
    if TONE_MAP == TONE_MAP_REINHARD {
        mapped = tone_map_reinhard(c);
    } else if TONE_MAP == TONE_MAP_ACES {
        mapped = tone_map_aces(c);
    } else if TONE_MAP == TONE_MAP_AGX {
        mapped = tone_map_agx(c);
    } else if TONE_MAP == TONE_MAP_KHRONOS_NEUTRAL {
        mapped = tone_map_khronos_neutral(c);
    }
    return clamp(mapped, vec3<f32>(0.0), vec3<f32>(1.0));
}

fn tone_map_reinhard(c: vec3<f32>) -> vec3<f32> {
    return c / (c + 1.0);
}

// WGSL's mat3x3 constructor takes columns: each matrix below is the transpose of the rows
// src/display.rs lists, so that m * v is the same product.
fn tone_map_aces(c: vec3<f32>) -> vec3<f32> {
    let input = transpose(mat3x3<f32>(
        0.59719, 0.35458, 0.04823,
        0.07600, 0.90834, 0.01566,
        0.02840, 0.13383, 0.83777,
    ));
    let output = transpose(mat3x3<f32>(
        1.60475, -0.53108, -0.07367,
        -0.10208, 1.10813, -0.00605,
        -0.00327, -0.07276, 1.07602,
    ));
    let v = input * c;
    let a = v * (v + 0.0245786) - 0.000090537;
    let b = v * (0.983729 * v + 0.4329510) + 0.238081;
    return output * (a / max(b, vec3<f32>(DISPLAY_EPSILON)));
}

fn tone_map_agx(c: vec3<f32>) -> vec3<f32> {
    let inset = transpose(mat3x3<f32>(
        0.842479062253094, 0.0784335999999992, 0.0792237451477643,
        0.0423282422610123, 0.878468636469772, 0.0791661274605434,
        0.0423756549057051, 0.0784336, 0.879142973793104,
    ));
    let outset = transpose(mat3x3<f32>(
        1.19687900512017, -0.0980208811401368, -0.0990297440797205,
        -0.0528968517574562, 1.15190312990417, -0.0989611768448433,
        -0.0529716355144438, -0.0980434501171241, 1.15107367264116,
    ));
    let v = max(inset * c, vec3<f32>(AGX_LOG_FLOOR));
    let ev = clamp(log2(v), vec3<f32>(AGX_MIN_EV), vec3<f32>(AGX_MAX_EV));
    let x = (ev - AGX_MIN_EV) / (AGX_MAX_EV - AGX_MIN_EV);
    let x2 = x * x;
    let x4 = x2 * x2;
    let s = 15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2
        + 0.1191 * x - 0.00232;
    return pow(max(outset * s, vec3<f32>(0.0)), vec3<f32>(2.2));
}

fn tone_map_khronos_neutral(c_in: vec3<f32>) -> vec3<f32> {
    let f90 = 0.04;
    let k_d = 0.15;
    let k_s = 0.8 - f90;
    let x = min(c_in.x, min(c_in.y, c_in.z));
    let offset = select(f90, x - x * x / (4.0 * f90), x < 2.0 * f90);
    let c = c_in - offset;
    let peak = max(c.x, max(c.y, c.z));
    if peak < k_s {
        return c;
    }
    let d = 1.0 - k_s;
    let new_peak = 1.0 - d * d / max(peak + d - k_s, DISPLAY_EPSILON);
    let scaled = c * (new_peak / max(peak, DISPLAY_EPSILON));
    let g = 1.0 - 1.0 / (k_d * (peak - new_peak) + 1.0);
    return mix(scaled, vec3<f32>(new_peak), g);
}

// Display-linear values through the transfer curve TRANSFER.
fn encode_transfer(v: vec3<f32>) -> vec3<f32> {
    if TRANSFER == TRANSFER_SRGB {
        return vec3<f32>(encode_srgb(v.x), encode_srgb(v.y), encode_srgb(v.z));
    }
    return pow(v, vec3<f32>(1.0 / 2.2));
}

fn encode_srgb(v: f32) -> f32 {
    if v <= 0.0031308 {
        return 12.92 * v;
    }
    return 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

fn decode_srgb(v: f32) -> f32 {
    if v <= 0.04045 {
        return v / 12.92;
    }
    return pow((v + 0.055) / 1.055, 2.4);
}
