// brdf.wgsl: the BRDF terms, name for name the f64 functions of src/brdf evaluated in f32
// (docs/design/model.md). Conventions: normal +z, mu_o = n.v, mu_i = n.l, alpha =
// roughness^2. Fresnel-dependent functions take vec3 (one Rust call per channel).

#define_import_path shadeballs::brdf
#import shadeballs::constants::{PI, DIV_EPSILON, ROUGHNESS_MIN, LAMBDA_MAX}
#import shadeballs::constants::{GEOMETRY_SMITH, GEOMETRY_SMITH_CORRELATED, F_ADD_GAMES202, FRESNEL_SCHLICK}

// The roughness the model uses: clamped to [ROUGHNESS_MIN, 1] (src/brdf roughness_clamped;
// the shader never sees NaN: scenes are validated on load).
fn roughness_clamped(roughness: f32) -> f32 {
    return clamp(roughness, ROUGHNESS_MIN, 1.0);
}

// alpha = roughness^2 (Burley 2012's remapping), after the roughness clamp.
fn alpha_from_roughness(roughness: f32) -> f32 {
    let r = roughness_clamped(roughness);
    return r * r;
}

// GGX / Trowbridge-Reitz NDF (Walter et al. 2007, "Microfacet Models for Refraction
// through Rough Surfaces", eq. 33): D(h) = alpha^2 / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2),
// with 1 - (n.h)^2 formed first, as (1 - n.h)(1 + n.h), to keep precision near the mirror
// direction (1 - n.h is exact there; 1 - (n.h)^2 would carry the square's rounding).
fn d_ggx(n_dot_h: f32, alpha: f32) -> f32 {
    if n_dot_h <= 0.0 {
        return 0.0;
    }
    let c = min(n_dot_h, 1.0);
    let c2 = c * c;
    let a2 = alpha * alpha;
    let s2 = (1.0 - c) * (1.0 + c);
    let denom = max(c2 * a2 + s2, DIV_EPSILON);
    return a2 / (PI * denom * denom);
}

// Schlick-GGX G1 (Schlick 1994, eq. 19, with Karis 2013's k = alpha / 2):
// G1(c) = c / (c (1 - k) + k).
fn g1_schlick(c_in: f32, k: f32) -> f32 {
    let c = max(c_in, 0.0);
    return c / max(c * (1.0 - k) + k, DIV_EPSILON);
}

// Separable Schlick-GGX: G = G1(mu_o) G1(mu_i), k = roughness^2 / 2.
fn g_schlick(mu_o: f32, mu_i: f32, roughness: f32) -> f32 {
    let k = alpha_from_roughness(roughness) / 2.0;
    return g1_schlick(mu_o, k) * g1_schlick(mu_i, k);
}

// Smith's Lambda for GGX (Heitz 2014, eq. 72): (-1 + sqrt(1 + alpha^2 tan^2)) / 2, written
// alpha^2 tan^2 / (2 (1 + sqrt(1 + alpha^2 tan^2))) against cancellation, sin^2 as
// (1 - c)(1 + c). c = 0 gives LAMBDA_MAX (+infinity in the Rust model).
fn lambda_smith(c_in: f32, alpha: f32) -> f32 {
    let c = clamp(c_in, 0.0, 1.0);
    let c2 = c * c;
    if c2 <= 0.0 {
        return LAMBDA_MAX;
    }
    let a2t2 = alpha * alpha * ((1.0 - c) * (1.0 + c)) / c2;
    return a2t2 / (2.0 * (1.0 + sqrt(1.0 + a2t2)));
}

// Exact Smith G1 for GGX (Walter et al. 2007, eq. 34): 2 / (1 + sqrt(1 + alpha^2 tan^2)),
// written 2c / (c + sqrt(c^2 + alpha^2 (1 - c^2))), finite at c = 0.
fn g1_smith(c_in: f32, alpha: f32) -> f32 {
    let c = clamp(c_in, 0.0, 1.0);
    let root = sqrt(c * c + alpha * alpha * (1.0 - c * c));
    return 2.0 * c / max(c + root, DIV_EPSILON);
}

// Separable Smith: G = G1(mu_o) G1(mu_i).
fn g_smith(mu_o: f32, mu_i: f32, roughness: f32) -> f32 {
    let alpha = alpha_from_roughness(roughness);
    return g1_smith(mu_o, alpha) * g1_smith(mu_i, alpha);
}

// Height-correlated Smith (Heitz 2014, "Understanding the Masking-Shadowing Function in
// Microfacet-Based BRDFs", eq. 99): G = 1 / (1 + Lambda(mu_o) + Lambda(mu_i)).
fn g_smith_correlated(mu_o: f32, mu_i: f32, roughness: f32) -> f32 {
    let alpha = alpha_from_roughness(roughness);
    return 1.0 / (1.0 + lambda_smith(mu_o, alpha) + lambda_smith(mu_i, alpha));
}

// The G of `geometry` (GEOMETRY_*; src/brdf Geometry::g). The tables must be baked with the
// same G (a pipeline passes a constant, which the compiler folds).
fn geometry_g(mu_o: f32, mu_i: f32, roughness: f32, geometry: u32) -> f32 {
    if geometry == GEOMETRY_SMITH {
        return g_smith(mu_o, mu_i, roughness);
    }
    if geometry == GEOMETRY_SMITH_CORRELATED {
        return g_smith_correlated(mu_o, mu_i, roughness);
    }
    return g_schlick(mu_o, mu_i, roughness);
}

// Anisotropic GGX (Heitz 2014, "Understanding the Masking-Shadowing Function in
// Microfacet-Based BRDFs", JCGT 3(2); src/brdf/anisotropy.rs, name for name), vectors in
// the local frame (tangent x, alpha_t; bitangent y, alpha_b; normal z).
// D(h) = 1 / (pi alpha_t alpha_b ((h_x / alpha_t)^2 + (h_y / alpha_b)^2 + h_z^2)^2).
fn d_ggx_aniso(h: vec3<f32>, alpha_t: f32, alpha_b: f32) -> f32 {
    if h.z <= 0.0 {
        return 0.0;
    }
    let x = h.x / alpha_t;
    let y = h.y / alpha_b;
    let s = x * x + y * y + h.z * h.z;
    return 1.0 / max(PI * alpha_t * alpha_b * s * s, DIV_EPSILON);
}

// Smith's Lambda of anisotropic GGX: a / (2 (1 + sqrt(1 + a))), a = (alpha_t^2 w_x^2 +
// alpha_b^2 w_y^2) / w_z^2; LAMBDA_MAX at or below the horizon.
fn lambda_smith_aniso(w: vec3<f32>, alpha_t: f32, alpha_b: f32) -> f32 {
    let z = max(w.z, 0.0);
    let z2 = z * z;
    if z2 <= 0.0 {
        return LAMBDA_MAX;
    }
    let a = (alpha_t * alpha_t * w.x * w.x + alpha_b * alpha_b * w.y * w.y) / z2;
    return a / (2.0 * (1.0 + sqrt(1.0 + a)));
}

// The G of `geometry` for the anisotropic lobe: height-correlated Smith
// 1 / (1 + Lambda(o) + Lambda(i)), separable Smith 1 / ((1 + Lambda(o)) (1 + Lambda(i))), or
// Schlick-GGX at the isotropic-equivalent roughness (alpha_t alpha_b)^(1/4).
fn g_aniso(o: vec3<f32>, i: vec3<f32>, alpha_t: f32, alpha_b: f32, geometry: u32) -> f32 {
    if geometry == GEOMETRY_SMITH_CORRELATED {
        return 1.0 / (1.0 + lambda_smith_aniso(o, alpha_t, alpha_b) + lambda_smith_aniso(i, alpha_t, alpha_b));
    }
    if geometry == GEOMETRY_SMITH {
        return 1.0 / ((1.0 + lambda_smith_aniso(o, alpha_t, alpha_b)) * (1.0 + lambda_smith_aniso(i, alpha_t, alpha_b)));
    }
    return g_schlick(o.z, i.z, sqrt(sqrt(alpha_t * alpha_b)));
}

// The anisotropic lobe's single scattering F G D / (4 mu_i mu_o), local o, i and their half
// vector h; 0 below the horizon.
fn f_micro_aniso(fresnel: vec3<f32>, o: vec3<f32>, i: vec3<f32>, h: vec3<f32>, alpha_t: f32, alpha_b: f32, geometry: u32) -> vec3<f32> {
    if o.z <= 0.0 || i.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    let d = d_ggx_aniso(h, alpha_t, alpha_b);
    let g = g_aniso(o, i, alpha_t, alpha_b, geometry);
    return fresnel * (g * d / max(4.0 * i.z * o.z, DIV_EPSILON));
}

// The ball's tangent field at unit normal n (brdf::ball_tangent): the tangent of the circle
// of latitude about +y, normalize(y x n) (+x at the poles), turned by the rotation (cos, sin)
// about n; returns the frame (t, b, n) as columns.
fn ball_tangent_frame(n: vec3<f32>, turn: vec2<f32>) -> mat3x3<f32> {
    let around = vec3<f32>(n.z, 0.0, -n.x);
    let len2 = dot(around, around);
    var t0 = vec3<f32>(1.0, 0.0, 0.0);
    if len2 > DIV_EPSILON {
        t0 = around / sqrt(len2);
    }
    let b0 = cross(n, t0);
    let t = turn.x * t0 + turn.y * b0;
    return mat3x3<f32>(t, cross(n, t), n);
}

// The roughness of the isotropic lobe of an anisotropic pair's solid angle, alpha =
// sqrt(alpha_t alpha_b): the level the split sum reads the prefiltered map at (src/brdf
// equal_area_roughness).
fn equal_area_roughness(alpha_t: f32, alpha_b: f32) -> f32 {
    return sqrt(sqrt(max(alpha_t * alpha_b, 0.0)));
}

// Schlick's approximation (Schlick 1994, "An Inexpensive BRDF Model for Physically-based
// Rendering", eq. 15): F = F0 + (1 - F0) (1 - cos)^5, cos = v.h, clamped to [0, 1].
fn f_schlick(f0: vec3<f32>, cos_theta: f32) -> vec3<f32> {
    let m = clamp(1.0 - clamp(cos_theta, 0.0, 1.0), 0.0, 1.0);
    let m2 = m * m;
    return f0 + (1.0 - f0) * (m2 * m2 * m);
}

// Cosine-weighted average of Schlick's Fresnel: F_avg = F0 + (1 - F0) / 21 (Kulla & Conty
// 2017, slide 26 gives the same integral).
fn f_avg_schlick(f0: vec3<f32>) -> vec3<f32> {
    return f0 + (1.0 - f0) / 21.0;
}

// The homework's F_avg: Kulla & Conty 2017 (slide 26)'s polynomial fit of the average
// Fresnel of Gulbrandsen 2014's artist-friendly conductor, reflectivity r, edge tint g.
fn f_avg_games202(r: vec3<f32>, g: vec3<f32>) -> vec3<f32> {
    return 0.087237 + 0.0230685 * g - 0.0864902 * g * g + 0.0774594 * g * g * g + 0.782654 * r
        - 0.136432 * r * r
        + 0.278708 * r * r * r
        + 0.19744 * g * r
        + 0.0360605 * g * g * r
        - 0.2586 * g * r * r;
}

// The energy-compensation lobe (Kulla & Conty 2017, slide 18):
// f_ms = (1 - E(mu_o)) (1 - E(mu_i)) / (pi (1 - E_avg)), from the losses 1 - E as the
// tables store them and the normalisation 1 / (pi (1 - E_avg)), constant over a ball and
// formed once per ball on the CPU (src/brdf f_ms_norm; src/gpu/uniforms.rs balls), not
// divided per pixel.
fn f_ms(loss_o: f32, loss_i: f32, norm: f32) -> f32 {
    return loss_o * loss_i * norm;
}

// Fresnel scale of the lobe, summed over all bounces after the first (Kulla & Conty 2017,
// slide 26, with the square that the geometric series gives; docs/design/model.md, "Where
// F_avg^2 comes from"): F_avg^2 E_avg / (1 - F_avg (1 - E_avg)).
fn f_add_accurate(f_avg: vec3<f32>, e_avg: f32) -> vec3<f32> {
    return f_avg * f_avg * e_avg / f_add_denominator(f_avg, e_avg);
}

// The homework's Fresnel scale F_avg E_avg / (1 - F_avg (1 - E_avg)) (no square; GAMES202
// homework 1, Kulla & Conty 2017 slide 26 as the homework transcribes it).
fn f_add_games202(f_avg: vec3<f32>, e_avg: f32) -> vec3<f32> {
    return f_avg * e_avg / f_add_denominator(f_avg, e_avg);
}

// 1 - F_avg (1 - E_avg) as (1 - F_avg) + F_avg E_avg: two non-negative terms, no cancellation
// as F_avg -> 1 (src/brdf f_add_denominator).
fn f_add_denominator(f_avg: vec3<f32>, e_avg: f32) -> vec3<f32> {
    return max((1.0 - f_avg) + f_avg * e_avg, vec3<f32>(DIV_EPSILON));
}

// The Fresnel scale f_add as the preset computes it (Kulla & Conty 2017, slide 26; src/brdf
// f_add_preset): form F_ADD_ACCURATE = f_add_accurate of Schlick's F_avg(F0); F_ADD_GAMES202 =
// f_add_games202 of the homework's polynomial F_avg of F0 and `edge_tint`.
fn f_add_preset(form: u32, f0: vec3<f32>, edge_tint: vec3<f32>, e_avg: f32) -> vec3<f32> {
    if form == F_ADD_GAMES202 {
        return f_add_games202(f_avg_games202(f0, edge_tint), e_avg);
    }
    return f_add_accurate(f_avg_schlick(f0), e_avg);
}

// The single-scattering Cook-Torrance BRDF (Cook & Torrance 1982; Walter et al. 2007):
// F G D / (4 mu_i mu_o) for a Fresnel value per channel, G of `geometry` (GEOMETRY_*);
// below the horizon 0.
fn f_micro(fresnel: vec3<f32>, mu_o: f32, mu_i: f32, n_dot_h: f32, roughness: f32, geometry: u32) -> vec3<f32> {
    if mu_o <= 0.0 || mu_i <= 0.0 {
        return vec3<f32>(0.0);
    }
    let alpha = alpha_from_roughness(roughness);
    let d = d_ggx(n_dot_h, alpha);
    let g = geometry_g(mu_o, mu_i, roughness, geometry);
    return fresnel * (g * d / max(4.0 * mu_i * mu_o, DIV_EPSILON));
}

// The multiple-scattering compensations other than Kulla-Conty's lobe (f_ms in lut.wgsl's
// neighbour, lighting.wgsl), per channel as src/brdf/compensation.rs.
//
// Turquin 2019 ("Practical multiple scattering compensation for microfacet models"): the
// single-scattering result `single` times 1 + F0 (1 / E - 1); returns the added part.
fn term_turquin(single: vec3<f32>, f0: vec3<f32>, e_o: f32) -> vec3<f32> {
    return single * f0 * (1.0 / max(e_o, DIV_EPSILON) - 1.0);
}

// Fdez-Aguera 2019 ("A Multiple-Scattering Microfacet Model for Real-Time Image-based
// Lighting"): the multiple-scattering energy FmsEms = FssEss F_avg Ems / (1 - Ems F_avg),
// Ems = 1 - E(mu_o), F_avg = F0 + (1 - F0) / 21; it reflects light as if diffuse (times the
// irradiance, or 1 / pi per unit of light and cosine).
fn term_fdez_aguera(fss_ess: vec3<f32>, f0: vec3<f32>, loss_o: f32) -> vec3<f32> {
    let f_avg = f_avg_schlick(f0);
    return fss_ess * f_avg * loss_o / max(1.0 - loss_o * f_avg, vec3<f32>(DIV_EPSILON));
}

// The exact unpolarised Fresnel reflectance of a dielectric interface (Walter et al. 2007,
// eq. 22): eta = n_t / n_i, g^2 = eta^2 - 1 + c^2, and 1 past the critical angle.
fn fresnel_dielectric(cos_theta: f32, eta: f32) -> f32 {
    let c = min(abs(cos_theta), 1.0);
    let g2 = eta * eta - 1.0 + c * c;
    if g2 < 0.0 {
        return 1.0;
    }
    let g = sqrt(g2);
    let a = (g - c) / max(g + c, DIV_EPSILON);
    let b = (c * (g + c) - 1.0) / max(c * (g - c) + 1.0, DIV_EPSILON);
    return clamp(0.5 * a * a * (1.0 + b * b), 0.0, 1.0);
}

// F0 = ((eta - 1) / (eta + 1))^2, Schlick's F0 of a dielectric (glTF KHR_materials_ior).
fn f0_from_ior(eta: f32) -> f32 {
    let r = (eta - 1.0) / max(eta + 1.0, DIV_EPSILON);
    return r * r;
}

// The base under a dielectric coating, each form as a BRDF (src/brdf/layering.rs, name for
// name; albedo per channel, the coating's specular albedo E_spec achromatic).
// Today's constant weighting: albedo (1 - F_avg) / pi.
fn f_base_constant(albedo: vec3<f32>, f_avg: f32) -> vec3<f32> {
    return albedo * ((1.0 - f_avg) / PI);
}

// glTF 2.0's fresnel_mix (appendix B): albedo (1 - F(v.h)) / pi.
fn f_base_gltf(albedo: vec3<f32>, fresnel_vh: f32) -> vec3<f32> {
    return albedo * ((1.0 - fresnel_vh) / PI);
}

// Cycles' Principled v2 and MaterialX, view-only: albedo (1 - E_spec(mu_o)) / pi.
fn f_base_view_only(albedo: vec3<f32>, e_spec_o: f32) -> vec3<f32> {
    return albedo * ((1.0 - e_spec_o) / PI);
}

// OpenPBR's reciprocal scaling (Kutz et al. 2021):
// albedo (1 - E_spec(mu_i)) (1 - E_spec(mu_o)) / (pi (1 - E_spec_avg)).
fn f_base_reciprocal(albedo: vec3<f32>, e_spec_o: f32, e_spec_i: f32, e_spec_avg: f32) -> vec3<f32> {
    return albedo * ((1.0 - e_spec_o) * (1.0 - e_spec_i) / (PI * max(1.0 - e_spec_avg, DIV_EPSILON)));
}

// F_in = 1 - (1 - E_spec_avg) / eta^2: the substrate's light the coating sends back down.
fn coating_inside_reflectance(e_spec_avg: f32, eta: f32) -> f32 {
    return 1.0 - (1.0 - e_spec_avg) / max(eta * eta, DIV_EPSILON);
}

// The physical form, a Lambertian substrate under the coating, internal bounces summed:
// rho (1 - E_spec(mu_i)) (1 - E_spec(mu_o)) / (pi eta^2 (1 - rho F_in)).
fn f_base_physical(rho: vec3<f32>, e_spec_o: f32, e_spec_i: f32, e_spec_avg: f32, eta: f32) -> vec3<f32> {
    let f_in = coating_inside_reflectance(e_spec_avg, eta);
    let shape = (1.0 - e_spec_o) * (1.0 - e_spec_i) / PI;
    return rho * shape / max(eta * eta * (vec3<f32>(1.0) - rho * f_in), vec3<f32>(DIV_EPSILON));
}

// The substrate albedo whose light through the coating averages `apparent`:
// rho = apparent / (T + apparent F_in), T = 1 - F_in.
fn substrate_albedo(apparent: vec3<f32>, e_spec_avg: f32, eta: f32) -> vec3<f32> {
    let f_in = coating_inside_reflectance(e_spec_avg, eta);
    return apparent / max(vec3<f32>(1.0 - f_in) + apparent * f_in, vec3<f32>(DIV_EPSILON));
}

// Each form's directional albedo, its integral over the light's hemisphere (what a uniform
// light or a map's irradiance meets; src/brdf/layering.rs, name for name).
// albedo (1 - F_avg).
fn base_albedo_constant(albedo: vec3<f32>, f_avg: f32) -> vec3<f32> {
    return albedo * (1.0 - f_avg);
}

// glTF's under image-based light, the view's Fresnel for the half vector's: albedo (1 - F(mu_o)).
fn base_albedo_gltf(albedo: vec3<f32>, fresnel_o: f32) -> vec3<f32> {
    return albedo * (1.0 - fresnel_o);
}

// The view-only and the reciprocal forms: albedo (1 - E_spec(mu_o)).
fn base_albedo_view_only(albedo: vec3<f32>, e_spec_o: f32) -> vec3<f32> {
    return albedo * (1.0 - e_spec_o);
}

// The physical form: rho (1 - E_spec(mu_o)) (1 - E_spec_avg) / (eta^2 (1 - rho F_in)).
fn base_albedo_physical(rho: vec3<f32>, e_spec_o: f32, e_spec_avg: f32, eta: f32) -> vec3<f32> {
    let f_in = coating_inside_reflectance(e_spec_avg, eta);
    let shape = (1.0 - e_spec_o) * (1.0 - e_spec_avg);
    return rho * shape / max(eta * eta * (vec3<f32>(1.0) - rho * f_in), vec3<f32>(DIV_EPSILON));
}

// The coating's Fresnel (src/brdf/fresnel.rs f_dielectric): exact (FRESNEL_EXACT) or
// Schlick's of the same index (FRESNEL_SCHLICK).
fn f_dielectric(cos_theta: f32, eta: f32, form: u32) -> f32 {
    if form == FRESNEL_SCHLICK {
        return f_schlick(vec3<f32>(f0_from_ior(eta)), cos_theta).x;
    }
    return fresnel_dielectric(cos_theta, eta);
}

// The share of the base's light under the clear coat of weight `weight`, light arriving
// with the coat's transmission t_coat_i: (1 - weight) + weight out t_coat_i, out per
// channel the view's part (src/brdf/clearcoat.rs).
fn clearcoat_through_physical(weight: f32, out: vec3<f32>, t_coat_i: f32) -> vec3<f32> {
    return vec3<f32>(1.0 - weight) + weight * out * t_coat_i;
}

// A Lambertian base's light through the physical coat: 1 / (eta^2 (1 - A_avg F_in))
// (src/brdf/clearcoat.rs clearcoat_inside_scale).
fn clearcoat_inside_scale(a_avg: vec3<f32>, e_coat_avg: f32, eta: f32) -> vec3<f32> {
    let f_in = coating_inside_reflectance(e_coat_avg, eta);
    return 1.0 / max((eta * eta) * (1.0 - a_avg * f_in), vec3<f32>(DIV_EPSILON));
}

// A glossy base's light through the physical coat, escaping with the share `escape` on
// its first way up: (1 - (1 - X) (1 - A_avg) / (1 - A_avg F_in)) / (1 - E_c_avg)
// (src/brdf/clearcoat.rs clearcoat_lobe_scale).
fn clearcoat_lobe_scale(a_avg: vec3<f32>, escape: f32, e_coat_avg: f32, eta: f32) -> vec3<f32> {
    let f_in = coating_inside_reflectance(e_coat_avg, eta);
    let kept = (1.0 - escape) * (1.0 - a_avg) / max(1.0 - a_avg * f_in, vec3<f32>(DIV_EPSILON));
    return (1.0 - kept) / max(1.0 - e_coat_avg, DIV_EPSILON);
}

// The cosine at which a glossy base's Fresnel is read under the physical coat: c refracted
// into the coat of index eta, mixed with c by the weight (src/brdf/clearcoat.rs
// clearcoat_base_cosine).
fn clearcoat_base_cosine(c: f32, eta: f32, weight: f32) -> f32 {
    let sin2 = max(1.0 - c * c, 0.0) / max(eta * eta, DIV_EPSILON);
    let refracted = sqrt(max(1.0 - sin2, 0.0));
    return c + weight * (refracted - c);
}

// The cosine-weighted average of Schlick's (1 - mu)^5 inside the coat's critical cone,
// 2 eta^2 (X^6 / 6 - X^7 / 7) with X = 1 - sqrt(1 - 1 / eta^2), mixed with the hemisphere's
// 1 / 21 by the weight (src/brdf/clearcoat.rs clearcoat_base_schlick_avg).
fn clearcoat_base_schlick_avg(eta: f32, weight: f32) -> f32 {
    let eta2 = max(eta * eta, 1.0);
    let x = 1.0 - sqrt(1.0 - 1.0 / eta2);
    let x2 = x * x;
    let x6 = x2 * x2 * x2;
    let cone = 2.0 * eta2 * (x6 / 6.0 - x6 * x / 7.0);
    return 1.0 / 21.0 + weight * (cone - 1.0 / 21.0);
}

// A ball's escape curve (four unorm8 nodes at sqrt(mu) = k / 3) read at mu, linear in
// sqrt(mu) (src/brdf/clearcoat.rs clearcoat_escape_at).
fn clearcoat_escape_at(packed: u32, mu: f32) -> f32 {
    let nodes = unpack4x8unorm(packed);
    let x = sqrt(clamp(mu, 0.0, 1.0)) * 3.0;
    let k = min(u32(floor(x)), 2u);
    let t = x - f32(k);
    return nodes[k] + t * (nodes[k + 1u] - nodes[k]);
}

// The share of the base's light under an engine's clear coat: 1 - weight F.
fn clearcoat_through_engine(weight: f32, fresnel: f32) -> f32 {
    return 1.0 - weight * fresnel;
}
