//! A clear coat over a whole ball's shading (docs/design/coat.md): a rough dielectric
//! interface of its own roughness and index over whatever the ball is (metal, plastic or
//! a mix), weighted by the coat's `weight` as OpenPBR's `coat_weight` is (a mix: a share
//! `1 - weight` of the surface has no coat).
//!
//! The physical form (the default) follows the layering of Weidlich and Wilkie 2007
//! ("Arbitrarily Layered Micro-Facet Surfaces") as Kulla and Conty 2017 ("Revisiting
//! Physically Based Shading at Imageworks", the layering section) write it with albedos: the
//! coat reflects its own specular albedo `E_c(mu)` (its single scattering and its
//! Kulla-Conty term), the base is seen through it with the transmission `1 - E_c` both ways,
//! and the light the base sends back up is partly reflected down again by the coat, the
//! internal reflections summed as a geometric series of the base's average albedo
//! `A_avg` and the coat's inside reflectance `F_in = 1 - (1 - E_c_avg) / eta^2`:
//! `f = f_c + (1 - E_c(mu_o)) (1 - E_c(mu_i)) f_base / (eta^2 (1 - A_avg F_in))`.
//! A white base (`A = 1` at every angle) then reflects everything under uniform light, as
//! [`crate::brdf::f_base_physical`] does for the Lambertian substrate. That sum treats the
//! base's light as Lambertian; a glossy base's (a metal's lobe, a plastic's specular) leaves
//! mostly through the coat's escape cone on its first way up, with the share
//! [`clearcoat_escape`], and takes [`clearcoat_lobe_scale`] instead.
//!
//! The engines' forms, for comparison, conserve no energy: Filament's (the clear coat of
//! "Physically Based Rendering in Filament", Guy and Agopian) attenuates the base by `1 -
//! F_c(v.h)`; glTF's `KHR_materials_clearcoat` mixes base and coat by `weight F_c(n.v)`.

use super::DIV_EPSILON;

/// The factor of the base's light seen through the physical coat, after the two
/// transmissions: `1 / (eta^2 (1 - A_avg F_in))`, `F_in = 1 - (1 - E_c_avg) / eta^2`
/// ([`super::coating_inside_reflectance`]): the internal reflections between the coat and a
/// base of average albedo `a_avg` summed, and the radiance's `1 / eta^2` on leaving the
/// denser coat.
pub(crate) fn clearcoat_inside_scale(a_avg: f64, e_coat_avg: f64, eta: f64) -> f64 {
    let f_in = super::coating_inside_reflectance(e_coat_avg, eta);
    1.0 / ((eta * eta) * (1.0 - a_avg * f_in)).max(DIV_EPSILON)
}

/// The factor of a glossy base's light (a metal's lobe, a plastic's specular) seen through
/// the physical coat, after the two transmissions: `G / (1 - E_c_avg)` with
/// `G = X + (1 - X) c`, `c = A_avg (1 - F_in) / (1 - A_avg F_in)`. The base's first
/// reflection leaves through the coat with the share `escape` (`X`, [`clearcoat_escape`]),
/// and the rest, reflected back down, is summed as the Lambertian base's internal
/// reflections (Weidlich and Wilkie 2007), each bounce leaving with `1 - F_in`. With `X`
/// the Lambertian base's `1 - F_in` this is [`clearcoat_inside_scale`]; with `A_avg = 1`
/// it is `1 / (1 - E_c_avg)` whatever `X`, so a white base under the coat still
/// reflects everything.
pub(crate) fn clearcoat_lobe_scale(a_avg: f64, escape: f64, e_coat_avg: f64, eta: f64) -> f64 {
    let f_in = super::coating_inside_reflectance(e_coat_avg, eta);
    let kept = (1.0 - escape) * (1.0 - a_avg) / (1.0 - a_avg * f_in).max(DIV_EPSILON);
    (1.0 - kept) / (1.0 - e_coat_avg).max(DIV_EPSILON)
}

/// The roughness at which the physical coat's base reads the map's prefiltered layers: the
/// base's lobe as it leaves the coat. Weidlich and Wilkie 2007 evaluate the lower layer at
/// the directions refracted through the coat; seen from outside, its lobe is then wider.
/// Near the normal, a deviation `d` inside leaves as `eta d` (Snell's law), so the base's
/// `alpha` becomes `eta alpha_base`. Each pass through the rough coat turns a ray by about
/// `(eta - 1)` times its facet's tilt. The two passes widen the lobe with the variance
/// `2 (eta - 1)^2 alpha_coat^2`: `alpha^2 = (eta alpha_base)^2 + 2 (eta - 1)^2 alpha_coat^2`,
/// as a roughness (`sqrt(alpha)`), at most 1. Only the map's direction and blur take it;
/// the base's albedos stay at its own roughness, so the white furnace is untouched.
pub(crate) fn clearcoat_base_roughness(roughness_base: f64, roughness_coat: f64, eta: f64) -> f64 {
    let alpha_base = super::alpha_from_roughness(roughness_base);
    let alpha_coat = super::alpha_from_roughness(roughness_coat);
    let alpha2 = (eta * alpha_base).powi(2) + 2.0 * ((eta - 1.0) * alpha_coat).powi(2);
    alpha2.sqrt().sqrt().min(1.0)
}

/// The cosine at which a glossy base's Fresnel is read under the physical coat of index
/// `eta` and weight `weight`: the outside cosine `c` refracted into the coat (Snell's law,
/// `sin_t = sin / eta`), as Weidlich and Wilkie 2007 light the lower layer along the
/// refracted directions and the walk's base sees them, mixed with `c` by the weight (the
/// bare base's at weight 0, as [`clearcoat_base_roughness`] is). A white base (`F0 = 1`)
/// has `F = 1` at every cosine, so the white furnace is untouched.
pub(crate) fn clearcoat_base_cosine(c: f64, eta: f64, weight: f64) -> f64 {
    let sin2 = (1.0 - c * c).max(0.0) / (eta * eta).max(DIV_EPSILON);
    let refracted = (1.0 - sin2).max(0.0).sqrt();
    c + weight * (refracted - c)
}

/// The cosine-weighted average of Schlick's `(1 - mu)^5` seen by a glossy base under the
/// physical coat of index `eta` and weight `weight`: uniform light outside reaches the base
/// inside the coat's critical cone, cosine-weighted there too (`sin_t^2 = sin^2 / eta^2`
/// is uniform on `[0, 1 / eta^2]`), so the average is
/// `eta^2 int_{mu_c}^1 (1 - mu)^5 2 mu dmu = 2 eta^2 (X^6 / 6 - X^7 / 7)` with
/// `X = 1 - mu_c`, `mu_c = sqrt(1 - 1 / eta^2)` (1.6e-4 at index 1.5), mixed with the bare
/// hemisphere's `1 / 21` ([`super::f_avg_schlick`]) by the weight. Index 1 gives `1 / 21`.
pub(crate) fn clearcoat_base_schlick_avg(eta: f64, weight: f64) -> f64 {
    let eta2 = (eta * eta).max(1.0);
    let x = 1.0 - (1.0 - 1.0 / eta2).sqrt();
    let cone = 2.0 * eta2 * (x.powi(6) / 6.0 - x.powi(7) / 7.0);
    1.0 / 21.0 + weight * (cone - 1.0 / 21.0)
}

/// The nodes of a ball's escape curve: the physical model's `X` at `sqrt(mu) = k / 3`,
/// [`clearcoat_escape`] scaled so that a Lambertian lobe gives the model's own
/// `1 - F_in` (the paths' single scattering loses what the coat's term gives back), in
/// [0, 1].
pub(crate) const CLEARCOAT_ESCAPE_NODES: usize = 4;

/// `CLEARCOAT_ESCAPE_NODES` values of `X` for a base lobe of `alpha_base` under a coat
/// of `alpha_coat`, index `eta` and average albedo `e_coat_avg`.
pub fn clearcoat_escape_nodes(
    alpha_base: f64,
    alpha_coat: f64,
    eta: f64,
    e_coat_avg: f64,
) -> [f64; CLEARCOAT_ESCAPE_NODES] {
    let x_d = 1.0 - super::coating_inside_reflectance(e_coat_avg, eta);
    std::array::from_fn(|k| {
        let s = k as f64 / (CLEARCOAT_ESCAPE_NODES - 1) as f64;
        let (x, _, x_d_paths) = escape_parts(s * s, alpha_base, alpha_coat, eta);
        (x * x_d / x_d_paths.max(DIV_EPSILON)).clamp(0.0, 1.0)
    })
}

/// The nodes packed as WGSL's `pack4x8unorm` packs them: node `k` in bits `8k..8k + 8`,
/// `round(255 x)`.
pub(crate) fn clearcoat_escape_pack(nodes: [f64; CLEARCOAT_ESCAPE_NODES]) -> u32 {
    nodes.iter().enumerate().fold(0, |acc, (k, x)| {
        acc | (((x.clamp(0.0, 1.0) * 255.0).round() as u32) << (8 * k))
    })
}

/// `clearcoat_escape_at` of `brdf.wgsl`: the packed curve read at `mu`, linear in
/// `sqrt(mu)` between its nodes (WGSL's `unpack4x8unorm`: each byte over 255).
pub(crate) fn clearcoat_escape_at(packed: u32, mu: f64) -> f64 {
    let node = |k: usize| f64::from((packed >> (8 * k)) & 0xff) / 255.0;
    let x = mu.clamp(0.0, 1.0).sqrt() * (CLEARCOAT_ESCAPE_NODES - 1) as f64;
    let k = (x.floor() as usize).min(CLEARCOAT_ESCAPE_NODES - 2);
    let t = x - k as f64;
    node(k) + t * (node(k + 1) - node(k))
}

/// The share of the base's light under a coat of weight `weight` for light arriving with
/// the coat's transmission `t_coat_i`: `(1 - weight) + weight out t_coat_i`, `out` the
/// view's part (the physical form's `(1 - E_c(mu_o))` times [`clearcoat_inside_scale`] or
/// [`clearcoat_lobe_scale`]; 1 under the engines' forms, whose `t_coat_i` is `1 - F`).
pub(crate) fn clearcoat_through_physical(weight: f64, out: f64, t_coat_i: f64) -> f64 {
    (1.0 - weight) + weight * out * t_coat_i
}

/// The share of the base's light under an engine's coat of weight `weight`: `1 - weight F`,
/// `F` the coat's Fresnel at `v.h` (Filament) or at `n.v` (glTF).
pub(crate) fn clearcoat_through_engine(weight: f64, fresnel: f64) -> f64 {
    1.0 - weight * fresnel
}

/// Samples of [`clearcoat_escape`]'s quadrature (a low-discrepancy set of paths).
pub(crate) const CLEARCOAT_ESCAPE_SAMPLES: usize = 192;

/// The share `X(mu)` of a glossy base's light that leaves through the coat on its first
/// way up, for light arriving at cosine `mu` (by reciprocity: the view's): the path of the
/// walk's first bounce followed with one microfacet per interface, each drawn from the
/// distribution of visible normals (Heitz 2018):
/// - into the coat through a facet of the coat's GGX (`alpha_coat`), weighted by the
///   dielectric Fresnel transmission and refracted by Snell's law (Walter, Marschner, Li
///   and Torrance 2007, "Microfacet Models for Refraction through Rough Surfaces");
/// - reflected by a facet of the base's GGX lobe (`alpha_base`), weighted by the Smith
///   masking of the way out (the lobe's single scattering, Heitz et al. 2016);
/// - up through a facet of the coat seen from inside, transmitted with the Fresnel of the
///   relative index `1 / eta`, 0 past the critical angle (the escape cone of Weidlich and
///   Wilkie 2007's total internal reflection).
///
/// `X` is the transmitted weight over the weight that reached the base. A Lambertian base
/// would give the diffuse share `(1 - E_c_avg) / eta^2`; a mirror base under a smooth coat
/// the coat's transmission at `mu`. The points are the R_6 sequence (Roberts 2018, "The
/// Unreasonable Effectiveness of Quasirandom Sequences"), the same every call.
#[allow(dead_code)] // the closed form the tables stand for; the docs name it
pub(crate) fn clearcoat_escape(mu: f64, alpha_base: f64, alpha_coat: f64, eta: f64) -> f64 {
    escape_parts(mu, alpha_base, alpha_coat, eta).0
}

/// `(X, T, X_d)` of [`clearcoat_escape`]: its `X`, the coat's transmission `T` at `mu`
/// and a Lambertian base's escape `X_d`, all three from the same paths.
fn escape_parts(mu: f64, alpha_base: f64, alpha_coat: f64, eta: f64) -> (f64, f64, f64) {
    use glam::DVec3;
    let mu = mu.clamp(ESCAPE_MU_MIN, 1.0);
    let o = DVec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
    let disk = |u1: f64, u2: f64| {
        let r = u1.sqrt();
        let phi = std::f64::consts::TAU * u2;
        (r * phi.cos(), r * phi.sin())
    };
    // R_6: 1 / phi_6^j, phi_6 the positive root of x^7 = x + 1.
    let phi6: f64 = 1.097_740_477_074_786_5;
    let g: [f64; 6] = std::array::from_fn(|j| phi6.powi(-(j as i32 + 1)));
    let (mut arrived, mut through) = (0.0, 0.0);
    let (mut sent, mut entered, mut diffuse) = (0.0f64, 0.0, 0.0);
    let inv_eta = 1.0 / eta.max(DIV_EPSILON);
    // The way out through the coat from inside, along `up` (z > 0): the Fresnel
    // transmission of the relative index 1 / eta, 0 past the critical angle.
    let leave = |up: DVec3, p1: f64, p2: f64| {
        let seen = DVec3::new(-up.x, -up.y, up.z);
        let m3 = super::visible_normal(alpha_coat, seen, p1, p2);
        let c3 = seen.dot(m3);
        match refracted(-seen, m3, inv_eta) {
            Some(out) if c3 > 0.0 && out.z < 0.0 => 1.0 - super::fresnel_dielectric(c3, inv_eta),
            _ => 0.0,
        }
    };
    for k in 0..CLEARCOAT_ESCAPE_SAMPLES {
        let u: [f64; 6] = std::array::from_fn(|j| (0.5 + g[j] * k as f64).fract());
        // Into the coat.
        let (p1, p2) = disk(u[0], u[1]);
        let m1 = super::visible_normal(alpha_coat, o, p1, p2);
        let c1 = o.dot(m1);
        sent += 1.0;
        // A Lambertian base's way out, for X_d.
        let (q1, q2) = disk(u[2], u[3]);
        let lambert = DVec3::new(q1, q2, (1.0 - q1 * q1 - q2 * q2).max(0.0).sqrt());
        let (q1, q2) = disk(u[4], u[5]);
        diffuse += leave(lambert, q1, q2);
        let Some(down) = refracted(-o, m1, eta) else {
            continue;
        };
        if c1 <= 0.0 || down.z >= 0.0 {
            continue;
        }
        let t_in = 1.0 - super::fresnel_dielectric(c1, eta);
        entered += t_in;
        // Off the base's lobe.
        let up_in = -down;
        let (p1, p2) = disk(u[2], u[3]);
        let m2 = super::visible_normal(alpha_base, up_in, p1, p2);
        let up = 2.0 * up_in.dot(m2) * m2 - up_in;
        if up.z <= 0.0 {
            continue;
        }
        let w = t_in * super::g1_smith(up.z, alpha_base);
        arrived += w;
        // Out through the coat, in the frame turned over (the inside is its upper side).
        let (p1, p2) = disk(u[4], u[5]);
        through += w * leave(up, p1, p2);
    }
    let sent = sent.max(1.0);
    (
        through / arrived.max(DIV_EPSILON),
        entered / sent,
        diffuse / sent,
    )
}

/// The smallest cosine [`clearcoat_escape`] is evaluated at.
pub(crate) const ESCAPE_MU_MIN: f64 = 1e-3;

/// Snell's refraction of the direction `dir` (arriving: `dir.m < 0`) through the facet
/// `m` into the side of relative index `eta`; `None` past the critical angle.
fn refracted(dir: glam::DVec3, m: glam::DVec3, eta: f64) -> Option<glam::DVec3> {
    let cos_i = (-dir.dot(m)).clamp(0.0, 1.0);
    let r = 1.0 / eta.max(DIV_EPSILON);
    let sin2_t = r * r * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((r * dir + (r * cos_i - cos_t) * m).normalize())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::{alpha_from_roughness, fresnel_dielectric};

    #[test]
    fn base_roughness_widens_as_the_coat_refracts() {
        // A coat of index 1 bends nothing: the base keeps its roughness.
        for r in [0.1, 0.4, 0.8] {
            let same = clearcoat_base_roughness(r, 0.7, 1.0);
            assert!((same - r).abs() < 1e-12, "index 1, roughness {r}: {same}");
        }
        // A smooth coat widens the base's alpha by eta.
        let smooth = clearcoat_base_roughness(0.4, 0.0, 1.5);
        let alpha = alpha_from_roughness(0.4) * 1.5;
        assert!(
            (smooth - alpha.sqrt()).abs() < 1e-3,
            "smooth coat: {smooth}"
        );
        // A rougher coat widens it further; never past 1.
        let rough = clearcoat_base_roughness(0.4, 0.7, 1.5);
        assert!(
            rough > smooth + 0.01,
            "rough coat: {rough} against {smooth}"
        );
        assert_eq!(clearcoat_base_roughness(1.0, 1.0, 2.0), 1.0);
    }

    #[test]
    fn escape_meets_its_limits() {
        // A mirror under a smooth coat: the light leaves at its own angle, with the
        // coat's transmission.
        for mu in [0.3, 0.7, 1.0] {
            let x = clearcoat_escape(mu, 1e-4, 1e-4, 1.5);
            let t = 1.0 - fresnel_dielectric(mu, 1.5);
            assert!((x - t).abs() < 0.01, "mu {mu}: {x} against {t}");
        }
        // The roughest lobe under the roughest coat is nearly Lambert's.
        let (x, _, x_d) = escape_parts(0.7, 1.0, 1.0, 1.5);
        assert!((x - x_d).abs() < 0.05, "{x} against {x_d}");
        // A glossy lobe leaves more than a Lambertian one at normal view, and less near
        // grazing (its lobe straddles the critical angle).
        let a = alpha_from_roughness(0.3);
        let (x, _, x_d) = escape_parts(0.9, a, a, 1.5);
        assert!(x > x_d + 0.3, "{x} against {x_d}");
        let (x, _, x_d) = escape_parts(0.05, a, a, 1.5);
        assert!(x < x_d, "{x} against {x_d}");
    }

    #[test]
    fn lobe_scale_limits_and_packing() {
        let (e_avg, eta) = (0.09, 1.5);
        let x_d = 1.0 - crate::brdf::coating_inside_reflectance(e_avg, eta);
        for a in [0.0, 0.4, 0.9] {
            let lobe = clearcoat_lobe_scale(a, x_d, e_avg, eta);
            let inside = clearcoat_inside_scale(a, e_avg, eta);
            assert!(
                (lobe - inside).abs() < 1e-12,
                "A {a}: {lobe} against {inside}"
            );
        }
        for x in [0.0, 0.5, 1.0] {
            let white = clearcoat_lobe_scale(1.0, x, e_avg, eta);
            assert!(
                (white * (1.0 - e_avg) - 1.0).abs() < 1e-12,
                "X {x}: {white}"
            );
        }
        let nodes = [0.1, 0.5, 0.75, 0.96];
        let packed = clearcoat_escape_pack(nodes);
        for (k, x) in nodes.iter().enumerate() {
            let mu = (k as f64 / 3.0).powi(2);
            assert!((clearcoat_escape_at(packed, mu) - x).abs() <= 0.5 / 255.0 + 1e-12);
        }
        let mid = clearcoat_escape_at(packed, 0.5f64.powi(2));
        assert!((mid - 0.625).abs() < 1.0 / 255.0, "{mid}");
    }
}
