// probe.wgsl: evaluates lut_e and lut_e_avg, the functions the renderer reads the tables
// with, on an N x N grid (mu = i / (N - 1), roughness = j / (N - 1)); `shadeballs probe`.

#define_import_path shadeballs::probe
#import shadeballs::brdf::roughness_clamped
#import shadeballs::lut::{lut_e, lut_e_avg, lut_loss_row}
#import shadeballs::bindings::{globals, e_table, e_avg_table}

// x: N; y: the number of rows (probe_rows_main).
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
    probe_out[k] = vec2<f32>(lut_e(e_table, globals.lut, mu, roughness), lut_e_avg(e_avg_table, globals.lut, roughness));
}

// Along a scene's own rows (src/lut/rows.rs): row j (roughness in row 1 of e_avg_table),
// mu = i / (N - 1), read as a ball reads it: lut_loss_row with no weight on the next row;
// E_avg is the row's own (row 0 of e_avg_table).
@compute @workgroup_size(64)
fn probe_rows_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let n = probe_grid.x;
    let k = id.x;
    if n < 2u || k >= n * probe_grid.y {
        return;
    }
    let j = k / n;
    let mu = f32(k % n) / f32(n - 1u);
    let r = roughness_clamped(textureLoad(e_avg_table, vec2<u32>(j, 1u), 0).r);
    let row = vec3<f32>(f32(j), 0.0, r * r);
    let loss_avg = textureLoad(e_avg_table, vec2<u32>(j, 0u), 0).r;
    probe_out[k] = vec2<f32>(1.0 - lut_loss_row(e_table, globals.lut, mu, row), 1.0 - loss_avg);
}
