//! The renderer's tables: what a plan needs, baked, uploaded and bound. Rows come from a
//! memory cache keyed by every input that changes their values (`lut::RowKey`), so the
//! viewer, which re-plans on every change, bakes only the rows it has not baked before; the
//! 2-D table is kept for its config. A plan that needs nothing keeps whatever is bound (its
//! pipelines never read it) or binds 1 x 1 placeholders. The last few bind groups are kept
//! too, so that switching back and forth (a caller asking for the 2-D table between
//! planned frames) uploads nothing.
//!
//! The cache holds handles of the renderer's device, queue and group 0 (wgpu's handles
//! are shared references), so that it can bake, upload and bind on its own.

use std::collections::HashMap;
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::bindings::Bindings;
use super::upload::GpuTables;
use crate::lut::{self, BakeConfig, Row, RowKey, RowSet, TableKey, TableSet, Tables};

/// Most rows the memory cache keeps (about 0.8 KB each at 64 texels): past it, the rows
/// not bound are dropped.
pub(crate) const MAX_CACHED_ROWS: usize = 4096;

/// Bind groups kept besides the bound one (their textures stay alive with them).
const MAX_KEPT_BINDS: usize = 4;

/// Bound tables: their key, the tables (read by the uniforms and the probe) and their bind
/// group. With [`TableSet::None`] the group holds one-texel placeholders.
pub(crate) struct Bound {
    key: TableKey,
    pub tables: TableSet,
    pub bind: wgpu::BindGroup,
}

/// The tables baked, uploaded and bound.
pub(crate) struct TableCache {
    device: wgpu::Device,
    queue: wgpu::Queue,
    bindings: Bindings,
    rows: HashMap<RowKey, Arc<Row>>,
    /// The latest 2-D table (baked here or given by `pin`).
    full: Option<Arc<Tables>>,
    /// The bound tables.
    bound: Option<Bound>,
    /// Recently bound tables, oldest first.
    kept: Vec<Bound>,
}

impl TableCache {
    /// An empty cache that uploads on `device` and `queue` and binds with `bindings`.
    pub(crate) fn new(device: &wgpu::Device, queue: &wgpu::Queue, bindings: &Bindings) -> Self {
        TableCache {
            device: device.clone(),
            queue: queue.clone(),
            bindings: bindings.clone(),
            rows: HashMap::new(),
            full: None,
            bound: None,
            kept: Vec::new(),
        }
    }

    /// Bakes (what is not cached), uploads and binds the tables of `key`. Returns the wall
    /// time spent baking (zero when everything was cached or bound).
    pub(crate) fn ensure(&mut self, key: &TableKey) -> Duration {
        match key {
            TableSet::None => {
                if self.bound.is_none() && !self.reuse(key) {
                    let placeholder = GpuTables::placeholder(&self.device, &self.queue);
                    self.replace_bound(self.bind(TableSet::None, &placeholder));
                }
                Duration::ZERO
            }
            TableSet::Full(config) => self.full_table(*config).1,
            TableSet::Rows(_) if self.reuse(key) => Duration::ZERO,
            TableSet::Rows(keys) => self.bind_rows(keys),
        }
    }

    /// A bound entry of `tables` uploaded as `gpu_tables`.
    fn bind(&self, tables: TableSet, gpu_tables: &GpuTables) -> Bound {
        Bound {
            key: tables.key(),
            tables,
            bind: self.bindings.bind(&self.device, gpu_tables),
        }
    }

    /// Binds the rows of `keys`, baking those not in the cache; the time spent baking.
    fn bind_rows(&mut self, keys: &[RowKey]) -> Duration {
        let missing: Vec<RowKey> = keys
            .iter()
            .filter(|k| !self.rows.contains_key(k))
            .copied()
            .collect();
        let mut baked_in = Duration::ZERO;
        if !missing.is_empty() {
            let start = Instant::now();
            let baked = lut::bake_rows(&missing);
            baked_in = start.elapsed();
            log::debug!(
                "baked {} of {} rows in {:.2} ms",
                missing.len(),
                keys.len(),
                baked_in.as_secs_f64() * 1e3
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
        let gpu_tables = GpuTables::upload_rows(&self.device, &self.queue, &set);
        self.replace_bound(self.bind(TableSet::Rows(set), &gpu_tables));
        baked_in
    }

    /// Makes the bind group of `key` the bound one if it is bound or kept; whether it was.
    fn reuse(&mut self, key: &TableKey) -> bool {
        if matches!(&self.bound, Some(b) if b.key == *key) {
            return true;
        }
        match self.kept.iter().position(|b| b.key == *key) {
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

    /// The 2-D table for `config`, baked if neither held nor kept bound, and bound; with
    /// the wall time spent baking it (zero when it was held).
    pub(crate) fn full_table(&mut self, config: BakeConfig) -> (Arc<Tables>, Duration) {
        if self.reuse(&TableSet::Full(config)) {
            if let Some(t) = self.bound.as_ref().and_then(|b| b.tables.as_full()) {
                let t = t.clone();
                self.full = Some(t.clone());
                return (t, Duration::ZERO);
            }
        }
        let (tables, baked_in) = match &self.full {
            Some(t) if t.config == config => (t.clone(), Duration::ZERO),
            _ => {
                let start = Instant::now();
                let t = Arc::new(lut::bake(&config));
                let baked_in = start.elapsed();
                log::debug!(
                    "baked the {}x{} table in {:.2} ms",
                    config.layout.mu_size,
                    config.layout.r_size,
                    baked_in.as_secs_f64() * 1e3
                );
                self.full = Some(t.clone());
                (t, baked_in)
            }
        };
        // Not bound nor kept (checked above): upload and bind it.
        let gpu_tables = GpuTables::upload(&self.device, &self.queue, &tables);
        self.replace_bound(self.bind(TableSet::Full(tables.clone()), &gpu_tables));
        (tables, baked_in)
    }

    /// Holds `tables` as the 2-D table of their config, replacing any other tables of the
    /// same config (which may hold other values), and binds them.
    pub(crate) fn pin(&mut self, tables: Arc<Tables>) {
        self.full = Some(tables.clone());
        let key = TableSet::Full(tables.config);
        self.kept.retain(|b| b.key != key);
        if matches!(&self.bound, Some(b) if b.key == key) {
            self.bound = None;
        }
        self.full_table(tables.config);
    }

    /// The tables bound now (what the last draw read).
    pub(crate) fn bound(&self) -> Option<&Bound> {
        self.bound.as_ref()
    }

    /// Rows in the memory cache.
    pub(crate) fn cached_rows(&self) -> usize {
        self.rows.len()
    }
}
