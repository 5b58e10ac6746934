//! The layers of docs/design/layers.md ("Imports run one way"), checked on the source: no
//! product module refers to the lab or the front ends, the lab to no front end, the viewer
//! neither to the command line nor to the lab, and within the library each layer only to
//! those below it; no import cycles among the modules of a top-level module, the lab's
//! crate's (lab/src, read as the module `lab`) included. Reads every `.rs` file under `src/` and `lab/src` (but the
//! binaries' `main.rs`), drops comments and literals, and resolves
//! `crate::`, `$crate::` and `super::` chains, `use` groups and the crate root's own
//! relative paths to the top-level module they name.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The library's modules, and lib.rs (`crate`).
const LIBRARY: [&str; 19] = [
    "crate",
    "render",
    "brdf",
    "sampling",
    "lut",
    "walk",
    "environment",
    "scene",
    "prepared",
    "import",
    "gpu",
    "cpu",
    "display",
    "labels",
    "output",
    "memory",
    "stats",
    "error",
    "wgsl",
];

/// Each top-level module (`crate`: lib.rs itself) and the top-level modules it must not
/// refer to. Every module under `src/` must be listed.
fn forbidden(module: &str) -> Option<Vec<&'static str>> {
    const FRONT: [&str; 3] = ["lab", "cli", "viewer"];
    let below = |extra: &[&'static str]| FRONT.iter().chain(extra).copied().collect();
    Some(match module {
        "brdf" => below(&[
            "sampling",
            "lut",
            "walk",
            "environment",
            "scene",
            "prepared",
            "gpu",
            "cpu",
        ]),
        // The sampling maths sit on the maths alone.
        "sampling" => below(&[
            "lut",
            "walk",
            "environment",
            "scene",
            "prepared",
            "gpu",
            "cpu",
        ]),
        "lut" => below(&["walk", "environment", "scene", "prepared", "gpu", "cpu"]),
        "walk" => below(&["environment", "scene", "prepared", "gpu", "cpu"]),
        "environment" => below(&["scene", "prepared", "gpu", "cpu"]),
        "scene" => below(&["import", "prepared", "gpu", "cpu"]),
        // A scene prepared for a frame (tables, coating rows, each ball's coating): on the
        // scene, below both renderers, which take it.
        "prepared" => below(&["import", "gpu", "cpu"]),
        // glTF files read as scenes: on the scene, beside the renderers.
        "import" => below(&["gpu", "cpu"]),
        "cpu" => below(&["gpu"]),
        "gpu" => below(&["cpu"]),
        // Labels are laid out from the scene alone and drawn into any RGBA8 image.
        "labels" => below(&["gpu", "cpu"]),
        // The render by any backend sits on both renderers, below the front ends.
        "render" => below(&[]),
        m if LIBRARY.contains(&m) => below(&[]),
        // The lab's crate: its command line shares the `shadeballs` one's flags
        // (`shadeballs::cli`, not a `crate::` path), and nothing here can import it.
        "lab" => vec!["viewer"],
        "viewer" => vec!["cli", "lab"],
        "cli" => vec![],
        _ => return None,
    })
}

/// A token of the source: an identifier (`$crate` included) or one punctuation character
/// (`::` as one token), with its line.
#[derive(Clone, Debug, PartialEq)]
struct Token {
    text: String,
    line: usize,
}

/// The tokens that matter for paths: comments, strings and characters are dropped,
/// numbers and lifetimes kept as words.
fn tokens(source: &str) -> Vec<Token> {
    let c: Vec<char> = source.chars().collect();
    let mut out = Vec::new();
    let (mut i, mut line) = (0, 1);
    let at = |i: usize| c.get(i).copied().unwrap_or('\0');
    while i < c.len() {
        let ch = c[i];
        if ch == '\n' {
            line += 1;
            i += 1;
        } else if ch.is_whitespace() {
            i += 1;
        } else if ch == '/' && at(i + 1) == '/' {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
        } else if ch == '/' && at(i + 1) == '*' {
            // Block comments nest.
            let mut depth = 0;
            while i < c.len() {
                if c[i] == '/' && at(i + 1) == '*' {
                    depth += 1;
                    i += 2;
                } else if c[i] == '*' && at(i + 1) == '/' {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    line += usize::from(c[i] == '\n');
                    i += 1;
                }
            }
        } else if let Some(hashes) = raw_string_start(&c, i) {
            // r"..", r#".."#, br"..": ends at '"' followed by as many '#'.
            i += c[i..].iter().position(|&x| x == '"').unwrap() + 1;
            while i < c.len() {
                let closes = c[i] == '"' && (1..=hashes).all(|k| at(i + k) == '#');
                line += usize::from(c[i] == '\n');
                i += 1;
                if closes {
                    i += hashes;
                    break;
                }
            }
        } else if ch == '"' || (ch == 'b' && at(i + 1) == '"') {
            i += if ch == 'b' { 2 } else { 1 };
            while i < c.len() && c[i] != '"' {
                if c[i] == '\\' {
                    i += 1; // the escaped character may be a line break
                }
                line += usize::from(at(i) == '\n');
                i += 1;
            }
            i += 1;
        } else if ch == '\'' || (ch == 'b' && at(i + 1) == '\'') {
            let start = if ch == 'b' { i + 1 } else { i };
            if at(start + 1) == '\\' {
                // '\n', '\'', '\\', '\u{..}': the escaped character, then up to the quote.
                i = start + 3;
                while i < c.len() && c[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else if at(start + 2) == '\'' {
                i = start + 3;
            } else {
                // A lifetime or label: skip the quote, the name follows as a word.
                i = start + 1;
            }
        } else if ch.is_alphanumeric() || ch == '_' || (ch == '$' && at(i + 1).is_alphabetic()) {
            let start = i;
            i += 1;
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
            out.push(Token {
                text: c[start..i].iter().collect(),
                line,
            });
        } else if ch == ':' && at(i + 1) == ':' {
            out.push(Token {
                text: "::".into(),
                line,
            });
            i += 2;
        } else {
            out.push(Token {
                text: ch.to_string(),
                line,
            });
            i += 1;
        }
    }
    out
}

/// The number of `#` of a raw (byte) string starting at `i`, if one does.
fn raw_string_start(c: &[char], i: usize) -> Option<usize> {
    let mut j = i;
    if c.get(j) == Some(&'b') {
        j += 1;
    }
    if c.get(j) != Some(&'r') || (i > 0 && (c[i - 1].is_alphanumeric() || c[i - 1] == '_')) {
        return None;
    }
    j += 1;
    let hashes = c[j..].iter().take_while(|&&x| x == '#').count();
    (c.get(j + hashes) == Some(&'"')).then_some(hashes)
}

fn is_word(t: &str) -> bool {
    t.starts_with(|ch: char| ch.is_alphanumeric() || ch == '_' || ch == '$')
}

/// The paths of the `use` tree starting at `toks[*i]`, each with `prefix` before it and
/// the line of its last segment; `*i` ends after the tree.
fn use_tree(
    toks: &[Token],
    i: &mut usize,
    prefix: Vec<String>,
    out: &mut Vec<(Vec<String>, usize)>,
) {
    let mut path = prefix;
    while let Some(t) = toks.get(*i) {
        match t.text.as_str() {
            "::" => *i += 1,
            "{" => {
                *i += 1;
                while toks.get(*i).is_some_and(|t| t.text != "}") {
                    let before = *i;
                    use_tree(toks, i, path.clone(), out);
                    if toks.get(*i).is_some_and(|t| t.text == ",") {
                        *i += 1;
                    } else if *i == before {
                        *i += 1; // not a tree: skip rather than loop
                    }
                }
                *i += 1;
                return;
            }
            "*" => {
                path.push("*".into());
                out.push((path, t.line));
                *i += 1;
                return;
            }
            w if is_word(w) => {
                path.push(w.into());
                *i += 1;
                if toks.get(*i).is_some_and(|t| t.text == "::") {
                    continue;
                }
                if toks.get(*i).is_some_and(|t| t.text == "as") {
                    *i += 2;
                }
                out.push((path, t.line));
                return;
            }
            _ => return,
        }
    }
}

/// The module path (`a::b` as `["a", "b"]`) of the file at `rel` (relative to `src/`);
/// `None` for the binary's `main.rs`.
fn module_of(rel: &Path) -> Option<Vec<String>> {
    if rel == Path::new("main.rs") {
        return None;
    }
    let mut parts: Vec<String> = rel
        .with_extension("")
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if matches!(parts.last().map(String::as_str), Some("mod" | "lib")) {
        parts.pop();
    }
    Some(parts)
}

/// One reference of a source file to a crate module.
#[derive(Debug)]
struct Reference {
    line: usize,
    /// The path as resolved from the crate root (`["lut", "Tables"]`; `["*"]` for a glob
    /// of the root).
    path: Vec<String>,
}

/// Every path of `source` (the file of module `module`) that names a crate module: `use`
/// trees and paths starting with `crate`, `$crate`, `self` or `super`, and in the crate
/// root also paths starting with a top-level module's name (`tops`).
fn references(source: &str, module: &[String], tops: &BTreeSet<String>) -> Vec<Reference> {
    let toks = tokens(source);
    let mut refs = Vec::new();
    // Inline modules (`mod tests { .. }`) and the brace depth each opened at.
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut depth = 0usize;
    let mut i = 0;
    while i < toks.len() {
        let t = toks[i].text.as_str();
        let after_colons = i > 0 && toks[i - 1].text == "::";
        let here: Vec<String> = module
            .iter()
            .cloned()
            .chain(inline.iter().map(|(m, _)| m.clone()))
            .collect();
        let mut paths = Vec::new();
        match t {
            "{" => {
                depth += 1;
                i += 1;
            }
            "}" => {
                if inline.last().is_some_and(|&(_, d)| d == depth) {
                    inline.pop();
                }
                depth = depth.saturating_sub(1);
                i += 1;
            }
            "mod" if toks.get(i + 2).is_some_and(|t| t.text == "{") => {
                inline.push((toks[i + 1].text.clone(), depth + 1));
                i += 2;
            }
            "use" if !after_colons => {
                i += 1;
                use_tree(&toks, &mut i, Vec::new(), &mut paths);
            }
            w if is_word(w) && !after_colons && toks.get(i + 1).is_some_and(|t| t.text == "::") => {
                let mut path = vec![w.to_string()];
                let line = toks[i].line;
                i += 1;
                while toks.get(i).is_some_and(|t| t.text == "::")
                    && toks.get(i + 1).is_some_and(|t| is_word(&t.text))
                {
                    path.push(toks[i + 1].text.clone());
                    i += 2;
                }
                paths.push((path, line));
            }
            _ => i += 1,
        }
        for (path, line) in paths {
            if let Some(path) = resolve(&path, &here, tops) {
                refs.push(Reference { line, path });
            }
        }
    }
    refs
}

/// `path`, written in module `here`, from the crate root; `None` when it does not start
/// in the crate (`std::..`, a local name, a child module's relative path) or climbs above
/// the root.
fn resolve(path: &[String], here: &[String], tops: &BTreeSet<String>) -> Option<Vec<String>> {
    let first = path.first()?.as_str();
    let (mut base, mut rest) = match first {
        "crate" | "$crate" => (Vec::new(), &path[1..]),
        "self" => (here.to_vec(), &path[1..]),
        "super" => (here.to_vec(), path),
        _ if here.is_empty() && tops.contains(first) => (Vec::new(), path),
        _ => return None,
    };
    while rest.first().is_some_and(|s| s == "super") {
        base.pop()?;
        rest = &rest[1..];
    }
    base.extend(rest.iter().cloned());
    // `use crate::lut::{self, ..}` names `lut`.
    if base.len() > 1 && base.last().is_some_and(|s| s == "self") {
        base.pop();
    }
    Some(base)
}

/// A source file: its path relative to `src/`, its module and its references.
struct Parsed<'a> {
    rel: &'a Path,
    module: Vec<String>,
    refs: Vec<Reference>,
}

/// `source` up to its unit tests: a file's last item `#[cfg(test)] mod tests` (or
/// `#[cfg(all(test, ...))]`) may use any layer of the library (brdf's tests integrate
/// with lut's quadrature); the product code above it may not.
fn without_unit_tests(source: &str) -> &str {
    let start = ["\n#[cfg(test)]\nmod tests", "\n#[cfg(all(test"]
        .iter()
        .filter_map(|m| source.find(m))
        .min();
    start.map_or(source, |k| &source[..k])
}

fn parse_all(files: &[(PathBuf, String)]) -> Vec<Parsed<'_>> {
    let modules: Vec<_> = files
        .iter()
        .filter_map(|(rel, src)| Some((rel, src, module_of(rel)?)))
        .collect();
    let tops: BTreeSet<String> = modules
        .iter()
        .filter_map(|(_, _, m)| m.first().cloned())
        .collect();
    modules
        .into_iter()
        .map(|(rel, source, module)| Parsed {
            rel,
            // A `tests` module's files (`gpu/tests/*.rs`) are unit tests too.
            refs: if module.iter().any(|m| m == "tests") {
                Vec::new()
            } else {
                references(without_unit_tests(source), &module, &tops)
            },
            module,
        })
        .collect()
}

/// The violations of the layer rules in `files` (path relative to `src/`, source): one
/// line each, `file:line: module refers to target (path)`, then the import cycles within
/// each top-level module (the lab's included).
fn violations(files: &[(PathBuf, String)]) -> Vec<String> {
    let parsed = parse_all(files);
    let mut found = Vec::new();
    for Parsed { rel, module, refs } in &parsed {
        let top = module.first().map_or("crate", String::as_str);
        let Some(banned) = forbidden(top) else {
            found.push(format!(
                "src/{}: module `{top}` has no layer in tests/suite/layers.rs",
                rel.display()
            ));
            continue;
        };
        for r in refs {
            let Some(target) = r.path.first() else {
                continue;
            };
            let hits: Vec<&str> = if target == "*" {
                banned.clone()
            } else {
                banned.iter().copied().filter(|b| b == target).collect()
            };
            for b in hits {
                found.push(format!(
                    "src/{}:{}: `{top}` refers to `{b}` (crate::{})",
                    rel.display(),
                    r.line,
                    r.path.join("::")
                ));
            }
        }
    }
    // Import cycles among the modules of each top-level module (issue 34: the files of
    // `cpu`, `gpu` and `viewer` had three): the library's and the lab's alike.
    let tops: BTreeSet<&str> = parsed
        .iter()
        .filter_map(|p| p.module.first().map(String::as_str))
        .collect();
    for top in tops {
        found.extend(cycles(&parsed, top));
    }
    found
}

/// Import cycles among sibling modules under the top-level module `under` (`a::x` uses
/// `a::y`, which uses `a::x`, each through any file inside them): one line each, the
/// cycle with the place of each step.
fn cycles(parsed: &[Parsed], under: &str) -> Vec<String> {
    let known: BTreeSet<&[String]> = parsed.iter().map(|p| p.module.as_slice()).collect();
    // Edges between the two children of the deepest common parent, with the first place
    // each is made.
    let mut edges: BTreeMap<(String, String), String> = BTreeMap::new();
    for p in parsed
        .iter()
        .filter(|p| p.module.first().is_some_and(|t| t == under))
    {
        for r in &p.refs {
            let k = p
                .module
                .iter()
                .zip(&r.path)
                .take_while(|(a, b)| a == b)
                .count();
            if k == 0 || k >= p.module.len() || k >= r.path.len() || !known.contains(&r.path[..=k])
            {
                continue;
            }
            edges
                .entry((p.module[..=k].join("::"), r.path[..=k].join("::")))
                .or_insert_with(|| format!("src/{}:{}", p.rel.display(), r.line));
        }
    }
    // For each edge a -> b, a path b -> .. -> a closes a cycle; each cycle once.
    let mut seen = BTreeSet::new();
    let mut found = Vec::new();
    for (a, b) in edges.keys() {
        let Some(back) = path_between(&edges, b, a) else {
            continue;
        };
        let mut ring: Vec<String> = std::iter::once(a.clone()).chain(back).collect();
        ring.pop(); // `back` ends at `a`
        if !seen.insert(ring.iter().cloned().collect::<BTreeSet<String>>()) {
            continue;
        }
        let steps: Vec<String> = ring
            .iter()
            .zip(ring.iter().cycle().skip(1))
            .map(|(x, y)| format!("{x} -> {y} ({})", edges[&(x.clone(), y.clone())]))
            .collect();
        found.push(format!("import cycle: {}", steps.join(", ")));
    }
    found
}

/// The shortest path `from` .. `to` along `edges` (both ends included), if any.
fn path_between(
    edges: &BTreeMap<(String, String), String>,
    from: &String,
    to: &String,
) -> Option<Vec<String>> {
    let mut came: BTreeMap<&String, &String> = BTreeMap::new();
    let mut queue = std::collections::VecDeque::from([from]);
    while let Some(x) = queue.pop_front() {
        if x == to {
            let mut path = vec![x.clone()];
            let mut at = x;
            while let Some(&prev) = came.get(at) {
                path.push(prev.clone());
                at = prev;
            }
            path.reverse();
            return Some(path);
        }
        for (_, y) in edges.keys().filter(|(a, _)| a == x) {
            if y != from && !came.contains_key(y) {
                came.insert(y, x);
                queue.push_back(y);
            }
        }
    }
    None
}

/// Every `.rs` file under `dir`, relative to `root`, with its text.
fn read_sources(root: &Path, dir: &Path, out: &mut Vec<(PathBuf, String)>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            read_sources(root, &path, out);
        } else if path.extension().is_some_and(|x| x == "rs") {
            let text = std::fs::read_to_string(&path).unwrap();
            out.push((path.strip_prefix(root).unwrap().to_path_buf(), text));
        }
    }
}

#[test]
fn layers_import_only_downwards() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let src = root.join("src");
    let mut files = Vec::new();
    read_sources(&src, &src, &mut files);
    // The lab's crate (lab/src) as the module `lab`, for its import cycles: its `crate::`
    // is that module. (Cargo keeps the library from importing it: the lab depends on the
    // library.)
    let lab = root.join("lab/src");
    let mut lab_files = Vec::new();
    read_sources(&lab, &lab, &mut lab_files);
    assert!(
        lab_files.len() > 30,
        "read {} files under {}",
        lab_files.len(),
        lab.display()
    );
    files.extend(
        lab_files
            .into_iter()
            .filter(|(p, _)| p != Path::new("main.rs"))
            .map(|(p, text)| {
                let rel = if p == Path::new("lib.rs") {
                    PathBuf::from("lab/mod.rs")
                } else {
                    Path::new("lab").join(p)
                };
                (rel, text.replace("crate::", "crate::lab::"))
            }),
    );
    assert!(
        files.len() > 50 && files.iter().any(|(p, _)| p == Path::new("lib.rs")),
        "read {} files under {}",
        files.len(),
        src.display()
    );
    let found = violations(&files);
    assert!(
        found.is_empty(),
        "imports against the layers (lib.rs):\n{}",
        found.join("\n")
    );
}

/// The checker itself: a fake tree that breaks each rule once is reported, line by line,
/// and what only looks like a reference (comments, strings, a child's relative path) is not.
#[test]
fn layers_checker_reports_a_fake_violation() {
    let fake = |files: &[(&str, &str)]| -> Vec<(PathBuf, String)> {
        files
            .iter()
            .map(|(p, s)| (PathBuf::from(p), s.to_string()))
            .collect()
    };
    let tree = fake(&[
        (
            "lib.rs",
            "pub mod brdf;\n#[cfg(feature = \"lab\")]\npub mod lab;\npub use lab::Thing;\n",
        ),
        (
            "brdf/mod.rs",
            "//! crate::lab in a comment\nuse crate::{error, lut::{self, Tables}};\n",
        ),
        (
            "lut/mod.rs",
            r#"const S: &str = "crate::gpu \" crate::cpu \\";
fn f() { let (c, d, e) = ('"', '\\', '\''); crate::scene::load(); }
"#,
        ),
        (
            "scene/file.rs",
            "/* crate::gpu /* nested */ crate::cpu */ use super::super::cpu::Image;\n",
        ),
        (
            "gpu/draw.rs",
            "mod tests {\n    use super::super::super::cpu::render;\n}\n",
        ),
        // A unit test module at the end may use any layer (not reported); the same use
        // outside it is (walk -> gpu above).
        (
            "walk/mod.rs",
            "use crate::gpu::Gpu;\n#[cfg(test)]\nmod tests {\n    use crate::cpu::render;\n}\n",
        ),
        (
            "gpu/mod.rs",
            r##"use super::display::tone_map;
fn g<'a>(x: &'a str) { r#"crate::lab"#; b"crate::cli"; }
"##,
        ),
        (
            "cpu/mod.rs",
            "pub(crate) fn h() -> crate::Result<()> { $crate::gpu::Gpu::new() }\n",
        ),
        ("output.rs", "use crate::*;\n"),
        // Two files of one layer that import each other.
        ("cpu/shade.rs", "use super::montecarlo::Frame;\n"),
        (
            "cpu/montecarlo.rs",
            "\nuse crate::cpu::shade::{loss, per_channel};\n",
        ),
        (
            "lab/bench/mod.rs",
            "use crate::viewer;\nuse crate::brdf::Geometry;\n",
        ),
        (
            "viewer/mod.rs",
            "fn v() { crate::cli::main(); }\nuse crate::lab as l;\n",
        ),
        ("cli/mod.rs", "use crate::{lab, viewer};\n"),
        ("lab/bench/kernel.rs", "use super::lookup::Filter;\n"),
        (
            "lab/bench/lookup.rs",
            "\n\nuse super::kernel::{self, Kernel};\n",
        ),
        (
            "lab/bench/plot.rs",
            "use super::Sweep;\nuse crate::lab::truth::Study;\n",
        ),
        ("lab/truth/mod.rs", "use crate::lab::bench::plot;\n"),
        ("plugin/mod.rs", "\n"),
        ("main.rs", "use crate::lab;\n"),
    ]);
    let found = violations(&tree);
    let expected = [
        "src/lib.rs:4: `crate` refers to `lab` (crate::lab::Thing)",
        "src/brdf/mod.rs:2: `brdf` refers to `lut` (crate::lut)",
        "src/brdf/mod.rs:2: `brdf` refers to `lut` (crate::lut::Tables)",
        "src/lut/mod.rs:2: `lut` refers to `scene` (crate::scene::load)",
        "src/scene/file.rs:1: `scene` refers to `cpu` (crate::cpu::Image)",
        "src/gpu/draw.rs:2: `gpu` refers to `cpu` (crate::cpu::render)",
        "src/walk/mod.rs:1: `walk` refers to `gpu` (crate::gpu::Gpu)",
        "src/cpu/mod.rs:1: `cpu` refers to `gpu` (crate::gpu::Gpu::new)",
        "src/output.rs:1: `output` refers to `lab` (crate::*)",
        "src/output.rs:1: `output` refers to `cli` (crate::*)",
        "src/output.rs:1: `output` refers to `viewer` (crate::*)",
        "src/lab/bench/mod.rs:1: `lab` refers to `viewer` (crate::viewer)",
        "src/viewer/mod.rs:1: `viewer` refers to `cli` (crate::cli::main)",
        "src/viewer/mod.rs:2: `viewer` refers to `lab` (crate::lab)",
        "import cycle: lab::bench::kernel -> lab::bench::lookup (src/lab/bench/kernel.rs:1), \
         lab::bench::lookup -> lab::bench::kernel (src/lab/bench/lookup.rs:3)",
        "import cycle: lab::bench -> lab::truth (src/lab/bench/plot.rs:2), \
         lab::truth -> lab::bench (src/lab/truth/mod.rs:1)",
        "import cycle: cpu::montecarlo -> cpu::shade (src/cpu/montecarlo.rs:2), \
         cpu::shade -> cpu::montecarlo (src/cpu/shade.rs:1)",
        "src/plugin/mod.rs: module `plugin` has no layer in tests/suite/layers.rs",
    ];
    let found: BTreeSet<&str> = found.iter().map(String::as_str).collect();
    let expected: BTreeSet<&str> = expected.into_iter().collect();
    assert_eq!(found, expected);
}
