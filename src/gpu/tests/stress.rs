//! Stress over the edge grid (issue 6): every BRDF function, the table reads and the baker
//! at the edges of their domains and at every f32 value within `ULPS` steps of each edge,
//! subnormals included. Nothing may be NaN, infinite or negative. (What the roughness
//! clamp does to the energy: `clamp.rs`.)
//!
//! The grids run in f64 on f32 inputs (the values the GPU can be handed); the same kind of
//! grid runs through the WGSL functions in `gpu_stress.rs`.

use std::sync::atomic::{AtomicU64, Ordering};

use crate::brdf::*;
use crate::lut::{
    bake, e_avg_reference, e_reference, BakeConfig, Layout, LayoutKind, Method, PointSet, Storage,
};
use rayon::prelude::*;

/// How many f32 neighbours on each side of an edge the grids take.
pub(crate) const ULPS: u32 = 16;

/// `x` and its `k` f32 neighbours on each side (`next_up` / `next_down`: through zero and
/// the subnormals, across the normal/subnormal boundary).
pub(crate) fn neighbours(x: f32, k: u32) -> Vec<f32> {
    let mut v = vec![x];
    let (mut up, mut down) = (x, x);
    for _ in 0..k {
        up = up.next_up();
        down = down.next_down();
        v.extend([up, down]);
    }
    v
}

/// Values of a quantity in `[0, 1]` (a reflectance, a loss, E_avg, F_avg): both ends and
/// every f32 within `k` steps inside them, the smallest subnormals, the normal/subnormal
/// boundary, `DIV_EPSILON`, the roughness clamp, and a few interior values.
pub(crate) fn unit_edges(k: u32) -> Vec<f32> {
    let mut v = Vec::new();
    for x in [
        0.0,
        f32::from_bits(1),
        f32::MIN_POSITIVE,
        DIV_EPSILON as f32,
        1e-6,
        ROUGHNESS_MIN as f32,
        0.25,
        0.5,
        1.0,
    ] {
        v.extend(neighbours(x, k));
    }
    v.retain(|x| (0.0..=1.0).contains(x));
    v.sort_by(f32::total_cmp);
    v.dedup_by(|a, b| a.to_bits() == b.to_bits());
    v
}

/// Cosines: the unit edges, `-0.0` and negative values (below the horizon, at and near it),
/// and values just above 1 (what rounding in `normalize` can give).
pub(crate) fn cos_edges(k: u32) -> Vec<f32> {
    let mut v = unit_edges(k);
    v.extend(neighbours(-0.0, k).into_iter().filter(|x| *x <= 0.0));
    v.extend(neighbours(1.0, k).into_iter().filter(|x| *x > 1.0));
    v.extend([-f32::MIN_POSITIVE, -1e-6, -0.5, -1.0]);
    v
}

/// Roughness: the cosines' values (negative and above 1 are clamped), and on the CPU NaN.
pub(crate) fn roughness_edges(k: u32, with_nan: bool) -> Vec<f32> {
    let mut v = cos_edges(k);
    v.extend([2.0, f32::INFINITY, f32::NEG_INFINITY]);
    if with_nan {
        v.push(f32::NAN);
    }
    v
}

fn ok(v: f64) -> bool {
    v.is_finite() && v >= 0.0
}

/// Runs `f` on every point of a grid in parallel; returns (evaluations, failures with their
/// first example).
fn grid<P, F>(points: &[P], f: F) -> (u64, Vec<String>)
where
    P: Sync + std::fmt::Debug,
    F: Fn(&P) -> Vec<f64> + Sync,
{
    let count = AtomicU64::new(0);
    let bad: Vec<String> = points
        .par_iter()
        .filter_map(|p| {
            let values = f(p);
            count.fetch_add(values.len() as u64, Ordering::Relaxed);
            let bad = values.iter().position(|v| !ok(*v));
            bad.map(|k| format!("{p:?}: value {k} = {}", values[k]))
        })
        .collect();
    (count.into_inner(), bad)
}

fn report(what: &str, (count, bad): (u64, Vec<String>)) -> u64 {
    println!(
        "edge grid, {what}: {count} evaluations, {} non-finite or negative",
        bad.len()
    );
    assert!(
        bad.is_empty(),
        "{what}: {} failures, e.g. {:?}",
        bad.len(),
        &bad[..bad.len().min(5)]
    );
    count
}

fn cartesian3(a: &[f32], b: &[f32], c: &[f32]) -> Vec<[f32; 3]> {
    a.iter()
        .flat_map(|&x| {
            b.iter()
                .flat_map(move |&y| c.iter().map(move |&z| [x, y, z]))
        })
        .collect()
}

#[test]
fn every_brdf_function_is_finite_and_non_negative_on_the_edge_grid() {
    let (cos, unit, rough) = (
        cos_edges(ULPS),
        unit_edges(ULPS),
        roughness_edges(ULPS, true),
    );
    let f = |x: f32| x as f64;
    let mut total = 0;
    // One- and two-argument terms over their full grids.
    let pairs = cartesian3(&cos, &rough, &[0.0]);
    total += report(
        "d_ggx, g1_*, lambda_smith (n.h or mu) x roughness",
        grid(&pairs, |&[c, r, _]| {
            let alpha = alpha_from_roughness(f(r));
            let lambda = lambda_smith(f(c), alpha);
            vec![
                d_ggx(f(c), alpha),
                g1_schlick(f(c), alpha / 2.0),
                g1_smith(f(c), alpha),
                // +infinity at c <= 0 by definition (fully masked); finite everywhere else.
                if f(c) <= 0.0 { 0.0 } else { lambda },
                roughness_clamped(f(r)),
            ]
        }),
    );
    let reflect = cartesian3(&unit, &cos, &[0.0]);
    total += report(
        "f_schlick (F0 x cos), f_avg_*",
        grid(&reflect, |&[f0, c, _]| {
            vec![
                f_schlick(f(f0), f(c)),
                f_avg_schlick(f(f0)),
                f_avg_games202(f(f0), f(f0)),
            ]
        }),
    );
    let averages = cartesian3(&unit, &unit, &[0.0]);
    total += report(
        "f_add_accurate, f_add_games202 (F_avg x E_avg)",
        grid(&averages, |&[fa, ea, _]| {
            vec![f_add_accurate(f(fa), f(ea)), f_add_games202(f(fa), f(ea))]
        }),
    );
    let losses = cartesian3(&unit, &unit, &unit);
    total += report(
        "f_ms (loss_o x loss_i x loss_avg)",
        grid(&losses, |&[a, b, c]| {
            vec![f_ms(f(a), f(b), f_ms_norm(f(c)))]
        }),
    );
    let g = cartesian3(&cos, &cos, &rough);
    total += report(
        "g_schlick, g_smith, g_smith_correlated",
        grid(&g, |&[o, i, r]| {
            Geometry::ALL
                .iter()
                .map(|geo| geo.g(f(o), f(i), f(r)))
                .collect()
        }),
    );
    // f_micro has five arguments: the grid takes fewer neighbours (4) per edge.
    let (cos4, rough4) = (cos_edges(4), roughness_edges(4, true));
    let micro: Vec<[f32; 4]> = cartesian3(&cos4, &cos4, &cos4)
        .into_iter()
        .flat_map(|[o, i, h]| rough4.iter().map(move |&r| [o, i, h, r]))
        .collect();
    total += report(
        "f_micro (mu_o x mu_i x n.h x roughness, 3 G, F = 1)",
        grid(&micro, |&[o, i, h, r]| {
            Geometry::ALL
                .iter()
                .map(|&geo| f_micro(1.0, f(o), f(i), f(h), f(r), geo))
                .collect()
        }),
    );
    println!("edge grid, BRDF functions: {total} evaluations in all");
    assert!(total > 10_000_000, "the grid shrank: {total}");
}

#[test]
fn table_reads_are_finite_and_in_range_on_the_edge_grid() {
    let (cos, rough) = (cos_edges(ULPS), roughness_edges(ULPS, true));
    let mut total = 0;
    for geometry in Geometry::ALL {
        for kind in LayoutKind::ALL {
            let tables = bake(&BakeConfig {
                geometry,
                layout: Layout::of_kind(kind),
                ..BakeConfig::default()
            });
            let points = cartesian3(&cos, &rough, &[0.0]);
            // A loss read is in [0, 1]; so are E and E_avg.
            let (count, bad) = grid(&points, |&[mu, r, _]| {
                let values = [
                    tables.lut_loss(mu, r),
                    tables.lut_e(mu, r),
                    tables.lut_loss_avg(r),
                    tables.lut_e_avg(r),
                ];
                values
                    .iter()
                    .map(|&v| if v <= 1.0 { v as f64 } else { -1.0 })
                    .collect()
            });
            total += report(
                &format!("table reads, {geometry} G, {kind} layout"),
                (count, bad),
            );
        }
    }
    println!("edge grid, table reads: {total} evaluations in all");
}

#[test]
fn the_baker_is_finite_and_bounded_at_every_size_method_and_storage_edge() {
    let mut texels = 0;
    for geometry in Geometry::ALL {
        for kind in LayoutKind::ALL {
            for storage in Storage::ALL {
                for (method, samples) in [
                    (Method::Quadrature, 1),
                    (Method::Quadrature, 16),
                    (Method::Vndf, 1),
                    (Method::Ndf, 1),
                    (Method::Cosine, 1),
                ] {
                    // The CLI's smallest table (2 x 2), an odd size, and the layout's own.
                    let own = Layout::of_kind(kind);
                    for (mu, r) in [(2, 2), (3, 5), (own.mu_size, own.r_size)] {
                        let layout = own.with_size(mu, r).with_storage(storage);
                        let t = bake(&BakeConfig {
                            geometry,
                            method,
                            points: PointSet::Random,
                            samples,
                            layout,
                        });
                        let unit = |v: f64| v.is_finite() && (0.0..=1.0).contains(&v);
                        assert!(
                            t.e.iter().chain(&t.e_avg).all(|&v| unit(v))
                                && t.stored_loss
                                    .iter()
                                    .chain(&t.stored_loss_avg)
                                    .all(|&v| unit(v as f64)),
                            "{geometry} {kind} {storage:?} {method} x{samples} {mu}x{r}"
                        );
                        texels += t.e.len() + t.e_avg.len();
                    }
                }
            }
        }
    }
    println!("baker edges: {texels} texels baked, all finite and in [0, 1]");
}

#[test]
fn the_reference_is_finite_and_bounded_on_the_edge_grid() {
    // The precise reference at every mu edge (k = 2) and the roughness edges (k = 2).
    let (mus, rs) = (unit_edges(2), roughness_edges(2, true));
    let points = cartesian3(&mus, &rs, &[0.0]);
    let mut total = 0;
    for geometry in Geometry::ALL {
        let (count, bad) = grid(&points, |&[mu, r, _]| {
            let e = e_reference(mu as f64, r as f64, geometry);
            vec![if e <= 1.0 + 1e-9 { e } else { -e }]
        });
        total += report(&format!("e_reference, {geometry} G"), (count, bad));
        let (count, bad) = grid(&[0.0f32, ROUGHNESS_MIN as f32, 1.0], |&r| {
            vec![e_avg_reference(r as f64, geometry)]
        });
        total += report(&format!("e_avg_reference, {geometry} G"), (count, bad));
    }
    println!("edge grid, precise reference: {total} evaluations");
}
