// montecarlo.wgsl: the Monte Carlo of the model on the GPU (`render --backend montecarlo`;
// src/gpu/montecarlo.rs; docs/design/environment.md, "The Monte Carlo backend"), the f32
// mirror of src/cpu/montecarlo.rs, name for name: the lights evaluated directly, the
// environment by three strategies (GGX visible normals, cosine hemisphere, the map's
// luminance; a coated point's coat's visible normals a fourth) combined by the
// multi-sample balance heuristic (Veach & Guibas 1995,
// "Optimally Combining Sampling Techniques for Monte Carlo Rendering").
//
// Each pass draws every ball's quad with a depth test; a fragment of the nearest ball draws
// MC_SAMPLES estimates and merges their mean and sum of squared deviations with those of
// the passes before (read from the previous pair of Rgba32Float textures; Chan, Golub and
// LeVeque 1979, "Updating Formulae and a Pairwise Algorithm for Computing Sample
// Variances"). Differences from the CPU estimator: f32; the map's radiance is the f16
// texture's bilinear read; the generator is a PCG hash seeded per pixel and pass.

#define_import_path shadeballs::montecarlo
#import shadeballs::constants::{PI, DIV_EPSILON}
#import shadeballs::brdf::alpha_from_roughness
#import shadeballs::environment::{direction_to_uv, uv_to_direction, env_to_map}
#import shadeballs::sampling::{duff_frame, sample_vndf, sample_cosine, arriving, equirect_density, guide_buckets}
#import shadeballs::types::{Ball, BallOut, ball_of, HAS_ENVIRONMENT, HAS_LIGHTS, IBL, HAS_CLEARCOAT}
#import shadeballs::model::{ShadingPoint, shading_point, coated_point, model_brdf, pdf_vndf, pdf_vndf_lobe, sample_lobe, PART_WHOLE}
#import shadeballs::coating::has_clearcoat
#import shadeballs::clearcoat::clearcoat_begin
#import shadeballs::bindings::{globals, lights, env, env_radiance, env_sampler}
#import shadeballs::screen::{primary_ray, surface_normal, DEPTH_SCALE}
#import shadeballs::footprint::{ball_footprint, background_radiance}

// Estimates a fragment draws a pass (src/gpu/montecarlo.rs PASS_SAMPLES, or the last
// pass's rest): a pipeline-time constant, so no loop exit reads a uniform.
override MC_SAMPLES: u32 = 16u;

// Mirrors src/gpu/montecarlo.rs McParams.
struct McParams {
    // The render's seed, low and high 32 bits.
    seed: vec2<u32>,
    // The pass's index (0 for the first).
    pass_index: u32,
    // 1 where any environment radiance can be non-zero (else only the lights shade).
    lit: u32,
    // The map's texels across and down (luminance tables in mc_cdf).
    map_size: vec2<u32>,
    // The strategies drawn (STRATEGY_*): the map's where it has a sampler
    // (src/cpu/montecarlo.rs LuminanceCdf).
    strategies: u32,
    // Always 7: see estimate.
    shape: u32,
    // PART_WHOLE or PART_MULTIPLE: the whole model, or the term's lobe alone (the
    // reference for a real-time term; src/cpu/montecarlo.rs Part).
    part: u32,
    padding: u32,
}

// Bits of McParams.strategies.
const STRATEGY_VNDF: u32 = 1u;
const STRATEGY_COSINE: u32 = 2u;
const STRATEGY_MAP: u32 = 4u;

// Group 2 (src/gpu/montecarlo.rs layout): the previous pass's means (rgb; a: estimates so
// far) and sums of squared deviations (rgb), the parameters, and the luminance tables:
// the marginal (H values), then each row's CDF (W H), each texel's probability (W H), the
// marginal's guide (guide_buckets(H) + 1) and each row's (H (guide_buckets(W) + 1)).
@group(2) @binding(0) var mc_mean: texture_2d<f32>;
@group(2) @binding(1) var mc_m2: texture_2d<f32>;
@group(2) @binding(2) var<uniform> mc: McParams;
@group(2) @binding(3) var<storage, read> mc_cdf: array<f32>;

// The generator (Jarzynski and Olano 2020, "Hash Functions for GPU Rendering", JCGT
// 9(3)): PCG's state step and its RXS-M-XS output permutation, 32 bits.
fn mc_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// A pixel's stream for a pass: the seed, the pass and the pixel hashed in turn (the CPU's
// Rng::new(&[seed, px, py]): each pixel its own generator).
fn mc_seed(px: u32, py: u32) -> u32 {
    let s = mc_hash(mc.seed.y ^ mc_hash(mc.seed.x ^ 0x4d43u));
    return mc_hash(px ^ mc_hash(py ^ mc_hash(mc.pass_index ^ s)));
}

// Uniform in [0, 1) with 24 random bits; advances the stream.
fn mc_uniform(state: ptr<function, u32>) -> f32 {
    *state = *state * 747796405u + 2891336453u;
    let s = *state;
    let word = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    return f32(((word >> 22u) ^ word) >> 8u) * (1.0 / 16777216.0);
}

// Radiance arriving from world direction w: the uniform environment plus the map.
fn incident(w: vec3<f32>) -> vec3<f32> {
    return arriving(w, HAS_ENVIRONMENT == 1u, globals.environment.xyz, IBL != 0u, env_radiance, env_sampler, env.rotation, env.intensity);
}

// The first index in [0, count) of the CDF at mc_cdf[first] whose value exceeds x in
// [0, 1) (count if none), the CPU's partition_point(|c| c <= x), found through the CDF's
// guide at mc_cdf[guide_first] as lighting.wgsl's luminance_partition finds it.
fn partition_point(first: u32, guide_first: u32, count: u32, x: f32) -> u32 {
    let m = guide_buckets(count);
    let k = min(u32(x * f32(m)), m - 1u);
    var lo = u32(mc_cdf[guide_first + k]);
    var hi = u32(mc_cdf[guide_first + k + 1u]);
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if mc_cdf[first + mid] <= x {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return lo;
}

// A world direction drawn from the map's luminance tables (src/cpu/montecarlo.rs
// EnvSampler::sample); w = 0 where rounding lands on a texel of zero weight.
fn env_sample(u: vec4<f32>) -> vec4<f32> {
    let w = mc.map_size.x;
    let h = mc.map_size.y;
    // The guides follow the tables: the marginal's, then one of guide_buckets(w) + 1 a row.
    let guides = h + 2u * w * h;
    let row_guides = guides + guide_buckets(h) + 1u;
    let j = min(partition_point(0u, guides, h, u.x), h - 1u);
    let i = min(partition_point(h + j * w, row_guides + j * (guide_buckets(w) + 1u), w, u.y), w - 1u);
    if mc_cdf[h + w * h + j * w + i] <= 0.0 {
        return vec4<f32>(0.0);
    }
    let uv = vec2<f32>((f32(i) + u.z) / f32(w), (f32(j) + u.w) / f32(h));
    // The map's frame to the world's: the rotation's inverse (Environment::from_map).
    let d = env_to_map(uv_to_direction(uv), vec2<f32>(env.rotation.x, -env.rotation.y));
    return vec4<f32>(d, 1.0);
}

// The density per solid angle of env_sample at world direction l (EnvSampler::pdf).
fn env_pdf(l: vec3<f32>) -> f32 {
    let w = mc.map_size.x;
    let h = mc.map_size.y;
    let d = env_to_map(l, env.rotation);
    let uv = direction_to_uv(d);
    let fi = floor(uv.x * f32(w));
    let i = u32(fi - f32(w) * floor(fi / f32(w))) % w;
    let j = min(u32(max(floor(uv.y * f32(h)), 0.0)), h - 1u);
    return equirect_density(mc_cdf[h + w * h + j * w + i], d, vec2<f32>(f32(w), f32(h)));
}

// One sample's share of the multi-sample balance-heuristic estimator:
// f_r L mu_i / sum_k pdf_k(l) (src/cpu/montecarlo.rs Lighting::contribution).
fn contribution(b: Ball, p: ShadingPoint, l: vec3<f32>, alpha: f32) -> vec3<f32> {
    let mu_i = dot(p.n, l);
    if mu_i <= 0.0 {
        return vec3<f32>(0.0);
    }
    var pdf = pdf_vndf_lobe(p, l, alpha) + mu_i / PI;
    if (mc.strategies & STRATEGY_MAP) != 0u {
        pdf += env_pdf(l);
    }
    if HAS_CLEARCOAT == 1u && p.clearcoat {
        pdf += pdf_vndf(p, l, alpha_from_roughness(b.clearcoat_roughness));
    }
    if pdf <= DIV_EPSILON {
        return vec3<f32>(0.0);
    }
    return model_brdf(b, p, l) * incident(l) * (mu_i / pdf);
}

// The lights' exact contribution (f_r L mu_i) of the first n_lights lights.
fn direct(b: Ball, p: ShadingPoint, n_lights: u32) -> vec3<f32> {
    var lo = vec3<f32>(0.0);
    if HAS_LIGHTS == 1u {
        for (var k = 0u; k < n_lights; k++) {
            let l = lights[k].direction.xyz;
            lo += model_brdf(b, p, l) * lights[k].radiance.xyz * dot(p.n, l);
        }
    }
    return lo;
}

// A pass's estimates at one point: (the mean of MC_SAMPLES estimates of the environment's
// part, its sum of squared deviations), by Welford's running update per channel.
struct Estimates {
    mean: vec3<f32>,
    m2: vec3<f32>,
}

fn estimate(b: Ball, p: ShadingPoint, rng: ptr<function, u32>) -> Estimates {
    var out = Estimates(vec3<f32>(0.0), vec3<f32>(0.0));
    // The steps below under branches on the bits of mc.shape (uniform, all set by the
    // host): written without those branches, lavapipe (Mesa 22.3, LLVM 15) crashed the
    // process in its rasterizer threads running this shader (with every scene tried).
    if (mc.shape & 1u) != 0u && (mc.lit == 0u || p.mu_o <= 0.0) {
        return out;
    }
    var frame = mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0));
    if (mc.shape & 2u) != 0u {
        frame = duff_frame(p.n);
    }
    let v_local = transpose(frame) * p.v;
    var alpha = 0.5;
    if (mc.shape & 4u) != 0u {
        alpha = alpha_from_roughness(p.lobe.x);
    }
    // Each strategy under a branch on its bit of mc.strategies (uniform: all set but the
    // map's without a sampler).
    for (var k = 0u; k < MC_SAMPLES; k++) {
        var x = vec3<f32>(0.0);
        if (mc.strategies & STRATEGY_VNDF) != 0u {
            let u1 = mc_uniform(rng);
            let u2 = mc_uniform(rng);
            x += contribution(b, p, sample_lobe(p, frame, v_local, alpha, vec2<f32>(u1, u2)), alpha);
        }
        if (mc.strategies & STRATEGY_COSINE) != 0u {
            let u3 = mc_uniform(rng);
            let u4 = mc_uniform(rng);
            x += contribution(b, p, frame * sample_cosine(u3, u4), alpha);
        }
        if (mc.strategies & STRATEGY_MAP) != 0u {
            let u = vec4<f32>(mc_uniform(rng), mc_uniform(rng), mc_uniform(rng), mc_uniform(rng));
            let s = env_sample(u);
            if s.w > 0.0 {
                x += contribution(b, p, s.xyz, alpha);
            }
        }
        // A clear coat's own lobe, a fourth strategy at a coated point: its visible normals.
        if HAS_CLEARCOAT == 1u && p.clearcoat {
            let u5 = mc_uniform(rng);
            let u6 = mc_uniform(rng);
            let coat_alpha = alpha_from_roughness(b.clearcoat_roughness);
            x += contribution(b, p, frame * sample_vndf(v_local, coat_alpha, u5, u6), alpha);
        }
        // A non-finite estimate (a guard) counts as 0 rather than poisoning the sums.
        x = select(vec3<f32>(0.0), x, all(abs(x) < vec3<f32>(3.0e38)));
        let delta = x - out.mean;
        out.mean += delta / f32(k + 1u);
        out.m2 += delta * (x - out.mean);
    }
    return out;
}

struct McFragment {
    @location(0) mean: vec4<f32>,
    @location(1) m2: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

// One pass at a ball's pixel: MC_SAMPLES estimates merged with the previous passes'
// (Chan et al.: the means by their counts, the squared deviations plus delta^2 n_a n_b / n).
// The pixel's footprint is the ball renderer's (footprint.wgsl ball_footprint, under the
// pipeline's AA): near a silhouette the estimates are made along the ray through the covered
// part's centroid and mixed with the background (along the rest's) by the coverage, so only
// the ball's share carries noise (its squared deviations times the coverage squared), as
// the CPU estimator's Bins::view (docs/design/antialiasing.md, "Monte Carlo").
@fragment
fn fs_montecarlo(in: BallOut) -> McFragment {
    let b = ball_of(in);
    let f = ball_footprint(in.position.xy, b.center, b.radius);
    if !(f.t > 0.0) {
        discard;
    }
    let ray = primary_ray(f.hit);
    let px = vec2<i32>(in.position.xy);
    let before = textureLoad(mc_mean, px, 0i);
    let m2_before = textureLoad(mc_m2, px, 0i).rgb;
    var rng = mc_seed(u32(px.x), u32(px.y));
    let n = surface_normal(ray[0] + f.t * ray[1] - b.center, ray[1]);
    var p = shading_point(b, n, -ray[1]);
    p.part = mc.part;
    if has_clearcoat(b) {
        clearcoat_begin(b, n, -ray[1], b.ms);
        p = coated_point(b, p);
    }
    let drawn = estimate(b, p, &rng);
    var mean_b = direct(b, p, in.counts.y) + drawn.mean;
    // The ball's emission, exact (no part of the BRDF: the term's lobe alone has none).
    if mc.part == PART_WHOLE {
        mean_b += b.emission;
    }
    var m2_b = drawn.m2;
    // A loop of 0 or 1 iterations, as in ball_footprint: the background only where needed.
    for (var once = f.coverage < 1.0; once; once = false) {
        mean_b = mix(background_radiance(primary_ray(f.miss)[1]), mean_b, f.coverage);
        m2_b *= f.coverage * f.coverage;
    }
    let n_a = before.w;
    let n_b = f32(MC_SAMPLES);
    let count = n_a + n_b;
    let delta = mean_b - before.rgb;
    var out: McFragment;
    out.mean = vec4<f32>(before.rgb + delta * (n_b / count), count);
    out.m2 = vec4<f32>(m2_before + m2_b + delta * delta * (n_a * n_b / count), 0.0);
    out.depth = f.t * DEPTH_SCALE;
    return out;
}
