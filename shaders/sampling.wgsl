// sampling.wgsl: the sampling maths the lobe (lighting.wgsl), the Monte Carlo
// (montecarlo.wgsl), the walk (walk.wgsl) and the prefilter (prefilter.wgsl) share, once.
// Library functions: no bindings, no override constants; the map, its sampler and the
// uniform environment are arguments. Each has an f64 twin of the same name in
// src/sampling.rs.

#define_import_path shadeballs::sampling
#import shadeballs::constants::{PI, DIV_EPSILON}
#import shadeballs::brdf::{d_ggx, d_ggx_aniso}
#import shadeballs::environment::{direction_to_uv, env_to_map}

// An orthonormal frame about unit n, as columns (tangent, bitangent, n) (Duff et al. 2017,
// "Building an Orthonormal Basis, Revisited", JCGT 6(1)).
fn duff_frame(n: vec3<f32>) -> mat3x3<f32> {
    let sign = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    return mat3x3<f32>(
        vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        vec3<f32>(b, sign + n.y * n.y * a, -n.y),
        n,
    );
}

// A reflected direction (local frame, normal +z) whose half vector follows GGX's
// distribution of normals visible from v (Heitz 2018, "Sampling the GGX Distribution of
// Visible Normals", JCGT 7(4), listing 1). May lie below the horizon.
fn sample_vndf(v: vec3<f32>, alpha: f32, u1: f32, u2: f32) -> vec3<f32> {
    return sample_vndf_aniso(v, alpha, alpha, u1, u2);
}

// The density per solid angle of sample_vndf's direction with half vector at n.h:
// G1(v) D(h) / (4 mu_o), G1 / mu_o written to stay finite at grazing v.
fn vndf_density(mu_o: f32, n_dot_h: f32, alpha: f32) -> f32 {
    let c = clamp(mu_o, 0.0, 1.0);
    let root = sqrt(c * c + alpha * alpha * (1.0 - c * c));
    let g1_over_mu = 2.0 / max(c + root, DIV_EPSILON);
    return d_ggx(n_dot_h, alpha) * g1_over_mu / 4.0;
}

// sample_vndf of anisotropic GGX, alpha_t along local x and alpha_b along y (Heitz 2018's
// listing 1 takes the two alphas: the stretch is per axis).
fn sample_vndf_aniso(v: vec3<f32>, alpha_t: f32, alpha_b: f32, u1: f32, u2: f32) -> vec3<f32> {
    let stretched = vec3<f32>(alpha_t * v.x, alpha_b * v.y, max(v.z, 0.0));
    let vh = stretched / max(length(stretched), DIV_EPSILON);
    let lensq = vh.x * vh.x + vh.y * vh.y;
    var t1 = vec3<f32>(1.0, 0.0, 0.0);
    if lensq > DIV_EPSILON {
        t1 = vec3<f32>(-vh.y, vh.x, 0.0) / sqrt(lensq);
    }
    let t2 = cross(vh, t1);
    let r = sqrt(u1);
    let phi = 2.0 * PI * u2;
    let p1 = r * cos(phi);
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * r * sin(phi);
    let nh = p1 * t1 + p2 * t2 + sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0)) * vh;
    let ne = vec3<f32>(alpha_t * nh.x, alpha_b * nh.y, max(nh.z, 0.0));
    let h = ne / max(length(ne), DIV_EPSILON);
    return 2.0 * dot(v, h) * h - v;
}

// The density per solid angle of sample_vndf_aniso's direction with local half vector h:
// G1(v) D(h) / (4 v_z), G1 / v_z written to stay finite at grazing v.
fn vndf_density_aniso(v: vec3<f32>, h: vec3<f32>, alpha_t: f32, alpha_b: f32) -> f32 {
    let c = clamp(v.z, 0.0, 1.0);
    let x = alpha_t * v.x;
    let y = alpha_b * v.y;
    let root = sqrt(c * c + x * x + y * y);
    let g1_over_mu = 2.0 / max(c + root, DIV_EPSILON);
    return d_ggx_aniso(h, alpha_t, alpha_b) * g1_over_mu / 4.0;
}

// A cosine-distributed direction about +z (Malley's method), density mu_i / pi.
fn sample_cosine(u1: f32, u2: f32) -> vec3<f32> {
    let r = sqrt(u1);
    let phi = 2.0 * PI * u2;
    return vec3<f32>(r * cos(phi), r * sin(phi), sqrt(max(1.0 - u1, 0.0)));
}

// The density per solid angle of a direction d (the map's frame) drawn by picking texel
// (i, j) of a w x h equirectangular map with probability p_texel, then uniformly in its
// (u, v) rectangle: p_texel w h / (2 pi^2 sin theta), the mapping's Jacobian (Pharr, Jakob &
// Humphreys, "Physically Based Rendering", 3rd ed., 2016, section 14.2.4).
fn equirect_density(p_texel: f32, d: vec3<f32>, size: vec2<f32>) -> f32 {
    let sin_theta = sqrt(max(1.0 - d.y * d.y, 0.0));
    return p_texel * size.x * size.y / (2.0 * PI * PI * max(sin_theta, DIV_EPSILON));
}

// The buckets of the guide of a CDF of n >= 1 values (the cutpoint method; LuminanceCdf's
// guide in src/environment/sampler.rs): n rounded up to a power of two, so that a uniform
// number's bucket, floor(x buckets), is exact in f32.
fn guide_buckets(n: u32) -> u32 {
    return 1u << (32u - countLeadingZeros(n - 1u));
}

// The power heuristic's estimate, exponent 2, of one sample of one of several strategies
// drawn equally often (Veach 1997, "Robust Monte Carlo Methods for Light Transport
// Simulation", PhD thesis, Stanford, section 9.2.4): the integrand f L mu_i over the drawing
// strategy's density `pdf_own`, weighted by pdf_own^2 / sum_k pdf_k(l)^2; written
// f L mu_i pdf_own / sum_k pdf_k(l)^2 (`pdf_square_sum`), 0 where that sum is below
// DIV_EPSILON^2 (a guard on densities, squared).
fn power_estimate(integrand: vec3<f32>, pdf_own: f32, pdf_square_sum: f32) -> vec3<f32> {
    let guard = DIV_EPSILON * DIV_EPSILON;
    return select(vec3<f32>(0.0), integrand * (pdf_own / max(pdf_square_sum, guard)), pdf_square_sum > guard);
}

// Radiance arriving from world direction d: the uniform environment `environment` where
// `has_uniform`, plus the map (its base level, turned by `rotation`, times `intensity`)
// where `has_map`.
fn arriving(
    d: vec3<f32>,
    has_uniform: bool,
    environment: vec3<f32>,
    has_map: bool,
    map: texture_2d<f32>,
    map_sampler: sampler,
    rotation: vec2<f32>,
    intensity: f32,
) -> vec3<f32> {
    var c = vec3<f32>(0.0);
    if has_uniform {
        c = environment;
    }
    if has_map {
        let uv = direction_to_uv(env_to_map(d, rotation));
        c += intensity * textureSampleLevel(map, map_sampler, uv, 0.0).rgb;
    }
    return c;
}
