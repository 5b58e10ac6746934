//! Rendering without a window: into a texture, read back ([`Readback`]) and returned.

use super::readback::Readback;
use super::renderer::{Renderer, Target};
use crate::error::{Error, Result};
use crate::scene::Scene;

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
pub const MAX_TRUTH_SPP: u32 = 1024;

/// Truth frames queued before the headless render waits for the device.
const FRAMES_IN_FLIGHT: u32 = 8;

impl Renderer {
    /// Renders `scene` into an `Rgba8Unorm` texture (not sRGB: gamma is applied in the
    /// shader) and reads it back.
    pub fn render_ldr(&mut self, scene: &Scene, width: u32, height: u32) -> Result<LdrImage> {
        let rgba = self.render_readback(scene, width, height, wgpu::TextureFormat::Rgba8Unorm)?;
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
        let format = if self.gpu().renderable(wgpu::TextureFormat::Rgba32Float) {
            wgpu::TextureFormat::Rgba32Float
        } else if self.gpu().renderable(wgpu::TextureFormat::Rgba32Uint) {
            wgpu::TextureFormat::Rgba32Uint
        } else {
            return Err(Error::Gpu {
                message: format!("{} cannot render to a 32-bit target", self.gpu().describe()),
            });
        };
        // Either format's texels are four f32s' bytes.
        let bytes = self.render_readback(scene, width, height, format)?;
        let rgba = bytemuck::pod_collect_to_vec(&bytes);
        Ok(HdrImage {
            width,
            height,
            rgba,
        })
    }

    /// [`Renderer::render_ldr`] with the truth balls' image the mean of `spp` estimates a
    /// pixel (the sums started again from zero; the other balls as always).
    pub fn render_truth_ldr(
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
    pub fn render_truth_hdr(
        &mut self,
        scene: &Scene,
        width: u32,
        height: u32,
        spp: u32,
    ) -> Result<HdrImage> {
        self.accumulate_frames(scene, width, height, spp)?;
        self.render_hdr(scene, width, height)
    }

    /// Starts the truth's sums again and adds `spp - 1` frames of estimates (the draw
    /// that follows adds the last). Waits for the device every [`FRAMES_IN_FLIGHT`]
    /// frames, so that no more are queued.
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
                message: format!("{spp}: --spp must be in 1..={MAX_TRUTH_SPP}"),
            });
        }
        self.gpu().check_size(width, height)?;
        if scene.has_truth() && !self.truth_supported() {
            return Err(Error::Gpu {
                message: format!(
                    "{} cannot render to Rgba32Float, which the truth's sums need \
                     (use --backend vulkan)",
                    self.gpu().describe()
                ),
            });
        }
        self.reset_truth();
        for k in 1..spp {
            self.accumulate_truth(scene, width, height)?;
            if k % FRAMES_IN_FLIGHT == 0 {
                let _ = self.gpu().device.poll(wgpu::PollType::wait_indefinitely());
            }
        }
        Ok(())
    }

    fn render_readback(
        &mut self,
        scene: &Scene,
        width: u32,
        height: u32,
        format: wgpu::TextureFormat,
    ) -> Result<Vec<u8>> {
        self.gpu().check_size(width, height)?;
        self.gpu().check()?;
        if scene.has_truth() && !self.truth_supported() {
            return Err(Error::Gpu {
                message: format!(
                    "{} cannot render to Rgba32Float, which the truth balls' sums need \
                     (use --backend vulkan)",
                    self.gpu().describe()
                ),
            });
        }
        let device = self.gpu().device.clone();
        let readback = Readback::new(&device, format, (width, height))?;
        let scopes = super::Scopes::push(&device);
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("frame"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        let mut encoder = device.create_command_encoder(&Default::default());
        self.encode(
            scene,
            Target {
                view: &view,
                format,
                width,
                height,
            },
            &mut encoder,
        );
        readback.record(&mut encoder, &texture);
        self.gpu().queue.submit([encoder.finish()]);
        scopes.pop()?;
        self.gpu().check()?;
        // A lost device fails the read; its own message says why, so it goes first.
        let data = readback.read(&device);
        self.gpu().check()?;
        data
    }
}
