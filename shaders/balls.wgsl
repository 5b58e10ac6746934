// balls.wgsl: the entry points of the ball renderer (the vertex stages and the output are
// screen.wgsl's).
//
// Each pixel casts its primary ray and intersects balls analytically (exact spheres, no
// tessellation). vs_ball / fs_ball (src/gpu/renderer.rs): one quad per ball over its
// screen-space bounds (CameraBasis::sphere_bounds), instanced per shader variant; a
// fragment intersects its own ball only, discards where the ray misses it, and writes the
// hit's distance as its depth (ball_depth): the depth test keeps the nearest ball, so a
// pixel costs one intersection whatever the number of balls. The background is the render
// pass's clear (or fs_background's map). Only the pixels a ball's quad covers are shaded.
// (The design before planning, one full-screen triangle whose pixels intersected every
// ball, is gone: docs/benchmarks.md, "Before planning".)

#define_import_path shadeballs::balls
#import shadeballs::types::{Ball, BallOut, ball_of}
#import shadeballs::lighting::shade
#import shadeballs::screen::{VsOut, primary_ray}
#import shadeballs::screen::{surface_normal, output_value, Colour, DEPTH_SCALE}
#import shadeballs::footprint::{Footprint, ball_footprint, background_radiance}
#import shadeballs::bindings::env_layer_set

// The linear radiance of footprint f on ball b (f.t > 0): the ball shaded along the ray
// through f.hit, mixed with the background along the ray through f.miss by the coverage.
fn footprint_radiance(f: Footprint, b: Ball, n_lights: u32, pixel: vec2<u32>) -> vec3<f32> {
    let ray = primary_ray(f.hit);
    var lo = shade_hit(ray[0], ray[1], f.t, b, n_lights, pixel);
    // A loop of 0 or 1 iterations, as in ball_footprint: the map's read only where needed.
    for (var once = f.coverage < 1.0; once; once = false) {
        lo = mix(background_radiance(primary_ray(f.miss)[1]), lo, f.coverage);
    }
    return lo;
}

// Radiance leaving ball b, hit at distance t along the ray, towards the eye, lit by the
// first `n_lights` lights; `pixel` (column, row) picks the lobe's samples (shade).
fn shade_hit(o: vec3<f32>, d: vec3<f32>, t: f32, b: Ball, n_lights: u32, pixel: vec2<u32>) -> vec3<f32> {
    let n = surface_normal(o + t * d - b.center, d);
    return shade(b, n, -d, n_lights, pixel);
}

struct BallFragment {
    @location(0) colour: Colour,
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
    let b = ball_of(in);
    let f = ball_footprint(in.position.xy, b.center, b.radius);
    if !(f.t > 0.0) {
        discard;
    }
    var out: BallFragment;
    let pixel = vec2<u32>(in.position.xy);
    env_layer_set = in.counts.x;
    out.colour = output_value(footprint_radiance(f, b, in.counts.y, pixel));
    out.depth = f.t * DEPTH_SCALE;
    return out;
}

// The background alone, drawn over the viewport before the balls' quads where it shows the
// environment map (the clear covers the other backgrounds).
@fragment
fn fs_background(in: VsOut) -> @location(0) Colour {
    return output_value(background_radiance(primary_ray(in.position.xy)[1]));
}
