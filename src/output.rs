//! Output files: every write is atomic (the bytes go to a temporary file beside the target,
//! which is renamed over it only once complete, so a failed write leaves nothing
//! half-written), and rendered images are `.png` (tone-mapped 8-bit, gamma 1/2.2 applied in
//! the renderer) or `.exr` (linear radiance before exposure and tone mapping).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use crate::error::{Error, Result};

fn write_error(path: &Path, reason: std::io::Error) -> Error {
    Error::Write {
        path: path.to_path_buf(),
        reason,
    }
}

fn invalid(path: &Path, why: &str) -> Error {
    write_error(
        path,
        std::io::Error::new(std::io::ErrorKind::InvalidInput, why.to_string()),
    )
}

/// Temporary files being written now, so that the binary's SIGINT / SIGTERM handler can
/// remove them ([`remove_temp_files_in_flight`]); the library installs no handler.
static IN_FLIGHT: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn in_flight() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    IN_FLIGHT.lock().unwrap_or_else(|e| e.into_inner())
}

/// Removes every temporary file a write of this process has open now, and returns how many
/// it removed. For a signal handler that then exits: a write still running fails to rename
/// its file, which is gone.
pub fn remove_temp_files_in_flight() -> usize {
    let mut files = in_flight();
    files
        .drain(..)
        .filter(|f| std::fs::remove_file(f).is_ok())
        .count()
}

/// The file `path` names once its symbolic links are followed (a link is written through,
/// not replaced); `path` itself when it is not a link, or does not exist.
fn follow_links(path: &Path) -> Result<PathBuf> {
    let mut p = path.to_path_buf();
    // Linux's own limit on links followed in one lookup.
    for _ in 0..40 {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let to = std::fs::read_link(&p).map_err(|e| write_error(path, e))?;
                p = folder_of(&p).join(to);
            }
            _ => return Ok(p),
        }
    }
    Err(invalid(path, "too many levels of symbolic links"))
}

/// Checks, before any work, that `path` can name an output file: its folder exists and is a
/// folder, and the path (once its links are followed) is not something other than a
/// regular file (a folder, a device, a pipe), which the final rename would replace, nor a
/// read-only file, which a rename would silently replace. Other permissions are left to
/// the write itself.
pub fn check_output_path(path: &Path) -> Result<()> {
    if path.file_name().is_none() {
        return Err(invalid(path, "not a file name"));
    }
    let target = follow_links(path)?;
    let dir = folder_of(&target);
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => return Err(invalid(path, "its folder is not a folder")),
        Err(e) => return Err(write_error(path, e)),
    }
    match std::fs::metadata(&target) {
        Ok(m) if !m.is_file() => Err(invalid(path, "it exists and is not a regular file")),
        Ok(m) if m.permissions().readonly() => Err(invalid(
            path,
            "the file is read-only (make it writable, or remove it, to replace it)",
        )),
        _ => Ok(()),
    }
}

fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// The temporary name a write of `name` by process `pid` uses: `.NAME.tmp-PID`.
fn temp_name(name: &str, pid: u32) -> String {
    format!(".{name}.tmp-{pid}")
}

/// Removes temporary files that earlier writes of `name` in `dir` left behind when they
/// were killed: `.NAME.tmp-PID` files of this user whose process is no longer running
/// (Linux: no `/proc/PID`). Best effort; elsewhere it does nothing.
fn remove_stale_temp_files(dir: &Path, name: &str) {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let Ok(me) = std::fs::metadata("/proc/self") else {
            return;
        };
        let prefix = format!(".{name}.tmp-");
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for entry in entries.flatten() {
            let file_name = entry.file_name();
            let Some(pid) = file_name
                .to_str()
                .and_then(|n| n.strip_prefix(prefix.as_str()))
                .and_then(|p| p.parse::<u32>().ok())
            else {
                continue;
            };
            let ours = entry
                .metadata()
                .is_ok_and(|m| m.is_file() && m.uid() == me.uid());
            let running = Path::new("/proc").join(pid.to_string()).exists();
            if ours && !running && pid != std::process::id() {
                log::info!("removing {}, left by process {pid}", entry.path().display());
                let _ = std::fs::remove_file(entry.path());
            }
        }
    }
}

/// Writes `path` atomically: `write` fills a temporary file in the same folder (buffered),
/// which is then synced and renamed over the file. A link is written through (its target
/// is replaced, the link kept); an existing file keeps its permissions. A failed write, or
/// one interrupted by a signal the binary handles, leaves no temporary file; one killed
/// outright leaves `.NAME.tmp-PID`, which the next write of that name removes.
pub fn write_atomic_with(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<()>,
) -> Result<()> {
    check_output_path(path)?;
    let err = |reason| write_error(path, reason);
    let target = follow_links(path)?;
    let dir = folder_of(&target);
    let name = target
        .file_name()
        .ok_or_else(|| invalid(path, "not a file name"))?
        .to_string_lossy()
        .into_owned();
    remove_stale_temp_files(dir, &name);
    let tmp = dir.join(temp_name(&name, std::process::id()));
    let keep = std::fs::metadata(&target).ok().map(|m| m.permissions());
    in_flight().push(tmp.clone());
    let result = File::create(&tmp)
        .and_then(|f| match keep {
            Some(p) => f.set_permissions(p).map(|_| f),
            None => Ok(f),
        })
        .map_err(err)
        .and_then(|f| {
            let mut w = BufWriter::with_capacity(1 << 20, f);
            write(&mut w)?;
            let f = w.into_inner().map_err(|e| err(e.into_error()))?;
            f.sync_all().map_err(err)
        })
        .and_then(|_| std::fs::rename(&tmp, &target).map_err(err));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    in_flight().retain(|f| f != &tmp);
    result
}

/// Writes `bytes` to `path` atomically ([`write_atomic_with`]).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic_with(path, |w| {
        w.write_all(bytes).map_err(|e| write_error(path, e))
    })
}

/// The lower-case extension of `path`, or "" when it has none.
pub fn extension(path: &Path) -> String {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default()
}

/// Encodes `image` in `format` straight into the temporary file and renames it
/// ([`write_atomic_with`]): no encoded copy is held in memory.
pub fn write_image(
    path: &Path,
    image: &image::DynamicImage,
    format: image::ImageFormat,
) -> Result<()> {
    write_atomic_with(path, |w| {
        image.write_to(w, format).map_err(|e| match e {
            image::ImageError::IoError(reason) => write_error(path, reason),
            e => Error::Encode {
                path: path.to_path_buf(),
                message: e.to_string(),
            },
        })
    })
}

/// What an output path asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageKind {
    /// `.png`: display values, RGBA8.
    Png,
    /// `.exr`: linear radiance, RGBA f32.
    Exr,
}

/// The kind of image `path` names by its extension, or an error naming the choices.
pub fn image_kind(path: &Path) -> Result<ImageKind> {
    match extension(path).as_str() {
        "png" => Ok(ImageKind::Png),
        "exr" => Ok(ImageKind::Exr),
        _ => Err(Error::Format {
            path: path.to_path_buf(),
            expected: format_hint(path, "expected .png or .exr"),
        }),
    }
}

/// `expected`, or for a name that is all extension (`.png`: a hidden file with no
/// extension) a hint to name the file.
pub fn format_hint(path: &Path, expected: &'static str) -> &'static str {
    let dotted = path
        .file_name()
        .and_then(|n| n.to_str())
        .is_some_and(|n| n.starts_with('.') && !n[1..].contains('.'));
    if dotted && path.extension().is_none() {
        "the name is only an extension (a hidden file without one): put a name before the dot"
    } else {
        expected
    }
}

/// Writes RGBA8 display values as PNG.
pub fn write_png(path: &Path, width: u32, height: u32, rgba: Vec<u8>) -> Result<()> {
    let image = image::RgbaImage::from_raw(width, height, rgba).ok_or_else(|| Error::Encode {
        path: path.to_path_buf(),
        message: "pixel count does not match the size".into(),
    })?;
    write_image(
        path,
        &image::DynamicImage::ImageRgba8(image),
        image::ImageFormat::Png,
    )
}

/// Writes RGBA f32 linear radiance as OpenEXR.
pub fn write_exr(path: &Path, width: u32, height: u32, rgba: Vec<f32>) -> Result<()> {
    let image =
        image::Rgba32FImage::from_raw(width, height, rgba).ok_or_else(|| Error::Encode {
            path: path.to_path_buf(),
            message: "pixel count does not match the size".into(),
        })?;
    write_image(
        path,
        &image::DynamicImage::ImageRgba32F(image),
        image::ImageFormat::OpenExr,
    )
}
