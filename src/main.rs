//! The `shadeballs` binary: sets up the process (Mesa's runtime folder, logging) and runs
//! the command line ([`shadeballs::cli`]).

use std::path::PathBuf;
use std::process::ExitCode;

/// Mesa's drivers print "error: XDG_RUNTIME_DIR is invalid or not set" on every start
/// without a private runtime folder, which reads like a failure. When none is set, point
/// it at a 0700 folder of this user's under the temp folder. Runs first, before any thread exists.
#[cfg(unix)]
fn give_mesa_a_runtime_dir() {
    use std::os::unix::fs::{MetadataExt, PermissionsExt};
    let usable = std::env::var_os("XDG_RUNTIME_DIR")
        .map(PathBuf::from)
        .is_some_and(|d| d.is_dir());
    if usable {
        return;
    }
    // One folder per user, reused by every run (the uid of this process owns /proc/self).
    let uid = std::fs::metadata("/proc/self")
        .map(|m| m.uid())
        .unwrap_or(0);
    let dir = std::env::temp_dir().join(format!("shadeballs-runtime-{uid}"));
    let made = std::fs::create_dir_all(&dir)
        .and_then(|_| std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o700)));
    if made.is_ok() {
        std::env::set_var("XDG_RUNTIME_DIR", &dir);
    }
}

#[cfg(not(unix))]
fn give_mesa_a_runtime_dir() {}

fn main() -> ExitCode {
    give_mesa_a_runtime_dir();
    // wgpu, naga and the drivers log through `log`: warnings by default, `RUST_LOG` to
    // choose (`RUST_LOG=wgpu=info`).
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn"))
        .format_timestamp(None)
        .init();
    shadeballs::cli::main()
}
