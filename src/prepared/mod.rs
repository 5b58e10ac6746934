//! A scene prepared for a frame: the tables E and E_avg are read from, the coating rows of
//! its dielectrics and each ball's coating formed from them ([`Prepared`]), made once and
//! taken by the GPU renderer's plan and every CPU twin (the reference renderer, the Monte
//! Carlo, the truth), so that both read the same numbers and neither bakes them again.
//! The scene itself bakes nothing.

mod clearcoat;
mod coat;
mod substrate;

use std::collections::HashMap;

use glam::DVec3;

pub(crate) use clearcoat::{base_roughness_under_coat, Clearcoat, ClearcoatConstants};
pub(crate) use coat::{coating_spec_albedo, CoatingConstants};
pub(crate) use substrate::{base_albedo, with_substrates};

use crate::lut::{CoatingKey, CoatingRows, TableSet, COATING_ROW_LEN};
use crate::scene::{Ball, Scene, MAX_BALLS};

/// Coating rows baked before, by key: what a renderer keeps between frames so that a
/// scene's rows are baked once ([`Prepared::with_cache`]).
pub(crate) type CoatingCache = HashMap<CoatingKey, [f32; COATING_ROW_LEN]>;

/// What a frame of one scene reads besides the scene: the tables, the coating rows of its
/// dielectrics (`lut::coating`) and each ball's coating (`Coat`), index for index with
/// `scene.balls` (up to [`MAX_BALLS`]). Made for one scene; a frame of another scene
/// needs its own.
#[derive(Clone, Debug)]
pub struct Prepared {
    tables: TableSet,
    coating: CoatingRows,
    coats: Vec<Option<Coat>>,
    clearcoats: Vec<Option<Clearcoat>>,
}

impl Default for Prepared {
    /// Nothing prepared: no tables, no rows, no ball.
    fn default() -> Self {
        Prepared {
            tables: TableSet::None,
            coating: CoatingRows::default(),
            coats: Vec::new(),
            clearcoats: Vec::new(),
        }
    }
}

impl Prepared {
    /// `scene` prepared with `tables`: its coating rows baked, each ball's coating formed.
    pub fn new(scene: &Scene, tables: &TableSet) -> Self {
        Self::with_cache(scene, tables, &mut CoatingCache::new())
    }

    /// [`Prepared::new`] taking the rows already in `cache` and adding those it bakes.
    pub(crate) fn with_cache(scene: &Scene, tables: &TableSet, cache: &mut CoatingCache) -> Self {
        let coating = CoatingRows::bake(
            scene
                .balls
                .iter()
                .take(MAX_BALLS)
                .flat_map(|b| scene.ball_coating_keys(b)),
            cache,
        );
        let coats = scene
            .balls
            .iter()
            .take(MAX_BALLS)
            .map(|b| Coat::of_ball(scene, b, tables, &coating))
            .collect();
        let clearcoats = scene
            .balls
            .iter()
            .take(MAX_BALLS)
            .map(|b| Clearcoat::of_ball(scene, b, tables, &coating))
            .collect();
        Prepared {
            tables: tables.clone(),
            coating,
            coats,
            clearcoats,
        }
    }

    /// The tables E and E_avg are read from.
    pub(crate) fn tables(&self) -> &TableSet {
        &self.tables
    }

    /// The coating rows of the scene's dielectrics.
    pub(crate) fn coating_rows(&self) -> &CoatingRows {
        &self.coating
    }

    /// Ball `k`'s clear coat; `None` without one.
    pub(crate) fn clearcoat(&self, k: usize) -> Option<&Clearcoat> {
        self.clearcoats.get(k).and_then(Option::as_ref)
    }

    /// Ball `k`'s coating; `None` for an all-metal ball.
    pub(crate) fn coat(&self, k: usize) -> Option<&Coat> {
        self.coats.get(k).and_then(Option::as_ref)
    }
}

/// A ball's coating as both renderers read it, formed once per ball: its row and its
/// constants, in f32 as the GPU holds them, and the base's albedo as the shading takes it
/// ([`base_albedo`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Coat {
    /// The ball's coating row.
    pub row: [f32; COATING_ROW_LEN],
    /// Its constants, each rounded to f32.
    pub constants: CoatingConstants,
    /// The base's albedo.
    pub albedo: DVec3,
}

impl Coat {
    /// Ball `b`'s coat, from its row of `rows` and E read from `e`; `None` for an all-metal
    /// ball. A ball of no scene (a single point's shading) takes rows baked for it alone.
    pub(crate) fn of_ball(
        scene: &Scene,
        b: &Ball,
        e: &TableSet,
        rows: &CoatingRows,
    ) -> Option<Self> {
        let c = CoatingConstants::of_ball(scene, b, e, rows)?;
        let key = scene.coating_key(b)?;
        let f32_of = |x: f64| x as f32 as f64;
        Some(Coat {
            row: *rows.row(&key)?,
            albedo: base_albedo(scene, b, e, rows.row(&key), Some(&c)),
            constants: CoatingConstants {
                eta: f32_of(c.eta),
                f_add: f32_of(c.f_add),
                f_avg: f32_of(c.f_avg),
                e_spec_avg: f32_of(c.e_spec_avg),
            },
        })
    }
}
