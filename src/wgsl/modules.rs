//! The crate's WGSL modules by import path, and the programs the renderer composes from
//! them (each root with its shader defs). Included by the build script too (`build.rs`),
//! which composes every program at build time.

use super::compose::Module;

/// A module of `shaders/NAME.wgsl`, imported as `shadeballs::NAME`.
macro_rules! module {
    ($name:literal) => {
        Module {
            path: concat!("shadeballs::", $name),
            file: concat!($name, ".wgsl"),
            source: include_str!(concat!("../../shaders/", $name, ".wgsl")),
        }
    };
}

/// Every module, by import path. The library (no bindings, no override constants):
/// `constants`, `brdf`, `lut`, `environment`, `sampling`. The renderer's: `types` (override constants,
/// the boundary structs), `bindings` (groups 0 and 1), `clearcoat` (a clear coat over a ball), `coating` (the dielectric's shading), `model` (the whole
/// model's BRDF for the sampling estimators), `lighting`, `screen` (the vertex
/// stages, rays and output the ball renderer and the truth share), `footprint` (a pixel's
/// antialiased footprint and the background, the ball renderer's and the Monte Carlo's), and the roots `balls`,
/// `walk` (the truth), `montecarlo` (the model's Monte Carlo), `accumulate` (the lobe's
/// progressive image), `probe`, `prefilter`, and the viewer's `blit` and `difference`.
pub const MODULES: [Module; 21] = [
    module!("constants"),
    module!("brdf"),
    module!("lut"),
    module!("environment"),
    module!("sampling"),
    module!("types"),
    module!("bindings"),
    module!("clearcoat"),
    module!("coating"),
    module!("model"),
    module!("lighting"),
    module!("screen"),
    module!("footprint"),
    module!("balls"),
    module!("walk"),
    module!("montecarlo"),
    module!("accumulate"),
    module!("probe"),
    module!("prefilter"),
    module!("blit"),
    module!("difference"),
];

/// The shader def of the modules that write to an `Rgba32Uint` target: the fragment entry
/// points return the bits of linear radiance (`Colour` and `output_value` in `screen.wgsl`).
pub(crate) const OUTPUT_BITS: &str = "OUTPUT_BITS";

/// A program: a shader module the renderer creates, the composition of `root` under
/// `defs`; `name` is its file in the build's output (`NAME.wgsl`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Program {
    /// The file name in the build's output, without `.wgsl`.
    pub name: &'static str,
    /// The import path of the root module.
    pub root: &'static str,
    /// The shader defs it is composed under.
    pub defs: &'static [&'static str],
}

/// The ball renderer's module for float and display targets.
pub(crate) const BALLS: Program = Program {
    name: "balls",
    root: "shadeballs::balls",
    defs: &[],
};
/// The ball renderer's module for an `Rgba32Uint` target.
pub(crate) const BALLS_BITS: Program = Program {
    name: "balls_bits",
    root: "shadeballs::balls",
    defs: &[OUTPUT_BITS],
};
/// The truth's module (accumulation and resolve) for float and display targets.
pub(crate) const TRUTH: Program = Program {
    name: "truth",
    root: "shadeballs::walk",
    defs: &[],
};
/// The truth's module for an `Rgba32Uint` target (its resolve writes bits).
pub(crate) const TRUTH_BITS: Program = Program {
    name: "truth_bits",
    root: "shadeballs::walk",
    defs: &[OUTPUT_BITS],
};
/// The Monte Carlo of the model (`--backend montecarlo` on the GPU).
pub(crate) const MONTECARLO: Program = Program {
    name: "montecarlo",
    root: "shadeballs::montecarlo",
    defs: &[],
};
/// The lobe's progressive image: its frames summed on the GPU and their mean resolved.
pub(crate) const ACCUMULATE: Program = Program {
    name: "accumulate",
    root: "shadeballs::accumulate",
    defs: &[],
};
/// The lobe's progressive image for an `Rgba32Uint` target (its resolve writes bits).
pub(crate) const ACCUMULATE_BITS: Program = Program {
    name: "accumulate_bits",
    root: "shadeballs::accumulate",
    defs: &[OUTPUT_BITS],
};
/// The table probe.
pub(crate) const PROBE: Program = Program {
    name: "probe",
    root: "shadeballs::probe",
    defs: &[],
};
/// The environment prefilter (compute).
pub(crate) const PREFILTER: Program = Program {
    name: "prefilter",
    root: "shadeballs::prefilter",
    defs: &[],
};

/// The viewer's copy of its frame image into a GL window.
pub(crate) const BLIT: Program = Program {
    name: "blit",
    root: "shadeballs::blit",
    defs: &[],
};
/// The viewer's difference view of two scene images.
pub(crate) const DIFFERENCE: Program = Program {
    name: "difference",
    root: "shadeballs::difference",
    defs: &[],
};

/// Every program the build composes.
pub(crate) const PROGRAMS: [Program; 11] = [
    BALLS,
    BALLS_BITS,
    TRUTH,
    TRUTH_BITS,
    MONTECARLO,
    ACCUMULATE,
    ACCUMULATE_BITS,
    PROBE,
    PREFILTER,
    BLIT,
    DIFFERENCE,
];

/// The root of [`crate::wgsl::KULLA_CONTY`]: the library's functions and the table reads.
pub(crate) const KULLA_CONTY_ROOT: &str = "#import shadeballs::constants
#import shadeballs::brdf
#import shadeballs::lut
";
