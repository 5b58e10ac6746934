// lookup.wgsl (the lab's): what one read of the E table costs and returns, the shader's own
// manual bilinear read (lut_loss of lut.wgsl, four textureLoad) against the sampler's
// hardware filtering of the same texels (`shadeballs-lab bench`, lab/src/bench/kernel.rs).
// Uses `globals` (table dims) and `e_table`.

#import shadeballs::brdf::roughness_clamped
#import shadeballs::lut
#import shadeballs::bindings::{globals, e_table}

// x: reads per invocation; y: invocation count.
@group(1) @binding(0) var<uniform> lookup: vec4<u32>;
@group(1) @binding(1) var filtered_table: texture_2d<f32>;
@group(1) @binding(2) var bilinear: sampler;
// Per invocation: the sum of its reads of 1 - E.
@group(1) @binding(3) var<storage, read_write> lookup_out: array<f32>;

// PCG hash (Jarzynski & Olano 2020, "Hash Functions for GPU Rendering"); lab/src/bench/kernel.rs
// pcg_hash computes the same points on the CPU.
fn pcg_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// The top 24 bits as a float in [0, 1): exact in f32.
fn unit_float(h: u32) -> f32 {
    return f32(h >> 8u) / 16777216.0;
}

// 1 - E through the sampler: the same coordinates as lut_loss, then one bilinear sample
// (texel i is at u = (i + 0.5) / n; clamp-to-edge clamps like lut_texel_span).
fn lut_loss_filtered(mu: f32, roughness: f32) -> f32 {
    let r = roughness_clamped(roughness);
    let l = globals.lut;
    let x = mu_coord(mu, r * r, MU_AXIS);
    let p = vec2<f32>(x * l.mu_scale + l.mu_bias, r_coord(roughness, l) * l.r_scale + l.r_bias);
    let uv = (p + 0.5) / vec2<f32>(f32(l.mu_size), f32(l.r_size));
    return textureSampleLevel(filtered_table, bilinear, uv, 0.0).r;
}

// The next point of invocation `k`'s sequence: (mu, roughness), and the new state in z.
fn next_point(state: u32) -> vec3<u32> {
    let a = pcg_hash(state);
    let b = pcg_hash(a);
    return vec3<u32>(a, b, b);
}

@compute @workgroup_size(64)
fn lookup_none(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= lookup.y {
        return;
    }
    var state = id.x;
    var sum = 0.0;
    for (var s = 0u; s < lookup.x; s++) {
        let p = next_point(state);
        state = p.z;
        sum += unit_float(p.x) * unit_float(p.y);
    }
    lookup_out[id.x] = sum;
}

@compute @workgroup_size(64)
fn lookup_manual(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= lookup.y {
        return;
    }
    var state = id.x;
    var sum = 0.0;
    for (var s = 0u; s < lookup.x; s++) {
        let p = next_point(state);
        state = p.z;
        sum += lut_loss(e_table, lut_params(), unit_float(p.x), unit_float(p.y));
    }
    lookup_out[id.x] = sum;
}

@compute @workgroup_size(64)
fn lookup_filtered(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= lookup.y {
        return;
    }
    var state = id.x;
    var sum = 0.0;
    for (var s = 0u; s < lookup.x; s++) {
        let p = next_point(state);
        state = p.z;
        sum += lut_loss_filtered(unit_float(p.x), unit_float(p.y));
    }
    lookup_out[id.x] = sum;
}
