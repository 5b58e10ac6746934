//! The exact model for image errors: tables whose reads return the precise reference
//! (within 1e-6; 1e-4 for height-correlated Smith, whose E has a `mu ln mu` term at grazing
//! angles) at the roughness values a scene uses, so that the CPU reference renderer
//! (`src/cpu`) evaluates the model with E and E_avg replaced by precise values.
//!
//! Calling the adaptive reference per pixel would cost an E_avg integral (thousands of E
//! integrals) per pixel; instead every roughness of the scene is a row of its own, exactly
//! on a texel centre (rows at multiples of 1/20: the reference scene's 0.15 ... 0.95), each
//! holding the reference at `EXACT_MU_SIZE` points of the warped mu axis, where a linear
//! read between neighbours is within 4e-7 of the reference (5.3e-5 for height-correlated
//! Smith; tested).

use rayon::prelude::*;

use shadeballs::brdf::Geometry;
use shadeballs::error::{Error, Result};
use shadeballs::lut::{
    e_avg_reference, e_reference, BakeConfig, Centres, EAvgRead, Layout, LayoutKind, MuAxis, RAxis,
    Storage, Tables,
};
use shadeballs::scene::Scene;

/// Rows of the exact tables: roughness `j / (EXACT_R_SIZE - 1)`.
pub const EXACT_R_SIZE: usize = 21;
/// Points along the warped mu axis of each row.
pub const EXACT_MU_SIZE: usize = 1025;

/// The layout of the exact tables.
pub fn exact_layout() -> Layout {
    Layout {
        kind: LayoutKind::Warped,
        mu_axis: MuAxis::Warped,
        r_axis: RAxis::Full,
        e_avg_read: EAvgRead::Linear,
        centres: Centres::Endpoints,
        mu_size: EXACT_MU_SIZE,
        r_size: EXACT_R_SIZE,
        storage: Storage::F32,
    }
}

/// Precise tables for every roughness `scene` uses, or an error naming a roughness that is
/// not a multiple of `1 / (EXACT_R_SIZE - 1)`.
pub fn exact_tables(scene: &Scene) -> Result<Tables> {
    let steps = (EXACT_R_SIZE - 1) as f64;
    for b in &scene.balls {
        let j = b.roughness * steps;
        if (j - j.round()).abs() > 1e-9 {
            return Err(Error::Invalid {
                what: "exact reference",
                message: format!(
                    "roughness {} is not a multiple of 1/{steps}: the exact tables have no row for it",
                    b.roughness
                ),
            });
        }
    }
    Ok(exact_for(scene.effective_geometry()))
}

/// Precise tables on [`exact_layout`] for `geometry` (every row).
pub fn exact_for(geometry: Geometry) -> Tables {
    let layout = exact_layout();
    let e: Vec<f64> = (0..layout.texels())
        .into_par_iter()
        .map(|k| {
            let (i, j) = (k % layout.mu_size, k / layout.mu_size);
            e_reference(
                layout.mu_of_texel(i, j),
                layout.roughness_of_texel(j),
                geometry,
            )
        })
        .collect();
    let e_avg: Vec<f64> = (0..layout.r_size)
        .into_par_iter()
        .map(|j| e_avg_reference(layout.roughness_of_texel(j), geometry))
        .collect();
    Tables {
        config: BakeConfig {
            geometry,
            layout,
            ..BakeConfig::default()
        },
        stored_loss: e.iter().map(|&v| (1.0 - v) as f32).collect(),
        stored_loss_avg: e_avg.iter().map(|&v| (1.0 - v) as f32).collect(),
        e,
        e_avg,
    }
}
