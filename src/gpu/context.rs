//! Choosing a backend and opening a device, and keeping its failures as errors.
//!
//! wgpu reports errors that no error scope captures (an out-of-memory texture, any call on
//! a destroyed or lost device) to a handler that panics by default. A device this crate
//! opens ([`Gpu::new`]) gets a handler and a device-lost callback that record them instead,
//! and every operation of the renderer asks [`Gpu::check`] afterwards, so a failing device
//! is an [`Error::Gpu`], never a panic. A host's device ([`Gpu::from_device`]) keeps the
//! host's handlers: this crate installs nothing on it and relies on its error scopes.

use std::sync::{Arc, Mutex};

use crate::error::{one_line, Error, Result};

/// Where to render: the command line's `--backend`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Backend {
    /// Any GPU adapter wgpu finds (honours `WGPU_BACKEND`); the CPU renderer if none.
    #[default]
    Auto,
    /// Vulkan adapters only (`wgpu::Backends::VULKAN`).
    Vulkan,
    /// OpenGL adapters only (`wgpu::Backends::GL`).
    Gl,
    /// The CPU reference renderer.
    Cpu,
    /// The Monte Carlo reference: the model integrated against the lights and the
    /// environment by importance sampling, on any GPU adapter wgpu finds
    /// ([`crate::Renderer::render_montecarlo`]), else on the CPU (`crate::cpu::montecarlo`).
    Montecarlo,
    /// The CPU Monte Carlo reference (`crate::cpu::montecarlo`) whatever the adapters.
    MontecarloCpu,
    /// The CPU truth (`crate::cpu::truth`): every ball shaded with the random walk.
    Truth,
}

impl Backend {
    /// Every backend, in a fixed order.
    pub(crate) const ALL: [Backend; 7] = [
        Backend::Auto,
        Backend::Vulkan,
        Backend::Gl,
        Backend::Cpu,
        Backend::Montecarlo,
        Backend::MontecarloCpu,
        Backend::Truth,
    ];

    /// The name used on the command line and in messages.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Backend::Auto => "auto",
            Backend::Vulkan => "vulkan",
            Backend::Gl => "gl",
            Backend::Cpu => "cpu",
            Backend::Montecarlo => "montecarlo",
            Backend::MontecarloCpu => "montecarlo-cpu",
            Backend::Truth => "truth",
        }
    }

    /// The wgpu backends this choice allows (`None` for the CPU renderers and the Monte
    /// Carlo backends: `render --backend montecarlo` tries `auto`'s adapters itself).
    pub fn wgpu_backends(self) -> Option<wgpu::Backends> {
        match self {
            Backend::Auto => Some(
                wgpu::Backends::from_env().unwrap_or(wgpu::Backends::VULKAN | wgpu::Backends::GL),
            ),
            Backend::Vulkan => Some(wgpu::Backends::VULKAN),
            Backend::Gl => Some(wgpu::Backends::GL),
            Backend::Cpu | Backend::Montecarlo | Backend::MontecarloCpu | Backend::Truth => None,
        }
    }
}

crate::named_enum!(Backend, "backend");

/// A device and its queue, and the adapter when this crate opened the device.
pub struct Gpu {
    /// The adapter the device was opened on; `None` for a host's device
    /// (`Gpu::from_device`).
    pub adapter: Option<wgpu::Adapter>,
    /// The device the renderer creates its resources on.
    pub device: wgpu::Device,
    /// The device's queue.
    pub queue: wgpu::Queue,
    faults: Arc<Mutex<Faults>>,
}

/// What the device reported outside any error scope.
#[derive(Default)]
struct Faults {
    /// Why the device was lost (destroyed, driver reset): every later operation fails.
    lost: Option<String>,
    /// The first uncaptured error since the last [`Gpu::check`].
    uncaptured: Option<String>,
}

fn record(faults: &Mutex<Faults>, f: impl FnOnce(&mut Faults)) {
    // A poisoned lock still holds the data; a fault must never be lost to it.
    let mut guard = faults.lock().unwrap_or_else(|e| e.into_inner());
    f(&mut guard);
}

impl Gpu {
    /// Opens the first adapter of `backends` with the adapter's own limits (lavapipe:
    /// 16384-texel textures).
    pub fn new(backends: wgpu::Backends) -> Result<Gpu> {
        Self::with_features(backends, wgpu::Features::empty())
    }

    /// As [`Gpu::new`], also enabling those of `wanted` the adapter offers (the bench asks
    /// for `FLOAT32_FILTERABLE`).
    pub fn with_features(backends: wgpu::Backends, wanted: wgpu::Features) -> Result<Gpu> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        desc.backends = backends;
        let instance = wgpu::Instance::new(desc);
        Self::open(&instance, backends, None, wanted)
    }

    /// Opens the first adapter of `instance` (created for `backends`; one that can present
    /// to `surface`, if given: the viewer's window) with the adapter's own limits and those
    /// of `wanted` it offers.
    pub(crate) fn open(
        instance: &wgpu::Instance,
        backends: wgpu::Backends,
        surface: Option<&wgpu::Surface<'_>>,
        wanted: wgpu::Features,
    ) -> Result<Gpu> {
        let options = wgpu::RequestAdapterOptions {
            compatible_surface: surface,
            ..Default::default()
        };
        let adapter = pollster::block_on(instance.request_adapter(&options)).map_err(|e| {
            Error::NoAdapter {
                backends: format!("{backends:?}"),
                // Under a memory limit the driver's failure says "no adapter" too
                // (issue 38, 8): the memory is named, not a package to install.
                message: match crate::memory::short_for_driver() {
                    Some(short) => format!("{e}; {short}"),
                    None => e.to_string(),
                },
            }
        })?;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("shadeballs"),
            required_features: adapter.features() & wanted,
            required_limits: adapter.limits(),
            ..Default::default()
        }))
        .map_err(|e| Error::Gpu {
            message: format!("cannot open the device: {e}"),
        })?;
        let info = adapter.get_info();
        log::info!(
            "opened {} ({:?}, {})",
            info.name,
            info.backend,
            info.driver_info
        );
        let faults = Arc::new(Mutex::new(Faults::default()));
        let sink = faults.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            log::debug!("uncaptured wgpu error (returned by the next check): {e}");
            record(&sink, |f| {
                f.uncaptured.get_or_insert_with(|| one_line(&e.to_string()));
            })
        }));
        let sink = faults.clone();
        device.set_device_lost_callback(move |reason, message| {
            record(&sink, |f| {
                f.lost = Some(match reason {
                    wgpu::DeviceLostReason::Destroyed => "the device was destroyed".to_string(),
                    _ => format!("the device was lost ({})", one_line(&message)),
                });
            })
        });
        Ok(Gpu {
            adapter: Some(adapter),
            device,
            queue,
            faults,
        })
    }

    /// Another handle on this device, its adapter and what it reported (the viewer's second
    /// renderer draws on the window's device).
    pub(crate) fn share(&self) -> Gpu {
        Gpu {
            adapter: self.adapter.clone(),
            device: self.device.clone(),
            queue: self.queue.clone(),
            faults: Arc::clone(&self.faults),
        }
    }

    /// A host program's device and queue (handles: cloning shares them): no adapter of this
    /// crate's, no handler or callback installed.
    pub(crate) fn from_device(device: &wgpu::Device, queue: &wgpu::Queue) -> Gpu {
        Gpu {
            adapter: None,
            device: device.clone(),
            queue: queue.clone(),
            faults: Arc::default(),
        }
    }

    /// `Err` when the device is lost, or when an error escaped every error scope since the
    /// last call (that error is then cleared: an out-of-memory texture does not poison the
    /// next, smaller frame).
    pub(crate) fn check(&self) -> Result<()> {
        let mut guard = self.faults.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(lost) = &guard.lost {
            return Err(Error::Gpu {
                message: format!("{lost}; no further GPU work is possible"),
            });
        }
        match guard.uncaptured.take() {
            Some(message) => Err(Error::Gpu { message }),
            None => Ok(()),
        }
    }

    /// "name (backend)" of the adapter, for messages.
    pub fn describe(&self) -> String {
        match &self.adapter {
            Some(adapter) => {
                let info = adapter.get_info();
                format!("{} ({:?})", info.name, info.backend)
            }
            None => "the host's device".to_string(),
        }
    }

    /// Whether `format` can be a render target here (GL cannot render to Rgba32Float). On a
    /// host's device (no adapter here) a 1x1 target is made in an error scope: what WebGPU
    /// guarantees is not what a downlevel device (GL) allows, and a texture the device
    /// refuses is a validation error, not a panic.
    pub(crate) fn renderable(&self, format: wgpu::TextureFormat) -> bool {
        let Some(adapter) = &self.adapter else {
            let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
            let probe = super::sums::texture(
                &self.device,
                "renderable probe",
                format,
                (1, 1),
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            );
            probe.destroy();
            return pollster::block_on(scope.pop()).is_none();
        };
        adapter
            .get_texture_format_features(format)
            .allowed_usages
            .contains(wgpu::TextureUsages::RENDER_ATTACHMENT)
    }

    /// Checks an image size against 1 and the device's largest 2-D texture.
    /// (`Renderer::render_ldr` / `render_hdr` also check the read-back buffer's size.)
    pub(crate) fn check_size(&self, width: u32, height: u32) -> Result<()> {
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
