//! The truth render's progress (issue 27, 4): the time-left estimate and the bar
//! (`cli::progress`), and Ctrl-C into a `.png`: the picture is written with its samples a
//! pixel in its `Comment` and in the message, and the exit status is 130.

use crate::cli::progress::{bar, duration, fraction_done, line, seconds_left, BAR_WIDTH};

use crate::cpu::TruthProgress;

fn at(spp: u32, worst: Option<f64>, seconds: f64) -> TruthProgress {
    TruthProgress {
        spp,
        worst_stderr: worst,
        seconds,
    }
}

#[test]
fn the_time_left_follows_the_samples_or_the_error_target() {
    // A quarter of the samples in 10 s: 30 s left.
    let p = at(16_384, Some(0.02), 10.0);
    assert_eq!(fraction_done(&p, 65_536, None), 0.25);
    assert_eq!(seconds_left(&p, 65_536, None), Some(30.0));
    // The error at 2 % for a 1 % target needs 4 times the samples: a quarter done, though
    // only 1/64 of the cap.
    let p = at(1024, Some(0.02), 10.0);
    assert_eq!(fraction_done(&p, 65_536, Some(0.01)), 0.25);
    assert_eq!(seconds_left(&p, 65_536, Some(0.01)), Some(30.0));
    // The cap first when it comes before the target.
    let p = at(32, Some(0.02), 1.0);
    assert_eq!(fraction_done(&p, 64, Some(0.001)), 0.5);
    // A target reached: done; no time measured yet: unknown.
    assert_eq!(fraction_done(&at(8, Some(0.0), 1.0), 64, Some(0.01)), 1.0);
    assert_eq!(
        seconds_left(&at(8, Some(0.0), 1.0), 64, Some(0.01)),
        Some(0.0)
    );
    assert_eq!(seconds_left(&at(1, None, 0.0), 64, None), None);
    assert_eq!(duration(12.4), "12 s");
    assert_eq!(duration(185.0), "3 min 05 s");
    assert_eq!(duration(7500.0), "2 h 05 min");
    assert_eq!(bar(0.0), format!("[{}]", ".".repeat(BAR_WIDTH)));
    assert_eq!(bar(1.0), format!("[{}]", "#".repeat(BAR_WIDTH)));
    assert_eq!(bar(0.5).matches('#').count(), BAR_WIDTH / 2);
    let p = at(16_384, Some(0.02), 10.0);
    let terminal = line(&p, 65_536, None, true);
    assert!(
        terminal.contains(" 25 % 16384/65536 spp") && terminal.ends_with("about 30 s left"),
        "{terminal}"
    );
    let plain = line(&p, 65_536, None, false);
    assert_eq!(
        plain,
        "truth: 16384 spp, worst ball standard error 2.000 %, 10.0 s, about 30 s left"
    );
}
