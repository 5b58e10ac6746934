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

/// [`remove_temp_files_in_flight`] unless the list is locked now (by the thread that calls
/// this, in the middle of a write: the out-of-memory exit may come from there), when it
/// removes none.
pub(crate) fn try_remove_temp_files_in_flight() -> usize {
    IN_FLIGHT
        .try_lock()
        .map_or(0, |mut files| remove_all(&mut files))
}

/// Removes every temporary file a write of this process has open now, and returns how many
/// it removed. For a signal handler that then exits: a write still running fails to rename
/// its file, which is gone.
pub(crate) fn remove_temp_files_in_flight() -> usize {
    remove_all(&mut in_flight())
}

/// Removes the files `files` lists and empties it; how many it removed.
fn remove_all(files: &mut Vec<PathBuf>) -> usize {
    files
        .drain(..)
        .filter(|f| std::fs::remove_file(f).is_ok())
        .count()
}

/// The file `path` names once its symbolic links are followed (a link is written through,
/// not replaced); `path` itself when it is not a link, or does not exist.
pub(crate) fn follow_links(path: &Path) -> Result<PathBuf> {
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
pub(crate) fn check_output_path(path: &Path) -> Result<()> {
    if path.file_name().is_none() {
        return Err(invalid(path, "not a file name"));
    }
    let target = follow_links(path)?;
    if let Some(name) = target.file_name() {
        let bytes = name.as_encoded_bytes().len();
        if bytes > NAME_MAX {
            return Err(invalid(
                path,
                &format!(
                    "the file name is {bytes} bytes, more than the {NAME_MAX} a name may have"
                ),
            ));
        }
    }
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

/// Bytes a file name may have (Linux's `NAME_MAX`, that of ext4, XFS, Btrfs, tmpfs).
pub(crate) const NAME_MAX: usize = 255;

/// Checks, before any work, that `path` can be an output folder: it is one, or does not
/// exist yet (it is made later); a file there is refused in one line.
pub fn check_output_folder(path: &Path) -> Result<()> {
    match std::fs::metadata(path) {
        Ok(m) if !m.is_dir() => Err(invalid(
            path,
            "it exists and is not a folder (this command writes a folder of files)",
        )),
        _ => Ok(()),
    }
}

pub(crate) fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// Bytes of the output's name a temporary name keeps: with the hash and the process id it
/// stays well under [`NAME_MAX`] whatever the output's name (issue 28, 7).
const TEMP_NAME_KEEP: usize = 64;

/// The start of every temporary name of `name`: `.NAME.tmp-`, or for a long name
/// `.PREFIX~HASH.tmp-` (its first [`TEMP_NAME_KEEP`] bytes, cut at a character, and a
/// 64-bit FNV-1a hash of all of it, so that two long names with one prefix differ).
fn temp_prefix(name: &str) -> String {
    if name.len() <= TEMP_NAME_KEEP {
        return format!(".{name}.tmp-");
    }
    let mut cut = TEMP_NAME_KEEP;
    while !name.is_char_boundary(cut) {
        cut -= 1;
    }
    // FNV-1a (Fowler, Noll, Vo), 64-bit offset basis and prime.
    let hash = name.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    });
    format!(".{}~{hash:016x}.tmp-", &name[..cut])
}

/// The temporary name a write of `name` by process `pid` uses: `.NAME.tmp-PID`
/// ([`temp_prefix`]).
fn temp_name(name: &str, pid: u32) -> String {
    format!("{}{pid}", temp_prefix(name))
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
        let prefix = temp_prefix(name);
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

/// A file written in full to its temporary name beside `path`, not yet renamed over it:
/// [`Staged::commit`] renames it; dropped uncommitted, it is removed. Several staged files
/// commit together ([`commit_all`]), so a failed write of any leaves every old file.
#[must_use = "a staged file is removed unless committed"]
pub(crate) struct Staged {
    path: PathBuf,
    tmp: PathBuf,
    target: PathBuf,
    committed: bool,
}

impl Staged {
    /// Renames the temporary file over its target.
    pub(crate) fn commit(mut self) -> Result<()> {
        let result =
            std::fs::rename(&self.tmp, &self.target).map_err(|e| write_error(&self.path, e));
        self.committed = result.is_ok();
        result
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_file(&self.tmp);
        }
        in_flight().retain(|f| f != &self.tmp);
    }
}

/// Renames every staged file over its target, in order. They are all written by then, so
/// only a rename can fail (it does not for files in one folder short of the disk being
/// yanked): the files not yet renamed are removed.
pub(crate) fn commit_all(files: Vec<Staged>) -> Result<()> {
    for f in files {
        f.commit()?;
    }
    Ok(())
}

/// Writes `path`'s bytes to its temporary file: `write` fills it (buffered), then it is
/// synced; [`Staged::commit`] renames it over `path`. A link is written through (its
/// target is replaced, the link kept); an existing file keeps its permissions. A failed
/// write, or one interrupted by a signal the binary handles, leaves no temporary file;
/// one killed outright leaves `.NAME.tmp-PID`, which the next write of that name removes.
pub(crate) fn stage_with(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<()>,
) -> Result<Staged> {
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
    let staged = Staged {
        path: path.to_path_buf(),
        tmp: tmp.clone(),
        target: target.clone(),
        committed: false,
    };
    File::create(&tmp)
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
        })?;
    Ok(staged)
}

/// Writes `path` atomically: [`stage_with`], then [`Staged::commit`].
pub(crate) fn write_atomic_with(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<()>,
) -> Result<()> {
    stage_with(path, write)?.commit()
}

/// Writes `bytes` to `path` atomically (`write_atomic_with`).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic_with(path, |w| {
        w.write_all(bytes).map_err(|e| write_error(path, e))
    })
}

/// The lower-case extension of `path`, or "" when it has none.
pub(crate) fn extension(path: &Path) -> String {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default()
}

#[cfg(feature = "image-files")]
/// A writer that keeps the first I/O error its inner writer gave: an encoder that fails on
/// one reports it as its own format error (the EXR encoder says "Format error decoding
/// OpenExr" for a full disk), and the write's error names the real cause instead.
struct Recording<'a, W> {
    inner: &'a mut W,
    error: Option<std::io::Error>,
}

#[cfg(feature = "image-files")]
impl<W> Recording<'_, W> {
    fn keep<T>(&mut self, r: std::io::Result<T>) -> std::io::Result<T> {
        if let Err(e) = &r {
            if self.error.is_none() {
                self.error = Some(std::io::Error::new(e.kind(), e.to_string()));
            }
        }
        r
    }
}

#[cfg(feature = "image-files")]
impl<W: Write> Write for Recording<'_, W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let r = self.inner.write(buf);
        self.keep(r)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        let r = self.inner.flush();
        self.keep(r)
    }
}

#[cfg(feature = "image-files")]
impl<W: std::io::Seek> std::io::Seek for Recording<'_, W> {
    fn seek(&mut self, pos: std::io::SeekFrom) -> std::io::Result<u64> {
        let r = self.inner.seek(pos);
        self.keep(r)
    }
}

#[cfg(feature = "image-files")]
/// Encodes `image` in `format` straight into the temporary file ([`stage_with`]): no
/// encoded copy is held in memory.
pub(crate) fn stage_image(
    path: &Path,
    image: &image::DynamicImage,
    format: image::ImageFormat,
) -> Result<Staged> {
    stage_with(path, |w| {
        let mut w = Recording {
            inner: w,
            error: None,
        };
        let result = image.write_to(&mut w, format);
        result.map_err(|e| match (e, w.error) {
            (image::ImageError::IoError(reason), _) | (_, Some(reason)) => {
                write_error(path, reason)
            }
            (e, None) => Error::Encode {
                path: path.to_path_buf(),
                message: e.to_string(),
            },
        })
    })
}

#[cfg(feature = "image-files")]
/// Encodes `image` in `format` and renames it over `path` (`stage_image`).
pub fn write_image(
    path: &Path,
    image: &image::DynamicImage,
    format: image::ImageFormat,
) -> Result<()> {
    stage_image(path, image, format)?.commit()
}

/// What an output path asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ImageKind {
    /// `.png`: display values, RGBA8.
    Png,
    /// `.exr`: linear radiance, RGBA f32.
    Exr,
}

/// The kind of image `path` names by its extension, or an error naming the choices.
pub(crate) fn image_kind(path: &Path) -> Result<ImageKind> {
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
pub(crate) fn format_hint(path: &Path, expected: &'static str) -> &'static str {
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

#[cfg(feature = "image-files")]
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

#[cfg(feature = "image-files")]
/// [`write_png`] with a `Comment` text chunk holding `note` (what the picture is, as the
/// samples a pixel of a truth render; `png`'s encoder, since `image`'s writes no text).
pub(crate) fn write_png_noted(
    path: &Path,
    width: u32,
    height: u32,
    rgba: Vec<u8>,
    note: &str,
) -> Result<()> {
    if rgba.len() as u64 != 4 * u64::from(width) * u64::from(height) {
        return Err(Error::Encode {
            path: path.to_path_buf(),
            message: "pixel count does not match the size".into(),
        });
    }
    let encode_error = |e: png::EncodingError| match e {
        png::EncodingError::IoError(reason) => write_error(path, reason),
        e => Error::Encode {
            path: path.to_path_buf(),
            message: e.to_string(),
        },
    };
    write_atomic_with(path, |w| {
        let mut encoder = png::Encoder::new(w, width, height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        encoder
            .add_text_chunk("Comment".to_string(), note.to_string())
            .map_err(encode_error)?;
        let mut writer = encoder.write_header().map_err(encode_error)?;
        writer.write_image_data(&rgba).map_err(encode_error)?;
        writer.finish().map_err(encode_error)
    })
}

#[cfg(feature = "image-files")]
/// [`stage_exr`] with a `comment` text attribute holding `note`, ZIP-compressed in scan
/// lines.
pub(crate) fn stage_exr_noted(
    path: &Path,
    width: u32,
    height: u32,
    rgba: Vec<f32>,
    note: &str,
) -> Result<Staged> {
    encode_exr(
        path,
        (width, height),
        &rgba,
        exr::prelude::Encoding::SMALL_LOSSLESS,
        Some(note),
    )
}

#[cfg(feature = "image-files")]
/// Encodes RGBA f32 `rgba` of `size` as OpenEXR into `path`'s temporary file, with `note`
/// as a `comment` attribute if given. The blocks are written in increasing order: `exr`
/// compresses them on several threads and, in its default order ("unspecified"), writes
/// each as it is done, so two writes of the same pixels gave different bytes (the offset
/// table); in increasing order it sorts them first, and the same pixels give the same file.
fn encode_exr(
    path: &Path,
    size: (u32, u32),
    rgba: &[f32],
    encoding: exr::prelude::Encoding,
    note: Option<&str>,
) -> Result<Staged> {
    use exr::prelude::{
        AttributeValue, Image, Layer, LayerAttributes, LineOrder, SpecificChannels, Text, Vec2,
        WritableImage,
    };
    let (w, h) = (size.0 as usize, size.1 as usize);
    if rgba.len() != 4 * w * h {
        return Err(Error::Encode {
            path: path.to_path_buf(),
            message: "pixel count does not match the size".into(),
        });
    }
    let pixel = |p: Vec2<usize>| {
        let i = 4 * (p.y() * w + p.x());
        (rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3])
    };
    let encoding = exr::prelude::Encoding {
        line_order: LineOrder::Increasing,
        ..encoding
    };
    let layer = Layer::new(
        (w, h),
        LayerAttributes::default(),
        encoding,
        SpecificChannels::rgba(pixel),
    );
    let mut image = Image::from_layer(layer);
    if let Some(note) = note {
        image.attributes.other.insert(
            Text::from("comment"),
            AttributeValue::Text(Text::from(note)),
        );
    }
    stage_with(path, |out| {
        let mut out = Recording {
            inner: out,
            error: None,
        };
        let result = image.write().to_buffered(&mut out);
        result.map_err(|e| match (e, out.error) {
            (exr::error::Error::Io(reason), _) | (_, Some(reason)) => write_error(path, reason),
            (e, None) => Error::Encode {
                path: path.to_path_buf(),
                message: e.to_string(),
            },
        })
    })
}

#[cfg(feature = "image-files")]
/// Writes RGBA f32 linear radiance as OpenEXR.
pub(crate) fn write_exr(path: &Path, width: u32, height: u32, rgba: Vec<f32>) -> Result<()> {
    stage_exr(path, width, height, rgba)?.commit()
}

#[cfg(feature = "image-files")]
/// Encodes RGBA f32 linear radiance as OpenEXR into `path`'s temporary file
/// ([`stage_with`]), for [`commit_all`] with the files that go with it.
pub(crate) fn stage_exr(path: &Path, width: u32, height: u32, rgba: Vec<f32>) -> Result<Staged> {
    // RLE in 64x64 tiles: what `image`'s encoder wrote before, in a fixed order.
    encode_exr(
        path,
        (width, height),
        &rgba,
        exr::prelude::Encoding::FAST_LOSSLESS,
        None,
    )
}

#[cfg(all(test, feature = "image-files"))]
mod tests {
    use super::*;

    /// The same pixels written twice give the same bytes, plain and with a note: before the
    /// blocks were sorted, the offset table followed the order the threads finished in.
    #[test]
    fn an_exr_of_the_same_pixels_is_the_same_file() {
        let dir = std::env::temp_dir().join(format!("shadeballs-exr-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // 517 x 389: many 64 x 64 tiles and many 16-line ZIP blocks, each different.
        let (w, h) = (517u32, 389u32);
        let rgba: Vec<f32> = (0..4 * w * h)
            .map(|i| ((i as f32) * 0.618_034).fract() * 7.0)
            .collect();
        for noted in [false, true] {
            let mut files = Vec::new();
            for k in 0..6 {
                let path = dir.join(format!("{noted}-{k}.exr"));
                let staged = if noted {
                    stage_exr_noted(&path, w, h, rgba.clone(), "4 spp").unwrap()
                } else {
                    stage_exr(&path, w, h, rgba.clone()).unwrap()
                };
                staged.commit().unwrap();
                files.push(std::fs::read(&path).unwrap());
            }
            assert!(
                files.iter().all(|f| *f == files[0]),
                "noted = {noted}: six writes of the same pixels differ in their bytes"
            );
            let back = image::open(dir.join(format!("{noted}-0.exr")))
                .unwrap()
                .into_rgba32f();
            assert_eq!(back.into_raw(), rgba, "noted = {noted}: pixels changed");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
