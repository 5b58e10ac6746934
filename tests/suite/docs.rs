//! The docs against the code: the module list of docs/design/layers.md ("The modules")
//! names exactly the folders and `.rs` files directly under `src/` and the lab's
//! `lab/src/`, and the `shaders/*.wgsl` files, and every relative link in `docs/**/*.md` and `README.md` points at a file that
//! exists and, with a `#anchor`, at a heading of that file.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The paths the module list names: the first word of each line of the first ```text
/// block after the heading "## The modules" that does not start with a space (the other
/// lines continue a description).
fn listed_paths(layers_md: &str) -> Result<Vec<String>, String> {
    let after = layers_md
        .split_once("\n## The modules\n")
        .ok_or("docs/design/layers.md has no heading \"## The modules\"")?
        .1;
    let block = after
        .split_once("```text\n")
        .ok_or("docs/design/layers.md: \"The modules\" has no ```text block")?
        .1;
    let block = block
        .split_once("\n```")
        .ok_or("docs/design/layers.md: the module list's block is not closed")?
        .0;
    Ok(block
        .lines()
        .filter(|l| !l.is_empty() && !l.starts_with(char::is_whitespace))
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .collect())
}

/// What the code has: `src/NAME/` for each folder and `src/NAME.rs` for each Rust file
/// directly under `src/` (the library and the binary) and `lab/src/` (the lab's crate),
/// and `shaders/NAME.wgsl` for each shader.
fn code_paths(root: &Path) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for src in ["src", "lab/src"] {
        for entry in std::fs::read_dir(root.join(src)).unwrap_or_else(|e| panic!("{src}/: {e}")) {
            let path = entry.expect("read an entry of a source folder").path();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            if path.is_dir() {
                out.insert(format!("{src}/{name}/"));
            } else if name.ends_with(".rs") {
                out.insert(format!("{src}/{name}"));
            }
        }
    }
    for entry in std::fs::read_dir(root.join("shaders")).expect("read shaders/") {
        let name = entry.expect("read an entry of shaders/").file_name();
        let name = name.to_string_lossy();
        if name.ends_with(".wgsl") {
            out.insert(format!("shaders/{name}"));
        }
    }
    out
}

/// One line per disagreement between the list and the code, naming the entry. Listed
/// paths outside `src/`, `lab/src/` and `shaders/` (examples, tests, benches) only have to
/// exist.
fn list_mismatches(
    listed: &[String],
    code: &BTreeSet<String>,
    exists: impl Fn(&str) -> bool,
) -> Vec<String> {
    let mut out = Vec::new();
    let mut seen = BTreeSet::new();
    for path in listed {
        if !seen.insert(path.as_str()) {
            out.push(format!("{path}: listed twice in docs/design/layers.md"));
        } else if ["src/", "lab/src/", "shaders/"]
            .iter()
            .any(|p| path.starts_with(p))
        {
            if !code.contains(path) {
                out.push(format!(
                    "{path}: listed in docs/design/layers.md but not in the code"
                ));
            }
        } else if !exists(path) {
            out.push(format!(
                "{path}: listed in docs/design/layers.md but does not exist"
            ));
        }
    }
    for path in code.iter().filter(|p| !seen.contains(p.as_str())) {
        out.push(format!(
            "{path}: in the code but not listed in docs/design/layers.md (\"The modules\")"
        ));
    }
    out
}

#[test]
fn layer_list_matches_the_modules() {
    let text = std::fs::read_to_string(root().join("docs/design/layers.md"))
        .expect("read docs/design/layers.md");
    let listed = listed_paths(&text).unwrap_or_else(|e| panic!("{e}"));
    let code = code_paths(root());
    // A floor, not a count: the list and the tree both hold at least these.
    assert!(
        code.contains("src/lib.rs")
            && code.contains("lab/src/lib.rs")
            && code.contains("shaders/brdf.wgsl"),
        "read the wrong tree: {code:?}"
    );
    let found = list_mismatches(&listed, &code, |p| root().join(p).exists());
    assert!(found.is_empty(), "{}", found.join("\n"));
}

/// GitHub's anchor of a heading: lower case, punctuation dropped but `-` and `_`, spaces
/// as `-`.
fn anchor(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | ' '))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The lines of a Markdown text outside fenced code blocks, with their numbers.
fn prose_lines(text: &str) -> Vec<(usize, &str)> {
    let mut fenced = false;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        } else if !fenced {
            out.push((i + 1, line));
        }
    }
    out
}

/// The anchors of a Markdown file's headings; a repeated heading gets `-1`, `-2`, ...
fn anchors(text: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for (_, line) in prose_lines(text) {
        let Some(heading) = line.strip_prefix('#') else {
            continue;
        };
        let base = anchor(heading.trim_start_matches('#'));
        let mut name = base.clone();
        let mut k = 0;
        while !out.insert(name.clone()) {
            k += 1;
            name = format!("{base}-{k}");
        }
    }
    out
}

/// The targets of the inline links `[text](target)` of a line, code spans left out.
fn link_targets(line: &str) -> Vec<String> {
    let mut prose = String::new();
    for (i, part) in line.split('`').enumerate() {
        if i % 2 == 0 {
            prose.push_str(part);
        }
    }
    let mut out = Vec::new();
    let mut rest = prose.as_str();
    while let Some(at) = rest.find("](") {
        rest = &rest[at + 2..];
        let Some(end) = rest.find(')') else { break };
        let target = rest[..end].split_whitespace().next().unwrap_or("");
        out.push(target.to_string());
        rest = &rest[end..];
    }
    out
}

/// One line per broken relative link of `file` (relative to the repository root), naming
/// the file, the line and the target. `read` gives a repository file's text, `None` when
/// there is no such file (a folder reads as `Some("")`).
fn broken_links(file: &str, text: &str, read: &dyn Fn(&Path) -> Option<String>) -> Vec<String> {
    let dir = Path::new(file).parent().unwrap_or(Path::new(""));
    let mut out = Vec::new();
    for (n, line) in prose_lines(text) {
        for target in link_targets(line) {
            if target.is_empty() || target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            let (path, hash) = match target.split_once('#') {
                Some((p, h)) => (p, Some(h)),
                None => (target.as_str(), None),
            };
            let (resolved, body) = if path.is_empty() {
                (PathBuf::from(file), Some(text.to_string()))
            } else {
                let resolved = normalise(&dir.join(path));
                let body = read(&resolved);
                (resolved, body)
            };
            let Some(body) = body else {
                out.push(format!("{file}:{n}: link to {target}: no such file"));
                continue;
            };
            let markdown = resolved.extension().is_some_and(|x| x == "md");
            if let Some(hash) = hash.filter(|_| markdown) {
                if !anchors(&body).contains(hash) {
                    out.push(format!(
                        "{file}:{n}: link to {target}: {} has no heading #{hash}",
                        resolved.display()
                    ));
                }
            }
        }
    }
    out
}

/// `a/b/../c` as `a/c`, `./a` as `a`.
fn normalise(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for part in path.components() {
        match part {
            std::path::Component::ParentDir => {
                if !out.pop() {
                    out.push("..");
                }
            }
            std::path::Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

/// Every `.md` file under `docs/`, relative to the repository root.
fn markdown_files(dir: &Path, out: &mut Vec<String>) {
    for entry in std::fs::read_dir(dir).expect("read docs/") {
        let path = entry.expect("read an entry of docs/").path();
        if path.is_dir() {
            markdown_files(&path, out);
        } else if path.extension().is_some_and(|x| x == "md") {
            let relative = path.strip_prefix(root()).unwrap();
            out.push(relative.to_string_lossy().replace('\\', "/"));
        }
    }
}

fn read_repo_file(path: &Path) -> Option<String> {
    let full = root().join(path);
    if full.is_dir() {
        return Some(String::new());
    }
    // Binary targets (pictures) exist but are not text: their anchors are not checked.
    std::fs::read(&full)
        .ok()
        .map(|bytes| String::from_utf8_lossy(&bytes).into_owned())
}

#[test]
fn doc_links_point_at_files_and_headings() {
    let mut files = vec!["README.md".to_string()];
    markdown_files(&root().join("docs"), &mut files);
    // design.md and the layer list are among the files read.
    assert!(
        files.iter().any(|f| f == "docs/design/layers.md"),
        "read {files:?}"
    );
    let mut found = Vec::new();
    let mut links = 0;
    for file in &files {
        let text = std::fs::read_to_string(root().join(file)).expect("read a doc");
        links += prose_lines(&text)
            .iter()
            .map(|(_, l)| link_targets(l).len())
            .sum::<usize>();
        found.extend(broken_links(file, &text, &read_repo_file));
    }
    // The docs hold well over 100 links today; fewer than 50 means the parser lost them.
    assert!(links > 50, "found only {links} links in {files:?}");
    assert!(found.is_empty(), "broken links:\n{}", found.join("\n"));
}

/// The checkers themselves, on made-up input: each kind of disagreement is named.
#[test]
fn docs_checkers_name_what_is_wrong() {
    let list = "# L\n\n## The modules\n\n```text\nsrc/lib.rs   facade\n               more\n\
                src/gone/    not there\nshaders/a.wgsl  a\nexamples/none.rs  x\n```\n";
    let listed = listed_paths(list).unwrap();
    assert_eq!(
        listed,
        [
            "src/lib.rs",
            "src/gone/",
            "shaders/a.wgsl",
            "examples/none.rs"
        ]
    );
    let code: BTreeSet<String> = ["src/lib.rs", "src/new.rs", "shaders/a.wgsl"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let found = list_mismatches(&listed, &code, |_| false);
    assert_eq!(found.len(), 3, "{found:?}");
    assert!(found[0].starts_with("src/gone/: listed"), "{found:?}");
    assert!(
        found[1].starts_with("examples/none.rs: listed"),
        "{found:?}"
    );
    assert!(found[2].starts_with("src/new.rs: in the code"), "{found:?}");
    assert!(listed_paths("# no list\n").is_err());

    let doc = "# Top\n\n## The `uniform` layout\n\n[a](b.md#nope) [c](b.md#here) `[d](gone.md)`\n\
               [e](gone.md) [f](#the-uniform-layout) [g](#top-1) [h](https://x.org/y)\n\
               ```\n[i](gone.md)\n```\n";
    let read = |p: &Path| (p == Path::new("docs/b.md")).then(|| "## Here\n".to_string());
    let found = broken_links("docs/a.md", doc, &read);
    assert_eq!(found.len(), 3, "{found:?}");
    assert!(found[0].contains(":5: link to b.md#nope"), "{found:?}");
    assert!(
        found[1].contains(":6: link to gone.md: no such file"),
        "{found:?}"
    );
    assert!(found[2].contains(":6: link to #top-1"), "{found:?}");
    assert_eq!(anchor(" wgpu 30's API"), "wgpu-30s-api");
    assert_eq!(
        normalise(Path::new("docs/design/../x.md")),
        Path::new("docs/x.md")
    );
}

/// The library as a bake-only host links it (`default-features = false`): no crate for
/// files, scene files, windows, panels or command lines in its dependency tree (README,
/// "Features"; docs/crates.md says which feature brings each).
#[test]
fn the_library_alone_pulls_no_file_or_window_crate() {
    let out = std::process::Command::new(env!("CARGO"))
        .current_dir(root())
        .args([
            "tree",
            "--offline",
            "--no-default-features",
            "-e",
            "normal",
            "-p",
            "shadeballs",
            "--prefix",
            "none",
        ])
        .output()
        .expect("cargo tree");
    let tree = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let crates: BTreeSet<&str> = tree.lines().filter_map(|l| l.split(' ').next()).collect();
    // The tree is the library's: wgpu and glam are in it (an empty tree would pass below).
    assert!(crates.contains("wgpu") && crates.contains("glam"), "{tree}");
    for absent in [
        "image",
        "png",
        "exr",
        "toml",
        "serde",
        "winit",
        "egui",
        "clap",
        "anyhow",
        "ab_glyph",
        "env_logger",
        "plotters",
    ] {
        assert!(
            !crates.contains(absent),
            "{absent} is in the default-off tree:\n{tree}"
        );
    }
}
