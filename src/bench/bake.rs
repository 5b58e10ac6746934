//! Baking (time against bake error) and reading (memory against read-path error).

use super::median_ms;
use super::table::{sci, Table};
use crate::brdf::Geometry;
use crate::lut::accuracy::{random_points, ReferencePoints, ReferenceTables};
use crate::lut::{self, BakeConfig, Layout, LayoutKind, Method, PointSet, Storage};

/// The bake-error goal of the default bake (issue 2).
pub const BAKE_ERROR_GOAL: f64 = 1e-4;

/// Repeats a measurement more often when it is fast: the median of up to 15 runs, at
/// least one, within about a second of total run time.
fn repeats_for(first_ms: f64) -> usize {
    (1000.0 / first_ms.max(1e-3)).clamp(1.0, 15.0) as usize
}

fn timed_bake(config: &BakeConfig) -> (f64, lut::Tables) {
    let start = std::time::Instant::now();
    let tables = lut::bake(config);
    let first = start.elapsed().as_secs_f64() * 1e3;
    match repeats_for(first) {
        // Slow enough that one run is its own median, and noise is small against it.
        1 => (first, tables),
        n => median_ms(n, || lut::bake(config)),
    }
}

/// The homework's configuration: cosine-weighted random sampling, 1024 samples a texel,
/// its 128 x 128 layout.
pub fn homework_config(geometry: Geometry) -> BakeConfig {
    BakeConfig {
        geometry,
        method: Method::Cosine,
        points: PointSet::Random,
        samples: 1024,
        layout: Layout::of_kind(LayoutKind::Games202),
    }
}

fn sample_counts(method: Method, quick: bool) -> &'static [usize] {
    match (method, quick) {
        (Method::Quadrature | Method::Chebyshev, false) => &[4, 6, 8, 12, 16, 24, 32],
        (Method::Quadrature, true) => &[8, 16],
        (Method::Vndf, false) => &[64, 256, 1024, 4096],
        (Method::Cosine | Method::Ndf, false) => &[64, 256, 1024],
        (_, true) => &[256],
    }
}

/// Every estimator at a sweep of sample counts on the default layout, per geometry term,
/// then the homework's 128 x 128 configuration against the default method on the same
/// layout.
pub fn bake_sweep(quick: bool) -> Vec<Table> {
    let mut sweep = Table::new(
        "bake",
        "Baking: wall time against bake error (default layout)",
        &[
            "geometry",
            "method",
            "points",
            "samples",
            "size",
            "time_ms",
            "e_max",
            "e_mean",
            "e_avg_max",
            "meets_1e-4",
        ],
    );
    let geometries: &[Geometry] = if quick {
        &[Geometry::Schlick]
    } else {
        &Geometry::ALL
    };
    for &geometry in geometries {
        let layout = Layout::default();
        let reference = ReferenceTables::new(layout, geometry);
        for method in Method::ALL {
            for &samples in sample_counts(method, quick) {
                let config = BakeConfig {
                    geometry,
                    method,
                    samples,
                    ..BakeConfig::default()
                };
                let (ms, tables) = timed_bake(&config);
                let (e, avg) = reference.bake_error(&tables);
                let meets = e.max <= BAKE_ERROR_GOAL && avg.max <= BAKE_ERROR_GOAL;
                sweep.push(vec![
                    geometry.to_string(),
                    method.to_string(),
                    if method == Method::Quadrature {
                        "-".into()
                    } else {
                        config.points.to_string()
                    },
                    samples.to_string(),
                    format!("{}x{}", layout.mu_size, layout.r_size),
                    format!("{ms:.3}"),
                    sci(e.max),
                    sci(e.mean),
                    sci(avg.max),
                    meets.to_string(),
                ]);
            }
        }
    }
    sweep.note = format!(
        "Goal: e_max and e_avg_max <= {BAKE_ERROR_GOAL:.0e}; the default is {} with {} nodes a segment.",
        lut::DEFAULT_METHOD,
        lut::DEFAULT_SAMPLES
    );
    vec![sweep, homework_comparison()]
}

/// The homework's lut-gen configuration against the default method, both on the homework's
/// 128 x 128 layout, same run.
fn homework_comparison() -> Table {
    let mut t = Table::new(
        "bake_vs_homework",
        "Baking the homework's 128x128 table: its configuration against the default method",
        &["config", "time_ms", "e_max", "e_mean", "e_avg_max"],
    );
    let homework = homework_config(Geometry::Schlick);
    let ours = BakeConfig {
        layout: homework.layout,
        ..BakeConfig::default()
    };
    let reference = ReferenceTables::new(homework.layout, homework.geometry);
    let mut figures = Vec::new();
    for (name, config) in [
        ("homework (cosine, 1024 random)", homework),
        ("default (quadrature)", ours),
    ] {
        let (ms, tables) = timed_bake(&config);
        let (e, avg) = reference.bake_error(&tables);
        figures.push((ms, e.max));
        t.push(vec![
            name.into(),
            format!("{ms:.3}"),
            sci(e.max),
            sci(e.mean),
            sci(avg.max),
        ]);
    }
    t.note = format!(
        "Default against homework, same run: {:.0}x faster, {:.0}x more accurate (max error).",
        figures[0].0 / figures[1].0,
        figures[0].1 / figures[1].1.max(f64::MIN_POSITIVE)
    );
    t
}

/// Every layout, size and storage: read-path error at random `(mu, roughness)` against
/// memory. Tables are baked with the default (accurate) method, so the error is the
/// layout's own.
pub fn read_sweep(quick: bool) -> Vec<Table> {
    let mut t = Table::new(
        "read",
        "Reading: read-path error of a bilinear lookup against memory (schlick G)",
        &[
            "layout",
            "size",
            "storage",
            "bytes",
            "e_max",
            "e_mean",
            "e_avg_max",
        ],
    );
    let n = if quick { 2_000 } else { 20_000 };
    let geometry = Geometry::Schlick;
    let points = ReferencePoints::new(random_points(n, 2017), geometry);
    let rough: Vec<f64> = random_points(if quick { 50 } else { 200 }, 7)
        .iter()
        .map(|p| p.1)
        .collect();
    let avg_ref: Vec<f64> = rough
        .iter()
        .map(|&r| lut::e_avg_reference(r, geometry))
        .collect();
    let mut layouts = vec![
        Layout::of_kind(LayoutKind::Games202),
        Layout::of_kind(LayoutKind::Games202).with_storage(Storage::F32),
    ];
    let sizes: &[(usize, usize)] = if quick {
        &[(32, 32), (64, 64)]
    } else {
        &[(16, 16), (32, 32), (64, 32), (48, 48), (64, 64), (128, 128)]
    };
    for &(mu, r) in sizes {
        layouts.push(Layout::default().with_size(mu, r));
    }
    for &(mu, r) in if quick {
        &[(64, 64)][..]
    } else {
        &[(32, 32), (64, 64), (128, 128)][..]
    } {
        layouts.push(Layout::of_kind(LayoutKind::SqrtMu).with_size(mu, r));
    }
    for storage in [Storage::F16, Storage::Unorm8] {
        layouts.push(Layout::default().with_storage(storage));
    }
    for layout in layouts {
        let tables = lut::bake(&BakeConfig {
            geometry,
            layout,
            ..BakeConfig::default()
        });
        let e = points.read_error(&tables);
        let avg = rough
            .iter()
            .zip(&avg_ref)
            .map(|(&r, &exact)| (tables.lut_e_avg(r as f32) as f64 - exact).abs())
            .fold(0.0, f64::max);
        t.push(vec![
            layout.kind.to_string(),
            format!("{}x{}", layout.mu_size, layout.r_size),
            layout.storage.to_string(),
            layout.bytes().to_string(),
            sci(e.max),
            sci(e.mean),
            sci(avg),
        ]);
    }
    t.note = format!("{n} uniformly random (mu, roughness) in [0, 1]^2 (seed 2017); goal: max <= 1e-3, mean <= 1e-4.");
    vec![t]
}
