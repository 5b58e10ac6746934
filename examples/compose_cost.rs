//! What composing the crate's WGSL programs costs at start-up: the crate's own composer
//! (`shadeballs::wgsl::compose_module`, which the build runs once so the renderer pays
//! nothing at run time) against naga_oil (Bevy's composer) composing the same roots from the
//! same module files, each then parsed by naga as wgpu's `create_shader_module` does with
//! WGSL text. The medians of `--runs` runs (default 20), in milliseconds. naga_oil 0.23
//! composes only the programs that import no `override` declaration (the prefilter; see
//! tests/suite/shaders.rs), and says so for the others.
//!
//! ```text
//! cargo run --release --example compose_cost [-- --runs N]
//! ```

use std::time::Instant;

use naga_oil::compose::{ComposableModuleDescriptor, Composer, NagaModuleDescriptor};
use shadeballs::wgsl::{self, Program};

fn median_ms(runs: usize, mut f: impl FnMut()) -> f64 {
    let mut times: Vec<f64> = (0..runs)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// naga_oil's composition of `program`: every module the root needs added, then the root.
fn naga_oil_compose(program: &Program) -> Result<naga::Module, String> {
    let composed = wgsl::compose_module(program.root, program.defs).map_err(|e| e.to_string())?;
    let mut composer = Composer::default();
    let defs = program
        .defs
        .iter()
        .map(|d| (d.to_string(), naga_oil::compose::ShaderDefValue::Bool(true)))
        .collect();
    let (root, imports) = composed.modules.split_last().ok_or("no root module")?;
    for path in imports {
        let module = wgsl::module(path).ok_or("unknown module")?;
        composer
            .add_composable_module(ComposableModuleDescriptor {
                source: module.source,
                file_path: module.file,
                shader_defs: program
                    .defs
                    .iter()
                    .map(|d| (d.to_string(), naga_oil::compose::ShaderDefValue::Bool(true)))
                    .collect(),
                ..Default::default()
            })
            .map_err(|e| format!("{path}: {e:?}"))?;
    }
    let root = wgsl::module(root).ok_or("unknown root")?;
    composer
        .make_naga_module(NagaModuleDescriptor {
            source: root.source,
            file_path: root.file,
            shader_defs: defs,
            ..Default::default()
        })
        .map_err(|e| format!("{}: {e:?}", root.path))
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let runs = match args.iter().position(|a| a == "--runs") {
        Some(i) => match args.get(i + 1).and_then(|n| n.parse::<usize>().ok()) {
            Some(n) if n > 0 => n,
            _ => {
                eprintln!("error: --runs takes a positive count");
                std::process::exit(2);
            }
        },
        None => 20,
    };
    println!("program      ours: compose  + naga parse   naga_oil: compose (parses itself)");
    for program in wgsl::PROGRAMS {
        let ours = median_ms(runs, || {
            let _ = wgsl::compose_module(program.root, program.defs);
        });
        let text = wgsl::compose_module(program.root, program.defs)
            .map(|c| c.source)
            .unwrap_or_default();
        let parse = median_ms(runs, || {
            let _ = naga::front::wgsl::parse_str(&text);
        });
        let oil = match naga_oil_compose(&program) {
            Ok(_) => format!(
                "{:8.3}",
                median_ms(runs, || drop(naga_oil_compose(&program)))
            ),
            Err(e) => format!("fails: {}", e.chars().take(60).collect::<String>()),
        };
        println!("{:12} {ours:8.3}     {parse:8.3}       {oil}", program.name);
    }
}
