// lighting.wgsl: outgoing radiance at a ball's surface point: the metal's shading here, the
// dielectric coating's in coating.wgsl, mixed by the ball's metallic.
// Mirrored in f64 by src/cpu/shade.rs (same model, same order of terms).

#define_import_path shadeballs::lighting
#import shadeballs::constants::PI
#import shadeballs::brdf::{f_schlick, f_micro, f_ms, term_turquin, term_fdez_aguera}
#import shadeballs::brdf::{alpha_from_roughness, f_micro_aniso, ball_tangent_frame, equal_area_roughness}
#import shadeballs::lut::lut_loss_row
#import shadeballs::environment::{env_to_map, specular_direction, specular_direction_aniso, env_specular, env_irradiance}
#import shadeballs::environment::{env_multiple, split_sum_bias, split_sum_scale, direction_to_uv, uv_to_direction}
#import shadeballs::environment::{pixel_scramble, lobe_frame_point, strategy_scramble}
#import shadeballs::sampling::{duff_frame, sample_vndf, sample_cosine, equirect_density, power_estimate, guide_buckets}
#import shadeballs::model::{ShadingPoint, shading_point, coated_point, model_brdf, pdf_vndf, pdf_vndf_lobe, sample_lobe}
#import shadeballs::types::{Ball, GEOMETRY, MS_TERM, HAS_ENVIRONMENT, HAS_LIGHTS, IBL, IBL_SAMPLES, IBL_COSINE_SAMPLES, HAS_ANISOTROPY, HAS_CLEARCOAT}
#import shadeballs::types::{HAS_METAL, HAS_DIELECTRIC}
#import shadeballs::types::{TERM_FDEZ_AGUERA, DOMINANT_DIRECTION, by_term}
#import shadeballs::coating::{shade_coating, has_clearcoat, clearcoat_in, clearcoat_through_lobe, clearcoat_environment_lobe}
#import shadeballs::coating::{clearcoat_base_lobe, clearcoat_base_fresnel_cosine, clearcoat_base_f_avg}
#import shadeballs::clearcoat::{clearcoat_begin, shade_clearcoat}
#import shadeballs::bindings::{globals, lights, e_table, lut_params, env, env_sampler}
#import shadeballs::bindings::{env_layer_set, env_specular_layers, env_convolved, env_split_sum, env_radiance, env_cdf}

// Radiance leaving ball `b` at unit normal n towards unit direction v (to the eye), lit by
// the first `n_lights` lights (a count the caller passes in, not read here from the uniform
// buffer: screen.wgsl loop_counts says why): the metal's and the coating's, each with its
// own term, mixed by the ball's metallic (an all-metal or all-dielectric ball shades one).
// `pixel` (column, row) picks the pixel's sequence of samples in the lobe mode (IBL = 2),
// where the map's part is the whole model's, sampled once (shade_environment_mis), and the
// metal's and the coating's shading leave it out.
// A clear coat (clearcoat.wgsl) adds its own lobe and weights the base's light by what it
// lets through. The ball's emission (Ball.emission, no part of the BRDF) is added last,
// undimmed by a clear coat.
fn shade(b: Ball, n: vec3<f32>, v: vec3<f32>, n_lights: u32, pixel: vec2<u32>) -> vec3<f32> {
    if has_clearcoat(b) {
        clearcoat_begin(b, n, v, term_weight(b));
        return shade_base(b, n, v, n_lights, pixel) + shade_clearcoat(b, n, v, n_lights) + b.emission;
    }
    return shade_base(b, n, v, n_lights, pixel) + b.emission;
}

// The ball under its clear coat (all of it without one): the metal's and the coating's
// parts mixed by metallic, the lobe mode's map part weighted by what a coat lets through.
fn shade_base(b: Ball, n: vec3<f32>, v: vec3<f32>, n_lights: u32, pixel: vec2<u32>) -> vec3<f32> {
    var map_part = vec3<f32>(0.0);
    if IBL == 2u {
        // The whole model's map part, a clear coat's lobe and its shares of the base's
        // light included (model_brdf after clearcoat_begin, as the Monte Carlo).
        map_part = shade_environment_mis(b, n, v, pixel);
    }
    let metallic = b.metallic;
    if HAS_DIELECTRIC == 0u || metallic >= 1.0 {
        return shade_metal(b, n, v, n_lights) + map_part;
    }
    let coating = shade_coating(b, n, v, n_lights, term_weight(b));
    if HAS_METAL == 0u || metallic <= 0.0 {
        return coating + map_part;
    }
    return metallic * shade_metal(b, n, v, n_lights) + (1.0 - metallic) * coating + map_part;
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
fn shade_metal(b: Ball, n: vec3<f32>, v: vec3<f32>, n_lights: u32) -> vec3<f32> {
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
    // Under a clear coat the base's Fresnel is read inside the coat (refracted cosines).
    let f_avg_ss = clearcoat_base_f_avg(b, f0);
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
        let mu_fresnel = clearcoat_base_fresnel_cosine(b, mu_o);
        fss_ess = split_sum_scale(f0, e_o, split_sum_bias(env_split_sum, mu_fresnel, roughness));
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
    // IBL = 2: the map's part is the whole model's (shade_environment_mis, in shade).
    if IBL == 1u {
        lo += shade_environment_map(b, n, v, loss_o, fss_ess, fms_ems, ms, f_add);
    }
    // The share of uniform light and the map that a clear coat lets through (1 without):
    // a glossy base's.
    lo *= clearcoat_environment_lobe(b);
    if HAS_LIGHTS == 0u {
        return lo;
    }
    // An anisotropic lobe (docs/design/anisotropy.md): the lights' single scattering in the
    // ball's tangent frame; `roughness` is its isotropic equivalent for the rest.
    let aniso = has_anisotropy(b);
    var frame = mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), n);
    if aniso {
        frame = ball_tangent_frame(n, vec2<f32>(b.anisotropy_cos, b.anisotropy_sin));
    }
    let v_local = v * frame;
    // Under a clear coat the lobe leaves the coat wider (clearcoat_base_lobe).
    let lobe_of = clearcoat_base_lobe(b, mu_o);
    for (var k = 0u; k < n_lights; k++) {
        let l = lights[k].direction.xyz;
        let mu_i = dot(n, l);
        if mu_i <= 0.0 || mu_o <= 0.0 {
            continue;
        }
        let h = normalize(v + l);
        let fresnel = f_schlick(f0, clearcoat_base_fresnel_cosine(b, dot(v, h)));
        var spec = vec3<f32>(0.0);
        if aniso {
            let alphas = lobe_of.z * vec2<f32>(b.anisotropy_alpha_t, b.anisotropy_alpha_b);
            spec = f_micro_aniso(fresnel, v_local, l * frame, h * frame, alphas.x, alphas.y, GEOMETRY);
        } else {
            spec = f_micro(fresnel, mu_o, mu_i, dot(n, h), lobe_of.x, GEOMETRY);
        }
        spec *= lobe_of.y;
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
        let through = clearcoat_through_lobe(b, clearcoat_in(b, mu_i, dot(v, h)));
        lo += through * f_r * lights[k].radiance.xyz * mu_i;
    }
    return lo;
}

// Radiance leaving ball b at normal n towards v lit by the environment map
// (docs/design/environment.md, "Shading under a map (image-based lighting)"): the split sum
// (the prefiltered radiance along the mirror direction bent towards the normal,
// specular_direction, times F0 A + B) and the ball's multiple-scattering term, weighted by
// `ms`. `loss_o` is 1 - E(mu_o) as read from
// the E table; `fss_ess` the split sum's F0 A + B; `fms_ems` Fdez-Aguera's energy (zero for
// the other terms); f_add the ball's (zero with the term compiled out). IBL = 1 only (the
// lobe mode: shade_environment_mis). Mirrored by src/cpu/shade.rs shade_environment_map.
fn shade_environment_map(
    b: Ball,
    n: vec3<f32>,
    v: vec3<f32>,
    loss_o: f32,
    fss_ess: vec3<f32>,
    fms_ems: vec3<f32>,
    ms: f32,
    f_add: vec3<f32>,
) -> vec3<f32> {
    let roughness = b.roughness;
    let f0 = b.f0;
    let rotation = env.rotation;
    let intensity = env.intensity;
    let n_map = env_to_map(n, rotation);
    let irradiance = intensity * env_irradiance(env_convolved, env_sampler, n_map, env_layer_set);
    let e_o = 1.0 - loss_o;
    let r = 2.0 * dot(n, v) * n - v;
    // An anisotropic lobe reads the map at its equal solid angle (its albedos at its
    // stand-in's roughness); under a clear coat the lobe leaves the coat wider
    // (clearcoat_base_roughness).
    var map_roughness = roughness;
    if has_anisotropy(b) {
        map_roughness = equal_area_roughness(b.anisotropy_alpha_t, b.anisotropy_alpha_b);
    }
    if has_clearcoat(b) {
        map_roughness = b.clearcoat_base_roughness;
    }
    // DOMINANT_DIRECTION = 0: the plain mirror direction (a measurement's switch).
    var dominant = select(r, specular_direction(n, r, map_roughness), DOMINANT_DIRECTION == 1u);
    // An anisotropic lobe's read leans to n by each axis's own roughness.
    if has_anisotropy(b) && DOMINANT_DIRECTION == 1u {
        let frame = ball_tangent_frame(n, vec2<f32>(b.anisotropy_cos, b.anisotropy_sin));
        dominant = specular_direction_aniso(n, r, frame[0], frame[1], b.anisotropy_alpha_t, b.anisotropy_alpha_b, map_roughness);
    }
    let prefiltered = intensity * env_specular(env_specular_layers, env_sampler, env_to_map(dominant, rotation), map_roughness, env_layer_set);
    let single = prefiltered * fss_ess;
    var lo = single;
    if ms > 0.0 {
        let term = b.term;
        let multiple = intensity * env_multiple(env_convolved, env_sampler, n_map, roughness, env_layer_set);
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

// The map's part of ball b's shading at normal n towards v in the lobe mode (IBL = 2;
// docs/design/environment.md, "Lighting that follows the lobe"): the integral of the whole
// model's BRDF (model_brdf: the metal's and the coating's single scattering, their terms and
// the coating's base, mixed by metallic, and a clear coat's lobe and shares) times the map's
// radiance and mu_i, estimated from IBL_SAMPLES samples of each strategy but the cosine's
// (IBL_COSINE_SAMPLES: all, half or a quarter) and the lobe's (lobe_samples), the samples
// env.lobe.x .. + IBL_SAMPLES of the pixel's Sobol sequence (the cosine's, and a lobe of
// fewer: the same frame's share of its own; lobe_frame_point: every frame a net, and its
// first frames together): GGX's visible normals reflected (sample_lobe: an
// anisotropic lobe's own), the cosine hemisphere (sample_cosine; for every ball, metals too:
// the term's lobe and the map's dim parts, which the map's strategy leaves to the others),
// the map's luminance above its mean (luminance_sample, where the map has tables:
// LuminanceCdf::compensated) and a clear coat's visible normals, combined by the power
// heuristic (power_estimate, Veach 1997). Each sample reads the map's base
// level (bilinear), as the Monte Carlo does: reads at the footprint's level (filtered
// importance sampling, as the lobe mode did before) blur the bright texels the map's
// samples find on purpose into the dim ones the other strategies weigh as rare, a bias that
// measured 34 % at 64 samples under studio (docs/design/environment.md). Mirrored by
// src/cpu/shade.rs shade_environment_mis.
fn shade_environment_mis(b: Ball, n: vec3<f32>, v: vec3<f32>, pixel: vec2<u32>) -> vec3<f32> {
    var p = shading_point(b, n, v);
    if p.mu_o <= 0.0 {
        return vec3<f32>(0.0);
    }
    // A coated point (clearcoat_begin has formed it in shade): the coat's lobe and its
    // shares of the base's light are the model's, and its visible normals a fourth strategy.
    if has_clearcoat(b) {
        p = coated_point(b, p);
    }
    let coat_alpha = alpha_from_roughness(b.clearcoat_roughness);
    // The base's lobe as the model reads it (widened under a coat: coated_point).
    let alpha = alpha_from_roughness(p.lobe.x);
    let frame = duff_frame(n);
    let v_local = v * frame;
    let scramble = pixel_scramble(pixel);
    let first = u32(env.lobe.x);
    let size = luminance_size();
    var sum = vec3<f32>(0.0);
    // The lobe's samples (lobe_samples: half of them on a dielectric under a map whose
    // samples find most of its light) with the map's and the coat's of the same j, then
    // the map's and the coat's alone. Drawing fewer, the lobe takes the same frame's share
    // of its own sequence (as the cosine's below), else the others' indices, whose points
    // then share their bits (a loop of the lobe's own cost metals and the sky 3 % to 11 %
    // of the frame).
    let lobe_count = lobe_samples(b);
    let lobe_first = select(first, (first / IBL_SAMPLES) * lobe_count, lobe_count < IBL_SAMPLES);
    for (var j = 0u; j < lobe_count; j++) {
        let u = lobe_frame_point(lobe_first, j, scramble);
        let l = sample_lobe(p, frame, v_local, alpha, u);
        sum += mis_contribution(b, p, l, size, MIS_LOBE);
        sum += mis_map_and_coat(b, p, vec2<u32>(first, j), scramble, size, frame, coat_alpha);
    }
    for (var j = lobe_count; j < IBL_SAMPLES; j++) {
        sum += mis_map_and_coat(b, p, vec2<u32>(first, j), scramble, size, frame, coat_alpha);
    }
    // The cosine's samples (IBL_COSINE_SAMPLES: Scene::cosine_samples, half or a quarter
    // of IBL_SAMPLES under a map whose light mostly stands above its mean), in a loop of
    // their own: lavapipe runs the body of a branch no pixel takes, so skipping every
    // other one in the loop above saved nothing.
    let cosine_count = IBL_COSINE_SAMPLES;
    let cosine_first = (first / IBL_SAMPLES) * cosine_count;
    for (var j = 0u; j < cosine_count; j++) {
        let c = lobe_frame_point(cosine_first, j, strategy_scramble(scramble, 1u));
        sum += mis_contribution(b, p, frame * sample_cosine(c.x, c.y), size, MIS_COSINE);
    }
    return env.intensity * sum / f32(IBL_SAMPLES);
}

// Sample j of the map's and of a clear coat's strategies in shade_environment_mis (their
// shares: mis_term), the map's where it has tables: index first + j of the pixel's
// sequence (scramble), the coat's visible normals of coat_alpha about `frame`.
fn mis_map_and_coat(b: Ball, p: ShadingPoint, index: vec2<u32>, scramble: vec2<u32>, size: vec2<u32>, frame: mat3x3<f32>, coat_alpha: f32) -> vec3<f32> {
    let first = index.x;
    let j = index.y;
    var sum = vec3<f32>(0.0);
    if size.x > 0u {
        let t = lobe_frame_point(first, j, strategy_scramble(scramble, 2u));
        let x = lobe_frame_point(first, j, strategy_scramble(scramble, 3u));
        let s = luminance_sample(vec4<f32>(t, x), size);
        if s.w > 0.0 {
            // The map's frame to the world's: the rotation's inverse (Environment::from_map).
            let from_map = vec2<f32>(env.rotation.x, -env.rotation.y);
            sum += mis_term(b, p, env_to_map(s.xyz, from_map), s.xyz, s.w, MIS_MAP);
        }
    }
    if HAS_CLEARCOAT == 1u && p.clearcoat {
        let c = lobe_frame_point(first, j, strategy_scramble(scramble, 4u));
        let v_local = p.v * frame;
        sum += mis_contribution(b, p, frame * sample_vndf(v_local, coat_alpha, c.x, c.y), size, MIS_COAT);
    }
    return sum;
}

// The strategies of shade_environment_mis, as mis_term's `strategy`: the lobe's visible
// normals, the cosine hemisphere, the map's luminance, a clear coat's visible normals.
const MIS_LOBE: u32 = 0u;
const MIS_COSINE: u32 = 1u;
const MIS_MAP: u32 = 2u;
const MIS_COAT: u32 = 3u;

// One direction l's share of shade_environment_mis (without the map's intensity), drawn by
// `strategy`: its density under the map's strategy looked up (0 where the map has no
// tables), then mis_term.
fn mis_contribution(b: Ball, p: ShadingPoint, l: vec3<f32>, size: vec2<u32>, strategy: u32) -> vec3<f32> {
    let l_map = env_to_map(l, env.rotation);
    var map_density = 0.0;
    if size.x > 0u {
        map_density = luminance_density(l_map, size);
    }
    return mis_term(b, p, l, l_map, map_density, strategy);
}

// The share of direction l drawn by `strategy` (MIS_*; l_map in the map's frame,
// `map_density` its density under the map's strategy: looked up, or the drawn texel's for
// the map's own samples): the model's BRDF times the map's radiance (base level) and mu_i,
// weighted against every drawn strategy's density at l by the power heuristic; 0 below the
// horizon.
fn mis_term(b: Ball, p: ShadingPoint, l: vec3<f32>, l_map: vec3<f32>, map_density: f32, strategy: u32) -> vec3<f32> {
    let mu_i = dot(p.n, l);
    if mu_i <= 0.0 {
        return vec3<f32>(0.0);
    }
    var coat = 0.0;
    if HAS_CLEARCOAT == 1u && p.clearcoat {
        coat = pdf_vndf(p, l, alpha_from_roughness(b.clearcoat_roughness));
    }
    // Indexed by MIS_*; each density times its strategy's share of the samples (the
    // lobe's: lobe_samples of IBL_SAMPLES; the cosine's: IBL_COSINE_SAMPLES), as the
    // heuristic weighs them (Veach 1997, sec. 9.2.4).
    let cosine_share = f32(IBL_COSINE_SAMPLES) / f32(IBL_SAMPLES);
    let lobe_share = f32(lobe_samples(b)) / f32(IBL_SAMPLES);
    let pdf = vec4<f32>(lobe_share * pdf_vndf_lobe(p, l, alpha_from_roughness(p.lobe.x)), cosine_share * mu_i / PI, map_density, coat);
    let radiance = textureSampleLevel(env_radiance, env_sampler, direction_to_uv(l_map), 0.0).rgb;
    return power_estimate(model_brdf(b, p, l) * radiance * mu_i, pdf[strategy], dot(pdf, pdf));
}

// The map's luminance tables' size (env_cdf's first two values): (0, 0) where it has none.
fn luminance_size() -> vec2<u32> {
    return vec2<u32>(u32(env_cdf[0]), u32(env_cdf[1]));
}

// The first index in [0, count) of the CDF at env_cdf[first] whose value exceeds x in
// [0, 1) (count if none), found through its guide at env_cdf[guide_first]: a search of the
// entries between two of the guide's, not of all count (the cutpoint method: LuminanceCdf's
// guide and luminance_partition in src/environment/sampler.rs, which says why the search
// between entries k and k + 1 is exact).
fn luminance_partition(first: u32, guide_first: u32, count: u32, x: f32) -> u32 {
    let m = guide_buckets(count);
    let k = min(u32(x * f32(m)), m - 1u);
    var lo = u32(env_cdf[guide_first + k]);
    var hi = u32(env_cdf[guide_first + k + 1u]);
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if env_cdf[first + mid] <= x {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return lo;
}

// A map-frame direction drawn from the map's luminance tables of `size` with four uniform
// numbers (LuminanceCdf::luminance_sample; the Monte Carlo's env_sample): a row by the
// marginal, a texel by the row's CDF (each through its guide), a point uniformly in its
// (u, v) rectangle; w its density there, the drawn texel's (not looked up again from the
// direction, whose rounding may land in a neighbour), 0 where rounding lands on a texel of
// zero weight.
fn luminance_sample(u: vec4<f32>, size: vec2<u32>) -> vec4<f32> {
    let w = size.x;
    let h = size.y;
    // The guides follow the tables: the marginal's, then one of guide_buckets(w) + 1 a row.
    let guides = 2u + h + 2u * w * h;
    let row_guides = guides + guide_buckets(h) + 1u;
    let j = min(luminance_partition(2u, guides, h, u.x), h - 1u);
    let i = min(luminance_partition(2u + h + j * w, row_guides + j * (guide_buckets(w) + 1u), w, u.y), w - 1u);
    let p_texel = env_cdf[2u + h + w * h + j * w + i];
    if p_texel <= 0.0 {
        return vec4<f32>(0.0);
    }
    let uv = vec2<f32>((f32(i) + u.z) / f32(w), (f32(j) + u.w) / f32(h));
    let d = uv_to_direction(uv);
    return vec4<f32>(d, equirect_density(p_texel, d, vec2<f32>(f32(w), f32(h))));
}

// The density per solid angle of luminance_sample at map-frame direction d
// (LuminanceCdf::luminance_density).
fn luminance_density(d: vec3<f32>, size: vec2<u32>) -> f32 {
    let w = size.x;
    let h = size.y;
    let uv = direction_to_uv(d);
    let fi = floor(uv.x * f32(w));
    let i = u32(fi - f32(w) * floor(fi / f32(w))) % w;
    let j = min(u32(max(floor(uv.y * f32(h)), 0.0)), h - 1u);
    return equirect_density(env_cdf[2u + h + w * h + j * w + i], d, vec2<f32>(f32(w), f32(h)));
}

// The lobe strategy's samples a frame of ball b in shade_environment_mis
// (src/environment/lobe.rs lobe_samples): half of IBL_SAMPLES, rounded up, on a dielectric
// (metallic 0) where the cosine's are fewer too (a map whose own samples find most of its
// light), whose lobe is its specular, at most the Fresnel's share of its light; else all.
// A constant in a pipeline of metals only or of dielectrics only (so that the metals'
// lobe and map samples share their points' bits: shade_environment_mis).
fn lobe_samples(b: Ball) -> u32 {
    if IBL_COSINE_SAMPLES < IBL_SAMPLES && HAS_DIELECTRIC == 1u && (HAS_METAL == 0u || b.metallic <= 0.0) {
        return (IBL_SAMPLES + 1u) / 2u;
    }
    return IBL_SAMPLES;
}

// Whether ball b's lobe is anisotropic (alpha_t > alpha_b); false wherever the pipeline
// compiles the anisotropic code out (HAS_ANISOTROPY = 0: no ball it draws has one).
fn has_anisotropy(b: Ball) -> bool {
    return HAS_ANISOTROPY == 1u && b.anisotropy_alpha_t > b.anisotropy_alpha_b;
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
