//! A ball's coating constants, formed once per ball on the CPU for both renderers (the GPU's
//! `Ball.eta`, `Ball.coat_f_add`, `Ball.coat_f_avg`, `Ball.e_spec_avg`; `cpu::coating`),
//! and `coating_spec_albedo` of `shaders/coating.wgsl`, the coating's specular albedo with
//! the ball's term, which they average.

use crate::brdf::DielectricFresnel;
use crate::environment::IblTerm;
use crate::scene::{Ball, Preset, Scene};

/// What a ball's coating shading takes that is constant over the ball, formed once per ball
/// on the CPU (the GPU's `Ball.eta`, `coat_f_add`, `coat_f_avg`, `e_spec_avg`;
/// `cpu::coating`).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub(crate) struct CoatingConstants {
    /// The coating's relative index.
    pub eta: f64,
    /// Kulla-Conty's `f_add` of the coating, from its average Fresnel (0 without the term).
    pub f_add: f64,
    /// The coating's average Fresnel `F_avg` (the preset's: exact or Schlick's).
    pub f_avg: f64,
    /// `E_spec_avg`, the cosine-weighted average of the coating's specular albedo with the
    /// ball's term ([`coating_spec_albedo`]) as the shader reads it.
    pub e_spec_avg: f64,
}

/// Gauss-Legendre nodes of the average of `E_spec` under Turquin's and Fdez-Aguera's terms
/// (Kulla-Conty's is in closed form from the rows and `E_avg`).
const SPEC_AVG_NODES: usize = 48;

impl CoatingConstants {
    /// Ball `b`'s constants as both renderers form them, once per ball: from its row of
    /// `rows`, with E and E_avg read from `e` as the shader reads them, and its term;
    /// `None` for an all-metal ball.
    pub(crate) fn of_ball(
        scene: &Scene,
        b: &Ball,
        e: &crate::lut::TableSet,
        rows: &crate::lut::CoatingRows,
    ) -> Option<Self> {
        let key = scene.coating_key(b)?;
        let row = rows.row(&key).expect("every coating's row is baked");
        let ms = if b.model.has_term() { 1.0 } else { 0.0 };
        let term = b.model.term().unwrap_or(IblTerm::KullaConty);
        let r = b.shading_roughness() as f32;
        let e_avg = 1.0 - f64::from(e.lut_loss_avg(r));
        let loss = |mu: f64| f64::from(e.lut_loss(mu as f32, r));
        Some(Self::new(
            b.material.ior,
            row,
            scene.preset,
            (ms, term),
            e_avg,
            loss,
        ))
    }

    /// The constants of a coating of index `eta` read from `row`, for a ball whose term
    /// weight is `ms` and term `term`, with the preset `preset`; `e_avg` is `E_avg` at the
    /// ball's roughness as the shader reads it and `loss(mu)` its `1 - E(mu)` read.
    pub(crate) fn new(
        eta: f64,
        row: &[f32; crate::lut::COATING_ROW_LEN],
        preset: Preset,
        (ms, term): (f64, IblTerm),
        e_avg: f64,
        loss: impl Fn(f64) -> f64,
    ) -> Self {
        use crate::brdf::{f0_from_ior, f_add_accurate, f_add_games202, f_avg_dielectric};
        let f0 = f0_from_ior(eta);
        let f_avg = match preset.dielectric_fresnel() {
            DielectricFresnel::Exact => f_avg_dielectric(eta),
            DielectricFresnel::Schlick => crate::brdf::f_avg_schlick(f0),
        };
        let f_add = if ms > 0.0 {
            match preset.f_avg_form() {
                crate::brdf::FAvgForm::Accurate => f_add_accurate(f_avg, e_avg),
                crate::brdf::FAvgForm::Games202 => f_add_games202(f_avg, e_avg),
            }
        } else {
            0.0
        };
        let e_f_avg = crate::lut::coating_albedo_avg(row);
        let e_spec_avg = match term {
            _ if ms == 0.0 => e_f_avg,
            IblTerm::KullaConty => e_f_avg + ms * f_add * (1.0 - e_avg),
            IblTerm::Turquin | IblTerm::FdezAguera => {
                let (x, w) = crate::lut::gauss_legendre_unit(SPEC_AVG_NODES);
                x.iter()
                    .zip(&w)
                    .map(|(&mu, wk)| {
                        let e_f = f64::from(crate::lut::coating_albedo(row, mu as f32));
                        2.0 * wk * mu * coating_spec_albedo(e_f, loss(mu), f0, f_add, ms, term)
                    })
                    .sum()
            }
        };
        CoatingConstants {
            eta,
            f_add,
            f_avg,
            e_spec_avg,
        }
    }
}

/// `coating_spec_albedo` of `shaders/coating.wgsl`: the coating's specular albedo
/// `E_spec(mu)` with the ball's term (weight `ms`), from its single scattering `e_f` and
/// `loss = 1 - E(mu)`: Kulla-Conty's `e_f + f_add loss`, Turquin's `e_f (1 + F0 (1 / E -
/// 1))`, Fdez-Aguera's `e_f + FmsEms`.
pub(crate) fn coating_spec_albedo(
    e_f: f64,
    loss: f64,
    f0: f64,
    f_add: f64,
    ms: f64,
    term: IblTerm,
) -> f64 {
    use crate::brdf::{term_fdez_aguera, term_turquin};
    let added = match term {
        IblTerm::KullaConty => f_add * loss,
        IblTerm::Turquin => term_turquin(e_f, f0, 1.0 - loss),
        IblTerm::FdezAguera => term_fdez_aguera(e_f, f0, loss),
    };
    e_f + ms * added
}
