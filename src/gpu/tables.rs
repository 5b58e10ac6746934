//! The renderer's tables: what a plan needs, baked and bound. Rows come from a memory
//! cache keyed by every input that changes their values (`lut::RowKey`), so the viewer,
//! which re-plans on every change, bakes only the rows it has not baked before; the 2-D
//! table is kept for its config. A plan that needs nothing keeps whatever is bound (its
//! pipelines never read it) or binds 1 x 1 placeholders. The last few bind groups are kept
//! too, so that switching back and forth (a caller asking for the 2-D table between
//! planned frames) uploads nothing.

use std::collections::HashMap;
use std::sync::Arc;
use std::time::Instant;

use super::renderer::Renderer;
use super::uniforms::BoundTables;
use crate::brdf::Geometry;
use crate::gpu::{Plan, TablePlan};
use crate::lut::{self, BakeConfig, Row, RowKey, RowSet, Tables};

/// Most rows the memory cache keeps (about 0.8 KB each at 64 texels): past it, the rows
/// not bound are dropped.
pub const MAX_CACHED_ROWS: usize = 4096;

/// Bind groups kept besides the bound one (their textures stay alive with them).
const MAX_KEPT_BINDS: usize = 4;

/// What is bound: the read it gives and its bind group.
pub(super) struct Bound {
    pub what: BoundKey,
    pub read: BoundTables,
    pub bind: wgpu::BindGroup,
}

/// Identifies bound tables: their config and, for rows, each row's key.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum BoundKey {
    Placeholder,
    Rows(Vec<RowKey>),
    Full(BakeConfig),
}

/// The tables held apart from the bound ones.
#[derive(Default)]
pub(super) struct TableCache {
    pub rows: HashMap<RowKey, Arc<Row>>,
    /// The latest 2-D table (baked here or given by `set_tables`).
    pub full: Option<Arc<Tables>>,
    /// Recently bound tables, oldest first.
    pub binds: Vec<Bound>,
}

impl Renderer {
    /// Bakes (what is not cached) and binds the tables `plan` needs; sets the bake's wall
    /// time when it bakes anything.
    pub(super) fn ensure_tables(&mut self, plan: &Plan) {
        match &plan.tables {
            TablePlan::None => {
                if self.bound.is_none() && !self.reuse(&BoundKey::Placeholder) {
                    let bind = self.resources.bind_none(&self.gpu.device, &self.gpu.queue);
                    self.replace_bound(Bound {
                        what: BoundKey::Placeholder,
                        read: BoundTables::None,
                        bind,
                    });
                }
            }
            TablePlan::Full => {
                self.full_table(plan.bake);
            }
            TablePlan::Rows(roughness) => {
                let keys: Vec<RowKey> = roughness
                    .iter()
                    .map(|&r| RowKey::new(&plan.bake, r))
                    .collect();
                if !self.reuse(&BoundKey::Rows(keys.clone())) {
                    self.bind_rows(keys);
                }
            }
        }
    }

    /// Binds the rows of `keys`, baking those not in the cache.
    fn bind_rows(&mut self, keys: Vec<RowKey>) {
        let missing: Vec<RowKey> = keys
            .iter()
            .filter(|k| !self.cache.rows.contains_key(k))
            .copied()
            .collect();
        if !missing.is_empty() {
            let start = Instant::now();
            let baked = lut::bake_rows(&missing);
            self.last_bake = Some(start.elapsed());
            if self.cache.rows.len() + baked.len() > MAX_CACHED_ROWS {
                self.cache.rows.retain(|k, _| keys.contains(k));
            }
            for row in baked {
                self.cache.rows.insert(row.key, Arc::new(row));
            }
        }
        let rows = keys.iter().map(|k| self.cache.rows[k].clone()).collect();
        let set = Arc::new(RowSet::new(rows));
        let bind = self
            .resources
            .bind_rows(&self.gpu.device, &self.gpu.queue, &set);
        self.replace_bound(Bound {
            what: BoundKey::Rows(keys),
            read: BoundTables::Rows(set),
            bind,
        });
    }

    /// Makes the bind group of `what` the bound one if it is bound or kept; whether it was.
    fn reuse(&mut self, what: &BoundKey) -> bool {
        if matches!(&self.bound, Some(b) if b.what == *what) {
            return true;
        }
        match self.cache.binds.iter().position(|b| b.what == *what) {
            Some(i) => {
                let kept = self.cache.binds.remove(i);
                self.replace_bound(kept);
                true
            }
            None => false,
        }
    }

    /// Binds `next`, keeping the one it replaces among the last few.
    fn replace_bound(&mut self, next: Bound) {
        if let Some(previous) = self.bound.replace(next) {
            self.cache.binds.push(previous);
            if self.cache.binds.len() > MAX_KEPT_BINDS {
                self.cache.binds.remove(0);
            }
        }
    }

    /// The 2-D table for `config`, baked if neither held nor kept bound, and bound.
    pub(super) fn full_table(&mut self, config: BakeConfig) -> Arc<Tables> {
        if self.reuse(&BoundKey::Full(config)) {
            if let Some(Bound {
                read: BoundTables::Full(t),
                ..
            }) = &self.bound
            {
                self.cache.full = Some(t.clone());
                return t.clone();
            }
        }
        let tables = match &self.cache.full {
            Some(t) if t.config == config => t.clone(),
            _ => {
                let start = Instant::now();
                let t = Arc::new(lut::bake(&config));
                self.last_bake = Some(start.elapsed());
                self.cache.full = Some(t.clone());
                t
            }
        };
        // Not bound nor kept (checked above): bind it.
        let bind = self
            .resources
            .bind_tables(&self.gpu.device, &self.gpu.queue, &tables);
        self.replace_bound(Bound {
            what: BoundKey::Full(config),
            read: BoundTables::Full(tables.clone()),
            bind,
        });
        tables
    }

    /// The 2-D table for `geometry` with the bake config (baked if not held) and bound.
    pub fn tables_for(&mut self, geometry: Geometry) -> Arc<Tables> {
        self.bake_config.geometry = geometry;
        self.full_table(self.bake_config)
    }

    /// Uses `tables` (baked for their `config.geometry`) for every scene from now on, as
    /// the 2-D table whatever the plan would choose, and bakes with their config when the
    /// geometry changes; [`Renderer::set_bake_config`] returns to planning.
    pub fn set_tables(&mut self, tables: Arc<Tables>) {
        self.bake_config = tables.config;
        self.cache.full = Some(tables.clone());
        self.pinned = true;
        // Other tables of the same config may hold other values: bind these anew.
        let what = BoundKey::Full(tables.config);
        self.cache.binds.retain(|b| b.what != what);
        if matches!(&self.bound, Some(b) if b.what == what) {
            self.bound = None;
        }
        self.full_table(tables.config);
    }

    /// The tables bound now (what the last draw read).
    pub fn bound_tables(&self) -> BoundTables {
        self.bound
            .as_ref()
            .map_or(BoundTables::None, |b| b.read.clone())
    }

    /// Rows in the memory cache.
    pub fn cached_rows(&self) -> usize {
        self.cache.rows.len()
    }
}
