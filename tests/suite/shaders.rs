//! The WGSL programs, composed as the pipelines get them, parse and validate with naga (no
//! GPU needed), import only modules their pipelines use, and mirror the Rust functions name
//! for name.
use std::collections::BTreeSet;

use shadeballs::gpu::shaders;
use shadeballs::wgsl::{self, Program, PROGRAMS};

fn validate(name: &str, source: &str) {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{name} does not parse:\n{}", e.emit_to_string(source)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{name} does not validate:\n{}", e.emit_to_string(source)));
}

#[test]
fn modules_parse_and_validate() {
    for program in PROGRAMS {
        let source = shaders::source(&program).expect("a built program");
        validate(program.name, source);
    }
    validate("the flat library", wgsl::KULLA_CONTY);
    validate("viewer blit", include_str!("../../shaders/blit.wgsl"));
}

#[test]
fn the_built_programs_are_their_composition() {
    for program in PROGRAMS {
        let composed = wgsl::compose_module(program.root, program.defs)
            .unwrap_or_else(|e| panic!("{}: {e}", program.name));
        assert_eq!(Some(composed.source.as_str()), shaders::source(&program));
        assert!(!composed.source.contains("#import"), "{}", program.name);
    }
    let library: Vec<&str> = wgsl::LIBRARY.to_vec();
    let root: String = library.iter().map(|p| format!("#import {p}\n")).collect();
    let composed = wgsl::compose("library", &root, &[]).expect("the library composes");
    assert_eq!(composed.source, wgsl::KULLA_CONTY);
    assert_eq!(composed.modules, library);
}

/// The named items of a composed module: functions, entry points, global variables,
/// overrides and named types (what `naga::compact` removes when nothing uses it), and
/// with `constants` the named constants (which it keeps, and which naga folds into the
/// expressions that use them).
fn items(module: &naga::Module, constants: bool) -> BTreeSet<String> {
    let mut names = BTreeSet::new();
    names.extend(module.functions.iter().filter_map(|(_, f)| f.name.clone()));
    names.extend(module.entry_points.iter().map(|e| e.name.clone()));
    names.extend(
        module
            .global_variables
            .iter()
            .filter_map(|(_, v)| v.name.clone()),
    );
    names.extend(module.overrides.iter().filter_map(|(_, o)| o.name.clone()));
    names.extend(module.types.iter().filter_map(|(_, t)| t.name.clone()));
    if constants {
        names.extend(module.constants.iter().filter_map(|(_, c)| c.name.clone()));
    }
    names
}

/// The identifiers in the bodies of the functions `functions` of `source` (how a
/// function's use of a constant is seen: naga folds constants into literals).
fn identifiers_in(source: &str, functions: &BTreeSet<String>) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    for name in functions {
        let Some(at) = source.find(&format!("fn {name}(")) else {
            continue;
        };
        let Some(open) = source[at..].find('{').map(|o| at + o) else {
            continue;
        };
        let mut depth = 0usize;
        let mut end = source.len();
        for (i, c) in source[open..].char_indices() {
            match c {
                '{' => depth += 1,
                '}' => {
                    depth -= 1;
                    if depth == 0 {
                        end = open + i;
                        break;
                    }
                }
                _ => {}
            }
        }
        let body = &source[open..end];
        found.extend(
            body.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .filter(|w| !w.is_empty())
                .map(str::to_string),
        );
    }
    found
}

fn parse(name: &str, source: &str) -> naga::Module {
    naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{name} does not parse:\n{}", e.emit_to_string(source)))
}

/// The imported modules of `program` that contribute no item reachable from the entry
/// points its pipelines use (`shaders::entry_points`).
fn unused_modules(program: &Program, source: &str, modules: &[&str]) -> Vec<String> {
    let mut module = parse(program.name, source);
    let used = shaders::entry_points(program);
    assert!(!used.is_empty(), "{}: no entry points", program.name);
    for e in used {
        assert!(
            module.entry_points.iter().any(|p| p.name == *e),
            "{}: no entry point {e}",
            program.name
        );
    }
    module
        .entry_points
        .retain(|e| used.contains(&e.name.as_str()));
    naga::compact::compact(&mut module, naga::compact::KeepUnused::No);
    let mut reachable = items(&module, false);
    let functions: BTreeSet<String> = module
        .functions
        .iter()
        .filter_map(|(_, f)| f.name.clone())
        .chain(module.entry_points.iter().map(|e| e.name.clone()))
        .collect();
    reachable.extend(identifiers_in(source, &functions));
    // Each module's own items: those of its composition less those of its imports'.
    let own = |path: &str| -> BTreeSet<String> {
        let alone = wgsl::compose_module(path, program.defs).expect("the module composes");
        let mut names = items(&parse(path, &alone.source), true);
        for dep in alone.modules.iter().filter(|d| **d != path) {
            let dep = wgsl::compose_module(dep, program.defs).expect("the module composes");
            for n in items(&parse(program.name, &dep.source), true) {
                names.remove(&n);
            }
        }
        names
    };
    modules
        .iter()
        .filter(|m| own(m).is_disjoint(&reachable))
        .map(|m| m.to_string())
        .collect()
}

#[test]
fn every_module_a_program_imports_serves_its_pipelines() {
    for program in PROGRAMS {
        let composed = wgsl::compose_module(program.root, program.defs).expect("composes");
        let unused = unused_modules(&program, &composed.source, &composed.modules);
        assert!(
            unused.is_empty(),
            "{} imports unused modules {unused:?}",
            program.name
        );
    }
    // The ball renderer's modules do not carry the truth's walk.
    let balls = wgsl::compose_module("shadeballs::balls", &[]).expect("composes");
    assert!(!balls.modules.contains(&"shadeballs::walk"));
}

#[test]
fn a_module_no_pipeline_uses_is_found() {
    // Control: the walk imported into the ball renderer serves none of its entry points.
    let root = "#import shadeballs::walk\n#import shadeballs::balls\n";
    let composed = wgsl::compose("balls and walk", root, &[]).expect("composes");
    let program = wgsl::PROGRAMS[0];
    assert_eq!(program.root, "shadeballs::balls");
    let unused = unused_modules(&program, &composed.source, &composed.modules);
    assert_eq!(unused, ["shadeballs::walk"]);
}

#[test]
fn wgsl_mirrors_the_rust_function_names() {
    let all = format!(
        "{}{}",
        shaders::balls_source(false),
        shaders::probe_source()
    );
    let names = [
        "d_ggx",
        "g1_schlick",
        "g_schlick",
        "lambda_smith",
        "g1_smith",
        "g_smith",
        "g_smith_correlated",
        "f_schlick",
        "f_avg_schlick",
        "f_avg_games202",
        "f_ms",
        "f_add_accurate",
        "f_add_games202",
        "f_add_denominator",
        "f_add_preset",
        "alpha_from_roughness",
        "roughness_clamped",
        "f_micro",
        "lut_texel_span",
        "lut_e",
        "lut_e_avg",
        "lut_loss",
        "lut_loss_avg",
    ];
    for name in names {
        assert!(
            all.contains(&format!("fn {name}(")),
            "no `fn {name}(` in the WGSL"
        );
    }
}

#[test]
fn brdf_functions_cite_their_source() {
    let brdf = wgsl::module("shadeballs::brdf")
        .expect("the brdf module")
        .source;
    for (name, source) in [
        ("d_ggx", "Walter et al. 2007"),
        ("g1_schlick", "Schlick 1994"),
        ("lambda_smith", "Heitz 2014"),
        ("g1_smith", "Walter et al. 2007"),
        ("g_smith_correlated", "Heitz 2014"),
        ("f_schlick", "Schlick 1994"),
        ("f_avg_games202", "Gulbrandsen 2014"),
        ("f_ms", "Kulla & Conty 2017"),
        ("f_add_accurate", "Kulla & Conty 2017"),
    ] {
        let at = brdf.find(&format!("fn {name}(")).unwrap();
        let comment = &brdf[brdf[..at].rfind("\n\n").unwrap_or(0)..at];
        assert!(comment.contains(source), "{name} does not cite {source}");
    }
}

#[test]
fn naga_oil_takes_every_module_by_its_import_path() {
    // naga_oil parses each module with only what its `#import` lines name in scope, so a
    // module that uses a name it does not import fails here (the crate's own composer
    // only checks that the listed items exist).
    use naga_oil::compose::{ComposableModuleDescriptor, Composer};
    let mut composer = Composer::default();
    for module in wgsl::MODULES {
        composer
            .add_composable_module(ComposableModuleDescriptor {
                source: module.source,
                file_path: module.file,
                ..Default::default()
            })
            .unwrap_or_else(|e| panic!("{}: {e:?}", module.path));
    }
}
