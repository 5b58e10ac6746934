// clearcoat.wgsl: a clear coat over a ball's whole shading (docs/design/coat.md; the maths
// in src/brdf/clearcoat.rs): the coat's own lobe, and the share of the base's light that
// comes through it, per light (clearcoat_through) and under uniform light and the map
// (clearcoat_environment). Mirrored in f64 by src/cpu/clearcoat.rs (same model, same order
// of terms).

#define_import_path shadeballs::clearcoat
#import shadeballs::brdf::{f_micro, f_ms, f_dielectric, clearcoat_through_physical, clearcoat_through_engine}
#import shadeballs::lut::lut_loss_row
#import shadeballs::environment::{env_to_map, specular_direction, env_specular, env_multiple}
#import shadeballs::types::{Ball, GEOMETRY, HAS_ENVIRONMENT, HAS_LIGHTS, IBL, DOMINANT_DIRECTION}
#import shadeballs::types::{COAT_FORM_FILAMENT, COAT_FORM_GLTF, COATING_ROW_LEN}
#import shadeballs::bindings::{globals, lights, e_table, lut_params, env, env_sampler}
#import shadeballs::bindings::{env_specular_layers, env_convolved, coating_rows}

// What a coated point forms once per pixel (clearcoat_begin), for the base's shading and
// the coat's own.
struct ClearcoatPoint {
    // The physical form's view part of the base's weight, (1 - E_c(mu_o)) inside, per channel.
    out: vec3<f32>,
    // The coat's directional albedo at the view under its form: E_c(mu_o) (physical),
    // E_F(mu_o) (Filament's), F_c(mu_o) E(mu_o) (glTF's).
    albedo_o: f32,
    // The base's weight under uniform light and the map.
    environment: vec3<f32>,
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

// With IBL = 2, the mean radiance of the coat's own lobe under the map (set by
// lighting.wgsl shade).
var<private> clearcoat_lobe: vec3<f32>;

// The coat's single-scattering albedo E_F(mu) from its row of coating_rows: the read of
// coating.wgsl's coating_albedo (that module imports this one, so this one cannot import it).
fn clearcoat_row_albedo(row: u32, mu: f32) -> f32 {
    let x = sqrt(clamp(mu, 0.0, 1.0)) * f32(COATING_ROW_LEN - 1u);
    let k = min(u32(floor(x)), COATING_ROW_LEN - 2u);
    let t = x - f32(k);
    let first = row * COATING_ROW_LEN + k;
    let a = coating_rows[first];
    return a + t * (coating_rows[first + 1u] - a);
}

// Whether ball b has a clear coat.
fn has_clearcoat(b: Ball) -> bool {
    return b.clearcoat > 0.0;
}

// The coat's specular albedo E_c(mu) under the physical form: its row's E_F(mu) and its
// term's f_add (1 - E(mu)) (ms its weight).
fn clearcoat_albedo(b: Ball, mu: f32, ms: f32) -> f32 {
    var loss = 0.0;
    if ms > 0.0 {
        loss = lut_loss_row(e_table, lut_params(), mu, b.clearcoat_lut_row);
    }
    return clearcoat_row_albedo(b.clearcoat_row, mu) + ms * b.clearcoat_f_add * loss;
}

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
    p.e_f_o = clearcoat_row_albedo(b.clearcoat_row, mu_o);
    p.fresnel_o = f_dielectric(mu_o, b.clearcoat_eta, b.clearcoat_fresnel);
    p.out = vec3<f32>(0.0);
    switch form {
        case COAT_FORM_FILAMENT: {
            p.albedo_o = p.e_f_o;
            p.environment = vec3<f32>(clearcoat_through_engine(w, p.fresnel_o));
        }
        case COAT_FORM_GLTF: {
            p.albedo_o = p.fresnel_o * (1.0 - p.loss_o);
            p.environment = vec3<f32>(clearcoat_through_engine(w, p.fresnel_o));
        }
        default: {
            let e_o = p.e_f_o + p.ms * b.clearcoat_f_add * p.loss_o;
            p.albedo_o = e_o;
            p.out = (1.0 - e_o) * b.clearcoat_inside;
            p.environment = clearcoat_through_physical(w, p.out, b.clearcoat_e_avg);
        }
    }
    clearcoat_point = p;
}

// The share of the base's light from a light at cosine mu_i (v_dot_h: the view's cosine
// to the half vector) that comes through ball b's coat; 1 without a coat.
fn clearcoat_through(b: Ball, mu_i: f32, v_dot_h: f32) -> vec3<f32> {
    if !has_clearcoat(b) {
        return vec3<f32>(1.0);
    }
    let w = b.clearcoat;
    switch b.clearcoat_form {
        case COAT_FORM_FILAMENT: {
            let fresnel = f_dielectric(v_dot_h, b.clearcoat_eta, b.clearcoat_fresnel);
            return vec3<f32>(clearcoat_through_engine(w, fresnel));
        }
        case COAT_FORM_GLTF: {
            return vec3<f32>(clearcoat_through_engine(w, clearcoat_point.fresnel_o));
        }
        default: {
            let e_i = clearcoat_albedo(b, mu_i, clearcoat_point.ms);
            return clearcoat_through_physical(w, clearcoat_point.out, e_i);
        }
    }
}

// The share of the base's light from uniform light and the map that comes through ball
// b's coat; 1 without a coat.
fn clearcoat_environment(b: Ball) -> vec3<f32> {
    if !has_clearcoat(b) {
        return vec3<f32>(1.0);
    }
    return clearcoat_point.environment;
}

// The coat's own radiance at unit normal n towards v (after clearcoat_begin), lit by the
// first n_lights lights, the uniform environment and the map, times its weight.
fn shade_clearcoat(b: Ball, n: vec3<f32>, v: vec3<f32>, n_lights: u32) -> vec3<f32> {
    let p = clearcoat_point;
    let form = b.clearcoat_form;
    let roughness = b.clearcoat_roughness;
    let mu_o = max(dot(n, v), 0.0);
    var lo = vec3<f32>(0.0);
    if HAS_ENVIRONMENT == 1u {
        lo = globals.environment.xyz * p.albedo_o;
    }
    if IBL != 0u {
        lo += shade_clearcoat_map(b, n, v);
    }
    if HAS_LIGHTS == 1u {
        for (var k = 0u; k < n_lights; k++) {
            let l = lights[k].direction.xyz;
            let mu_i = dot(n, l);
            if mu_i <= 0.0 || mu_o <= 0.0 {
                continue;
            }
            let h = normalize(v + l);
            var fresnel = f_dielectric(dot(v, h), b.clearcoat_eta, b.clearcoat_fresnel);
            if form == COAT_FORM_GLTF {
                fresnel = 1.0;
            }
            var spec = f_micro(vec3<f32>(fresnel), mu_o, mu_i, dot(n, h), roughness, GEOMETRY).x;
            if form == COAT_FORM_GLTF {
                spec *= p.fresnel_o;
            }
            if p.ms > 0.0 {
                let loss_i = lut_loss_row(e_table, lut_params(), mu_i, b.clearcoat_lut_row);
                spec += p.ms * b.clearcoat_f_add * f_ms(p.loss_o, loss_i, b.clearcoat_ms_norm);
            }
            lo += spec * lights[k].radiance.xyz * mu_i;
        }
    }
    return b.clearcoat * lo;
}

// The map's part of shade_clearcoat: the prefiltered radiance at the coat's roughness
// along its dominant direction (or, with IBL = 2, its own lobe's mean, clearcoat_lobe)
// times the coat's albedo at the view, and the physical form's term as the coating's.
fn shade_clearcoat_map(b: Ball, n: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    let p = clearcoat_point;
    let roughness = b.clearcoat_roughness;
    let rotation = env.rotation;
    let intensity = env.intensity;
    var radiance = clearcoat_lobe;
    if IBL != 2u {
        let r = 2.0 * dot(n, v) * n - v;
        let dominant = select(r, specular_direction(n, r, roughness), DOMINANT_DIRECTION == 1u);
        radiance = intensity * env_specular(env_specular_layers, env_sampler, env_to_map(dominant, rotation), roughness);
    }
    var lo = radiance * p.albedo_o;
    if b.clearcoat_form != COAT_FORM_FILAMENT && b.clearcoat_form != COAT_FORM_GLTF && p.ms > 0.0 {
        // albedo_o holds the term's part too: the single scattering alone takes the
        // prefiltered radiance, the term the multiple-scattering convolution.
        let multiple = intensity * env_multiple(env_convolved, env_sampler, env_to_map(n, rotation), roughness);
        let added = p.ms * b.clearcoat_f_add * p.loss_o;
        lo = radiance * p.e_f_o + added * multiple;
    }
    return lo;
}
