// footprint.wgsl: what a pixel sees of a ball (its antialiased footprint) and of the
// background, shared by the ball renderer (balls.wgsl) and the Monte Carlo (montecarlo.wgsl),
// so that both filter pixels alike (docs/design/antialiasing.md).

#define_import_path shadeballs::footprint
#import shadeballs::constants::DIV_EPSILON
#import shadeballs::environment::{direction_to_uv, env_to_map}
#import shadeballs::types::{IBL, AA}
#import shadeballs::bindings::{globals, env, env_radiance, env_sampler}
#import shadeballs::screen::{primary_ray, intersect_sphere}

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

// AA_EDGE_PX: how near a silhouette, in pixel footprints, a centre ray must pass for the
// pixel to be partly covered: half a pixel's diagonal (0.71) and a margin for rounding.
// generated from the Rust constants by src/gpu/tests/boundary.rs: do not edit
const AA_EDGE_PX: f32 = 1.0; // scene::AA_EDGE_PX
// end of the generated constants

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

// What a pixel whose ray (unit direction d) hits no ball shows: the background's fixed
// radiance, plus the environment map along d where the background shows it (IBL != 0).
// The map's share is weighted by the 0/1 flag rather than branched on: a branch on a
// uniform value costs a shader compile per bind on lavapipe (loop_counts says why).
fn background_radiance(d: vec3<f32>) -> vec3<f32> {
    var c = env.background.rgb;
    if IBL != 0u {
        let uv = direction_to_uv(env_to_map(d, env.rotation));
        let shown = env.shows_map * env.intensity;
        c += shown * textureSampleLevel(env_radiance, env_sampler, uv, 0.0).rgb;
    }
    return c;
}
