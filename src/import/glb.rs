//! The binary glTF container (glTF 2.0 specification, section 4.4 "GLB File Format
//! Specification"): a 12-byte header (magic `glTF`, version 2, total length), then chunks
//! of `length, type, data`, the first the JSON, the optional second the binary buffer
//! (`BIN`). Every length is checked against the file; a broken chunk is an error naming it.

/// `glTF` in ASCII, little-endian.
const MAGIC: u32 = 0x4654_6C67;
/// The chunk type of the JSON chunk (`JSON`).
const CHUNK_JSON: u32 = 0x4E4F_534A;
/// The chunk type of the binary buffer (`BIN\0`).
const CHUNK_BIN: u32 = 0x004E_4942;
/// Bytes of the header and of a chunk's header.
const HEADER: usize = 12;
const CHUNK_HEADER: usize = 8;

/// The parts of a `.glb`: its JSON chunk and its binary chunk, if any.
pub(crate) struct Glb<'a> {
    /// The JSON chunk's bytes (trailing space padding included: JSON ignores it).
    pub json: &'a [u8],
    /// The `BIN` chunk's bytes (buffer 0 of a buffer without `uri`).
    pub bin: Option<&'a [u8]>,
}

fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at + 4)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Whether `bytes` start as a `.glb` does (its magic): a `.gltf` named `.glb` or the
/// reverse is read by what it holds.
pub(crate) fn is_glb(bytes: &[u8]) -> bool {
    u32_at(bytes, 0) == Some(MAGIC)
}

/// Splits a `.glb` into its chunks, or says what is broken.
pub(crate) fn split(bytes: &[u8]) -> Result<Glb<'_>, String> {
    let header = |what: &str| format!("not a .glb: {what}");
    if bytes.len() < HEADER {
        return Err(header(&format!(
            "{} bytes, shorter than its 12-byte header",
            bytes.len()
        )));
    }
    if u32_at(bytes, 0) != Some(MAGIC) {
        return Err(header("its first 4 bytes are not 'glTF'"));
    }
    let version = u32_at(bytes, 4).unwrap_or(0);
    if version != 2 {
        return Err(format!(".glb version {version}: only glTF 2.0 is read"));
    }
    let length = u32_at(bytes, 8).unwrap_or(0) as usize;
    if length != bytes.len() {
        return Err(format!(
            ".glb header says {length} bytes, the file has {}",
            bytes.len()
        ));
    }
    let mut chunks = Vec::new();
    let mut at = HEADER;
    while at < bytes.len() {
        let index = chunks.len();
        let (Some(len), Some(kind)) = (u32_at(bytes, at), u32_at(bytes, at + 4)) else {
            return Err(format!(
                ".glb chunk {index} at byte {at}: its 8-byte header runs past the end of the file"
            ));
        };
        let start = at + CHUNK_HEADER;
        let len = len as usize;
        let Some(end) = start.checked_add(len).filter(|&e| e <= bytes.len()) else {
            return Err(format!(
                ".glb chunk {index} at byte {at}: {len} bytes of data run past the end of the \
                 file ({} bytes)",
                bytes.len()
            ));
        };
        if !len.is_multiple_of(4) {
            return Err(format!(
                ".glb chunk {index} at byte {at}: its length {len} is not a multiple of 4"
            ));
        }
        chunks.push((kind, &bytes[start..end]));
        at = end;
    }
    let Some(&(kind, json)) = chunks.first() else {
        return Err(".glb has no chunk: its JSON chunk is missing".to_string());
    };
    if kind != CHUNK_JSON {
        return Err(format!(
            ".glb chunk 0 is of type 0x{kind:08x}, not JSON (0x{CHUNK_JSON:08x})"
        ));
    }
    let bin = match chunks.get(1) {
        Some(&(CHUNK_BIN, data)) => Some(data),
        Some(&(kind, _)) => {
            return Err(format!(
                ".glb chunk 1 is of type 0x{kind:08x}, not BIN (0x{CHUNK_BIN:08x})"
            ))
        }
        None => None,
    };
    Ok(Glb { json, bin })
}

/// A `.glb` of `json` (padded with spaces) and `bin` (padded with zeros), for the tests.
#[cfg(test)]
pub(crate) fn assemble(json: &[u8], bin: Option<&[u8]>) -> Vec<u8> {
    let pad = |n: usize| (4 - n % 4) % 4;
    let mut out = Vec::new();
    let json_len = json.len() + pad(json.len());
    let bin_len = bin.map_or(0, |b| b.len() + pad(b.len()));
    let total = HEADER + CHUNK_HEADER + json_len + bin.map_or(0, |_| CHUNK_HEADER + bin_len);
    out.extend_from_slice(&MAGIC.to_le_bytes());
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_len as u32).to_le_bytes());
    out.extend_from_slice(&CHUNK_JSON.to_le_bytes());
    out.extend_from_slice(json);
    out.extend(std::iter::repeat_n(b' ', pad(json.len())));
    if let Some(b) = bin {
        out.extend_from_slice(&(bin_len as u32).to_le_bytes());
        out.extend_from_slice(&CHUNK_BIN.to_le_bytes());
        out.extend_from_slice(b);
        out.extend(std::iter::repeat_n(0u8, pad(b.len())));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_glb_splits_into_its_chunks() {
        let glb = assemble(br#"{"asset":{"version":"2.0"}}"#, Some(&[1, 2, 3]));
        let parts = split(&glb).unwrap();
        assert!(parts.json.starts_with(br#"{"asset""#));
        assert_eq!(parts.bin.unwrap(), &[1, 2, 3, 0]);
        assert!(split(&assemble(b"{}", None)).unwrap().bin.is_none());
    }

    #[test]
    fn a_broken_glb_says_what_is_broken() {
        let good = assemble(b"{}", Some(&[0; 8]));
        let mut long_chunk = good.clone();
        long_chunk[24..28].copy_from_slice(&1000u32.to_le_bytes());
        let mut wrong_length = good.clone();
        wrong_length[8] += 4;
        let mut bad_magic = good.clone();
        bad_magic[0] = b'x';
        let cases: [(&[u8], &str); 5] = [
            (&good[..good.len() - 4], "header says"),
            (&long_chunk, "chunk 1"),
            (&wrong_length, "header says"),
            (&bad_magic, "not 'glTF'"),
            (&good[..6], "shorter than"),
        ];
        for (bytes, expected) in cases {
            let e = split(bytes).err().expect("an error");
            assert!(e.contains(expected), "{e}");
            assert!(!e.contains('\n'));
        }
    }
}
