//! The ball shading for other engines (`shadeballs export-shader`; docs/interop.md, "The
//! BRDF in another engine"): [`KULLA_CONTY`](super::KULLA_CONTY) (GGX, the table reads,
//! the multiple-scattering terms, the coating's forms) followed by [`BALL_FRAGMENT`], a
//! fragment entry point `fs_ball` that shades one ball of the engines' material (metallic,
//! base colour, roughness, IOR) under one directional light and a uniform environment, with
//! the Kulla-Conty term on the metal and on the coating and the physical layering of the
//! base. naga translates the WGSL to GLSL, HLSL and MSL.

/// The fragment program after the library: its bindings (group 0: the `BallUniforms`
/// block, the E table, the E_avg table, the ball's coating row) and `fs_ball`.
///
/// `BallUniforms` (std140, 16-byte fields; the host fills it once per ball):
/// - `lut`: the tables' `LutParams` (`Tables::layout().lut_params()`);
/// - `base_color_metallic`: linear base colour, metallic in `w`;
/// - `roughness_ior`: roughness, the coating's index, its average Fresnel `F_avg`
///   (`brdf::f_avg_dielectric`), the coating's `E_spec_avg` (`prepared::CoatingConstants`);
/// - `light_direction`: towards the light (unit), `light_radiance` its radiance, and
///   `environment` the uniform environment's radiance (the base read as the apparent
///   colour when `environment.w` is 1: the substrate solved in the shader, else taken as
///   the substrate's albedo);
/// - `viewport`: the target's width and height in pixels (the ball fills its middle).
///
/// The coating row (`coating_row`, 12 `vec4`s: E_F at `sqrt(mu) = k / 47`) is
/// `lut::coating_row` of the ball's roughness and index ([`crate::lut::COATING_ROW_LEN`]
/// values).
pub(crate) const BALL_FRAGMENT: &str = r#"
const EXPORT_COATING_ROW_LEN: u32 = 48u;

struct BallUniforms {
    lut: LutParams,
    base_color_metallic: vec4<f32>,
    roughness_ior: vec4<f32>,
    light_direction: vec4<f32>,
    light_radiance: vec4<f32>,
    environment: vec4<f32>,
    viewport: vec4<f32>,
}

@group(0) @binding(0) var<uniform> ball: BallUniforms;
@group(0) @binding(1) var e_table: texture_2d<f32>;
@group(0) @binding(2) var e_avg_table: texture_2d<f32>;
@group(0) @binding(3) var<uniform> coating_row: array<vec4<f32>, 12>;

// E_F(mu) of the coating: the row's values at sqrt(mu) = k / 47, linear between.
fn export_coating_albedo(mu: f32) -> f32 {
    let x = sqrt(clamp(mu, 0.0, 1.0)) * f32(EXPORT_COATING_ROW_LEN - 1u);
    let k = min(u32(floor(x)), EXPORT_COATING_ROW_LEN - 2u);
    let t = x - f32(k);
    let a = coating_row[k / 4u][k % 4u];
    let b = coating_row[(k + 1u) / 4u][(k + 1u) % 4u];
    return a + t * (b - a);
}

// Radiance towards v of the ball's point of unit normal n.
fn shade_ball(n: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    let base = ball.base_color_metallic.xyz;
    let metallic = ball.base_color_metallic.w;
    let roughness = ball.roughness_ior.x;
    let eta = ball.roughness_ior.y;
    let coat_f_avg = ball.roughness_ior.z;
    let e_spec_avg = ball.roughness_ior.w;
    let l = ball.light_direction.xyz;
    let mu_o = max(dot(n, v), 0.0);
    let mu_i = dot(n, l);
    let loss_o = lut_loss(e_table, ball.lut, mu_o, roughness);
    let loss_avg = lut_loss_avg(e_avg_table, ball.lut, roughness);
    let e_avg = 1.0 - loss_avg;
    let norm = 1.0 / max(PI * loss_avg, DIV_EPSILON);
    // The metal: GGX with Schlick's Fresnel of F0 = base, Kulla-Conty's lobe.
    let metal_f_add = f_add_preset(F_ADD_ACCURATE, base, GAMES202_EDGE_TINT, e_avg);
    // The coating: the dielectric's Fresnel, its own f_add, the base under it.
    let coat_f_add = f_add_accurate(vec3<f32>(coat_f_avg), e_avg).x;
    let e_spec_o = export_coating_albedo(mu_o) + coat_f_add * loss_o;
    var rho = base;
    if ball.environment.w == 1.0 {
        rho = substrate_albedo(base, e_spec_avg, eta);
    }
    // Uniform environment (the renderer's approximation, lighting.wgsl): the metal's albedo
    // F_avg E(mu_o) with its term, the coating's E_spec(mu_o) and its base.
    let e_o = 1.0 - loss_o;
    let metal_albedo = f_avg_schlick(base) * e_o + metal_f_add * loss_o;
    let coat_albedo = vec3<f32>(e_spec_o) + base_albedo_physical(rho, e_spec_o, e_spec_avg, eta);
    var radiance = ball.environment.xyz * mix(coat_albedo, metal_albedo, metallic);
    if mu_i > 0.0 && mu_o > 0.0 {
        let h = normalize(v + l);
        let loss_i = lut_loss(e_table, ball.lut, mu_i, roughness);
        let lobe = f_ms(loss_o, loss_i, norm);
        let metal = f_micro(f_schlick(base, dot(v, h)), mu_o, mu_i, dot(n, h), roughness,
            GEOMETRY_SMITH_CORRELATED) + metal_f_add * lobe;
        let fresnel = f_dielectric(dot(v, h), eta, FRESNEL_EXACT);
        let e_spec_i = export_coating_albedo(mu_i) + coat_f_add * loss_i;
        let coat = f_micro(vec3<f32>(fresnel), mu_o, mu_i, dot(n, h), roughness,
            GEOMETRY_SMITH_CORRELATED) + vec3<f32>(coat_f_add * lobe)
            + f_base_physical(rho, e_spec_o, e_spec_i, e_spec_avg, eta);
        radiance += mix(coat, metal, metallic) * ball.light_radiance.xyz * mu_i;
    }
    return radiance;
}

// One ball filling the middle of the viewport, seen from +z (orthographic): linear
// radiance, alpha 0 outside the ball.
@fragment
fn fs_ball(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let size = ball.viewport.xy;
    let radius = 0.45 * min(size.x, size.y);
    let p = (frag.xy - 0.5 * size) / radius;
    let r2 = dot(p, p);
    if r2 >= 1.0 {
        return vec4<f32>(0.0);
    }
    let n = vec3<f32>(p.x, -p.y, sqrt(1.0 - r2));
    return vec4<f32>(shade_ball(n, vec3<f32>(0.0, 0.0, 1.0)), 1.0);
}
"#;

/// The whole WGSL program: the library, then [`BALL_FRAGMENT`].
pub(crate) fn ball_program() -> String {
    format!("{}\n{BALL_FRAGMENT}", super::KULLA_CONTY)
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_row_length_is_the_tables_and_the_program_validates() {
        assert_eq!(crate::lut::COATING_ROW_LEN, 48);
        assert!(super::BALL_FRAGMENT.contains("array<vec4<f32>, 12>"));
    }
}
