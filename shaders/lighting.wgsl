// lighting.wgsl: outgoing radiance at a ball's surface point: the metal's shading here, the
// dielectric coating's in coating.wgsl, mixed by the ball's metallic.
// Mirrored in f64 by src/cpu/shade.rs (same model, same order of terms).

#define_import_path shadeballs::lighting
#import shadeballs::constants::{PI, DIV_EPSILON}
#import shadeballs::brdf::{f_schlick, f_avg_schlick, f_micro, f_ms, term_turquin, term_fdez_aguera}
#import shadeballs::brdf::{alpha_from_roughness, f_dielectric}
#import shadeballs::lut::lut_loss_row
#import shadeballs::environment::{env_to_map, specular_direction, env_specular, env_irradiance}
#import shadeballs::environment::{env_multiple, split_sum_bias, split_sum_scale, direction_to_uv}
#import shadeballs::environment::{pixel_scramble, lobe_frame_point, lobe_lod}
#import shadeballs::sampling::{duff_frame, sample_vndf, vndf_density}
#import shadeballs::types::{Ball, GEOMETRY, MS_TERM, HAS_ENVIRONMENT, HAS_LIGHTS, IBL, IBL_SAMPLES}
#import shadeballs::types::{TERM_FDEZ_AGUERA, DOMINANT_DIRECTION, by_term}
#import shadeballs::coating::{shade_coating, coating_lobe, has_clearcoat, clearcoat_through, clearcoat_environment}
#import shadeballs::clearcoat::{clearcoat_begin, shade_clearcoat, clearcoat_lobe}
#import shadeballs::bindings::{globals, lights, e_table, lut_params, env, env_sampler}
#import shadeballs::bindings::{env_specular_layers, env_convolved, env_split_sum, env_radiance}

// Radiance leaving ball `b` at unit normal n towards unit direction v (to the eye), lit by
// the first `n_lights` lights (a count the caller passes in, not read here from the uniform
// buffer: screen.wgsl loop_counts says why): the metal's and the coating's, each with its
// own term, mixed by the ball's metallic (an all-metal or all-dielectric ball shades one).
// `pixel` (column, row) picks the pixel's sequence of lobe samples (IBL = 2).
// With IBL = 2 the coating's specular lobe is sampled here too (lobe_mean_radiance with
// the coating's Fresnel) and handed to shade_coating through coating_lobe.
// A clear coat (clearcoat.wgsl) adds its own lobe and weights the base's light by what it
// lets through.
fn shade(b: Ball, n: vec3<f32>, v: vec3<f32>, n_lights: u32, pixel: vec2<u32>) -> vec3<f32> {
    if has_clearcoat(b) {
        clearcoat_begin(b, n, v, term_weight(b));
        if IBL == 2u {
            clearcoat_lobe = lobe_mean_radiance(n, v, b.clearcoat_roughness, vec3<f32>(0.0), b.clearcoat_eta, b.clearcoat_fresnel, pixel);
        }
        return shade_base(b, n, v, n_lights, pixel) + shade_clearcoat(b, n, v, n_lights);
    }
    return shade_base(b, n, v, n_lights, pixel);
}

// The ball under its clear coat (all of it without one): the metal's and the coating's
// parts mixed by metallic.
fn shade_base(b: Ball, n: vec3<f32>, v: vec3<f32>, n_lights: u32, pixel: vec2<u32>) -> vec3<f32> {
    let metallic = b.metallic;
    if metallic >= 1.0 {
        return shade_metal(b, n, v, n_lights, pixel);
    }
    if IBL == 2u {
        coating_lobe = lobe_mean_radiance(n, v, b.roughness, vec3<f32>(0.0), b.eta, b.fresnel, pixel);
    }
    let coating = shade_coating(b, n, v, n_lights, term_weight(b));
    if metallic <= 0.0 {
        return coating;
    }
    return metallic * shade_metal(b, n, v, n_lights, pixel) + (1.0 - metallic) * coating;
}

// The metal's part of `shade`.
//
// Directional lights: f_r = f_micro (Schlick F with F0 per channel, GGX D, the GEOMETRY G)
// + the ball's term; Lo += f_r L mu_i. The term (ball_term) is Kulla-Conty's
// lobe f_add f_ms, Turquin's f_micro F0 (1 / E(mu_o) - 1), or Fdez-Aguera's FmsEms / pi.
//
// Uniform environment L_env: the cosine-weighted hemispherical integral of f_r. The
// Kulla-Conty lobe integrates exactly to f_add (1 - E(mu_o)) (its construction),
// Fdez-Aguera's lobe to FmsEms. The single-scattering part
// with Schlick F, FssEss, has no table of its own without a map: it is approximated by
// F_avg_schlick(F0) E(mu_o), i.e. F replaced by its cosine-weighted average. That is exact
// when F is constant (F0 = 1, the furnace, where it gives E(mu_o) and Lo = L_env exactly
// with the term on) and otherwise an approximation of the split-sum kind; with a map bound
// FssEss is the split sum's F0 A + B (Karis 2013's second table).
fn shade_metal(b: Ball, n: vec3<f32>, v: vec3<f32>, n_lights: u32, pixel: vec2<u32>) -> vec3<f32> {
    let roughness = b.roughness;
    let f0 = b.f0;
    let ms = term_weight(b);
    let term = b.term;
    let mu_o = max(dot(n, v), 0.0);
    // E(mu_o) is read for the term and for the environment's part, not otherwise.
    var loss_o = 0.0;
    if MS_TERM != 0u || HAS_ENVIRONMENT == 1u || IBL != 0u {
        loss_o = lut_loss_row(e_table, lut_params(), mu_o, b.lut_row);
    }
    let e_o = 1.0 - loss_o;
    let f_avg_ss = f_avg_schlick(f0);
    // f_add and the lobe's normalisation are constant over the ball: formed once on the
    // CPU, per preset (f_add_preset, f_ms_norm; src/gpu/uniforms.rs balls).
    var norm = 0.0;
    var f_add = vec3<f32>(0.0);
    if MS_TERM != 0u {
        norm = b.ms_norm;
        f_add = b.f_add;
    }
    // The single-scattering albedo: the split sum with a map bound, else F_avg E(mu_o).
    var fss_ess = f_avg_ss * e_o;
    if IBL != 0u {
        fss_ess = split_sum_scale(f0, e_o, split_sum_bias(env_split_sum, mu_o, roughness));
    }
    // Fdez-Aguera's energy, formed once for every light (zero for the other terms).
    var fms_ems = vec3<f32>(0.0);
    if MS_TERM != 0u && term == TERM_FDEZ_AGUERA {
        fms_ems = term_fdez_aguera(fss_ess, f0, loss_o);
    }

    var lo = vec3<f32>(0.0);
    if HAS_ENVIRONMENT == 1u {
        let single = f_avg_ss * e_o;
        let added = by_term(term, f_add * loss_o, term_turquin(single, f0, e_o), fms_ems);
        lo = globals.environment.xyz * (single + ms * added);
    }
    if IBL != 0u {
        lo += shade_environment_map(b, n, v, loss_o, fss_ess, fms_ems, ms, f_add, pixel);
    }
    // The share of uniform light and the map that a clear coat lets through (1 without).
    lo *= clearcoat_environment(b);
    if HAS_LIGHTS == 0u {
        return lo;
    }
    for (var k = 0u; k < n_lights; k++) {
        let l = lights[k].direction.xyz;
        let mu_i = dot(n, l);
        if mu_i <= 0.0 || mu_o <= 0.0 {
            continue;
        }
        let h = normalize(v + l);
        let fresnel = f_schlick(f0, dot(v, h));
        let spec = f_micro(fresnel, mu_o, mu_i, dot(n, h), roughness, GEOMETRY);
        var lobe = vec3<f32>(0.0);
        // Compiled in (2) or a branch on the ball's flag (1): balls without the term skip
        // its E read; then a branch on the ball's own term.
        if MS_TERM == 2u || (MS_TERM == 1u && ms > 0.0) {
            let loss_i = lut_loss_row(e_table, lut_params(), mu_i, b.lut_row);
            lobe = by_term(
                term,
                ms * f_add * f_ms(loss_o, loss_i, norm),
                ms * term_turquin(spec, f0, e_o),
                ms * fms_ems / PI,
            );
        }
        let f_r = spec + lobe;
        lo += clearcoat_through(b, mu_i, dot(v, h)) * f_r * lights[k].radiance.xyz * mu_i;
    }
    return lo;
}

// Radiance leaving ball b at normal n towards v lit by the environment map
// (docs/design/environment.md, "Shading under a map (image-based lighting)"): the split sum
// (the prefiltered radiance along the mirror direction bent towards the normal,
// specular_direction, times F0 A + B) and the ball's multiple-scattering term, weighted by
// `ms`. `loss_o` is 1 - E(mu_o) as read from
// the E table; `fss_ess` the split sum's F0 A + B; `fms_ems` Fdez-Aguera's energy (zero for
// the other terms); f_add the ball's (zero with the term compiled out). With IBL = 2 the
// single scattering is the lobe's samples instead (shade_environment_lobe; the terms as
// under the split sum). Mirrored by src/cpu/shade.rs shade_environment_map.
fn shade_environment_map(
    b: Ball,
    n: vec3<f32>,
    v: vec3<f32>,
    loss_o: f32,
    fss_ess: vec3<f32>,
    fms_ems: vec3<f32>,
    ms: f32,
    f_add: vec3<f32>,
    pixel: vec2<u32>,
) -> vec3<f32> {
    let roughness = b.roughness;
    let f0 = b.f0;
    let rotation = env.rotation;
    let intensity = env.intensity;
    let n_map = env_to_map(n, rotation);
    let irradiance = intensity * env_irradiance(env_convolved, env_sampler, n_map);
    let e_o = 1.0 - loss_o;
    var single = vec3<f32>(0.0);
    if IBL == 2u {
        single = shade_environment_lobe(n, v, f0, roughness, fss_ess, pixel);
    } else {
        let r = 2.0 * dot(n, v) * n - v;
        // DOMINANT_DIRECTION = 0: the plain mirror direction (a measurement's switch).
        let dominant = select(r, specular_direction(n, r, roughness), DOMINANT_DIRECTION == 1u);
        let prefiltered = intensity * env_specular(env_specular_layers, env_sampler, env_to_map(dominant, rotation), roughness);
        single = prefiltered * fss_ess;
    }
    var lo = single;
    if ms > 0.0 {
        let term = b.term;
        let multiple = intensity * env_multiple(env_convolved, env_sampler, n_map, roughness);
        // Each share added to lo in its own arm, as the shader always summed it.
        lo = by_term(
            term,
            lo + ms * f_add * loss_o * multiple,
            lo + ms * term_turquin(single, f0, e_o),
            lo + ms * fms_ems * irradiance,
        );
    }
    return lo;
}

// The metal's single scattering at normal n towards v lit by the map, from IBL_SAMPLES
// directions of its own lobe (docs/design/environment.md, "Lighting that follows the
// lobe"): the lobe's mean radiance (lobe_mean_radiance, Schlick's F of f0) times the split
// sum's exactly tabulated fss_ess = F0 A + B, the lobe's albedo.
// Mirrored by src/cpu/shade.rs shade_environment_lobe.
fn shade_environment_lobe(
    n: vec3<f32>,
    v: vec3<f32>,
    f0: vec3<f32>,
    roughness: f32,
    fss_ess: vec3<f32>,
    pixel: vec2<u32>,
) -> vec3<f32> {
    return lobe_mean_radiance(n, v, roughness, f0, 0.0, 0u, pixel) * fss_ess;
}

// The self-normalised mean radiance of a microfacet lobe at normal n towards v, lit by the
// map: sum w L / sum w over the pixel's samples env.lobe.x .. + IBL_SAMPLES
// (lobe_frame_point: a net in the first frame, the R2 sequence after), each a GGX visible
// normal reflected (sample_vndf), dropped below the horizon, weighted by
// w = f_micro mu_i / pdf (F G2 / G1(v), the estimator of Heitz 2018) and reading the map's
// mip chain at its footprint (lobe_lod, among all the samples so far); 0 where no sample
// lies above the horizon. Times the lobe's albedo it estimates the lobe's single
// scattering, the weights' noise cancelled. F: Schlick's of f0 per channel where eta is
// 0 (a metal), else the dielectric's of index eta in form `fresnel` (a coating).
// Mirrored by src/cpu/shade.rs lobe_mean_radiance.
fn lobe_mean_radiance(
    n: vec3<f32>,
    v: vec3<f32>,
    roughness: f32,
    f0: vec3<f32>,
    eta: f32,
    fresnel: u32,
    pixel: vec2<u32>,
) -> vec3<f32> {
    let mu_o = max(dot(n, v), 0.0);
    let alpha = alpha_from_roughness(roughness);
    let frame = duff_frame(n);
    let v_local = v * frame;
    let scramble = pixel_scramble(pixel);
    let first = u32(env.lobe.x);
    let count = env.lobe.x + f32(IBL_SAMPLES);
    let max_level = f32(textureNumLevels(env_radiance) - 1u);
    var sum = vec3<f32>(0.0);
    var weights = vec3<f32>(0.0);
    for (var j = 0u; j < IBL_SAMPLES; j++) {
        let u = lobe_frame_point(first, j, IBL_SAMPLES, scramble);
        let l = frame * sample_vndf(v_local, alpha, u.x, u.y);
        let mu_i = dot(n, l);
        if mu_i <= 0.0 || mu_o <= 0.0 {
            continue;
        }
        let h = normalize(v + l);
        let n_dot_h = dot(n, h);
        let pdf = vndf_density(mu_o, n_dot_h, alpha);
        if pdf <= DIV_EPSILON {
            continue;
        }
        var f = f_schlick(f0, dot(v, h));
        if eta > 0.0 {
            f = vec3<f32>(f_dielectric(dot(v, h), eta, fresnel));
        }
        let w = f_micro(f, mu_o, mu_i, n_dot_h, roughness, GEOMETRY) * (mu_i / pdf);
        let l_map = env_to_map(l, env.rotation);
        let lod = lobe_lod(pdf, count, l_map, env.lobe.zw, max_level);
        let radiance = textureSampleLevel(env_radiance, env_sampler, direction_to_uv(l_map), lod).rgb;
        sum += w * radiance;
        weights += w;
    }
    let mean = select(sum / max(weights, vec3<f32>(DIV_EPSILON)), vec3<f32>(0.0), weights <= vec3<f32>(DIV_EPSILON));
    return env.intensity * mean;
}

// The weight of ball b's multiple-scattering term under MS_TERM: 1 compiled in, the ball's
// flag under a branch, 0 compiled out.
fn term_weight(b: Ball) -> f32 {
    if MS_TERM == 2u {
        return 1.0;
    }
    if MS_TERM == 1u {
        return b.ms;
    }
    return 0.0;
}
