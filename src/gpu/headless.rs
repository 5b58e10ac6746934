//! Rendering without a window: into a texture, read back ([`Readback`]) and returned
//! (the work of [`Renderer::render_ldr`], [`Renderer::render_hdr`] and the truth renders).

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

/// Renders `scene` into an `Rgba8Unorm` texture and reads it back ([`Renderer::render_ldr`]).
pub(super) fn render_ldr(
    r: &mut Renderer,
    scene: &Scene,
    width: u32,
    height: u32,
) -> Result<LdrImage> {
    let format = wgpu::TextureFormat::Rgba8Unorm;
    let rgba = render_readback(r, scene, (width, height), format, Draw::Frame)?;
    Ok(LdrImage {
        width,
        height,
        rgba,
    })
}

/// Renders linear radiance into a 32-bit target and reads it back as f32
/// ([`Renderer::render_hdr`]).
pub(super) fn render_hdr(
    r: &mut Renderer,
    scene: &Scene,
    width: u32,
    height: u32,
) -> Result<HdrImage> {
    let format = hdr_format(r)?;
    // Either format's texels are four f32s' bytes.
    let bytes = render_readback(r, scene, (width, height), format, Draw::Frame)?;
    let rgba = bytemuck::pod_collect_to_vec(&bytes);
    Ok(HdrImage {
        width,
        height,
        rgba,
    })
}

/// Starts the truth's sums again and adds `spp - 1` frames of estimates (the draw that
/// follows adds the last). Waits for the device every [`FRAMES_IN_FLIGHT`] frames, so that
/// no more are queued.
pub(super) fn accumulate_frames(
    r: &mut Renderer,
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
    r.gpu().check_size(width, height)?;
    r.check_truth_supported(scene)?;
    r.reset_truth();
    for k in 1..spp {
        r.accumulate_truth(scene, width, height)?;
        if k % FRAMES_IN_FLIGHT == 0 {
            let _ = r.gpu().device.poll(wgpu::PollType::wait_indefinitely());
        }
    }
    Ok(())
}

/// The 32-bit target of a linear render: `Rgba32Float`, or where 32-bit float is not
/// renderable (GL) `Rgba32Uint` for its bits.
fn hdr_format(r: &Renderer) -> Result<wgpu::TextureFormat> {
    if r.gpu().renderable(wgpu::TextureFormat::Rgba32Float) {
        Ok(wgpu::TextureFormat::Rgba32Float)
    } else if r.gpu().renderable(wgpu::TextureFormat::Rgba32Uint) {
        Ok(wgpu::TextureFormat::Rgba32Uint)
    } else {
        Err(Error::Gpu {
            message: format!("{} cannot render to a 32-bit target", r.gpu().describe()),
        })
    }
}

/// How [`render_readback`] draws: one frame ([`Renderer::encode`]), or the lobe's
/// progressive image with a frame added (`Renderer::encode_lobe_mean`) or as held
/// (`Renderer::encode_lobe_held`).
#[derive(Clone, Copy, PartialEq)]
enum Draw {
    Frame,
    Progressive,
    Held,
}

/// The progressive image held, read back as f32 ([`Renderer::render_progressive_hdr`]).
pub(super) fn render_progressive_hdr(
    r: &mut Renderer,
    scene: &Scene,
    (width, height): (u32, u32),
) -> Result<HdrImage> {
    let format = hdr_format(r)?;
    let bytes = render_readback(r, scene, (width, height), format, Draw::Held)?;
    Ok(HdrImage {
        width,
        height,
        rgba: bytemuck::pod_collect_to_vec(&bytes),
    })
}

/// Draws `scene` into a new `width x height` texture of `format` and reads its texels back.
fn render_readback(
    r: &mut Renderer,
    scene: &Scene,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    draw: Draw,
) -> Result<Vec<u8>> {
    r.gpu().check_size(width, height)?;
    r.gpu().check()?;
    r.check_truth_supported(scene)?;
    let device = r.gpu().device.clone();
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
    let target = Target {
        view: &view,
        format,
        width,
        height,
    };
    let encoded = match draw {
        Draw::Frame => r.encode(scene, target, &mut encoder),
        Draw::Progressive => r.encode_lobe_mean(scene, target, &mut encoder),
        Draw::Held => r.encode_lobe_held(scene, target, &mut encoder),
    };
    readback.record(&mut encoder, &texture);
    r.gpu().queue.submit([encoder.finish()]);
    scopes.pop()?;
    encoded?;
    r.gpu().check()?;
    // A lost device fails the read; its own message says why, so it goes first.
    let data = readback.read(&device);
    r.gpu().check()?;
    data
}

/// The mean of frames `0..frames` of the lobe's samples ([`Renderer::render_lobe_hdr`]):
/// the sums started again, `frames - 1` frames added on the GPU
/// ([`Renderer::accumulate_lobe`]), waiting for the device every [`FRAMES_IN_FLIGHT`], then
/// the last added and the mean resolved (`Renderer::encode_lobe_mean`) into a 32-bit
/// target read back once. A scene whose balls use no lobe is drawn once. The renderer's
/// lobe frame ([`Renderer::set_lobe_frame`], which the sums do not read) is 0 afterwards.
pub(super) fn render_lobe_hdr(
    r: &mut Renderer,
    scene: &Scene,
    (width, height): (u32, u32),
    frames: u32,
) -> Result<HdrImage> {
    if !(1..=crate::environment::lobe::MAX_IBL_FRAMES).contains(&frames) {
        return Err(Error::Invalid {
            what: "lobe frames",
            message: format!(
                "{frames}: must be in 1..={}",
                crate::environment::lobe::MAX_IBL_FRAMES
            ),
        });
    }
    r.gpu().check_size(width, height)?;
    r.set_lobe_frame(0);
    r.reset_lobe();
    for k in 1..frames {
        r.accumulate_lobe(scene, width, height)?;
        if k % FRAMES_IN_FLIGHT == 0 {
            let _ = r.gpu().device.poll(wgpu::PollType::wait_indefinitely());
        }
    }
    let format = hdr_format(r)?;
    let bytes = render_readback(r, scene, (width, height), format, Draw::Progressive)?;
    Ok(HdrImage {
        width,
        height,
        rgba: bytemuck::pod_collect_to_vec(&bytes),
    })
}
