//! Per-pixel maths of the CPU reference renderer, term for term `shaders/lighting.wgsl`
//! (the coating's part is `coating.rs`, `shaders/coating.wgsl`'s twin) and
//! `intersect_sphere` of `shaders/screen.wgsl`, in f64.

use glam::DVec3;

use super::clearcoat::{
    clearcoat_base_f_avg, clearcoat_base_fresnel_cosine, clearcoat_refraction, BaseLobe,
    ClearcoatPoint,
};
use super::forms::{Forms, LobeSamples};
use super::light::CpuEnvironment;
use super::light::{f_add_rgb, loss, loss_avg, per_channel};
use super::model::{
    anisotropic_frame, coated_point, model_brdf, pdf_vndf, pdf_vndf_lobe, sample_lobe, ShadingPoint,
};
use crate::brdf::{
    alpha_from_roughness, f_micro, f_micro_aniso, f_ms, f_ms_norm, f_schlick, term_fdez_aguera,
    term_turquin, FAvgForm, Geometry,
};
use crate::environment::{lobe, IblTerm};
use crate::lut::{CoatingRows, TableSet};
use crate::prepared::Coat;
use crate::sampling::{power_estimate, sample_cosine, sample_vndf};
use crate::scene::{Ball, Scene};

/// `intersect_sphere` of `screen.wgsl`: nearest positive distance along unit `d` from `o`
/// to the sphere, or -1.
pub fn intersect_sphere(o: DVec3, d: DVec3, center: DVec3, r: f64) -> f64 {
    let oc = o - center;
    let b = oc.dot(d);
    let perp = oc - b * d;
    let disc = r * r - perp.dot(perp);
    if disc < 0.0 {
        return -1.0;
    }
    let q = -b + if b > 0.0 { -disc.sqrt() } else { disc.sqrt() };
    if q.abs() < crate::brdf::DIV_EPSILON {
        return -1.0;
    }
    let c = oc.dot(oc) - r * r;
    let (t0, t1) = ((c / q).min(q), (c / q).max(q));
    if t0 > 0.0 {
        t0
    } else if t1 > 0.0 {
        t1
    } else {
        -1.0
    }
}

/// `shade` of `lighting.wgsl` without the environment map's part: radiance leaving ball `b`
/// at unit normal `n` towards `v` (see the shader for the model and the environment
/// approximation), its coating's rows baked for the call. The renderer's shading, with
/// the map's part, is `shade_point`.
pub fn shade(
    scene: &Scene,
    b: &Ball,
    n: DVec3,
    v: DVec3,
    e: &TableSet,
    form: FAvgForm,
    geometry: Geometry,
) -> DVec3 {
    let rows = CoatingRows::bake(scene.ball_coating_keys(b), &mut Default::default());
    let coat = Coat::of_ball(scene, b, e, &rows);
    let clearcoat = crate::prepared::Clearcoat::of_ball(scene, b, e, &rows);
    let forms = Forms {
        form,
        geometry,
        map: None,
        lobe: LobeSamples::of(scene, (0, 0), 0),
        coat: None,
    };
    shade_point(
        scene,
        (b, (coat.as_ref(), clearcoat.as_ref())),
        n,
        v,
        e,
        &forms,
    )
}

/// `shade` of `lighting.wgsl`: radiance leaving ball `b` at unit normal `n` towards `v`,
/// lit by the scene's lights, its uniform environment and its map (`forms.map`): the
/// metal's and the coating's parts, each with its own term, mixed by `metallic` (an
/// all-metal or all-dielectric ball shades one), plus the ball's emission (no part of the
/// BRDF; a clear coat does not dim it). `coat` is the ball's coating, formed once per ball
/// (`None` for an all-metal ball).
pub(super) fn shade_point(
    scene: &Scene,
    (b, (coat, clearcoat)): (&Ball, Coats<'_>),
    n: DVec3,
    v: DVec3,
    e: &TableSet,
    forms: &Forms<'_>,
) -> DVec3 {
    let Some(clearcoat) = clearcoat else {
        return shade_base(scene, (b, coat), n, v, e, forms) + b.material.emission;
    };
    let point = super::clearcoat::ClearcoatPoint::new(scene, b, clearcoat, (n, v), e);
    let forms = Forms {
        coat: Some(point),
        lobe: forms.lobe,
        ..*forms
    };
    // The lobe mode samples the coat's lobe with the whole model (shade_environment_mis).
    let split_sum = forms.map.filter(|_| forms.lobe.is_none());
    shade_base(scene, (b, coat), n, v, e, &forms)
        + super::clearcoat::shade_clearcoat(scene, &point, (n, v), e, (split_sum, forms.geometry))
        + b.material.emission
}

/// A ball's coating and clear coat, each formed once per ball (`None` without one).
pub(super) type Coats<'a> = (Option<&'a Coat>, Option<&'a crate::prepared::Clearcoat>);

/// `shade_base` of `lighting.wgsl`: the ball under its clear coat (all of it without one),
/// the base's light weighted by `forms.coat`.
fn shade_base(
    scene: &Scene,
    (b, coat): (&Ball, Option<&Coat>),
    n: DVec3,
    v: DVec3,
    e: &TableSet,
    forms: &Forms<'_>,
) -> DVec3 {
    let metallic = b.material.metallic as f32 as f64;
    // A clear coat weights the environment's part (the uniform's and the map's): the
    // metal's as a glossy base's light.
    let through = forms.coat.map_or(DVec3::ONE, |c| c.environment_lobe());
    // The lobe mode: the map's part is the whole model's, a clear coat's lobe and its
    // shares of the base's light included, sampled once.
    let map_part = match (forms.map, forms.lobe) {
        (Some(map), Some(lobe)) => {
            shade_environment_mis(scene, (b, coat, forms.coat), (n, v), e, map, lobe)
        }
        _ => DVec3::ZERO,
    };
    let metal = || {
        let (lo, terms, lights) = shade_with_terms(scene, b, n, v, e, forms);
        let map = match (forms.map, forms.lobe) {
            (Some(map), None) => shade_environment_map(scene, b, n, v, &terms, map),
            _ => DVec3::ZERO,
        };
        (lo + map) * through + lights
    };
    let Some(coat) = coat.filter(|_| metallic < 1.0) else {
        return metal() + map_part;
    };
    let coating = super::coating::shade_coating(scene, (b, coat), n, v, e, forms);
    if metallic <= 0.0 {
        return coating + map_part;
    }
    metallic * metal() + (1.0 - metallic) * coating + map_part
}

/// What `shade` forms once per pixel and the environment map's part takes from it, as
/// `lighting.wgsl` hands them to `shade_environment_map`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PointTerms {
    /// `max(n.v, 0)` (the WGSL twin's member; no Rust code reads it).
    #[allow(dead_code)]
    pub mu_o: f64,
    /// `1 - E(mu_o)` as read.
    pub loss_o: f64,
    /// 1 with the multiple-scattering term, else 0.
    pub ms: f64,
    /// The ball's term (Kulla-Conty when it has none: `ms` is then 0).
    pub term: IblTerm,
    /// The single-scattering albedo per channel: the split sum's `F0 A + B` where the
    /// scene has a map, else `F_avg E(mu_o)`.
    pub fss_ess: DVec3,
    /// Fdez-Aguera's energy `FmsEms` (zero for the other terms).
    pub fms_ems: DVec3,
    /// `f_add` of the preset per channel.
    pub f_add: DVec3,
    /// The roughness the map's prefiltered layers are read at.
    pub map_roughness: f64,
}

/// The metal's part of [`shade_point`] without the map's (`shade_metal` of
/// `lighting.wgsl`), and the terms it formed.
pub(super) fn shade_with_terms(
    scene: &Scene,
    b: &Ball,
    n: DVec3,
    v: DVec3,
    e: &TableSet,
    forms: &Forms<'_>,
) -> (DVec3, PointTerms, DVec3) {
    let Forms { form, geometry, .. } = *forms;
    let split = forms.map.map(|m| &m.split);
    let roughness = b.shading_roughness();
    let f0 = b.material.f0;
    let ms = if b.model.has_term() { 1.0 } else { 0.0 };
    let term = b.model.term().unwrap_or(IblTerm::KullaConty);
    let mu_o = n.dot(v).max(0.0);
    let loss_o = loss(e, mu_o, roughness);
    let e_o = 1.0 - loss_o;
    let loss_avg = loss_avg(e, roughness);
    let e_avg = 1.0 - loss_avg;
    let norm = f_ms_norm(loss_avg);
    // Under a clear coat the base's Fresnel is read inside the coat (refracted cosines).
    let refraction = clearcoat_refraction(scene, b);
    let f_avg_ss = clearcoat_base_f_avg(refraction, f0);
    let f_add = f_add_rgb(form, f0, e_avg);
    let fss_ess = match split {
        Some(split) => {
            let mu_fresnel = clearcoat_base_fresnel_cosine(refraction, mu_o);
            let bias = split.bias_at(mu_fresnel as f32, roughness as f32) as f64;
            // split_sum_scale: F0 A + B with A = E - B.
            f0 * e_o + (DVec3::ONE - f0) * bias
        }
        None => f_avg_ss * e_o,
    };
    let fms_ems = if term == IblTerm::FdezAguera {
        DVec3::new(
            term_fdez_aguera(fss_ess.x, f0.x, loss_o),
            term_fdez_aguera(fss_ess.y, f0.y, loss_o),
            term_fdez_aguera(fss_ess.z, f0.z, loss_o),
        )
    } else {
        DVec3::ZERO
    };

    let single = f_avg_ss * e_o;
    let added = match term {
        IblTerm::KullaConty => f_add * loss_o,
        IblTerm::Turquin => turquin_rgb(single, f0, e_o),
        IblTerm::FdezAguera => fms_ems,
    };
    let lo = scene.environment * (single + ms * added);
    let mut lights = DVec3::ZERO;
    // An anisotropic lobe: the lights' single scattering in the ball's tangent frame.
    let aniso = anisotropic_frame(b, n);
    // Under a clear coat the lobe leaves the coat wider (clearcoat_base_lobe).
    let lobe_of = forms
        .coat
        .map_or(BaseLobe::bare(roughness), |c| c.base_lobe());
    for light in &scene.lights {
        let l = light.direction;
        let mu_i = n.dot(l);
        if mu_i <= 0.0 || mu_o <= 0.0 {
            continue;
        }
        let h = (v + l).normalize();
        let v_dot_h = v.dot(h);
        let n_dot_h = n.dot(h);
        let fresnel_cosine = clearcoat_base_fresnel_cosine(refraction, v_dot_h);
        let spec = per_channel(f0, |f| {
            let fresnel = f_schlick(f, fresnel_cosine);
            match aniso {
                Some((frame, (alpha_t, alpha_b))) => f_micro_aniso(
                    fresnel,
                    frame.to_local(v),
                    frame.to_local(l),
                    frame.to_local(h),
                    (lobe_of.alpha_scale * alpha_t, lobe_of.alpha_scale * alpha_b),
                    geometry,
                ),
                None => f_micro(fresnel, mu_o, mu_i, n_dot_h, lobe_of.roughness, geometry),
            }
        }) * lobe_of.energy;
        let lobe = match term {
            IblTerm::KullaConty => f_add * f_ms(loss_o, loss(e, mu_i, roughness), norm),
            IblTerm::Turquin => turquin_rgb(spec, f0, e_o),
            IblTerm::FdezAguera => fms_ems / std::f64::consts::PI,
        };
        let f_r = spec + ms * lobe;
        let through = forms
            .coat
            .map_or(DVec3::ONE, |c| c.through_lobe(c.transmit(e, mu_i, v_dot_h)));
        lights += through * f_r * light.radiance * mu_i;
    }
    let terms = PointTerms {
        mu_o,
        loss_o,
        ms,
        term,
        fss_ess,
        fms_ems,
        f_add,
        map_roughness: forms
            .coat
            .map_or(b.material.map_roughness(b.roughness), |c| {
                c.base_roughness()
            }),
    };
    (lo, terms, lights)
}

/// `shade_environment_map` of `lighting.wgsl`: radiance leaving ball `b`'s metal at normal
/// `n` towards `v` lit by the scene's environment map (zero without one), from the terms
/// [`shade`] formed at the point.
pub(crate) fn shade_environment_map(
    scene: &Scene,
    b: &Ball,
    n: DVec3,
    v: DVec3,
    terms: &PointTerms,
    ibl: &CpuEnvironment,
) -> DVec3 {
    let Some(environment) = &scene.environment_map else {
        return DVec3::ZERO;
    };
    let roughness = b.shading_roughness();
    let f0 = b.material.f0;
    let PointTerms {
        loss_o,
        ms,
        term,
        fss_ess,
        fms_ems,
        f_add,
        ..
    } = *terms;
    let e_o = 1.0 - loss_o;
    let intensity = ibl.intensity(environment);
    let r = 2.0 * n.dot(v) * n - v;
    let n_map = environment.to_map(n);
    // An anisotropic lobe's read leans to n by each axis's own roughness.
    let dominant = match anisotropic_frame(b, n) {
        Some((frame, alphas)) => crate::environment::prefilter::specular_direction_aniso(
            (n, r),
            frame.tangents(),
            alphas,
            terms.map_roughness,
        ),
        None => crate::environment::prefilter::specular_direction(n, r, terms.map_roughness),
    };
    let prefiltered = intensity
        * ibl
            .prefiltered
            .specular(environment.to_map(dominant), terms.map_roughness);
    let irradiance = intensity * ibl.prefiltered.irradiance(n_map);
    let single = prefiltered * fss_ess;
    let mut lo = single;
    if ms > 0.0 {
        lo += ms
            * match term {
                IblTerm::Turquin => turquin_rgb(single, f0, e_o),
                IblTerm::FdezAguera => fms_ems * irradiance,
                IblTerm::KullaConty => {
                    f_add * loss_o * intensity * ibl.prefiltered.multiple(n_map, roughness)
                }
            };
    }
    lo
}

/// The strategies of [`shade_environment_mis`] (`MIS_*` of `lighting.wgsl`): the lobe's
/// visible normals, the cosine hemisphere, the map's luminance, a clear coat's visible normals.
const MIS_LOBE: usize = 0;
const MIS_COSINE: usize = 1;
const MIS_MAP: usize = 2;
const MIS_COAT: usize = 3;

/// `shade_environment_mis` of `lighting.wgsl`: the map's part of ball `b`'s shading at
/// normal `n` towards `v` in the lobe mode, the whole model's BRDF ([`model_brdf`], a clear
/// coat's lobe and shares included where `clearcoat` is formed) against the map by
/// `lobe.count` samples of each strategy but the cosine's (`lobe.cosine`) and the lobe's
/// ([`lobe::lobe_samples`]) (the lobe's
/// visible normals, the cosine hemisphere, the map's luminance where it has tables, a clear
/// coat's visible normals) combined by the
/// power heuristic ([`power_estimate`]), each reading
/// the f16 chain's base level. The same points as the GPU (integer arithmetic), the same f32
/// tables.
pub(super) fn shade_environment_mis(
    scene: &Scene,
    (b, coat, clearcoat): (&Ball, Option<&Coat>, Option<ClearcoatPoint>),
    (n, v): (DVec3, DVec3),
    e: &TableSet,
    ibl: &CpuEnvironment,
    lobe: LobeSamples,
) -> DVec3 {
    let Some(environment) = &scene.environment_map else {
        return DVec3::ZERO;
    };
    let mut p = ShadingPoint::with_coat(scene, (b, coat), (n, v), e).with_split_sum(&ibl.split);
    // The GPU's ball holds metallic in f32.
    p.metallic = b.material.metallic as f32 as f64;
    if p.mu_o <= 0.0 {
        return DVec3::ZERO;
    }
    // A coated point: the coat's lobe and its shares of the base's light are the model's,
    // and its visible normals a fourth strategy.
    let p = coated_point(p, clearcoat);
    let coat_alpha = clearcoat.map(|c| c.alpha());
    // The base's lobe as the model reads it (widened under a coat: coated_point).
    let alpha = alpha_from_roughness(p.lobe.roughness);
    let frame = crate::sampling::duff_frame(n);
    let v_local = frame.to_local(v);
    let map = ibl.luminance.as_ref();
    // Each density in the heuristic times its strategy's share of the samples.
    let cosine_count = lobe.cosine;
    let cosine_share = (cosine_count as f32 / lobe.count as f32) as f64;
    let lobe_count = lobe::lobe_samples(lobe.count, cosine_count, p.metallic);
    let lobe_share = (lobe_count as f32 / lobe.count as f32) as f64;
    // `mis_term` of `lighting.wgsl`: the share of direction l drawn by `strategy` (`MIS_*`),
    // given its map-frame direction and its density under the map's strategy.
    let mis_term = |l: DVec3, l_map: DVec3, map_density: f64, strategy: usize| -> DVec3 {
        let mu_i = n.dot(l);
        if mu_i <= 0.0 {
            return DVec3::ZERO;
        }
        let coat = coat_alpha.map_or(0.0, |a| pdf_vndf(&p, l, a));
        // Indexed by `MIS_*`.
        let pdf = [
            lobe_share * pdf_vndf_lobe(&p, l, alpha),
            cosine_share * mu_i / std::f64::consts::PI,
            map_density,
            coat,
        ];
        let square_sum = pdf.iter().map(|q| q * q).sum();
        let radiance = ibl.chain.sample(l_map, 0.0);
        power_estimate(
            model_brdf(&p, l, e) * radiance * mu_i,
            pdf[strategy],
            square_sum,
        )
    };
    // `mis_contribution` of `lighting.wgsl`: the map's density looked up.
    let contribution = |l: DVec3, strategy: usize| -> DVec3 {
        let l_map = environment.to_map(l);
        mis_term(
            l,
            l_map,
            map.map_or(0.0, |m| m.luminance_density(l_map)),
            strategy,
        )
    };
    let point = |j: u32, k: u32| {
        let s = lobe::strategy_scramble(lobe.scramble, k);
        lobe::lobe_frame_point(lobe.first, j, s)
    };
    let mut sum = DVec3::ZERO;
    // The lobe's samples in a loop of their own, their Sobol indices the frame's share of
    // the lobe's own (all of `lobe.count` but on a dielectric under a map whose samples
    // find its light: `lobe::lobe_samples`).
    let lobe_first = (lobe.first / lobe.count) * lobe_count;
    for j in 0..lobe_count {
        let (u1, u2) = lobe::lobe_frame_point(lobe_first, j, lobe.scramble);
        sum += contribution(sample_lobe(&p, &frame, v_local, alpha, (u1, u2)), MIS_LOBE);
    }
    for j in 0..lobe.count {
        if let Some(m) = map {
            let (t1, t2) = point(j, 2);
            let (x1, x2) = point(j, 3);
            if let Some((d, density)) = m.luminance_sample([t1, t2, x1, x2]) {
                sum += mis_term(environment.from_map(d), d, density, MIS_MAP);
            }
        }
        if let Some(a) = coat_alpha {
            let (c1, c2) = point(j, 4);
            sum += contribution(frame.to_world(sample_vndf(v_local, a, c1, c2)), MIS_COAT);
        }
    }
    let cosine_first = (lobe.first / lobe.count) * cosine_count;
    let cosine_scramble = lobe::strategy_scramble(lobe.scramble, 1);
    for j in 0..cosine_count {
        let (c1, c2) = lobe::lobe_frame_point(cosine_first, j, cosine_scramble);
        sum += contribution(frame.to_world(sample_cosine(c1, c2)), MIS_COSINE);
    }
    ibl.intensity(environment) * sum / f64::from(lobe.count)
}

/// [`term_turquin`] per channel.
fn turquin_rgb(single: DVec3, f0: DVec3, e_o: f64) -> DVec3 {
    DVec3::new(
        term_turquin(single.x, f0.x, e_o),
        term_turquin(single.y, f0.y, e_o),
        term_turquin(single.z, f0.z, e_o),
    )
}
