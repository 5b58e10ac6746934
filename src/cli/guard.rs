//! Checks of a command's outputs before any work, shared by every command that writes a
//! file (issue 38, findings 2, 5 and 6): no output is, or links to, one of the command's
//! inputs (the scene file, a glTF file and the buffers and images it names, the environment
//! map) or another of its outputs (the truth's sidecar and its
//! image), and every output's folder takes a new file (the write is a temporary file
//! there, renamed over the output: `crate::output`).

use std::path::{Path, PathBuf};

use super::args::SceneArgs;
use crate::environment::Source;
use crate::error::{Error, Result};
use crate::output;
use crate::scene::Scene;

/// A file a command reads or writes, with the flag (or role) that names it.
pub(crate) type Named = (String, PathBuf);

/// The files `args` names that the command reads, before the scene is read (`--scene`,
/// and `--environment` where it is a file), and with `scene` its map's file.
pub(crate) fn scene_inputs(args: &SceneArgs, scene: Option<&Scene>) -> Vec<Named> {
    let mut inputs = Vec::new();
    if let Some(path) = &args.scene {
        inputs.push(("the scene file --scene".to_string(), path.clone()));
        if crate::import::is_gltf(path) {
            inputs.extend(gltf_files(path));
        }
    }
    if let Some(name) = &args.environment {
        let path = Path::new(name);
        if path.exists() {
            inputs.push(("the map --environment".to_string(), path.to_path_buf()));
        }
    }
    if let Some(Source::File(path)) = scene
        .and_then(|s| s.environment_map.as_ref())
        .map(|e| &e.source)
    {
        inputs.push(("the scene's environment map".to_string(), path.clone()));
    }
    inputs
}

/// The files beside the glTF file `path` that it names (its buffers, which a read opens,
/// and its images): inputs too ([`crate::import::external_files`]).
pub(crate) fn gltf_files(path: &Path) -> Vec<Named> {
    crate::import::external_files(path)
        .into_iter()
        .map(|(what, file)| (format!("the glTF file's {what}"), file))
        .collect()
}

/// The outputs among `named` that are given.
pub(crate) fn outputs(named: &[(&str, Option<&Path>)]) -> Vec<Named> {
    named
        .iter()
        .filter_map(|(what, p)| p.map(|p| (what.to_string(), p.to_path_buf())))
        .collect()
}

/// Refuses, in one line, an output that is (or links to, or is a hard link of) one of
/// `inputs` or another output: writing it would destroy the input, or one output would
/// replace the other.
pub(crate) fn refuse_overlaps(outputs: &[Named], inputs: &[Named]) -> Result<()> {
    for (i, (what, out)) in outputs.iter().enumerate() {
        for (other, path) in outputs[..i].iter().chain(inputs) {
            if same_file(out, path) {
                return Err(Error::Invalid {
                    what: "output",
                    message: format!(
                        "{what} '{}' is {other} '{}' (or a link to it): writing it would \
                         replace that file; choose another output path",
                        out.display(),
                        path.display()
                    ),
                });
            }
        }
    }
    Ok(())
}

/// [`refuse_overlaps`] and [`probe_folders`] for a command of one output, `--out`, and
/// `inputs` (`bake`, `environment`, `probe`, `import`, `export-shader`).
pub(crate) fn check_out(out: &Path, inputs: &[Named]) -> Result<()> {
    let outputs = outputs(&[("--out", Some(out))]);
    refuse_overlaps(&outputs, inputs)?;
    probe_folders(&outputs)
}

/// Checks that each output's folder (the folder of the file its links lead to) takes a new
/// file, by making one there and removing it: a folder the user cannot write in, or a
/// read-only file system, is refused before the work, not after it.
pub(crate) fn probe_folders(outputs: &[Named]) -> Result<()> {
    for (_, path) in outputs {
        let target = output::follow_links(path)?;
        let dir = output::folder_of(&target);
        let probe = dir.join(format!(".shadeballs-probe-{}", std::process::id()));
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&probe)
        {
            Ok(_) => {
                let _ = std::fs::remove_file(&probe);
            }
            // A file of that name (another probe of this process id, left by a kill):
            // the folder is writable enough to have it.
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
            Err(e) => {
                return Err(Error::Write {
                    path: path.clone(),
                    reason: std::io::Error::new(
                        e.kind(),
                        format!("its folder '{}' takes no new file: {e}", dir.display()),
                    ),
                })
            }
        }
    }
    Ok(())
}

/// Refuses a camera whose pixels the GPU's f32 rays cannot resolve at `w x h`
/// ([`crate::scene::Camera::gpu_problem`]; issue 38, 4).
pub(crate) fn check_f32_camera(scene: &Scene, w: u32, h: u32) -> Result<()> {
    match scene.camera.gpu_problem(w, h) {
        Some(message) => Err(Error::Invalid {
            what: "camera",
            message,
        }),
        None => Ok(()),
    }
}

/// Why `--ibl-frames frames` does nothing for `scene`, where it does nothing (issue 38, 9:
/// ignored silently, or 8 frames drawn for nothing): `on_gpu` is whether a GPU backend
/// draws the scene (only it accumulates lobe frames).
pub(crate) fn ibl_frames_ignored(
    frames: Option<u32>,
    on_gpu: bool,
    scene: &Scene,
) -> Option<String> {
    let frames = frames.filter(|&n| n > 1)?;
    let why = if !on_gpu {
        "only a GPU backend (auto, vulkan, gl) accumulates lobe frames"
    } else if scene.ibl_method != crate::environment::IblMethod::Lobe {
        "the split sum draws one exact frame (--ibl-method lobe accumulates frames)"
    } else if scene.environment_map.is_none() {
        "the scene has no environment map for --ibl-method lobe to sample"
    } else {
        return None;
    };
    Some(format!("notice: --ibl-frames {frames} is ignored: {why}"))
}

/// Whether `a` and `b` name one file: the same device and inode where both exist (links,
/// hard links, `..` in paths), else the same path once links are followed and folders made
/// canonical (an output that does not exist yet, or a link to where another will be).
fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
    }
    match (resolved(a), resolved(b)) {
        (Some(x), Some(y)) => x == y,
        _ => false,
    }
}

/// The path `path` writes to once its links are followed, its folder made canonical.
fn resolved(path: &Path) -> Option<PathBuf> {
    let target = output::follow_links(path).ok()?;
    let dir = std::fs::canonicalize(output::folder_of(&target)).ok()?;
    Some(dir.join(target.file_name()?))
}
