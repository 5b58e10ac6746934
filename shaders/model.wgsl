// model.wgsl: the model's BRDF at a shading point, whole, for the estimators that integrate it
// against the map by sampling: the Monte Carlo (montecarlo.wgsl) and the lobe mode's multiple
// importance sampling (lighting.wgsl shade_environment_mis). The f32 twin of
// src/cpu/montecarlo.rs ShadingPoint and model_brdf, name for name.

#define_import_path shadeballs::model
#import shadeballs::constants::{PI, DIV_EPSILON}
#import shadeballs::brdf::{f_schlick, f_avg_schlick, f_micro, f_ms, f_micro_aniso, ball_tangent_frame}
#import shadeballs::brdf::{f_dielectric, f0_from_ior, term_turquin, term_fdez_aguera}
#import shadeballs::lut::lut_loss_row
#import shadeballs::environment::{split_sum_bias, split_sum_scale}
#import shadeballs::sampling::{sample_vndf, sample_vndf_aniso, vndf_density, vndf_density_aniso}
#import shadeballs::types::{Ball, GEOMETRY, IBL, TERM_FDEZ_AGUERA, HAS_ANISOTROPY, HAS_CLEARCOAT, HAS_METAL, HAS_DIELECTRIC, by_term, by_term_f32}
#import shadeballs::coating::{coating_albedo, coating_spec_albedo, coating_base, two_sided}
#import shadeballs::coating::{clearcoat_in, clearcoat_through, clearcoat_through_lobe, clearcoat_base_lobe, clearcoat_base_fresnel_cosine}
#import shadeballs::clearcoat::clearcoat_brdf
#import shadeballs::bindings::{e_table, lut_params, env_split_sum}

// Values of ShadingPoint.part (and of montecarlo.wgsl's McParams.part): the whole model, or
// the term's lobe alone (the reference for a real-time term; src/cpu/montecarlo.rs Part).
const PART_WHOLE: u32 = 0u;
const PART_MULTIPLE: u32 = 1u;

// One visible surface point (src/cpu/montecarlo.rs ShadingPoint): what does not depend on
// the incident direction, formed once per fragment.
struct ShadingPoint {
    n: vec3<f32>,
    v: vec3<f32>,
    mu_o: f32,
    roughness: f32,
    f0: vec3<f32>,
    // The term's weight: 1 with it, 0 without.
    ms: f32,
    // 1 - E(mu_o).
    loss_o: f32,
    // Fdez-Aguera's FssEss of the metal (the split sum's with a map).
    fss_ess: vec3<f32>,
    // The coating's E_spec(mu_o) and Fdez-Aguera energy.
    e_spec_o: f32,
    coat_fms_ems: f32,
    // PART_WHOLE or PART_MULTIPLE: what model_brdf returns (the Monte Carlo's McParams.part;
    // the lobe's estimator takes the whole).
    part: u32,
    // An anisotropic metal lobe's (alpha_t, alpha_b), (0, 0) for an isotropic one, and its
    // tangent frame (src/cpu/model.rs ShadingPoint::anisotropy; ball_tangent_frame's
    // columns t, b, n); roughness is then its isotropic equivalent.
    alphas: vec2<f32>,
    tangent_frame: mat3x3<f32>,
    // Whether model_brdf adds a clear coat's lobe and its shares of the base's light (the
    // Monte Carlo's, after clearcoat.wgsl clearcoat_begin; src/cpu/montecarlo.rs
    // ShadingPoint::clearcoat), and the lobe mode's (lighting.wgsl shade_environment_mis).
    clearcoat: bool,
    // The single-scattering lobes' (roughness, energy scale, alpha scale): (roughness, 1, 1),
    // under a clear coat widened (coated_point, coating.wgsl clearcoat_base_lobe).
    lobe: vec3<f32>,
}

fn shading_point(b: Ball, n: vec3<f32>, v: vec3<f32>) -> ShadingPoint {
    var p: ShadingPoint;
    p.n = n;
    p.v = v;
    p.mu_o = max(dot(n, v), 0.0);
    p.roughness = b.roughness;
    p.f0 = b.f0;
    p.ms = b.ms;
    p.part = PART_WHOLE;
    p.lobe = vec3<f32>(b.roughness, 1.0, 1.0);
    p.loss_o = lut_loss_row(e_table, lut_params(), p.mu_o, b.lut_row);
    if HAS_ANISOTROPY == 1u && b.anisotropy_alpha_t > b.anisotropy_alpha_b {
        p.alphas = vec2<f32>(b.anisotropy_alpha_t, b.anisotropy_alpha_b);
        p.tangent_frame = ball_tangent_frame(n, vec2<f32>(b.anisotropy_cos, b.anisotropy_sin));
    }
    let e_o = 1.0 - p.loss_o;
    p.fss_ess = f_avg_schlick(p.f0) * e_o;
    if IBL != 0u {
        p.fss_ess = split_sum_scale(p.f0, e_o, split_sum_bias(env_split_sum, p.mu_o, p.roughness));
    }
    if HAS_DIELECTRIC == 1u && b.metallic < 1.0 {
        let f0 = f0_from_ior(b.eta);
        let loss = p.loss_o * p.ms;
        // Under a clear coat the coating's Fresnel is read inside the coat (a refracted
        // cosine).
        let e_f_o = coating_albedo(b.coating_row, clearcoat_base_fresnel_cosine(b, p.mu_o));
        p.e_spec_o = coating_spec_albedo(e_f_o, loss, f0, b.coat_f_add, p.ms, b.term);
        if p.ms > 0.0 && b.term == TERM_FDEZ_AGUERA {
            p.coat_fms_ems = term_fdez_aguera(vec3<f32>(e_f_o), vec3<f32>(f0), loss).x;
        }
    }
    return p;
}

// Point p of ball b under its clear coat (after clearcoat.wgsl clearcoat_begin): model_brdf
// adds the coat's lobe and its shares of the base's light, and reads the base's lobes as
// they leave the coat, wider (clearcoat_base_lobe; an anisotropic lobe's alphas scaled with
// it). src/cpu/model.rs coated_point.
fn coated_point(b: Ball, p_in: ShadingPoint) -> ShadingPoint {
    var p = p_in;
    p.clearcoat = true;
    p.lobe = clearcoat_base_lobe(b, p.mu_o);
    p.alphas *= p.lobe.z;
    return p;
}

// The BRDF f_r(v, l) of the ball's model per channel, 0 below either horizon
// (src/cpu/montecarlo.rs model_brdf; the light loops of shade_metal in lighting.wgsl and
// shade_coating in coating.wgsl): the metal's and the coating's mixed by metallic; under a
// clear coat (p.clearcoat) the coat's own lobe, and the base's light times what the coat
// lets through, a glossy base's and a Lambertian one's (docs/design/coat.md).
fn model_brdf(b: Ball, p: ShadingPoint, l: vec3<f32>) -> vec3<f32> {
    let mu_i = dot(p.n, l);
    if mu_i <= 0.0 || p.mu_o <= 0.0 {
        return vec3<f32>(0.0);
    }
    let sum = p.v + l;
    let len = length(sum);
    if len <= DIV_EPSILON {
        return vec3<f32>(0.0);
    }
    let h = sum / len;
    var loss_i = 0.0;
    if p.ms > 0.0 {
        loss_i = lut_loss_row(e_table, lut_params(), mu_i, b.lut_row);
    }
    var through_lobe = vec3<f32>(1.0);
    var through_base = vec3<f32>(1.0);
    var coat = 0.0;
    if HAS_CLEARCOAT == 1u && p.clearcoat {
        let t_in = clearcoat_in(b, mu_i, dot(p.v, h));
        if p.part == PART_WHOLE {
            coat = clearcoat_brdf(b, p.n, p.v, l);
        }
        through_lobe = clearcoat_through_lobe(b, t_in);
        through_base = clearcoat_through(b, t_in);
    }
    let metallic = b.metallic;
    var f = vec3<f32>(0.0);
    if HAS_METAL == 1u && metallic > 0.0 {
        f = metallic * through_lobe * metal_brdf(b, p, l, mu_i, h, loss_i);
    }
    if HAS_DIELECTRIC == 1u && metallic < 1.0 {
        f += (1.0 - metallic) * coating_brdf(b, p, l, mu_i, h, loss_i, through_lobe, through_base);
    }
    return f + vec3<f32>(coat);
}

// The metal's part of model_brdf: f_micro with Schlick F per channel (f_micro_aniso in the
// tangent frame for an anisotropic lobe) and the ball's term.
fn metal_brdf(b: Ball, p: ShadingPoint, l: vec3<f32>, mu_i: f32, h: vec3<f32>, loss_i: f32) -> vec3<f32> {
    // Under a clear coat the base's Fresnel is read inside the coat (a refracted cosine).
    let fresnel = f_schlick(p.f0, clearcoat_base_fresnel_cosine(b, dot(p.v, h)));
    var spec: vec3<f32>;
    if HAS_ANISOTROPY == 1u && p.alphas.x > p.alphas.y {
        let to_local = transpose(p.tangent_frame);
        spec = f_micro_aniso(fresnel, to_local * p.v, to_local * l, to_local * h, p.alphas.x, p.alphas.y, GEOMETRY);
    } else {
        spec = f_micro(fresnel, p.mu_o, mu_i, dot(p.n, h), p.lobe.x, GEOMETRY);
    }
    spec *= p.lobe.y;
    var multiple = vec3<f32>(0.0);
    if p.ms > 0.0 {
        multiple = by_term(
            b.term,
            p.ms * b.f_add * f_ms(p.loss_o, loss_i, b.ms_norm),
            p.ms * term_turquin(spec, p.f0, 1.0 - p.loss_o),
            p.ms * term_fdez_aguera(p.fss_ess, p.f0, p.loss_o) / PI,
        );
    }
    if p.part == PART_MULTIPLE {
        return multiple;
    }
    return spec + multiple;
}

// The coating's part of model_brdf (src/cpu/coating.rs CoatingPoint::brdf), its specular
// and term times through_lobe and its base times through_base (a clear coat's shares; 1
// without one).
fn coating_brdf(b: Ball, p: ShadingPoint, l: vec3<f32>, mu_i: f32, h: vec3<f32>, loss_i: f32, through_lobe: vec3<f32>, through_base: vec3<f32>) -> vec3<f32> {
    let eta = b.eta;
    let f_add = b.coat_f_add;
    let f0 = f0_from_ior(eta);
    let fresnel = f_dielectric(clearcoat_base_fresnel_cosine(b, dot(p.v, h)), eta, b.fresnel);
    let spec = p.lobe.y * f_micro(vec3<f32>(fresnel), p.mu_o, mu_i, dot(p.n, h), p.lobe.x, GEOMETRY).x;
    let loss_o = p.loss_o * p.ms;
    var lobe = 0.0;
    if p.ms > 0.0 {
        lobe = by_term_f32(
            b.term,
            f_add * f_ms(loss_o, loss_i, b.ms_norm),
            term_turquin(vec3<f32>(spec), vec3<f32>(f0), 1.0 - loss_o).x,
            p.coat_fms_ems / PI,
        );
    }
    var e_spec_i = 0.0;
    if two_sided(b) {
        let e_f_i = coating_albedo(b.coating_row, clearcoat_base_fresnel_cosine(b, mu_i));
        e_spec_i = coating_spec_albedo(e_f_i, loss_i, f0, f_add, p.ms, b.term);
    }
    if p.part == PART_MULTIPLE {
        return through_lobe * (p.ms * lobe);
    }
    return through_lobe * (spec + p.ms * lobe) + through_base * coating_base(b, p.e_spec_o, e_spec_i, fresnel);
}

// Density (solid angle) of sample_vndf at l (vndf_density at l's half vector).
fn pdf_vndf(p: ShadingPoint, l: vec3<f32>, alpha: f32) -> f32 {
    let sum = p.v + l;
    let len = length(sum);
    if len <= DIV_EPSILON {
        return 0.0;
    }
    let h = sum / len;
    return vndf_density(p.mu_o, dot(p.n, h), alpha);
}

// A direction drawn from the metal lobe's visible normals, reflected (src/cpu/model.rs
// sample_lobe): an anisotropic lobe's own in its tangent frame (sample_vndf_aniso), an
// isotropic one's of alpha in `frame`, any orthonormal frame about n, where v is v_local
// (sample_vndf). Its density is pdf_vndf_lobe's.
fn sample_lobe(p: ShadingPoint, frame: mat3x3<f32>, v_local: vec3<f32>, alpha: f32, u: vec2<f32>) -> vec3<f32> {
    if HAS_ANISOTROPY == 1u && p.alphas.x > 0.0 {
        let to_local = transpose(p.tangent_frame);
        return p.tangent_frame * sample_vndf_aniso(to_local * p.v, p.alphas.x, p.alphas.y, u.x, u.y);
    }
    return frame * sample_vndf(v_local, alpha, u.x, u.y);
}

// Density (solid angle) of sample_lobe at l: vndf_density_aniso at l's half vector in the
// tangent frame of an anisotropic lobe, else pdf_vndf of alpha.
fn pdf_vndf_lobe(p: ShadingPoint, l: vec3<f32>, alpha: f32) -> f32 {
    if HAS_ANISOTROPY == 1u && p.alphas.x > 0.0 {
        let sum = p.v + l;
        let len = length(sum);
        if len <= DIV_EPSILON {
            return 0.0;
        }
        let to_local = transpose(p.tangent_frame);
        return vndf_density_aniso(to_local * p.v, to_local * (sum / len), p.alphas.x, p.alphas.y);
    }
    return pdf_vndf(p, l, alpha);
}
