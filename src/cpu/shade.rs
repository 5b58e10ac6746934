//! Per-pixel maths of the CPU reference renderer, term for term `shaders/lighting.wgsl`
//! (the coating's part is `coating.rs`, `shaders/coating.wgsl`'s twin) and
//! `intersect_sphere` of `shaders/screen.wgsl`, in f64.

use glam::DVec3;

use crate::brdf::{alpha_from_roughness, DIV_EPSILON};
use crate::brdf::{
    f_add_preset, f_avg_schlick, f_micro, f_ms, f_ms_norm, f_schlick, term_fdez_aguera,
    term_turquin, FAvgForm, Geometry, GAMES202_EDGE_TINT,
};
use crate::environment::{lobe, Environment, IblMethod, IblTerm, MipChain, Prefiltered};
use crate::lut::{CoatingRows, SplitSum, TableSet, Tables};
use crate::scene::{Ball, Scene};

/// `1 - E(mu, roughness)` as the shader reads `e` (f32, [`TableSet::lut_loss`]), in f64.
pub(crate) fn loss(e: &TableSet, mu: f64, roughness: f64) -> f64 {
    e.lut_loss(mu as f32, roughness as f32) as f64
}

/// `1 - E_avg(roughness)` as the shader reads `e` ([`TableSet::lut_loss_avg`]), in f64.
pub(crate) fn loss_avg(e: &TableSet, roughness: f64) -> f64 {
    e.lut_loss_avg(roughness as f32) as f64
}

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

/// `f` applied to each channel of `v`.
pub(crate) fn per_channel(v: DVec3, f: impl Fn(f64) -> f64) -> DVec3 {
    DVec3::new(f(v.x), f(v.y), f(v.z))
}

/// `f_add_preset` per channel of `f0` (the games202 form's edge tint per channel).
pub(crate) fn f_add_rgb(form: FAvgForm, f0: DVec3, e_avg: f64) -> DVec3 {
    DVec3::new(
        f_add_preset(form, f0.x, GAMES202_EDGE_TINT[0], e_avg),
        f_add_preset(form, f0.y, GAMES202_EDGE_TINT[1], e_avg),
        f_add_preset(form, f0.z, GAMES202_EDGE_TINT[2], e_avg),
    )
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
    let rows = CoatingRows::bake(scene.coating_key(b), &mut Default::default());
    let coat = super::coating::Coat::of_ball(scene, b, e, &rows);
    let forms = Forms {
        form,
        geometry,
        map: None,
        lobe: LobeSamples::of(scene, (0, 0), 0),
    };
    shade_point(scene, (b, coat.as_ref()), n, v, e, &forms)
}

/// The scene-wide choices a point's shading takes: the preset's forms, G, and the map
/// prepared for shading where the scene has one (its split sum's table gives `FssEss`).
pub(super) struct Forms<'a> {
    pub form: FAvgForm,
    pub geometry: Geometry,
    pub map: Option<&'a CpuEnvironment>,
    /// The pixel's lobe samples where the scene's `ibl_method` is the lobe's, else `None`.
    pub lobe: Option<LobeSamples>,
}

/// Which of a pixel's lobe samples a draw takes (`shade_environment_lobe`): the pixel's
/// sequence rotation, the index of the first sample and the count (the GPU's `env.lobe.x`
/// and `IBL_SAMPLES`).
#[derive(Clone, Copy, Debug)]
pub(super) struct LobeSamples {
    pub scramble: [u32; 2],
    pub first: u32,
    pub count: u32,
}

impl LobeSamples {
    /// The samples of pixel `(px, py)` at frame `frame` under `scene`'s method (`None`
    /// under the split sum).
    pub fn of(scene: &Scene, (px, py): (u32, u32), frame: u32) -> Option<Self> {
        (scene.ibl_method == IblMethod::Lobe).then(|| {
            let count = scene
                .ibl_samples
                .clamp(1, crate::environment::MAX_IBL_SAMPLES);
            LobeSamples {
                scramble: lobe::pixel_scramble(px, py),
                // As the GPU's uniform holds it: an f32.
                first: (u64::from(frame) * u64::from(count)) as f32 as u32,
                count,
            }
        })
    }
}

/// `shade` of `lighting.wgsl`: radiance leaving ball `b` at unit normal `n` towards `v`,
/// lit by the scene's lights, its uniform environment and its map (`forms.map`): the
/// metal's and the coating's parts, each with its own term, mixed by `metallic` (an
/// all-metal or all-dielectric ball shades one). `coat` is the ball's coating, formed once
/// per ball (`None` for an all-metal ball).
pub(super) fn shade_point(
    scene: &Scene,
    (b, coat): (&Ball, Option<&super::coating::Coat>),
    n: DVec3,
    v: DVec3,
    e: &TableSet,
    forms: &Forms<'_>,
) -> DVec3 {
    let metallic = b.material.metallic as f32 as f64;
    let metal = || {
        let (lo, terms) = shade_with_terms(scene, b, n, v, e, forms);
        match forms.map {
            Some(map) => match forms.lobe {
                Some(lobe) => {
                    let lobe = (lobe, forms.geometry);
                    lo + shade_environment_lobe_map(scene, b, (n, v), &terms, map, lobe)
                }
                None => lo + shade_environment_map(scene, b, n, v, &terms, map),
            },
            None => lo,
        }
    };
    let Some(coat) = coat.filter(|_| metallic < 1.0) else {
        return metal();
    };
    let coating = super::coating::shade_coating(scene, (b, coat), n, v, e, forms);
    if metallic <= 0.0 {
        return coating;
    }
    metallic * metal() + (1.0 - metallic) * coating
}

/// What `shade` forms once per pixel and the environment map's part takes from it, as
/// `lighting.wgsl` hands them to `shade_environment_map`.
#[derive(Clone, Copy, Debug)]
pub struct PointTerms {
    /// `max(n.v, 0)`.
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
) -> (DVec3, PointTerms) {
    let Forms { form, geometry, .. } = *forms;
    let split = forms.map.map(|m| &m.split);
    let roughness = b.roughness;
    let f0 = b.material.f0;
    let ms = if b.model.has_term() { 1.0 } else { 0.0 };
    let term = b.model.term().unwrap_or(IblTerm::KullaConty);
    let mu_o = n.dot(v).max(0.0);
    let loss_o = loss(e, mu_o, roughness);
    let e_o = 1.0 - loss_o;
    let loss_avg = loss_avg(e, roughness);
    let e_avg = 1.0 - loss_avg;
    let norm = f_ms_norm(loss_avg);
    let f_avg_ss = per_channel(f0, f_avg_schlick);
    let f_add = f_add_rgb(form, f0, e_avg);
    let fss_ess = match split {
        Some(split) => {
            let bias = split.bias_at(mu_o as f32, roughness as f32) as f64;
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
    let mut lo = scene.environment * (single + ms * added);
    for light in &scene.lights {
        let l = light.direction;
        let mu_i = n.dot(l);
        if mu_i <= 0.0 || mu_o <= 0.0 {
            continue;
        }
        let h = (v + l).normalize();
        let v_dot_h = v.dot(h);
        let n_dot_h = n.dot(h);
        let spec = per_channel(f0, |f| {
            f_micro(
                f_schlick(f, v_dot_h),
                mu_o,
                mu_i,
                n_dot_h,
                roughness,
                geometry,
            )
        });
        let lobe = match term {
            IblTerm::KullaConty => f_add * f_ms(loss_o, loss(e, mu_i, roughness), norm),
            IblTerm::Turquin => turquin_rgb(spec, f0, e_o),
            IblTerm::FdezAguera => fms_ems / std::f64::consts::PI,
        };
        let f_r = spec + ms * lobe;
        lo += f_r * light.radiance * mu_i;
    }
    let terms = PointTerms {
        mu_o,
        loss_o,
        ms,
        term,
        fss_ess,
        fms_ems,
        f_add,
    };
    (lo, terms)
}

/// An environment map prepared for the CPU renderer: the same mip chain, prefiltered
/// layers and split-sum table the GPU binds (`gpu::environment`), computed on the CPU.
pub struct CpuEnvironment {
    /// The map's mip chain (f16 values, as uploaded).
    pub chain: MipChain,
    /// The prefiltered layers.
    pub prefiltered: Prefiltered,
    /// The split sum's bias table.
    pub split: SplitSum,
}

impl CpuEnvironment {
    /// Prepares `environment` for shading with E from `tables` (its geometry).
    pub fn new(environment: &Environment, tables: &Tables) -> Self {
        let chain = MipChain::new(&environment.map);
        let kernels = crate::environment::prefilter::kernels(tables);
        let prefiltered = Prefiltered::new(&chain, &kernels, tables.config.geometry);
        CpuEnvironment {
            chain,
            prefiltered,
            split: SplitSum::shipped(tables.config.geometry),
        }
    }

    /// The intensity the GPU's uniform holds: the environment's times the chain's f16
    /// scale, which its levels and the prefiltered layers are divided by.
    pub fn intensity(&self, environment: &Environment) -> f64 {
        environment.intensity * f64::from(self.chain.scale)
    }

    /// `background_radiance`'s map part in `balls.wgsl`: the map along world direction `d`
    /// (level 0, bilinear), times the intensity.
    pub fn background(&self, environment: &Environment, d: DVec3) -> DVec3 {
        let uv = crate::environment::direction_to_uv(environment.to_map(d));
        self.intensity(environment) * self.chain.levels[0].bilinear(uv)
    }
}

/// `shade_environment_map` of `lighting.wgsl`: radiance leaving ball `b`'s metal at normal
/// `n` towards `v` lit by the scene's environment map (zero without one), from the terms
/// [`shade`] formed at the point.
pub fn shade_environment_map(
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
    let roughness = b.roughness;
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
    let dominant = crate::environment::prefilter::specular_direction(n, r, roughness);
    let prefiltered = intensity
        * ibl
            .prefiltered
            .specular(environment.to_map(dominant), roughness);
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

/// `shade_environment_map` of `lighting.wgsl` with `IBL = 2`: the single scattering by
/// the lobe's samples ([`shade_environment_lobe`]), the term as under the split sum.
pub(super) fn shade_environment_lobe_map(
    scene: &Scene,
    b: &Ball,
    (n, v): (DVec3, DVec3),
    terms: &PointTerms,
    ibl: &CpuEnvironment,
    lobe: (LobeSamples, Geometry),
) -> DVec3 {
    let Some(environment) = &scene.environment_map else {
        return DVec3::ZERO;
    };
    let PointTerms {
        loss_o,
        ms,
        term,
        fms_ems,
        f_add,
        ..
    } = *terms;
    let intensity = ibl.intensity(environment);
    let n_map = environment.to_map(n);
    let single = shade_environment_lobe(environment, ibl, b, (n, v), terms.fss_ess, lobe);
    if ms <= 0.0 {
        return single;
    }
    single
        + ms * match term {
            IblTerm::Turquin => turquin_rgb(single, b.material.f0, 1.0 - loss_o),
            IblTerm::FdezAguera => fms_ems * intensity * ibl.prefiltered.irradiance(n_map),
            IblTerm::KullaConty => {
                f_add * loss_o * intensity * ibl.prefiltered.multiple(n_map, b.roughness)
            }
        }
}

/// `shade_environment_lobe` of `lighting.wgsl`: the metal's single scattering at normal `n`
/// towards `v` lit by the map, the lobe's mean radiance ([`lobe_mean_radiance`], Schlick's
/// F of the ball's F0) times the split sum's `fss_ess` (`F0 A + B`).
pub(super) fn shade_environment_lobe(
    environment: &Environment,
    ibl: &CpuEnvironment,
    b: &Ball,
    (n, v): (DVec3, DVec3),
    fss_ess: DVec3,
    lobe: (LobeSamples, Geometry),
) -> DVec3 {
    let f0 = b.material.f0;
    let fresnel = |v_dot_h: f64| per_channel(f0, |f| f_schlick(f, v_dot_h));
    lobe_mean_radiance(environment, ibl, (n, v), b.roughness, &fresnel, lobe) * fss_ess
}

/// `lobe_mean_radiance` of `lighting.wgsl`: the self-normalised mean radiance `sum w L /
/// sum w` of the lobe of `roughness` at normal `n` towards `v` over `lobe.count` samples of
/// its GGX visible normals, each weighted by `w = f_micro mu_i / pdf` with the scene's G and
/// `fresnel(v.h)` per channel, read at its footprint's mip level; 0 where no sample lies
/// above the horizon.
pub(super) fn lobe_mean_radiance(
    environment: &Environment,
    ibl: &CpuEnvironment,
    (n, v): (DVec3, DVec3),
    roughness: f64,
    fresnel: &dyn Fn(f64) -> DVec3,
    (lobe, geometry): (LobeSamples, Geometry),
) -> DVec3 {
    let mu_o = n.dot(v).max(0.0);
    let alpha = alpha_from_roughness(roughness);
    let frame = crate::sampling::duff_frame(n);
    let v_local = frame.to_local(v);
    let level0 = &ibl.chain.levels[0];
    let size = (f64::from(level0.width), f64::from(level0.height));
    let max_level = (ibl.chain.levels.len() - 1) as f64;
    let count = f64::from(lobe.first) + f64::from(lobe.count);
    let (mut sum, mut weights) = (DVec3::ZERO, DVec3::ZERO);
    for j in 0..lobe.count {
        let (u1, u2) = lobe::lobe_frame_point(lobe.first, j, lobe.count, lobe.scramble);
        let l = frame.to_world(crate::sampling::sample_vndf(v_local, alpha, u1, u2));
        let mu_i = n.dot(l);
        if mu_i <= 0.0 || mu_o <= 0.0 {
            continue;
        }
        let h = (v + l).normalize();
        let n_dot_h = n.dot(h);
        let pdf = crate::sampling::vndf_density(mu_o, n_dot_h, alpha);
        if pdf <= DIV_EPSILON {
            continue;
        }
        let w = per_channel(fresnel(v.dot(h)), |f| {
            f_micro(f, mu_o, mu_i, n_dot_h, roughness, geometry) * (mu_i / pdf)
        });
        let l_map = environment.to_map(l);
        let lod = lobe::lobe_lod(pdf, count, l_map, size, max_level);
        sum += w * ibl.chain.sample(l_map, lod);
        weights += w;
    }
    let mean = DVec3::from_array(std::array::from_fn(|c| {
        if weights[c] <= DIV_EPSILON {
            0.0
        } else {
            sum[c] / weights[c]
        }
    }));
    ibl.intensity(environment) * mean
}

/// [`term_turquin`] per channel.
fn turquin_rgb(single: DVec3, f0: DVec3, e_o: f64) -> DVec3 {
    DVec3::new(
        term_turquin(single.x, f0.x, e_o),
        term_turquin(single.y, f0.y, e_o),
        term_turquin(single.z, f0.z, e_o),
    )
}
