//! The GPU table probe: what the shader reads equals the CPU model of the read
//! (`Tables::lut_e`, `lut_e_avg`), and how far that is from the precise reference.
use rayon::prelude::*;
use shadeballs::brdf::Geometry;
use shadeballs::lut::{e_avg_reference, e_reference};

use crate::pixels::vulkan;

const N: u32 = 65;

#[test]
fn probe_equals_the_cpu_model_of_the_read() {
    let mut r = vulkan();
    for geometry in Geometry::ALL {
        let (tables, samples) = r.probe(geometry, N).unwrap();
        let (mut de, mut da) = (0.0f32, 0.0f32);
        for s in &samples {
            de = de.max((s.e - tables.lut_e(s.mu, s.roughness)).abs());
            da = da.max((s.e_avg - tables.lut_e_avg(s.roughness)).abs());
        }
        println!("{geometry}: GPU probe vs Tables::lut_e max |diff| {de:.2e}, lut_e_avg {da:.2e}");
        assert!(
            de <= 1e-6 && da <= 1e-6,
            "{geometry}: E {de:e}, E_avg {da:e}"
        );
    }
}

/// Max |GPU read - precise reference| on the 65 x 65 grid, for E and E_avg.
fn errors_against_reference(geometry: Geometry) -> (f64, (f32, f32), f64, f32) {
    let (_, samples) = vulkan().probe(geometry, N).unwrap();
    let e_err: Vec<(f64, (f32, f32))> = samples
        .par_iter()
        .map(|s| {
            (
                (s.e as f64 - e_reference(s.mu as f64, s.roughness as f64, geometry)).abs(),
                (s.mu, s.roughness),
            )
        })
        .collect();
    let (e_max, at) = e_err
        .iter()
        .copied()
        .fold((0.0, (0.0, 0.0)), |a, b| if b.0 > a.0 { b } else { a });
    let rows: Vec<(f64, f32)> = samples[..]
        .par_chunks(N as usize)
        .map(|row| {
            (
                (row[0].e_avg as f64 - e_avg_reference(row[0].roughness as f64, geometry)).abs(),
                row[0].roughness,
            )
        })
        .collect();
    let (a_max, a_at) = rows
        .iter()
        .copied()
        .fold((0.0, 0.0), |a, b| if b.0 > a.0 { b } else { a });
    (e_max, at, a_max, a_at)
}

#[test]
fn probe_against_the_precise_reference() {
    let mut failures = Vec::new();
    for geometry in Geometry::ALL {
        let (e_max, at, a_max, a_at) = errors_against_reference(geometry);
        println!(
            "{geometry}, {N}x{N} grid: max |E_read - E_ref| = {e_max:.3e} at (mu, r) = {at:?}; \
             max |E_avg_read - E_avg_ref| = {a_max:.3e} at r = {a_at}"
        );
        if e_max > 1e-3 || a_max > 1e-3 {
            failures.push(format!(
                "{geometry}: E {e_max:e} at {at:?}, E_avg {a_max:e} at r = {a_at}"
            ));
        }
    }
    assert!(failures.is_empty(), "read error above 1e-3: {failures:?}");
}
