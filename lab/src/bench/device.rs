//! The bench's GPU: a device with the adapter's own limits and, where the adapter offers it,
//! `FLOAT32_FILTERABLE` (hardware filtering of R32Float tables); the tables as textures in
//! each storage format; waiting for the queue to drain.

use shadeballs::error::{Error, Result};
use shadeballs::gpu::{Backend, Gpu};
use shadeballs::lut::{Storage, Tables};

/// Opens the first adapter `WGPU_BACKEND` allows (Vulkan or GL by default), with
/// `FLOAT32_FILTERABLE` where offered.
pub fn open() -> Result<Gpu> {
    let backends = Backend::Auto
        .wgpu_backends()
        .unwrap_or(wgpu::Backends::VULKAN | wgpu::Backends::GL);
    Gpu::with_features(backends, wgpu::Features::FLOAT32_FILTERABLE)
}

/// Blocks until the GPU has finished all submitted work.
pub fn wait(gpu: &Gpu) -> Result<()> {
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map(|_| ())
        .map_err(|e| Error::Gpu {
            message: format!("waiting for the GPU: {e}"),
        })
}

/// The texture format that holds a table of `storage`.
pub fn format_of(storage: Storage) -> wgpu::TextureFormat {
    match storage {
        Storage::F32 => wgpu::TextureFormat::R32Float,
        Storage::F16 => wgpu::TextureFormat::R16Float,
        Storage::Unorm8 => wgpu::TextureFormat::R8Unorm,
    }
}

/// Whether the sampler may filter `storage`'s format on this device.
pub fn filterable(gpu: &Gpu, storage: Storage) -> bool {
    storage != Storage::F32
        || gpu
            .device
            .features()
            .contains(wgpu::Features::FLOAT32_FILTERABLE)
}

/// `1 - E` of `tables` (already quantised to the layout's storage) as a texture of that
/// storage's format, `mu_size x r_size`.
pub fn loss_texture(gpu: &Gpu, tables: &Tables) -> wgpu::TextureView {
    let l = tables.layout();
    let bytes: Vec<u8> = match l.storage {
        Storage::F32 => bytemuck::cast_slice(&tables.stored_loss).to_vec(),
        Storage::F16 => tables
            .stored_loss
            .iter()
            .flat_map(|&v| half::f16::from_f32(v).to_le_bytes())
            .collect(),
        Storage::Unorm8 => tables
            .stored_loss
            .iter()
            .map(|&v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
            .collect(),
    };
    let size = wgpu::Extent3d {
        width: l.mu_size as u32,
        height: l.r_size as u32,
        depth_or_array_layers: 1,
    };
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("bench 1 - E"),
        size,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: format_of(l.storage),
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    gpu.queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture: &texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        &bytes,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(size.width * l.storage.bytes_per_texel() as u32),
            rows_per_image: Some(size.height),
        },
        size,
    );
    texture.create_view(&Default::default())
}

/// Maps the first `size` bytes of `buffer` (MAP_READ, its copy already waited for) and
/// copies them out.
pub fn read(gpu: &Gpu, buffer: &wgpu::Buffer, size: u64) -> Result<Vec<u8>> {
    shadeballs::gpu::readback::read_prefix(&gpu.device, buffer, size)
}

/// A compute-stage bind group layout entry.
pub fn entry(binding: u32, ty: wgpu::BindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty,
        count: None,
    }
}

/// A 2-D float texture binding.
pub fn texture(filterable: bool) -> wgpu::BindingType {
    wgpu::BindingType::Texture {
        sample_type: wgpu::TextureSampleType::Float { filterable },
        view_dimension: wgpu::TextureViewDimension::D2,
        multisampled: false,
    }
}

/// A buffer binding of `ty`.
pub fn buffer(ty: wgpu::BufferBindingType) -> wgpu::BindingType {
    wgpu::BindingType::Buffer {
        ty,
        has_dynamic_offset: false,
        min_binding_size: None,
    }
}

/// The format the bench's frames are drawn in (display values, as a PNG).
pub const FRAME_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// A `w x h` colour target of [`FRAME_FORMAT`] to time frames in, and its view.
pub fn frame_target(gpu: &Gpu, w: u32, h: u32) -> (wgpu::Texture, wgpu::TextureView) {
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("bench frame"),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: FRAME_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    (texture, view)
}
