//! Ctrl-C during a render that can stop cleanly (`render --backend truth`): the binary's
//! signal thread ([`request_stop`]) asks it to stop after its pass instead of exiting; the
//! render then writes what it has, says how many samples a pixel that is, and the command
//! exits with 128 + the signal's number ([`Interrupted`]), as a shell reports an
//! interrupted process. A second signal, or one while nothing can stop cleanly, exits at
//! once (the binary removes the unfinished files).

use std::path::PathBuf;
use std::sync::atomic::{AtomicI32, AtomicUsize, Ordering};

/// Renders running now that stop cleanly at a signal.
static STOPPABLE: AtomicUsize = AtomicUsize::new(0);
/// The signal that asked them to stop (0: none).
static STOP: AtomicI32 = AtomicI32::new(0);

/// Held while a render that stops cleanly runs.
pub(crate) struct Stoppable(());

impl Stoppable {
    /// Marks a render that stops cleanly as running.
    pub(crate) fn start() -> Self {
        STOPPABLE.fetch_add(1, Ordering::SeqCst);
        Stoppable(())
    }
}

impl Drop for Stoppable {
    fn drop(&mut self) {
        STOPPABLE.fetch_sub(1, Ordering::SeqCst);
    }
}

/// For the binary's signal thread: whether a render takes `signal` as a request to stop
/// after its pass (true only for the first signal while one runs); false: exit now.
pub(crate) fn request_stop(signal: i32) -> bool {
    STOPPABLE.load(Ordering::SeqCst) > 0
        && STOP
            .compare_exchange(0, signal, Ordering::SeqCst, Ordering::SeqCst)
            .is_ok()
}

/// The signal that asked the render to stop, if one did.
pub(crate) fn stop_requested() -> Option<i32> {
    match STOP.load(Ordering::SeqCst) {
        0 => None,
        s => Some(s),
    }
}

/// The name of signal `signal` (`SIGINT`, `SIGTERM`, else its number).
pub(crate) fn signal_name(signal: i32) -> String {
    match signal {
        2 => "SIGINT".to_string(),
        15 => "SIGTERM".to_string(),
        s => format!("signal {s}"),
    }
}

/// A render stopped by a signal after writing what it had: the command's error (one line)
/// and its exit status, 128 + the signal's number.
#[derive(Debug)]
pub(crate) struct Interrupted {
    /// The signal.
    pub signal: i32,
    /// Samples a pixel in the image written.
    pub spp: u32,
    /// The image written.
    pub out: PathBuf,
}

impl Interrupted {
    /// The exit status: 128 + the signal's number.
    pub(crate) fn exit_status(&self) -> u8 {
        (128 + self.signal).clamp(0, 255) as u8
    }
}

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "interrupted by {} after {} spp: {} holds the {} spp rendered so far",
            signal_name(self.signal),
            self.spp,
            self.out.display(),
            self.spp
        )
    }
}

impl std::error::Error for Interrupted {}
