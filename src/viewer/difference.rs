//! The difference view (`shaders/difference.wgsl`): two scene images' displayed values
//! differenced per pixel (the largest channel's `|a - b|`), scaled, in a colour ramp; the
//! ramp's CPU mirror (`difference_colour`, the colour bar's colours) and the colour bar
//! with its legend, as egui shapes drawn into the scene image with the labels.

use egui::epaint::ClippedShape;

use crate::labels::Rect;

/// The ramp's stops, display values (sRGB-coded), evenly spaced over `[0, 1]`: black (no
/// difference) through purple, red and orange to pale yellow.
const STOPS: [[f32; 3]; 5] = [
    [0.0, 0.0, 0.0],
    [0.30, 0.05, 0.55],
    [0.80, 0.15, 0.35],
    [1.0, 0.55, 0.05],
    [1.0, 1.0, 0.75],
];

/// The ramp's colour at `t` (clamped to `[0, 1]`): the CPU mirror of `difference_colour` in
/// `shaders/difference.wgsl`, in f32 as there.
pub(crate) fn difference_colour(t: f32) -> [f32; 3] {
    let x = t.clamp(0.0, 1.0) * 4.0;
    let i = (x as usize).min(3);
    let f = x - i as f32;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    [0, 1, 2].map(|c| a[c] + (b[c] - a[c]) * f)
}

/// The difference view's pixel of two displayed RGBA8 pixels at `scale` (what the shader
/// computes from the bytes, rounded to bytes as a unorm target stores them).
pub fn difference_pixel(a: [u8; 4], b: [u8; 4], scale: u32) -> [u8; 4] {
    let d = (0..3)
        .map(|c| (a[c] as f32 / 255.0 - b[c] as f32 / 255.0).abs())
        .fold(0.0f32, f32::max);
    let colour = difference_colour(d * scale as f32);
    let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    [byte(colour[0]), byte(colour[1]), byte(colour[2]), 255]
}

/// Pixels the bar's legend takes around the bar: its numbers at the left, its title above,
/// a margin right and below ([`colour_bar`]).
const LEGEND_LEFT_PX: u32 = 80;
const LEGEND_TOP_PX: u32 = 40;
const LEGEND_MARGIN_PX: u32 = 8;
/// The shortest bar drawn off the balls; where no strip has room for it, the bar goes at
/// its first place, over whatever is there.
const MIN_BAR_PX: u32 = 48;
/// The tallest bar.
const MAX_BAR_PX: u32 = 256;

/// The colour bar's place in a scene area `width x height` pixels: `(x0, y0, x1, y1)`, its
/// left, top, right and bottom edges in whole pixels. 16 px wide, near the area's right
/// edge (24 px in), else near its left edge (its numbers' width in), over the tallest span
/// of rows where the bar and its legend meet none of `obstacles` (the balls' bounds and the
/// labels' rooms), up to 256 px; with no such span 48 px tall, the first place (40 px below
/// the top at the right).
pub fn colour_bar_rect(width: u32, height: u32, obstacles: &[Rect]) -> (u32, u32, u32, u32) {
    let right = width.saturating_sub(24);
    let left = (LEGEND_LEFT_PX + 8 + 16).min(right);
    let mut best: Option<(u32, u32, u32, u32)> = None;
    for x1 in [right, left] {
        let x0 = x1.saturating_sub(16);
        let (lx0, lx1) = (
            x0.saturating_sub(LEGEND_LEFT_PX) as f32,
            (x1 + LEGEND_MARGIN_PX) as f32,
        );
        // The rows the obstacles in this strip cover, sorted.
        let mut taken: Vec<(f32, f32)> = obstacles
            .iter()
            .filter(|o| o.x0 < lx1 && o.x1 > lx0 && o.y1 > o.y0)
            .map(|o| (o.y0.max(0.0), o.y1))
            .collect();
        taken.sort_by(|a, b| a.0.total_cmp(&b.0));
        let bottom = height.saturating_sub(24) as f32;
        let mut free_from = 0.0f32;
        let mut gaps = Vec::new();
        for (t0, t1) in taken.into_iter().chain([(bottom, f32::MAX)]) {
            if t0 > free_from {
                gaps.push((free_from, t0.min(bottom)));
            }
            free_from = free_from.max(t1);
        }
        for (g0, g1) in gaps {
            let y0 = (g0.ceil() as u32 + LEGEND_TOP_PX).max(LEGEND_TOP_PX.min(height / 4));
            let end = (g1.floor() as u32).saturating_sub(LEGEND_MARGIN_PX);
            let y1 = end.min(y0 + MAX_BAR_PX);
            if y1 >= y0 + MIN_BAR_PX && best.is_none_or(|b| y1 - y0 > b.3 - b.1) {
                best = Some((x0, y0, x1, y1));
            }
        }
        if best.is_some_and(|b| b.3 - b.1 >= MAX_BAR_PX) {
            break;
        }
    }
    best.unwrap_or_else(|| {
        let x0 = right.saturating_sub(16);
        let y0 = LEGEND_TOP_PX.min(height / 4);
        let y1 = (y0 + MAX_BAR_PX).min(height.saturating_sub(24)).max(y0 + 1);
        (x0, y0, right, y1)
    })
}

/// The colour of the bar's pixel row `row` of `rows` (top first): the ramp at the row's
/// centre, 1 at the top.
pub fn colour_bar_row(row: u32, rows: u32) -> [u8; 3] {
    let t = 1.0 - (row as f32 + 0.5) / rows.max(1) as f32;
    difference_colour(t).map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
}

/// The colour bar and its legend (the title `|a - b| x scale`, `1/scale` at the top, `0`
/// at the bottom) as egui shapes over a scene area `width x height` pixels at `ppp`
/// pixels a point, off `obstacles` where there is room ([`colour_bar_rect`]): one
/// rectangle a pixel row, so that its colours are the ramp's exactly.
pub(crate) fn colour_bar(
    painter: &egui::Painter,
    (width, height): (u32, u32),
    ppp: f32,
    scale: u32,
    obstacles: &[Rect],
) -> Vec<ClippedShape> {
    let (x0, y0, x1, y1) = colour_bar_rect(width, height, obstacles);
    let clip = egui::Rect::from_min_size(
        egui::Pos2::ZERO,
        egui::vec2(width as f32 / ppp, height as f32 / ppp),
    );
    let px = |x: u32, y: u32| egui::pos2(x as f32 / ppp, y as f32 / ppp);
    let mut shapes = Vec::new();
    let mut push = |shape: egui::Shape| {
        shapes.push(ClippedShape {
            clip_rect: clip,
            shape,
            transform_after_tessellation: egui::emath::TSTransform::IDENTITY,
        })
    };
    let rows = y1 - y0;
    for row in 0..rows {
        let [r, g, b] = colour_bar_row(row, rows);
        let rect = egui::Rect::from_min_max(px(x0, y0 + row), px(x1, y0 + row + 1));
        push(egui::Shape::rect_filled(
            rect,
            0.0,
            egui::Color32::from_rgb(r, g, b),
        ));
    }
    let font = egui::FontId::proportional(13.0 / ppp);
    let light = egui::Color32::from_gray(235);
    let text = |pos: egui::Pos2, align: egui::Align2, s: String| {
        let galley = painter.layout_no_wrap(s, font.clone(), light);
        let rect = align.anchor_size(pos, galley.size());
        egui::Shape::galley(rect.min.round(), galley, light)
    };
    let left = |y: u32| egui::pos2((x0 as f32 - 6.0) / ppp, y as f32 / ppp);
    push(text(
        px(x1, y0.saturating_sub(8)),
        egui::Align2::RIGHT_BOTTOM,
        format!("|a - b| x {scale}"),
    ));
    push(text(
        left(y0),
        egui::Align2::RIGHT_TOP,
        format!("1/{scale}"),
    ));
    push(text(left(y1), egui::Align2::RIGHT_BOTTOM, "0".into()));
    shapes
}

/// The difference pass: a full-screen triangle over the scene area whose fragments difference
/// the two scene images' texels.
pub(crate) struct Difference {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    params: wgpu::Buffer,
}

impl Difference {
    /// The pass writing into `format` images (their non-sRGB view: the bytes themselves).
    pub(crate) fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("difference"),
            source: wgpu::ShaderSource::Wgsl(crate::gpu::shaders::difference_source().into()),
        });
        let texture = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("difference"),
            entries: &[
                texture(0),
                texture(1),
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("difference"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("difference"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("difference_vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("difference_fs"),
                compilation_options: Default::default(),
                targets: &[Some(format.remove_srgb_suffix().into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("difference params"),
            size: 16,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Difference {
            layout,
            pipeline,
            params,
        }
    }

    /// Records the difference of `a` and `b` at `scale` into the top-left `width x height`
    /// of `to` (the rest of `to` is left as it is).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn encode(
        &self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        encoder: &mut wgpu::CommandEncoder,
        (a, b): (&wgpu::Texture, &wgpu::Texture),
        to: &wgpu::Texture,
        (width, height): (u32, u32),
        scale: u32,
    ) {
        let params = [scale as f32, 0.0, 0.0, 0.0];
        queue.write_buffer(&self.params, 0, bytemuck::cast_slice(&params));
        let bytes = |t: &wgpu::Texture| {
            t.create_view(&wgpu::TextureViewDescriptor {
                format: Some(t.format().remove_srgb_suffix()),
                ..Default::default()
            })
        };
        let (view_a, view_b, target) = (bytes(a), bytes(b), bytes(to));
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("difference"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&view_a),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&view_b),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: self.params.as_entire_binding(),
                },
            ],
        });
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("difference"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            ..Default::default()
        });
        pass.set_scissor_rect(0, 0, width, height);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.draw(0..3, 0..1);
    }
}
