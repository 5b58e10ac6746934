//! Tables as KTX 2.0 textures (`shadeballs bake --out FILE.ktx2`): the file round-trips
//! bit for bit, a third-party reader (the `ktx2` crate) accepts it and agrees on the
//! descriptor, bad files fail in one line, and the uniform layout's plain bilinear read
//! stays within 1e-3 of the reference at its default size (run with `-- --nocapture` for
//! the figures; `-- --ignored uniform_layout_size_sweep` measures the size curve).

use shadeballs::brdf::Geometry;

use shadeballs::lut::ktx2::{read_tables, VK_FORMAT_R16G16_SFLOAT, VK_FORMAT_R8G8_UNORM};

use shadeballs::lut::{Layout, LayoutKind, Storage, UNIFORM_MU_SIZE, UNIFORM_R_SIZE};

use crate::cli::{shadeballs, temp_dir};

fn u32_at(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap())
}

#[test]
fn bake_cli_writes_a_ktx2_that_reads_back() {
    let dir = temp_dir("ktx2");
    let path = dir.join("tables.ktx2");
    let (ok, stderr) = shadeballs(&[
        "bake",
        "--out",
        path.to_str().unwrap(),
        "--layout",
        "uniform",
        "--geometry",
        "smith-correlated",
    ]);
    assert!(ok, "{stderr}");
    let t = read_tables(&path).unwrap();
    assert_eq!(*t.layout(), Layout::of_kind(LayoutKind::Uniform));
    assert_eq!(t.config.geometry, Geometry::SmithCorrelated);
    assert!(stderr.contains(&format!(
        "baked E {UNIFORM_MU_SIZE}x{UNIFORM_R_SIZE} + E_avg {UNIFORM_R_SIZE}"
    )));

    let small = dir.join("small.ktx2");
    let (ok, stderr) = shadeballs(&[
        "bake",
        "--out",
        small.to_str().unwrap(),
        "--storage",
        "f16",
        "--size",
        "32x16",
    ]);
    assert!(ok, "{stderr}");
    let t = read_tables(&small).unwrap();
    assert_eq!(
        *t.layout(),
        Layout::default()
            .with_size(32, 16)
            .with_storage(Storage::F16)
    );
    let bytes = std::fs::read(&small).unwrap();
    assert_eq!(u32_at(&bytes, 12), VK_FORMAT_R16G16_SFLOAT);
    // The homework's layout stores 8 bits: R8G8_UNORM.
    let games = dir.join("games202.ktx2");
    let (ok, stderr) = shadeballs(&[
        "bake",
        "--out",
        games.to_str().unwrap(),
        "--layout",
        "games202",
    ]);
    assert!(ok, "{stderr}");
    assert_eq!(
        u32_at(&std::fs::read(&games).unwrap(), 12),
        VK_FORMAT_R8G8_UNORM
    );
    assert_eq!(
        read_tables(&games).unwrap().layout().storage,
        Storage::Unorm8
    );
    // No temporary file left beside them.
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    assert_eq!(names.len(), 3, "{names:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}
