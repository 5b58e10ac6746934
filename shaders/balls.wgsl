// balls.wgsl: the entry points of the ball renderer.
//
// Each pixel casts its primary ray and intersects balls analytically (exact spheres, no
// tessellation). Two ways to cover the pixels:
// - vs_ball / fs_ball (the planned renderer, src/gpu/renderer.rs): one quad per ball over
//   its screen-space bounds (CameraBasis::sphere_bounds), instanced per shader variant; a
//   fragment intersects its own ball only, discards where the ray misses it, and writes
//   the hit's distance as its depth (ball_depth): the depth test keeps the nearest ball,
//   so a pixel costs one intersection whatever the number of balls. The background is the
//   render pass's clear. Only the pixels a ball's quad covers are shaded.
// - vs_main / fs_main: one full-screen triangle that also paints the background, each
//   pixel intersecting every ball (nearest_hit; the design before planning, kept for
//   comparison in `shadeballs bench`).

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

struct Hit {
    // Distance along the ray, or -1 for no hit.
    t: f32,
    ball: u32,
}

// The nearest of the first `n_balls` balls along the ray (lowest index on a tie).
fn nearest_hit(o: vec3<f32>, d: vec3<f32>, n_balls: u32) -> Hit {
    var best_t = -1.0;
    var best = 0u;
    for (var k = 0u; k < n_balls; k++) {
        let t = intersect_sphere(o, d, balls[k].center_radius.xyz, balls[k].center_radius.w);
        if t > 0.0 && (best_t < 0.0 || t < best_t) {
            best_t = t;
            best = k;
        }
    }
    return Hit(best_t, best);
}

// Radiance leaving ball b, hit at distance t along the ray, towards the eye, lit by the
// first `n_lights` lights.
fn shade_hit(o: vec3<f32>, d: vec3<f32>, t: f32, b: Ball, n_lights: u32) -> vec3<f32> {
    let n = surface_normal(o + t * d - b.center_radius.xyz, d);
    return shade(b, n, -d, n_lights);
}

// Linear radiance seen through pixel position `frag`, background included; `counts` from
// loop_counts.
fn radiance_at(frag: vec2<f32>, counts: vec2<u32>) -> vec3<f32> {
    let ray = primary_ray(frag);
    let hit = nearest_hit(ray[0], ray[1], counts.x);
    if hit.t < 0.0 {
        return background_radiance(ray[1]);
    }
    return shade_hit(ray[0], ray[1], hit.t, balls[hit.ball], counts.y);
}

// What a pixel whose ray (unit direction d) hits no ball shows: the background's fixed
// radiance, plus the environment map along d where the background shows it (IBL != 0).
// The map's share is weighted by the 0/1 flag rather than branched on: a branch on a
// uniform value costs a shader compile per bind on lavapipe (loop_counts says why).
fn background_radiance(d: vec3<f32>) -> vec3<f32> {
    var c = env.background.rgb;
    if IBL != 0u {
        let uv = direction_to_uv(env_to_map(d, env.rotation_intensity.xy));
        let shown = env.rotation_intensity.w * env.rotation_intensity.z;
        c += shown * textureSampleLevel(env_radiance, env_sampler, uv, 0.0).rgb;
    }
    return c;
}

// The target's value of linear radiance: itself on a float target, else tone-mapped.
fn output_value(radiance: vec3<f32>) -> vec4<f32> {
    if OUTPUT_LINEAR == 1u {
        return vec4<f32>(radiance, 1.0);
    }
    return vec4<f32>(tone_map(radiance, globals.environment.w), 1.0);
}

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

// The bits of linear radiance (and alpha 1) for an `Rgba32Uint` target: GL renders to no
// 32-bit float format, and the read-back reinterprets the bits as f32 (src/gpu/headless.rs
// render_hdr), so `.exr` keeps f32 there too. Compiled with OUTPUT_LINEAR = 1.
fn output_bits(radiance: vec3<f32>) -> vec4<u32> {
    return bitcast<vec4<u32>>(vec4<f32>(radiance, 1.0));
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    return output_value(radiance_at(in.position.xy, in.counts));
}

// fs_main for an Rgba32Uint target (output_bits).
@fragment
fn fs_main_bits(in: VsOut) -> @location(0) vec4<u32> {
    return output_bits(radiance_at(in.position.xy, in.counts));
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
    @location(4) @interpolate(flat) diffuse_ms: vec4<f32>,
    @location(5) @interpolate(flat) f_add_ms_norm: vec4<f32>,
    @location(6) @interpolate(flat) lut_row: vec4<f32>,
}

// The ball a BallOut carries.
fn ball_of(in: BallOut) -> Ball {
    return Ball(in.center_radius, in.f0_roughness, in.diffuse_ms, in.f_add_ms_norm, in.lut_row);
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
    @location(4) diffuse_ms: vec4<f32>,
    @location(5) f_add_ms_norm: vec4<f32>,
    @location(6) lut_row: vec4<f32>,
) -> BallOut {
    // Corners (0,0) (1,0) (0,1) (1,1): the index's bits.
    let cx = f32(index & 1u);
    let cy = f32((index >> 1u) & 1u);
    var out: BallOut;
    out.position = vec4<f32>(mix(rect.x, rect.z, cx), mix(rect.y, rect.w, cy), 0.0, 1.0);
    out.counts = loop_counts();
    out.center_radius = center_radius;
    out.f0_roughness = f0_roughness;
    out.diffuse_ms = diffuse_ms;
    out.f_add_ms_norm = f_add_ms_norm;
    out.lut_row = lut_row;
    return out;
}

// The depth of a hit at distance t > 0: t scaled by the power of two DEPTH_SCALE, which is
// exact in f32 (no two distances the f32 ray tells apart share a depth), so the depth
// test (less) keeps the nearest hit as nearest_hit does. Every distance in a valid scene
// is below 2^43 (coordinates and radii within MAX_MAGNITUDE = 1e12 of src/scene: at most
// 2 sqrt(3) 1e12 + 1e12 = 4.5e12), so depths stay in [0, 1).
const DEPTH_SCALE: f32 = 5.684341886080802e-14; // 2^-44

struct BallFragment {
    @location(0) colour: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

// The distance along the pixel's primary ray `ray` to the quad's own ball (not > 0 where
// the ray misses it).
fn ball_distance(in: BallOut, ray: array<vec3<f32>, 2>) -> f32 {
    return intersect_sphere(ray[0], ray[1], in.center_radius.xyz, in.center_radius.w);
}

// The pixel's radiance on this quad's ball, at its depth; discarded where the ray misses
// the ball (another quad or the clear covers it). The depth test settles which ball is in
// front: one intersection a fragment, not one per ball.
@fragment
fn fs_ball(in: BallOut) -> BallFragment {
    let ray = primary_ray(in.position.xy);
    let t = ball_distance(in, ray);
    if !(t > 0.0) {
        discard;
    }
    var out: BallFragment;
    out.colour = output_value(shade_hit(ray[0], ray[1], t, ball_of(in), in.counts.y));
    out.depth = t * DEPTH_SCALE;
    return out;
}

struct BallBits {
    @location(0) colour: vec4<u32>,
    @builtin(frag_depth) depth: f32,
}

// fs_ball for an Rgba32Uint target (output_bits); the same discard and depth.
@fragment
fn fs_ball_bits(in: BallOut) -> BallBits {
    let ray = primary_ray(in.position.xy);
    let t = ball_distance(in, ray);
    if !(t > 0.0) {
        discard;
    }
    var out: BallBits;
    out.colour = output_bits(shade_hit(ray[0], ray[1], t, ball_of(in), in.counts.y));
    out.depth = t * DEPTH_SCALE;
    return out;
}

// The background alone, drawn over the viewport before the balls' quads where it shows the
// environment map (the clear covers the other backgrounds).
@fragment
fn fs_background(in: VsOut) -> @location(0) vec4<f32> {
    return output_value(background_radiance(primary_ray(in.position.xy)[1]));
}

// fs_background for an Rgba32Uint target (output_bits).
@fragment
fn fs_background_bits(in: VsOut) -> @location(0) vec4<u32> {
    return output_bits(background_radiance(primary_ray(in.position.xy)[1]));
}
