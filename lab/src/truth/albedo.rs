//! The directional-albedo study: the walk and every model on a grid of incidence cosine
//! `mu` and roughness, for every channel of the study's materials.

use rayon::prelude::*;

use super::fresnel::{Fresnel, Metal};
use super::microsurface::Microsurface;
use super::models::ChannelData;
use super::single::{single_albedo, Rules};
use super::walk::{self, Albedo};
use shadeballs::brdf::Geometry;

/// The grid and the effort per cell.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    pub roughness: Vec<f64>,
    pub mu: Vec<f64>,
    /// Walk paths per cell.
    pub paths: usize,
}

impl Grid {
    /// The full study: 10 roughness values x 16 cosines, denser towards grazing.
    pub fn full() -> Self {
        Grid {
            roughness: (1..=10).map(|k| k as f64 / 10.0).collect(),
            mu: vec![
                0.02, 0.04, 0.07, 0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95,
                1.0,
            ],
            paths: 400_000,
        }
    }

    /// A few cells with few paths (about a second): the corners of the full grid, where
    /// the largest errors are (low roughness and grazing mu, roughness 1), and two inside.
    pub fn quick() -> Self {
        Grid {
            roughness: vec![0.1, 0.2, 0.6, 1.0],
            mu: vec![0.02, 0.05, 0.3, 1.0],
            paths: 40_000,
        }
    }
}

/// How a channel's Fresnel is modelled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FresnelKind {
    /// `F = 1`.
    White,
    /// Schlick with `F0 = r`: the Fresnel of the renderer's `f_micro`.
    Schlick,
    /// The full conductor Fresnel of the (r, g) pair.
    Conductor,
}

/// One colour channel of one material.
#[derive(Clone, Copy, Debug)]
pub struct Channel {
    pub material: &'static str,
    pub kind: FresnelKind,
    /// 0, 1, 2 for R, G, B (0 for white).
    pub index: usize,
    pub fresnel: Fresnel,
    pub data: ChannelData,
}

impl Channel {
    /// "R", "G", "B", or "-" for white.
    pub fn name(&self) -> &'static str {
        match (self.kind, self.index) {
            (FresnelKind::White, _) => "-",
            (_, 0) => "R",
            (_, 1) => "G",
            _ => "B",
        }
    }
}

/// The study's channels: white, then copper and gold with Schlick's Fresnel, then copper
/// and gold with the full conductor Fresnel.
pub fn channels() -> Vec<Channel> {
    let mut out = vec![Channel {
        material: "white",
        kind: FresnelKind::White,
        index: 0,
        fresnel: Fresnel::One,
        data: ChannelData {
            f0: 1.0,
            edge_tint: 1.0,
            f_avg: 1.0,
        },
    }];
    let metals = [Metal::copper(), Metal::gold()];
    for kind in [FresnelKind::Schlick, FresnelKind::Conductor] {
        for m in &metals {
            for c in 0..3 {
                let fresnel = match kind {
                    FresnelKind::Conductor => m.conductor(c),
                    _ => m.schlick(c),
                };
                out.push(Channel {
                    material: m.name,
                    kind,
                    index: c,
                    fresnel,
                    data: ChannelData {
                        f0: m.r[c],
                        edge_tint: m.g[c],
                        f_avg: fresnel.average(),
                    },
                });
            }
        }
    }
    out
}

/// One grid cell: the walk and the single-scattering albedo of every channel.
#[derive(Clone, Debug)]
pub struct Cell {
    pub roughness: f64,
    pub mu: f64,
    pub walk: Albedo,
    /// `[geometry in Geometry::ALL order][channel]`.
    pub single: Vec<Vec<f64>>,
}

impl Cell {
    pub fn single_of(&self, g: Geometry, ch: usize) -> f64 {
        let k = Geometry::ALL.iter().position(|&x| x == g).unwrap_or(0);
        self.single[k][ch]
    }

    /// The walk's albedo: the exact single scattering (height-correlated G, the walk's own,
    /// by quadrature) plus the walk's multiple scattering. Both parts are unbiased; the
    /// quadrature only removes the single-scattering noise.
    pub fn truth(&self, ch: usize) -> f64 {
        self.single_of(Geometry::SmithCorrelated, ch) + self.walk.multiple[ch].mean()
    }

    pub fn truth_stderr(&self, ch: usize) -> f64 {
        self.walk.multiple[ch].stderr()
    }
}

/// Runs the walk and the quadrature on every cell (rayon over cells and over chunks of
/// paths; deterministic for any thread count).
pub fn compute(grid: &Grid, channels: &[Channel]) -> Vec<Cell> {
    let fresnels: Vec<Fresnel> = channels.iter().map(|c| c.fresnel).collect();
    let rules = Rules::default();
    let cells: Vec<(usize, usize)> = (0..grid.roughness.len())
        .flat_map(|j| (0..grid.mu.len()).map(move |i| (j, i)))
        .collect();
    cells
        .par_iter()
        .map(|&(j, i)| {
            let (r, mu) = (grid.roughness[j], grid.mu[i]);
            let seed = [1, j as u64, i as u64];
            Cell {
                roughness: r,
                mu,
                walk: walk::albedo(&Microsurface::new(r), mu, &fresnels, grid.paths, &seed),
                single: single_albedo(&rules, mu, r, &fresnels, &Geometry::ALL),
            }
        })
        .collect()
}
