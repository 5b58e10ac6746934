//! The WGSL programs, composed as the pipelines get them, parse and validate with naga (no
//! GPU needed), import only modules their pipelines use, and mirror the Rust functions name
//! for name.
use std::collections::BTreeSet;

use crate::gpu::shaders;
use crate::wgsl::{self, Program, PROGRAMS};

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

/// The items module `path` declares itself: those of its composition under `defs` less
/// those of its imports'.
fn own_items(path: &str, defs: &[&str]) -> BTreeSet<String> {
    let alone = wgsl::compose_module(path, defs).expect("the module composes");
    let mut names = items(&parse(path, &alone.source), true);
    for dep in alone.modules.iter().filter(|d| **d != path) {
        let dep = wgsl::compose_module(dep, defs).expect("the module composes");
        for n in items(&parse(path, &dep.source), true) {
            names.remove(&n);
        }
    }
    names
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
    modules
        .iter()
        .filter(|m| own_items(m, program.defs).is_disjoint(&reachable))
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
        "fresnel_dielectric",
        "f0_from_ior",
        "f_base_constant",
        "f_base_gltf",
        "f_base_view_only",
        "f_base_reciprocal",
        "coating_inside_reflectance",
        "f_base_physical",
        "substrate_albedo",
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
        ("fresnel_dielectric", "Walter et al. 2007"),
        ("f_base_gltf", "glTF 2.0"),
        ("f_base_view_only", "Principled v2"),
        ("f_base_reciprocal", "OpenPBR"),
    ] {
        let at = brdf.find(&format!("fn {name}(")).unwrap();
        let comment = &brdf[brdf[..at].rfind("\n\n").unwrap_or(0)..at];
        assert!(comment.contains(source), "{name} does not cite {source}");
    }
}

/// naga_oil's composition of `program`: every module its root needs added (each after
/// its imports), then the root, under the program's defs.
#[cfg(feature = "naga-oil")]
fn naga_oil_compose(program: &Program) -> naga::Module {
    use naga_oil::compose::{
        ComposableModuleDescriptor, Composer, NagaModuleDescriptor, ShaderDefValue,
    };
    let defs = || {
        program
            .defs
            .iter()
            .map(|d| (d.to_string(), ShaderDefValue::Bool(true)))
            .collect()
    };
    let composed = wgsl::compose_module(program.root, program.defs).expect("composes");
    let (root, imports) = composed.modules.split_last().expect("a root");
    let mut composer = Composer::default();
    for path in imports {
        let module = wgsl::module(path).expect("a module");
        composer
            .add_composable_module(ComposableModuleDescriptor {
                source: module.source,
                file_path: module.file,
                shader_defs: defs(),
                ..Default::default()
            })
            .unwrap_or_else(|e| panic!("{path}: {e:?}"));
    }
    let root = wgsl::module(root).expect("the root module");
    composer
        .make_naga_module(NagaModuleDescriptor {
            source: root.source,
            file_path: root.file,
            shader_defs: defs(),
            ..Default::default()
        })
        .unwrap_or_else(|e| panic!("{}: {e:?}", program.name))
}

#[cfg(feature = "naga-oil")]
#[test]
fn naga_oil_composes_the_programs_without_pipeline_overrides() {
    // naga_oil parses each module with only what its `#import` lines name in scope, and
    // checks that its own round trip through WGSL keeps every name. naga_oil 0.23 does
    // not carry an `override` declaration into the modules that import it (its
    // `import_pipeline_override` is gated on the module's functions), so only the programs
    // that import no override compose with it: the prefilter, and the library's modules
    // under a host's root (the doctest of `crate::wgsl`).
    let composable: Vec<Program> = PROGRAMS
        .into_iter()
        .filter(|p| p.name == "prefilter")
        .collect();
    assert_eq!(composable.len(), 1);
    for program in composable {
        let module = naga_oil_compose(&program);
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::all(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}: {e:?}", program.name));
        for entry in shaders::entry_points(&program) {
            assert!(
                module.entry_points.iter().any(|e| e.name == *entry),
                "{}: naga_oil's module lacks {entry}",
                program.name
            );
        }
    }
}

/// The identifiers `source` uses outside comments and directive lines, member accesses
/// (`.name`) left out.
fn used_identifiers(source: &str) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    for line in source.lines() {
        let code = line.split("//").next().unwrap_or("");
        if code.trim_start().starts_with('#') {
            continue;
        }
        let mut previous = ' ';
        let mut word = String::new();
        for c in code.chars().chain([' ']) {
            if c.is_ascii_alphanumeric() || c == '_' {
                if word.is_empty() && previous == '.' {
                    word.push('.');
                }
                word.push(c);
            } else {
                if !word.is_empty() && !word.starts_with('.') {
                    found.insert(word.clone());
                }
                word.clear();
                previous = c;
            }
        }
    }
    found
}

/// What `source`'s `#import` lines take from module `path`: `None` if nothing, `Some` of
/// the items (empty: the whole module).
fn imported_from(source: &str, path: &str) -> Option<Vec<String>> {
    let mut taken: Option<Vec<String>> = None;
    for line in source.lines() {
        let Some(spec) = line.trim().strip_prefix("#import ") else {
            continue;
        };
        let spec = spec.trim();
        let items: Vec<String> = if spec == path {
            Vec::new()
        } else if let Some(list) = spec.strip_prefix(&format!("{path}::{{")) {
            list.trim_end_matches('}')
                .split(',')
                .map(|i| i.trim().to_string())
                .collect()
        } else if let Some(item) = spec.strip_prefix(&format!("{path}::")) {
            vec![item.to_string()]
        } else {
            continue;
        };
        let all = taken.get_or_insert_with(Vec::new);
        if items.is_empty() {
            *all = Vec::new();
            return taken;
        }
        all.extend(items);
    }
    taken
}

/// The items of other modules `source` (the text of module `path`) uses without
/// importing them, under either output def.
fn missing_imports(path: &str, source: &str) -> Vec<String> {
    let used = used_identifiers(source);
    let mut missing = Vec::new();
    for defs in [&[][..], &[wgsl::OUTPUT_BITS][..]] {
        let composed = wgsl::compose_module(path, defs).expect("composes");
        for dep in composed.modules.iter().filter(|d| **d != path) {
            let taken = imported_from(source, dep);
            for item in own_items(dep, defs).intersection(&used) {
                let ok = taken
                    .as_ref()
                    .is_some_and(|t| t.is_empty() || t.contains(item));
                let what = format!("{path} uses {dep}::{item}");
                if !ok && !missing.contains(&what) {
                    missing.push(what);
                }
            }
        }
    }
    missing
}

#[test]
fn every_module_imports_each_name_it_uses() {
    // What naga_oil requires (each module parsed with only what it imports in scope),
    // checked by name: an item of another module the file uses must be imported.
    let missing: Vec<String> = wgsl::MODULES
        .iter()
        .flat_map(|m| missing_imports(m.path, m.source))
        .collect();
    assert!(missing.is_empty(), "not imported: {missing:?}");
    // Control: brdf.wgsl without LAMBDA_MAX in its import list.
    let brdf = wgsl::module("shadeballs::brdf").expect("brdf").source;
    let cut = brdf.replace(", LAMBDA_MAX}", "}");
    assert_ne!(cut, brdf, "brdf.wgsl's imports moved: update this test");
    assert_eq!(
        missing_imports("shadeballs::brdf", &cut),
        ["shadeballs::brdf uses shadeballs::constants::LAMBDA_MAX"]
    );
}
