//! The README's library section is a complete program that builds as written (issue 39):
//! its `toml` dependency block and its `rust` program, taken from the README, make a crate
//! of their own outside this workspace (an empty `[workspace]` table), the dependency's
//! path pointed at this checkout and nothing else changed. It is built with this
//! workspace's `Cargo.lock`, offline, into this workspace's target folder, in cargo's dev
//! profile without debug info (the same code and features; none of the workspace's
//! release build is reused, since the library's lean graph gives its dependencies other
//! features, and the dev build took 42 s where release took 110 s of CI's time); then it
//! runs and must write its picture. The same host crate holds a second program,
//! `without_image_files`: the library as the README's line builds it (no default features)
//! refuses a map file by name, in one line, and writes nothing. This build is the one
//! build of the library without default features that CI runs (tests/run.sh says why).

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::cli::temp_dir;

/// The README's path to the crate, which the test points at this checkout.
const README_PATH: &str = "path = \"../shadeballs\"";

/// The first fenced block of `lang` in `text`.
fn block<'a>(text: &'a str, lang: &str) -> &'a str {
    let fence = format!("```{lang}\n");
    let start = text
        .find(&fence)
        .unwrap_or_else(|| panic!("no ```{lang} block"))
        + fence.len();
    let len = text[start..].find("```").expect("an unclosed block");
    &text[start..start + len]
}

/// The target folder this test binary was built into (`target/release/deps/suite-*`).
fn target_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("test binary path");
    exe.ancestors().nth(3).expect("target folder").to_path_buf()
}

#[test]
fn readme_library_program_builds_and_runs() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let at = readme
        .find("## Using it as a library")
        .expect("the README's library section");
    let section = &readme[at..];
    let section = &section[..section[3..].find("\n## ").map_or(section.len(), |i| i + 3)];
    let dependencies = block(section, "toml");
    let program = block(section, "rust");
    assert!(
        dependencies.contains(README_PATH) && dependencies.contains("default-features = false"),
        "the README's dependency line changed: {dependencies}"
    );
    assert!(program.contains("fn main()"), "not a program: {program}");

    let dir = temp_dir("readme-library");
    std::fs::create_dir_all(dir.join("src")).unwrap();
    let manifest =
        format!(
        "[package]\nname = \"shadeballs-readme-host\"\nversion = \"0.1.0\"\nedition = \"2021\"\n\
         publish = false\n\n# Not a member of any workspace above it.\n[workspace]\n\n{}\n\
         # The dev profile without debug info: the quickest build of the same code.\n\
         [profile.dev]\ndebug = false\n",
        dependencies.replace(README_PATH, &format!("path = {:?}", root.display().to_string()))
    );
    std::fs::write(dir.join("Cargo.toml"), manifest).unwrap();
    std::fs::write(dir.join("src/main.rs"), program).unwrap();
    std::fs::create_dir_all(dir.join("src/bin")).unwrap();
    std::fs::write(
        dir.join("src/bin/without_image_files.rs"),
        WITHOUT_IMAGE_FILES,
    )
    .unwrap();
    std::fs::copy(root.join("Cargo.lock"), dir.join("Cargo.lock")).unwrap();
    let target = target_dir();
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let started = std::time::Instant::now();
    let out = Command::new(&cargo)
        .args(["build", "--offline", "--quiet"])
        .current_dir(&dir)
        .env("CARGO_TARGET_DIR", &target)
        // tests/run.sh lints this workspace's crates as they build, with clippy-driver as
        // the workspace's rustc wrapper; the host crate is a user's program, built as a
        // user builds it.
        .env_remove("RUSTC_WORKSPACE_WRAPPER")
        .env_remove("CLIPPY_ARGS")
        .output()
        .expect("run cargo");
    assert!(
        out.status.success(),
        "the README's program does not build:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    println!(
        "the README's program built in {:.1} s",
        started.elapsed().as_secs_f64()
    );

    let exe = target.join("debug").join("shadeballs-readme-host");
    let out = Command::new(&exe)
        .current_dir(&dir)
        .output()
        .expect("run the README's program");
    assert!(
        out.status.success(),
        "the README's program failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    // Its picture: a PPM of two lit balls on black, the left one (with the term) brighter.
    let ppm = std::fs::read(dir.join("balls.ppm")).expect("balls.ppm written");
    let header = b"P6 320 180 255\n";
    assert!(ppm.starts_with(header), "not the PPM the README writes");
    let pixels = &ppm[header.len()..];
    assert_eq!(pixels.len(), 320 * 180 * 3);
    let half_sum = |left: bool| -> u64 {
        pixels
            .chunks_exact(3)
            .enumerate()
            .filter(|(i, _)| ((i % 320) < 160) == left)
            .map(|(_, p)| p.iter().map(|&c| u64::from(c)).sum::<u64>())
            .sum()
    };
    let (left, right) = (half_sum(true), half_sum(false));
    println!("the README's picture: left half {left}, right half {right}");
    assert!(right > 0 && left > right, "left {left}, right {right}");

    let out = Command::new(target.join("debug").join("without_image_files"))
        .arg(&dir)
        .output()
        .expect("run without_image_files");
    assert!(
        out.status.success(),
        "the library without image files: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The host's second program: without the crate feature `image-files` a map file is one
/// error naming the feature, on loading and on saving, and nothing is written.
const WITHOUT_IMAGE_FILES: &str = r#"fn main() {
    let dir = std::env::args().nth(1).expect("a folder");
    let path = std::path::Path::new(&dir).join("map.hdr");
    let err = shadeballs::environment::load(&path).unwrap_err().to_string();
    assert!(err.contains("image-files") && !err.contains('\n'), "{err}");
    let map = shadeballs::environment::Builtin::Sky.generate(16);
    let err = shadeballs::environment::save(&map, &path).unwrap_err().to_string();
    assert!(err.contains("image-files") && !err.contains('\n'), "{err}");
    assert!(!path.exists(), "{} was written", path.display());
}
"#;
