//! Reading: what the shader's read of the tables returns against the precise reference,
//! against memory (CPU model of the read, every layout, size and storage) and against
//! lookup cost on the GPU (manual bilinear against hardware filtering).

use super::bake::{homework_config, HOMEWORK};
use super::lookup::{self, Filter};
use super::table::{sci, Table};
use super::Sweep;
use crate::plot::{Plot, Series, Style};
use shadeballs::brdf::Geometry;
use shadeballs::error::Result;
use shadeballs::gpu::Gpu;
use shadeballs::lut::accuracy::{random_points, ErrorStats, ReferencePoints};
use shadeballs::lut::{self, BakeConfig, Layout, LayoutKind, Storage, Tables};

/// Max and mean read error of E at `points`, max of E_avg at `rough`.
fn read_errors(
    tables: &Tables,
    points: &ReferencePoints,
    rough: &[(f64, f64)],
) -> (ErrorStats, f64) {
    let e = points.read_error(tables);
    let avg = rough
        .iter()
        .map(|&(r, exact)| (tables.lut_e_avg(r as f32) as f64 - exact).abs())
        .fold(0.0, f64::max);
    (e, avg)
}

/// Every layout, size and storage: read-path error at random `(mu, roughness)` against
/// memory. Tables are baked with the default method, so the error is the layout's own,
/// except the homework row (its own bake).
pub fn read_sweep(quick: bool) -> Sweep {
    let mut t = Table::new(
        "read",
        "Reading: read-path error of the shader's bilinear read against memory (schlick G, CPU model of the read)",
        &["config", "layout", "size", "storage", "bytes", "e_max", "e_mean", "e_avg_max"],
    );
    let n = if quick { 2_000 } else { 20_000 };
    let geometry = Geometry::Schlick;
    let points = ReferencePoints::new(random_points(n, 2017), geometry);
    let rough: Vec<(f64, f64)> = random_points(if quick { 50 } else { 200 }, 7)
        .iter()
        .map(|p| (p.1, lut::e_avg_reference(p.1, geometry)))
        .collect();
    let mut configs = vec![(HOMEWORK.to_string(), homework_config(geometry))];
    let mut layouts = vec![
        Layout::of_kind(LayoutKind::Games202),
        Layout::of_kind(LayoutKind::Games202).with_storage(Storage::F32),
    ];
    let sizes: &[usize] = if quick {
        &[32, 64]
    } else {
        &[16, 32, 48, 64, 96, 128]
    };
    for &s in sizes {
        layouts.push(Layout::default().with_size(s, s));
    }
    for &s in if quick { &[64][..] } else { &[32, 64, 128][..] } {
        layouts.push(Layout::of_kind(LayoutKind::SqrtMu).with_size(s, s));
    }
    for storage in [Storage::F16, Storage::Unorm8] {
        layouts.push(Layout::default().with_storage(storage));
    }
    for layout in layouts {
        let label = if layout == Layout::default() {
            "default"
        } else {
            "-"
        };
        configs.push((
            label.to_string(),
            BakeConfig {
                geometry,
                layout,
                ..BakeConfig::default()
            },
        ));
    }
    let mut series: Vec<Series> = Vec::new();
    for (label, config) in configs {
        let tables = lut::bake(&config);
        let (e, avg) = read_errors(&tables, &points, &rough);
        let layout = config.layout;
        t.push(vec![
            label.clone(),
            layout.kind.to_string(),
            format!("{}x{}", layout.mu_size, layout.r_size),
            layout.storage.to_string(),
            layout.bytes().to_string(),
            sci(e.max),
            sci(e.mean),
            sci(avg),
        ]);
        let name = if label == HOMEWORK {
            "homework".to_string()
        } else {
            format!("{} {}", layout.kind, layout.storage)
        };
        let point = (layout.bytes() as f64, e.max);
        match series.iter_mut().find(|s| s.label == name) {
            Some(s) => s.points.push(point),
            None => series.push(Series {
                label: name,
                points: vec![point],
                style: if label == HOMEWORK {
                    Style::Peer
                } else {
                    Style::Marked
                },
                ..Default::default()
            }),
        }
    }
    let (full_row, rows_row) = super::plan::per_scene_rows(geometry, n);
    t.push(full_row);
    t.push(rows_row);
    t.note = format!("{n} uniformly random (mu, roughness) in [0, 1]^2 (seed 2017); goal (issue 2): max <= 1e-3, mean <= 1e-4. The last two rows read only at the default scene's five roughness values ({n} random mu in all): the default 2-D table there, and the scene's own rows (one exact row per roughness, `lut::rows`; what the planned renderer reads); bytes: the E values and one E_avg each.");
    let plot = Plot {
        title: "Read: memory against max read error (schlick G)".into(),
        x_label: "GPU memory of E and E_avg (bytes)".into(),
        y_label: "max |E_read - E_ref|".into(),
        series,
        goals: vec![("1e-3".into(), None, Some(1e-3))],
    };
    Sweep {
        tables: vec![t],
        plots: vec![("read".into(), plot)],
        goals: Vec::new(),
    }
}

/// On the GPU: cost per read and error of the values read, manual bilinear (the renderer's
/// read) against hardware filtering, per layout and storage.
pub fn lookup_sweep(gpu: &Gpu, quick: bool) -> Result<Sweep> {
    let mut t = Table::new(
        "lookup",
        "Reading on the GPU: cost of one read in a compute shader against its error (schlick G)",
        &[
            "config",
            "layout",
            "size",
            "storage",
            "filter",
            "bytes",
            "ns_per_read",
            "e_max",
            "e_mean",
        ],
    );
    let (reads, repeats, n_points) = if quick {
        (16, 5, 4096)
    } else {
        (64, 11, 32768)
    };
    let geometry = Geometry::Schlick;
    let reference = ReferencePoints::new(lookup::shader_points(n_points), geometry);
    let default = |storage| BakeConfig {
        layout: Layout::default().with_storage(storage),
        ..BakeConfig::default()
    };
    let games202 = Layout::of_kind(LayoutKind::Games202);
    let mut runs: Vec<(String, BakeConfig, Filter)> = vec![
        (
            HOMEWORK.to_string(),
            homework_config(geometry),
            Filter::Hardware,
        ),
        ("-".into(), default(Storage::F32), Filter::None),
        ("default".into(), default(Storage::F32), Filter::Manual),
    ];
    for storage in Storage::ALL {
        runs.push(("-".into(), default(storage), Filter::Hardware));
    }
    if !quick {
        for storage in [Storage::F16, Storage::Unorm8] {
            runs.push(("-".into(), default(storage), Filter::Manual));
        }
        let accurate_202 = BakeConfig {
            layout: games202,
            ..BakeConfig::default()
        };
        runs.push(("-".into(), accurate_202, Filter::Hardware));
        runs.push(("-".into(), accurate_202, Filter::Manual));
    }
    let mut series: Vec<Series> = Vec::new();
    for (label, config, filter) in runs {
        if filter == Filter::Hardware && !super::device::filterable(gpu, config.layout.storage) {
            t.push(vec![
                label,
                config.layout.kind.to_string(),
                format!("{}x{}", config.layout.mu_size, config.layout.r_size),
                config.layout.storage.to_string(),
                "hardware (not filterable here)".into(),
                (config.layout.texels() * config.layout.storage.bytes_per_texel()).to_string(),
                "-".into(),
                "-".into(),
                "-".into(),
            ]);
            continue;
        }
        let tables = lut::bake(&config);
        let bytes = lookup::texture_bytes(&tables, filter);
        let m = lookup::measure(gpu, &tables, filter, reads, repeats, &reference)?;
        let (e_max, e_mean) = m
            .error
            .map_or(("-".into(), "-".into()), |e| (sci(e.max), sci(e.mean)));
        let l = config.layout;
        t.push(vec![
            label.clone(),
            l.kind.to_string(),
            format!("{}x{}", l.mu_size, l.r_size),
            l.storage.to_string(),
            filter.name().into(),
            bytes.to_string(),
            format!("{:.3}", m.ns_per_read),
            e_max,
            e_mean,
        ]);
        if let Some(e) = m.error {
            let name = if label == HOMEWORK {
                "homework (hardware, unorm8)".to_string()
            } else {
                format!("{} {} {}", l.kind, l.storage, filter.name())
            };
            let point = (m.ns_per_read, e.max);
            match series.iter_mut().find(|s| s.label == name) {
                Some(s) => s.points.push(point),
                None => series.push(Series {
                    label: name,
                    points: vec![point],
                    style: if label == HOMEWORK {
                        Style::Peer
                    } else {
                        Style::Points
                    },
                    ..Default::default()
                }),
            }
        }
    }
    t.note = format!(
        "{} on {}: median wall time of a dispatch of {} invocations x {reads} reads at hashed (mu, roughness), per read ({repeats} runs); the 'none' row is the loop without the read. Bytes: the E texture the read fetches from (manual: the renderer's 2x2 blocks, 16 bytes a texel, values quantised to the storage; hardware: the storage format). Errors: {n_points} reads read back, against the precise reference.",
        if quick { "Quick" } else { "Full" },
        gpu.describe(),
        lookup::INVOCATIONS
    );
    let plot = Plot {
        title: "GPU read: cost against max error (schlick G)".into(),
        x_label: "wall time per read (ns, whole dispatch / reads)".into(),
        y_label: "max |E_read - E_ref|".into(),
        series,
        goals: Vec::new(),
    };
    Ok(Sweep {
        tables: vec![t],
        plots: vec![("lookup".into(), plot)],
        goals: Vec::new(),
    })
}
