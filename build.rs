//! Composes the crate's WGSL programs (`src/wgsl/modules.rs` PROGRAMS) and the flat
//! library `wgsl::KULLA_CONTY` into `OUT_DIR`, with the composer the library itself runs
//! (`src/wgsl/compose.rs`): a broken import fails the build, and the renderer creates its
//! shader modules from text composed once.

use std::path::Path;

#[allow(dead_code)]
#[path = "src/wgsl/compose.rs"]
mod compose;
#[allow(dead_code)]
#[path = "src/wgsl/modules.rs"]
mod modules;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=shaders");
    println!("cargo:rerun-if-changed=src/wgsl/compose.rs");
    println!("cargo:rerun-if-changed=src/wgsl/modules.rs");
    let Some(out) = std::env::var_os("OUT_DIR") else {
        eprintln!("error: cargo sets no OUT_DIR");
        std::process::exit(1);
    };
    let out = Path::new(&out);
    let mut outputs = Vec::new();
    for program in modules::PROGRAMS {
        let composed = compose::compose_module(program.root, program.defs, &modules::MODULES);
        outputs.push((program.name, composed));
    }
    let library = compose::compose(
        "kulla_conty",
        modules::KULLA_CONTY_ROOT,
        &[],
        &modules::MODULES,
    );
    outputs.push(("kulla_conty", library));
    for (name, composed) in outputs {
        let written = composed.map_err(|e| e.to_string()).and_then(|c| {
            std::fs::write(out.join(format!("{name}.wgsl")), c.source).map_err(|e| e.to_string())
        });
        if let Err(e) = written {
            eprintln!("error: the WGSL program `{name}`: {e}");
            std::process::exit(1);
        }
    }
}
