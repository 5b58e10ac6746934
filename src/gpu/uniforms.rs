//! The shader data's Rust side: `Globals`, `Ball`, `Light` of `shaders/types.wgsl`, member
//! for member (every vector of three followed by a scalar, every member 4-byte aligned
//! within 16-byte rows, so the WGSL layout is the `repr(C)` one; src/gpu/tests/boundary.rs
//! compares naga's layout of each with these).

use bytemuck::{Pod, Zeroable};

use crate::brdf::{f_add_preset, f_ms_norm, GAMES202_EDGE_TINT};
use crate::environment::IblTerm;
use crate::lut::{LutParams, TableSet};
use crate::prepared::{ClearcoatConstants, CoatingConstants, Prepared};
use crate::scene::{CoatForm, Layering, Model, Scene, MAX_BALLS, MAX_LIGHTS};

/// The per-frame uniforms: `Globals` of `types.wgsl` (`globals`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Globals {
    /// xyz: the eye, always 0: the balls are uploaded relative to it (`balls`); w: 1.
    pub cam_origin: [f32; 4],
    /// xyz: unit view direction; w: 0.
    pub cam_forward: [f32; 4],
    /// xyz: right scaled by `tan(vfov / 2) * aspect` (`crate::scene::CameraBasis::right`);
    /// w: 0.
    pub cam_right: [f32; 4],
    /// xyz: up scaled by `tan(vfov / 2)`; w: 0.
    pub cam_up: [f32; 4],
    /// rgb: linear environment radiance (also the background); w: exposure.
    pub environment: [f32; 4],
    /// Width and height of the image in pixels, the roughness from which a ball takes the
    /// map's sun as a light ([`crate::scene::SunLight::roughness_min`]; 0 without one), 0.
    pub size: [f32; 4],
    /// Ball count and light count (at most `MAX_BALLS` and `MAX_LIGHTS`), 0, 0.
    pub counts: [u32; 4],
    /// How the bound tables are read (`TableSet::lut_params`).
    pub lut: LutParams,
}

super::ball::gpu_ball! {
    /// One ball of the balls storage buffer and of each quad's instance: `Ball` of
    /// `types.wgsl` ([`balls`]). The one list of its members: `gpu::ball` generates the
    /// WGSL and the vertex layout from it.
    struct GpuBall {
        /// Centre less the camera's position (computed in f64: the GPU works relative to
        /// the camera).
        center: [f32; 3],
        /// Radius.
        radius: f32,
        /// The metal's linear F0.
        f0: [f32; 3],
        /// Roughness (raw; the shader clamps it).
        roughness: f32,
        /// The dielectric's linear base colour (0 for a metal).
        diffuse: [f32; 3],
        /// The multiple-scattering term's weight: 1 with it, 0 without.
        ms: f32,
        /// `f_add` of the scene's preset (0 without the term).
        f_add: [f32; 3],
        /// `f_ms_norm` of `1 - E_avg` at the ball's roughness as read (0 without the term).
        ms_norm: f32,
        /// The roughness half of the ball's E reads ([`TableSet::lut_row`]).
        lut_row: [f32; 3],
        /// The ball's term ([`term_code`]: `TERM_*` of `types.wgsl`; 0 without one).
        term: u32,
        /// The metal's share ([`CoatingConstants`]).
        metallic: f32,
        /// The coating's index.
        eta: f32,
        /// The coating's `f_add` (0 without the term).
        coat_f_add: f32,
        /// The coating's average Fresnel.
        coat_f_avg: f32,
        /// The coating's `E_spec_avg` ([`CoatingConstants::e_spec_avg`]).
        e_spec_avg: f32,
        /// The ball's row of the coating rows (0 for an all-metal ball).
        coating_row: u32,
        /// The layering form ([`LAYERING_CODES`]).
        layering: u32,
        /// The coating's Fresnel (`FRESNEL_*`, [`crate::gpu::shaders::fresnel_id`]).
        fresnel: u32,
        /// The anisotropic lobe's `alpha_t` ([`crate::brdf::anisotropic_alphas`]; 0 for an
        /// isotropic ball, whose `roughness` is then its own).
        anisotropy_alpha_t: f32,
        /// The anisotropic lobe's `alpha_b` (0 for an isotropic ball).
        anisotropy_alpha_b: f32,
        /// The cosine of the anisotropy's rotation.
        anisotropy_cos: f32,
        /// The sine of the anisotropy's rotation.
        anisotropy_sin: f32,
        /// The clear coat's E reads' roughness half ([`TableSet::lut_row`] of its roughness).
        clearcoat_lut_row: [f32; 3],
        /// The clear coat's weight (0: no coat; [`ClearcoatConstants`]).
        clearcoat: f32,
        /// The physical coat's base average albedo `A_avg` per channel (1 otherwise).
        clearcoat_base_avg: [f32; 3],
        /// The clear coat's roughness.
        clearcoat_roughness: f32,
        /// The clear coat's index.
        clearcoat_eta: f32,
        /// The clear coat's Kulla-Conty `f_add` (0 without the term or the physical form).
        clearcoat_f_add: f32,
        /// `f_ms_norm` of the clear coat's `1 - E_avg` (0 where its `f_add` is).
        clearcoat_ms_norm: f32,
        /// The clear coat's `E_c_avg` ([`ClearcoatConstants::e_avg`]).
        clearcoat_e_avg: f32,
        /// The clear coat's row of the coating rows (0 without a coat).
        clearcoat_row: u32,
        /// The coat form ([`COAT_FORM_CODES`]).
        clearcoat_form: u32,
        /// The E reads' row of the base's widened roughness under the physical coat,
        /// packed ([`ClearcoatConstants::base_row`]; 0 otherwise). (The coat's Fresnel form
        /// follows from the form and `fresnel`: `coating.wgsl` `clearcoat_fresnel`.)
        clearcoat_base_row: u32,
        /// The physical coat's escape curve, four unorm8 nodes
        /// ([`crate::brdf::clearcoat_escape_pack`]; 0 otherwise). It also fills the
        /// clear coat's 16-byte row.
        clearcoat_escape: u32,
        /// Linear radiance the surface emits ([`crate::scene::Material::emission`]; 0:
        /// none), added where a ray first meets the ball.
        emission: [f32; 3],
        /// The roughness at which the base reads the map's prefiltered layers under the
        /// clear coat ([`ClearcoatConstants::base_roughness`]; 0 without a coat). It also
        /// fills the emission's 16-byte row.
        clearcoat_base_roughness: f32,
    }
}

/// One light of the lights uniform array: `Light` of `types.wgsl` ([`lights`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct GpuLight {
    /// xyz: unit vector from the surface towards the light; w: 0.
    pub direction: [f32; 4],
    /// rgb: linear radiance ([`crate::scene::Light::radiance`]); w: 0.
    pub radiance: [f32; 4],
}

fn v4(v: glam::DVec3, w: f64) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, w as f32]
}

fn v3(v: glam::DVec3) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

/// Globals for rendering `scene` at `width x height` with `tables`.
pub(crate) fn globals(scene: &Scene, tables: &TableSet, width: u32, height: u32) -> Globals {
    let basis = scene.camera.basis(width, height);
    Globals {
        // The GPU works relative to the camera (issue 38, 4): the eye at the origin, each
        // ball's centre less the eye in f64 (`balls`), so f32 holds the offsets that
        // matter, not coordinates far from the world's origin.
        cam_origin: v4(glam::DVec3::ZERO, 1.0),
        cam_forward: v4(basis.forward, 0.0),
        cam_right: v4(basis.right, 0.0),
        cam_up: v4(basis.up, 0.0),
        environment: v4(scene.environment, scene.exposure),
        size: [
            width as f32,
            height as f32,
            scene.sun_light().map_or(0.0, |s| s.roughness_min),
            0.0,
        ],
        counts: [
            scene.balls.len().min(MAX_BALLS) as u32,
            scene.lights.len().min(MAX_LIGHTS) as u32,
            0,
            0,
        ],
        lut: tables.lut_params(),
    }
}

/// The balls (the used prefix of the balls storage buffer, and each quad's instance data).
/// Each ball carries what the
/// multiple-scattering term needs that is constant over the ball: `1 - E_avg` at its
/// roughness as the shader reads it (`Tables::lut_loss_avg`, the f32 arithmetic of
/// `lut_loss_avg` in `lut.wgsl`, or its own row's, `RowSet::lut_loss_avg`) and `f_add` of
/// the scene's preset from it, per channel, in f64 like the CPU renderer (`cpu::shade`),
/// with the lobe's normalisation `f_ms_norm` of it (no division per pixel);
/// and the roughness half of every E read (`Tables::lut_row`, `RowSet::lut_row`). Done once
/// per ball instead of once per pixel, this takes about half of what the term cost a frame
/// on lavapipe (docs/benchmarks.md, "Measured results").
pub(crate) fn balls(scene: &Scene, prepared: &Prepared) -> Vec<GpuBall> {
    let tint = GAMES202_EDGE_TINT;
    let (tables, coating) = (prepared.tables(), prepared.coating_rows());
    scene
        .balls
        .iter()
        .take(MAX_BALLS)
        .enumerate()
        .map(|(k, b)| {
            let loss_avg = tables.lut_loss_avg(b.shading_roughness() as f32);
            let e_avg = 1.0 - loss_avg as f64;
            // E_avg and F_avg only for the balls whose term reads them (zero otherwise: the
            // shader multiplies them by the ball's zero flag or compiles them out).
            let (f_add, ms_norm) = if b.model.has_term() {
                let f0 = b.material.f0.to_array();
                let f_add =
                    |c: usize| f_add_preset(scene.preset.f_avg_form(), f0[c], tint[c], e_avg);
                let norm = f_ms_norm(loss_avg as f64) as f32;
                ([f_add(0) as f32, f_add(1) as f32, f_add(2) as f32], norm)
            } else {
                ([0.0; 3], 0.0)
            };
            let ms = if b.model.has_term() { 1.0 } else { 0.0 };
            // The anisotropic lobe (`roughness` above is then its isotropic equivalent).
            let anisotropy = if b.material.is_anisotropic() {
                let (t, bt) = b.material.anisotropic_alphas(b.roughness);
                let (c, s) = b.material.anisotropy_turn();
                (t, bt, c, s)
            } else {
                (0.0, 0.0, 1.0, 0.0)
            };
            let coat = prepared.coat(k);
            let coating_constants = coat.map_or(CoatingConstants::default(), |c| c.constants);
            let coating_row = scene
                .coating_key(b)
                .map_or(0, |key| coating.index_of(&key) as u32);
            let clearcoat = prepared.clearcoat(k).map(|c| c.constants);
            let clearcoat_row = scene
                .clearcoat_key(b)
                .map_or(0, |key| coating.index_of(&key) as u32);
            let cc = |f: fn(&ClearcoatConstants) -> f64| clearcoat.as_ref().map_or(0.0, f) as f32;
            let cc_roughness = b.material.clearcoat.roughness as f32;
            GpuBall {
                center: v3(b.center - scene.camera.position),
                radius: b.radius as f32,
                f0: v3(b.material.f0),
                roughness: b.shading_roughness() as f32,
                // The substrate the base reading implies (prepared::base_albedo).
                diffuse: coat
                    .map_or(b.material.diffuse, |c| c.albedo)
                    .as_vec3()
                    .to_array(),
                ms: ms as f32,
                f_add,
                ms_norm,
                lut_row: tables.lut_row(b.shading_roughness() as f32),
                term: term_code(b.model),
                metallic: b.material.metallic as f32,
                eta: coating_constants.eta as f32,
                coat_f_add: coating_constants.f_add as f32,
                coat_f_avg: coating_constants.f_avg as f32,
                e_spec_avg: coating_constants.e_spec_avg as f32,
                coating_row,
                layering: layering_code(scene.layering),
                fresnel: crate::gpu::shaders::fresnel_id(scene.preset.dielectric_fresnel()),
                anisotropy_alpha_t: anisotropy.0 as f32,
                anisotropy_alpha_b: anisotropy.1 as f32,
                anisotropy_cos: anisotropy.2 as f32,
                anisotropy_sin: anisotropy.3 as f32,
                clearcoat_lut_row: tables.lut_row(cc_roughness),
                clearcoat: cc(|c| c.weight),
                clearcoat_base_avg: v3(clearcoat.map_or(glam::DVec3::ONE, |c| c.base_avg)),
                clearcoat_roughness: cc_roughness,
                clearcoat_eta: cc(|c| c.eta),
                clearcoat_f_add: cc(|c| c.f_add),
                clearcoat_ms_norm: cc(|c| c.ms_norm),
                clearcoat_e_avg: cc(|c| c.e_avg),
                clearcoat_row,
                clearcoat_form: coat_form_code(scene.coat_form),
                clearcoat_base_row: clearcoat.map_or(0, |c| c.base_row),
                clearcoat_escape: clearcoat.map_or(0, |c| c.escape),
                emission: v3(b.material.emission),
                clearcoat_base_roughness: cc(|c| c.base_roughness),
            }
        })
        .collect()
}

/// The code of each layering form in `Ball.layering`, and the WGSL constant `LAYERING_*`
/// of `types.wgsl` generated from it (src/gpu/tests/boundary.rs).
pub(crate) const LAYERING_CODES: [(u32, Layering); 5] = [
    (0, Layering::Constant),
    (1, Layering::Gltf),
    (2, Layering::ViewOnly),
    (3, Layering::Reciprocal),
    (4, Layering::Physical),
];

/// A layering form as `coating.wgsl` reads it from `Ball.layering`.
pub(crate) fn layering_code(form: Layering) -> u32 {
    LAYERING_CODES
        .iter()
        .find(|(_, f)| *f == form)
        .map_or(0, |(code, _)| *code)
}

/// The code of each coat form in `Ball.clearcoat_form`, and the WGSL constant
/// `COAT_FORM_*` of `types.wgsl` generated from it (src/gpu/tests/boundary.rs).
pub(crate) const COAT_FORM_CODES: [(u32, CoatForm); 3] = [
    (0, CoatForm::Physical),
    (1, CoatForm::Filament),
    (2, CoatForm::Gltf),
];

/// A coat form as `clearcoat.wgsl` reads it from `Ball.clearcoat_form`.
pub(crate) fn coat_form_code(form: CoatForm) -> u32 {
    COAT_FORM_CODES
        .iter()
        .find(|(_, f)| *f == form)
        .map_or(0, |(code, _)| *code)
}

/// A ball's term as `lighting.wgsl` reads it from `Ball.term` (`TERM_*` in `types.wgsl`,
/// generated from [`TERM_CODES`]; 0 without one).
pub(crate) fn term_code(model: Model) -> u32 {
    match model.term() {
        None => 0,
        Some(term) => TERM_CODES
            .iter()
            .find(|(_, t)| *t == term)
            .map_or(0, |(code, _)| *code),
    }
}

/// The code of each term in `Ball.term`, and the WGSL constant `TERM_*` of `types.wgsl`
/// generated from it (src/gpu/tests/boundary.rs).
pub(crate) const TERM_CODES: [(u32, IblTerm); 3] = [
    (1, IblTerm::KullaConty),
    (2, IblTerm::Turquin),
    (3, IblTerm::FdezAguera),
];

/// The lights array (the used prefix of the uniform array): the scene's, then the map's
/// sun's lights where the split sum takes it as lights ([`Scene::sun_light`]; the balls
/// that take it loop over `SUN_POINTS` lights more, `vs_ball`).
pub(crate) fn lights(scene: &Scene) -> Vec<GpuLight> {
    let sun = scene.sun_light().map(|s| s.lights);
    scene
        .lights
        .iter()
        .take(MAX_LIGHTS)
        .chain(sun.iter().flatten())
        .map(|l| GpuLight {
            direction: v4(l.direction, 0.0),
            radiance: v4(l.radiance, 0.0),
        })
        .collect()
}
