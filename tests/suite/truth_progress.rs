//! The truth render's progress (issue 27, 4): the time-left estimate and the bar
//! (`cli::progress`), and Ctrl-C into a `.png`: the picture is written with its samples a
//! pixel in its `Comment` and in the message, and the exit status is 130.
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use shadeballs::cli::progress::{bar, duration, fraction_done, line, seconds_left, BAR_WIDTH};
use shadeballs::cpu::TruthProgress;

use crate::cli::{interrupt, temp_dir};

fn at(spp: u32, worst: Option<f64>, seconds: f64) -> TruthProgress {
    TruthProgress {
        spp,
        worst_stderr: worst,
        seconds,
    }
}

/// The samples a pixel the message of an interrupted render names ("after N spp").
pub fn interrupted_spp(stderr: &str) -> u32 {
    let tail = stderr
        .split("interrupted by SIGINT after ")
        .nth(1)
        .unwrap_or_else(|| panic!("no interrupted line: {stderr}"));
    let n = tail.split(' ').next().unwrap_or_default();
    let spp: u32 = n.parse().unwrap_or_else(|_| panic!("{n:?} in {stderr}"));
    assert!(
        tail.contains(&format!("holds the {spp} spp rendered so far")),
        "{stderr}"
    );
    spp
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

#[test]
fn ctrl_c_during_a_truth_render_writes_the_png_with_its_samples() {
    let dir = temp_dir("truth_interrupted_png");
    let out = dir.join("truth.png");
    let mut child = Command::new(env!("CARGO_BIN_EXE_shadeballs"))
        .args([
            "render",
            "--backend",
            "truth",
            "--spp",
            "65536",
            "--width",
            "320",
            "--height",
            "180",
            "--out",
            out.to_str().unwrap(),
        ])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(700));
    assert!(child.try_wait().unwrap().is_none(), "finished early");
    let start = Instant::now();
    let stderr = interrupt(child, "INT", 130);
    // 30 s: a pass of 16 estimates a pixel at 320x180 takes well under a second here.
    assert!(start.elapsed() < Duration::from_secs(30));
    assert!(stderr.contains("stopping after this pass"), "{stderr}");
    // Off a terminal, a line a pass, each with the time left.
    assert!(
        stderr.contains("truth: 1 spp,") && stderr.contains(" left\n"),
        "{stderr}"
    );
    let spp = interrupted_spp(&stderr);
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&out).unwrap()));
    let reader = decoder.read_info().unwrap();
    let info = reader.info();
    assert_eq!((info.width, info.height), (320, 180));
    let comment = info
        .uncompressed_latin1_text
        .iter()
        .find(|t| t.keyword == "Comment")
        .map(|t| t.text.clone())
        .unwrap_or_default();
    assert_eq!(
        comment,
        format!("shadeballs truth (random walk): {spp} spp, interrupted by SIGINT")
    );
    let picture = image::open(&out).unwrap().to_rgb8();
    assert!(
        picture.as_raw().iter().any(|&v| v > 0),
        "the picture is black"
    );
}

#[test]
fn a_truth_render_that_ends_says_its_samples_in_the_file_and_exits_0() {
    let dir = temp_dir("truth_png_note");
    let out = dir.join("truth.png");
    let (ok, stderr) = crate::cli::shadeballs(&[
        "render",
        "--backend",
        "truth",
        "--spp",
        "4",
        "--width",
        "64",
        "--height",
        "36",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&out).unwrap()));
    let reader = decoder.read_info().unwrap();
    let comment: Vec<_> = reader
        .info()
        .uncompressed_latin1_text
        .iter()
        .map(|t| (t.keyword.clone(), t.text.clone()))
        .collect();
    assert_eq!(
        comment,
        [(
            "Comment".to_string(),
            "shadeballs truth (random walk): 4 spp".to_string()
        )]
    );
}
