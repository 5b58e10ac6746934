//! Choosing a backend and opening a device.

use crate::error::{Error, Result};

/// Where to render: the command line's `--backend`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Backend {
    /// Any GPU adapter wgpu finds (honours `WGPU_BACKEND`); the CPU renderer if none.
    #[default]
    Auto,
    Vulkan,
    Gl,
    /// The CPU reference renderer.
    Cpu,
}

impl Backend {
    pub const ALL: [Backend; 4] = [Backend::Auto, Backend::Vulkan, Backend::Gl, Backend::Cpu];

    pub fn name(self) -> &'static str {
        match self {
            Backend::Auto => "auto",
            Backend::Vulkan => "vulkan",
            Backend::Gl => "gl",
            Backend::Cpu => "cpu",
        }
    }

    /// The wgpu backends this choice allows (`None` for the CPU renderer).
    pub fn wgpu_backends(self) -> Option<wgpu::Backends> {
        match self {
            Backend::Auto => Some(
                wgpu::Backends::from_env().unwrap_or(wgpu::Backends::VULKAN | wgpu::Backends::GL),
            ),
            Backend::Vulkan => Some(wgpu::Backends::VULKAN),
            Backend::Gl => Some(wgpu::Backends::GL),
            Backend::Cpu => None,
        }
    }
}

crate::named_enum!(Backend, "backend");

/// An adapter, its device and queue.
pub struct Gpu {
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
}

impl Gpu {
    /// Opens the first adapter of `backends` with the adapter's own limits (lavapipe:
    /// 16384-texel textures).
    pub fn new(backends: wgpu::Backends) -> Result<Gpu> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        desc.backends = backends;
        let instance = wgpu::Instance::new(desc);
        let adapter =
            pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))
                .map_err(|e| Error::NoAdapter {
                backends: format!("{backends:?}"),
                message: e.to_string(),
            })?;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("shadeballs"),
            required_limits: adapter.limits(),
            ..Default::default()
        }))
        .map_err(|e| Error::Gpu {
            message: format!("cannot open the device: {e}"),
        })?;
        Ok(Gpu {
            adapter,
            device,
            queue,
        })
    }

    /// "name (backend)" of the adapter, for messages.
    pub fn describe(&self) -> String {
        let info = self.adapter.get_info();
        format!("{} ({:?})", info.name, info.backend)
    }

    /// Whether `format` can be a render target here (GL cannot render to Rgba32Float).
    pub fn renderable(&self, format: wgpu::TextureFormat) -> bool {
        self.adapter
            .get_texture_format_features(format)
            .allowed_usages
            .contains(wgpu::TextureUsages::RENDER_ATTACHMENT)
    }

    /// Checks an image size against 1 and the device's largest 2-D texture.
    pub fn check_size(&self, width: u32, height: u32) -> Result<()> {
        let max = self.device.limits().max_texture_dimension_2d;
        if width == 0 || height == 0 || width > max || height > max {
            return Err(Error::Invalid {
                what: "image size",
                message: format!("{width}x{height}: each side must be in 1..={max} on this device"),
            });
        }
        Ok(())
    }
}
