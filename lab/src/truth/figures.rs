//! The study's PNG figures: albedo against mu and roughness, albedo error, lobe slices.
//! Colours (also in docs/truth.md): walk black, none grey (dashed), accurate green, games202
//! red, Turquin blue, Fdez-Aguera orange.

use super::albedo::{Cell, FresnelKind};
use super::compare::{Comparison, MODELS};
use super::lobes::{LobePoint, Slice};
use crate::plot::{Figure, Panel, Series, Style};

const WALK: [u8; 3] = [0, 0, 0];
/// The walk's two-standard-error band.
const SIGMA: [u8; 3] = [120, 120, 120];
/// Colours of [`MODELS`], in order.
const COLOURS: [[u8; 3]; 5] = [
    [150, 150, 150],
    [0, 150, 60],
    [215, 40, 40],
    [40, 90, 220],
    [240, 140, 0],
];

fn series(label: &str, color: [u8; 3], dashed: bool, points: Vec<(f64, f64)>) -> Series {
    Series {
        label: label.into(),
        points,
        colour: Some(color),
        style: if dashed { Style::Dashed } else { Style::Line },
    }
}

/// The values of `wanted` nearest to ones in `have`, without repeats.
fn nearest(have: &[f64], wanted: &[f64]) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    for &w in wanted {
        if let Some(&v) = have
            .iter()
            .min_by(|a, b| (*a - w).abs().total_cmp(&(*b - w).abs()))
        {
            if !out.contains(&v) {
                out.push(v);
            }
        }
    }
    out
}

/// The Schlick (or white) channels of `material`.
fn channel_ids(cmp: &Comparison, material: &str) -> Vec<usize> {
    cmp.channel_ids(FresnelKind::Schlick, Some(material))
        .into_iter()
        .filter(|&k| cmp.channels[k].material == material)
        .collect()
}

/// Albedo of each model (and the walk, or errors against it) along the cells selected by
/// `on_curve`, against `x(cell)`.
fn albedo_panel(
    cmp: &Comparison,
    k: usize,
    on_curve: impl Fn(&Cell) -> bool,
    x: impl Fn(&Cell) -> f64,
    errors: bool,
) -> Vec<Series> {
    let cells: Vec<&Cell> = cmp.cells.iter().filter(|c| on_curve(c)).collect();
    let mut out = Vec::new();
    if !errors {
        out.push(series(
            "walk",
            WALK,
            false,
            cells.iter().map(|c| (x(c), c.truth(k))).collect(),
        ));
    }
    for (m, name) in MODELS.iter().enumerate() {
        let pts = cells
            .iter()
            .map(|c| {
                let v = cmp.models(c, k)[m];
                (x(c), if errors { v - c.truth(k) } else { v })
            })
            .collect();
        out.push(series(name, COLOURS[m], m == 0, pts));
    }
    out
}

/// Albedo figures of one material: (file stem, figure) for against-mu, against-roughness
/// and error-against-mu.
pub fn albedo_figures(
    cmp: &Comparison,
    material: &str,
    roughness: &[f64],
    mu: &[f64],
) -> Vec<(String, Figure)> {
    let ids = channel_ids(cmp, material);
    let rs = nearest(roughness, &[0.2, 0.6, 1.0]);
    let mus = nearest(mu, &[0.05, 0.5, 1.0]);
    let mut figs = Vec::new();
    for (stem, errors) in [("albedo_vs_mu", false), ("albedo_error", true)] {
        let mut panels = Vec::new();
        for &k in &ids {
            for &r in &rs {
                panels.push(Panel {
                    title: format!("{} {} r={r}", material, cmp.channels[k].name()),
                    x_label: "mu".into(),
                    series: albedo_panel(cmp, k, |c| c.roughness == r, |c| c.mu, errors),
                    with_zero: errors,
                });
            }
        }
        let what = if errors {
            "Directional albedo, model minus walk"
        } else {
            "Directional albedo"
        };
        let title = format!("{what}, {material}, against mu");
        figs.push((
            format!("{stem}_{material}"),
            Figure {
                title,
                cols: rs.len(),
                panels,
            },
        ));
    }
    let mut panels = Vec::new();
    for &k in &ids {
        for &m in &mus {
            panels.push(Panel {
                title: format!("{} {} mu={m}", material, cmp.channels[k].name()),
                x_label: "roughness".into(),
                series: albedo_panel(cmp, k, |c| c.mu == m, |c| c.roughness, false),
                with_zero: false,
            });
        }
    }
    let title = format!("Directional albedo, {material}, against roughness");
    figs.push((
        format!("albedo_vs_roughness_{material}"),
        Figure {
            title,
            cols: mus.len(),
            panels,
        },
    ));
    figs
}

/// Lobe slices of one material (rows: roughness x channel, columns: incident angle); with
/// `ms_only`, the multiple-scattering parts alone.
pub fn lobe_figure(
    cmp: &Comparison,
    slices: &[Slice],
    theta_o: &[f64],
    material: &str,
    ms_only: bool,
) -> Figure {
    let ids = channel_ids(cmp, material);
    let mut rs: Vec<f64> = slices.iter().map(|s| s.roughness).collect();
    rs.dedup();
    let cols = slices.len() / rs.len().max(1);
    let mut panels = Vec::new();
    for &r in &rs {
        for &k in &ids {
            for s in slices.iter().filter(|s| s.roughness == r) {
                let curve = |v: &dyn Fn(&LobePoint) -> f64| -> Vec<(f64, f64)> {
                    theta_o
                        .iter()
                        .zip(&s.points)
                        .map(|(&t, row)| (t, v(&row[k])))
                        .collect()
                };
                let series_list = if ms_only {
                    vec![
                        series("walk", WALK, false, curve(&|p| p.truth_ms)),
                        series(
                            "walk ± 2σ",
                            SIGMA,
                            true,
                            curve(&|p| p.truth_ms + 2.0 * p.truth_stderr),
                        ),
                        series(
                            "walk ± 2σ",
                            SIGMA,
                            true,
                            curve(&|p| p.truth_ms - 2.0 * p.truth_stderr),
                        ),
                        series("accurate", COLOURS[1], false, curve(&|p| p.accurate_ms)),
                        series("games202", COLOURS[2], false, curve(&|p| p.games202_ms)),
                    ]
                } else {
                    vec![
                        series("walk", WALK, false, curve(&|p| p.truth)),
                        series("none", COLOURS[0], true, curve(&|p| p.none)),
                        series("accurate", COLOURS[1], false, curve(&|p| p.accurate)),
                        series("games202", COLOURS[2], false, curve(&|p| p.games202)),
                        series("turquin", COLOURS[3], false, curve(&|p| p.turquin)),
                    ]
                };
                panels.push(Panel {
                    title: format!(
                        "{} {} r={r} theta_i={}",
                        material,
                        cmp.channels[k].name(),
                        s.theta_i
                    ),
                    x_label: "theta_o (deg)".into(),
                    series: series_list,
                    with_zero: true,
                });
            }
        }
    }
    let what = if ms_only {
        "Multiple-scattering part of the BRDF"
    } else {
        "BRDF"
    };
    Figure {
        title: format!("{what} in the plane of incidence, {material}"),
        cols: cols.max(1),
        panels,
    }
}
