//! The crate's WGSL, as modules and as one flat library.
//!
//! Each file under `shaders/` is a module with an import path (`shadeballs::brdf`, ...)
//! that says what it needs with `#import` lines, in the dialect of naga_oil (Bevy's
//! shader composer): [`MODULES`] lists them, [`compose`] resolves a root's imports and
//! shader defs into plain WGSL (the crate's own programs are composed so at build time).
//!
//! [`KULLA_CONTY`] is a WGSL library with no bindings and no override constants: the BRDF
//! terms (`d_ggx`, `geometry_g`, `f_schlick`, `f_micro`, `f_ms`, `f_add_preset`, ...: the
//! f32 twins of [`crate::brdf`], name for name) and the table reads (`lut_loss`, `lut_e`,
//! `lut_loss_avg`, `lut_e_avg`: the f32 twins of [`crate::lut::Tables`]' reads), each taking
//! the table textures and their [`crate::lut::LutParams`] as arguments. naga has no
//! `#include`: put the library before your own shader text.
//!
//! With naga_oil (the composer of Bevy's shader system), add the modules ([`module`],
//! [`LIBRARY`]) and import them by path instead (the example below is a doctest with the
//! feature `naga-oil`).
//!
#![cfg_attr(
    feature = "naga-oil",
    doc = r##"```
use naga_oil::compose::{ComposableModuleDescriptor, Composer, NagaModuleDescriptor};

let mut composer = Composer::default();
// The library's modules, each after those it imports.
for path in shadeballs::wgsl::LIBRARY {
    let module = shadeballs::wgsl::module(path).expect("a module of the crate");
    composer
        .add_composable_module(ComposableModuleDescriptor {
            source: module.source,
            file_path: module.file,
            ..Default::default()
        })
        .expect("naga_oil takes the module");
}
let host = r#"
#import shadeballs::constants::LutParams
#import shadeballs::lut::{lut_e, lut_e_avg}

@group(0) @binding(0) var<uniform> params: LutParams;
@group(0) @binding(1) var e_table: texture_2d<f32>;
@group(0) @binding(2) var e_avg_table: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    let e = lut_e(e_table, params, p.x / 256.0, 0.5);
    return vec4<f32>(e, lut_e_avg(e_avg_table, params, 0.5), 0.0, 1.0);
}
"#;
let module = composer
    .make_naga_module(NagaModuleDescriptor {
        source: host,
        file_path: "host.wgsl",
        ..Default::default()
    })
    .expect("composes");
naga::valid::Validator::new(Default::default(), naga::valid::Capabilities::all())
    .validate(&module)
    .expect("validates");
```

"##
)]
//! As one flat text:
//!
//! ```
//! let source = format!(
//!     "{}\n{}",
//!     shadeballs::wgsl::KULLA_CONTY,
//!     r#"
//! @group(0) @binding(0) var<uniform> params: LutParams;
//! @group(0) @binding(1) var e_table: texture_2d<f32>;
//! @group(0) @binding(2) var e_avg_table: texture_2d<f32>;
//!
//! @fragment
//! fn fs_main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
//!     let mu = p.x / 256.0;
//!     let e = lut_e(e_table, params, mu, 0.5);
//!     let e_avg = lut_e_avg(e_avg_table, params, 0.5);
//!     return vec4<f32>(e, e_avg, 0.0, 1.0);
//! }
//! "#
//! );
//! // The text wgpu's `create_shader_module` takes; naga (wgpu's shader compiler) accepts it.
//! let module = naga::front::wgsl::parse_str(&source).expect("parses");
//! naga::valid::Validator::new(Default::default(), naga::valid::Capabilities::all())
//!     .validate(&module)
//!     .expect("validates");
//! ```

mod compose;
pub(crate) mod export;
// The programs (build.rs composes them, the tests read them) and the modules.
#[allow(dead_code)]
mod modules;
#[cfg(all(test, feature = "cli"))]
mod tests;

pub use compose::ComposeError;
pub use compose::Composed;
pub use compose::Module;
#[cfg(test)]
pub(crate) use modules::Program;
pub use modules::MODULES;
#[cfg(test)]
pub(crate) use modules::{OUTPUT_BITS, PROGRAMS};

/// The WGSL library, composed at build time from `shadeballs::constants` (the constants
/// and `struct LutParams`), `shadeballs::brdf` (the BRDF terms) and `shadeballs::lut` (the
/// table reads), in that order, their directive lines removed.
pub const KULLA_CONTY: &str = include_str!(concat!(env!("OUT_DIR"), "/kulla_conty.wgsl"));

/// The import paths of [`KULLA_CONTY`]'s modules, in order.
pub const LIBRARY: [&str; 3] = [
    "shadeballs::constants",
    "shadeballs::brdf",
    "shadeballs::lut",
];

/// Composes `root` (the text of `file`, with `#import` lines of [`MODULES`]) under the
/// shader defs `defs`: every module it needs, each once, before it, as plain WGSL.
pub fn compose(file: &str, root: &str, defs: &[&str]) -> Result<Composed, ComposeError> {
    compose::compose(file, root, defs, &MODULES)
}

/// Composes the module of import path `path` as a program's root under `defs`.
pub fn compose_module(path: &str, defs: &[&str]) -> Result<Composed, ComposeError> {
    compose::compose_module(path, defs, &MODULES)
}

/// The module of import path `path`.
pub fn module(path: &str) -> Option<&'static Module> {
    MODULES.iter().find(|m| m.path == path)
}
