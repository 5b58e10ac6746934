//! Reading a texture back to the CPU: a copy into a buffer whose rows are padded to
//! `COPY_BYTES_PER_ROW_ALIGNMENT` (256 bytes), mapped after the submit, rows unpadded.
//! Serves the headless renderer and the viewer's screenshot.

use crate::error::{Error, Result};

/// A buffer for one image, its copy recorded on an encoder ([`Readback::record`]), read
/// once the encoder is submitted ([`Readback::read`]).
pub struct Readback {
    buffer: wgpu::Buffer,
    /// Bytes per row of the image, and per row in the buffer (padded).
    row: u32,
    padded: u32,
    height: u32,
}

impl Readback {
    /// A buffer for a `width x height` image of `format`; fails when it would exceed the
    /// device's limit.
    pub fn new(
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        (width, height): (u32, u32),
    ) -> Result<Readback> {
        let texel = format.block_copy_size(None).unwrap_or(4);
        let row = width * texel;
        let padded =
            row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let bytes = padded as u64 * height as u64;
        let max = device.limits().max_buffer_size;
        if bytes > max {
            return Err(Error::Invalid {
                what: "image size",
                message: format!(
                    "{width}x{height} in {format:?} needs a {bytes}-byte read-back buffer; \
                     this device allows {max} (use a smaller size or a .png)"
                ),
            });
        }
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: bytes,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        Ok(Readback {
            buffer,
            row,
            padded,
            height,
        })
    }

    /// Records on `encoder` the copy of the image (the top-left corner of `texture`, whose
    /// format is the one given to [`Readback::new`]) into the buffer.
    pub fn record(&self, encoder: &mut wgpu::CommandEncoder, texture: &wgpu::Texture) {
        let width = self.row / texture.format().block_copy_size(None).unwrap_or(4);
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &self.buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.padded),
                    rows_per_image: Some(self.height),
                },
            },
            wgpu::Extent3d {
                width,
                height: self.height,
                depth_or_array_layers: 1,
            },
        );
    }

    /// Waits for the copy (its encoder must have been submitted) and returns the image's
    /// bytes, row-major, row 0 at the top, without padding.
    pub fn read(self, device: &wgpu::Device) -> Result<Vec<u8>> {
        let data = read_buffer(device, &self.buffer)?;
        let mut out = Vec::with_capacity(self.row as usize * self.height as usize);
        for y in 0..self.height as usize {
            let start = y * self.padded as usize;
            out.extend_from_slice(&data[start..start + self.row as usize]);
        }
        Ok(out)
    }
}

/// Maps `buffer` for reading, waits, and copies its contents out.
pub(crate) fn read_buffer(device: &wgpu::Device, buffer: &wgpu::Buffer) -> Result<Vec<u8>> {
    read_prefix(device, buffer, buffer.size())
}

/// As `read_buffer`, the first `len` bytes only.
pub fn read_prefix(device: &wgpu::Device, buffer: &wgpu::Buffer, len: u64) -> Result<Vec<u8>> {
    let slice = buffer.slice(..len);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
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
    let data = slice
        .get_mapped_range()
        .map_err(|e| Error::Gpu {
            message: format!("mapping the readback buffer: {e}"),
        })?
        .to_vec();
    buffer.unmap();
    Ok(data)
}
