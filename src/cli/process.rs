//! The process around a command line (the `shadeballs` binary's and the lab's): Mesa's
//! runtime folder, the clean-up of temporary files on SIGINT and SIGTERM, logging, the worker
//! threads.

use std::path::PathBuf;

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

/// On SIGINT (Ctrl-C) or SIGTERM, unless a render that stops cleanly takes it
/// (`cli::interrupt`): remove the temporary files of writes in flight (a 4096 x
/// 4096 table or an 8192 x 8192 image is hundreds of MB), say so in one line, and exit
/// with 128 + the signal's number (130, 143), as a shell reports a process it interrupted.
/// A thread reads the signals, so the removal runs outside any signal handler.
#[cfg(unix)]
fn clean_up_on_interrupt() {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) else {
        return;
    };
    let spawned = std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            for signal in signals.forever() {
                // A render that stops cleanly (the CPU truth) finishes its pass and writes what
                // it has; a second signal exits at once.
                if super::interrupt::request_stop(signal) {
                    eprintln!(
                        "\n{}: stopping after this pass to write what is rendered (again to quit \
                     at once)",
                        super::interrupt::signal_name(signal)
                    );
                    continue;
                }
                let removed = crate::output::remove_temp_files_in_flight();
                let name = if signal == SIGINT {
                    "SIGINT"
                } else {
                    "SIGTERM"
                };
                eprintln!(
                    "error: interrupted by {name}{}",
                    match removed {
                        0 => String::new(),
                        n => format!("; removed {n} unfinished output file(s)"),
                    }
                );
                std::process::exit(128 + signal);
            }
        });
    if let Err(e) = spawned {
        cannot_start("the thread that cleans up on interrupt", e);
    }
}

#[cfg(not(unix))]
fn clean_up_on_interrupt() {}

/// Starts the worker threads that the bake, the built-in maps and the CPU renderers share
/// (rayon's global pool) while the process is still small. Left to the first parallel
/// loop, the pool started after a GPU driver had mapped hundreds of MB of address space,
/// and under `ulimit -v` of 100 or 300 MB its threads sometimes could not start: rayon
/// panicked there (`messages_under_memory_limits_name_the_memory` failed in one CI run of
/// several). A pool that cannot start even here is one line and exit status 1.
fn start_worker_threads() {
    if let Err(e) = rayon::ThreadPoolBuilder::new().build_global() {
        cannot_start("the worker threads", e);
    }
}

/// The system's allocator, with an allocation that fails a one-line error and exit status
/// 1 ([`out_of_memory`]) where Rust would abort with "memory allocation of N bytes failed"
/// and a killed process: under `ulimit -v` of 100 MB a GPU driver that starts can leave too
/// little for the built-in map's 6 MiB (`messages_under_memory_limits_name_the_memory`
/// failed so in one CI run). The binary installs it (`src/main.rs`); the library leaves a
/// host's allocator alone.
pub struct ExitsWhenShortOfMemory;

// SAFETY: every method forwards to `System` under the caller's own contract, and only looks
// at the returned pointer.
unsafe impl std::alloc::GlobalAlloc for ExitsWhenShortOfMemory {
    unsafe fn alloc(&self, layout: std::alloc::Layout) -> *mut u8 {
        // SAFETY: the caller's contract for `alloc` is `System`'s.
        let p = unsafe { std::alloc::System.alloc(layout) };
        if p.is_null() {
            out_of_memory(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: std::alloc::Layout) -> *mut u8 {
        // SAFETY: as `alloc`.
        let p = unsafe { std::alloc::System.alloc_zeroed(layout) };
        if p.is_null() {
            out_of_memory(layout.size());
        }
        p
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: std::alloc::Layout, new_size: usize) -> *mut u8 {
        // SAFETY: as `alloc`: `ptr` and `layout` are the caller's, from this allocator.
        let p = unsafe { std::alloc::System.realloc(ptr, layout, new_size) };
        if p.is_null() {
            out_of_memory(new_size);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: std::alloc::Layout) {
        // SAFETY: `ptr` came from this allocator, that is from `System`, with `layout`.
        unsafe { std::alloc::System.dealloc(ptr, layout) }
    }
}

/// An allocation of `size` bytes failed: the unfinished output files removed where the
/// list is free, one line (formatted on the stack: nothing more is allocated for it), exit
/// status 1. A second failure on the way (the removal allocates a path) exits at once.
fn out_of_memory(size: usize) -> ! {
    use std::io::Write;
    use std::sync::atomic::{AtomicBool, Ordering};
    static EXITING: AtomicBool = AtomicBool::new(false);
    if !EXITING.swap(true, Ordering::SeqCst) {
        let mut line = [0u8; 256];
        let mut rest = &mut line[..];
        let _ = writeln!(
            rest,
            "error: an allocation of {size} bytes failed, {}; raise the limit (ulimit -v, the \
             cgroup) or choose a smaller size",
            crate::error::SHORT_OF_MEMORY
        );
        let written = 256 - rest.len();
        let _ = std::io::stderr().write_all(&line[..written]);
        crate::output::try_remove_temp_files_in_flight();
    }
    std::process::exit(1);
}

/// A thread the process needs could not start (`what`, the error `e`): one line, exit
/// status 1, where the standard library and rayon would panic.
pub(crate) fn cannot_start(what: &str, e: impl std::fmt::Display) -> ! {
    eprintln!(
        "error: {what} could not start, {} or of threads ({e}); raise the limit (ulimit -v, \
         ulimit -u, the cgroup)",
        crate::error::SHORT_OF_MEMORY
    );
    std::process::exit(1);
}

/// Sets up the process: Mesa's runtime folder, the clean-up on interrupt, `log` through
/// env_logger (warnings by default, `RUST_LOG` to choose: `RUST_LOG=wgpu=info`; wgpu, naga
/// and the drivers log through `log`) and the worker threads. Call it first, before any
/// thread exists.
pub fn init() {
    give_mesa_a_runtime_dir();
    clean_up_on_interrupt();
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn"))
        .format_timestamp(None)
        .init();
    start_worker_threads();
}
