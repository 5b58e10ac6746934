//! Rendering without a window: into a texture, copied to a buffer (rows padded to 256
//! bytes), mapped and returned.

use super::renderer::{Renderer, Target};
use crate::error::{Error, Result};
use crate::scene::Scene;

/// Display values, RGBA8, row-major, row 0 at the top.
pub struct LdrImage {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
}

/// Linear radiance, RGBA f32, row-major, row 0 at the top.
pub struct HdrImage {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<f32>,
}

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

    /// Renders linear radiance into `Rgba32Float` (or `Rgba16Float` where 32-bit float is
    /// not renderable, as on GL) and reads it back as f32.
    pub fn render_hdr(&mut self, scene: &Scene, width: u32, height: u32) -> Result<HdrImage> {
        let format = if self.gpu.renderable(wgpu::TextureFormat::Rgba32Float) {
            wgpu::TextureFormat::Rgba32Float
        } else if self.gpu.renderable(wgpu::TextureFormat::Rgba16Float) {
            wgpu::TextureFormat::Rgba16Float
        } else {
            return Err(Error::Gpu {
                message: format!("{} cannot render to a float target", self.gpu.describe()),
            });
        };
        let bytes = self.render_readback(scene, width, height, format)?;
        let rgba = match format {
            wgpu::TextureFormat::Rgba32Float => bytemuck::pod_collect_to_vec(&bytes),
            _ => bytes
                .chunks_exact(2)
                .map(|b| half::f16::from_le_bytes([b[0], b[1]]).to_f32())
                .collect(),
        };
        Ok(HdrImage {
            width,
            height,
            rgba,
        })
    }

    fn render_readback(
        &mut self,
        scene: &Scene,
        width: u32,
        height: u32,
        format: wgpu::TextureFormat,
    ) -> Result<Vec<u8>> {
        self.gpu.check_size(width, height)?;
        self.gpu.check()?;
        let texel = format.block_copy_size(None).unwrap_or(4);
        let row = width * texel;
        let padded =
            row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let bytes = padded as u64 * height as u64;
        let max = self.gpu.device.limits().max_buffer_size;
        if bytes > max {
            return Err(Error::Invalid {
                what: "image size",
                message: format!(
                    "{width}x{height} in {format:?} needs a {bytes}-byte read-back buffer; \
                     this device allows {max} (use a smaller size or a .png)"
                ),
            });
        }
        let device = self.gpu.device.clone();
        let scopes = super::Scopes::push(&device);
        let size = wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        };
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("frame"),
            size,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: bytes,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
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
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded),
                    rows_per_image: Some(height),
                },
            },
            size,
        );
        self.gpu.queue.submit([encoder.finish()]);
        scopes.pop()?;
        self.gpu.check()?;
        // A lost device fails the read; its own message says why, so it goes first.
        let data = read_buffer(&device, &buffer);
        self.gpu.check()?;
        let data = data?;
        let mut out = Vec::with_capacity((row * height) as usize);
        for y in 0..height as usize {
            let start = y * padded as usize;
            out.extend_from_slice(&data[start..start + row as usize]);
        }
        Ok(out)
    }
}

/// Maps `buffer` for reading, waits, and copies its contents out.
pub(super) fn read_buffer(device: &wgpu::Device, buffer: &wgpu::Buffer) -> Result<Vec<u8>> {
    let (tx, rx) = std::sync::mpsc::channel();
    buffer.slice(..).map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| Error::Gpu {
            message: format!("waiting for the GPU: {e}"),
        })?;
    // The wait above runs the callback; one that never ran means the device failed.
    let mapped = rx.try_recv().map_err(|_| Error::Gpu {
        message: "the read-back did not complete (the device failed)".to_string(),
    })?;
    mapped.map_err(|e| Error::Gpu {
        message: format!("mapping the readback buffer: {e}"),
    })?;
    let data = buffer
        .slice(..)
        .get_mapped_range()
        .map_err(|e| Error::Gpu {
            message: format!("mapping the readback buffer: {e}"),
        })?
        .to_vec();
    buffer.unmap();
    Ok(data)
}
