//! The lobe study's CSV and summary: where the Kulla-Conty lobe's shape departs from the
//! walk's multiple scattering.

use std::fmt::Write as _;

use super::albedo::{Channel, FresnelKind};
use super::lobes::{LobePoint, Slice};
use super::report::Csv;

fn f(v: f64) -> String {
    format!("{v:.6}")
}

/// `lobes.csv`: every slice, outgoing angle and (white or Schlick) channel.
pub fn lobes_csv(slices: &[Slice], theta_o: &[f64], channels: &[Channel]) -> Csv {
    let mut csv = Csv::new(&[
        "material",
        "channel",
        "roughness",
        "theta_i",
        "theta_o",
        "truth",
        "truth_stderr",
        "truth_ms",
        "none",
        "accurate",
        "accurate_ms",
        "games202",
        "games202_ms",
        "turquin",
    ]);
    for s in slices {
        for (k, c) in channels.iter().enumerate() {
            if c.kind == FresnelKind::Conductor {
                continue;
            }
            for (j, &to) in theta_o.iter().enumerate() {
                let p = &s.points[j][k];
                csv.row(&[
                    c.material.into(),
                    c.name().into(),
                    f(s.roughness),
                    f(s.theta_i),
                    f(to),
                    f(p.truth),
                    format!("{:.2e}", p.truth_stderr),
                    f(p.truth_ms),
                    f(p.none),
                    f(p.accurate),
                    f(p.accurate_ms),
                    f(p.games202),
                    f(p.games202_ms),
                    f(p.turquin),
                ]);
            }
        }
    }
    csv
}

/// `sum |a - b| / sum |b|` over a slice.
fn relative_l1(
    points: &[&LobePoint],
    a: impl Fn(&LobePoint) -> f64,
    b: impl Fn(&LobePoint) -> f64,
) -> f64 {
    let num: f64 = points.iter().map(|p| (a(p) - b(p)).abs()).sum();
    let den: f64 = points.iter().map(|p| b(p).abs()).sum();
    num / den.max(1e-300)
}

/// Per slice, for channel `k`: the multiple-scattering lobes compared (shape and where the
/// walk's peaks), and the whole lobe's error.
pub fn lobes_summary(slices: &[Slice], theta_o: &[f64], channels: &[Channel], k: usize) -> String {
    let c = &channels[k];
    let mut md = format!(
        "Channel: {} {}. Multiple scattering alone (`ms`): the walk's orders >= 2 against the \
         `accurate` preset's `f_add f_ms`; `L1` is `sum |model - walk| / sum walk` over the \
         slice; angles in degrees, positive on the mirror side.\n\n",
        c.material,
        c.name()
    );
    md.push_str(
        "| roughness | theta_i | walk ms at 0 | K-C ms at 0 | walk ms peak (angle) | walk ms at +grazing | K-C ms at +grazing | walk ms at -grazing | K-C ms at -grazing | ms L1, accurate | whole lobe L1, accurate | whole lobe L1, games202 | whole lobe L1, turquin |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let zero = theta_o
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
        .map_or(0, |x| x.0);
    let last = theta_o.len().saturating_sub(1);
    for s in slices {
        let pts: Vec<&LobePoint> = s.points.iter().map(|row| &row[k]).collect();
        let (peak_j, peak) = pts
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.truth_ms.total_cmp(&b.1.truth_ms))
            .map_or((0, 0.0), |(j, p)| (j, p.truth_ms));
        let _ = writeln!(
            md,
            "| {} | {} | {:.4} | {:.4} | {:.4} ({}) | {:.4} | {:.4} | {:.4} | {:.4} | {:.2} | {:.3} | {:.3} | {:.3} |",
            s.roughness,
            s.theta_i,
            pts[zero].truth_ms,
            pts[zero].accurate_ms,
            peak,
            theta_o[peak_j],
            pts[last].truth_ms,
            pts[last].accurate_ms,
            pts[0].truth_ms,
            pts[0].accurate_ms,
            relative_l1(&pts, |p| p.accurate_ms, |p| p.truth_ms),
            relative_l1(&pts, |p| p.accurate, |p| p.truth),
            relative_l1(&pts, |p| p.games202, |p| p.truth),
            relative_l1(&pts, |p| p.turquin, |p| p.truth),
        );
    }
    md
}
