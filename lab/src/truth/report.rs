//! The study's tables: CSV files and the markdown summary.

use std::fmt::Write as _;

use super::albedo::{Channel, FresnelKind};
use super::compare::{ablation_variants, Comparison, MODELS};
use super::models::{FAvgSource, KcParts};
use super::Study;
use shadeballs::brdf::{f_avg_games202, f_avg_schlick, FAvgForm, Geometry};

/// A CSV document built row by row.
pub struct Csv(pub String);

impl Csv {
    pub fn new(header: &[&str]) -> Self {
        Csv(header.join(",") + "\n")
    }
    pub fn row(&mut self, cells: &[String]) {
        self.0.push_str(&cells.join(","));
        self.0.push('\n');
    }
}

fn f(v: f64) -> String {
    format!("{v:.6}")
}

const MATERIALS: [&str; 3] = ["white", "copper", "gold"];

/// `albedo.csv`: every Schlick (and white) channel, every cell, every model.
pub fn albedo_csv(cmp: &Comparison) -> Csv {
    let mut header = vec![
        "material",
        "channel",
        "roughness",
        "mu",
        "truth",
        "truth_stderr",
    ];
    header.extend(MODELS.iter().map(|m| m.trim()));
    let mut csv = Csv::new(&header);
    for cell in cmp.cells {
        for k in cmp.channel_ids(FresnelKind::Schlick, None) {
            let c = &cmp.channels[k];
            let mut row = vec![
                c.material.into(),
                c.name().into(),
                f(cell.roughness),
                f(cell.mu),
            ];
            row.push(f(cell.truth(k)));
            row.push(format!("{:.2e}", cell.truth_stderr(k)));
            row.extend(cmp.models(cell, k).iter().map(|&v| f(v)));
            csv.row(&row);
        }
    }
    csv
}

/// The conductor study's Kulla-Conty variants: height-correlated G, the squared form, and
/// each source of F_avg.
pub fn conductor_variants() -> [KcParts; 3] {
    [
        FAvgSource::Own,
        FAvgSource::ConductorFit,
        FAvgSource::SchlickF0,
    ]
    .map(|f_avg| KcParts {
        geometry: Geometry::SmithCorrelated,
        f_avg,
        form: FAvgForm::Accurate,
    })
}

/// The Schlick channel of the same material and colour as conductor channel `k`.
fn schlick_twin(channels: &[Channel], k: usize) -> usize {
    let c = &channels[k];
    channels
        .iter()
        .position(|o| {
            o.kind == FresnelKind::Schlick && o.material == c.material && o.index == c.index
        })
        .unwrap_or(k)
}

/// `albedo_conductor.csv`: the walk with the full conductor Fresnel against Kulla-Conty
/// with that Fresnel in `f_micro` and three sources of F_avg.
pub fn conductor_csv(cmp: &Comparison) -> Csv {
    let mut csv = Csv::new(&[
        "material",
        "channel",
        "roughness",
        "mu",
        "truth",
        "truth_stderr",
        "truth_schlick",
        "none",
        "kc_own_average",
        "kc_conductor_fit",
        "kc_schlick_f0",
    ]);
    for cell in cmp.cells {
        for k in cmp.channel_ids(FresnelKind::Conductor, None) {
            let c = &cmp.channels[k];
            if c.kind == FresnelKind::White {
                continue;
            }
            let mut row = vec![
                c.material.into(),
                c.name().into(),
                f(cell.roughness),
                f(cell.mu),
            ];
            row.push(f(cell.truth(k)));
            row.push(format!("{:.2e}", cell.truth_stderr(k)));
            row.push(f(cell.truth(schlick_twin(cmp.channels, k))));
            row.push(f(cell.single_of(Geometry::SmithCorrelated, k)));
            row.extend(conductor_variants().iter().map(|&v| f(cmp.kc(cell, k, v))));
            csv.row(&row);
        }
    }
    csv
}

/// Largest error per material and over all, for `value`, on channels of `kind`.
fn errors_by_material(
    cmp: &Comparison,
    kind: FresnelKind,
    value: impl Fn(&super::albedo::Cell, usize) -> f64 + Copy,
) -> ([f64; 3], (f64, usize, usize)) {
    let per = MATERIALS.map(|m| {
        let ids: Vec<usize> = cmp
            .channel_ids(kind, Some(m))
            .into_iter()
            .filter(|&k| cmp.channels[k].material == m)
            .collect();
        cmp.max_error(&ids, value).0
    });
    let all = cmp.max_error(&cmp.channel_ids(kind, None), value);
    (per, all)
}

fn sci(v: f64) -> String {
    format!("{v:.2e}")
}

/// Mean absolute error over every cell and the channels `ids`.
fn mean_error(
    cmp: &Comparison,
    ids: &[usize],
    value: impl Fn(&super::albedo::Cell, usize) -> f64,
) -> f64 {
    let mut sum = 0.0;
    for cell in cmp.cells {
        for &k in ids {
            sum += (value(cell, k) - cell.truth(k)).abs();
        }
    }
    sum / (cmp.cells.len() * ids.len()).max(1) as f64
}

/// The headline: every model's largest albedo error against the walk (Schlick Fresnel).
/// Returns the markdown and `(accurate, games202)` maxima.
pub fn headline(cmp: &Comparison) -> (String, f64, f64) {
    let mut md = String::from(
        "| model | white | copper | gold | all | where (all) | mean (all) |\n|---|---|---|---|---|---|---|\n",
    );
    let ids = cmp.channel_ids(FresnelKind::Schlick, None);
    let mut maxima = [0.0; 5];
    for (m, name) in MODELS.iter().enumerate() {
        let value = |c: &super::albedo::Cell, k: usize| cmp.models(c, k)[m];
        let (per, (all, n, k)) = errors_by_material(cmp, FresnelKind::Schlick, value);
        maxima[m] = all;
        let (cell, ch) = (&cmp.cells[n], &cmp.channels[k]);
        let _ = writeln!(
            md,
            "| {name} | {} | {} | {} | **{}** | {} {}, roughness {}, mu {} | {} |",
            sci(per[0]),
            sci(per[1]),
            sci(per[2]),
            sci(all),
            ch.material,
            ch.name(),
            cell.roughness,
            cell.mu,
            sci(mean_error(cmp, &ids, value)),
        );
    }
    (md, maxima[1], maxima[2])
}

/// Largest error of each model per roughness (all Schlick channels).
pub fn by_roughness(cmp: &Comparison, roughness: &[f64]) -> String {
    let mut md = String::from("| model |");
    let mut rule = String::from("|---|");
    for r in roughness {
        let _ = write!(md, " {r} |");
        rule.push_str("---|");
    }
    md = md + "\n" + &rule + "\n";
    let ids = cmp.channel_ids(FresnelKind::Schlick, None);
    for (m, name) in MODELS.iter().enumerate() {
        let _ = write!(md, "| {name} |");
        for &r in roughness {
            let value = |c: &super::albedo::Cell, k: usize| {
                if c.roughness == r {
                    cmp.models(c, k)[m]
                } else {
                    c.truth(k)
                }
            };
            let _ = write!(md, " {} |", sci(cmp.max_error(&ids, value).0));
        }
        md.push('\n');
    }
    md
}

/// The ablation over the Kulla-Conty parts (Schlick Fresnel), as CSV and markdown.
pub fn ablation(cmp: &Comparison) -> (Csv, String) {
    let mut csv = Csv::new(&[
        "geometry", "f_avg", "form", "white", "copper", "gold", "all", "mean_all",
    ]);
    let mut md = String::from(
        "| G | F_avg | f_add form | white | copper | gold | all | mean (all) |\n|---|---|---|---|---|---|---|---|\n",
    );
    let ids = cmp.channel_ids(FresnelKind::Schlick, None);
    for v in ablation_variants() {
        let value = |c: &super::albedo::Cell, k: usize| cmp.kc(c, k, v);
        let (per, (all, _, _)) = errors_by_material(cmp, FresnelKind::Schlick, value);
        let mean = mean_error(cmp, &ids, value);
        let form = match v.form {
            FAvgForm::Accurate => "squared",
            FAvgForm::Games202 => "unsquared",
        };
        let cells = [
            v.geometry.name().into(),
            v.f_avg.name().into(),
            form.to_string(),
        ];
        let mut row = cells.to_vec();
        row.extend([per[0], per[1], per[2], all, mean].map(sci));
        csv.row(&row);
        let _ = writeln!(md, "| {} |", row.join(" | "));
    }
    (csv, md)
}

/// The conductor section: F_avg values and the variants' largest errors.
pub fn conductor_summary(study: &Study, cmp: &Comparison) -> String {
    let mut md = String::from(
        "| metal | channel | r | edge tint | F_avg exact | K-C fit | Schlick(r) |\n|---|---|---|---|---|---|---|\n",
    );
    for c in study
        .channels
        .iter()
        .filter(|c| c.kind == FresnelKind::Conductor)
    {
        let d = &c.data;
        let _ = writeln!(
            md,
            "| {} | {} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} |",
            c.material,
            c.name(),
            d.f0,
            d.edge_tint,
            d.f_avg,
            f_avg_games202(d.f0, d.edge_tint),
            f_avg_schlick(d.f0)
        );
    }
    md.push_str("\n| model (conductor Fresnel in the walk and in f_micro) | copper | gold | all |\n|---|---|---|---|\n");
    let metals = |value: &dyn Fn(&super::albedo::Cell, usize) -> f64| {
        let ids = |m: Option<&str>| -> Vec<usize> {
            cmp.channel_ids(FresnelKind::Conductor, m)
                .into_iter()
                .filter(|&k| cmp.channels[k].kind == FresnelKind::Conductor)
                .collect()
        };
        [Some("copper"), Some("gold"), None].map(|m| sci(cmp.max_error(&ids(m), value).0))
    };
    let none = metals(&|c, k| c.single_of(Geometry::SmithCorrelated, k));
    let _ = writeln!(md, "| none | {} |", none.join(" | "));
    for v in conductor_variants() {
        let e = metals(&|c, k| cmp.kc(c, k, v));
        let _ = writeln!(
            md,
            "| Kulla-Conty, F_avg {} | {} |",
            v.f_avg.name(),
            e.join(" | ")
        );
    }
    let e = metals(&|c, k| c.truth(schlick_twin(cmp.channels, k)));
    let _ = writeln!(
        md,
        "| the Schlick walk (same r), as a model of the conductor walk | {} |",
        e.join(" | ")
    );
    md
}
