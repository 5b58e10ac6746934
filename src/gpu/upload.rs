//! The tables on a GPU: [`GpuTables::upload`] puts baked tables onto any `wgpu::Device`
//! (the renderer's own or a host program's) as the two textures the WGSL table reads take
//! (`lut.wgsl`), with their read parameters. Read with `textureLoad` (no filtering feature
//! needed, the same on Vulkan and GL): `1 - E` as 2x2 blocks in `Rgba32Float`
//! ([`loss_quads`]), `1 - E_avg` and each row's roughness as `R32Float`.

use crate::lut::{LutParams, RowSet, Tables};

/// Baked tables uploaded to a device: what `lut_loss`, `lut_e`, `lut_loss_avg` and
/// `lut_e_avg` of [`crate::wgsl::KULLA_CONTY`] take as arguments.
///
/// ```
/// # let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
/// # let adapter = pollster::block_on(instance.request_adapter(&Default::default()))
/// #     .expect("a GPU adapter (lavapipe: apt-get install mesa-vulkan-drivers)");
/// # let (device, queue) = pollster::block_on(adapter.request_device(&Default::default())).unwrap();
/// // A host program's device and queue (opened above, hidden): bake at startup, upload.
/// let tables = shadeballs::bake(&shadeballs::BakeConfig::default());
/// let gpu_tables = shadeballs::GpuTables::upload(&device, &queue, &tables);
/// assert_eq!(gpu_tables.e.texture().width(), tables.layout().mu_size as u32);
/// // Bind `gpu_tables.e` and `gpu_tables.e_avg` as `texture_2d<f32>` (not filterable:
/// // `GpuTables::layout_entry`), and `gpu_tables.params` in a uniform buffer.
/// let params: &[u8] = bytemuck::bytes_of(&gpu_tables.params);
/// assert_eq!(params.len(), 48);
/// ```
#[derive(Clone, Debug)]
pub struct GpuTables {
    /// `1 - E(mu, roughness)`, `mu_size x r_size` texels of `Rgba32Float`, each holding
    /// the 2x2 block it starts ([`loss_quads`]): the WGSL's `e_table`.
    pub e: wgpu::TextureView,
    /// `R32Float`, `r_size x 2`: row 0 `1 - E_avg` per roughness row, row 1 each row's
    /// roughness: the WGSL's `e_avg_table`.
    pub e_avg: wgpu::TextureView,
    /// How to read them: the WGSL's `LutParams`.
    pub params: LutParams,
}

impl GpuTables {
    /// Uploads `tables` (the 2-D table) onto `device` through `queue`: two textures, no
    /// device of this crate's own, no error handler installed.
    pub fn upload(device: &wgpu::Device, queue: &wgpu::Queue, tables: &Tables) -> GpuTables {
        let l = tables.layout();
        // Row 1: each row's roughness as the power-law read uses it (`Layout::row_roughness`,
        // computed from the f64 texel coordinate here so the shader does not re-derive it).
        let mut e_avg_rows = tables.stored_loss_avg.clone();
        e_avg_rows.extend((0..l.r_size).map(|j| l.row_roughness(j)));
        Self::from_parts(
            device,
            queue,
            &tables.stored_loss,
            &e_avg_rows,
            l.lut_params(),
        )
    }

    /// Uploads a scene's rows as a `mu_size x rows` table (a ball reads its row with a zero
    /// weight on the next: `lut_loss_row`), with each row's `1 - E_avg` and roughness.
    pub(crate) fn upload_rows(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        rows: &RowSet,
    ) -> GpuTables {
        let mut e_avg_rows: Vec<f32> = rows.rows.iter().map(|r| r.loss_avg).collect();
        e_avg_rows.extend(rows.rows.iter().map(|r| r.key.roughness()));
        Self::from_parts(
            device,
            queue,
            &rows.stored_loss(),
            &e_avg_rows,
            rows.lut_params(),
        )
    }

    /// 1 x 1 placeholders for a scene that reads no table (its pipelines never read them).
    pub(crate) fn placeholder(device: &wgpu::Device, queue: &wgpu::Queue) -> GpuTables {
        let params = LutParams {
            mu_size: 1,
            r_size: 1,
            ..LutParams::default()
        };
        Self::from_parts(device, queue, &[0.0], &[0.0, 0.0], params)
    }

    fn from_parts(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        loss: &[f32],
        e_avg_rows: &[f32],
        params: LutParams,
    ) -> GpuTables {
        let (mu_size, r_size) = (params.mu_size as usize, params.r_size as usize);
        let quads = loss_quads(loss, mu_size, r_size);
        let e = f32_texture(
            device,
            queue,
            "1 - E, 2x2 blocks",
            wgpu::TextureFormat::Rgba32Float,
            (mu_size as u32, r_size as u32),
            &quads,
        );
        let e_avg = f32_texture(
            device,
            queue,
            "1 - E_avg",
            wgpu::TextureFormat::R32Float,
            (r_size as u32, 2),
            e_avg_rows,
        );
        GpuTables { e, e_avg, params }
    }

    /// The bind group layout entry of either texture at `binding`: a non-filterable float
    /// 2-D texture (the reads use `textureLoad`).
    pub fn layout_entry(
        binding: u32,
        visibility: wgpu::ShaderStages,
    ) -> wgpu::BindGroupLayoutEntry {
        wgpu::BindGroupLayoutEntry {
            binding,
            visibility,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        }
    }
}

/// A `width x height` table as 2x2 blocks: block (i, j) holds texels (i, j), (i + 1, j),
/// (i, j + 1), (i + 1, j + 1) (clamped at the last column and row), RGBA, so that a
/// bilinear read is one `textureLoad` (`loss_quad` in `lut.wgsl`). Four times the memory of
/// the table: 64 KiB at the default 64 x 64.
pub fn loss_quads(data: &[f32], width: usize, height: usize) -> Vec<f32> {
    let t = |i: usize, j: usize| data[j.min(height - 1) * width + i.min(width - 1)];
    (0..height)
        .flat_map(|j| {
            (0..width).flat_map(move |i| [t(i, j), t(i + 1, j), t(i, j + 1), t(i + 1, j + 1)])
        })
        .collect()
}

/// A sampled `width x height` texture of an f32 `format` (R32Float, Rgba32Float) holding
/// `data`, rows packed.
fn f32_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    format: wgpu::TextureFormat,
    (width, height): (u32, u32),
    data: &[f32],
) -> wgpu::TextureView {
    let size = wgpu::Extent3d {
        width,
        height,
        depth_or_array_layers: 1,
    };
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let bytes_per_texel = format.block_copy_size(None).unwrap_or(4);
    queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture: &texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        bytemuck::cast_slice(data),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(width * bytes_per_texel),
            rows_per_image: Some(height),
        },
        size,
    );
    texture.create_view(&wgpu::TextureViewDescriptor::default())
}
