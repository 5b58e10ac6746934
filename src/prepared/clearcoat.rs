//! A ball's clear coat prepared once for both renderers (docs/design/coat.md): its
//! constants ([`ClearcoatConstants`]: the GPU's `Ball.clearcoat*` members) and its row with
//! them in f32 ([`Clearcoat`], what `cpu::clearcoat` reads).

use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

use glam::DVec3;

use super::{base_albedo, CoatingConstants};
use crate::brdf::{
    alpha_from_roughness, base_albedo_physical, clearcoat_escape_nodes, clearcoat_escape_pack,
    f_add_preset, f_avg_schlick, DielectricFresnel, GAMES202_EDGE_TINT,
};
use crate::environment::IblTerm;
use crate::lut::{lut_row_pack, CoatingRows, TableSet, COATING_ROW_LEN};
use crate::scene::{Ball, CoatForm, Layering, Scene};

/// What a ball's clear coat takes that is constant over the ball, formed once per ball on
/// the CPU (the GPU's `Ball.clearcoat*`; `cpu::clearcoat`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ClearcoatConstants {
    /// The coat's weight.
    pub weight: f64,
    /// The coat's roughness.
    pub roughness: f64,
    /// The coat's index.
    pub eta: f64,
    /// The coat's Kulla-Conty `f_add` (0 without the ball's term and under the engines'
    /// forms).
    pub f_add: f64,
    /// `f_ms_norm` of the coat's `1 - E_avg` (0 where `f_add` is).
    pub ms_norm: f64,
    /// `E_c_avg`, the cosine-weighted average of the coat's specular albedo (its row and
    /// its term) as the shader reads it.
    pub e_avg: f64,
    /// The base's average albedo `A_avg` per channel ([`base_average_albedo`]), which the
    /// physical form's internal reflections take ([`crate::brdf::clearcoat_inside_scale`],
    /// [`crate::brdf::clearcoat_lobe_scale`]; 1 under the others).
    pub base_avg: DVec3,
    /// The physical form's escape curve of the base's lobe, packed
    /// ([`clearcoat_escape_nodes`], [`clearcoat_escape_pack`]; 0 under the others).
    pub escape: u32,
    /// The roughness at which the base reads the map's prefiltered layers under the coat
    /// ([`crate::brdf::clearcoat_base_roughness`] under the physical form at weight 1,
    /// towards the base's own as the weight goes to 0; the base's own under the others).
    pub base_roughness: f64,
    /// The E reads' row of `base_roughness` (its `lut_row`, packed:
    /// [`crate::lut::lut_row_pack`]; 0 under the engines' forms), for the base's lobe's
    /// energy factor under the coat (`cpu::clearcoat::clearcoat_base_lobe`).
    pub base_row: u32,
    /// The form.
    pub form: CoatForm,
    /// The coat's Fresnel ([`CoatForm::fresnel`]).
    pub fresnel: DielectricFresnel,
}

impl ClearcoatConstants {
    /// Ball `b`'s coat constants, from its row of `rows` and E read from `e`; `None`
    /// without a coat.
    pub(crate) fn of_ball(
        scene: &Scene,
        b: &Ball,
        e: &TableSet,
        rows: &CoatingRows,
    ) -> Option<Self> {
        let key = scene.clearcoat_key(b)?;
        let row = rows.row(&key).expect("every clear coat's row is baked");
        let coat = b.material.clearcoat;
        let form = scene.coat_form;
        let physical = form == CoatForm::Physical;
        let ms = if physical && b.model.has_term() {
            1.0
        } else {
            0.0
        };
        let r = coat.roughness as f32;
        let loss_avg = f64::from(e.lut_loss_avg(r));
        let loss = |mu: f64| f64::from(e.lut_loss(mu as f32, r));
        let c = CoatingConstants::new(
            coat.ior,
            row,
            scene.preset,
            (ms, IblTerm::KullaConty),
            1.0 - loss_avg,
            loss,
        );
        let base_roughness = base_roughness_under_coat(scene, b);
        // The widened lobe's E row: the tables hold one for it (gpu::Plan).
        let base_row = if physical {
            lut_row_pack(e.lut_row(base_roughness as f32))
        } else {
            0
        };
        let (base_avg, escape) = if physical {
            let alphas = (
                alpha_from_roughness(b.shading_roughness()),
                alpha_from_roughness(coat.roughness),
            );
            (
                base_average_albedo(scene, b, e, rows),
                escape_curve(alphas, coat.ior, c.e_spec_avg),
            )
        } else {
            (DVec3::ONE, 0)
        };
        Some(ClearcoatConstants {
            weight: coat.weight,
            roughness: coat.roughness,
            eta: coat.ior,
            f_add: c.f_add,
            ms_norm: if ms > 0.0 {
                crate::brdf::f_ms_norm(loss_avg)
            } else {
                0.0
            },
            e_avg: c.e_spec_avg,
            base_avg,
            escape,
            base_roughness,
            base_row,
            form,
            fresnel: form.fresnel(scene.preset.dielectric_fresnel()),
        })
    }
}

/// The roughness ball `b`'s base's lobe leaves its clear coat with
/// ([`ClearcoatConstants::base_roughness`]): under the physical form
/// [`crate::brdf::clearcoat_base_roughness`], mixed with the base's own by the coat's weight
/// (OpenPBR's coat weight mixes the coated ball with the bare one, and the base's one read
/// serves both, so a coat fading out does not jump to the bare ball at weight 0); the
/// base's own under the engines' forms or without a coat.
pub(crate) fn base_roughness_under_coat(scene: &Scene, b: &Ball) -> f64 {
    let own = b.shading_roughness();
    let coat = b.material.clearcoat;
    if scene.coat_form != CoatForm::Physical || !coat.is_on() {
        return own;
    }
    let widened = crate::brdf::clearcoat_base_roughness(own, coat.roughness, coat.ior);
    own + coat.weight * (widened - own)
}

/// The packed escape curve of a base lobe of `alphas.0` under a coat of `alphas.1`, index
/// `eta` and average albedo `e_avg` ([`clearcoat_escape_nodes`]), formed once per
/// distinct key in the process (a few hundred paths each: a scene's coats share a handful).
fn escape_curve(alphas: (f64, f64), eta: f64, e_avg: f64) -> u32 {
    type Cache = Mutex<HashMap<[u64; 4], u32>>;
    static CURVES: OnceLock<Cache> = OnceLock::new();
    let key = [alphas.0, alphas.1, eta, e_avg].map(f64::to_bits);
    let curves = CURVES.get_or_init(Default::default);
    if let Some(&c) = curves.lock().unwrap_or_else(|p| p.into_inner()).get(&key) {
        return c;
    }
    let c = clearcoat_escape_pack(clearcoat_escape_nodes(alphas.0, alphas.1, eta, e_avg));
    curves
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .insert(key, c);
    c
}

/// The cosine-weighted average of ball `b`'s own directional albedo under uniform light
/// (without its coat), per channel, as the renderers' uniform-light shading gives it: the
/// metal's `F_avg E_avg + f_add (1 - E_avg)` and the dielectric's `E_spec_avg` plus its
/// base's average under the scene's layering form, mixed by `metallic`.
pub(crate) fn base_average_albedo(
    scene: &Scene,
    b: &Ball,
    e: &TableSet,
    rows: &CoatingRows,
) -> DVec3 {
    let ms = if b.model.has_term() { 1.0 } else { 0.0 };
    let m = &b.material;
    let e_avg = 1.0 - f64::from(e.lut_loss_avg(b.roughness as f32));
    let metal = if m.has_metal() {
        let f0 = m.f0.to_array();
        let tint = GAMES202_EDGE_TINT;
        let c = |k: usize| {
            let f_add = f_add_preset(scene.preset.f_avg_form(), f0[k], tint[k], e_avg);
            f_avg_schlick(f0[k]) * e_avg + ms * f_add * (1.0 - e_avg)
        };
        DVec3::new(c(0), c(1), c(2))
    } else {
        DVec3::ZERO
    };
    let dielectric = match CoatingConstants::of_ball(scene, b, e, rows) {
        Some(c) => {
            let row = scene.coating_key(b).and_then(|k| rows.row(&k));
            let albedo = base_albedo(scene, b, e, row, Some(&c));
            let base = |a: f64| match scene.layering {
                Layering::Constant | Layering::Gltf => a * (1.0 - c.f_avg),
                Layering::ViewOnly | Layering::Reciprocal => a * (1.0 - c.e_spec_avg),
                Layering::Physical => base_albedo_physical(a, c.e_spec_avg, c.e_spec_avg, c.eta),
            };
            DVec3::splat(c.e_spec_avg) + DVec3::new(base(albedo.x), base(albedo.y), base(albedo.z))
        }
        None => DVec3::ZERO,
    };
    m.metallic * metal + (1.0 - m.metallic) * dielectric
}

/// A ball's clear coat as the CPU's shading reads it, formed once per ball (as the GPU's
/// uniforms are): its row and its constants, in f32 as the GPU holds them.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Clearcoat {
    /// The coat's row of the coating rows.
    pub row: [f32; COATING_ROW_LEN],
    /// Its constants, each rounded to f32.
    pub constants: ClearcoatConstants,
}

impl Clearcoat {
    /// Ball `b`'s clear coat, from its row of `rows` and E read from `e`; `None` without
    /// one.
    pub(crate) fn of_ball(
        scene: &Scene,
        b: &Ball,
        e: &TableSet,
        rows: &CoatingRows,
    ) -> Option<Self> {
        let c = ClearcoatConstants::of_ball(scene, b, e, rows)?;
        let key = scene.clearcoat_key(b)?;
        let f32_of = |x: f64| x as f32 as f64;
        Some(Clearcoat {
            row: *rows.row(&key)?,
            constants: ClearcoatConstants {
                weight: f32_of(c.weight),
                roughness: f32_of(c.roughness),
                eta: f32_of(c.eta),
                f_add: f32_of(c.f_add),
                ms_norm: f32_of(c.ms_norm),
                e_avg: f32_of(c.e_avg),
                base_roughness: f32_of(c.base_roughness),
                base_avg: c.base_avg.as_vec3().as_dvec3(),
                ..c
            },
        })
    }
}
