//! Materials as engines have them (docs/design/materials.md): the coating's tables, the
//! scene's material keys, the furnace of every metallic value, the layering forms.

use shadeballs::brdf::{DielectricFresnel, Geometry};
use shadeballs::lut::{
    coating_albedo, coating_albedo_read, coating_row, CoatingKey, CoatingRule, COATING_ROW_LEN,
};
use shadeballs::walk::single::{single_albedo, Rules};
use shadeballs::walk::{Dielectric, Schlick};

/// The coating's albedo against the precise quadrature of `walk::single_albedo` (48 x 48
/// nodes a segment, peak-mapped), at the nodes and as read between them.
#[test]
fn coating_rows_meet_the_precise_quadrature() {
    let rules = Rules::default();
    let rule = CoatingRule::default();
    let mut worst_node = 0.0f64;
    let mut worst_read = 0.0f64;
    let mut worst_read_above = 0.0f64;
    for geometry in Geometry::ALL {
        for r in [0.02, 0.05, 0.15, 0.35, 0.6, 1.0] {
            for eta in [1.1, 1.33, 1.5, 2.0, 2.5] {
                for fresnel in [DielectricFresnel::Exact, DielectricFresnel::Schlick] {
                    let key = CoatingKey::new(r, eta, fresnel, geometry);
                    let row = coating_row(&rule, &key);
                    for j in 0..=40 {
                        let mu = (j as f64 / 40.0).max(0.002);
                        let exact = match fresnel {
                            DielectricFresnel::Exact => single_albedo(
                                &rules,
                                mu,
                                key.roughness(),
                                &[Dielectric(key.eta())],
                                &[geometry],
                            )[0][0],
                            DielectricFresnel::Schlick => single_albedo(
                                &rules,
                                mu,
                                key.roughness(),
                                &[Schlick(shadeballs::brdf::f0_from_ior(key.eta()))],
                                &[geometry],
                            )[0][0],
                        };
                        let node = (coating_albedo(&rule, mu, &key) - exact).abs();
                        let read = (f64::from(coating_albedo_read(&row, mu as f32)) - exact).abs();
                        worst_node = worst_node.max(node);
                        worst_read = worst_read.max(read);
                        if mu >= 0.01 {
                            worst_read_above = worst_read_above.max(read);
                        }
                    }
                }
            }
        }
    }
    println!("worst node {worst_node:.2e} read {worst_read:.2e}, {worst_read_above:.2e} at mu >= 0.01 ({COATING_ROW_LEN} values a row)");
    // Thresholds: the measured worst with a little room: 1.3e-3 at the nodes (at mu =
    // 0.002 and roughness 0.02, where E_F changes over a span of mu of about alpha), 8.8e-4
    // as read from mu = 0.01 up, 4.8e-3 as read below.
    assert!(worst_node < 2e-3, "{worst_node}");
    assert!(worst_read_above < 1.2e-3, "{worst_read_above}");
    assert!(worst_read < 1e-2, "{worst_read}");
}

/// What the coating's rows cost at startup: the 15 of `plastic.toml` (3 indices x 5
/// roughness values), printed (docs/design/materials.md quotes it).
#[test]
fn coating_rows_bake_time() {
    let keys: Vec<CoatingKey> = [1.33, 1.5, 2.0]
        .iter()
        .flat_map(|&eta| {
            shadeballs::scene::REFERENCE_ROUGHNESS.map(|r| {
                CoatingKey::new(r, eta, DielectricFresnel::Exact, Geometry::SmithCorrelated)
            })
        })
        .collect();
    let mut times = Vec::new();
    for _ in 0..5 {
        let start = std::time::Instant::now();
        let rows =
            shadeballs::lut::CoatingRows::bake(keys.iter().copied(), &mut Default::default());
        times.push(start.elapsed().as_secs_f64() * 1e3);
        assert_eq!(rows.rows.len(), 15);
    }
    times.sort_by(f64::total_cmp);
    println!("15 coating rows: median {:.2} ms", times[2]);
}
