//! Baked tables as a KTX 2.0 texture for other programs (docs/design/table-files.md,
//! "KTX2"): what the shader reads, in one 2-D texture of `mu_size x r_size` texels, two
//! channels:
//!
//! - R = `1 - E(mu, r)` per texel, after the layout's storage quantisation
//!   ([`Tables::stored_loss`]);
//! - G = `1 - E_avg(r)` of the row, repeated along the row ([`Tables::stored_loss_avg`]).
//!
//! The format follows `--storage`: f32 is `R32G32_SFLOAT` (vkFormat 103), f16
//! `R16G16_SFLOAT` (83), unorm8 `R8G8_UNORM` (16). One level, one layer, one face, no
//! supercompression, a basic Data Format Descriptor for the format (Khronos Data Format
//! Specification 1.3, linear transfer, BT.709 primaries as the reference tools write), and
//! a key/value block with `KTXwriter` = `shadeballs <version>` and `LAYOUT_KEY`: the layout
//! as plain-text `key=value` lines (`layout_text`), so that a reader needs nothing else to
//! read the table correctly. Row `j` (roughness texel `j`) is stored `j`-th, row 0 first; the
//! file carries no `KTXorientation` key, the layout text says it in words.
//!
//! The reader ([`read_tables`], [`parse_tables`]) parses by hand with a bounds check on every
//! field (the `ktx2` crate's reader panics on some corrupt descriptors), accepts exactly
//! what the writer produces (any format above, any layout, any `KTXwriter` value: the
//! file must be byte for byte what the writer gives for the tables read from it), and
//! answers anything else with one line, [`Error::Invalid`] of "table file".

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use super::{
    BakeConfig, Centres, EAvgRead, Layout, LayoutKind, Method, MuAxis, PointSet, RAxis, Storage,
    Tables,
};
use crate::brdf::{Geometry, ROUGHNESS_MIN};
use crate::error::{Error, Result};

/// The 12 bytes every KTX 2.0 file starts with: `«KTX 20»\r\n\x1A\n`.
pub(crate) const IDENTIFIER: [u8; 12] = [
    0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
];

/// `VK_FORMAT_R8G8_UNORM`.
pub const VK_FORMAT_R8G8_UNORM: u32 = 16;
/// `VK_FORMAT_R16G16_SFLOAT`.
pub const VK_FORMAT_R16G16_SFLOAT: u32 = 83;
/// `VK_FORMAT_R32G32_SFLOAT`.
pub(crate) const VK_FORMAT_R32G32_SFLOAT: u32 = 103;

/// The key/value key holding the layout text.
pub(crate) const LAYOUT_KEY: &str = "shadeballs.layout";
/// The standard key naming the program that wrote the file.
pub(crate) const WRITER_KEY: &str = "KTXwriter";
/// What the two channels hold (the layout text's `channels`).
pub(crate) const CHANNELS: &str = "r=1-E g=1-E_avg";

/// Header (identifier and 17 fields), then the index of the one level.
const HEADER_LEN: usize = 80;
const LEVEL_INDEX_LEN: usize = 24;
/// Basic descriptor block: 24 bytes, then 16 a sample; two samples (R, G).
const DFD_BLOCK_LEN: usize = 24 + 2 * 16;

// Data Format Descriptor constants (Khronos Data Format Specification, basic block).
const KHR_DF_VERSION: u16 = 2;
const KHR_DF_MODEL_RGBSDA: u8 = 1;
const KHR_DF_PRIMARIES_BT709: u8 = 1;
const KHR_DF_TRANSFER_LINEAR: u8 = 1;
const KHR_DF_CHANNEL_RED: u8 = 0;
const KHR_DF_CHANNEL_GREEN: u8 = 1;
const KHR_DF_SAMPLE_DATATYPE_SIGNED: u8 = 0x40;
const KHR_DF_SAMPLE_DATATYPE_FLOAT: u8 = 0x80;

/// The vkFormat of a two-channel texture in `storage`.
pub(crate) fn vk_format(storage: Storage) -> u32 {
    match storage {
        Storage::F32 => VK_FORMAT_R32G32_SFLOAT,
        Storage::F16 => VK_FORMAT_R16G16_SFLOAT,
        Storage::Unorm8 => VK_FORMAT_R8G8_UNORM,
    }
}

fn storage_of(vk_format: u32) -> Option<Storage> {
    Storage::ALL
        .into_iter()
        .find(|&s| self::vk_format(s) == vk_format)
}

fn format_name(storage: Storage) -> &'static str {
    match storage {
        Storage::F32 => "R32G32_SFLOAT",
        Storage::F16 => "R16G16_SFLOAT",
        Storage::Unorm8 => "R8G8_UNORM",
    }
}

/// The basic Data Format Descriptor of the two-channel format of `storage`, with its
/// leading total size: `dfdTotalSize`, then one basic block (vendor Khronos, type basic,
/// version 2), colour model RGBSDA, BT.709 primaries, linear transfer, straight alpha,
/// a 1x1x1x1 texel block of `bytesPlane0` bytes, and one sample per channel (R at bit 0,
/// G after it; float formats signed and float with bounds -1.0 and 1.0 as 32-bit floats,
/// unorm8 bounds 0 and 255).
pub(crate) fn data_format_descriptor(storage: Storage) -> Vec<u8> {
    let bits = 8 * storage.bytes_per_texel();
    let mut d = Vec::with_capacity(4 + DFD_BLOCK_LEN);
    d.extend_from_slice(&((4 + DFD_BLOCK_LEN) as u32).to_le_bytes());
    // vendorId (17 bits) = 0 (Khronos), descriptorType (15 bits) = 0 (basic).
    d.extend_from_slice(&0u32.to_le_bytes());
    d.extend_from_slice(&KHR_DF_VERSION.to_le_bytes());
    d.extend_from_slice(&(DFD_BLOCK_LEN as u16).to_le_bytes());
    d.extend_from_slice(&[
        KHR_DF_MODEL_RGBSDA,
        KHR_DF_PRIMARIES_BT709,
        KHR_DF_TRANSFER_LINEAR,
        0, // flags: straight alpha
    ]);
    d.extend_from_slice(&[0; 4]); // texelBlockDimension0..3 (each size - 1)
    let mut planes = [0u8; 8];
    planes[0] = (2 * storage.bytes_per_texel()) as u8;
    d.extend_from_slice(&planes);
    let (qualifiers, lower, upper) = match storage {
        Storage::F32 | Storage::F16 => (
            KHR_DF_SAMPLE_DATATYPE_SIGNED | KHR_DF_SAMPLE_DATATYPE_FLOAT,
            (-1.0f32).to_bits(),
            1.0f32.to_bits(),
        ),
        Storage::Unorm8 => (0, 0, 255),
    };
    for (k, channel) in [KHR_DF_CHANNEL_RED, KHR_DF_CHANNEL_GREEN]
        .into_iter()
        .enumerate()
    {
        d.extend_from_slice(&((k * bits) as u16).to_le_bytes()); // bitOffset
        d.push((bits - 1) as u8); // bitLength - 1
        d.push(channel | qualifiers);
        d.extend_from_slice(&[0; 4]); // samplePosition0..3
        d.extend_from_slice(&lower.to_le_bytes());
        d.extend_from_slice(&upper.to_le_bytes());
    }
    d
}

/// The layout as the file states it: `key=value` lines, one a key. The first group is
/// what a reader needs ([`parse_tables`] checks it against the file); the second says
/// how to read the table in words.
pub(crate) fn layout_text(tables: &Tables) -> String {
    let c = &tables.config;
    let l = &c.layout;
    let (mu_scale, mu_bias) = l.scale_bias(l.mu_size);
    let (r_scale, r_bias) = l.scale_bias(l.r_size);
    let r_min = l.r_axis.r_min();
    let mut s = String::new();
    let mut line = |key: &str, value: &dyn std::fmt::Display| {
        let _ = writeln!(s, "{key}={value}");
    };
    line("kind", &l.kind);
    line("mu_size", &l.mu_size);
    line("r_size", &l.r_size);
    line("mu_axis", &l.mu_axis);
    line("mu_scale", &mu_scale);
    line("mu_bias", &mu_bias);
    line("r_scale", &r_scale);
    line("r_bias", &r_bias);
    line("r_min", &r_min);
    line("r_max", &1);
    line("centres", &l.centres);
    line("e_avg_read", &l.e_avg_read);
    line("geometry", &c.geometry);
    line("storage", &l.storage);
    line("channels", &CHANNELS);
    line("method", &c.method);
    line("points", &c.points);
    line("samples", &c.samples);
    let mu_coord = match l.mu_axis {
        MuAxis::Linear => "x = mu",
        MuAxis::Sqrt => "x = sqrt(mu)",
        MuAxis::Warped => "x = mu (1 + a) / (mu + a), a = roughness^2 (roughness clamped)",
    };
    line("mu_coord", &mu_coord);
    line(
        "r_coord",
        &format_args!("y = (clamp(roughness, {ROUGHNESS_MIN}, 1) - r_min) / (r_max - r_min)"),
    );
    line(
        "texel",
        &"p = clamp(x * scale + bias, 0, n - 1) on each axis; texel i holds the value at \
          p = i; read bilinearly between floor(p) and floor(p) + 1, clamp to edge, no mipmaps",
    );
    line(
        "uv",
        &"u = (p_x + 0.5) / mu_size, v = (p_y + 0.5) / r_size (the GPU's texel centres)",
    );
    line(
        "description",
        &"x (u) runs along mu, y (v) along roughness; row j is roughness texel j, stored \
          j-th, row 0 (r_min) first, at v = 0 in Vulkan, WebGPU, Metal and D3D texture \
          coordinates; r = 1 - E(mu, r) per texel, g = 1 - E_avg(r) of the row repeated \
          along it; E with F = 1",
    );
    if l.e_avg_read == EAvgRead::PowerLaw {
        line(
            "e_avg_note",
            &"power-law: between rows a, b read g as g_a (r / r_a)^k with k such that it \
              meets g_b at r_b (linear in ln g against ln r)",
        );
    }
    s
}

fn table_error(message: impl Into<String>) -> Error {
    Error::Invalid {
        what: "table",
        message: message.into(),
    }
}

/// The file's bytes for `tables`. Fails only on tables whose vectors do not match their
/// layout, or whose sizes a KTX2 header cannot hold.
pub fn encode_tables(tables: &Tables) -> Result<Vec<u8>> {
    let writer = format!("shadeballs {}", env!("CARGO_PKG_VERSION"));
    encode_with_writer(tables, &writer)
}

/// [`encode_tables`] with `writer` as the `KTXwriter` value (the reader re-encodes a file
/// with its own writer's value to check it byte for byte).
fn encode_with_writer(tables: &Tables, writer: &str) -> Result<Vec<u8>> {
    let l = tables.layout();
    let texels = l.texels();
    if tables.stored_loss.len() != texels || tables.stored_loss_avg.len() != l.r_size {
        return Err(table_error(format!(
            "{} stored texels and {} rows for a {}x{} layout",
            tables.stored_loss.len(),
            tables.stored_loss_avg.len(),
            l.mu_size,
            l.r_size
        )));
    }
    let (width, height) = match (u32::try_from(l.mu_size), u32::try_from(l.r_size)) {
        (Ok(w), Ok(h)) if w > 0 && h > 0 => (w, h),
        _ => {
            return Err(table_error(format!(
                "{}x{} texels do not fit a KTX2 header",
                l.mu_size, l.r_size
            )))
        }
    };
    let channel = l.storage.bytes_per_texel();
    let texel = 2 * channel;

    let dfd = data_format_descriptor(l.storage);
    let mut kvd = Vec::new();
    // Keys in byte order, as the spec asks ('K' < 's').
    for (key, value) in [
        (WRITER_KEY, writer),
        (LAYOUT_KEY, layout_text(tables).as_str()),
    ] {
        // keyAndValueByteLength, key, NUL, value, NUL (UTF-8 strings), then padding to 4.
        let len = key.len() + 1 + value.len() + 1;
        kvd.extend_from_slice(&(len as u32).to_le_bytes());
        kvd.extend_from_slice(key.as_bytes());
        kvd.push(0);
        kvd.extend_from_slice(value.as_bytes());
        kvd.push(0);
        kvd.resize(kvd.len().next_multiple_of(4), 0);
    }

    let dfd_offset = HEADER_LEN + LEVEL_INDEX_LEN;
    let kvd_offset = dfd_offset + dfd.len();
    // Level data aligned to lcm(texel block size, 4).
    let align = if texel.is_multiple_of(4) { texel } else { 4 };
    let data_offset = (kvd_offset + kvd.len()).next_multiple_of(align);
    let data_len = texels * texel;
    let total = data_offset + data_len;
    let too_big = || table_error(format!("{total} bytes do not fit a KTX2 file's index"));
    let u32_of = |v: usize| u32::try_from(v).map_err(|_| too_big());

    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(&IDENTIFIER);
    for field in [
        vk_format(l.storage),
        channel as u32, // typeSize
        width,
        height,
        0, // pixelDepth: 2-D
        0, // layerCount: not an array
        1, // faceCount
        1, // levelCount
        0, // supercompressionScheme: none
        u32_of(dfd_offset)?,
        u32_of(dfd.len())?,
        u32_of(kvd_offset)?,
        u32_of(kvd.len())?,
    ] {
        out.extend_from_slice(&field.to_le_bytes());
    }
    for field in [
        0u64, // sgdByteOffset
        0,    // sgdByteLength
        data_offset as u64,
        data_len as u64,
        data_len as u64, // uncompressedByteLength
    ] {
        out.extend_from_slice(&field.to_le_bytes());
    }
    debug_assert_eq!(out.len(), dfd_offset);
    out.extend_from_slice(&dfd);
    out.extend_from_slice(&kvd);
    out.resize(data_offset, 0);
    for j in 0..l.r_size {
        let avg = tables.stored_loss_avg[j];
        for &loss in &tables.stored_loss[j * l.mu_size..(j + 1) * l.mu_size] {
            for v in [loss, avg] {
                match l.storage {
                    Storage::F32 => out.extend_from_slice(&v.to_le_bytes()),
                    Storage::F16 => out.extend_from_slice(&half::f16::from_f32(v).to_le_bytes()),
                    Storage::Unorm8 => out.push((v.clamp(0.0, 1.0) as f64 * 255.0).round() as u8),
                }
            }
        }
    }
    debug_assert_eq!(out.len(), total);
    Ok(out)
}

/// Reads a table file written by [`encode_tables`] (`shadeballs bake --out FILE.ktx2`).
/// See [`parse_tables`].
pub fn read_tables(path: &Path) -> Result<Tables> {
    let bytes = std::fs::read(path).map_err(|e| Error::Invalid {
        what: "table file",
        message: format!("cannot read '{}': {e}", path.display()),
    })?;
    parse_tables(&bytes).map_err(|e| match e {
        Error::Invalid { what, message } => Error::Invalid {
            what,
            message: format!("'{}': {message}", path.display()),
        },
        other => other,
    })
}

fn invalid(message: impl Into<String>) -> Error {
    Error::Invalid {
        what: "table file",
        message: message.into(),
    }
}

/// Bounds-checked little-endian reads from the file.
struct Bytes<'a>(&'a [u8]);

impl<'a> Bytes<'a> {
    fn slice(&self, offset: u64, len: u64, what: &str) -> Result<&'a [u8]> {
        let end = offset.checked_add(len);
        match end {
            Some(end) if end <= self.0.len() as u64 => Ok(&self.0[offset as usize..end as usize]),
            _ => Err(invalid(format!(
                "truncated or corrupt: the {what} ({len} bytes at {offset}) runs past the end \
                 of the file ({} bytes)",
                self.0.len()
            ))),
        }
    }

    fn u32(&self, offset: usize) -> Result<u32> {
        let b = self.slice(offset as u64, 4, "header")?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    fn u64(&self, offset: usize) -> Result<u64> {
        let b = self.slice(offset as u64, 8, "header")?;
        let mut a = [0; 8];
        a.copy_from_slice(b);
        Ok(u64::from_le_bytes(a))
    }
}

/// Parses a table file's bytes back into [`Tables`]: the layout, geometry, method, point set
/// and sample count from the layout text, and the stored `1 - E` and `1 - E_avg` exactly
/// as in the file (bit for bit, as f32).
///
/// A file holds only what the shader reads, so `e` and `e_avg` are filled with
/// `1 - stored_loss` and `1 - stored_loss_avg` (in f64): the values as stored, not the
/// bake's unquantised ones. Every field is checked: the identifier, the format against
/// the layout text's storage, the sizes, the descriptor's structure, the key/value block,
/// the layout text (every key present once, `mu_scale` and the other derived values equal
/// to the layout's own), every texel finite and in `[0, 1]`, and the green channel constant
/// along each row. Anything else is one clear line, never a panic.
pub fn parse_tables(bytes: &[u8]) -> Result<Tables> {
    let b = Bytes(bytes);
    if bytes.len() < IDENTIFIER.len() || bytes[..IDENTIFIER.len()] != IDENTIFIER {
        return Err(invalid(
            "not a KTX2 file: it does not start with the KTX 2.0 identifier",
        ));
    }
    if bytes.len() < HEADER_LEN + LEVEL_INDEX_LEN {
        return Err(invalid(format!(
            "truncated: {} bytes, shorter than a KTX2 header and level index ({} bytes)",
            bytes.len(),
            HEADER_LEN + LEVEL_INDEX_LEN
        )));
    }
    let field = |i: usize| b.u32(12 + 4 * i);
    let format = field(0)?;
    let storage = storage_of(format).ok_or_else(|| {
        invalid(format!(
            "vkFormat {format} is not a table's: expected {VK_FORMAT_R32G32_SFLOAT} \
             (R32G32_SFLOAT), {VK_FORMAT_R16G16_SFLOAT} (R16G16_SFLOAT) or \
             {VK_FORMAT_R8G8_UNORM} (R8G8_UNORM)"
        ))
    })?;
    let channel = storage.bytes_per_texel();
    let texel = 2 * channel;
    let expect = |name: &str, got: u32, want: u32| -> Result<()> {
        if got == want {
            Ok(())
        } else {
            Err(invalid(format!(
                "{name} is {got}, a table's is {want} ({})",
                format_name(storage)
            )))
        }
    };
    expect("typeSize", field(1)?, channel as u32)?;
    let (width, height) = (field(2)?, field(3)?);
    if width == 0 || height == 0 {
        return Err(invalid(format!(
            "a table is a 2-D texture; this one is {width}x{height}"
        )));
    }
    expect("pixelDepth", field(4)?, 0)?;
    expect("layerCount", field(5)?, 0)?;
    expect("faceCount", field(6)?, 1)?;
    expect("levelCount", field(7)?, 1)?;
    expect("supercompressionScheme", field(8)?, 0)?;
    let (dfd_offset, dfd_len) = (field(9)?, field(10)?);
    let (kvd_offset, kvd_len) = (field(11)?, field(12)?);

    if (b.u64(64)?, b.u64(72)?) != (0, 0) {
        return Err(invalid(
            "supercompression global data in a file without supercompression",
        ));
    }
    // The one level: all of the table, uncompressed.
    let (data_offset, data_len, data_full) = (b.u64(80)?, b.u64(88)?, b.u64(96)?);
    let want_len = (width as u64 * height as u64)
        .checked_mul(texel as u64)
        .ok_or_else(|| invalid(format!("{width}x{height} texels: too many for any file")))?;
    if data_len != want_len || data_full != want_len {
        return Err(invalid(format!(
            "corrupt level index: {data_len} bytes ({data_full} uncompressed) for \
             {width}x{height} texels of {texel} bytes ({want_len})"
        )));
    }
    let data = b.slice(data_offset, data_len, "texel data")?;

    check_dfd(
        b.slice(dfd_offset as u64, dfd_len as u64, "data format descriptor")?,
        storage,
    )?;
    let kvd = b.slice(kvd_offset as u64, kvd_len as u64, "key/value data")?;
    let text = layout_value(kvd)?;
    let config = parse_layout(text, storage, width as usize, height as usize)?;
    let layout = config.layout;

    let (stored_loss, stored_loss_avg) = read_texels(data, storage, &layout)?;
    let tables = Tables {
        config,
        e: stored_loss.iter().map(|&v| 1.0 - v as f64).collect(),
        e_avg: stored_loss_avg.iter().map(|&v| 1.0 - v as f64).collect(),
        stored_loss,
        stored_loss_avg,
    };
    check_as_written(bytes, &tables, kvd)?;
    Ok(tables)
}

/// The texels of `data` in `storage`, row-major, as `layout`'s tables: R = 1 - E per texel,
/// G = 1 - E_avg of the row (the same along it); each in [0, 1].
fn read_texels(data: &[u8], storage: Storage, layout: &Layout) -> Result<(Vec<f32>, Vec<f32>)> {
    let channel = storage.bytes_per_texel();
    let value = |k: usize| -> f32 {
        let at = &data[k * channel..(k + 1) * channel];
        match storage {
            Storage::F32 => f32::from_le_bytes([at[0], at[1], at[2], at[3]]),
            Storage::F16 => half::f16::from_le_bytes([at[0], at[1]]).to_f32(),
            Storage::Unorm8 => (at[0] as f64 / 255.0) as f32,
        }
    };
    let mut stored_loss = Vec::with_capacity(layout.texels());
    let mut stored_loss_avg = Vec::with_capacity(layout.r_size);
    for j in 0..layout.r_size {
        let first = j * layout.mu_size;
        let avg = value(2 * first + 1);
        for i in 0..layout.mu_size {
            let (loss, g) = (value(2 * (first + i)), value(2 * (first + i) + 1));
            for (name, v) in [("r", loss), ("g", g)] {
                if !(0.0..=1.0).contains(&v) {
                    return Err(invalid(format!(
                        "texel ({i}, {j}) holds {name} = {v}, outside [0, 1]"
                    )));
                }
            }
            if g.to_bits() != avg.to_bits() {
                return Err(invalid(format!(
                    "row {j}: g (1 - E_avg) is {avg} at texel 0 but {g} at texel {i}; it must \
                     be the same along the row"
                )));
            }
            stored_loss.push(loss);
        }
        stored_loss_avg.push(avg);
    }
    Ok((stored_loss, stored_loss_avg))
}

/// The file must be the bytes the writer gives for the tables read from it, with the
/// file's own `KTXwriter` value (another version's): so nothing the writer never writes
/// is accepted (issue 28, 9: sample bounds, primaries, flags, offsets, padding, the layout
/// text's wording, trailing bytes). The first differing byte is named by its part.
fn check_as_written(bytes: &[u8], tables: &Tables, kvd: &[u8]) -> Result<()> {
    let writer = kv_value(kvd, WRITER_KEY).unwrap_or("");
    let want = encode_with_writer(tables, writer)?;
    let Some(at) = (0..bytes.len().min(want.len())).find(|&k| bytes[k] != want[k]) else {
        return match bytes.len().cmp(&want.len()) {
            std::cmp::Ordering::Equal => Ok(()),
            std::cmp::Ordering::Greater => Err(invalid(format!(
                "{} bytes after the texel data (the file ends at byte {})",
                bytes.len() - want.len(),
                want.len()
            ))),
            std::cmp::Ordering::Less => Err(invalid(format!(
                "{} bytes, {} fewer than a table of this layout",
                bytes.len(),
                want.len() - bytes.len()
            ))),
        };
    };
    let dfd = HEADER_LEN + LEVEL_INDEX_LEN;
    let kvd_start = dfd + 4 + DFD_BLOCK_LEN;
    let data =
        want.len() - tables.layout().texels() * 2 * tables.layout().storage.bytes_per_texel();
    let part = match at {
        _ if at < HEADER_LEN => "the header",
        _ if at < dfd => "the level index",
        _ if at < dfd + 4 + 24 => {
            "the data format descriptor's block header (model, primaries, transfer, flags, planes)"
        }
        _ if at < kvd_start => {
            "the data format descriptor's samples (positions, sampleLower, sampleUpper)"
        }
        _ if at < kvd_start + kvd.len() => "the key/value data (its entries, order or padding)",
        _ if at < data => "the padding before the texel data",
        _ => "the texel data (a value the writer would store otherwise)",
    };
    Err(invalid(format!(
        "byte {at} ({part}) is {:#04x}, the writer writes {:#04x} there: not a table file as \
         shadeballs writes it",
        bytes[at], want[at]
    )))
}

/// The value of `key` in key/value data already checked by [`layout_value`] (its trailing
/// NUL dropped), if there is one and it is UTF-8.
fn kv_value<'a>(kvd: &'a [u8], key: &str) -> Option<&'a str> {
    let mut rest = kvd;
    while rest.len() >= 4 {
        let len = u32::from_le_bytes([rest[0], rest[1], rest[2], rest[3]]) as usize;
        let entry = rest.get(4..)?.get(..len)?;
        let nul = entry.iter().position(|&c| c == 0)?;
        if &entry[..nul] == key.as_bytes() {
            let value = &entry[nul + 1..];
            return std::str::from_utf8(value.strip_suffix(&[0]).unwrap_or(value)).ok();
        }
        rest = &rest[(4 + len).next_multiple_of(4).min(rest.len())..];
    }
    None
}

/// Checks the descriptor's structure: the fields that say how to read the texels.
fn check_dfd(dfd: &[u8], storage: Storage) -> Result<()> {
    let bad = |why: String| invalid(format!("data format descriptor: {why}"));
    let word = |at: usize| -> Option<u32> {
        dfd.get(at..at + 4)
            .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]))
    };
    let total = word(0).ok_or_else(|| bad("shorter than 4 bytes".into()))?;
    if total as usize != dfd.len() {
        return Err(bad(format!(
            "dfdTotalSize {total} differs from its index's length {}",
            dfd.len()
        )));
    }
    let block = &dfd[4..];
    if block.len() < 24 {
        return Err(bad(format!(
            "{} bytes, shorter than a basic block",
            block.len()
        )));
    }
    let first = u32::from_le_bytes([block[0], block[1], block[2], block[3]]);
    let version = u16::from_le_bytes([block[4], block[5]]);
    let size = u16::from_le_bytes([block[6], block[7]]) as usize;
    if first != 0 {
        return Err(bad(format!(
            "the first block is not Khronos' basic block (vendor {}, type {})",
            first & 0x1_FFFF,
            first >> 17
        )));
    }
    if version != KHR_DF_VERSION {
        return Err(bad(format!(
            "basic block version {version}, expected {KHR_DF_VERSION}"
        )));
    }
    if size != DFD_BLOCK_LEN || size > block.len() {
        return Err(bad(format!(
            "a basic block of {size} bytes in {} ({DFD_BLOCK_LEN} for two samples)",
            block.len()
        )));
    }
    let (model, transfer) = (block[8], block[10]);
    if model != KHR_DF_MODEL_RGBSDA {
        return Err(bad(format!("colour model {model}, expected RGBSDA (1)")));
    }
    if transfer != KHR_DF_TRANSFER_LINEAR {
        return Err(bad(format!(
            "transfer function {transfer}, expected linear (1)"
        )));
    }
    if block[12..16] != [0; 4] {
        return Err(bad("texel blocks larger than one texel".into()));
    }
    let texel = 2 * storage.bytes_per_texel();
    if block[16] as usize != texel || block[17..24] != [0; 7] {
        return Err(bad(format!(
            "bytesPlane {:?}, expected one plane of {texel} bytes",
            &block[16..24]
        )));
    }
    let reference = data_format_descriptor(storage);
    let bits = 8 * storage.bytes_per_texel();
    for (k, name) in ["R", "G"].into_iter().enumerate() {
        let at = 24 + 16 * k;
        // bitOffset, bitLength and channelType with its qualifiers: how to decode the sample.
        if block[at..at + 4] != reference[4 + at..4 + at + 4] {
            return Err(bad(format!(
                "sample {k} is not {name} as {bits}-bit {} at bit {}",
                if storage == Storage::Unorm8 {
                    "unorm"
                } else {
                    "float"
                },
                k * bits
            )));
        }
    }
    Ok(())
}

/// The layout text from the key/value data: every entry bounds-checked, [`LAYOUT_KEY`] found
/// once, its value UTF-8 (one trailing NUL allowed).
fn layout_value(kvd: &[u8]) -> Result<&str> {
    let mut rest = kvd;
    let mut found = None;
    while !rest.is_empty() {
        if rest.len() < 4 {
            return Err(invalid("key/value data: a truncated entry length"));
        }
        let len = u32::from_le_bytes([rest[0], rest[1], rest[2], rest[3]]) as usize;
        let entry = rest
            .get(4..)
            .and_then(|r| r.get(..len))
            .ok_or_else(|| invalid("key/value data: an entry runs past the block"))?;
        let nul = entry
            .iter()
            .position(|&c| c == 0)
            .ok_or_else(|| invalid("key/value data: a key without its NUL terminator"))?;
        let (key, value) = (&entry[..nul], &entry[nul + 1..]);
        if key == LAYOUT_KEY.as_bytes() {
            if found.is_some() {
                return Err(invalid(format!("key/value data: '{LAYOUT_KEY}' twice")));
            }
            let value = value.strip_suffix(&[0]).unwrap_or(value);
            found = Some(std::str::from_utf8(value).map_err(|_| {
                invalid(format!("key/value data: '{LAYOUT_KEY}' is not UTF-8 text"))
            })?);
        }
        // The entry, then padding to a multiple of 4 (the last may stop at the block's end).
        let next = (4 + len).next_multiple_of(4).min(rest.len());
        rest = &rest[next..];
    }
    found.ok_or_else(|| {
        invalid(format!(
            "no '{LAYOUT_KEY}' key: not a table written by shadeballs"
        ))
    })
}

/// The layout text back into a [`BakeConfig`], checked against the file's format and size.
fn parse_layout(text: &str, storage: Storage, width: usize, height: usize) -> Result<BakeConfig> {
    let bad = |why: String| invalid(format!("layout: {why}"));
    let mut map = BTreeMap::new();
    for line in text.lines().map(str::trim).filter(|l| !l.is_empty()) {
        let (key, value) = line
            .split_once('=')
            .ok_or_else(|| bad(format!("line '{line}' is not key=value")))?;
        if map.insert(key.trim(), value.trim()).is_some() {
            return Err(bad(format!("'{}' given twice", key.trim())));
        }
    }
    let get = |key: &str| {
        map.get(key)
            .copied()
            .ok_or_else(|| bad(format!("no '{key}'")))
    };
    let parse_err = |key: &str, e: Error| bad(format!("'{key}': {e}"));
    let size = |key: &str| -> Result<usize> {
        get(key)?
            .parse::<usize>()
            .map_err(|_| bad(format!("'{key}' is not a whole number")))
    };
    let number = |key: &str| -> Result<f64> {
        get(key)?
            .parse::<f64>()
            .map_err(|_| bad(format!("'{key}' is not a number")))
    };
    macro_rules! enum_of {
        ($key:literal) => {
            get($key)?.parse().map_err(|e| parse_err($key, e))?
        };
    }
    let kind: LayoutKind = enum_of!("kind");
    let mu_axis: MuAxis = enum_of!("mu_axis");
    let centres: Centres = enum_of!("centres");
    let e_avg_read: EAvgRead = enum_of!("e_avg_read");
    let geometry: Geometry = enum_of!("geometry");
    let stated: Storage = enum_of!("storage");
    let method: Method = enum_of!("method");
    let points: PointSet = enum_of!("points");
    let samples = size("samples")?;
    let (mu_size, r_size) = (size("mu_size")?, size("r_size")?);
    if (mu_size, r_size) != (width, height) {
        return Err(bad(format!(
            "{mu_size}x{r_size} texels, but the texture is {width}x{height}"
        )));
    }
    if stated != storage {
        return Err(bad(format!(
            "storage {stated}, but the texture is {}",
            format_name(storage)
        )));
    }
    if get("channels")? != CHANNELS {
        return Err(bad(format!(
            "channels '{}', expected '{CHANNELS}'",
            get("channels")?
        )));
    }
    let r_min = number("r_min")?;
    let r_axis = [RAxis::Full, RAxis::Clamped]
        .into_iter()
        .find(|a| a.r_min() == r_min)
        .ok_or_else(|| bad(format!("r_min {r_min}, expected 0 or {ROUGHNESS_MIN}")))?;
    if number("r_max")? != 1.0 {
        return Err(bad(format!("r_max {}, expected 1", get("r_max")?)));
    }
    let layout = Layout {
        kind,
        mu_axis,
        r_axis,
        e_avg_read,
        centres,
        mu_size,
        r_size,
        storage,
    };
    // The texel-centre scale and bias are derived: they must be the layout's own.
    for (axis, n) in [("mu", mu_size), ("r", r_size)] {
        let (scale, bias) = layout.scale_bias(n);
        let (s, b) = (
            number(&format!("{axis}_scale"))?,
            number(&format!("{axis}_bias"))?,
        );
        if (s, b) != (scale, bias) {
            return Err(bad(format!(
                "{axis}_scale {s} and {axis}_bias {b} disagree with {centres} centres on \
                 {n} texels (scale {scale}, bias {bias})"
            )));
        }
    }
    if samples == 0 {
        return Err(bad("'samples' is 0".into()));
    }
    Ok(BakeConfig {
        geometry,
        method,
        points,
        samples,
        layout,
    })
}

// Tests that need the crate's internals (moved from the suite); with the command line's
// features only, so `cargo test --no-default-features --lib` runs them once.
#[cfg(all(test, feature = "cli"))]
mod tests;
