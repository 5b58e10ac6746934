// clearcoat.wgsl: a clear coat over a ball's whole shading (docs/design/coat.md; the maths
// in src/brdf/clearcoat.rs): the coat's own lobe (shade_clearcoat) and its point's forming
// (clearcoat_begin); the share of the base's light that comes through it is coating.wgsl's
// clearcoat_through and clearcoat_environment (the base's shading reads them). Mirrored in
// f64 by src/cpu/clearcoat.rs (same model, same order of terms).

#define_import_path shadeballs::clearcoat
#import shadeballs::brdf::{f_micro, f_ms, f_dielectric, clearcoat_through_physical, clearcoat_through_engine}
#import shadeballs::brdf::{clearcoat_inside_scale, clearcoat_lobe_scale, clearcoat_escape_at}
#import shadeballs::lut::lut_loss_row
#import shadeballs::environment::{env_to_map, specular_direction, env_specular, env_multiple}
#import shadeballs::types::{Ball, GEOMETRY, HAS_ENVIRONMENT, HAS_LIGHTS, IBL, DOMINANT_DIRECTION}
#import shadeballs::types::{COAT_FORM_FILAMENT, COAT_FORM_GLTF}
#import shadeballs::bindings::{globals, lights, e_table, lut_params, env, env_sampler}
#import shadeballs::bindings::{env_layer_set, env_specular_layers, env_convolved}
#import shadeballs::coating::{coating_albedo, ClearcoatPoint, clearcoat_point, clearcoat_fresnel}

// Forms ball b's coat at unit normal n towards v (ms: the ball's term weight) into
// clearcoat_point. Called once per pixel before the base is shaded.
fn clearcoat_begin(b: Ball, n: vec3<f32>, v: vec3<f32>, ms_ball: f32) {
    var p: ClearcoatPoint;
    let w = b.clearcoat;
    let form = b.clearcoat_form;
    let mu_o = max(dot(n, v), 0.0);
    p.ms = select(ms_ball, 0.0, form == COAT_FORM_FILAMENT || form == COAT_FORM_GLTF);
    p.loss_o = 0.0;
    if p.ms > 0.0 || (form == COAT_FORM_GLTF && (HAS_ENVIRONMENT == 1u || IBL != 0u)) {
        p.loss_o = lut_loss_row(e_table, lut_params(), mu_o, b.clearcoat_lut_row);
    }
    p.e_f_o = coating_albedo(b.clearcoat_row, mu_o);
    p.fresnel_o = f_dielectric(mu_o, b.clearcoat_eta, clearcoat_fresnel(b));
    // The engines' forms: the base's light times 1 - w F, the same for every base.
    p.out = vec3<f32>(1.0);
    p.out_lobe = vec3<f32>(1.0);
    p.environment = vec3<f32>(clearcoat_through_engine(w, p.fresnel_o));
    switch form {
        case COAT_FORM_FILAMENT: {
            p.albedo_o = p.e_f_o;
        }
        case COAT_FORM_GLTF: {
            p.albedo_o = p.fresnel_o * (1.0 - p.loss_o);
        }
        default: {
            let e_o = p.e_f_o + p.ms * b.clearcoat_f_add * p.loss_o;
            p.albedo_o = e_o;
            let a_avg = b.clearcoat_base_avg;
            let e_avg = b.clearcoat_e_avg;
            let eta = b.clearcoat_eta;
            p.out = (1.0 - e_o) * clearcoat_inside_scale(a_avg, e_avg, eta);
            let escape = clearcoat_escape_at(b.clearcoat_escape, mu_o);
            p.out_lobe = (1.0 - e_o) * clearcoat_lobe_scale(a_avg, escape, e_avg, eta);
            p.environment = clearcoat_through_physical(w, p.out, 1.0 - e_avg);
            p.environment_lobe = clearcoat_through_physical(w, p.out_lobe, 1.0 - e_avg);
        }
    }
    if form == COAT_FORM_FILAMENT || form == COAT_FORM_GLTF {
        p.environment_lobe = p.environment;
    }
    clearcoat_point = p;
}

// The coat's own radiance at unit normal n towards v (after clearcoat_begin), lit by the
// first n_lights lights, the uniform environment and the map, times its weight.
fn shade_clearcoat(b: Ball, n: vec3<f32>, v: vec3<f32>, n_lights: u32) -> vec3<f32> {
    let p = clearcoat_point;
    let mu_o = max(dot(n, v), 0.0);
    var lo = vec3<f32>(0.0);
    if HAS_ENVIRONMENT == 1u {
        lo = globals.environment.xyz * p.albedo_o;
    }
    // The lobe mode (IBL = 2) samples the coat's lobe with the whole model
    // (lighting.wgsl shade_environment_mis).
    if IBL == 1u {
        lo += shade_clearcoat_map(b, n, v);
    }
    if HAS_LIGHTS == 1u {
        for (var k = 0u; k < n_lights; k++) {
            let l = lights[k].direction.xyz;
            let mu_i = dot(n, l);
            if mu_i <= 0.0 || mu_o <= 0.0 {
                continue;
            }
            lo += clearcoat_lobe(b, n, v, l, mu_o, mu_i) * lights[k].radiance.xyz * mu_i;
        }
    }
    return b.clearcoat * lo;
}

// The coat's own BRDF towards unit direction l under its form, without its weight (after
// clearcoat_begin; mu_o = n.v and mu_i = n.l both above 0).
fn clearcoat_lobe(b: Ball, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, mu_o: f32, mu_i: f32) -> f32 {
    let p = clearcoat_point;
    let form = b.clearcoat_form;
    let h = normalize(v + l);
    var fresnel = f_dielectric(dot(v, h), b.clearcoat_eta, clearcoat_fresnel(b));
    if form == COAT_FORM_GLTF {
        fresnel = 1.0;
    }
    var spec = f_micro(vec3<f32>(fresnel), mu_o, mu_i, dot(n, h), b.clearcoat_roughness, GEOMETRY).x;
    if form == COAT_FORM_GLTF {
        spec *= p.fresnel_o;
    }
    if p.ms > 0.0 {
        let loss_i = lut_loss_row(e_table, lut_params(), mu_i, b.clearcoat_lut_row);
        spec += p.ms * b.clearcoat_f_add * f_ms(p.loss_o, loss_i, b.clearcoat_ms_norm);
    }
    return spec;
}

// The coat's own BRDF towards unit direction l, times its weight; 0 with l or v below the
// horizon (src/cpu/clearcoat.rs ClearcoatPoint::brdf: the Monte Carlo's model_brdf).
fn clearcoat_brdf(b: Ball, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> f32 {
    let mu_o = dot(n, v);
    let mu_i = dot(n, l);
    if mu_i <= 0.0 || mu_o <= 0.0 {
        return 0.0;
    }
    return b.clearcoat * clearcoat_lobe(b, n, v, l, mu_o, mu_i);
}

// The map's part of shade_clearcoat under the split sum: the prefiltered radiance at the
// coat's roughness along its dominant direction times the coat's albedo at the view, and
// the physical form's term as the coating's.
fn shade_clearcoat_map(b: Ball, n: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    let p = clearcoat_point;
    let roughness = b.clearcoat_roughness;
    let rotation = env.rotation;
    let intensity = env.intensity;
    let r = 2.0 * dot(n, v) * n - v;
    let dominant = select(r, specular_direction(n, r, roughness), DOMINANT_DIRECTION == 1u);
    let radiance = intensity * env_specular(env_specular_layers, env_sampler, env_to_map(dominant, rotation), roughness, env_layer_set);
    var lo = radiance * p.albedo_o;
    if b.clearcoat_form != COAT_FORM_FILAMENT && b.clearcoat_form != COAT_FORM_GLTF && p.ms > 0.0 {
        // albedo_o holds the term's part too: the single scattering alone takes the
        // prefiltered radiance, the term the multiple-scattering convolution.
        let multiple = intensity * env_multiple(env_convolved, env_sampler, env_to_map(n, rotation), roughness, env_layer_set);
        let added = p.ms * b.clearcoat_f_add * p.loss_o;
        lo = radiance * p.e_f_o + added * multiple;
    }
    return lo;
}
