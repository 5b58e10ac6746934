// screen.wgsl: what the ball renderer (balls.wgsl) and the truth (walk.wgsl) share on
// screen: the vertex stages (the full-screen triangle, the per-ball quads), the primary
// rays, the ray-sphere intersection, the depth of a hit, and the colour a fragment writes
// (the display transform, or the bits of linear radiance under the shader def OUTPUT_BITS).

#define_import_path shadeballs::screen
#import shadeballs::constants::DIV_EPSILON
#import shadeballs::types::{Ball, MAX_BALLS, MAX_LIGHTS, OUTPUT_LINEAR}
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

// The target's value of linear radiance: itself on a float target, else tone-mapped.
fn output_value(radiance: vec3<f32>) -> Colour {
    if OUTPUT_LINEAR == 1u {
        return vec4<f32>(radiance, 1.0);
    }
    return vec4<f32>(tone_map(radiance, globals.environment.w), 1.0);
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

struct BallOut {
    @builtin(position) position: vec4<f32>,
    // loop_counts(), as in VsOut.
    @location(1) @interpolate(flat) counts: vec2<u32>,
    // The quad's ball, from its instance (src/gpu/bindings.rs BallInstance) and handed on
    // as flat varyings: a fragment shades only its own ball, so it reads no per-ball buffer.
    // On lavapipe a buffer read at a per-pixel index is a gather that costs about what a
    // table read does; a flat varying is a broadcast (docs/benchmarks.md, "The term's cost").
    @location(2) @interpolate(flat) center_radius: vec4<f32>,
    @location(3) @interpolate(flat) f0_roughness: vec4<f32>,
    @location(4) @interpolate(flat) diffuse: vec3<f32>,
    @location(7) @interpolate(flat) ms: f32,
    @location(5) @interpolate(flat) f_add_ms_norm: vec4<f32>,
    @location(6) @interpolate(flat) lut_row: vec3<f32>,
    @location(8) @interpolate(flat) term: u32,
}

// The ball a BallOut carries.
fn ball_of(in: BallOut) -> Ball {
    return Ball(in.center_radius, in.f0_roughness, in.diffuse, in.ms, in.f_add_ms_norm, in.lut_row, in.term);
}

// One corner of a ball's quad per vertex (a triangle strip, vertices 0..4): `rect` is its
// bounds in NDC, [x0, y0, x1, y1], the other attributes the ball's members (src/gpu/
// renderer.rs encode, one instance per ball).
@vertex
fn vs_ball(
    @builtin(vertex_index) index: u32,
    @location(0) rect: vec4<f32>,
    @location(2) center_radius: vec4<f32>,
    @location(3) f0_roughness: vec4<f32>,
    @location(4) diffuse: vec3<f32>,
    @location(7) ms: f32,
    @location(5) f_add_ms_norm: vec4<f32>,
    @location(6) lut_row: vec3<f32>,
    @location(8) term: u32,
) -> BallOut {
    // Corners (0,0) (1,0) (0,1) (1,1): the index's bits.
    let cx = f32(index & 1u);
    let cy = f32((index >> 1u) & 1u);
    var out: BallOut;
    out.position = vec4<f32>(mix(rect.x, rect.z, cx), mix(rect.y, rect.w, cy), 0.0, 1.0);
    out.counts = loop_counts();
    out.center_radius = center_radius;
    out.f0_roughness = f0_roughness;
    out.diffuse = diffuse;
    out.ms = ms;
    out.f_add_ms_norm = f_add_ms_norm;
    out.lut_row = lut_row;
    out.term = term;
    return out;
}

// The depth of a hit at distance t > 0: t scaled by the power of two DEPTH_SCALE, which is
// exact in f32 (no two distances the f32 ray tells apart share a depth), so the depth
// test (less) keeps the nearest hit, as the CPU renderer does. Every distance in a valid scene
// is below 2^43 (coordinates and radii within MAX_MAGNITUDE = 1e12 of src/scene: at most
// 2 sqrt(3) 1e12 + 1e12 = 4.5e12), so depths stay in [0, 1).
const DEPTH_SCALE: f32 = 5.684341886080802e-14; // 2^-44

// Display transform (docs/design/reference-scene.md, "The balls, the light and the
// camera"): exposure, Reinhard c / (c + 1), gamma 1/2.2.
fn tone_map(radiance: vec3<f32>, exposure: f32) -> vec3<f32> {
    let c = max(radiance * exposure, vec3<f32>(0.0));
    return pow(c / (c + 1.0), vec3<f32>(1.0 / 2.2));
}
