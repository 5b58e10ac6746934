// prefilter.wgsl: prefiltering an environment map at load (src/gpu/environment.rs), the
// GPU twin of src/environment/prefilter.rs (same names, same samples). Each invocation
// writes one texel of one layer.

#define_import_path shadeballs::prefilter
#import shadeballs::constants::PI
#import shadeballs::brdf::{d_ggx, geometry_g}
#import shadeballs::environment::{direction_to_uv, uv_to_direction}
#import shadeballs::sampling::duff_frame

// The constants of src/environment/prefilter.rs, same names.
// generated from the Rust constants by src/gpu/tests/boundary.rs: do not edit
const KERNEL_SIZE: u32 = 64u; // environment::prefilter::KERNEL_SIZE
const FIS_LOD_BIAS: f32 = 0.0; // environment::prefilter::FIS_LOD_BIAS
const WEIGHT_EPSILON: f32 = 1e-30; // environment::prefilter::WEIGHT_EPSILON
const POLE_SIN_MIN: f32 = 0.0001; // environment::prefilter::POLE_SIN_MIN
const BRIGHT_MAX: u32 = 512u; // environment::prefilter::BRIGHT_MAX
// end of the generated constants

struct PrefilterParams {
    // Output layer size (texels), level-0 size of the map.
    size: vec4<u32>,
    // A convolution's source: the mip level's size, the level, the kernel layer. (The size
    // is passed rather than asked of textureDimensions: naga's GLSL output of that call
    // with a level does not compile on Mesa's GL.)
    source: vec4<u32>,
    // x: alpha of the specular layer (0: the mirror, read at lod y); y: that lod; z: its
    // roughness; w: the G (GEOMETRY_* of constants.wgsl) its samples are weighted by.
    layer: vec4<f32>,
    // x: samples a texel (specular_samples); y: the coarsest level filtered importance
    // sampling reads (fis_max_level); z: the bright texels (Bright::texels' length).
    limits: vec4<u32>,
}

// One texel of Bright (prefilter.rs): xyz its direction; rgb its excess radiance times its
// solid angle.
struct BrightTexel {
    direction: vec4<f32>,
    power: vec4<f32>,
}

@group(0) @binding(0) var radiance: texture_2d<f32>;
@group(0) @binding(1) var radiance_sampler: sampler;
@group(0) @binding(2) var output: texture_storage_2d<rgba16float, write>;
@group(0) @binding(3) var<uniform> params: PrefilterParams;
// The zonal kernels, KERNEL_SIZE samples per layer, four to a vec4 (kernels()).
@group(0) @binding(4) var<uniform> kernels: array<vec4<f32>, 160>;
// The map's bright texels (Bright in prefilter.rs), params.limits.z of them; `radiance` is
// then the map with them clipped, from the bright level down.
@group(0) @binding(5) var<uniform> bright: array<BrightTexel, BRIGHT_MAX>;

// The bits of i mirrored about the binary point (van der Corput).
fn radical_inverse(i: u32) -> f32 {
    return f32(reverseBits(i)) / 4294967296.0;
}

// The GGX-filtered radiance about r (n = v = r) at alpha: SPECULAR_SAMPLES half-vectors with
// pdf D cos(theta_h), each read at the mip level its solid angle covers (Krivanek & Colbert
// 2008), weighted by G(1, n.l) of `geometry` at `roughness` (prefilter_specular in
// prefilter.rs says why not n.l).
fn prefilter_specular(r: vec3<f32>, alpha: f32, roughness: f32, geometry: u32, samples: u32) -> vec3<f32> {
    let w0 = f32(params.size.z);
    let h0 = f32(params.size.w);
    let basis = duff_frame(r);
    let a2 = alpha * alpha;
    let max_lod = f32(params.limits.y);
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    for (var i = 0u; i < samples; i++) {
        let u1 = (f32(i) + 0.5) / f32(samples);
        let u2 = radical_inverse(i);
        let cos2 = (1.0 - u1) / (1.0 + (a2 - 1.0) * u1);
        let cos_h = sqrt(cos2);
        let sin_h = sqrt(max(1.0 - cos2, 0.0));
        let phi = 2.0 * PI * u2;
        let h = basis[0] * (sin_h * cos(phi)) + basis[1] * (sin_h * sin(phi)) + r * cos_h;
        let l = 2.0 * cos_h * h - r;
        let n_dot_l = dot(l, r);
        if n_dot_l <= 0.0 {
            continue;
        }
        let denom = cos2 * (a2 - 1.0) + 1.0;
        let d = a2 / (PI * denom * denom);
        let omega_s = 4.0 / (f32(samples) * d);
        let sin_l = max(sqrt(max(1.0 - l.y * l.y, 0.0)), POLE_SIN_MIN);
        let omega_p = 2.0 * PI * PI / (w0 * h0) * sin_l;
        let lod = clamp(0.5 * log2(omega_s / omega_p) + FIS_LOD_BIAS, 0.0, max_lod);
        let g = geometry_g(1.0, n_dot_l, roughness, geometry);
        sum += textureSampleLevel(radiance, radiance_sampler, direction_to_uv(l), lod).rgb * g;
        weight += g;
    }
    let excess = bright_specular(r, alpha, roughness, geometry);
    return (sum + excess * f32(samples)) / max(weight, WEIGHT_EPSILON);
}

// int L_b D G / 4 dw about r (n = v = r) for the bright texels' excess L_b, each texel a
// point of its solid angle (bright_specular in prefilter.rs).
fn bright_specular(r: vec3<f32>, alpha: f32, roughness: f32, geometry: u32) -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < params.limits.z; k++) {
        let t = dot(r, bright[k].direction.xyz);
        if t <= 0.0 {
            continue;
        }
        let n_dot_h = sqrt(0.5 * (1.0 + t));
        let lobe = d_ggx(n_dot_h, alpha) * geometry_g(1.0, t, roughness, geometry) / 4.0;
        sum += bright[k].power.rgb * lobe;
    }
    return sum;
}

// Kernel layer `layer` at t (0 below the horizon), linear between its samples (kernel_at).
fn kernel_at(layer: u32, t: f32) -> f32 {
    if t <= 0.0 {
        return 0.0;
    }
    let x = min(t, 1.0) * f32(KERNEL_SIZE - 1u);
    let i0 = min(u32(floor(x)), KERNEL_SIZE - 2u);
    let f = x - f32(i0);
    let k0 = layer * KERNEL_SIZE + i0;
    let a = kernels[k0 / 4u][k0 % 4u];
    let b = kernels[(k0 + 1u) / 4u][(k0 + 1u) % 4u];
    return a * (1.0 - f) + b * f;
}

// The kernel-weighted average of mip level `level` (at most CONVOLUTION_SOURCE_WIDTH wide)
// about unit n (prefilter_convolved). With n and a texel's direction w in polar angles,
// n.w = cos(theta_n) cos(theta_w) + sin(theta_n) sin(theta_w) cos(phi_w - phi_n): the
// polar part once per row, the azimuthal cosine by turning (cos, sin) of phi_w - phi_n one
// texel's angle a step (no trigonometry in the inner loop; the CPU twin takes the cosine
// directly, 1e-6 apart after 64 steps in f32).
fn prefilter_convolved(size: vec2<u32>, level: u32, layer: u32, n: vec3<f32>) -> vec3<f32> {
    let uv_n = direction_to_uv(n);
    let cos_n = cos(uv_n.y * PI);
    let sin_n = sin(uv_n.y * PI);
    let phi0 = (0.5 / f32(size.x) - uv_n.x) * 2.0 * PI;
    let step = 2.0 * PI / f32(size.x);
    let turn = vec2<f32>(cos(step), sin(step));
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    for (var j = 0u; j < size.y; j++) {
        let t0 = PI * f32(j) / f32(size.y);
        let t1 = PI * f32(j + 1u) / f32(size.y);
        let omega = 2.0 * PI / f32(size.x) * (cos(t0) - cos(t1));
        let theta = (f32(j) + 0.5) / f32(size.y) * PI;
        let a = cos_n * cos(theta);
        let b = sin_n * sin(theta);
        var dphi = vec2<f32>(cos(phi0), sin(phi0));
        for (var i = 0u; i < size.x; i++) {
            let w = kernel_at(layer, a + b * dphi.x) * omega;
            dphi = vec2<f32>(dphi.x * turn.x - dphi.y * turn.y, dphi.y * turn.x + dphi.x * turn.y);
            sum += textureLoad(radiance, vec2<i32>(i32(i), i32(j)), i32(level)).rgb * w;
            weight += w;
        }
    }
    if weight < WEIGHT_EPSILON {
        return vec3<f32>(0.0);
    }
    return sum / weight;
}

// The texel's direction, or none outside the layer.
fn texel_direction(id: vec3<u32>) -> vec3<f32> {
    let uv = (vec2<f32>(id.xy) + 0.5) / vec2<f32>(params.size.xy);
    return uv_to_direction(uv);
}

@compute @workgroup_size(8, 8)
fn specular_main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.size.x || id.y >= params.size.y {
        return;
    }
    let r = texel_direction(id);
    var value: vec3<f32>;
    if params.layer.x == 0.0 {
        value = textureSampleLevel(radiance, radiance_sampler, direction_to_uv(r), params.layer.y).rgb;
    } else {
        value = prefilter_specular(r, params.layer.x, params.layer.z, u32(params.layer.w), params.limits.x);
    }
    textureStore(output, id.xy, vec4<f32>(value, 1.0));
}

@compute @workgroup_size(8, 8)
fn convolved_main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.size.x || id.y >= params.size.y {
        return;
    }
    let n = texel_direction(id);
    let value = prefilter_convolved(params.source.xy, params.source.z, params.source.w, n);
    textureStore(output, id.xy, vec4<f32>(value, 1.0));
}
