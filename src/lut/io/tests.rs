//! Table files of the baked tables: CSV, EXR and PNG, their values and their refusals.
//! (The maths of baking and reading the tables are the unit tests of `src/lut/mod.rs`.)

use crate::brdf::ROUGHNESS_MIN;

use crate::lut::io::write_tables;

use crate::lut::{bake, BakeConfig, Layout};

#[test]
fn tables_are_written_as_csv_exr_and_png() {
    let dir = std::env::temp_dir().join(format!("shadeballs-lut-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let tables = bake(&BakeConfig {
        layout: Layout::default().with_size(8, 4),
        ..BakeConfig::default()
    });

    let csv = dir.join("t.csv");
    write_tables(&tables, &csv).unwrap();
    let text = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "table,roughness,mu,value");
    assert_eq!(lines.len(), 1 + 8 * 4 + 4);
    let last_e: Vec<f64> = lines[32]
        .split(',')
        .skip(1)
        .map(|v| v.parse().unwrap())
        .collect();
    assert_eq!(last_e[..2], [1.0, 1.0]);
    // What the storage holds (f32 here): 1 - the stored loss, not the f64 bake.
    assert_eq!(last_e[2], 1.0 - f64::from(tables.stored_loss[31]));
    assert!(lines[33].starts_with(&format!("E_avg,{ROUGHNESS_MIN},,")));

    for ext in ["exr", "png"] {
        let path = dir.join(format!("t.{ext}"));
        write_tables(&tables, &path).unwrap();
        let img = image::open(&path).unwrap().into_rgb32f();
        assert_eq!(img.dimensions(), (8, 4));
        let tol = if ext == "png" { 1.0 / 65535.0 } else { 1e-7 };
        assert!((img.get_pixel(3, 2)[0] as f64 - tables.e[2 * 8 + 3]).abs() <= tol);
        assert!((img.get_pixel(0, 2)[1] as f64 - tables.e_avg[2]).abs() <= tol);
    }

    // Bad paths: a clear error and no file, half-written or temporary, left behind.
    let err = write_tables(&tables, &dir.join("t.txt"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("use .csv, .exr or .png"), "{err}");
    let missing = dir.join("no/such/folder/t.csv");
    assert!(write_tables(&tables, &missing)
        .unwrap_err()
        .to_string()
        .contains("cannot write"));
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp"))
        .collect();
    assert!(leftovers.is_empty());
    std::fs::remove_dir_all(&dir).unwrap();
}
