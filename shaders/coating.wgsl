// coating.wgsl: the dielectric part of a ball's shading, a rough coating of index eta over
// a Lambertian base (docs/design/materials.md). Mirrored in f64 by src/cpu/coating.rs
// (same model, same order of terms).

#define_import_path shadeballs::coating
#import shadeballs::constants::{PI, DIV_EPSILON, FRESNEL_SCHLICK}
#import shadeballs::brdf::alpha_from_roughness
#import shadeballs::brdf::{f_micro, f_ms, f_dielectric, f0_from_ior, term_turquin, term_fdez_aguera}
#import shadeballs::brdf::{f_base_constant, f_base_gltf, f_base_view_only, f_base_reciprocal, f_base_physical}
#import shadeballs::brdf::{base_albedo_constant, base_albedo_gltf, base_albedo_view_only, base_albedo_physical}
#import shadeballs::brdf::{clearcoat_through_physical, clearcoat_base_cosine, clearcoat_base_schlick_avg, f_avg_schlick}
#import shadeballs::lut::{lut_loss_row, lut_row_unpack}
#import shadeballs::environment::{env_to_map, specular_direction, env_specular, env_irradiance, env_multiple}
#import shadeballs::types::{Ball, GEOMETRY, HAS_ENVIRONMENT, HAS_LIGHTS, IBL, COATING_ROW_LEN}
#import shadeballs::types::{TERM_FDEZ_AGUERA, DOMINANT_DIRECTION, by_term, by_term_f32}
#import shadeballs::types::{LAYERING_CONSTANT, LAYERING_GLTF, LAYERING_VIEW_ONLY, LAYERING_RECIPROCAL, LAYERING_PHYSICAL}
#import shadeballs::types::{COAT_FORM_PHYSICAL, COAT_FORM_FILAMENT, COAT_FORM_GLTF, HAS_CLEARCOAT}
#import shadeballs::bindings::{globals, lights, e_table, lut_params, env, env_sampler}
#import shadeballs::bindings::{env_layer_set, env_specular_layers, env_convolved, coating_rows}

// The coating's single-scattering albedo E_F(mu) from the ball's row of coating_rows
// (src/lut/coating.rs): values at sqrt(mu) = k / (COATING_ROW_LEN - 1), linear between.
fn coating_albedo(row: u32, mu: f32) -> f32 {
    let x = sqrt(clamp(mu, 0.0, 1.0)) * f32(COATING_ROW_LEN - 1u);
    let k = min(u32(floor(x)), COATING_ROW_LEN - 2u);
    let t = x - f32(k);
    let first = row * COATING_ROW_LEN + k;
    let a = coating_rows[first];
    return a + t * (coating_rows[first + 1u] - a);
}

// A clear coat's point and the share of the base's light it lets through, read here by
// the base's shading and formed by clearcoat.wgsl clearcoat_begin (src/cpu/clearcoat.rs).
// What a coated point forms once per pixel (clearcoat_begin), for the base's shading and
// the coat's own.
struct ClearcoatPoint {
    // The view's part of the weight of a Lambertian base's light: (1 - E_c(mu_o))
    // clearcoat_inside_scale per channel (physical form), 1 (the engines').
    out: vec3<f32>,
    // The same for a glossy base's light (a metal's lobe, a plastic's specular):
    // (1 - E_c(mu_o)) clearcoat_lobe_scale (physical form), 1 (the engines').
    out_lobe: vec3<f32>,
    // The coat's directional albedo at the view under its form: E_c(mu_o) (physical),
    // E_F(mu_o) (Filament's), F_c(mu_o) E(mu_o) (glTF's).
    albedo_o: f32,
    // The Lambertian base's weight under uniform light and the map.
    environment: vec3<f32>,
    // The glossy base's weight under uniform light and the map.
    environment_lobe: vec3<f32>,
    // The coat's 1 - E(mu_o) (its Fresnel-free table).
    loss_o: f32,
    // The coat's single scattering E_F(mu_o), its row's.
    e_f_o: f32,
    // The coat's Fresnel at the view.
    fresnel_o: f32,
    // The weight of the coat's Kulla-Conty term (physical form only).
    ms: f32,
}

// The point being shaded (clearcoat_begin), read by clearcoat_through and the coat's own
// shading. (A private, as coating.wgsl's coating_lobe: the base's shading keeps its
// signatures.)
var<private> clearcoat_point: ClearcoatPoint;

// Whether ball b has a clear coat.
fn has_clearcoat(b: Ball) -> bool {
    return HAS_CLEARCOAT == 1u && b.clearcoat > 0.0;
}

// The coat's specular albedo E_c(mu) under the physical form: its row's E_F(mu) and its
// term's f_add (1 - E(mu)) (ms its weight).
fn clearcoat_albedo(b: Ball, mu: f32, ms: f32) -> f32 {
    var loss = 0.0;
    if ms > 0.0 {
        loss = lut_loss_row(e_table, lut_params(), mu, b.clearcoat_lut_row);
    }
    return coating_albedo(b.clearcoat_row, mu) + ms * b.clearcoat_f_add * loss;
}

// The coat's transmission of a light at cosine mu_i (v_dot_h: the view's cosine to the
// half vector) under its form: 1 - E_c(mu_i) (physical), 1 - F_c(v.h) (Filament's),
// 1 - F_c(n.v) (glTF's); 1 without a coat.
fn clearcoat_in(b: Ball, mu_i: f32, v_dot_h: f32) -> f32 {
    if !has_clearcoat(b) {
        return 1.0;
    }
    switch b.clearcoat_form {
        case COAT_FORM_FILAMENT: {
            return 1.0 - f_dielectric(v_dot_h, b.clearcoat_eta, clearcoat_fresnel(b));
        }
        case COAT_FORM_GLTF: {
            return 1.0 - clearcoat_point.fresnel_o;
        }
        default: {
            return 1.0 - clearcoat_albedo(b, mu_i, clearcoat_point.ms);
        }
    }
}

// The share of a Lambertian base's light from a light the coat transmits with t_in
// (clearcoat_in) that comes through ball b's coat; 1 without a coat.
fn clearcoat_through(b: Ball, t_in: f32) -> vec3<f32> {
    if !has_clearcoat(b) {
        return vec3<f32>(1.0);
    }
    return clearcoat_through_physical(b.clearcoat, clearcoat_point.out, t_in);
}

// clearcoat_through for a glossy base's light.
fn clearcoat_through_lobe(b: Ball, t_in: f32) -> vec3<f32> {
    if !has_clearcoat(b) {
        return vec3<f32>(1.0);
    }
    return clearcoat_through_physical(b.clearcoat, clearcoat_point.out_lobe, t_in);
}

// The share of a Lambertian base's light from uniform light and the map that comes
// through ball b's coat; 1 without a coat.
fn clearcoat_environment(b: Ball) -> vec3<f32> {
    if !has_clearcoat(b) {
        return vec3<f32>(1.0);
    }
    return clearcoat_point.environment;
}

// clearcoat_environment for a glossy base's light.
fn clearcoat_environment_lobe(b: Ball) -> vec3<f32> {
    if !has_clearcoat(b) {
        return vec3<f32>(1.0);
    }
    return clearcoat_point.environment_lobe;
}

// A glossy base's single-scattering lobe under ball b's coat at the view's cosine mu_o
// (docs/design/coat.md, "The base's lobe leaves the coat wider"): (roughness, energy
// scale, alpha scale). Under the physical form the lobe is read at
// b.clearcoat_base_roughness, scaled by E(mu_o) / E_wide(mu_o) (E_wide along the ball's
// b.clearcoat_base_row) so its albedo at the view stays the base's own (the split sum's
// reading: the map at the widened roughness, the albedos at the base's), and an
// anisotropic lobe's alphas scale as its isotropic equivalent's; (b.roughness, 1, 1)
// otherwise. src/cpu/clearcoat.rs clearcoat_base_lobe.
fn clearcoat_base_lobe(b: Ball, mu_o: f32) -> vec3<f32> {
    if !has_clearcoat(b) || b.clearcoat_form != COAT_FORM_PHYSICAL {
        return vec3<f32>(b.roughness, 1.0, 1.0);
    }
    let wide = b.clearcoat_base_roughness;
    let e_own = 1.0 - lut_loss_row(e_table, lut_params(), mu_o, b.lut_row);
    let row = lut_row_unpack(b.clearcoat_base_row, wide);
    let e_wide = 1.0 - lut_loss_row(e_table, lut_params(), mu_o, row);
    // alpha_from_roughness clamps the roughness: the denominator is at least ROUGHNESS_MIN^2.
    let alpha_scale = alpha_from_roughness(wide) / alpha_from_roughness(b.roughness);
    return vec3<f32>(wide, e_own / max(e_wide, DIV_EPSILON), alpha_scale);
}

// The cosine at which a glossy base's Schlick Fresnel is read under ball b's coat: c
// refracted into the coat under the physical form (brdf.wgsl clearcoat_base_cosine), c
// otherwise. src/cpu/clearcoat.rs clearcoat_base_fresnel_cosine.
fn clearcoat_base_fresnel_cosine(b: Ball, c: f32) -> f32 {
    if !has_clearcoat(b) || b.clearcoat_form != COAT_FORM_PHYSICAL {
        return c;
    }
    return clearcoat_base_cosine(c, b.clearcoat_eta, b.clearcoat);
}

// The cosine-weighted average of Schlick's Fresnel of F0 as a glossy base sees uniform
// light under ball b's coat: inside the coat's critical cone under the physical form
// (brdf.wgsl clearcoat_base_schlick_avg), F0 + (1 - F0) / 21 otherwise.
// src/cpu/clearcoat.rs clearcoat_base_f_avg.
fn clearcoat_base_f_avg(b: Ball, f0: vec3<f32>) -> vec3<f32> {
    if !has_clearcoat(b) || b.clearcoat_form != COAT_FORM_PHYSICAL {
        return f_avg_schlick(f0);
    }
    return f0 + (1.0 - f0) * clearcoat_base_schlick_avg(b.clearcoat_eta, b.clearcoat);
}

// The Fresnel form of ball b's clear coat (CoatForm::fresnel): the scene's (b.fresnel)
// under the physical form, Schlick's under the engines'.
fn clearcoat_fresnel(b: Ball) -> u32 {
    return select(b.fresnel, FRESNEL_SCHLICK, b.clearcoat_form != COAT_FORM_PHYSICAL);
}

// The coating's specular albedo E_spec(mu) with the ball's term (weight ms): Kulla-Conty's
// e_f + f_add loss, Turquin's e_f (1 + F0 (1 / E - 1)), Fdez-Aguera's e_f + FmsEms; loss
// is 1 - E(mu) (src/scene coating_spec_albedo).
fn coating_spec_albedo(e_f: f32, loss: f32, f0: f32, f_add: f32, ms: f32, term: u32) -> f32 {
    let added = by_term_f32(
        term,
        f_add * loss,
        term_turquin(vec3<f32>(e_f), vec3<f32>(f0), 1.0 - loss).x,
        term_fdez_aguera(vec3<f32>(e_f), vec3<f32>(f0), loss).x,
    );
    return e_f + ms * added;
}

// Whether the ball's layering form reads E_spec at the light's direction too.
fn two_sided(b: Ball) -> bool {
    return b.layering == LAYERING_RECIPROCAL || b.layering == LAYERING_PHYSICAL;
}

// The base's BRDF under the ball's layering form (src/brdf/layering.rs): e_spec_o and
// e_spec_i the coating's specular albedo at the view and the light, fresnel_vh the
// coating's Fresnel at the half vector.
fn coating_base(b: Ball, e_spec_o: f32, e_spec_i: f32, fresnel_vh: f32) -> vec3<f32> {
    let albedo = b.diffuse;
    switch b.layering {
        case LAYERING_CONSTANT: {
            return f_base_constant(albedo, b.coat_f_avg);
        }
        case LAYERING_GLTF: {
            return f_base_gltf(albedo, fresnel_vh);
        }
        case LAYERING_VIEW_ONLY: {
            return f_base_view_only(albedo, e_spec_o);
        }
        case LAYERING_RECIPROCAL: {
            return f_base_reciprocal(albedo, e_spec_o, e_spec_i, b.e_spec_avg);
        }
        default: {
            return f_base_physical(albedo, e_spec_o, e_spec_i, b.e_spec_avg, b.eta);
        }
    }
}

// The base's directional albedo under the ball's layering form: what a uniform light or a
// map's irradiance meets (fresnel_o the coating's Fresnel at the view).
fn coating_base_albedo(b: Ball, e_spec_o: f32, fresnel_o: f32) -> vec3<f32> {
    let albedo = b.diffuse;
    switch b.layering {
        case LAYERING_CONSTANT: {
            return base_albedo_constant(albedo, b.coat_f_avg);
        }
        case LAYERING_GLTF: {
            return base_albedo_gltf(albedo, fresnel_o);
        }
        case LAYERING_VIEW_ONLY, LAYERING_RECIPROCAL: {
            return base_albedo_view_only(albedo, e_spec_o);
        }
        default: {
            return base_albedo_physical(albedo, e_spec_o, b.e_spec_avg, b.eta);
        }
    }
}

// Radiance leaving ball b's coating at unit normal n towards v, lit by the first n_lights
// lights, the uniform environment and the map; ms the weight of the ball's term
// (term_weight in lighting.wgsl). The specular is the metal's with the coating's Fresnel
// (f_dielectric of the index: exact, or Schlick's in games202) and the coating's own term
// (Kulla-Conty's f_add from the coating's F_avg); under uniform light its albedo is the
// row's E_F(mu_o) with the term's part, E_spec(mu_o), and the base is weighted by the
// ball's layering form.
fn shade_coating(b: Ball, n: vec3<f32>, v: vec3<f32>, n_lights: u32, ms: f32) -> vec3<f32> {
    let eta = b.eta;
    let f_add = b.coat_f_add;
    let f0 = f0_from_ior(eta);
    let term = b.term;
    let norm = b.ms_norm;
    let mu_o = max(dot(n, v), 0.0);
    var loss_o = 0.0;
    if ms > 0.0 {
        loss_o = lut_loss_row(e_table, lut_params(), mu_o, b.lut_row);
    }
    let e_o = 1.0 - loss_o;
    // Under a clear coat the coating's Fresnel is read inside the coat (refracted cosines):
    // its albedo E_F and the base's share with it.
    let mu_fresnel = clearcoat_base_fresnel_cosine(b, mu_o);
    let e_f_o = coating_albedo(b.coating_row, mu_fresnel);
    let e_spec_o = coating_spec_albedo(e_f_o, loss_o, f0, f_add, ms, term);
    let base_o = coating_base_albedo(b, e_spec_o, f_dielectric(mu_fresnel, eta, b.fresnel));
    // The shares of uniform light and the map that a clear coat lets through (1 without):
    // the specular's as a glossy base's, the base's as a Lambertian one's.
    let through_lobe = clearcoat_environment_lobe(b);
    let through_base = clearcoat_environment(b);
    var lo = vec3<f32>(0.0);
    if HAS_ENVIRONMENT == 1u {
        lo = globals.environment.xyz * (e_spec_o * through_lobe + base_o * through_base);
    }
    // Fdez-Aguera's energy, formed once for every light (zero for the other terms).
    var fms_ems = 0.0;
    if ms > 0.0 && term == TERM_FDEZ_AGUERA {
        fms_ems = term_fdez_aguera(vec3<f32>(e_f_o), vec3<f32>(f0), loss_o).x;
    }
    // IBL = 2: the map's part is the whole model's (lighting.wgsl shade_environment_mis).
    if IBL == 1u {
        lo += shade_coating_map(b, n, v, e_f_o, loss_o, fms_ems, ms, base_o, through_lobe, through_base);
    }
    if HAS_LIGHTS == 0u {
        return lo;
    }
    // Under a clear coat the specular leaves the coat wider (clearcoat_base_lobe).
    let lobe_of = clearcoat_base_lobe(b, mu_o);
    for (var k = 0u; k < n_lights; k++) {
        let l = lights[k].direction.xyz;
        let mu_i = dot(n, l);
        if mu_i <= 0.0 || mu_o <= 0.0 {
            continue;
        }
        let h = normalize(v + l);
        let fresnel = f_dielectric(clearcoat_base_fresnel_cosine(b, dot(v, h)), eta, b.fresnel);
        let spec = lobe_of.y * f_micro(vec3<f32>(fresnel), mu_o, mu_i, dot(n, h), lobe_of.x, GEOMETRY).x;
        var lobe = 0.0;
        var loss_i = 0.0;
        if ms > 0.0 {
            loss_i = lut_loss_row(e_table, lut_params(), mu_i, b.lut_row);
            lobe = by_term_f32(
                term,
                f_add * f_ms(loss_o, loss_i, norm),
                term_turquin(vec3<f32>(spec), vec3<f32>(f0), e_o).x,
                fms_ems / PI,
            );
        }
        var e_spec_i = 0.0;
        if two_sided(b) {
            let e_f_i = coating_albedo(b.coating_row, clearcoat_base_fresnel_cosine(b, mu_i));
            e_spec_i = coating_spec_albedo(e_f_i, loss_i, f0, f_add, ms, term);
        }
        let t_in = clearcoat_in(b, mu_i, dot(v, h));
        let f_r = clearcoat_through_lobe(b, t_in) * (spec + ms * lobe)
            + clearcoat_through(b, t_in) * coating_base(b, e_spec_o, e_spec_i, fresnel);
        lo += f_r * lights[k].radiance.xyz * mu_i;
    }
    return lo;
}

// The map's part of shade_coating (docs/design/environment.md, "Shading under a map"): the
// prefiltered radiance along the dominant direction times the row's E_F(mu_o) (the split
// sum's second factor is the directional albedo), the coating's term as the metal's, and
// the base's albedo times the irradiance (IBL = 1 only: the lobe mode samples the whole
// model instead, lighting.wgsl shade_environment_mis).
fn shade_coating_map(
    b: Ball,
    n: vec3<f32>,
    v: vec3<f32>,
    e_f_o: f32,
    loss_o: f32,
    fms_ems: f32,
    ms: f32,
    base_o: vec3<f32>,
    through_lobe: vec3<f32>,
    through_base: vec3<f32>,
) -> vec3<f32> {
    let roughness = b.roughness;
    let rotation = env.rotation;
    let intensity = env.intensity;
    let r = 2.0 * dot(n, v) * n - v;
    let n_map = env_to_map(n, rotation);
    // Under a clear coat the lobe leaves the coat wider (clearcoat_base_roughness).
    var map_roughness = roughness;
    if has_clearcoat(b) {
        map_roughness = b.clearcoat_base_roughness;
    }
    // DOMINANT_DIRECTION = 0: the plain mirror direction (a measurement's switch).
    let dominant = select(r, specular_direction(n, r, map_roughness), DOMINANT_DIRECTION == 1u);
    let prefiltered = intensity * env_specular(env_specular_layers, env_sampler, env_to_map(dominant, rotation), map_roughness, env_layer_set);
    let irradiance = intensity * env_irradiance(env_convolved, env_sampler, n_map, env_layer_set);
    let single = prefiltered * e_f_o;
    var lobe = single;
    if ms > 0.0 {
        let term = b.term;
        let multiple = intensity * env_multiple(env_convolved, env_sampler, n_map, roughness, env_layer_set);
        // Each share added to the lobe in its own arm, as the shader always summed it.
        lobe = by_term(
            term,
            lobe + ms * b.coat_f_add * loss_o * multiple,
            lobe + ms * term_turquin(single, vec3<f32>(f0_from_ior(b.eta)), 1.0 - loss_o),
            lobe + ms * fms_ems * irradiance,
        );
    }
    // A clear coat's shares (1 without): the specular's and the base's.
    return lobe * through_lobe + base_o * irradiance * through_base;
}
