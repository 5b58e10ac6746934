// walk.wgsl: the truth on the GPU. Balls with model = "truth" are path traced with the
// random walk on their microsurface (Heitz, Hanika, d'Eon and Dachsbacher 2016,
// "Multiple-Scattering Microfacet BSDFs with the Smith Model"), the f32 mirror of
// src/walk (microsurface.rs, mod.rs trace, coating.rs, clearcoat.rs), one estimate per
// pixel and frame, summed in an Rgba32Float accumulation target (src/gpu/truth.rs;
// docs/design/gpu-truth.md). Imports screen.wgsl for the rays, the quads and the output.
//
// A pixel's estimate mixes a ball's metal and dielectric parts by metallic, as
// src/cpu/truth.rs does. The metal: the lights' single scattering exactly (f_micro with
// Schlick F, GGX D, height-correlated Smith G) and one walk entering along the view
// direction (reciprocity) that gives
// - every escape, from the first event on, times the radiance arriving from its direction
//   (uniform environment plus map): the environment's single scattering is carried by
//   the walk's order-1 escape (unbiased; the CPU tabulates it by quadrature instead);
// - next-event estimates towards every light from the second event on.
// The dielectric: one walk through the rough coating over its Lambertian base
// (coating_walk, every order), next-event estimates at the interface before the first
// arrival at the base, the base's gathering after, its exit times the arriving radiance.
// An anisotropic ball's metal walks the stretched surface in the ball's tangent frame
// (HAS_ANISOTROPY); a clear-coated ball is walked whole under its coat, its exit times
// the arriving radiance (clearcoat_walk, src/walk/clearcoat.rs; HAS_CLEARCOAT).
// Differences from the CPU walk: f32; a metal path ends after WALK_MAX_EVENTS events (the
// CPU's guard is 10 000; a coating path's guard is the CPU's); the generator is a PCG
// hash, not SplitMix64.

#define_import_path shadeballs::walk
#import shadeballs::constants::{PI, DIV_EPSILON, GEOMETRY_SMITH_CORRELATED}
#import shadeballs::brdf::{alpha_from_roughness, d_ggx, lambda_smith, f_schlick, fresnel_dielectric}
#import shadeballs::brdf::{f_micro, f_micro_aniso, d_ggx_aniso, lambda_smith_aniso, ball_tangent_frame}
#import shadeballs::sampling::{duff_frame, arriving}
#import shadeballs::types::{Ball, BallOut, ball_of, HAS_ENVIRONMENT, HAS_LIGHTS, IBL, HAS_ANISOTROPY, HAS_CLEARCOAT, HAS_METAL, HAS_DIELECTRIC}
#import shadeballs::bindings::{globals, lights, env, env_radiance, env_sampler}
#import shadeballs::screen::{VsOut, primary_ray, intersect_sphere}
#import shadeballs::screen::{surface_normal, output_value, Colour, DEPTH_SCALE}

// Scattering events a GPU path may have (a cut, not a roulette: it loses the energy of
// longer paths, a bias the furnace test of tests/suite/gpu_truth.rs bounds;
// docs/design/gpu-truth.md, "Differences from the CPU walk", gives the share of longer
// paths); the loop's cost grows with the longest path of a SIMD group.
const WALK_MAX_EVENTS: u32 = 32u;
// WALK_RR_BELOW: Russian roulette below this path mass (src/walk RR_BELOW).
// generated from the Rust constants by src/gpu/tests/boundary.rs: do not edit
const WALK_RR_BELOW: f32 = 0.05; // walk::RR_BELOW
// end of the generated constants
// Smallest C1 value and exponent guard of walk_pow (f32: 1e-30 keeps log2 finite).
const WALK_TINY: f32 = 1e-30;

// The generator (Jarzynski and Olano 2020, "Hash Functions for GPU Rendering", JCGT
// 9(3)): PCG's state step and its RXS-M-XS output permutation, 32 bits.
fn pcg_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// A pixel's stream for its `frame`-th estimate: the keys hashed in turn.
fn rng_seed(px: u32, py: u32, frame: u32) -> u32 {
    return pcg_hash(px ^ pcg_hash(py ^ pcg_hash(frame ^ 0x5348u)));
}

// Uniform in [0, 1) with 24 random bits; advances the stream.
fn rng_uniform(state: ptr<function, u32>) -> f32 {
    *state = *state * 747796405u + 2891336453u;
    let s = *state;
    let word = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    return f32(((word >> 22u) ^ word) >> 8u) * (1.0 / 16777216.0);
}

// x^y for x in [0, 1] (x clamped away from 0, where pow is undefined).
fn walk_pow(x: f32, y: f32) -> f32 {
    return exp2(y * log2(max(x, WALK_TINY)));
}

// The microsurface (Heitz et al. 2016; src/walk/microsurface.rs, name for name), of GGX
// alphas s = (alpha_t, alpha_b): along the local x (the tangent) and y. An isotropic
// surface has equal alphas and takes the isotropic formulas; the anisotropic ones (the
// stretch of Heitz et al. 2016, section 4) are compiled in only with HAS_ANISOTROPY.
fn walk_anisotropic(s: vec2<f32>) -> bool {
    return HAS_ANISOTROPY == 1u && s.x != s.y;
}

// Smith's Lambda of a direction w, signed below the horizon: Lambda(-w) = -1 - Lambda(w).
fn walk_lambda(w: vec3<f32>, s: vec2<f32>) -> f32 {
    if walk_anisotropic(s) {
        if w.z > 0.0 {
            return lambda_smith_aniso(w, s.x, s.y);
        }
        return -1.0 - lambda_smith_aniso(-w, s.x, s.y);
    }
    if w.z > 0.0 {
        return lambda_smith(w.z, s.x);
    }
    return -1.0 - lambda_smith(-w.z, s.x);
}

// Probability that a ray leaving height c = C1(h) along an upward direction dir escapes:
// c^Lambda (0 at or below the horizon).
fn walk_g1(dir: vec3<f32>, c: f32, s: vec2<f32>) -> f32 {
    if dir.z <= 0.0 {
        return 0.0;
    }
    return walk_pow(c, walk_lambda(dir, s));
}

// C1 of the next intersection of a ray from c along dir, given that it hits, from u
// uniform in [0, 1): upward, u scaled into [0, 1 - G1) and (c / c')^Lambda inverted;
// downward (Lambda <= -1) always a hit.
fn walk_next_height(dir: vec3<f32>, c: f32, u: f32, s: vec2<f32>) -> f32 {
    let lambda = walk_lambda(dir, s);
    if dir.z > 0.0 {
        let escape = walk_pow(c, lambda);
        let v = u * (1.0 - escape);
        let inv = 1.0 / max(lambda, DIV_EPSILON);
        return min(c / max(walk_pow(1.0 - v, inv), WALK_TINY), 1.0);
    }
    return c * walk_pow(1.0 - u, -1.0 / min(lambda, -1.0));
}

// Projected area of the microsurface along w (Heitz 2014): (w.z + sqrt(w.z^2 + alpha^2
// (1 - w.z^2))) / 2, the anisotropic alpha^2 (1 - z^2) being alpha_t^2 w_x^2 + alpha_b^2 w_y^2.
fn walk_projected_area(w: vec3<f32>, s: vec2<f32>) -> f32 {
    let z = clamp(w.z, -1.0, 1.0);
    if walk_anisotropic(s) {
        let x = s.x * w.x;
        let y = s.y * w.y;
        return 0.5 * (z + sqrt(z * z + x * x + y * y));
    }
    return 0.5 * (z + sqrt(z * z + s.x * s.x * (1.0 - z * z)));
}

// GGX's D(h) of the surface at unit local h.
fn walk_d(h: vec3<f32>, s: vec2<f32>) -> f32 {
    if walk_anisotropic(s) {
        return d_ggx_aniso(h, s.x, s.y);
    }
    return d_ggx(h.z, s.x);
}

// The conductor's phase function without Fresnel, D(h) / (4 A(wi)), h = normalize(wi +
// wo), wi pointing back along the arriving ray; returns (p, wi.h), p = 0 where h faces
// down or away from wi.
fn walk_phase(wi: vec3<f32>, wo: vec3<f32>, s: vec2<f32>) -> vec2<f32> {
    let sum = wi + wo;
    let len = length(sum);
    if len <= DIV_EPSILON {
        return vec2<f32>(0.0);
    }
    let h = sum / len;
    let cos = dot(wi, h);
    if h.z <= 0.0 || cos <= 0.0 {
        return vec2<f32>(0.0);
    }
    let area = max(walk_projected_area(wi, s), DIV_EPSILON);
    return vec2<f32>(walk_d(h, s) / (4.0 * area), cos);
}

// A microfacet normal from the distribution of normals visible from wi (Heitz 2018,
// "Sampling the GGX Distribution of Visible Normals", JCGT 7(4)), wi on either side of
// the horizon: stretch by (alpha_t, alpha_b), sample, unstretch.
fn walk_sample_visible_normal(wi: vec3<f32>, s: vec2<f32>, u1: f32, u2: f32) -> vec3<f32> {
    let vh = normalize(vec3<f32>(s.x * wi.x, s.y * wi.y, wi.z));
    let lensq = vh.x * vh.x + vh.y * vh.y;
    var t1 = vec3<f32>(1.0, 0.0, 0.0);
    if lensq > 0.0 {
        t1 = vec3<f32>(-vh.y, vh.x, 0.0) / sqrt(lensq);
    }
    let t2 = cross(vh, t1);
    let r = sqrt(u1);
    let phi = 2.0 * PI * u2;
    let p1 = r * cos(phi);
    let sh = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - sh) * sqrt(max(1.0 - p1 * p1, 0.0)) + sh * r * sin(phi);
    let lift = sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0));
    let nh = p1 * t1 + p2 * t2 + lift * vh;
    let m = vec3<f32>(s.x * nh.x, s.y * nh.y, max(nh.z, 0.0));
    return m / max(length(m), DIV_EPSILON);
}

// Radiance arriving from world direction d: the uniform environment plus the map.
fn walk_arriving(d: vec3<f32>) -> vec3<f32> {
    return arriving(d, HAS_ENVIRONMENT == 1u, globals.environment.xyz, IBL != 0u, env_radiance, env_sampler, env.rotation, env.intensity);
}

// One walk entering along v (local wi, wi.z > 0) on a conductor of Schlick F0 `f0`: the
// escapes from the first event on times the arriving radiance, and next-event estimates
// to the first `n_lights` lights from the second event on (src/walk trace with the
// callbacks of src/cpu/truth.rs estimate). An upward ray deposits its escape mass and
// continues with the rest, down to a Russian roulette (src/walk/mod.rs).
fn walk_estimate(frame: mat3x3<f32>, wi: vec3<f32>, f0: vec3<f32>, s: vec2<f32>, n_lights: u32, rng: ptr<function, u32>) -> vec3<f32> {
    let to_local = transpose(frame);
    var x = vec3<f32>(0.0);
    var w = vec3<f32>(1.0);
    var dir = -wi;
    var c = 1.0;
    var carry = 1.0;
    var order = 0u;
    loop {
        if dir.z > 0.0 {
            let escape = walk_g1(dir, c, s);
            if HAS_ENVIRONMENT == 1u || IBL != 0u {
                x += (carry * escape) * w * walk_arriving(frame * dir);
            }
            carry *= 1.0 - escape;
            if carry <= 0.0 {
                break;
            }
        }
        if order >= WALK_MAX_EVENTS {
            break;
        }
        c = walk_next_height(dir, c, rng_uniform(rng), s);
        order += 1u;
        let wi_k = -dir;
        if HAS_LIGHTS == 1u && order >= 2u {
            for (var k = 0u; k < n_lights; k++) {
                let l = to_local * lights[k].direction.xyz;
                if l.z <= 0.0 {
                    continue;
                }
                let p = walk_phase(wi_k, l, s);
                if p.x <= 0.0 {
                    continue;
                }
                let base = carry * p.x * walk_pow(c, walk_lambda(l, s));
                x += base * w * f_schlick(f0, p.y) * lights[k].radiance.xyz;
            }
        }
        let u1 = rng_uniform(rng);
        let u2 = rng_uniform(rng);
        let m = walk_sample_visible_normal(wi_k, s, u1, u2);
        w *= f_schlick(f0, max(dot(wi_k, m), 0.0));
        dir = dir - 2.0 * dot(dir, m) * m;
        if carry < WALK_RR_BELOW {
            if rng_uniform(rng) * WALK_RR_BELOW < carry {
                carry = WALK_RR_BELOW;
            } else {
                break;
            }
        }
    }
    return x;
}

// The coating walk (src/walk/coating.rs, name for name): the truth for a ball's dielectric
// part, a rough dielectric interface of relative index eta over a Lambertian base of
// albedo rho, each microfacet event reflecting with probability F (the exact dielectric
// Fresnel) and refracting otherwise (Heitz et al. 2016, section 5, the dielectric
// microsurface), internal and total internal reflection included. Each side has its own
// frame, +z pointing away from the other medium (outside: the macro normal; inside: down,
// towards the base); crossing the interface negates the direction and turns the height c
// into 1 - c. Only Russian roulette ends a path early; COATING_MAX_ORDER is a guard.

// Events after which a coating path is cut (src/walk MAX_ORDER, the CPU walk's guard
// against a path stuck at the bottom of the surface; never reached in practice).
const COATING_MAX_ORDER: u32 = 10000u;

// A path through the coating: its direction in the frame of its side, its height C1(h) in
// that frame, its side, and its interface events so far.
struct CoatingPath {
    dir: vec3<f32>,
    c: f32,
    inside: bool,
    order: u32,
}

// A path entering the coating along wi (outside frame, wi.z > 0, pointing back along the
// arriving ray).
fn coating_path(wi: vec3<f32>) -> CoatingPath {
    return CoatingPath(-wi, 1.0, false, 0u);
}

// Whether an upward ray of the path escapes its side's surface (one draw, G1); a ray at
// or below the horizon hits without a draw.
fn coating_escapes(path: ptr<function, CoatingPath>, alpha: f32, rng: ptr<function, u32>) -> bool {
    if (*path).dir.z <= 0.0 {
        return false;
    }
    return rng_uniform(rng) < walk_g1((*path).dir, (*path).c, vec2<f32>(alpha));
}

// The next event's height, given that the ray hits (src/walk/coating.rs Coating::walk).
fn coating_hit(path: ptr<function, CoatingPath>, alpha: f32, rng: ptr<function, u32>) {
    (*path).c = walk_next_height((*path).dir, (*path).c, rng_uniform(rng), vec2<f32>(alpha));
    (*path).order += 1u;
}

// The relative index across the interface from the path's side (Event::eta).
fn event_eta(inside: bool, eta: f32) -> f32 {
    return select(eta, 1.0 / max(eta, DIV_EPSILON), inside);
}

// Snell's refraction of the ray direction dir (dir.m < 0) through the microfacet of unit
// normal m into the side of relative index eta = n_t / n_i: t = dir / eta + (cos_i / eta
// - cos_t) m (src/walk/coating.rs refract; WGSL's builtin takes that name). w: 1 where it
// refracts, 0 past the critical angle.
fn coating_refract(dir: vec3<f32>, m: vec3<f32>, eta: f32) -> vec4<f32> {
    let cos_i = clamp(-dot(dir, m), 0.0, 1.0);
    let r = 1.0 / max(eta, DIV_EPSILON);
    let sin2_t = r * r * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return vec4<f32>(0.0);
    }
    let cos_t = sqrt(1.0 - sin2_t);
    return vec4<f32>(normalize(r * dir + (r * cos_i - cos_t) * m), 1.0);
}

// The event's scattering: a microfacet normal visible from the arriving direction, then
// reflection with probability F(wi.m), refraction otherwise (which flips the frame).
fn coating_scatter(path: ptr<function, CoatingPath>, alpha: f32, eta: f32, rng: ptr<function, u32>) {
    let dir = (*path).dir;
    let wi_k = -dir;
    let u1 = rng_uniform(rng);
    let u2 = rng_uniform(rng);
    let m = walk_sample_visible_normal(wi_k, vec2<f32>(alpha), u1, u2);
    let eta_side = event_eta((*path).inside, eta);
    if rng_uniform(rng) >= fresnel_dielectric(dot(wi_k, m), eta_side) {
        let t = coating_refract(dir, m, eta_side);
        if t.w > 0.0 {
            (*path).inside = !(*path).inside;
            (*path).c = max(1.0 - (*path).c, WALK_TINY);
            (*path).dir = -t.xyz;
            return;
        }
    }
    (*path).dir = dir - 2.0 * dot(dir, m) * m;
}

// The dielectric microsurface's transmission phase function (Walter et al. 2007, eqs. 16
// and 21): from wi into the other side along wo (wo.z < 0 in the same frame) across eta =
// n_t / n_i, h = -(wi + eta wo) / |wi + eta wo| turned up, p = (1 - F(wi.h)) D_wi(h) eta^2
// |wo.h| / (wi.h + eta wo.h)^2; 0 where h does not separate the two.
fn transmission_phase(wi: vec3<f32>, wo: vec3<f32>, eta: f32, alpha: f32) -> f32 {
    let sum = wi + eta * wo;
    let len = length(sum);
    if len <= DIV_EPSILON {
        return 0.0;
    }
    var h = -sum / len;
    if h.z < 0.0 {
        h = -h;
    }
    let cos_i = dot(wi, h);
    let cos_o = dot(wo, h);
    if cos_i <= 0.0 || cos_o >= 0.0 {
        return 0.0;
    }
    let visible = cos_i * d_ggx(h.z, alpha) / max(walk_projected_area(wi, vec2<f32>(alpha)), DIV_EPSILON);
    let d = cos_i + eta * cos_o;
    let denominator = max(d * d, DIV_EPSILON);
    return (1.0 - fresnel_dielectric(cos_i, eta)) * visible * eta * eta * (-cos_o) / denominator;
}

// The density of leaving an event at height c, arrived along wi_k (its side's frame),
// towards the outside direction l (l.z > 0) and escaping along it (Event::towards):
// outside, the reflection's phase function times F times the escape from c; inside, the
// transmission's towards -l times the escape from the flipped height 1 - c.
fn event_towards(wi_k: vec3<f32>, c: f32, inside: bool, l: vec3<f32>, alpha: f32, eta: f32) -> f32 {
    if inside {
        let p = transmission_phase(wi_k, -l, event_eta(true, eta), alpha);
        return p * walk_g1(l, max(1.0 - c, WALK_TINY), vec2<f32>(alpha));
    }
    let p = walk_phase(wi_k, l, vec2<f32>(alpha));
    return p.x * fresnel_dielectric(p.y, eta) * walk_g1(l, c, vec2<f32>(alpha));
}

// Next-event estimation at the path's latest event towards the first n_lights lights
// (Gather::event): each light's radiance times the event's density towards it.
fn gather_event(to_local: mat3x3<f32>, path: CoatingPath, alpha: f32, eta: f32, n_lights: u32) -> vec3<f32> {
    var x = vec3<f32>(0.0);
    for (var k = 0u; k < n_lights; k++) {
        let l = to_local * lights[k].direction.xyz;
        if l.z <= 0.0 {
            continue;
        }
        let p = event_towards(-path.dir, path.c, path.inside, l, alpha, eta);
        x += p * lights[k].radiance.xyz;
    }
    return x;
}

// Whether light arriving from the outside direction l reaches the base (one draw): the
// walk from l stopped at its first arrival at the base, false where it leaves first. Its
// mean is the coating's transmittance tau(l), the interface's multiple scattering
// included.
fn reaches_base(l: vec3<f32>, alpha: f32, eta: f32, rng: ptr<function, u32>) -> bool {
    var path = coating_path(l);
    var reached = false;
    loop {
        if coating_escapes(&path, alpha, rng) {
            reached = path.inside;
            break;
        }
        if path.order >= COATING_MAX_ORDER {
            break;
        }
        coating_hit(&path, alpha, rng);
        coating_scatter(&path, alpha, eta, rng);
    }
    return reached;
}

// Each light's reaches_base draw, made at the path's first arrival at the base: bit k for
// light k (MAX_LIGHTS = 16 fits a u32).
fn reaches_base_bits(to_local: mat3x3<f32>, alpha: f32, eta: f32, n_lights: u32, rng: ptr<function, u32>) -> u32 {
    var bits = 0u;
    for (var k = 0u; k < n_lights; k++) {
        let l = to_local * lights[k].direction.xyz;
        if l.z <= 0.0 {
            continue;
        }
        if reaches_base(l, alpha, eta, rng) {
            bits |= 1u << k;
        }
    }
    return bits;
}

// The light the Lambertian base sends back towards the lights per unit of the arriving
// path's weight before its albedo (Gather::base): tau(l) mu_l / (pi eta^2) times each
// light's radiance, tau drawn (bit k of `reached`).
fn gather_base(to_local: mat3x3<f32>, reached: u32, eta: f32, n_lights: u32) -> vec3<f32> {
    var x = vec3<f32>(0.0);
    let eta2 = max(eta * eta, DIV_EPSILON);
    for (var k = 0u; k < n_lights; k++) {
        if (reached & (1u << k)) == 0u {
            continue;
        }
        let l = to_local * lights[k].direction.xyz;
        x += (l.z / (PI * eta2)) * lights[k].radiance.xyz;
    }
    return x;
}

// Russian roulette on a path's weights (src/walk/coating.rs russian_roulette): below
// WALK_RR_BELOW (their largest) the path survives with probability max / WALK_RR_BELOW and
// its weights are divided by it; whether it survives (a path of zero weights does not).
fn russian_roulette(w: ptr<function, vec3<f32>>, rng: ptr<function, u32>) -> bool {
    let m = max((*w).x, max((*w).y, (*w).z));
    if m >= WALK_RR_BELOW {
        return true;
    }
    if m <= 0.0 {
        return false;
    }
    if rng_uniform(rng) * WALK_RR_BELOW >= m {
        return false;
    }
    *w *= WALK_RR_BELOW / max(m, DIV_EPSILON);
    return true;
}

// A direction leaving the Lambertian base towards the interface, inside frame (z < 0),
// cosine-distributed: r = sqrt(u1), phi = 2 pi u2.
fn lambertian_towards_interface(u1: f32, u2: f32) -> vec3<f32> {
    let r = sqrt(u1);
    let phi = 2.0 * PI * u2;
    return vec3<f32>(r * cos(phi), r * sin(phi), -sqrt(max(1.0 - u1, 0.0)));
}

// One walk through the coating from the view (local wi, wi.z > 0) over a base of albedo
// rho (src/walk/coating.rs Coating::estimate, with the exits of src/cpu/truth.rs
// estimate_coating): every order, the coating's single scattering included. Before the
// first arrival at the base, next-event estimates at each interface event; from it on,
// each arrival's weight times rho tau(l) mu_l / (pi eta^2) towards each light, tau drawn by
// reaches_base once a light and walk; the exit times the radiance arriving from its
// direction.
fn coating_walk(frame: mat3x3<f32>, wi: vec3<f32>, rho: vec3<f32>, alpha: f32, eta: f32, n_lights: u32, rng: ptr<function, u32>) -> vec3<f32> {
    let to_local = transpose(frame);
    var x = vec3<f32>(0.0);
    var w = vec3<f32>(1.0);
    var path = coating_path(wi);
    var at_base = false;
    var reached = 0u;
    loop {
        if coating_escapes(&path, alpha, rng) {
            if !path.inside {
                if HAS_ENVIRONMENT == 1u || IBL != 0u {
                    x += w * walk_arriving(frame * path.dir);
                }
                break;
            }
            // Down through the medium to the base, and back up to the interface.
            if HAS_LIGHTS == 1u {
                if !at_base {
                    reached = reaches_base_bits(to_local, alpha, eta, n_lights, rng);
                }
                x += w * rho * gather_base(to_local, reached, eta, n_lights);
            }
            at_base = true;
            w *= rho;
            if !russian_roulette(&w, rng) {
                break;
            }
            let u1 = rng_uniform(rng);
            let u2 = rng_uniform(rng);
            path.dir = lambertian_towards_interface(u1, u2);
            path.c = 1.0;
            continue;
        }
        if path.order >= COATING_MAX_ORDER {
            break;
        }
        coating_hit(&path, alpha, rng);
        if HAS_LIGHTS == 1u && !at_base {
            x += w * gather_event(to_local, path, alpha, eta, n_lights);
        }
        coating_scatter(&path, alpha, eta, rng);
    }
    return x;
}

// Whether truth ball b walks its anisotropic (stretched) microsurface (lighting.wgsl
// has_anisotropy; src/cpu/model.rs anisotropic_frame): compiled out with HAS_ANISOTROPY = 0.
fn walk_has_anisotropy(b: Ball) -> bool {
    return HAS_ANISOTROPY == 1u && b.anisotropy_alpha_t > b.anisotropy_alpha_b;
}

// Whether truth ball b has a clear coat (coating.wgsl has_clearcoat): compiled out with
// HAS_CLEARCOAT = 0.
fn walk_has_clearcoat(b: Ball) -> bool {
    return HAS_CLEARCOAT == 1u && b.clearcoat > 0.0;
}

// One estimate of the radiance leaving truth ball b at unit normal n towards v, lit by
// the first `n_lights` lights (what src/cpu/truth.rs single_fixed + estimate give, with
// the metal's environment single scattering drawn instead of tabulated): the metal's part
// (the lights' single scattering exactly, then walk_estimate) and the dielectric's
// (coating_walk, every order) mixed by metallic (Ball.metallic). A pure metal draws no
// coating walk and shades as before it had one. An anisotropic ball walks its metal on
// the stretched surface in the ball's tangent frame (its coating stays isotropic); a
// clear-coated ball is walked whole under its coat (clearcoat_walk).
fn shade_truth(b: Ball, n: vec3<f32>, v: vec3<f32>, n_lights: u32, rng: ptr<function, u32>) -> vec3<f32> {
    let mu_o = dot(n, v);
    if mu_o <= 0.0 {
        return vec3<f32>(0.0);
    }
    let roughness = b.roughness;
    let alpha = alpha_from_roughness(roughness);
    var frame = duff_frame(n);
    var s = vec2<f32>(alpha);
    if walk_has_anisotropy(b) {
        frame = ball_tangent_frame(n, vec2<f32>(b.anisotropy_cos, b.anisotropy_sin));
        s = vec2<f32>(b.anisotropy_alpha_t, b.anisotropy_alpha_b);
    }
    let wi = transpose(frame) * v;
    if walk_has_clearcoat(b) {
        return clearcoat_walk(b, frame, wi, s, rng);
    }
    // A part no ball of the pipeline has is compiled out (HAS_METAL, HAS_DIELECTRIC); a
    // partial metal walks its coating first, then its metal.
    let metallic = b.metallic;
    if HAS_METAL == 0u || metallic <= 0.0 {
        return coating_walk(frame, wi, b.diffuse, alpha, b.eta, n_lights, rng);
    }
    if HAS_DIELECTRIC == 0u || metallic >= 1.0 {
        return shade_truth_metal(b, n, v, frame, s, n_lights, rng);
    }
    let coated = coating_walk(frame, wi, b.diffuse, alpha, b.eta, n_lights, rng);
    let metal = shade_truth_metal(b, n, v, frame, s, n_lights, rng);
    return metallic * metal + (1.0 - metallic) * coated;
}

// The metal's part of shade_truth (src/cpu/truth.rs single_fixed and estimate_metal): the
// lights' single scattering exactly (f_micro with Schlick F, GGX D, height-correlated
// Smith G; f_micro_aniso on an anisotropic surface) and one walk_estimate in `frame`.
fn shade_truth_metal(b: Ball, n: vec3<f32>, v: vec3<f32>, frame: mat3x3<f32>, s: vec2<f32>, n_lights: u32, rng: ptr<function, u32>) -> vec3<f32> {
    let roughness = b.roughness;
    let f0 = b.f0;
    let to_local = transpose(frame);
    let wi = to_local * v;
    let mu_o = dot(n, v);
    var lo = vec3<f32>(0.0);
    if HAS_LIGHTS == 1u {
        for (var k = 0u; k < n_lights; k++) {
            let l = lights[k].direction.xyz;
            let mu_i = dot(n, l);
            if mu_i <= 0.0 {
                continue;
            }
            let h = normalize(v + l);
            let fresnel = f_schlick(f0, dot(v, h));
            var spec: vec3<f32>;
            if walk_anisotropic(s) {
                let i = to_local * l;
                spec = f_micro_aniso(fresnel, wi, i, to_local * h, s.x, s.y, GEOMETRY_SMITH_CORRELATED);
            } else {
                spec = f_micro(fresnel, mu_o, mu_i, dot(n, h), roughness, GEOMETRY_SMITH_CORRELATED);
            }
            lo += spec * lights[k].radiance.xyz * mu_i;
        }
    }
    return lo + walk_estimate(frame, wi, f0, s, n_lights, rng);
}

// The clear coat's walk (src/walk/clearcoat.rs, name for name): a rough dielectric coat
// over the ball's whole material, walked as the coating is (Heitz et al. 2016, section 5),
// the ball's own walk at the bottom of the coat's medium: the conductor's (Schlick's F per
// event) or the plastic's (coating_exit), chosen per arrival with probability metallic.
// Every choice is drawn, so a lossless path weighs 1; only Russian roulette (or the
// COATING_MAX_ORDER guard) ends a path early. Frames as in the coating walk; a ray leaving
// the coat's interface downward along dir arrives at the base from (-dir.x, -dir.y,
// dir.z) in the base's own frame, and the base's exit o goes back up as (o.x, o.y, -o.z).
// The walk's exits: xyz the direction, w 1 where the path left and 0 where it ended inside.

// The conductor's walk with its exit drawn (conductor_exit): from wi on the surface of
// alphas s, Schlick's F of f0 at each event multiplied into w.
fn conductor_exit(wi: vec3<f32>, s: vec2<f32>, f0: vec3<f32>, w: ptr<function, vec3<f32>>, rng: ptr<function, u32>) -> vec4<f32> {
    var dir = -wi;
    var c = 1.0;
    var order = 0u;
    loop {
        if dir.z > 0.0 && rng_uniform(rng) < walk_g1(dir, c, s) {
            return vec4<f32>(dir, 1.0);
        }
        if order >= COATING_MAX_ORDER {
            return vec4<f32>(0.0);
        }
        c = walk_next_height(dir, c, rng_uniform(rng), s);
        order += 1u;
        let wi_k = -dir;
        let u1 = rng_uniform(rng);
        let u2 = rng_uniform(rng);
        let m = walk_sample_visible_normal(wi_k, s, u1, u2);
        *w *= f_schlick(f0, max(dot(wi_k, m), 0.0));
        dir = dir - 2.0 * dot(dir, m) * m;
        if !russian_roulette(w, rng) {
            return vec4<f32>(0.0);
        }
    }
    return vec4<f32>(0.0);
}

// The plastic's walk with its exit drawn (Coating::trace): through its rough interface of
// alpha and relative index eta over the Lambertian base of albedo rho, multiplied into w.
fn coating_exit(wi: vec3<f32>, rho: vec3<f32>, alpha: f32, eta: f32, w: ptr<function, vec3<f32>>, rng: ptr<function, u32>) -> vec4<f32> {
    var path = coating_path(wi);
    loop {
        if coating_escapes(&path, alpha, rng) {
            if !path.inside {
                return vec4<f32>(path.dir, 1.0);
            }
            *w *= rho;
            if !russian_roulette(w, rng) {
                return vec4<f32>(0.0);
            }
            let u1 = rng_uniform(rng);
            let u2 = rng_uniform(rng);
            path.dir = lambertian_towards_interface(u1, u2);
            path.c = 1.0;
            continue;
        }
        if path.order >= COATING_MAX_ORDER {
            return vec4<f32>(0.0);
        }
        coating_hit(&path, alpha, rng);
        coating_scatter(&path, alpha, eta, rng);
    }
    return vec4<f32>(0.0);
}

// The bare base's exit from wi (Layered::base): the conductor with probability metallic,
// else the plastic.
fn base_exit(b: Ball, wi: vec3<f32>, s: vec2<f32>, w: ptr<function, vec3<f32>>, rng: ptr<function, u32>) -> vec4<f32> {
    if rng_uniform(rng) < b.metallic {
        return conductor_exit(wi, s, b.f0, w, rng);
    }
    return coating_exit(wi, b.diffuse, alpha_from_roughness(b.roughness), b.eta, w, rng);
}

// The walk through the coat (Layered::through_coat): the coat's interface events, the base
// at the bottom of its medium.
fn through_coat(b: Ball, wi: vec3<f32>, s: vec2<f32>, w: ptr<function, vec3<f32>>, rng: ptr<function, u32>) -> vec4<f32> {
    let alpha = alpha_from_roughness(b.clearcoat_roughness);
    let eta = b.clearcoat_eta;
    var path = coating_path(wi);
    loop {
        if coating_escapes(&path, alpha, rng) {
            if !path.inside {
                return vec4<f32>(path.dir, 1.0);
            }
            // Down to the base and back up to the interface.
            let o = base_exit(b, vec3<f32>(-path.dir.x, -path.dir.y, path.dir.z), s, w, rng);
            if o.w == 0.0 || !russian_roulette(w, rng) {
                return vec4<f32>(0.0);
            }
            path.dir = vec3<f32>(o.x, o.y, -o.z);
            path.c = 1.0;
            continue;
        }
        if path.order >= COATING_MAX_ORDER {
            return vec4<f32>(0.0);
        }
        coating_hit(&path, alpha, rng);
        coating_scatter(&path, alpha, eta, rng);
    }
    return vec4<f32>(0.0);
}

// One path through a clear coat's ball from the view (Layered::sample, with the exit of
// src/cpu/truth.rs estimate_clearcoat): the coat with probability its weight, the bare
// base otherwise; the exit's weight times the radiance arriving from its direction. The
// lights are not walked (no next-event estimation through a coat: the renders refuse a
// coated truth ball under lights, src/render.rs check_clearcoat).
fn clearcoat_walk(b: Ball, frame: mat3x3<f32>, wi: vec3<f32>, s: vec2<f32>, rng: ptr<function, u32>) -> vec3<f32> {
    var w = vec3<f32>(1.0);
    var exit: vec4<f32>;
    if rng_uniform(rng) < b.clearcoat {
        exit = through_coat(b, wi, s, &w, rng);
    } else {
        exit = base_exit(b, wi, s, &w, rng);
    }
    if exit.w == 0.0 || !(HAS_ENVIRONMENT == 1u || IBL != 0u) {
        return vec3<f32>(0.0);
    }
    return w * walk_arriving(frame * exit.xyz);
}

// The running sum of the truth pixels (Rgba32Float: rgb the sum of estimates, a their
// count), read at the pixel by the accumulation (the previous frame's) and the resolve
// (this frame's): group 2 of the truth pipelines (src/gpu/truth.rs).
@group(2) @binding(0) var truth_sum: texture_2d<f32>;

struct TruthFragment {
    @location(0) sum: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

// The distance along the pixel's primary ray `ray` to the quad's own ball (not > 0 where
// the ray misses it): the truth traces one ray through each pixel's centre (its balls are
// not antialiased).
fn ball_distance(in: BallOut, ray: array<vec3<f32>, 2>) -> f32 {
    let b = ball_of(in);
    return intersect_sphere(ray[0], ray[1], b.center, b.radius);
}

// One more estimate at a truth ball's pixel: the previous sum plus this frame's, seeded
// by the pixel and the number of estimates so far (the sum's alpha), so the fragment
// stage reads no frame counter from a uniform buffer. A non-finite estimate (never seen;
// a guard) counts as 0 rather than poisoning the sum.
@fragment
fn fs_truth(in: BallOut) -> TruthFragment {
    let ray = primary_ray(in.position.xy);
    let t = ball_distance(in, ray);
    if !(t > 0.0) {
        discard;
    }
    let p = vec2<i32>(in.position.xy);
    let previous = textureLoad(truth_sum, p, 0i);
    var rng = rng_seed(u32(p.x), u32(p.y), u32(previous.w));
    let b = ball_of(in);
    let n = surface_normal(ray[0] + t * ray[1] - b.center, ray[1]);
    // The ball's emission is added at the first hit: no part of the walk.
    var x = shade_truth(b, n, -ray[1], in.counts.y, &rng) + b.emission;
    let finite = all(abs(x) < vec3<f32>(3.0e38));
    x = select(vec3<f32>(0.0), x, finite);
    var out: TruthFragment;
    out.sum = vec4<f32>(previous.rgb + x, previous.w + 1.0);
    out.depth = t * DEPTH_SCALE;
    return out;
}

// A ball of another model in the accumulation pass: it hides the truth balls behind it
// (depth) and leaves a zero sum, which the resolve skips.
@fragment
fn fs_truth_occluder(in: BallOut) -> TruthFragment {
    let ray = primary_ray(in.position.xy);
    let t = ball_distance(in, ray);
    if !(t > 0.0) {
        discard;
    }
    var out: TruthFragment;
    out.sum = vec4<f32>(0.0);
    out.depth = t * DEPTH_SCALE;
    return out;
}

// The mean of a truth pixel's estimates (sum / count) into the target; other pixels (a
// zero count) keep what the ball pass drew.
@fragment
fn fs_truth_resolve(in: VsOut) -> @location(0) Colour {
    let s = textureLoad(truth_sum, vec2<i32>(in.position.xy), 0i);
    if !(s.w > 0.0) {
        discard;
    }
    return output_value(s.rgb / s.w);
}
