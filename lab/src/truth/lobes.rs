//! The lobe study: BRDF against outgoing angle in the plane of incidence, at a few
//! incident angles and roughness values, for the walk and the models.

use glam::DVec3;
use rayon::prelude::*;

use super::albedo::{Channel, FresnelKind};
use super::microsurface::Microsurface;
use super::models::{preset_f_add, turquin_scale, ModelTables};
use super::walk::{self, incident};
use shadeballs::brdf::{f_micro, f_ms, f_ms_norm, FAvgForm, Geometry, DIV_EPSILON};

/// Which slices and how many paths each.
#[derive(Clone, Debug, PartialEq)]
pub struct Slices {
    pub roughness: Vec<f64>,
    /// Incident polar angles, degrees.
    pub theta_i: Vec<f64>,
    /// Outgoing polar angles, degrees, signed: positive on the mirror side.
    pub theta_o: Vec<f64>,
    pub paths: usize,
}

impl Slices {
    pub fn full() -> Self {
        Slices {
            roughness: vec![0.2, 0.6, 1.0],
            theta_i: vec![0.0, 45.0, 75.0, 85.0],
            theta_o: (0..90).map(|k| -89.0 + 2.0 * k as f64).collect(),
            paths: 200_000,
        }
    }

    pub fn quick() -> Self {
        Slices {
            roughness: vec![0.6, 1.0],
            theta_i: vec![0.0, 75.0],
            theta_o: (0..30).map(|k| -87.0 + 6.0 * k as f64).collect(),
            paths: 10_000,
        }
    }
}

/// The outgoing direction at signed polar angle `deg` (positive towards +x, the mirror
/// side of [`incident`]).
pub fn outgoing(deg: f64) -> DVec3 {
    let t = deg.to_radians();
    DVec3::new(t.sin(), 0.0, t.cos())
}

/// One point of one slice for one channel: the BRDF value of each model.
#[derive(Clone, Copy, Debug, Default)]
pub struct LobePoint {
    /// The walk: exact single scattering plus the next-event estimate of the rest.
    pub truth: f64,
    /// Standard error of `truth` (of its Monte Carlo part).
    pub truth_stderr: f64,
    /// The walk's multiple scattering alone (orders >= 2).
    pub truth_ms: f64,
    pub none: f64,
    pub accurate: f64,
    /// The accurate preset's lobe `f_add f_ms` alone.
    pub accurate_ms: f64,
    pub games202: f64,
    pub games202_ms: f64,
    pub turquin: f64,
}

/// One slice: `points[j][k]` for outgoing angle `j` and study channel `k` (only channels
/// with Schlick's Fresnel or white; others are left at zero).
#[derive(Clone, Debug)]
pub struct Slice {
    pub roughness: f64,
    pub theta_i: f64,
    pub points: Vec<Vec<LobePoint>>,
}

/// Runs the walk's next-event estimator and evaluates the models on every slice.
pub fn compute(
    slices: &Slices,
    channels: &[Channel],
    tables: &ModelTables,
    accurate: Geometry,
) -> Vec<Slice> {
    let used: Vec<usize> = (0..channels.len())
        .filter(|&k| channels[k].kind != FresnelKind::Conductor)
        .collect();
    let fresnels: Vec<_> = used.iter().map(|&k| channels[k].fresnel).collect();
    let wos: Vec<DVec3> = slices.theta_o.iter().map(|&d| outgoing(d)).collect();
    let jobs: Vec<(usize, usize)> = (0..slices.roughness.len())
        .flat_map(|a| (0..slices.theta_i.len()).map(move |b| (a, b)))
        .collect();
    jobs.par_iter()
        .map(|&(a, b)| {
            let (r, ti) = (slices.roughness[a], slices.theta_i[b]);
            let wi = incident(ti.to_radians().cos());
            let s = Microsurface::new(r);
            let seed = [2, a as u64, b as u64];
            let lobe = walk::lobe(&s, wi, &wos, &fresnels, slices.paths, &seed);
            let n = fresnels.len();
            let points = wos
                .iter()
                .enumerate()
                .map(|(j, wo)| {
                    let mut row = vec![LobePoint::default(); channels.len()];
                    for (u, &k) in used.iter().enumerate() {
                        let multi = lobe.multiple[j * n + u];
                        let mut p = models_at(&channels[k], tables, accurate, r, wi, *wo);
                        let cos = wo.z.max(DIV_EPSILON);
                        p.truth_ms = multi.mean() / cos;
                        p.truth += p.truth_ms;
                        p.truth_stderr = multi.stderr() / cos;
                        row[k] = p;
                    }
                    row
                })
                .collect();
            Slice {
                roughness: r,
                theta_i: ti,
                points,
            }
        })
        .collect()
}

/// The models' BRDF values at `(wi, wo)`, and in `truth` the walk's single scattering
/// (height-correlated Cook-Torrance, exact), to which the caller adds the walk's rest.
fn models_at(
    ch: &Channel,
    tables: &ModelTables,
    accurate: Geometry,
    r: f64,
    wi: DVec3,
    wo: DVec3,
) -> LobePoint {
    let h = (wi + wo).normalize();
    let (mu_o, mu_i) = (wo.z, wi.z);
    let fresnel = ch.fresnel.eval(wo.dot(h));
    let micro = |g: Geometry| f_micro(fresnel, mu_o, mu_i, h.z, r, g);
    let kc_ms = |g: Geometry, form: FAvgForm| {
        let loss_avg = tables.loss_avg(g, r);
        let f_add = preset_f_add(form, ch.data.f0, ch.index, 1.0 - loss_avg);
        let norm = f_ms_norm(loss_avg);
        f_add * f_ms(tables.loss(g, mu_o, r), tables.loss(g, mu_i, r), norm)
    };
    let sc = Geometry::SmithCorrelated;
    let accurate_ms = kc_ms(accurate, FAvgForm::Accurate);
    let games202_ms = kc_ms(Geometry::Schlick, FAvgForm::Games202);
    let e_o = 1.0 - tables.loss(sc, mu_o, r);
    LobePoint {
        truth: micro(sc),
        none: micro(accurate),
        accurate: micro(accurate) + accurate_ms,
        accurate_ms,
        games202: micro(Geometry::Schlick) + games202_ms,
        games202_ms,
        turquin: micro(sc) * turquin_scale(ch.data.f0, e_o),
        ..Default::default()
    }
}
