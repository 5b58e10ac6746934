//! The library's one error type: a clear one-line message per case. The front end turns it
//! into a message on stderr and a non-zero exit code.

use std::path::PathBuf;

/// What went wrong: one variant per kind of failure, its `Display` the message.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A name that is none of an enum's values (a layout, a backend, ...).
    #[error("unknown {what} '{given}': expected one of {expected}")]
    UnknownName {
        /// What was being named ("layout", "backend", ...).
        what: &'static str,
        /// The name given.
        given: String,
        /// The valid names, comma-separated.
        expected: String,
    },

    /// A value out of its range (an image size, a probe grid, ...).
    #[error("invalid {what}: {message}")]
    Invalid {
        /// What the value is ("image size", "probe grid", ...).
        what: &'static str,
        /// Why it is invalid.
        message: String,
    },

    /// The cause is part of the message, not a `source`: the front end prints the error's
    /// chain, which would repeat it.
    #[error("cannot write '{}': {reason}", path.display())]
    Write {
        /// The file (or folder) that could not be written.
        path: PathBuf,
        /// The I/O error.
        reason: std::io::Error,
    },

    /// An image that could not be encoded for the file `path`.
    #[error("cannot encode '{}': {message}", path.display())]
    Encode {
        /// The file the image was for.
        path: PathBuf,
        /// The encoder's reason.
        message: String,
    },

    /// An output file whose extension names no format this writer knows.
    #[error("unsupported output file '{}': {expected}", path.display())]
    Format {
        /// The output file.
        path: PathBuf,
        /// The extensions accepted, as a phrase ("expected .png or .exr").
        expected: &'static str,
    },

    /// A scene file that cannot be read, parsed or validated; `message` names the line and
    /// column.
    #[error("scene file '{}': {message}", path.display())]
    Scene {
        /// The scene file.
        path: PathBuf,
        /// What is wrong, and where.
        message: String,
    },

    /// An environment map that cannot be read, or is not an equirectangular map this
    /// renderer takes; `message` is the reason, on one line.
    #[error("environment map '{}': {message}", path.display())]
    Environment {
        /// The map file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },

    /// No adapter for the requested backends.
    #[error("no GPU adapter for {backends}: {message}{}", no_adapter_hint(message))]
    NoAdapter {
        /// The backends asked for (`Debug` of `wgpu::Backends`).
        backends: String,
        /// wgpu's reason.
        message: String,
    },

    /// No window could be opened (no display server, or it refused).
    #[error("cannot open a window: {message}")]
    Display {
        /// The windowing system's reason.
        message: String,
    },

    /// A scene with truth balls on a device that cannot hold their sums: it does not
    /// render to `Rgba32Float` (GL).
    #[error("{device} cannot render to Rgba32Float, which the truth balls' sums need")]
    TruthUnsupported {
        /// The device ([`crate::Gpu::describe`]).
        device: String,
    },

    /// The GPU device reported an error (validation, out of memory, lost device).
    #[error("GPU error: {message}")]
    Gpu {
        /// The error, on one line.
        message: String,
    },
}

/// The library's result type: [`Error`] on failure.
pub type Result<T> = std::result::Result<T, Error>;

/// `message` on one line: its non-empty lines, trimmed, joined by ": " (by " " after a line
/// that already ends in ':'). Messages of other crates (wgpu, clap, toml) span several
/// lines; the front end reports one.
pub fn one_line(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    for line in message.lines().map(str::trim).filter(|l| !l.is_empty()) {
        if !out.is_empty() {
            out.push_str(if out.ends_with(':') { " " } else { ": " });
        }
        out.push_str(line);
    }
    out
}

/// Parses `given` as one of `all` by each value's `name`.
pub fn parse_named<T: Copy>(
    given: &str,
    all: &[T],
    name: impl Fn(T) -> &'static str,
    what: &'static str,
) -> Result<T> {
    all.iter()
        .copied()
        .find(|&v| name(v) == given)
        .ok_or_else(|| Error::UnknownName {
            what,
            given: given.to_string(),
            expected: all.iter().map(|&v| name(v)).collect::<Vec<_>>().join(", "),
        })
}

/// Implements `FromStr` and `Display` for an enum with `ALL` and `name()`, so scene files
/// parse the same names the program prints (the command line's `clap::ValueEnum` impls,
/// `value_enum!` in `cli/args.rs`, take the same `ALL` and `name()`).
#[macro_export]
macro_rules! named_enum {
    ($ty:ty, $what:literal) => {
        impl std::str::FromStr for $ty {
            type Err = $crate::error::Error;
            fn from_str(s: &str) -> $crate::error::Result<Self> {
                $crate::error::parse_named(s, &<$ty>::ALL, <$ty>::name, $what)
            }
        }
        impl std::fmt::Display for $ty {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}

/// What [`Error::NoAdapter`] adds to wgpu's reason: where lavapipe is packaged, unless the
/// reason already says that memory was short (`gpu::Gpu::new` adds
/// [`crate::memory::short_for_driver`]'s line: issue 38, 8, where the package was advised
/// to a run under `ulimit -v`).
fn no_adapter_hint(message: &str) -> &'static str {
    if message.contains(SHORT_OF_MEMORY) {
        ""
    } else {
        "; software Vulkan (lavapipe) is in the package mesa-vulkan-drivers"
    }
}

/// The words of [`crate::memory::short_for_driver`] that [`Error::NoAdapter`]'s message and the
/// command line's advice look for.
pub(crate) const SHORT_OF_MEMORY: &str = "for want of memory";

/// A number for a message, in the shortest form that reads back as it (`{:?}`), but with an
/// exponent from 1e6 up and below 1e-4 (`1e13`, not `10000000000000.0`; issue 38, 9).
pub(crate) fn short_number(v: f64) -> String {
    let a = v.abs();
    if a.is_finite() && a != 0.0 && !(1e-4..1e6).contains(&a) {
        format!("{v:e}")
    } else {
        format!("{v:?}")
    }
}

/// [`short_number`] of each component: `[1e13, 0.0, 0.0]`.
pub(crate) fn short_numbers(v: &[f64]) -> String {
    let parts: Vec<String> = v.iter().map(|&c| short_number(c)).collect();
    format!("[{}]", parts.join(", "))
}
