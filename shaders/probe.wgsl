// probe.wgsl: evaluates lut_e and lut_e_avg, the functions the renderer reads the tables
// with, on an N x N grid (mu = i / (N - 1), roughness = j / (N - 1)); `shadeballs probe`.

// x: N.
@group(1) @binding(0) var<uniform> probe_grid: vec4<u32>;
// Per sample (row-major, row = roughness): (E, E_avg).
@group(1) @binding(1) var<storage, read_write> probe_out: array<vec2<f32>>;

@compute @workgroup_size(64)
fn probe_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let n = probe_grid.x;
    let k = id.x;
    if n < 2u || k >= n * n {
        return;
    }
    let mu = f32(k % n) / f32(n - 1u);
    let roughness = f32(k / n) / f32(n - 1u);
    probe_out[k] = vec2<f32>(lut_e(mu, roughness), lut_e_avg(roughness));
}
