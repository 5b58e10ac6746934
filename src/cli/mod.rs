//! The `shadeballs` command line (feature `cli`): one file per subcommand, each parsing
//! nothing itself (the flags are in `args.rs`), calling the library, and reporting on
//! stderr. The binary (`src/main.rs`) only sets up the process ([`process::init`]) and
//! calls [`main`]. The lab's binary (`shadeballs-lab`, lab/) shares the scene's flags
//! ([`SceneArgs`]), the process set-up, [`one_line_error`] and
//! [`advice`].

mod args;
mod bake;
mod environment;
mod export;
mod guard;
pub(crate) mod import;
pub(crate) mod interrupt;
mod probe;
pub mod process;
pub mod progress;
mod render;
mod view;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

pub use args::*;

#[derive(Parser)]
#[command(
    name = "shadeballs",
    version,
    about = "Shading balls for the Kulla-Conty multiple-scattering BRDF"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Bake E(mu, roughness) and E_avg(roughness) and write them to a file.
    Bake(BakeArgs),
    /// Write a built-in environment map (studio, sky, white) to .exr or .hdr.
    Environment(EnvironmentArgs),
    /// Render the shading balls (GPU, or the CPU reference renderer) to .png or .exr.
    Render(RenderArgs),
    /// Write the ball shading (GGX, the Kulla-Conty term, the coating, the table reads) as
    /// WGSL, GLSL, HLSL or MSL with a fragment entry point that shades one ball.
    ExportShader(export::ExportShaderArgs),
    /// Read a glTF 2.0 file's materials (and its spheres' places) into a scene file.
    Import(import::ImportArgs),
    /// Evaluate on the GPU what the shader reads from the tables on an N x N grid (CSV).
    Probe(ProbeArgs),
    /// Open a window showing the shading balls, with a panel to change them live.
    View(ViewArgs),
}

/// The backend names wgpu reads from `WGPU_BACKEND` (`wgpu::Backends::from_comma_list`,
/// which drops any other name with only a log line, leaving no backend at all).
const WGPU_BACKEND_NAMES: [&str; 11] = [
    "vulkan", "vk", "gl", "gles", "opengl", "dx12", "d3d12", "metal", "mtl", "webgpu", "noop",
];

/// Checks `WGPU_BACKEND` where `--backend auto` honours it: a name wgpu does not know
/// would leave no backend, and the error would then advise installing a driver.
pub fn check_wgpu_backend_env(backend: crate::gpu::Backend) -> crate::Result<()> {
    use crate::gpu::Backend;
    if !matches!(backend, Backend::Auto | Backend::Montecarlo) {
        return Ok(());
    }
    let Some(value) = std::env::var_os("WGPU_BACKEND") else {
        return Ok(());
    };
    let value = value.to_string_lossy();
    let known = |name: &str| WGPU_BACKEND_NAMES.contains(&name.trim().to_lowercase().as_str());
    if !value.split(',').all(known) {
        return Err(crate::Error::Invalid {
            what: "environment",
            message: format!(
                "WGPU_BACKEND='{value}' is not a backend: use vulkan or gl (or a comma-separated \
                 list of {}), or unset it",
                WGPU_BACKEND_NAMES.join(", ")
            ),
        });
    }
    Ok(())
}

/// Writes `text` and a newline to stdout; a reader that closed the pipe (`| head`) is not
/// an error worth a panic (`println!` panics on it).
pub fn print_stdout(text: &str) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stdout().lock(), "{text}");
}

/// Parses `std::env::args`, runs the subcommand and turns its error into one line on stderr
/// and the exit code (2 for bad flags, 1 for a failed run).
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => match one_line_error(&e) {
            Some(line) => {
                eprintln!("{line}");
                return ExitCode::from(2);
            }
            None => e.exit(),
        },
    };
    let result = match cli.command {
        Command::Bake(args) => bake::run(args),
        Command::Environment(args) => environment::run(args),
        Command::Render(args) => render::run(args),
        Command::Import(args) => import::run(args),
        Command::ExportShader(args) => export::run(args),
        Command::Probe(args) => probe::run(args),
        Command::View(args) => view::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if e.is::<interrupt::Interrupted>() => {
            // What was rendered is written: the one line says where, the status why.
            let status = e
                .downcast_ref::<interrupt::Interrupted>()
                .map_or(1, interrupt::Interrupted::exit_status);
            eprintln!("error: {e}");
            ExitCode::from(status)
        }
        Err(e) => {
            let advice = advice(&e).map_or(String::new(), |a| format!(" ({a})"));
            eprintln!(
                "error: {}{advice}",
                crate::error::one_line(&format!("{e:#}"))
            );
            ExitCode::FAILURE
        }
    }
}

/// What the user can do about a library error, in the command line's words: the library's
/// messages state what happened, the front end names the flag or command that helps.
pub fn advice(e: &anyhow::Error) -> Option<&'static str> {
    use crate::Error;
    match e.chain().find_map(|c| c.downcast_ref::<Error>())? {
        // Issue 38, 8: under a memory limit the driver fails for want of memory, not of a
        // package.
        Error::NoAdapter { message, .. } if message.contains(crate::error::SHORT_OF_MEMORY) => {
            Some("raise the memory limit (ulimit -v, the cgroup), or use --backend cpu")
        }
        Error::NoAdapter { .. } => Some("install it, or use --backend cpu"),
        // A device lost (or another GPU failure) with memory short: say so.
        Error::Gpu { .. } if crate::memory::short_for_driver().is_some() => Some(
            "less than 1 GB of memory is available: the device may have failed for want of \
             memory; raise the limit (ulimit -v, the cgroup) or choose a smaller size",
        ),
        Error::TruthUnsupported { .. } => Some("use --backend vulkan"),
        Error::Display { .. } => {
            Some("without a display, `shadeballs render` draws the same scene to a PNG")
        }
        Error::Invalid {
            what: "samples per pixel",
            ..
        } => Some("set with --spp"),
        Error::Invalid {
            what: "standard error",
            ..
        } => Some("set with --stderr"),
        _ => None,
    }
}

/// Each notice of a glTF import on stderr, one line each (`import`, and `render` / `view`
/// with `--scene FILE.gltf`).
pub(crate) fn print_import_notices(imported: &crate::import::Imported) {
    for n in &imported.notices {
        eprintln!("notice: {}", crate::error::one_line(n));
    }
}
