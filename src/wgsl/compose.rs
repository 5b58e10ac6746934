//! The composer of the crate's WGSL modules: `#import` and `#ifdef` resolved by text, in the
//! dialect of naga_oil (Bevy's shader composer), so that a naga_oil user can import the
//! same files by path.
//!
//! Each module file starts with `#define_import_path shadeballs::NAME` and says what it
//! needs with `#import shadeballs::OTHER::{item, item}` lines. [`compose`] puts every
//! module a root imports, directly or not, before the modules that import it, each once,
//! with the directive lines removed and the `#ifdef NAME` / `#ifndef NAME` / `#else` /
//! `#endif` blocks resolved against the given shader defs: the result is plain WGSL, the
//! text wgpu's `create_shader_module` takes. The items an import lists must be declared
//! by the imported module (a check of the list; naga_oil's composition, run by the tests,
//! checks that the lists are complete).
//!
//! Standard library only: the build script includes this file to compose the programs at
//! build time (`build.rs`).

use std::fmt;

/// One WGSL module file: its import path (its `#define_import_path`), its file name and its
/// text.
#[derive(Clone, Copy, Debug)]
pub struct Module {
    /// The import path, e.g. `shadeballs::brdf`.
    pub path: &'static str,
    /// The file under `shaders/`, e.g. `brdf.wgsl`.
    pub file: &'static str,
    /// The file's text, directives included.
    pub source: &'static str,
}

/// A composed program: the WGSL text, and the import paths of the modules in it, in the
/// order they appear (the root last when it is a module itself).
#[derive(Clone, Debug)]
pub struct Composed {
    /// Plain WGSL: no directive left.
    pub source: String,
    /// The import paths of the modules the text holds.
    pub modules: Vec<&'static str>,
}

/// Why a composition failed: each names the file and line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ComposeError {
    /// An `#import` of a module no file declares.
    UnknownModule {
        /// The importing file.
        file: String,
        /// Its line (1-based).
        line: usize,
        /// The import path as written.
        import: String,
    },
    /// An imported item the imported module does not declare.
    UnknownItem {
        /// The importing file.
        file: String,
        /// Its line (1-based).
        line: usize,
        /// The imported module's path.
        module: String,
        /// The item.
        item: String,
    },
    /// A module that imports itself, directly or not.
    Cycle {
        /// The chain of import paths, the repeated one last.
        chain: String,
    },
    /// A directive this composer does not know, a malformed one, or an unbalanced `#ifdef`.
    Directive {
        /// The file.
        file: String,
        /// Its line (1-based).
        line: usize,
        /// What is wrong.
        message: String,
    },
}

impl fmt::Display for ComposeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ComposeError::UnknownModule { file, line, import } => {
                write!(f, "{file}:{line}: no WGSL module `{import}`")
            }
            ComposeError::UnknownItem {
                file,
                line,
                module,
                item,
            } => write!(f, "{file}:{line}: `{module}` declares no `{item}`"),
            ComposeError::Cycle { chain } => write!(f, "WGSL modules import each other: {chain}"),
            ComposeError::Directive {
                file,
                line,
                message,
            } => write!(f, "{file}:{line}: {message}"),
        }
    }
}

impl std::error::Error for ComposeError {}

/// One `#import` line: the module path as written, and the items it lists (empty: the
/// module as a whole).
struct Import {
    line: usize,
    path: String,
    items: Vec<String>,
}

/// A file with its directives taken out: its body (plain WGSL), its declared import path
/// and its imports.
struct Parsed {
    body: String,
    declared: Option<String>,
    imports: Vec<Import>,
}

/// One open `#ifdef` block: whether the enclosing text is kept, whether this branch is, and
/// whether `#else` was seen.
struct Block {
    outer: bool,
    taken: bool,
    in_else: bool,
}

fn directive_error(file: &str, line: usize, message: String) -> ComposeError {
    ComposeError::Directive {
        file: file.to_string(),
        line,
        message,
    }
}

/// Splits an import spec (`a::b::{x, y}`, `a::b`, `a::b::x`) into its path and items; a
/// path without braces is resolved against the known modules later.
fn parse_import(spec: &str) -> Option<(String, Vec<String>)> {
    let spec = spec.trim();
    match spec.find("::{") {
        Some(at) => {
            let list = spec[at + 3..].strip_suffix('}')?;
            let items: Vec<String> = list
                .split(',')
                .map(|s| s.trim().to_string())
                .filter(|s| !s.is_empty())
                .collect();
            let ok = items.iter().all(|s| is_identifier(s));
            (ok && !items.is_empty()).then(|| (spec[..at].to_string(), items))
        }
        None => spec
            .split("::")
            .all(is_identifier)
            .then(|| (spec.to_string(), Vec::new())),
    }
}

fn is_identifier(s: &str) -> bool {
    let mut chars = s.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// A conditional directive (`#ifdef`, `#ifndef`, `#else`, `#endif`) applied to the stack of
/// open blocks; false when `directive` is none of them.
fn conditional(
    file: &str,
    number: usize,
    directive: &str,
    rest: &str,
    defs: &[&str],
    blocks: &mut Vec<Block>,
) -> Result<bool, ComposeError> {
    let keeping = blocks.last().is_none_or(|b| b.outer && b.taken);
    match directive {
        "#ifdef" | "#ifndef" => {
            if !is_identifier(rest) {
                let message = format!("`{directive}` takes one shader def name");
                return Err(directive_error(file, number, message));
            }
            let defined = defs.contains(&rest);
            blocks.push(Block {
                outer: keeping,
                taken: defined == (directive == "#ifdef"),
                in_else: false,
            });
        }
        "#else" | "#endif" => {
            let Some(block) = blocks.last_mut() else {
                let message = format!("`{directive}` without `#ifdef`");
                return Err(directive_error(file, number, message));
            };
            if directive == "#endif" {
                blocks.pop();
            } else if block.in_else {
                return Err(directive_error(file, number, "a second `#else`".into()));
            } else {
                block.taken = !block.taken;
                block.in_else = true;
            }
        }
        _ => return Ok(false),
    }
    Ok(true)
}

/// Takes the directives out of `text` (of `file`), keeping the lines that `defs` select.
fn preprocess(file: &str, text: &str, defs: &[&str]) -> Result<Parsed, ComposeError> {
    let mut parsed = Parsed {
        body: String::with_capacity(text.len()),
        declared: None,
        imports: Vec::new(),
    };
    let mut blocks: Vec<Block> = Vec::new();
    for (index, line) in text.lines().enumerate() {
        let number = index + 1;
        let trimmed = line.trim();
        if !trimmed.starts_with('#') {
            if blocks.last().is_none_or(|b| b.outer && b.taken) {
                parsed.body.push_str(line);
                parsed.body.push('\n');
            }
            continue;
        }
        let (directive, rest) = trimmed.split_once(' ').unwrap_or((trimmed, ""));
        let rest = rest.trim();
        if conditional(file, number, directive, rest, defs, &mut blocks)? {
            continue;
        }
        if !blocks.last().is_none_or(|b| b.outer && b.taken) {
            continue;
        }
        match directive {
            "#define_import_path" if is_identifier_path(rest) => {
                parsed.declared = Some(rest.to_string())
            }
            "#import" => {
                let Some((path, items)) = parse_import(rest) else {
                    let message = format!("malformed import `{rest}`");
                    return Err(directive_error(file, number, message));
                };
                parsed.imports.push(Import {
                    line: number,
                    path,
                    items,
                });
            }
            _ => {
                let message = format!("unknown or malformed directive `{trimmed}`");
                return Err(directive_error(file, number, message));
            }
        }
    }
    if !blocks.is_empty() {
        let message = "`#ifdef` without `#endif`".to_string();
        return Err(directive_error(file, text.lines().count(), message));
    }
    Ok(parsed)
}

fn is_identifier_path(s: &str) -> bool {
    s.split("::").all(is_identifier)
}

/// The names `body` declares at module scope: functions, constants, overrides, structs,
/// aliases and variables (declarations start a line, as in the crate's files).
fn declarations(body: &str) -> Vec<String> {
    let mut names = Vec::new();
    for line in body.lines() {
        let words = strip_attributes(line.trim_start());
        let rest = ["fn ", "const ", "override ", "struct ", "alias ", "var "]
            .iter()
            .find_map(|k| words.strip_prefix(k))
            .or_else(|| {
                // `var<uniform> name`, `var<storage, read> name`.
                let after = words.strip_prefix("var<")?;
                Some(&after[after.find('>')? + 1..])
            });
        if let Some(rest) = rest {
            let name: String = rest
                .trim_start()
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() {
                names.push(name);
            }
        }
    }
    names
}

/// `line` without its leading attributes (`@group(0) @binding(1) var ...` -> `var ...`).
fn strip_attributes(mut line: &str) -> &str {
    while let Some(rest) = line.strip_prefix('@') {
        let name_end = rest
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(rest.len());
        let mut after = &rest[name_end..];
        if let Some(args) = after.strip_prefix('(') {
            after = args.find(')').map_or("", |close| &args[close + 1..]);
        }
        line = after.trim_start();
    }
    line
}

/// The composition so far: each module's path, body and declarations, in order, and the
/// chain of modules being visited (for cycles).
struct State<'m> {
    modules: &'m [Module],
    defs: &'m [&'m str],
    done: Vec<(&'static str, String, Vec<String>)>,
    visiting: Vec<&'static str>,
}

impl State<'_> {
    /// Resolves `import` (of `file`) to a module and the items it names, and adds that
    /// module (after its own imports) unless it is already in.
    fn import(&mut self, file: &str, import: &Import) -> Result<(), ComposeError> {
        let find = |p: &str| self.modules.iter().find(|m| m.path == p).copied();
        // `a::b::c` without braces: the module `a::b::c`, or the item `c` of `a::b`.
        let (module, items) = match find(&import.path) {
            Some(m) => (m, import.items.clone()),
            None => {
                let split = import
                    .items
                    .is_empty()
                    .then(|| import.path.rsplit_once("::"));
                match split.flatten().and_then(|(p, item)| Some((find(p)?, item))) {
                    Some((m, item)) => (m, vec![item.to_string()]),
                    None => {
                        return Err(ComposeError::UnknownModule {
                            file: file.to_string(),
                            line: import.line,
                            import: import.path.clone(),
                        })
                    }
                }
            }
        };
        let at = self.visit(module)?;
        let declared = &self.done[at].2;
        match items.iter().find(|item| !declared.contains(item)) {
            Some(item) => Err(ComposeError::UnknownItem {
                file: file.to_string(),
                line: import.line,
                module: module.path.to_string(),
                item: item.clone(),
            }),
            None => Ok(()),
        }
    }

    /// Adds `module` after its imports, unless it is already in; its index in `done`.
    fn visit(&mut self, module: Module) -> Result<usize, ComposeError> {
        if let Some(at) = self.done.iter().position(|d| d.0 == module.path) {
            return Ok(at);
        }
        if self.visiting.contains(&module.path) {
            let mut chain = self.visiting.join(" -> ");
            chain.push_str(" -> ");
            chain.push_str(module.path);
            return Err(ComposeError::Cycle { chain });
        }
        let parsed = preprocess(module.file, module.source, self.defs)?;
        if parsed.declared.as_deref() != Some(module.path) {
            let message = format!(
                "the file must start with `#define_import_path {}`",
                module.path
            );
            return Err(directive_error(module.file, 1, message));
        }
        self.visiting.push(module.path);
        for import in &parsed.imports {
            self.import(module.file, import)?;
        }
        self.visiting.pop();
        let names = declarations(&parsed.body);
        self.done.push((module.path, parsed.body, names));
        Ok(self.done.len() - 1)
    }
}

/// Composes `root` (the text of `file`, directives included) with every module of
/// `modules` it imports, directly or not, under the shader defs `defs`: the imported
/// modules first, each once, in the order the imports are met (depth first), then the
/// root's own text.
pub(crate) fn compose(
    file: &str,
    root: &str,
    defs: &[&str],
    modules: &[Module],
) -> Result<Composed, ComposeError> {
    let parsed = preprocess(file, root, defs)?;
    let mut state = State {
        modules,
        defs,
        done: Vec::new(),
        visiting: Vec::new(),
    };
    if let Some(own) = modules
        .iter()
        .find(|m| Some(m.path) == parsed.declared.as_deref())
    {
        state.visiting.push(own.path);
    }
    for import in &parsed.imports {
        state.import(file, import)?;
    }
    let mut parts: Vec<&str> = state.done.iter().map(|d| d.1.as_str()).collect();
    if !parsed.body.is_empty() {
        parts.push(&parsed.body);
    }
    let mut names: Vec<&'static str> = state.done.iter().map(|d| d.0).collect();
    if let Some(own) = modules
        .iter()
        .find(|m| Some(m.path) == parsed.declared.as_deref())
    {
        names.push(own.path);
    }
    Ok(Composed {
        source: parts.join("\n"),
        modules: names,
    })
}

/// Composes the module of import path `path` of `modules` as a program's root.
pub(crate) fn compose_module(
    path: &str,
    defs: &[&str],
    modules: &[Module],
) -> Result<Composed, ComposeError> {
    match modules.iter().find(|m| m.path == path) {
        Some(m) => compose(m.file, m.source, defs, modules),
        None => Err(ComposeError::UnknownModule {
            file: "(root)".to_string(),
            line: 0,
            import: path.to_string(),
        }),
    }
}
