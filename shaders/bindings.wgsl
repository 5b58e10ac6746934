// bindings.wgsl: group 0, shared by the ball renderer and the table probe
// (src/gpu/resources.rs creates the matching layout).

@group(0) @binding(0) var<uniform> globals: Globals;
@group(0) @binding(1) var<uniform> balls: array<Ball, MAX_BALLS>;
@group(0) @binding(2) var<uniform> lights: array<Light, MAX_LIGHTS>;
// 1 - E(mu, roughness) (Tables::stored_loss), mu_size x r_size, row = roughness, as 2x2
// blocks: Rgba32Float texel (i, j) holds texels (i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1)
// (loss_quad in lut.wgsl; src/gpu/resources.rs loss_quads).
@group(0) @binding(3) var e_table: texture_2d<f32>;
// Row 0: 1 - E_avg(roughness) (Tables::stored_loss_avg); row 1: the roughness of each
// table row (f32, for the power-law read). R32Float, r_size x 2.
@group(0) @binding(4) var e_avg_table: texture_2d<f32>;
