//! The renderer's tables: what a plan needs, baked, uploaded and bound. Rows come from a
//! memory cache keyed by every input that changes their values (`lut::RowKey`), so the
//! viewer, which re-plans on every change, bakes only the rows it has not baked before; the
//! 2-D table is kept for its config. A plan that needs nothing keeps whatever is bound (its
//! pipelines never read it) or binds 1 x 1 placeholders. The last few bind groups are kept
//! too, so that switching back and forth (a caller asking for the 2-D table between
//! planned frames) uploads nothing.

use std::collections::HashMap;
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::bindings::Bindings;
use super::plan::{Plan, TablePlan};
use super::uniforms::BoundTables;
use super::upload::GpuTables;
use crate::lut::{self, BakeConfig, Row, RowKey, RowSet, Tables};

/// Most rows the memory cache keeps (about 0.8 KB each at 64 texels): past it, the rows
/// not bound are dropped.
pub const MAX_CACHED_ROWS: usize = 4096;

/// Bind groups kept besides the bound one (their textures stay alive with them).
const MAX_KEPT_BINDS: usize = 4;

/// What is bound: the read it gives and its bind group.
pub struct Bound {
    what: BoundKey,
    pub read: BoundTables,
    pub bind: wgpu::BindGroup,
}

/// Identifies bound tables: their config and, for rows, each row's key.
#[derive(Clone, Debug, PartialEq)]
enum BoundKey {
    Placeholder,
    Rows(Vec<RowKey>),
    Full(BakeConfig),
}

/// The tables baked, uploaded and bound, and the wall time of the latest bake.
#[derive(Default)]
pub struct TableCache {
    rows: HashMap<RowKey, Arc<Row>>,
    /// The latest 2-D table (baked here or given by `pin`).
    full: Option<Arc<Tables>>,
    /// The bound tables.
    bound: Option<Bound>,
    /// Recently bound tables, oldest first.
    kept: Vec<Bound>,
    /// Wall time of the latest bake, if any.
    last_bake: Option<Duration>,
}

/// What uploading and binding needs: the device, its queue and the renderer's group 0.
pub struct Upload<'a> {
    pub device: &'a wgpu::Device,
    pub queue: &'a wgpu::Queue,
    pub bindings: &'a Bindings,
}

impl Upload<'_> {
    fn bind(&self, what: BoundKey, read: BoundTables, tables: &GpuTables) -> Bound {
        Bound {
            what,
            read,
            bind: self.bindings.bind(self.device, tables),
        }
    }
}

impl TableCache {
    /// Bakes (what is not cached), uploads and binds the tables `plan` needs; returns them.
    /// Sets the bake's wall time when it bakes anything.
    pub fn ensure(&mut self, plan: &Plan, up: &Upload<'_>) -> &Bound {
        match &plan.tables {
            TablePlan::None => {
                if self.bound.is_none() && !self.reuse(&BoundKey::Placeholder) {
                    let tables = GpuTables::placeholder(up.device, up.queue);
                    self.replace_bound(up.bind(BoundKey::Placeholder, BoundTables::None, &tables));
                }
            }
            TablePlan::Full => {
                self.full_table(plan.bake, up);
            }
            TablePlan::Rows(roughness) => {
                let keys: Vec<RowKey> = roughness
                    .iter()
                    .map(|&r| RowKey::new(&plan.bake, r))
                    .collect();
                if !self.reuse(&BoundKey::Rows(keys.clone())) {
                    self.bind_rows(keys, up);
                }
            }
        }
        self.bound.as_ref().expect("every plan binds")
    }

    /// Binds the rows of `keys`, baking those not in the cache.
    fn bind_rows(&mut self, keys: Vec<RowKey>, up: &Upload<'_>) {
        let missing: Vec<RowKey> = keys
            .iter()
            .filter(|k| !self.rows.contains_key(k))
            .copied()
            .collect();
        if !missing.is_empty() {
            let start = Instant::now();
            let baked = lut::bake_rows(&missing);
            self.last_bake = Some(start.elapsed());
            log::debug!(
                "baked {} of {} rows in {:.2} ms",
                missing.len(),
                keys.len(),
                start.elapsed().as_secs_f64() * 1e3
            );
            if self.rows.len() + baked.len() > MAX_CACHED_ROWS {
                self.rows.retain(|k, _| keys.contains(k));
            }
            for row in baked {
                self.rows.insert(row.key, Arc::new(row));
            }
        }
        let rows = keys.iter().map(|k| self.rows[k].clone()).collect();
        let set = Arc::new(RowSet::new(rows));
        let tables = GpuTables::upload_rows(up.device, up.queue, &set);
        self.replace_bound(up.bind(BoundKey::Rows(keys), BoundTables::Rows(set), &tables));
    }

    /// Makes the bind group of `what` the bound one if it is bound or kept; whether it was.
    fn reuse(&mut self, what: &BoundKey) -> bool {
        if matches!(&self.bound, Some(b) if b.what == *what) {
            return true;
        }
        match self.kept.iter().position(|b| b.what == *what) {
            Some(i) => {
                let kept = self.kept.remove(i);
                self.replace_bound(kept);
                true
            }
            None => false,
        }
    }

    /// Binds `next`, keeping the one it replaces among the last few.
    fn replace_bound(&mut self, next: Bound) {
        if let Some(previous) = self.bound.replace(next) {
            self.kept.push(previous);
            if self.kept.len() > MAX_KEPT_BINDS {
                self.kept.remove(0);
            }
        }
    }

    /// The 2-D table for `config`, baked if neither held nor kept bound, and bound.
    pub fn full_table(&mut self, config: BakeConfig, up: &Upload<'_>) -> Arc<Tables> {
        if self.reuse(&BoundKey::Full(config)) {
            if let Some(Bound {
                read: BoundTables::Full(t),
                ..
            }) = &self.bound
            {
                self.full = Some(t.clone());
                return t.clone();
            }
        }
        let tables = match &self.full {
            Some(t) if t.config == config => t.clone(),
            _ => {
                let start = Instant::now();
                let t = Arc::new(lut::bake(&config));
                self.last_bake = Some(start.elapsed());
                log::debug!(
                    "baked the {}x{} table in {:.2} ms",
                    config.layout.mu_size,
                    config.layout.r_size,
                    start.elapsed().as_secs_f64() * 1e3
                );
                self.full = Some(t.clone());
                t
            }
        };
        // Not bound nor kept (checked above): upload and bind it.
        let gpu_tables = GpuTables::upload(up.device, up.queue, &tables);
        let read = BoundTables::Full(tables.clone());
        self.replace_bound(up.bind(BoundKey::Full(config), read, &gpu_tables));
        tables
    }

    /// Holds `tables` as the 2-D table of their config, replacing any other tables of the
    /// same config (which may hold other values), and binds them.
    pub fn pin(&mut self, tables: Arc<Tables>, up: &Upload<'_>) {
        self.full = Some(tables.clone());
        let what = BoundKey::Full(tables.config);
        self.kept.retain(|b| b.what != what);
        if matches!(&self.bound, Some(b) if b.what == what) {
            self.bound = None;
        }
        self.full_table(tables.config, up);
    }

    /// The tables bound now (what the last draw read).
    pub fn bound(&self) -> Option<&Bound> {
        self.bound.as_ref()
    }

    /// Rows in the memory cache.
    pub fn cached_rows(&self) -> usize {
        self.rows.len()
    }

    /// Wall time of the latest bake (see `Renderer::last_bake_time`).
    pub fn last_bake(&self) -> Option<Duration> {
        self.last_bake
    }

    /// Records that the latest change of plan baked nothing (yet).
    pub fn clear_last_bake(&mut self) {
        self.last_bake = Some(Duration::ZERO);
    }
}
