//! `shadeballs bake` as a user runs it: the real binary, its exit code and its messages.

use crate::cli::{shadeballs, temp_dir};

#[test]
fn bake_writes_each_format_and_reports_its_time() {
    let dir = temp_dir("bake");
    for ext in ["csv", "exr", "png"] {
        let path = dir.join(format!("tables.{ext}"));
        let (ok, stderr) = shadeballs(&[
            "bake",
            "--out",
            path.to_str().unwrap(),
            "--geometry",
            "smith-correlated",
        ]);
        assert!(ok, "{stderr}");
        assert!(
            stderr.contains("baked E 64x64 + E_avg 64") && stderr.contains(" ms -> "),
            "{stderr}"
        );
        assert!(std::fs::metadata(&path).unwrap().len() > 0);
    }
    let homework = dir.join("homework.csv");
    let (ok, stderr) = shadeballs(&[
        "bake",
        "--out",
        homework.to_str().unwrap(),
        "--layout",
        "games202",
        "--method",
        "cosine",
        "--samples",
        "64",
        "--points",
        "random",
        "--size",
        "16x8",
    ]);
    assert!(ok, "{stderr}");
    assert_eq!(
        std::fs::read_to_string(&homework).unwrap().lines().count(),
        1 + 16 * 8 + 8
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bake_rejects_bad_input_with_one_clear_line() {
    let cases: [(&[&str], &str); 6] = [
        (
            &["bake", "--out", "t.csv", "--size", "0"],
            "outside 2..=8192",
        ),
        (
            &["bake", "--out", "t.csv", "--size", "64xNaN"],
            "not a whole number",
        ),
        (&["bake", "--out", "t.csv", "--samples", "0"], "--samples"),
        (
            &["bake", "--out", "t.csv", "--geometry", "beckmann"],
            "[possible values: schlick, smith, smith-correlated]",
        ),
        (&["bake", "--out", "t.txt"], "use .csv, .exr or .png"),
        (&["bake", "--out", "/no/such/folder/t.csv"], "cannot write"),
    ];
    for (args, expected) in cases {
        let (ok, stderr) = shadeballs(args);
        assert!(!ok, "{args:?} succeeded");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
}
