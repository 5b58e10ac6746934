// bindings.wgsl: group 0, shared by the ball renderer and the table probe
// (src/gpu/bindings.rs creates the matching layout).

@group(0) @binding(0) var<uniform> globals: Globals;
// Every ball, for the full-screen path's loop (fs_main); the per-ball quads carry their
// ball in the instance buffer instead (vs_ball). A storage buffer: MAX_BALLS balls of 80
// bytes exceed the 64 KiB a uniform binding may hold.
@group(0) @binding(1) var<storage, read> balls: array<Ball>;
@group(0) @binding(2) var<uniform> lights: array<Light, MAX_LIGHTS>;
// 1 - E(mu, roughness) (Tables::stored_loss) as 2x2 blocks (lut.wgsl says how).
@group(0) @binding(3) var e_table: texture_2d<f32>;
// 1 - E_avg(roughness) (Tables::stored_loss_avg) and each row's roughness (lut.wgsl).
@group(0) @binding(4) var e_avg_table: texture_2d<f32>;

// The bound tables' read parameters, with the pipeline's MU_AXIS for the axis: a constant,
// so the compiler keeps only that axis's arithmetic (a select over all three cost about 1 %
// of a frame with the term; docs/benchmarks.md, "The term's cost").
fn lut_params() -> LutParams {
    var p = globals.lut;
    p.mu_axis = MU_AXIS;
    return p;
}
