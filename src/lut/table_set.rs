//! Which tables a frame reads: none, a scene's own rows, or the 2-D table. One type serves
//! every stage: the plan names the tables by their keys ([`TableKey`]), the GPU's table
//! cache binds them and the uniforms and the CPU renderer read them ([`TableSet`], whose
//! [`TableSet::key`] is the plan's key again).

use std::sync::Arc;

use super::{roughness_coord, BakeConfig, Layout, LutParams, MuAxis, RowKey, RowSet, Tables};

/// Which tables a frame reads, holding `R` for a scene's rows and `F` for the 2-D table:
/// the baked tables by default ([`TableSet`]), their keys in `TableKey`.
#[derive(Clone, Debug, PartialEq)]
pub enum TableSet<R = Arc<RowSet>, F = Arc<Tables>> {
    /// Nothing reads E: nothing baked (the GPU binds a one-texel placeholder).
    None,
    /// One exact row per roughness read, each ball its own row.
    Rows(R),
    /// The 2-D table.
    Full(F),
}

/// The tables a plan asks for, by key: each row's bake settings and roughness
/// ([`RowKey`]), or the 2-D table's bake settings.
pub(crate) type TableKey = TableSet<Vec<RowKey>, BakeConfig>;

impl TableKey {
    /// The key of one row per roughness in `roughness` (clamped like every read), or of
    /// nothing when it is empty.
    pub(crate) fn rows(config: &BakeConfig, roughness: &[f32]) -> Self {
        if roughness.is_empty() {
            return TableSet::None;
        }
        TableSet::Rows(roughness.iter().map(|&r| RowKey::new(config, r)).collect())
    }

    /// The roughness of each row asked for (empty unless rows).
    pub(crate) fn roughness(&self) -> Vec<f32> {
        match self {
            TableSet::Rows(keys) => keys.iter().map(RowKey::roughness).collect(),
            _ => Vec::new(),
        }
    }
}

impl TableSet {
    /// The 2-D table `tables` (shared, not copied, where the caller holds an `Arc`).
    pub fn full(tables: impl Into<Arc<Tables>>) -> Self {
        TableSet::Full(tables.into())
    }

    /// The key these tables were baked for: the plan's [`TableKey`] that binds them.
    pub(crate) fn key(&self) -> TableKey {
        match self {
            TableSet::None => TableSet::None,
            TableSet::Rows(rows) => TableSet::Rows(rows.rows.iter().map(|r| r.key).collect()),
            TableSet::Full(t) => TableSet::Full(t.config),
        }
    }

    /// The 2-D table, if that is what the set holds.
    pub(crate) fn as_full(&self) -> Option<&Arc<Tables>> {
        match self {
            TableSet::Full(t) => Some(t),
            _ => None,
        }
    }

    /// The read parameters of the tables (with none, those of the one-texel placeholder).
    pub(crate) fn lut_params(&self) -> LutParams {
        match self {
            TableSet::None => LutParams {
                mu_size: 1,
                r_size: 1,
                ..LutParams::default()
            },
            TableSet::Full(t) => t.layout().lut_params(),
            TableSet::Rows(rows) => rows.lut_params(),
        }
    }

    /// The mu axis of the tables (the pipelines' `MU_AXIS`); with none nothing reads it,
    /// and the default layout's is returned.
    pub(crate) fn mu_axis(&self) -> MuAxis {
        match self {
            TableSet::None => Layout::default().mu_axis,
            TableSet::Full(t) => t.layout().mu_axis,
            TableSet::Rows(rows) => rows.layout().mu_axis,
        }
    }

    /// A ball's `lut_row` (the roughness half of its E reads). With no tables the read (of
    /// the GPU's 1 x 1 placeholder) still runs where a pipeline branches on the ball's
    /// flag, so alpha is the ball's own, keeping the warped axis's division away from 0 / 0.
    pub(crate) fn lut_row(&self, roughness: f32) -> [f32; 3] {
        match self {
            TableSet::None => {
                let r = roughness_coord(roughness);
                [0.0, 0.0, r * r]
            }
            TableSet::Full(t) => t.lut_row(roughness),
            TableSet::Rows(rows) => rows.lut_row(roughness),
        }
    }

    /// `lut_loss_row` of `shaders/lut.wgsl`: `1 - E(mu)` along `row` (one of
    /// [`TableSet::lut_row`]'s; with none, the placeholder's 0).
    pub(crate) fn lut_loss_row(&self, mu: f32, row: [f32; 3]) -> f32 {
        match self {
            TableSet::None => 0.0,
            TableSet::Full(t) => t.lut_loss_row(mu, row),
            TableSet::Rows(rows) => rows.lut_loss_row(mu, row),
        }
    }

    /// `1 - E(mu, roughness)` as the shader reads it (f32; with none, the placeholder's 0).
    pub fn lut_loss(&self, mu: f32, roughness: f32) -> f32 {
        match self {
            TableSet::None => 0.0,
            TableSet::Full(t) => t.lut_loss(mu, roughness),
            TableSet::Rows(rows) => rows.lut_loss(mu, roughness),
        }
    }

    /// A ball's `1 - E_avg` as read: between rows of the 2-D table, or its own row's (with
    /// none, the placeholder's 0).
    pub fn lut_loss_avg(&self, roughness: f32) -> f32 {
        match self {
            TableSet::None => 0.0,
            TableSet::Full(t) => t.lut_loss_avg(roughness),
            TableSet::Rows(rows) => rows.lut_loss_avg(roughness),
        }
    }
}

impl From<Tables> for TableSet {
    fn from(tables: Tables) -> Self {
        TableSet::Full(Arc::new(tables))
    }
}

impl From<Arc<Tables>> for TableSet {
    fn from(tables: Arc<Tables>) -> Self {
        TableSet::Full(tables)
    }
}
