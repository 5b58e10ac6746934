//! The per-ball draw's depth target (`Depth32Float`, the hit's distance scaled:
//! `frag_depth` in `balls.wgsl`), the size of the colour attachment drawn into and made
//! again when that size changes.

use super::pipelines::DEPTH_FORMAT;

/// A depth texture and its view, of a colour target's size.
#[derive(Default)]
pub(crate) struct DepthTarget {
    held: Option<((u32, u32), wgpu::Texture, wgpu::TextureView)>,
}

impl DepthTarget {
    /// The view of a depth texture of `size`, made on `device` if the one held has another
    /// size (or none is held).
    pub(crate) fn view(&mut self, device: &wgpu::Device, size: (u32, u32)) -> &wgpu::TextureView {
        if self.held.as_ref().is_none_or(|(s, _, _)| *s != size) {
            let texture = device.create_texture(&wgpu::TextureDescriptor {
                label: Some("ball depth"),
                size: wgpu::Extent3d {
                    width: size.0,
                    height: size.1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: DEPTH_FORMAT,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                view_formats: &[],
            });
            let view = texture.create_view(&Default::default());
            self.held = Some((size, texture, view));
        }
        &self.held.as_ref().expect("made above").2
    }
}
