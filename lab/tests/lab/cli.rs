//! Running the real `shadeballs-lab` binary, as a user does: the helpers of the lab's CLI
//! tests, and the lab's share of the command line's hostile-input tests (one-line errors
//! for its flags, folders that are files, and its flags fuzzed in-process as
//! tests/suite/cli_fuzz.rs fuzzes the `shadeballs` binary's).

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use proptest::prelude::*;
use proptest::sample::select;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

/// One `shadeballs-lab` process at a time: each run uses both cores of the 2-core machine
/// (rayon, lavapipe), and `bench --quick` is timed against its goal of under a minute, which
/// another run of this binary beside it would halve.
static ONE_RUN: Mutex<()> = Mutex::new(());

/// Runs `shadeballs-lab args…`, one run at a time: (exit status was success, stderr).
pub fn lab(args: &[&str]) -> (bool, String) {
    let (ok, stderr, _) = lab_timed(args);
    (ok, stderr)
}

/// [`lab`] with the wall time of the run itself (the wait for another run left out).
pub fn lab_timed(args: &[&str]) -> (bool, String, Duration) {
    let _one = ONE_RUN.lock().unwrap_or_else(|e| e.into_inner());
    let start = Instant::now();
    let out = Command::new(env!("CARGO_BIN_EXE_shadeballs-lab"))
        .args(args)
        .output()
        .expect("run shadeballs-lab");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        start.elapsed(),
    )
}

/// A fresh folder under the system temp folder, unique to this process.
pub fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("shadeballs-lab-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `shadeballs-lab args…` and checks that it fails with one line on stderr, starting
/// `error: ` and containing `expect`.
fn fails_with_one_line(args: &[&str], expect: &str) {
    let (ok, stderr) = lab(args);
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    println!("{args:?} -> {stderr}");
    assert!(!ok, "{args:?} succeeded");
    assert!(
        lines.len() == 1 && lines[0].starts_with("error: ") && lines[0].contains(expect),
        "{args:?}: expected one line with {expect:?}, got {stderr:?}"
    );
}

fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn misread_bench_flags_are_named() {
    let dir = temp_dir("misread");
    let out = dir.to_str().unwrap();
    let cases: &[(&[&str], &str)] = &[
        (
            &["bench", "--cpu-only", "--only", "render", "--out", out],
            "nothing to measure",
        ),
        (
            &["bench", "--only", "bake", "--only", "read"],
            "cannot be used multiple times",
        ),
        (&["bnech"], "unrecognized subcommand"),
    ];
    for (args, expect) in cases {
        fails_with_one_line(args, expect);
    }
    assert_eq!(entries(&dir), Vec::<String>::new());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A folder's path that is a file is named as such (hostile input, finding 11).
#[test]
fn folder_outputs_that_are_files_are_named() {
    let dir = temp_dir("folder");
    let file = dir.join("taken");
    std::fs::write(&file, b"x").unwrap();
    for cmd in [
        vec!["compare", "--quick", "--backend", "cpu"],
        vec!["truth", "--quick"],
        vec!["bench", "--quick", "--only", "plan"],
    ] {
        let args = [&cmd[..], &["--out", file.to_str().unwrap()]].concat();
        let (ok, stderr, took) = lab_timed(&args);
        assert!(!ok, "{args:?} succeeded");
        assert!(
            stderr.trim().lines().count() == 1 && stderr.contains("is not a folder"),
            "{args:?}: {stderr}"
        );
        // The check comes before any work: 10 s is far above a process start (the run's
        // own time, not its wait for another run of the lab beside it).
        assert!(took < Duration::from_secs(10), "{args:?} took {took:?}");
    }
    assert_eq!(std::fs::read(&file).unwrap(), b"x");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// argv of the lab's subcommands: their flags and values, joined `--flag=value` forms.
fn argv() -> impl Strategy<Value = Vec<String>> {
    let flags = select(vec![
        "--out",
        "--quick",
        "--cpu-only",
        "--only",
        "--scene",
        "--preset",
        "--spp",
        "--seed",
        "--backend",
        "--geometry",
        "--help",
        "--version",
        "--bogus",
        "-",
        "--",
        "-x",
    ]);
    let values = select(vec![
        "0",
        "1",
        "2",
        "-1",
        "65536",
        "65537",
        "4294967296",
        "NaN",
        "",
        " ",
        "bake",
        "plan,read",
        "render,nope",
        "scale",
        "ibl",
        "accurate",
        "games202",
        "auto",
        "vulkan",
        "cpu",
        "truth",
        "montecarlo",
        "a.png",
        "/nonexistent/x",
        "\u{fc}ber",
        "=",
    ]);
    let token = prop_oneof![
        2 => flags.clone().prop_map(String::from),
        2 => values.clone().prop_map(String::from),
        1 => (flags, values).prop_map(|(f, v)| format!("{f}={v}")),
        1 => any::<String>(),
    ];
    (
        select(vec!["bench", "compare", "truth", ""]),
        prop::collection::vec(token, 0..8),
    )
        .prop_map(|(sub, rest)| {
            let mut v = vec!["shadeballs-lab".to_string()];
            if !sub.is_empty() {
                v.push(sub.to_string());
            }
            v.extend(rest);
            v
        })
}

#[test]
fn fuzzed_lab_command_lines_parse_or_fail_with_one_line_never_panic() {
    use clap::{Args, FromArgMatches};
    use shadeballs::cli::one_line_error;
    use shadeballs_lab::cli::{BenchArgs, CompareArgs, TruthArgs};
    let cmd = clap::Command::new("shadeballs-lab")
        .subcommand_required(true)
        .subcommand(BenchArgs::augment_args(clap::Command::new("bench")))
        .subcommand(CompareArgs::augment_args(clap::Command::new("compare")))
        .subcommand(TruthArgs::augment_args(clap::Command::new("truth")));
    let counts = Mutex::new([0usize; 4]); // parsed, errors, help/version, panics
    let config = Config {
        cases: 5_000,
        failure_persistence: None,
        ..Config::default()
    };
    let rng = TestRng::deterministic_rng(RngAlgorithm::ChaCha);
    let result = TestRunner::new_with_rng(config, rng).run(&argv(), |argv| {
        let outcome = catch_unwind(AssertUnwindSafe(|| {
            let m = cmd.clone().try_get_matches_from(&argv)?;
            match m.subcommand() {
                Some(("bench", m)) => BenchArgs::from_arg_matches(m).map(|_| ()),
                Some(("compare", m)) => CompareArgs::from_arg_matches(m).map(|_| ()),
                Some(("truth", m)) => TruthArgs::from_arg_matches(m).map(|_| ()),
                _ => unreachable!("subcommand_required"),
            }
        }));
        let mut c = counts.lock().unwrap();
        match outcome {
            Err(_) => {
                c[3] += 1;
                Err(TestCaseError::fail(format!("clap panicked on {argv:?}")))
            }
            Ok(Ok(())) => {
                c[0] += 1;
                Ok(())
            }
            Ok(Err(e)) => match one_line_error(&e) {
                None => {
                    c[2] += 1;
                    Ok(())
                }
                Some(line) => {
                    c[1] += 1;
                    prop_assert!(
                        line.starts_with("error: ") && !line.contains('\n'),
                        "{line:?} for {argv:?}"
                    );
                    Ok(())
                }
            },
        }
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    let [parsed, errors, help, panics] = counts.into_inner().unwrap();
    println!(
        "fuzzed lab command lines: {} run, {parsed} parsed, {errors} rejected with one line, \
         {help} help/version, {panics} panics",
        parsed + errors + help + panics
    );
    // Both outcomes seen often (a fuzzer that only ever fails to parse tests little): a
    // tenth of cases parsed and half rejected, the shares tests/suite/cli_fuzz.rs asks of
    // the `shadeballs` binary's (500 and 5000 of 20000), scaled to 5000 cases.
    assert!(
        panics == 0 && parsed >= 125 && errors >= 1250,
        "{parsed} {errors} {help} {panics}"
    );
}
