//! The progressive images: the truth balls' sums (`truth.rs`), one estimate a pixel a frame,
//! and the lobe's (`accumulate.rs`), one frame of its samples at a time, each kept while the
//! scene is unchanged.

use super::ball_pass::background;
use super::frame::Frame;
use super::{Renderer, Target};
use crate::error::Result;
use crate::gpu::accumulate::{LobeKey, LOBE_FORMAT, LOBE_IBL};
use crate::gpu::truth;
use crate::scene::Scene;

impl Renderer {
    /// Records one frame of the truth balls' estimates (returns false, logging why, where
    /// the device cannot: [`Renderer::truth_supported`]).
    pub(super) fn truth_frame(
        &mut self,
        scene: &Scene,
        frame: &Frame,
        encoder: &mut wgpu::CommandEncoder,
    ) -> bool {
        if !self.truth_supported() {
            // Once a process, not every frame of the viewer (issue 28, 11).
            static SAID: std::sync::Once = std::sync::Once::new();
            SAID.call_once(|| {
                log::error!(
                    "{} cannot render to Rgba32Float: the truth balls are not drawn",
                    self.gpu.describe()
                )
            });
            return false;
        }
        let quads = truth::quads(scene, &frame.balls, &frame.hidden, frame.size);
        let draw = frame.draw(&self.gpu);
        self.truth
            .accumulate(&draw, encoder, scene, frame.size, (&quads.0, &quads.1));
        true
    }

    /// Adds one frame of estimates to the truth balls' sums of `scene` at `w x h` (starting
    /// them again if the scene or the size changed) without drawing an image, and submits.
    /// A scene without truth balls does nothing.
    pub(crate) fn accumulate_truth(&mut self, scene: &Scene, w: u32, h: u32) -> Result<()> {
        self.scoped(|r| {
            let frame = r.prepare_frame(scene, w, h)?;
            if frame.plan.truth.is_empty() {
                return Ok(());
            }
            if !r.truth_supported() {
                return r.check_truth_supported(scene);
            }
            let mut encoder = r.gpu.device.create_command_encoder(&Default::default());
            r.truth_frame(scene, &frame, &mut encoder);
            r.gpu.queue.submit([encoder.finish()]);
            Ok(())
        })
    }

    /// Estimates per pixel the truth balls' image holds now (after the latest draw or
    /// [`Renderer::accumulate_truth`]); `None` before any scene with truth balls.
    pub(crate) fn truth_samples(&self) -> Option<u32> {
        self.truth.frames()
    }

    /// Starts the truth balls' sums again from zero at the next frame (they restart by
    /// themselves when the scene or the size changes).
    pub(crate) fn reset_truth(&mut self) {
        self.truth.reset();
    }

    /// Draws `scene` into `target` as [`Renderer::encode`] does, but a scene whose balls
    /// use the lobe (`ibl_method = "lobe"` with a map) converges: each call while the scene
    /// is unchanged (but for its exposure and display transform; the size, tables and draw
    /// options too) adds the next frame of the lobe's samples to sums held on the GPU and
    /// writes their mean (the lobe frame advances by itself; [`Renderer::set_lobe_frame`]
    /// is not read), and a changed scene starts again from one frame
    /// ([`Renderer::lobe_samples`]). Past [`Renderer::set_lobe_sample_cap`]'s cap it adds
    /// nothing and writes the mean held. A scene without the lobe is drawn by `encode`.
    /// A clear-coated truth ball under lights is refused, as [`Renderer::render`] refuses it
    /// (on a device without `Rgba32Float` targets the truth balls are left out with a
    /// warning, as in `encode`).
    pub(crate) fn encode_progressive(
        &mut self,
        scene: &Scene,
        target: Target<'_>,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Result<()> {
        scene.check_clearcoat_truth_lights(false)?;
        let capped = |samples: Option<u32>, cap: Option<u32>| {
            samples.zip(cap).is_some_and(|(n, cap)| n >= cap)
        };
        self.progressive(scene, target, encoder, |r| {
            !capped(r.lobe_samples(), r.lobe_cap)
        })
    }

    /// [`Renderer::encode_progressive`] and submits.
    #[cfg(test)]
    pub(crate) fn render_progressive(&mut self, scene: &Scene, target: Target<'_>) -> Result<()> {
        self.gpu.check()?;
        self.check_truth_supported(scene)?;
        self.submit_scoped(|r, encoder| r.encode_progressive(scene, target, encoder))
    }

    /// Samples a pixel the lobe's progressive image holds (frames summed times the scene's
    /// `ibl_samples`) after the latest [`Renderer::encode_progressive`],
    /// [`Renderer::accumulate_lobe`] or [`Renderer::render_lobe_hdr`]; `None` when that
    /// scene's balls use no lobe (or before any).
    pub(crate) fn lobe_samples(&self) -> Option<u32> {
        let frames = self.lobe.frames()?;
        Some(frames.saturating_mul(self.lobe.samples_a_frame()))
    }

    /// Stops [`Renderer::encode_progressive`] adding frames once the image holds `cap`
    /// samples a pixel (`None`, the default: no cap), so that an idle viewer goes idle.
    pub(crate) fn set_lobe_sample_cap(&mut self, cap: Option<u32>) {
        self.lobe_cap = cap;
    }

    /// Starts the lobe's sums again from zero at the next frame (they restart by
    /// themselves when the scene changes).
    pub(crate) fn reset_lobe(&mut self) {
        self.lobe.reset();
    }

    /// Adds the next frame of the lobe's samples of `scene` at `w x h` to the sums
    /// (starting them again if the scene changed) without drawing an image, and submits.
    /// A scene whose balls use no lobe does nothing.
    pub(crate) fn accumulate_lobe(&mut self, scene: &Scene, w: u32, h: u32) -> Result<()> {
        self.submit_scoped(|r, encoder| match r.start_lobe(scene, (w, h)) {
            Some(frames) => r.add_lobe_frame(scene, (w, h), frames, encoder).map(drop),
            None => Ok(()),
        })
    }

    /// Records the addition of frame `frames` (the count summed so far) of `scene` at `size`
    /// to the lobe's sums (after [`Renderer::start_lobe`]); returns the frame's uniforms.
    fn add_lobe_frame(
        &mut self,
        scene: &Scene,
        size: (u32, u32),
        frames: u32,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Result<Frame> {
        let frame = self.prepare_frame_at(scene, size, frames)?;
        self.encode_lobe_frame(scene, &frame, encoder);
        Ok(frame)
    }

    /// Keeps or starts the lobe's sums for `scene` at `size`: the frames summed so far, or
    /// `None` (the sums dropped) where its balls use no lobe.
    fn start_lobe(&mut self, scene: &Scene, size: (u32, u32)) -> Option<u32> {
        let plan = self.make_plan(scene);
        if !plan.draws.iter().any(|(v, _)| v.ibl == LOBE_IBL) {
            self.lobe.forget();
            return None;
        }
        let key = LobeKey::new(scene, size, &plan, self.options);
        Some(self.lobe.start(&self.gpu.device, key))
    }

    /// Records the balls' pass of `frame` into the lobe's frame texture and its addition to
    /// the sums (after [`Renderer::start_lobe`]).
    fn encode_lobe_frame(
        &mut self,
        scene: &Scene,
        frame: &Frame,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        let Some(view) = self.lobe.frame_view().cloned() else {
            return;
        };
        let target = Target {
            view: &view,
            format: LOBE_FORMAT,
            width: frame.size.0,
            height: frame.size.1,
        };
        self.encode_balls(scene, frame, target, encoder);
        let draw = frame.draw(&self.gpu);
        self.lobe.accumulate(&draw, encoder);
    }

    /// The work of [`Renderer::encode_progressive`]: a frame added where `add(self)` says
    /// so, then the mean resolved into `target` and the truth balls as `encode` draws them.
    pub(super) fn progressive(
        &mut self,
        scene: &Scene,
        target: Target<'_>,
        encoder: &mut wgpu::CommandEncoder,
        add: impl Fn(&Self) -> bool,
    ) -> Result<()> {
        let size = (target.width, target.height);
        let Some(frames) = self.start_lobe(scene, size) else {
            return self.encode(scene, target, encoder);
        };
        let frame = if frames == 0 || add(self) {
            self.add_lobe_frame(scene, size, frames, encoder)?
        } else {
            self.prepare_frame_at(scene, size, frames)?
        };
        let draw = frame.draw(&self.gpu);
        let clear = background(scene, target.format);
        self.lobe
            .resolve(&draw, encoder, (target.view, target.format), size, clear);
        if !frame.plan.truth.is_empty() && self.truth_frame(scene, &frame, encoder) {
            let draw = frame.draw(&self.gpu);
            self.truth
                .resolve(&draw, encoder, target.view, target.format, frame.size);
        }
        Ok(())
    }
}
