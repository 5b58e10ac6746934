// balls.wgsl: the entry points of the ball renderer.
//
// One full-screen triangle; the fragment shader casts the pixel's primary ray and
// intersects every ball analytically (exact spheres, no tessellation). Chosen over
// per-ball screen-space quads because it is one draw with no vertex data, resolves
// overlapping balls by the nearest hit without a depth buffer, and paints the background
// in the same pass; its cost (every pixel tests every ball) is small for the tens of balls
// a shading-ball scene holds.

struct VsOut {
    @builtin(position) position: vec4<f32>,
}

// The triangle (-1,-1), (3,-1), (-1,3) covers the whole viewport.
@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> VsOut {
    let x = f32((index << 1u) & 2u) * 2.0 - 1.0;
    let y = f32(index & 2u) * 2.0 - 1.0;
    var out: VsOut;
    out.position = vec4<f32>(x, y, 0.0, 1.0);
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

// Linear radiance seen through pixel position `frag` (pixel centres at +0.5).
fn radiance_at(frag: vec2<f32>) -> vec3<f32> {
    let ndc_x = 2.0 * frag.x / globals.size.x - 1.0;
    let ndc_y = 1.0 - 2.0 * frag.y / globals.size.y;
    let o = globals.cam_origin.xyz;
    let d = normalize(globals.cam_forward.xyz + ndc_x * globals.cam_right.xyz + ndc_y * globals.cam_up.xyz);
    var best_t = -1.0;
    var best = 0u;
    for (var k = 0u; k < min(globals.counts.x, MAX_BALLS); k++) {
        let t = intersect_sphere(o, d, balls[k].center_radius.xyz, balls[k].center_radius.w);
        if t > 0.0 && (best_t < 0.0 || t < best_t) {
            best_t = t;
            best = k;
        }
    }
    if best_t < 0.0 {
        return globals.environment.xyz;
    }
    let b = balls[best];
    let n = surface_normal(o + best_t * d - b.center_radius.xyz, d);
    return shade(b, n, -d);
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

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    let radiance = radiance_at(in.position.xy);
    if OUTPUT_LINEAR == 1u {
        return vec4<f32>(radiance, 1.0);
    }
    return vec4<f32>(tone_map(radiance, globals.environment.w), 1.0);
}
