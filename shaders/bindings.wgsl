// bindings.wgsl: group 0, shared by the ball renderer and the table probe
// (src/gpu/resources.rs creates the matching layout).

@group(0) @binding(0) var<uniform> globals: Globals;
@group(0) @binding(1) var<uniform> balls: array<Ball, MAX_BALLS>;
@group(0) @binding(2) var<uniform> lights: array<Light, MAX_LIGHTS>;
// 1 - E(mu, roughness): R32Float, mu_size x r_size, row = roughness (Tables::stored_loss).
@group(0) @binding(3) var e_table: texture_2d<f32>;
// Row 0: 1 - E_avg(roughness) (Tables::stored_loss_avg); row 1: the roughness of each
// table row (f32, for the power-law read). R32Float, r_size x 2.
@group(0) @binding(4) var e_avg_table: texture_2d<f32>;
