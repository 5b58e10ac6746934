//! The substrate a dielectric's base reading implies (docs/interop.md, "Two readings of
//! base colour"): under the apparent reading, the substrate albedo whose light, seen
//! through the coating, has the average albedo `base_color`, solved on the CPU once per
//! ball in closed form (`brdf::substrate_albedo`: `rho = a / (T + a F_in)`, the physical
//! layering's average albedo `rho T / (1 - rho F_in)` inverted), before the balls reach
//! either renderer; no shader changes. The coating's average albedo `E_spec_avg` in it is
//! the Kulla-Conty one (single scattering plus the term), whatever the ball's model: the
//! substrate is the material's, so a ball without the term, and the truth's walk, take the
//! same substrate as the ball with it.

use glam::DVec3;

use super::coat::CoatingConstants;
use super::Prepared;
use crate::environment::IblTerm;
use crate::lut::{TableSet, COATING_ROW_LEN};
use crate::scene::{Ball, BaseReading, Layering, Model, Scene, MAX_BALLS};

/// The substrate albedo ball `b`'s dielectric has under the scene's reading: its
/// `diffuse` under [`BaseReading::Substrate`] (or for an all-metal ball), else the albedo
/// solved from it with the coating's Kulla-Conty `E_spec_avg` read from `e` and `row`
/// (the ball's coating row) as the shader reads them.
pub(crate) fn substrate_albedo(
    scene: &Scene,
    b: &Ball,
    e: &TableSet,
    row: Option<&[f32; COATING_ROW_LEN]>,
) -> DVec3 {
    substrate_albedo_with(scene, b, e, row, None)
}

/// [`substrate_albedo`], with the ball's own coating constants where the caller has
/// formed them (`CoatingConstants::of_ball`): a Kulla-Conty ball's are the ones the
/// reading takes, so its `E_spec_avg` is not formed twice (an `F_avg` integral per ball
/// per frame).
pub(crate) fn substrate_albedo_with(
    scene: &Scene,
    b: &Ball,
    e: &TableSet,
    row: Option<&[f32; COATING_ROW_LEN]>,
    own: Option<&CoatingConstants>,
) -> DVec3 {
    let (BaseReading::Apparent, Some(row)) = (scene.base_reading, row) else {
        return b.material.diffuse;
    };
    if !b.material.has_dielectric() {
        return b.material.diffuse;
    }
    let eta = b.material.ior;
    let solve = |e_spec_avg: f64| {
        let d = b.material.diffuse;
        let s = |a: f64| crate::brdf::substrate_albedo(a, e_spec_avg, eta);
        DVec3::new(s(d.x), s(d.y), s(d.z))
    };
    if let (Model::KullaConty, Some(c)) = (b.model, own) {
        return solve(c.e_spec_avg);
    }
    let r = b.shading_roughness() as f32;
    let e_avg = 1.0 - f64::from(e.lut_loss_avg(r));
    let loss = |mu: f64| f64::from(e.lut_loss(mu as f32, r));
    let c = CoatingConstants::new(
        eta,
        row,
        scene.preset,
        (1.0, IblTerm::KullaConty),
        e_avg,
        loss,
    );
    solve(c.e_spec_avg)
}

/// The base albedo the renderers give ball `b`'s coating: the substrate
/// ([`substrate_albedo`]) where the scene's layering is the physical one or the ball is the
/// truth (the walk goes through a substrate), else `diffuse` as it is (the engines' forms
/// weight the colour a viewer sees); `own`: the ball's coating constants where the caller
/// has them ([`substrate_albedo_with`]).
pub(crate) fn base_albedo(
    scene: &Scene,
    b: &Ball,
    e: &TableSet,
    row: Option<&[f32; COATING_ROW_LEN]>,
    own: Option<&CoatingConstants>,
) -> DVec3 {
    if scene.layering == Layering::Physical || b.model == Model::Truth {
        substrate_albedo_with(scene, b, e, row, own)
    } else {
        b.material.diffuse
    }
}

/// `scene` with every dielectric's base replaced by the substrate albedo its reading
/// implies ([`substrate_albedo`], from the tables and coating rows `prepared` for it) and
/// the reading set to [`BaseReading::Substrate`]: what the random walks take (`cpu::truth`).
pub(crate) fn with_substrates(scene: &Scene, prepared: &Prepared) -> Scene {
    if scene.base_reading == BaseReading::Substrate {
        return scene.clone();
    }
    let (e, rows) = (prepared.tables(), prepared.coating_rows());
    let mut out = scene.clone();
    for b in out.balls.iter_mut().take(MAX_BALLS) {
        let row = scene.coating_key(b).and_then(|k| rows.row(&k));
        b.material.diffuse = substrate_albedo(scene, b, e, row);
    }
    out.base_reading = BaseReading::Substrate;
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Material;

    fn plastic(reading: BaseReading, base: f64) -> (Scene, TableSet) {
        let mut scene = Scene::reference();
        scene.balls.truncate(1);
        scene.balls[0].material = Material::dielectric(DVec3::splat(base), 1.5);
        scene.balls[0].roughness = 0.5;
        scene.base_reading = reading;
        let e = TableSet::Full(std::sync::Arc::new(crate::lut::bake(
            &crate::lut::BakeConfig::default(),
        )));
        (scene, e)
    }

    #[test]
    fn the_apparent_reading_brightens_the_substrate_and_keeps_white() {
        for (base, brighter) in [(0.2, true), (0.8, true), (1.0, false), (0.0, false)] {
            let (scene, e) = plastic(BaseReading::Apparent, base);
            let prepared = Prepared::new(&scene, &e);
            let rows = prepared.coating_rows();
            let b = &scene.balls[0];
            let row = rows.row(&scene.coating_key(b).unwrap());
            let rho = substrate_albedo(&scene, b, &e, row).x;
            if brighter {
                assert!(rho > base && rho < 1.0, "{base} -> {rho}");
            } else {
                assert_eq!(rho, base);
            }
            let (substrate, _) = plastic(BaseReading::Substrate, base);
            assert_eq!(substrate_albedo(&substrate, b, &e, row).x, base);
            assert_eq!(
                with_substrates(&scene, &prepared).balls[0]
                    .material
                    .diffuse
                    .x,
                rho
            );
            // A Kulla-Conty ball's own constants are the reading's: the same substrate.
            assert_eq!(b.model, Model::KullaConty);
            let own = CoatingConstants::of_ball(&scene, b, &e, rows).unwrap();
            assert_eq!(substrate_albedo_with(&scene, b, &e, row, Some(&own)).x, rho);
        }
    }
}
