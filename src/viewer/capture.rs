//! What the viewer writes besides its PNG screenshots (their time-stamped names,
//! [`timestamped`], are here too): the scene area's linear radiance
//! as an EXR (key E, the panel, `--screenshot FILE.exr`), and the scene as a scene file
//! (the panel, `--save-scene`) that `shadeballs render` draws as the viewer does.

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::output;
use crate::scene::Scene;

use super::compare::{Compare, View};
use super::state::State;
use super::{save, App};

/// What the next drawn frame writes besides a PNG screenshot.
#[derive(Default)]
pub(crate) struct Pending {
    /// The scene area's linear radiance, to this EXR.
    pub exr: Option<PathBuf>,
    /// The scene, to this scene file.
    pub scene: Option<PathBuf>,
}

impl App {
    /// Writes what is pending, at the scene area's size. A failure is the run's where the
    /// file is what a `--frames` run was for; in a window it is reported and the viewer
    /// goes on.
    pub(super) fn write_pending(&mut self) -> Result<()> {
        let Some(state) = &mut self.state else {
            return Ok(());
        };
        let size = (self.scene_width, state.size().1);
        let compare = self.controls.compare;
        let mut results = Vec::new();
        if let Some(path) = self.pending.exr.take() {
            results.push(write_exr(
                state,
                &path,
                (&self.scene, compare.as_ref()),
                size,
            ));
        }
        if let Some(path) = self.pending.scene.take() {
            results.push(save_scene(
                state,
                &path,
                &self.scene,
                compare.is_some(),
                size,
            ));
        }
        for result in results {
            match result {
                Err(e) if self.options.frames.is_some() => return Err(e),
                Err(e) => eprintln!("error: {e}"),
                Ok(()) => {}
            }
        }
        Ok(())
    }
}

/// The scene area's linear radiance (before exposure and tone mapping, as `render`'s EXR;
/// the lobe's image as converged so far): the scene's, or a wipe's two sides at the split, or a difference's `|a - b|` per channel.
fn write_exr(
    state: &mut State,
    path: &Path,
    (scene, compare): (&Scene, Option<&Compare>),
    (width, height): (u32, u32),
) -> Result<()> {
    let rgba = match compare {
        None => {
            let r = &mut state.renderer;
            r.render_progressive_hdr(scene, width, height)?.rgba
        }
        Some(c) => {
            let (a, b) = c.scenes(scene);
            let [(_, wa), (xb, wb)] = c.halves(width);
            let a = state.renderer.render_progressive_hdr(&a, wa, height)?;
            let b = state
                .second_renderer()
                .render_progressive_hdr(&b, wb, height)?;
            let (a, b) = (a.rgba, b.rgba);
            match c.view {
                View::Wipe => wipe(&a, &b, width, c.split_px(width)),
                View::SideBySide => side_by_side((&a, wa), (&b, wb), xb, width),
                View::Difference { .. } => a
                    .iter()
                    .zip(&b)
                    .enumerate()
                    // Alpha stays 1.
                    .map(|(i, (a, b))| if i % 4 == 3 { 1.0 } else { (a - b).abs() })
                    .collect(),
            }
        }
    };
    output::write_exr(path, width, height, rgba)?;
    eprintln!(
        "screenshot {width}x{height} (the scene area's linear radiance) -> {}",
        path.display()
    );
    Ok(())
}

/// Columns `0..split` of `a` and the rest of `b`, RGBA images `width` wide.
fn wipe(a: &[f32], b: &[f32], width: u32, split: u32) -> Vec<f32> {
    a.chunks_exact(4)
        .zip(b.chunks_exact(4))
        .enumerate()
        .flat_map(|(i, (a, b))| {
            let x = i as u32 % width.max(1);
            if x < split {
                a
            } else {
                b
            }
        })
        .copied()
        .collect()
}

/// An RGBA image `width` wide of `a` (`wa` wide) at its left and `b` (`wb` wide) from
/// column `xb`, rows of the same count.
fn side_by_side((a, wa): (&[f32], u32), (b, wb): (&[f32], u32), xb: u32, width: u32) -> Vec<f32> {
    let rows = a.len() / (4 * wa.max(1) as usize);
    let mut out = vec![0.0f32; 4 * width as usize * rows];
    for y in 0..rows {
        for (src, w, x0) in [(a, wa, 0), (b, wb, xb)] {
            let n = (w.min(width.saturating_sub(x0)) * 4) as usize;
            let from = y * 4 * w as usize;
            let to = 4 * (y * width as usize + x0 as usize);
            out[to..to + n].copy_from_slice(&src[from..from + n]);
        }
    }
    out
}

/// Writes `scene` as a scene file, checked to load back as the same scene (with the
/// scene files' parser, where built in), and says what `render` needs besides the file to
/// draw the same picture.
fn save_scene(
    state: &State,
    path: &Path,
    scene: &Scene,
    comparing: bool,
    size: (u32, u32),
) -> Result<()> {
    let invalid = |message: String| Error::Invalid {
        what: "scene to save",
        message,
    };
    let text = save::scene_toml(scene, size).map_err(invalid)?;
    #[cfg(feature = "scene-files")]
    {
        let back = crate::scene::parse(&text, path)?;
        if back != save::as_written(scene, size) {
            return Err(invalid(
                "the scene file written would load as another scene (a bug: please report it)"
                    .into(),
            ));
        }
    }
    output::write_atomic(path, text.as_bytes())?;
    eprintln!(
        "scene -> {} (render it with --width {} --height {})",
        path.display(),
        size.0,
        size.1
    );
    let default_layout = crate::lut::BakeConfig::default().layout;
    if state.renderer.bake_config().layout != default_layout {
        eprintln!(
            "note: the panel's table layout or size is not a scene key: `render` bakes the \
             default tables, so its picture may differ slightly"
        );
    }
    if let Some(n) = state.renderer.truth_samples().filter(|_| scene.has_truth()) {
        eprintln!("note: the truth balls hold {n} samples a pixel: render with --spp {n}");
    }
    if let Some(n) = state.renderer.lobe_samples() {
        let frames = n / scene.ibl_samples.max(1);
        eprintln!(
            "note: the lobe's image holds {n} samples a pixel: render with --ibl-frames {frames}"
        );
    }
    if comparing {
        eprintln!("note: the file holds the scene itself, not the comparison");
    }
    Ok(())
}

/// `shadeballs-<seconds since 1970>.<extension>` in the working folder.
pub(crate) fn timestamped(extension: &str) -> PathBuf {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    PathBuf::from(format!("shadeballs-{secs}.{extension}"))
}
