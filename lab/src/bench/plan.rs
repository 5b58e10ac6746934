//! Planning (issue 7): what a scene's own rows cost to bake against the 2-D table, which
//! sets the threshold past which the plan takes the table (`scene::MAX_PLANNED_ROWS`), and
//! what they read at the scene's roughness values against the precise reference.

use super::median_ms;
use super::table::{sci, Table};
use super::{Goal, Sweep};
use shadeballs::brdf::Geometry;
use shadeballs::gpu::{DrawOptions, Plan, MAX_PLANNED_ROWS};
use shadeballs::lut::accuracy::{random_points, ErrorStats, ReferencePoints};
use shadeballs::lut::{self, BakeConfig, RowSet, Tables};
use shadeballs::scene::Scene;

/// `k` roughness values spread over [0.05, 0.95].
fn spread(k: usize) -> Vec<f32> {
    (0..k)
        .map(|i| 0.05 + 0.9 * i as f32 / (k.max(2) - 1) as f32)
        .collect()
}

/// Median time (ms) of baking the rows of `config` at `roughness` from nothing (no cache).
fn rows_ms(config: &BakeConfig, roughness: &[f32], repeats: usize) -> (f64, RowSet) {
    median_ms(repeats, || RowSet::bake(config, roughness))
}

/// Max read error on the probe's grid (mu = i / 64) and mean at random mu, at `roughness`.
fn read_error(
    read: &dyn Fn(f32, f32) -> f32,
    config: &BakeConfig,
    roughness: &[f32],
) -> (f64, f64) {
    let mut max: f64 = 0.0;
    let (mut sum, mut n) = (0.0, 0.0);
    for &r in roughness {
        for i in 0..=64 {
            let mu = i as f64 / 64.0;
            let exact = lut::e_reference(mu, r as f64, config.geometry);
            max = max.max((read(mu as f32, r) as f64 - exact).abs());
        }
        for (mu, _) in random_points(400, 7) {
            let exact = lut::e_reference(mu, r as f64, config.geometry);
            sum += (read(mu as f32, r) as f64 - exact).abs();
            n += 1.0;
        }
    }
    (max, sum / n)
}

/// Bake time of k rows against the 2-D table, and the default scene's plan against the
/// table it replaces (same run).
pub fn plan_sweep(quick: bool) -> Sweep {
    let scene = Scene::reference();
    let config = BakeConfig {
        geometry: scene.effective_geometry(),
        ..BakeConfig::default()
    };
    let repeats = if quick { 5 } else { 21 };
    let mut t = Table::new(
        "plan",
        "Planning: bake time of k exact rows against the 64x64 table (smith-correlated G, chebyshev 24, same run)",
        &["config", "rows", "bake_ms", "table_ms", "rows_over_table", "probe_max_err", "random_mu_mean_err"],
    );
    let (table_ms, full): (f64, Tables) = median_ms(repeats, || lut::bake(&config));
    let counts: &[usize] = if quick {
        &[1, 5, 16, 24]
    } else {
        &[1, 2, 5, 8, 12, 16, 20, 24, 32]
    };
    let mut largest_cheaper = 0;
    let mut at_threshold = f64::NAN;
    for &k in counts {
        let (ms, _) = rows_ms(&config, &spread(k), repeats);
        if ms <= table_ms {
            largest_cheaper = largest_cheaper.max(k);
        }
        if k == MAX_PLANNED_ROWS {
            at_threshold = ms / table_ms;
        }
        t.push(vec![
            "-".into(),
            k.to_string(),
            format!("{ms:.3}"),
            format!("{table_ms:.3}"),
            format!("{:.2}", ms / table_ms),
            "-".into(),
            "-".into(),
        ]);
    }
    let plan = Plan::new(&scene, config, DrawOptions::default());
    // What re-planning costs a frame when nothing changed (the viewer plans every redraw):
    // the median ms of 1,000 plans, which is the us of one.
    let (plan_ms, _) = median_ms(repeats, || {
        (0..1000)
            .map(|_| {
                Plan::new(&scene, config, DrawOptions::default())
                    .rows()
                    .len()
            })
            .sum::<usize>()
    });
    let roughness = plan.rows().to_vec();
    let (scene_ms, rows) = rows_ms(&config, &roughness, repeats);
    let (rows_max, rows_mean) =
        read_error(&|mu, r| 1.0 - rows.lut_loss(mu, r), &config, &roughness);
    let (full_max, full_mean) = read_error(&|mu, r| full.lut_e(mu, r), &config, &roughness);
    t.push(vec![
        "default scene: its rows".into(),
        roughness.len().to_string(),
        format!("{scene_ms:.3}"),
        format!("{table_ms:.3}"),
        format!("{:.2}", scene_ms / table_ms),
        sci(rows_max),
        sci(rows_mean),
    ]);
    t.push(vec![
        "default scene: the 64x64 table".into(),
        "-".into(),
        format!("{table_ms:.3}"),
        format!("{table_ms:.3}"),
        "1.00".into(),
        sci(full_max),
        sci(full_mean),
    ]);
    t.note = format!(
        "Medians of {repeats} bakes each, rows from nothing (no cache), rayon on every core. Errors against the precise reference at the scene's roughness values: max on the probe's grid (mu = i/64, `shadeballs probe`), mean at 400 random mu. Largest k measured whose rows bake no slower than the table: {largest_cheaper}; the plan's threshold MAX_PLANNED_ROWS = {MAX_PLANNED_ROWS}. Planning the default scene (`Plan::new`, what the renderer redoes every frame): {:.2} us.",
        plan_ms
    );
    let goals = vec![
        Goal {
            what: "default scene, planned: read error of the probe at the scene's roughness <= 2e-4; bake no slower than the full-table default".into(),
            figure: format!(
                "max {} (table {}), mean {} (table {}); bake {scene_ms:.3} ms against {table_ms:.3} ms ({:.2}x)",
                sci(rows_max),
                sci(full_max),
                sci(rows_mean),
                sci(full_mean),
                scene_ms / table_ms
            ),
            met: rows_max <= 2e-4 && scene_ms <= table_ms,
        },
        Goal {
            what: format!("threshold: {MAX_PLANNED_ROWS} rows bake no slower than the table"),
            figure: format!("{at_threshold:.2}x the table's time; largest k no slower: {largest_cheaper}"),
            met: at_threshold <= 1.0,
        },
    ];
    Sweep {
        tables: vec![t],
        plots: Vec::new(),
        goals,
    }
}

/// The default 2-D table and the default scene's own rows, read at the scene's roughness
/// values and `n` random mu spread over them: two table rows.
pub fn per_scene_rows(geometry: Geometry, n: usize) -> (Vec<String>, Vec<String>) {
    let config = BakeConfig {
        geometry,
        ..BakeConfig::default()
    };
    let plan = Plan::new(&Scene::reference(), config, DrawOptions::default());
    let roughness = plan.rows().to_vec();
    let rows = RowSet::bake(&config, &roughness);
    let full = lut::bake(&config);
    let points: Vec<(f64, f64)> = random_points(n, 2017)
        .iter()
        .enumerate()
        .map(|(k, p)| (p.0, roughness[k % roughness.len()] as f64))
        .collect();
    let reference = ReferencePoints::new(points, geometry);
    let e_full = reference.read_error(&full);
    let e_rows = ErrorStats::from_errors(reference.points.iter().zip(&reference.e).map(
        |(&(mu, r), &exact)| {
            let e = (1.0 - rows.lut_loss(mu as f32, r as f32)) as f64;
            ((e - exact).abs(), mu, r)
        },
    ));
    let l = config.layout;
    let cell = |label: &str, size: String, bytes: usize, e: &ErrorStats| {
        vec![
            label.to_string(),
            l.kind.to_string(),
            size,
            l.storage.to_string(),
            bytes.to_string(),
            sci(e.max),
            sci(e.mean),
            "-".into(),
        ]
    };
    let k = roughness.len();
    (
        cell(
            "default table at the scene's roughness",
            format!("{}x{}", l.mu_size, l.r_size),
            l.bytes(),
            &e_full,
        ),
        cell(
            "per-scene rows",
            format!("{}x{k}", l.mu_size),
            (l.mu_size + 1) * k * l.storage.bytes_per_texel(),
            &e_rows,
        ),
    )
}
