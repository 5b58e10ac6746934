//! The truth render's progress on stderr (`render --backend truth`): on a terminal a bar
//! with the time left, redrawn in place after each pass; elsewhere (a pipe, a log) one line
//! a pass, the curve of the error against time (docs/truth.md).

use crate::cpu::TruthProgress;

/// Characters of the bar between its brackets.
pub(crate) const BAR_WIDTH: usize = 24;

/// The fraction of the render done after `p`: the larger of the samples done against the
/// cap `spp` and, with a `target` standard error, of the samples the target needs (the
/// error falls as `1 / sqrt(spp)`, so it needs `spp (worst / target)^2`). In `[0, 1]`.
pub(crate) fn fraction_done(p: &TruthProgress, spp: u32, target: Option<f64>) -> f64 {
    let by_count = f64::from(p.spp) / f64::from(spp.max(1));
    let by_error = match (target, p.worst_stderr) {
        // A worst error of 0 (every ball black and noiseless) has reached any target.
        (Some(t), Some(w)) if w <= t => 1.0,
        (Some(t), Some(w)) => (t / w).powi(2),
        _ => 0.0,
    };
    by_count.max(by_error).clamp(0.0, 1.0)
}

/// Seconds left after `p` at the rate so far (`None` before any time or work is measured):
/// the render's passes cost the same per sample, so the time left is the time so far times
/// the work left over the work done.
pub(crate) fn seconds_left(p: &TruthProgress, spp: u32, target: Option<f64>) -> Option<f64> {
    let f = fraction_done(p, spp, target);
    (f > 0.0 && p.seconds > 0.0).then(|| p.seconds * (1.0 - f) / f)
}

/// `s` seconds for a person: "12 s", "3 min 05 s", "2 h 05 min".
pub(crate) fn duration(s: f64) -> String {
    let s = s.max(0.0).round() as u64;
    match s {
        0..60 => format!("{s} s"),
        60..3600 => format!("{} min {:02} s", s / 60, s % 60),
        _ => format!("{} h {:02} min", s / 3600, (s % 3600) / 60),
    }
}

/// `[####....]` filled to `fraction` of [`BAR_WIDTH`].
pub(crate) fn bar(fraction: f64) -> String {
    let filled = ((fraction.clamp(0.0, 1.0) * BAR_WIDTH as f64).round() as usize).min(BAR_WIDTH);
    format!("[{}{}]", "#".repeat(filled), ".".repeat(BAR_WIDTH - filled))
}

/// The line after pass `p` of a render capped at `spp` with an optional `target` error: a
/// bar for a `terminal`, else the pass's figures; both with the time left.
pub fn line(p: &TruthProgress, spp: u32, target: Option<f64>, terminal: bool) -> String {
    let worst = p
        .worst_stderr
        .map_or("n/a".to_string(), |s| format!("{:.3} %", 100.0 * s));
    let left = seconds_left(p, spp, target).map_or("time left unknown".to_string(), |s| {
        format!("about {} left", duration(s))
    });
    if terminal {
        let goal = target.map_or(String::new(), |t| format!(" (target {:.3} %)", 100.0 * t));
        let f = fraction_done(p, spp, target);
        format!(
            "truth {} {:3.0} % {}/{spp} spp, worst {worst}{goal}, {:.1} s, {left}",
            bar(f),
            100.0 * f,
            p.spp,
            p.seconds
        )
    } else {
        format!(
            "truth: {} spp, worst ball standard error {worst}, {:.1} s, {left}",
            p.spp, p.seconds
        )
    }
}

/// The render's last line: the samples a pixel, the worst ball's error and the time taken.
pub(crate) fn summary(p: &TruthProgress) -> String {
    let worst = p
        .worst_stderr
        .map_or("n/a".to_string(), |s| format!("{:.3} %", 100.0 * s));
    format!(
        "truth: {} spp, worst ball standard error {worst}, {:.1} s",
        p.spp, p.seconds
    )
}

// Tests that need the crate's internals (moved from the suite); with the command line's
// features only, so `cargo test --no-default-features --lib` runs them once.
#[cfg(all(test, feature = "cli"))]
mod tests;
