//! Baking: wall time against bake error, every estimator at a sweep of sample counts (per
//! geometry term) and of table sizes, with the homework's configuration as the peer row.
//! Every error is against [`ReferenceTables`], the adaptive Gauss-Kronrod reference at the
//! same texels ([`bake_errors`]), never against another estimator.

use super::table::{sci, Table};
use super::{median_ms, Goal, Sweep};
use crate::plot::{Plot, Series, Style};
use shadeballs::brdf::Geometry;
use shadeballs::lut::accuracy::{ErrorStats, ReferenceTables};
use shadeballs::lut::{self, BakeConfig, Layout, LayoutKind, Method, PointSet, Tables};

/// The bake-error goal of the default bake (issue 2), and its time goal.
pub const BAKE_ERROR_GOAL: f64 = 1e-4;
pub const BAKE_TIME_GOAL_MS: f64 = 10.0;

/// The label of the homework's configuration in every table.
pub const HOMEWORK: &str = "homework (cosine 1024 random; 128x128 unorm8)";

/// Repeats a measurement more often when it is fast: the median of up to 15 runs, at
/// least one, within about a second of total run time (`quick`: a tenth of that).
fn repeats_for(first_ms: f64, quick: bool) -> usize {
    let budget = if quick { 100.0 } else { 1000.0 };
    (budget / first_ms.max(1e-3)).clamp(1.0, 15.0) as usize
}

/// Median bake time (ms) and the tables.
pub fn timed_bake(config: &BakeConfig, quick: bool) -> (f64, Tables) {
    let start = std::time::Instant::now();
    let tables = lut::bake(config);
    let first = start.elapsed().as_secs_f64() * 1e3;
    match repeats_for(first, quick) {
        // Slow enough that one run is its own median, and noise is small against it.
        1 => (first, tables),
        n => median_ms(n, || lut::bake(config)),
    }
}

/// The homework's configuration: cosine-weighted random sampling, 1024 samples a texel,
/// its 128 x 128 layout with 8-bit storage.
pub fn homework_config(geometry: Geometry) -> BakeConfig {
    BakeConfig {
        geometry,
        method: Method::Cosine,
        points: PointSet::Random,
        samples: 1024,
        layout: Layout::of_kind(LayoutKind::Games202),
    }
}

/// Bake error of `tables` (E per texel, E_avg per row) against the precise reference of
/// their own layout and geometry: what every bake table reports.
pub fn bake_errors(tables: &Tables) -> (ErrorStats, ErrorStats) {
    ReferenceTables::new(*tables.layout(), tables.config.geometry).bake_error(tables)
}

fn sample_counts(method: Method, quick: bool) -> &'static [usize] {
    match (method, quick) {
        (Method::Quadrature | Method::Chebyshev, false) => &[4, 6, 8, 12, 16, 20, 24, 32],
        (Method::Quadrature | Method::Chebyshev, true) => &[8, 16, 24],
        (Method::Vndf, false) => &[64, 256, 1024, 4096],
        (Method::Cosine | Method::Ndf, false) => &[64, 256, 1024],
        (_, true) => &[64, 256],
    }
}

const COLUMNS: [&str; 11] = [
    "config",
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
];

/// One measured bake as a row of [`COLUMNS`]; returns `(time, e_max)` too.
fn bake_row(
    config: &BakeConfig,
    label: &str,
    quick: bool,
    reference: &ReferenceTables,
) -> (Vec<String>, (f64, f64)) {
    let (ms, tables) = timed_bake(config, quick);
    let (e, avg) = reference.bake_error(&tables);
    let meets = e.max <= BAKE_ERROR_GOAL && avg.max <= BAKE_ERROR_GOAL;
    let points = match config.method {
        Method::Quadrature | Method::Chebyshev => "-".to_string(),
        _ => config.points.to_string(),
    };
    let l = config.layout;
    let row = vec![
        label.to_string(),
        config.geometry.to_string(),
        config.method.to_string(),
        points,
        config.samples.to_string(),
        format!("{}x{} {}", l.mu_size, l.r_size, l.storage),
        format!("{ms:.3}"),
        sci(e.max),
        sci(e.mean),
        sci(avg.max),
        meets.to_string(),
    ];
    (row, (ms, e.max))
}

/// The homework's configuration as a row, with its own 128 x 128 reference.
fn homework_row(quick: bool, hw_reference: &ReferenceTables) -> (Vec<String>, (f64, f64)) {
    bake_row(
        &homework_config(Geometry::Schlick),
        HOMEWORK,
        quick,
        hw_reference,
    )
}

/// Every estimator at a sweep of sample counts on the default layout, per geometry term;
/// every estimator at a sweep of table sizes; the homework's 128 x 128 table against the
/// default method.
pub fn bake_sweep(quick: bool) -> Sweep {
    let hw_reference =
        ReferenceTables::new(Layout::of_kind(LayoutKind::Games202), Geometry::Schlick);
    let (hw_row, hw_point) = homework_row(quick, &hw_reference);
    let mut sweep = Table::new(
        "bake",
        "Baking: wall time against bake error (default 64x64 warped layout)",
        &COLUMNS,
    );
    sweep.push(hw_row.clone());
    let geometries: &[Geometry] = if quick {
        &[Geometry::Schlick]
    } else {
        &Geometry::ALL
    };
    let mut plot = Plot {
        title: "Bake: time against max error (schlick G, 64x64)".into(),
        x_label: "bake wall time (ms, median)".into(),
        y_label: "max |E - E_ref|".into(),
        goals: vec![
            ("1e-4".into(), None, Some(BAKE_ERROR_GOAL)),
            ("10 ms".into(), Some(BAKE_TIME_GOAL_MS), None),
        ],
        ..Default::default()
    };
    let mut goals = Vec::new();
    for &geometry in geometries {
        let reference = ReferenceTables::new(Layout::default(), geometry);
        for method in Method::ALL {
            let mut points = Vec::new();
            for &samples in sample_counts(method, quick) {
                let config = BakeConfig {
                    geometry,
                    method,
                    samples,
                    ..BakeConfig::default()
                };
                let default = BakeConfig {
                    geometry,
                    ..BakeConfig::default()
                };
                let label = if config == default { "default" } else { "-" };
                let (row, point) = bake_row(&config, label, quick, &reference);
                if label == "default" {
                    goals.push(Goal {
                        what: format!("default bake ({geometry} G): max error <= 1e-4 in <= 10 ms"),
                        figure: format!("{} ms, E max {}, E_avg max {}", row[6], row[7], row[9]),
                        met: row[10] == "true" && point.0 <= BAKE_TIME_GOAL_MS,
                    });
                }
                points.push(point);
                sweep.push(row);
            }
            if geometry == Geometry::Schlick {
                plot.series.push(Series {
                    label: method.to_string(),
                    points,
                    ..Default::default()
                });
            }
        }
    }
    plot.series.push(Series {
        label: "homework (128x128)".into(),
        points: vec![hw_point],
        style: Style::Peer,
        ..Default::default()
    });
    sweep.note = format!(
        "Goal: e_max and e_avg_max <= {BAKE_ERROR_GOAL:.0e} in <= {BAKE_TIME_GOAL_MS} ms; the default is {} with {} nodes a segment. The homework row is on its own 128x128 layout.",
        lut::DEFAULT_METHOD,
        lut::DEFAULT_SAMPLES
    );
    let (sizes, sizes_plot) = size_sweep(quick, &hw_row, hw_point);
    let (versus, goal) = homework_comparison(quick, &hw_reference, hw_point, &hw_row);
    goals.push(goal);
    Sweep {
        tables: vec![sweep, sizes, versus],
        plots: vec![("bake".into(), plot), ("bake_sizes".into(), sizes_plot)],
        goals,
    }
}

/// Every estimator at its usual sample count over table sizes (schlick G, warped layout).
fn size_sweep(quick: bool, hw_row: &[String], hw_point: (f64, f64)) -> (Table, Plot) {
    let mut t = Table::new(
        "bake_sizes",
        "Baking: wall time against bake error over table sizes (schlick G, warped layout)",
        &COLUMNS,
    );
    t.push(hw_row.to_vec());
    let sizes: &[usize] = if quick {
        &[32, 64]
    } else {
        &[16, 32, 64, 128, 256]
    };
    let mut plot = Plot {
        title: "Bake over table sizes: time against max error (schlick G)".into(),
        x_label: "bake wall time (ms, median)".into(),
        y_label: "max |E - E_ref|".into(),
        ..Default::default()
    };
    // Each size's precise reference, once for every method.
    let references: Vec<ReferenceTables> = sizes
        .iter()
        .map(|&n| ReferenceTables::new(Layout::default().with_size(n, n), Geometry::Schlick))
        .collect();
    for method in Method::ALL {
        let samples = match method {
            Method::Quadrature | Method::Chebyshev => lut::DEFAULT_SAMPLES,
            _ if quick => 256,
            _ => 1024,
        };
        let mut points = Vec::new();
        for reference in &references {
            let layout = reference.layout;
            let config = BakeConfig {
                method,
                samples,
                layout,
                ..BakeConfig::default()
            };
            let (row, point) = bake_row(&config, "-", quick, reference);
            points.push(point);
            t.push(row);
        }
        plot.series.push(Series {
            label: format!("{method} ({samples})"),
            points,
            ..Default::default()
        });
    }
    plot.series.push(Series {
        label: "homework (128x128)".into(),
        points: vec![hw_point],
        style: Style::Peer,
        ..Default::default()
    });
    t.note = format!("Sizes {sizes:?} (N x N); quadrature and chebyshev at {} nodes a segment; a method's time grows with the texel count unless it interpolates (chebyshev).", lut::DEFAULT_SAMPLES);
    (t, plot)
}

/// The homework's configuration against the default method, both on the homework's 128 x
/// 128 8-bit layout, same run.
fn homework_comparison(
    quick: bool,
    reference: &ReferenceTables,
    hw_point: (f64, f64),
    hw_row: &[String],
) -> (Table, Goal) {
    let mut t = Table::new(
        "bake_vs_homework",
        "Baking the homework's 128x128 table: its configuration against the default method",
        &COLUMNS,
    );
    t.push(hw_row.to_vec());
    let ours = BakeConfig {
        layout: Layout::of_kind(LayoutKind::Games202),
        ..BakeConfig::default()
    };
    let (row, (ms, e_max)) = bake_row(&ours, "default method", quick, reference);
    t.push(row);
    let faster = hw_point.0 / ms;
    let accurate = hw_point.1 / e_max.max(f64::MIN_POSITIVE);
    t.note = format!(
        "Default against homework, same run: {faster:.0}x faster, {accurate:.0}x more accurate (max E error)."
    );
    let goal = Goal {
        what: "homework's 128x128 table: >= 100x faster and >= 100x more accurate than its configuration".into(),
        figure: format!("{faster:.0}x faster ({:.1} ms against {:.1} ms), {accurate:.0}x more accurate ({} against {})", ms, hw_point.0, sci(e_max), sci(hw_point.1)),
        met: faster >= 100.0 && accurate >= 100.0,
    };
    (t, goal)
}
