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

// Antialiased silhouettes (docs/design/antialiasing.md). A pixel integrates radiance over
// its square footprint (a box filter, as offline renderers do). Near a ball's silhouette
// the fraction of the pixel the ball covers is computed analytically: the silhouette is
// linearised at the pixel's centre (the level set |ray - centre| = r of the ray's distance
// from the ball's centre, its gradient over the pixel from central differences) and the
// area of the unit square on its inner side taken in closed form (box_coverage). The ball
// is shaded once, along the ray through the centroid of the covered part, the background
// once, along the ray through the centroid of the rest, and the two mixed by the covered
// fraction in linear radiance. Where the whole pixel is covered, the ray through its centre
// alone, bit for bit as without antialiasing. Only pixels near a silhouette
// (straddles_silhouette) do this work. src/cpu mirrors each function under the same name.

// The distance of the primary ray (o, d) through pixel position q from point c, and its
// derivatives along x and y per pixel (y down): with D the unnormalised direction
// (primary_ray), dd = (dD - d (d . dD)) / |D| with dD = 2 right / w or -2 up / h; the
// perpendicular P = oc - (oc . d) d moves by dP = -(oc . dd) d - (oc . d) dd, and |P| by
// P . dP / |P|. Analytic, not differences of neighbouring rays: no extra normalisation.
fn ray_distance(q: vec2<f32>, d: vec3<f32>, c: vec3<f32>) -> vec3<f32> {
    let oc = globals.cam_origin.xyz - c;
    let b = dot(oc, d);
    let p = oc - b * d;
    let len = length(p);
    let ndc_x = 2.0 * q.x / globals.size.x - 1.0;
    let ndc_y = 1.0 - 2.0 * q.y / globals.size.y;
    let inv = 1.0 / length(globals.cam_forward.xyz + ndc_x * globals.cam_right.xyz + ndc_y * globals.cam_up.xyz);
    let dx = 2.0 * globals.cam_right.xyz / globals.size.x;
    let dy = -2.0 * globals.cam_up.xyz / globals.size.y;
    let ddx = (dx - d * dot(d, dx)) * inv;
    let ddy = (dy - d * dot(d, dy)) * inv;
    let dpx = -dot(oc, ddx) * d - b * ddx;
    let dpy = -dot(oc, ddy) * d - b * ddy;
    let scale = 1.0 / max(len, DIV_EPSILON);
    return vec3<f32>(len, dot(p, dpx) * scale, dot(p, dpy) * scale);
}

// The area of the unit pixel square, centred on the origin, where n . q <= s (n a unit
// vector or 0): the integral of the square's chord across n, a trapezoid of half-widths
// (|nx| + |ny|) / 2 and (|nx| - |ny|) / 2 (the coverage of a half-plane; e.g. Gupta and
// Sproull, "Filtering edges for gray-scale displays", SIGGRAPH 1981, for a box filter).
fn box_coverage(s: f32, n: vec2<f32>) -> f32 {
    let a = max(abs(n.x), abs(n.y));
    let b = min(abs(n.x), abs(n.y));
    let h = 0.5 * (a + b);
    let k = 0.5 * (a - b);
    let corner = 1.0 / max(2.0 * a * b, DIV_EPSILON);
    let low = (s + h) * (s + h) * corner;
    let high = 1.0 - (h - s) * (h - s) * corner;
    let middle = 0.5 + s / max(a, DIV_EPSILON);
    let area = select(select(middle, high, s > k), low, s < -k);
    return clamp(select(area, select(0.0, 1.0, s > 0.0), s <= -h || s >= h), 0.0, 1.0);
}

// What a pixel sees of one ball: the distance of the hit it is shaded at (not > 0: the
// ball covers none of the pixel), the pixel positions of the ray the ball is shaded along
// and of the ray the background is seen along, and the fraction of the pixel the ball
// covers (1: the ray through the centre alone, as without antialiasing).
struct Footprint {
    t: f32,
    hit: vec2<f32>,
    miss: vec2<f32>,
    coverage: f32,
}

// How near a silhouette, in pixel footprints, a centre ray must pass for the pixel to be
// partly covered: half a pixel's diagonal (0.71) and a margin for rounding (src/scene
// AA_EDGE_PX).
const AA_EDGE_PX: f32 = 1.0;

// Whether the footprint of the pixel whose centre ray (unit direction d) passes `distance`
// from the centre of sphere (c, r) may straddle its silhouette: that distance within
// AA_EDGE_PX footprints of r, a footprint being |o - c| times an upper bound on the angle
// between neighbouring pixels' rays (src/scene CameraBasis::pixel_angle), what the distance
// moves at most per pixel.
fn straddles_silhouette(distance: f32, c: vec3<f32>, r: f32) -> bool {
    let pixel_angle = 2.0 * max(length(globals.cam_right.xyz) / globals.size.x, length(globals.cam_up.xyz) / globals.size.y);
    let footprint = length(globals.cam_origin.xyz - c) * pixel_angle;
    // A ball under half a footprint (about a pixel) has no silhouette to linearise: the
    // centre ray alone, as without antialiasing (src/cpu straddles_silhouette).
    return r >= 0.5 * footprint && abs(distance - r) <= AA_EDGE_PX * footprint;
}

// The footprint of pixel position `frag` (a pixel's centre) on sphere (c, r).
fn ball_footprint(frag: vec2<f32>, c: vec3<f32>, r: f32) -> Footprint {
    let ray = primary_ray(frag);
    var f = Footprint(intersect_sphere(ray[0], ray[1], c, r), frag, frag, 1.0);
    if AA == 0u {
        return f;
    }
    let oc = ray[0] - c;
    let near = straddles_silhouette(length(oc - dot(oc, ray[1]) * ray[1]), c, r);
    // The work near a silhouette as a loop of 0 or 1 iterations, not an if: lavapipe skips
    // a loop no pixel of a block enters but runs both sides of an if under a mask, so an
    // if would make every pixel pay (docs/benchmarks.md, "Antialiasing").
    for (var once = near; once; once = false) {
        // The ray's distance from the centre, and its change per pixel (y down, as frag).
        let rd = ray_distance(frag, ray[1], c);
        let len = length(rd.yz);
        // Outward unit normal of the silhouette in pixels, and how far (pixels) the
        // silhouette lies from the centre along it (> 0: the centre is inside).
        let n = rd.yz / max(len, DIV_EPSILON);
        let s = (r - rd.x) / max(len, DIV_EPSILON);
        let coverage = box_coverage(s, n);
        if coverage < 1.0 {
            // The square spans [-h, h] along n; the covered part is u <= s.
            let h = 0.5 * (abs(n.x) + abs(n.y));
            let edge = clamp(s, -h, h);
            let hit = frag + n * (0.5 * (edge - h));
            let through = primary_ray(hit);
            var t = intersect_sphere(through[0], through[1], c, r);
            // The centroid of the covered part is inside the silhouette; where rounding
            // says otherwise, the ray's closest approach to the centre (negative behind
            // the eye).
            if !(t > 0.0) {
                t = dot(c - through[0], through[1]);
            }
            f = Footprint(select(-1.0, t, coverage > 0.0), hit, frag + n * (0.5 * (edge + h)), coverage);
        }
    }
    return f;
}

// The linear radiance of footprint f on ball b (f.t > 0): the ball shaded along the ray
// through f.hit, mixed with the background along the ray through f.miss by the coverage.
fn footprint_radiance(f: Footprint, b: Ball, n_lights: u32) -> vec3<f32> {
    let ray = primary_ray(f.hit);
    var lo = shade_hit(ray[0], ray[1], f.t, b, n_lights);
    // A loop of 0 or 1 iterations, as in ball_footprint: the map's read only where needed.
    for (var once = f.coverage < 1.0; once; once = false) {
        lo = mix(background_radiance(primary_ray(f.miss)[1]), lo, f.coverage);
    }
    return lo;
}

// Radiance leaving ball b, hit at distance t along the ray, towards the eye, lit by the
// first `n_lights` lights.
fn shade_hit(o: vec3<f32>, d: vec3<f32>, t: f32, b: Ball, n_lights: u32) -> vec3<f32> {
    let n = surface_normal(o + t * d - b.center_radius.xyz, d);
    return shade(b, n, -d, n_lights);
}

// Linear radiance seen through pixel position `frag`, background included; `counts` from
// loop_counts. Without antialiasing (AA = 0), the nearest hit of the centre ray; with it, of every
// ball's footprint (ball_footprint) the one whose shading distance is the nearest (lowest
// index on a tie), as the per-ball draw's depth test keeps.
fn radiance_at(frag: vec2<f32>, counts: vec2<u32>) -> vec3<f32> {
    let ray = primary_ray(frag);
    if AA == 0u {
        let hit = nearest_hit(ray[0], ray[1], counts.x);
        if hit.t < 0.0 {
            return background_radiance(ray[1]);
        }
        return shade_hit(ray[0], ray[1], hit.t, balls[hit.ball], counts.y);
    }
    var best = Footprint(-1.0, frag, frag, 0.0);
    var best_ball = 0u;
    for (var k = 0u; k < counts.x; k++) {
        let f = ball_footprint(frag, balls[k].center_radius.xyz, balls[k].center_radius.w);
        if f.t > 0.0 && (best.t <= 0.0 || f.t < best.t) {
            best = f;
            best_ball = k;
        }
    }
    if !(best.t > 0.0) {
        return background_radiance(ray[1]);
    }
    return footprint_radiance(best, balls[best_ball], counts.y);
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

// The pixel's radiance on this quad's ball (its footprint: ball_footprint), at its depth;
// discarded where the ball covers none of the pixel (another quad or the clear covers it).
// A pixel the silhouette crosses shows this ball mixed with the background, also where
// another ball lies behind it (a limitation: docs/design/antialiasing.md, "Limitation:
// overlapping balls"). The depth test settles which ball is in front: one intersection a
// fragment, not one per ball.
@fragment
fn fs_ball(in: BallOut) -> BallFragment {
    let f = ball_footprint(in.position.xy, in.center_radius.xyz, in.center_radius.w);
    if !(f.t > 0.0) {
        discard;
    }
    var out: BallFragment;
    out.colour = output_value(footprint_radiance(f, ball_of(in), in.counts.y));
    out.depth = f.t * DEPTH_SCALE;
    return out;
}

struct BallBits {
    @location(0) colour: vec4<u32>,
    @builtin(frag_depth) depth: f32,
}

// fs_ball for an Rgba32Uint target (output_bits); the same discard and depth.
@fragment
fn fs_ball_bits(in: BallOut) -> BallBits {
    let f = ball_footprint(in.position.xy, in.center_radius.xyz, in.center_radius.w);
    if !(f.t > 0.0) {
        discard;
    }
    var out: BallBits;
    out.colour = output_bits(footprint_radiance(f, ball_of(in), in.counts.y));
    out.depth = f.t * DEPTH_SCALE;
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
