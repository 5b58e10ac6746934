//! The truth render's progress (issue 27, 4): the time-left estimate and the bar
//! (`cli::progress`), and Ctrl-C into a `.png`: the picture is written with its samples a
//! pixel in its `Comment` and in the message, and the exit status is 130.

use std::process::{Command, Stdio};

use std::time::{Duration, Instant};

use crate::cli::{interrupt, temp_dir};

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
