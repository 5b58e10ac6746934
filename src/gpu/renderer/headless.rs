//! Rendering without a window: into a texture, read back ([`Readback`]) and returned (LDR,
//! HDR, the truth's and the lobe's converged images), and the Monte Carlo of the model.

use super::Renderer;
use crate::error::{Error, Result};
use crate::gpu::montecarlo::{McFrame, MonteCarloPass};
use crate::gpu::readback::Readback;
use crate::gpu::Target;
use crate::scene::Scene;
use crate::stats::{MonteCarloImage, Part};

/// Display values, RGBA8, row-major, row 0 at the top.
pub struct LdrImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `4 * width * height` bytes: tone-mapped, gamma-encoded RGB and alpha 255.
    pub rgba: Vec<u8>,
}

/// Linear radiance, RGBA f32, row-major, row 0 at the top.
pub struct HdrImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `4 * width * height` values: linear radiance (before exposure) and alpha 1.
    pub rgba: Vec<f32>,
}

/// Most estimates a pixel of a GPU truth render: the sums are f32, whose count (alpha)
/// is exact to 2^24, and whose relative rounding per addition stays near 2^-24 times the
/// count (6e-5 at this cap, under the noise of any such render).
pub(crate) const MAX_TRUTH_SPP: u32 = 1024;

/// Truth frames queued before the headless render waits for the device.
const FRAMES_IN_FLIGHT: u32 = 8;

/// How [`Renderer::readback_render`] draws: one frame ([`Renderer::encode`]), or the lobe's
/// progressive image with a frame added or as held.
#[derive(Clone, Copy, PartialEq)]
enum Draw {
    Frame,
    Progressive,
    Held,
}

impl Renderer {
    /// Renders `scene` into an `Rgba8Unorm` texture (not sRGB: the transfer curve is
    /// applied in the shader) and reads it back. Into a host's own `*Srgb` target the
    /// renderer writes linear values, which the hardware encodes to the same bytes.
    pub fn render_ldr(&mut self, scene: &Scene, width: u32, height: u32) -> Result<LdrImage> {
        let format = wgpu::TextureFormat::Rgba8Unorm;
        let rgba = self.readback_render(scene, (width, height), format, Draw::Frame)?;
        Ok(LdrImage {
            width,
            height,
            rgba,
        })
    }

    /// Renders linear radiance into `Rgba32Float`, or where 32-bit float is not renderable
    /// (GL) its f32 bits into `Rgba32Uint` (`fs_ball_bits`), and reads it back as f32: the
    /// same f32 values on every backend, none clipped to a 16-bit float's range.
    pub fn render_hdr(&mut self, scene: &Scene, width: u32, height: u32) -> Result<HdrImage> {
        self.hdr_image(scene, (width, height), Draw::Frame)
    }

    /// [`Renderer::render_hdr`] averaged over frames `0..frames` of the lobe's samples
    /// (`ibl_method = "lobe"`: the estimate of `frames * ibl_samples` samples a pixel;
    /// `render --ibl-frames`): the sums started again, `frames - 1` frames added on the GPU
    /// (`Renderer::accumulate_lobe`), waiting for the device every `FRAMES_IN_FLIGHT` frames,
    /// then the last added and the mean resolved into a 32-bit target read back once. A
    /// scene whose balls use no lobe is drawn once. The renderer's lobe frame
    /// ([`Renderer::set_lobe_frame`], which the sums do not read) is 0 afterwards. Errors
    /// when `frames` is outside `1..=MAX_IBL_FRAMES`.
    pub fn render_lobe_hdr(
        &mut self,
        scene: &Scene,
        width: u32,
        height: u32,
        frames: u32,
    ) -> Result<HdrImage> {
        let max = crate::environment::lobe::MAX_IBL_FRAMES;
        if !(1..=max).contains(&frames) {
            return Err(Error::Invalid {
                what: "lobe frames",
                message: format!("{frames}: must be in 1..={max}"),
            });
        }
        self.gpu.check_size(width, height)?;
        self.set_lobe_frame(0);
        self.reset_lobe();
        for k in 1..frames {
            self.accumulate_lobe(scene, width, height)?;
            if k % FRAMES_IN_FLIGHT == 0 {
                let _ = self.gpu.device.poll(wgpu::PollType::wait_indefinitely());
            }
        }
        self.hdr_image(scene, (width, height), Draw::Progressive)
    }

    /// The linear radiance of the progressive image [`Renderer::encode_progressive`] holds
    /// for `scene` at `width x height` (as [`Renderer::render_hdr`] reads it back), adding
    /// no frame where the sums hold this scene's: what a viewer shows, for its EXR. A scene
    /// without the lobe is [`Renderer::render_hdr`]'s image.
    pub(crate) fn render_progressive_hdr(
        &mut self,
        scene: &Scene,
        width: u32,
        height: u32,
    ) -> Result<HdrImage> {
        self.hdr_image(scene, (width, height), Draw::Held)
    }

    /// [`Renderer::render_ldr`] with the truth balls' image the mean of `spp` estimates a
    /// pixel (the sums started again from zero; the other balls as always).
    #[cfg(test)]
    pub(crate) fn render_truth_ldr(
        &mut self,
        scene: &Scene,
        width: u32,
        height: u32,
        spp: u32,
    ) -> Result<LdrImage> {
        self.accumulate_frames(scene, width, height, spp)?;
        self.render_ldr(scene, width, height)
    }

    /// [`Renderer::render_hdr`] with the truth balls' image the mean of `spp` estimates a
    /// pixel (the sums started again from zero; the other balls as always).
    #[cfg(test)]
    pub(crate) fn render_truth_hdr(
        &mut self,
        scene: &Scene,
        width: u32,
        height: u32,
        spp: u32,
    ) -> Result<HdrImage> {
        self.accumulate_frames(scene, width, height, spp)?;
        self.render_hdr(scene, width, height)
    }

    /// Starts the truth's sums again and adds `spp - 1` frames of estimates (the draw that
    /// follows adds the last). Waits for the device every [`FRAMES_IN_FLIGHT`] frames, so
    /// that no more are queued.
    #[cfg(test)]
    fn accumulate_frames(
        &mut self,
        scene: &Scene,
        width: u32,
        height: u32,
        spp: u32,
    ) -> Result<()> {
        if !(1..=MAX_TRUTH_SPP).contains(&spp) {
            return Err(Error::Invalid {
                what: "samples per pixel",
                message: format!("{spp}: must be in 1..={MAX_TRUTH_SPP} on the GPU"),
            });
        }
        self.gpu.check_size(width, height)?;
        self.check_truth_supported(scene)?;
        self.reset_truth();
        for k in 1..spp {
            self.accumulate_truth(scene, width, height)?;
            if k % FRAMES_IN_FLIGHT == 0 {
                let _ = self.gpu.device.poll(wgpu::PollType::wait_indefinitely());
            }
        }
        Ok(())
    }

    /// The 32-bit target of a linear render: `Rgba32Float`, or where 32-bit float is not
    /// renderable (GL) `Rgba32Uint` for its bits.
    fn hdr_format(&self) -> Result<wgpu::TextureFormat> {
        if self.gpu.renderable(wgpu::TextureFormat::Rgba32Float) {
            Ok(wgpu::TextureFormat::Rgba32Float)
        } else if self.gpu.renderable(wgpu::TextureFormat::Rgba32Uint) {
            Ok(wgpu::TextureFormat::Rgba32Uint)
        } else {
            Err(Error::Gpu {
                message: format!("{} cannot render to a 32-bit target", self.gpu.describe()),
            })
        }
    }

    /// `scene` drawn by `draw` into a 32-bit target and read back as f32.
    fn hdr_image(
        &mut self,
        scene: &Scene,
        (width, height): (u32, u32),
        draw: Draw,
    ) -> Result<HdrImage> {
        let format = self.hdr_format()?;
        // Either format's texels are four f32s' bytes.
        let bytes = self.readback_render(scene, (width, height), format, draw)?;
        Ok(HdrImage {
            width,
            height,
            rgba: bytemuck::pod_collect_to_vec(&bytes),
        })
    }

    /// Draws `scene` into a new `width x height` texture of `format` and reads its texels
    /// back.
    fn readback_render(
        &mut self,
        scene: &Scene,
        (width, height): (u32, u32),
        format: wgpu::TextureFormat,
        draw: Draw,
    ) -> Result<Vec<u8>> {
        self.gpu.check_size(width, height)?;
        self.gpu.check()?;
        self.check_truth_supported(scene)?;
        let device = self.gpu.device.clone();
        let readback = Readback::new(&device, format, (width, height))?;
        self.submit_scoped(|r, encoder| {
            let texture = crate::gpu::sums::texture(
                &device,
                "frame",
                format,
                (width, height),
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            );
            let view = texture.create_view(&Default::default());
            let target = Target {
                view: &view,
                format,
                width,
                height,
            };
            let encoded = match draw {
                Draw::Frame => r.encode(scene, target, encoder),
                Draw::Progressive => r.progressive(scene, target, encoder, |_| true),
                Draw::Held => r.progressive(scene, target, encoder, |_| false),
            };
            readback.record(encoder, &texture);
            encoded
        })?;
        // A lost device fails the read; its own message says why, so it goes first.
        let data = readback.read(&device);
        self.gpu.check()?;
        data
    }

    /// The Monte Carlo of the model on the GPU: `spp` estimates a covered pixel of `scene`
    /// at `width x height` from `seed`, with the CPU estimator's strategies and weights
    /// (`crate::cpu::render_montecarlo`) in f32, and each pixel's standard error.
    /// Errors as the CPU's on a bad `spp` or map, and where the device cannot render to
    /// `Rgba32Float` (GL).
    pub fn render_montecarlo(
        &mut self,
        scene: &Scene,
        (width, height): (u32, u32),
        spp: u32,
        seed: u64,
    ) -> Result<MonteCarloImage> {
        self.render_montecarlo_progressive(scene, (width, height), (spp, seed), |_| true)
    }

    /// [`Renderer::render_montecarlo`] of one [`Part`](Part) of the model:
    /// `Part::Multiple` integrates only the lobe the term adds (the GPU twin of
    /// [`crate::cpu::render_montecarlo_part`]), the reference for a real-time term alone.
    pub fn render_montecarlo_part(
        &mut self,
        scene: &Scene,
        size: (u32, u32),
        (spp, seed): (u32, u64),
        part: Part,
    ) -> Result<MonteCarloImage> {
        self.montecarlo_checked(scene, size, (spp, seed, part), |_| true)
    }

    /// [`Renderer::render_montecarlo`] in passes of [`crate::gpu::MC_PASS_SAMPLES`] estimates:
    /// after each pass but the last, `keep_going(estimates so far)` may stop the render
    /// (the image then holds the passes done; its `spp` says how many).
    pub(crate) fn render_montecarlo_progressive(
        &mut self,
        scene: &Scene,
        (width, height): (u32, u32),
        (spp, seed): (u32, u64),
        keep_going: impl FnMut(u32) -> bool,
    ) -> Result<MonteCarloImage> {
        let whole = Part::Whole;
        self.montecarlo_checked(scene, (width, height), (spp, seed, whole), keep_going)
    }

    /// The checks and error scopes around [`Renderer::montecarlo_passes`].
    fn montecarlo_checked(
        &mut self,
        scene: &Scene,
        (width, height): (u32, u32),
        (spp, seed, part): (u32, u64, Part),
        keep_going: impl FnMut(u32) -> bool,
    ) -> Result<MonteCarloImage> {
        crate::stats::check_montecarlo_inputs(scene, spp)?;
        self.gpu.check_size(width, height)?;
        self.gpu.check()?;
        if !self.truth_supported() {
            return Err(Error::Gpu {
                message: format!(
                    "{} cannot render to Rgba32Float: no Monte Carlo on this device",
                    self.gpu.describe()
                ),
            });
        }
        self.scoped(|r| r.montecarlo_passes(scene, (width, height), (spp, seed, part), keep_going))
    }

    /// The passes of [`Renderer::render_montecarlo_progressive`], within its error scopes.
    fn montecarlo_passes(
        &mut self,
        scene: &Scene,
        size: (u32, u32),
        (spp, seed, part): (u32, u64, Part),
        keep_going: impl FnMut(u32) -> bool,
    ) -> Result<MonteCarloImage> {
        let frame = self.prepare_frame(scene, size.0, size.1)?;
        let device = &self.gpu.device;
        let (group0, group1) = (&self.bindings.layout, &self.environment.layout);
        let pass = self
            .montecarlo
            .get_or_insert_with(|| MonteCarloPass::new(device, group0, group1));
        let mc = McFrame {
            group0: &frame.group0,
            group1: &frame.group1,
            balls: &frame.balls,
            hidden: &frame.hidden,
            geometry: frame.plan.geometry,
            mu_axis: frame.plan.bake.layout.mu_axis,
            // The scene's pixel filter: antialiased silhouettes as the real-time renderers
            // draw them (docs/design/antialiasing.md, "Monte Carlo").
            variant: crate::gpu::plan::Variant {
                aa: scene.antialias,
                ..frame.plan.truth_variant
            },
            size,
            part,
        };
        pass.render(&self.gpu, scene, &mc, (spp, seed), keep_going)
    }
}
