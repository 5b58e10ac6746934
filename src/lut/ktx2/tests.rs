//! Tables as KTX 2.0 textures (`shadeballs bake --out FILE.ktx2`): the file round-trips
//! bit for bit, a third-party reader (the `ktx2` crate) accepts it and agrees on the
//! descriptor, bad files fail in one line, and the uniform layout's plain bilinear read
//! stays within 1e-3 of the reference at its default size (run with `-- --nocapture` for
//! the figures; `-- --ignored uniform_layout_size_sweep` measures the size curve).

use std::sync::OnceLock;

use crate::brdf::Geometry;

use crate::lut::accuracy::{random_points, ErrorStats, ReferencePoints};

use crate::lut::io::write_tables;

use crate::lut::ktx2::{
    data_format_descriptor, encode_tables, parse_tables, read_tables, IDENTIFIER, LAYOUT_KEY,
    VK_FORMAT_R16G16_SFLOAT, VK_FORMAT_R32G32_SFLOAT, VK_FORMAT_R8G8_UNORM,
};

use crate::lut::{
    bake, e_avg_reference, BakeConfig, Layout, LayoutKind, Storage, Tables, UNIFORM_MU_SIZE,
    UNIFORM_PRECISE_MU_SIZE, UNIFORM_PRECISE_R_SIZE, UNIFORM_R_SIZE,
};

use crate::pixels::temp_dir;

fn baked(kind: LayoutKind, storage: Storage, size: Option<(usize, usize)>) -> Tables {
    let mut layout = Layout::of_kind(kind).with_storage(storage);
    if let Some((mu, r)) = size {
        layout = layout.with_size(mu, r);
    }
    bake(&BakeConfig {
        geometry: Geometry::SmithCorrelated,
        layout,
        ..BakeConfig::default()
    })
}

fn u32_at(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap())
}

fn assert_same(read: &Tables, written: &Tables) {
    assert_eq!(read.config, written.config);
    assert_eq!(read.layout(), written.layout());
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&read.stored_loss), bits(&written.stored_loss));
    assert_eq!(bits(&read.stored_loss_avg), bits(&written.stored_loss_avg));
    // e and e_avg: 1 - the stored loss, as the reader documents.
    for (e, l) in read.e.iter().zip(&read.stored_loss) {
        assert_eq!(*e, 1.0 - *l as f64);
    }
    for (e, l) in read.e_avg.iter().zip(&read.stored_loss_avg) {
        assert_eq!(*e, 1.0 - *l as f64);
    }
}

#[test]
fn ktx2_round_trips_bit_exact_for_every_layout_and_storage() {
    for kind in LayoutKind::ALL {
        for storage in Storage::ALL {
            for size in [Some((8, 5)), None] {
                // The layouts' own sizes once, in f32 (the uniform one is large).
                if size.is_none() && storage != Storage::F32 {
                    continue;
                }
                let t = baked(kind, storage, size);
                let bytes = encode_tables(&t).unwrap();
                let read = parse_tables(&bytes).unwrap_or_else(|e| panic!("{kind} {storage}: {e}"));
                assert_same(&read, &t);
                // What the shader reads from the loaded table is what it read from the bake.
                for (mu, r) in [(0.0, 0.0), (0.3, 0.5), (1.0, 1.0), (0.01, 0.1)] {
                    assert_eq!(read.lut_loss(mu, r).to_bits(), t.lut_loss(mu, r).to_bits());
                    assert_eq!(read.lut_loss_avg(r).to_bits(), t.lut_loss_avg(r).to_bits());
                }
            }
        }
    }
}

#[test]
fn ktx2_file_has_the_identifier_format_and_layout_text() {
    for (storage, format, texel) in [
        (Storage::F32, VK_FORMAT_R32G32_SFLOAT, 8),
        (Storage::F16, VK_FORMAT_R16G16_SFLOAT, 4),
        (Storage::Unorm8, VK_FORMAT_R8G8_UNORM, 2),
    ] {
        let t = baked(LayoutKind::Uniform, storage, Some((16, 4)));
        let bytes = encode_tables(&t).unwrap();
        assert_eq!(
            bytes[..12],
            [0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A]
        );
        assert_eq!(bytes[..12], IDENTIFIER);
        assert_eq!(u32_at(&bytes, 12), format);
        assert_eq!((u32_at(&bytes, 20), u32_at(&bytes, 24)), (16, 4));
        // The last 16 x 4 texels are the data, R then G per texel, row 0 first.
        let data = &bytes[bytes.len() - 16 * 4 * texel..];
        if storage == Storage::F32 {
            let f = |k: usize| f32::from_le_bytes(data[4 * k..4 * k + 4].try_into().unwrap());
            assert_eq!(f(2 * (16 + 3)), t.stored_loss[16 + 3]);
            assert_eq!(f(2 * (16 + 3) + 1), t.stored_loss_avg[1]);
        }
        let text = String::from_utf8_lossy(&bytes);
        for line in [
            "kind=uniform\n",
            "mu_size=16\n",
            "r_size=4\n",
            "mu_axis=linear\n",
            "mu_scale=15\n",
            "mu_bias=0\n",
            "r_scale=3\n",
            "r_bias=0\n",
            "r_min=0\n",
            "r_max=1\n",
            "centres=endpoints\n",
            "e_avg_read=linear\n",
            "geometry=smith-correlated\n",
            "channels=r=1-E g=1-E_avg\n",
        ] {
            assert!(text.contains(line), "no {line:?} in the layout text");
        }
        assert!(text.contains(&format!("storage={storage}\n")));
        assert!(text.contains(&format!(
            "KTXwriter\0shadeballs {}\0",
            env!("CARGO_PKG_VERSION")
        )));
        assert!(!text.contains("KTXorientation"));
    }
    let warped = encode_tables(&baked(LayoutKind::Warped, Storage::F32, Some((8, 4)))).unwrap();
    let text = String::from_utf8_lossy(&warped);
    for line in [
        "mu_axis=warped\n",
        "r_min=0.02\n",
        "e_avg_read=power-law\n",
        "mu_scale=7\n",
    ] {
        assert!(text.contains(line), "no {line:?} in the layout text");
    }
    let games = encode_tables(&baked(LayoutKind::Games202, Storage::F16, Some((8, 4)))).unwrap();
    let text = String::from_utf8_lossy(&games);
    for line in [
        "centres=half-texel\n",
        "mu_scale=8\n",
        "mu_bias=-0.5\n",
        "r_scale=4\n",
    ] {
        assert!(text.contains(line), "no {line:?} in the layout text");
    }
}

/// An independent reader: the `ktx2` crate parses the file, finds the format, the one
/// level, the writer and the layout key, and generates the same descriptor from the
/// vkFormat alone.
#[test]
fn ktx2_crate_reads_our_files_and_agrees_on_the_descriptor() {
    for (storage, format) in [
        (Storage::F32, ::ktx2::Format::R32G32_SFLOAT),
        (Storage::F16, ::ktx2::Format::R16G16_SFLOAT),
        (Storage::Unorm8, ::ktx2::Format::R8G8_UNORM),
    ] {
        let t = baked(LayoutKind::Uniform, storage, Some((16, 8)));
        let bytes = encode_tables(&t).unwrap();
        let reader = ::ktx2::Reader::new(&bytes[..]).unwrap();
        let h = reader.header();
        assert_eq!(h.format, Some(format));
        assert_eq!((h.pixel_width, h.pixel_height, h.pixel_depth), (16, 8, 0));
        assert_eq!((h.layer_count, h.face_count, h.level_count), (0, 1, 1));
        assert_eq!(h.supercompression_scheme, None);
        let (basic, type_size) = ::ktx2::dfd::Basic::from_format(format).unwrap();
        assert_eq!(h.type_size, type_size);
        assert_eq!(reader.basic_dfd(), Some(&basic));
        assert_eq!(reader.dfd_blocks().len(), 1);
        let block = ::ktx2::dfd::Block::Basic(basic).to_vec();
        assert_eq!(data_format_descriptor(storage)[4..], block[..]);
        let levels: Vec<_> = reader.levels().collect();
        assert_eq!(levels.len(), 1);
        assert_eq!(levels[0].data.len(), 16 * 8 * 2 * storage.bytes_per_texel());
        assert_eq!(
            levels[0].data.as_ptr() as usize % (2 * storage.bytes_per_texel()).max(4),
            bytes.as_ptr() as usize % (2 * storage.bytes_per_texel()).max(4),
            "level data aligned in the file"
        );
        let writer = format!("shadeballs {}\0", env!("CARGO_PKG_VERSION"));
        assert_eq!(
            reader.writer(),
            Some(writer.as_str()),
            "KTXwriter is a NUL-terminated string"
        );
        let keys: Vec<&str> = reader.key_value_data().map(|(k, _)| k).collect();
        assert_eq!(keys, ["KTXwriter", LAYOUT_KEY]);
    }
}

fn read_err(bytes: &[u8]) -> String {
    let e = parse_tables(bytes).expect_err("a bad file was read");
    let msg = e.to_string();
    assert!(!msg.contains('\n'), "not one line: {msg}");
    assert!(msg.starts_with("invalid table file: "), "{msg}");
    msg
}

#[test]
fn ktx2_truncated_corrupt_and_foreign_files_fail_in_one_line() {
    let t = baked(LayoutKind::Warped, Storage::F32, Some((4, 3)));
    let good = encode_tables(&t).unwrap();
    parse_tables(&good).unwrap();

    // Every truncation.
    for n in 0..good.len() {
        read_err(&good[..n]);
    }
    // Every byte flipped: never a panic; in the header's fields that say what and where
    // the data is (all but the key/value offset and length and the level's offset, which
    // may land on equivalent bytes), always an error.
    let data_start = good.len() - 4 * 3 * 8;
    for at in 0..good.len() {
        for flip in [0xFF, 0x01, 0x80] {
            let mut bad = good.clone();
            bad[at] ^= flip;
            let r = parse_tables(&bad);
            if (12..56).contains(&at) || (64..80).contains(&at) || (88..104).contains(&at) {
                assert!(r.is_err(), "byte {at} ^ {flip:#x} read as a table");
            }
            if let Err(e) = r {
                assert!(!e.to_string().contains('\n'));
            }
        }
    }

    let msg = read_err(b"not a texture at all, but long enough to hold a header and an index of one level, really.....");
    assert!(msg.contains("KTX 2.0 identifier"), "{msg}");
    let mut ktx1 = good.clone();
    ktx1[..12].copy_from_slice(&[
        0xAB, 0x4B, 0x54, 0x58, 0x20, 0x31, 0x31, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
    ]);
    assert!(read_err(&ktx1).contains("identifier"));
    let with = |at: usize, v: u32| {
        let mut b = good.clone();
        b[at..at + 4].copy_from_slice(&v.to_le_bytes());
        b
    };
    assert!(read_err(&with(12, 100)).contains("vkFormat 100"));
    assert!(read_err(&with(12, 83)).contains("typeSize"));
    assert!(read_err(&with(40, 2)).contains("levelCount"));
    assert!(read_err(&with(44, 2)).contains("supercompressionScheme"));
    assert!(read_err(&with(20, 5)).contains("level index"));
    assert!(read_err(&with(88, 1 << 30)).contains("level index"));
    assert!(read_err(&with(80, u32::MAX)).contains("runs past the end"));
    assert!(read_err(&with(56, 1 << 31)).contains("key/value"));
    // A descriptor's texel block of 256 texels (the `ktx2` crate's reader panics here).
    let mut block = good.clone();
    block[104 + 4 + 12] = 0xFF;
    assert!(read_err(&block).contains("texel blocks"));
    // A width that matches the data but not the layout text.
    let mut wide = with(20, 6);
    wide[24..28].copy_from_slice(&2u32.to_le_bytes());
    assert!(read_err(&wide).contains("layout: 4x3 texels"));
    // The layout text: a derived value changed.
    let find = |needle: &[u8]| {
        good.windows(needle.len())
            .position(|w| w == needle)
            .unwrap()
    };
    let at = find(b"mu_scale=3\n");
    let mut scale = good.clone();
    scale[at + 9] = b'4';
    assert!(read_err(&scale).contains("mu_scale 4"));
    let at = find(b"channels=");
    let mut channels = good.clone();
    channels[at..at + 8].copy_from_slice(b"chanxels");
    assert!(read_err(&channels).contains("no 'channels'"));
    // Texels: NaN, out of range, and a G channel that changes along a row.
    let texel = |k: usize, v: f32| {
        let mut b = good.clone();
        b[data_start + 4 * k..data_start + 4 * k + 4].copy_from_slice(&v.to_le_bytes());
        b
    };
    assert!(read_err(&texel(0, f32::NAN)).contains("outside [0, 1]"));
    assert!(read_err(&texel(2, -0.5)).contains("outside [0, 1]"));
    assert!(read_err(&texel(3, 0.123)).contains("same along the row"));
    // A file that is not there.
    let e = read_tables(std::path::Path::new("/no/such/table.ktx2")).unwrap_err();
    assert!(e.to_string().contains("cannot read"), "{e}");
    // Garbage of every length.
    let mut state = 7u64;
    for n in [0, 1, 12, 79, 80, 104, 200, 4096] {
        let mut junk: Vec<u8> = (0..n)
            .map(|_| {
                state = state.wrapping_mul(6364136223846793005).wrapping_add(1);
                (state >> 56) as u8
            })
            .collect();
        read_err(&junk);
        if n >= 12 {
            junk[..12].copy_from_slice(&IDENTIFIER);
            read_err(&junk);
        }
    }
}

#[test]
fn write_tables_dispatches_ktx2_atomically() {
    let dir = temp_dir("ktx2-write");
    let t = baked(LayoutKind::SqrtMu, Storage::F16, Some((8, 4)));
    let path = dir.join("t.KTX2");
    write_tables(&t, &path).unwrap();
    assert_same(&read_tables(&path).unwrap(), &t);
    let err = write_tables(&t, &dir.join("t.ktx"))
        .unwrap_err()
        .to_string();
    assert!(err.contains(".ktx2"), "{err}");
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
    std::fs::remove_dir_all(&dir).unwrap();
}

// ---- The uniform layout: what a plain bilinear texture read returns ----------------------

/// Roughness range the uniform layout promises 1e-3 on.
const R_LO: f64 = 0.1;

const GEOMETRIES: [Geometry; 2] = [Geometry::Schlick, Geometry::SmithCorrelated];

/// Points of [`plain_points`] spread evenly (the grid and the random points): the mean
/// error is taken over these, the max over all.
const EVEN_POINTS: usize = 200 * 200 + 4000;

/// A 200 x 200 grid over mu in [0, 1] and roughness in [0.1, 1] and 4000 random points
/// ([`EVEN_POINTS`]), then two grids over the grazing corner where a linear mu axis is
/// weakest and the error peaks between texels 5e-4 apart: 300 x 100 over mu in [0, 0.04],
/// roughness in [0.1, 0.25], and 1201 x 61 over mu in [0, 0.03], roughness in [0.1, 0.13]
/// (steps 2.5e-5 and 5e-4; the maxima they find agree to 3 digits with a grid half as dense).
fn plain_points() -> Vec<(f64, f64)> {
    let mut p = Vec::new();
    for j in 0..200 {
        for i in 0..200 {
            p.push((i as f64 / 199.0, R_LO + (1.0 - R_LO) * j as f64 / 199.0));
        }
    }
    p.extend(
        random_points(4000, 0x6b74_7832)
            .into_iter()
            .map(|(mu, r)| (mu, R_LO + (1.0 - R_LO) * r)),
    );
    assert_eq!(p.len(), EVEN_POINTS);
    for j in 0..100 {
        for i in 0..300 {
            p.push((0.04 * i as f64 / 299.0, R_LO + 0.15 * j as f64 / 99.0));
        }
    }
    for j in 0..61 {
        for i in 0..1201 {
            p.push((0.03 * i as f64 / 1200.0, R_LO + 0.03 * j as f64 / 60.0));
        }
    }
    p
}

fn reference(geometry: Geometry) -> &'static ReferencePoints {
    static REFS: [OnceLock<ReferencePoints>; 2] = [OnceLock::new(), OnceLock::new()];
    let k = GEOMETRIES.iter().position(|&g| g == geometry).unwrap();
    REFS[k].get_or_init(|| ReferencePoints::new(plain_points(), geometry))
}

/// Precise E_avg at 901 roughnesses, steps of 1e-3 over [0.1, 1] (within 5 % of a row
/// spacing of every mid-row for tables of up to ~100 rows).
fn e_avg_reference_rows(geometry: Geometry) -> &'static [(f64, f64)] {
    static REFS: [OnceLock<Vec<(f64, f64)>>; 2] = [OnceLock::new(), OnceLock::new()];
    let k = GEOMETRIES.iter().position(|&g| g == geometry).unwrap();
    REFS[k].get_or_init(|| {
        use rayon::prelude::*;
        (0..901)
            .into_par_iter()
            .map(|j| {
                let r = R_LO + (1.0 - R_LO) * j as f64 / 900.0;
                (r, e_avg_reference(r, geometry))
            })
            .collect()
    })
}

/// Errors of a plain read against the reference.
struct PlainErrors {
    /// E over all points (max, where).
    e: ErrorStats,
    /// E over the evenly spread points (the mean to quote).
    e_even: ErrorStats,
    /// E_avg read linearly between rows.
    e_avg: ErrorStats,
}

/// The plain read of E (f32 weights, or `weight_bits` fractional bits) and of E_avg.
fn plain_errors(t: &Tables, weight_bits: Option<u32>) -> PlainErrors {
    let refs = reference(t.config.geometry);
    let errors: Vec<(f64, f64, f64)> = refs
        .points
        .iter()
        .zip(&refs.e)
        .map(|(&(mu, r), &exact)| {
            let read = 1.0 - t.plain_loss(mu as f32, r as f32, weight_bits) as f64;
            ((read - exact).abs(), mu, r)
        })
        .collect();
    let e_avg = ErrorStats::from_errors(e_avg_reference_rows(t.config.geometry).iter().map(
        |&(r, exact)| {
            let read = 1.0 - t.plain_loss_avg(r as f32, weight_bits) as f64;
            ((read - exact).abs(), f64::NAN, r)
        },
    ));
    PlainErrors {
        e: ErrorStats::from_errors(errors.iter().copied()),
        e_even: ErrorStats::from_errors(errors[..EVEN_POINTS].iter().copied()),
        e_avg,
    }
}

fn uniform(geometry: Geometry, mu: usize, r: usize) -> Tables {
    bake(&BakeConfig {
        geometry,
        layout: Layout::of_kind(LayoutKind::Uniform).with_size(mu, r),
        ..BakeConfig::default()
    })
}

fn report(t: &Tables, p: &PlainErrors) -> String {
    let l = t.layout();
    format!(
        "{:5} x {:4}: E max {:.2e} at (mu {:.5}, r {:.4}), mean {:.2e}; E_avg max {:.2e} (r {:.3}), \
         mean {:.2e}; {} B as R32G32",
        l.mu_size,
        l.r_size,
        p.e.max,
        p.e.worst_at.0,
        p.e.worst_at.1,
        p.e_even.mean,
        p.e_avg.max,
        p.e_avg.worst_at.1,
        p.e_avg.mean,
        l.texels() * 8
    )
}

/// The measurement behind [`UNIFORM_PRECISE_MU_SIZE`] x [`UNIFORM_PRECISE_R_SIZE`]: a plain bilinear
/// `textureSample` (clamp to edge, f32 weights, and the 8-bit fractional weights of real
/// GPUs' samplers) of the uniform table within 1e-3 of the reference at roughness >= 0.1,
/// for Schlick and height-correlated Smith G; and the default is near the smallest such:
/// 128 texels fewer along mu, or 12 rows fewer, is not (with 8-bit weights).
#[test]
fn uniform_layout_plain_bilinear_read_is_within_1e3_at_its_default_size() {
    let (mu, r) = (UNIFORM_PRECISE_MU_SIZE, UNIFORM_PRECISE_R_SIZE);
    let mut smaller_fail = [false; 2];
    for geometry in GEOMETRIES {
        let t = uniform(geometry, mu, r);
        assert_eq!(
            *t.layout(),
            Layout::of_kind(LayoutKind::Uniform).with_size(mu, r)
        );
        let p = plain_errors(&t, None);
        let p8 = plain_errors(&t, Some(8));
        eprintln!(
            "uniform layout, {geometry} G, plain bilinear read at roughness >= {R_LO} ({} points): {}; \
             with 8-bit filter weights E max {:.2e}",
            p.e.count,
            report(&t, &p),
            p8.e.max
        );
        assert!(p.e.max <= 1e-3, "{geometry}: {:?}", p.e);
        assert!(p8.e.max <= 1e-3, "{geometry}, 8-bit weights: {:?}", p8.e);
        assert!(p.e_avg.max <= 1e-4, "{geometry}: {:?}", p.e_avg);
        // Our own read of the same table agrees with the plain one (the same texel span).
        for &(m, rr) in &reference(geometry).points[..EVEN_POINTS] {
            let (a, b) = (
                t.lut_loss(m as f32, rr as f32),
                t.plain_loss(m as f32, rr as f32, None),
            );
            assert!((a - b).abs() <= 1e-5, "{m} {rr}: {a} vs {b}");
        }
        for (k, (smu, sr)) in [(mu - 128, r), (mu, r - 12)].into_iter().enumerate() {
            let s = uniform(geometry, smu, sr);
            let ps = plain_errors(&s, Some(8));
            eprintln!("  smaller, 8-bit weights: {}", report(&s, &ps));
            smaller_fail[k] |= ps.e.max > 1e-3;
        }
    }
    assert_eq!(
        smaller_fail,
        [true, true],
        "a smaller uniform table would do"
    );
}

/// The default uniform size, the engines' 128 x 128, and 64 x 64: the errors
/// docs/accuracy.md states for them ("Tables for engines"), with f32 and 8-bit filter
/// weights. Each bound is the measured figure rounded up in its second digit, so a change
/// to the bake or the read that makes them worse fails.
#[test]
fn uniform_layout_engine_sizes_have_their_stated_error() {
    assert_eq!((UNIFORM_MU_SIZE, UNIFORM_R_SIZE), (128, 128));
    // (size, geometry, E max, E mean over the even points), measured by this test
    // (--nocapture prints them).
    let stated = ENGINE_SIZE_ERRORS;
    for &(n, geometry, max, mean) in &stated {
        let t = uniform(geometry, n, n);
        let p = plain_errors(&t, None);
        let p8 = plain_errors(&t, Some(8));
        eprintln!(
            "uniform {n} x {n}, {geometry} G: {}; with 8-bit weights E max {:.2e}, mean {:.2e}",
            report(&t, &p),
            p8.e.max,
            p8.e_even.mean
        );
        for (what, e) in [("f32", &p), ("8-bit", &p8)] {
            assert!(e.e.max <= max, "{n} {geometry} {what}: max {:.3e}", e.e.max);
            assert!(
                e.e_even.mean <= mean,
                "{n} {geometry} {what}: mean {:.3e}",
                e.e_even.mean
            );
        }
    }
}

/// The size curve behind `UNIFORM_PRECISE_MU_SIZE x UNIFORM_PRECISE_R_SIZE` (seconds):
/// `cargo test --release uniform_layout_size_sweep -- --ignored --nocapture`; other sizes
/// with `SWEEP_MU=2048,2176 SWEEP_R=96,100` (comma-separated).
#[test]
#[ignore]
fn uniform_layout_size_sweep() {
    let list = |var: &str, default: &[usize]| -> Vec<usize> {
        std::env::var(var)
            .map(|v| v.split(',').map(|n| n.trim().parse().unwrap()).collect())
            .unwrap_or_else(|_| default.to_vec())
    };
    let mus = list("SWEEP_MU", &[256, 512, 1024, 2048, 2176, 2304, 4096]);
    let rs = list("SWEEP_R", &[32, 64, 96, 100, 128, 256]);
    for geometry in GEOMETRIES {
        eprintln!("{geometry} G, plain bilinear read, roughness >= {R_LO}:");
        for &r in &rs {
            for &mu in &mus {
                let t = uniform(geometry, mu, r);
                eprintln!("  {}", report(&t, &plain_errors(&t, None)));
            }
        }
    }
}

/// The errors of a plain read of a uniform table at the engines' sizes (see
/// `uniform_layout_engine_sizes_have_their_stated_error`): size N (N x N), G, E max, E mean.
/// Measured (the larger of f32 and 8-bit weights): 64 x 64 max 1.42e-1 / 5.43e-2, mean
/// 2.08e-4 / 1.26e-4; 128 x 128 max 7.86e-2 / 1.78e-2, mean 5.30e-5 / 3.21e-5 (Schlick /
/// smith-correlated).
const ENGINE_SIZE_ERRORS: [(usize, Geometry, f64, f64); 4] = [
    (64, Geometry::Schlick, 1.5e-1, 2.1e-4),
    (64, Geometry::SmithCorrelated, 5.5e-2, 1.3e-4),
    (128, Geometry::Schlick, 7.9e-2, 5.4e-5),
    (128, Geometry::SmithCorrelated, 1.8e-2, 3.3e-5),
];
