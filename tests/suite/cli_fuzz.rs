//! Fuzzing the command line (issue 6): random argv of flags, values and `--flag=value`
//! forms, edge values included, parsed in-process with the binary's own flag definitions
//! (`shadeballs::cli`) under `catch_unwind` and counted. A parse either succeeds or gives
//! one line starting `error: `; `--help` and `--version` print in full.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Mutex;

use proptest::prelude::*;
use proptest::sample::select;

use crate::props::run;

/// argv for one subcommand: flags, values and joined `--flag=value` forms, edge values
/// included.
fn argv() -> impl Strategy<Value = Vec<String>> {
    let flags = select(vec![
        "--out",
        "--size",
        "--geometry",
        "--method",
        "--samples",
        "--points",
        "--layout",
        "--storage",
        "--quick",
        "--scene",
        "--preset",
        "--width",
        "--height",
        "--backend",
        "--grid",
        "--help",
        "-h",
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
        "-0",
        "64",
        "8192",
        "8193",
        "16384",
        "4294967295",
        "4294967296",
        "99999999999999999999",
        "64x64",
        "2x8192",
        "0x5",
        "x",
        "64xNaN",
        "NaN",
        "nan",
        "inf",
        "1e3",
        "1.5",
        "",
        " ",
        "schlick",
        "smith",
        "smith-correlated",
        "beckmann",
        "quadrature",
        "vndf",
        "ndf",
        "cosine",
        "sobol",
        "hammersley",
        "random",
        "warped",
        "sqrt-mu",
        "games202",
        "f32",
        "f16",
        "unorm8",
        "accurate",
        "auto",
        "vulkan",
        "gl",
        "cpu",
        "metal",
        "a.png",
        "a.exr",
        "a.csv",
        "a.txt",
        "/nonexistent/x.png",
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
        select(vec!["bake", "render", "probe", "view", ""]),
        prop::collection::vec(token, 0..8),
    )
        .prop_map(|(sub, rest)| {
            let mut v = vec!["shadeballs".to_string()];
            if !sub.is_empty() {
                v.push(sub.to_string());
            }
            v.extend(rest);
            v
        })
}

#[test]
fn fuzzed_command_lines_parse_or_fail_with_one_line_never_panic() {
    use clap::{Args, FromArgMatches};
    use shadeballs::cli::{one_line_error, BakeArgs, ProbeArgs, RenderArgs};
    // The binary's top level: these three subcommands around the library's flags (the
    // lab's `bench` is fuzzed in lab/tests/lab/cli.rs).
    let cmd = clap::Command::new("shadeballs")
        .subcommand_required(true)
        .subcommand(BakeArgs::augment_args(clap::Command::new("bake")))
        .subcommand(RenderArgs::augment_args(clap::Command::new("render")))
        .subcommand(ProbeArgs::augment_args(clap::Command::new("probe")));
    let counts = Mutex::new([0usize; 4]); // parsed, errors, help/version, panics
    run(20_000, argv(), |argv| {
        let outcome = catch_unwind(AssertUnwindSafe(|| {
            let m = cmd.clone().try_get_matches_from(&argv)?;
            match m.subcommand() {
                Some(("bake", m)) => BakeArgs::from_arg_matches(m).map(|_| ()),
                Some(("render", m)) => RenderArgs::from_arg_matches(m).map(|_| ()),
                Some(("probe", m)) => ProbeArgs::from_arg_matches(m).map(|_| ()),
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
    let [parsed, errors, help, panics] = counts.into_inner().unwrap();
    println!(
        "fuzzed command lines: {} run, {parsed} parsed, {errors} rejected with one line, \
         {help} help/version, {panics} panics",
        parsed + errors + help + panics
    );
    assert!(
        panics == 0 && parsed >= 500 && errors >= 5000,
        "{parsed} {errors} {help} {panics}"
    );
}
