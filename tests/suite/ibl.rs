//! Image-based lighting: the split-sum table, the prefiltered environment (CPU and GPU),
//! and the shading under a map against its CPU twin.

use glam::DVec3;
use shadeballs::brdf::Geometry;
use shadeballs::environment::prefilter::{self, MipChain, Prefiltered};
use shadeballs::environment::EnvMap;
use shadeballs::lut::{self, e_reference, split_sum, BakeConfig, SplitSum};

/// A + B = E. Against E by the same `theta_i` nodes with the azimuth in closed form the
/// sum checks the split sum's azimuthal quadrature, and against the precise adaptive
/// reference the whole 2-D rule: within 1e-6 and 2e-6 (the tables' own accuracy goal) for
/// every G, over mu and roughness including grazing, but for the grazing near-mirror
/// (mu <= 1e-3 at roughness <= 0.05), where both are off by up to 3.1e-3 (measured,
/// height-correlated G at mu = 0, roughness 0; 1.9e-6 at roughness 0.05): the azimuth there has three scales (the peak,
/// a 1/phi^2 shoulder 1/alpha wider, a floor) that 2 x 32 nodes do not resolve.
#[test]
fn split_sum_adds_up_to_e() {
    let mut worst_same: (f64, f64, f64, &str) = (0.0, 0.0, 0.0, "");
    let mut worst_ref: (f64, f64, f64, &str) = (0.0, 0.0, 0.0, "");
    for g in Geometry::ALL {
        for &mu in &[0.0, 1e-3, 0.02, 0.1, 0.3, 0.5, 0.77, 0.99, 1.0] {
            for &r in &[0.0, 0.05, 0.15, 0.3, 0.5, 0.75, 1.0] {
                let (a, b) = split_sum(mu, r, g);
                assert!(a >= -1e-12 && b >= 0.0, "{mu} {r} {a} {b}");
                let same = (a + b - lut::e_same_nodes(mu, r, g)).abs();
                let reference = (a + b - e_reference(mu, r, g)).abs();
                if mu <= 1e-3 && r <= 0.05 {
                    assert!(
                        same < 5e-3 && reference < 5e-3,
                        "{mu} {r} {same} {reference}"
                    );
                    continue;
                }
                if same > worst_same.0 {
                    worst_same = (same, mu, r, g.name());
                }
                if reference > worst_ref.0 {
                    worst_ref = (reference, mu, r, g.name());
                }
            }
        }
    }
    assert!(
        worst_same.0 < 1e-6,
        "A + B - E (same nodes) worst {worst_same:?}"
    );
    assert!(
        worst_ref.0 < 2e-6,
        "A + B - E (reference) worst {worst_ref:?}"
    );
}

/// B is the Fresnel-weighted part: at normal incidence and low roughness v.h = 1 nearly
/// everywhere, so B is tiny; at grazing it is a large share of E.
#[test]
fn split_sum_bias_grows_towards_grazing() {
    let (_, b_normal) = split_sum(1.0, 0.1, Geometry::SmithCorrelated);
    let (a_grazing, b_grazing) = split_sum(0.05, 0.1, Geometry::SmithCorrelated);
    assert!(b_normal < 1e-3, "{b_normal}");
    assert!(
        b_grazing > 0.3 * (a_grazing + b_grazing),
        "{b_grazing} {a_grazing}"
    );
    let table = SplitSum::bake(Geometry::SmithCorrelated);
    let direct = split_sum(0.5, 0.5, Geometry::SmithCorrelated).1 as f32;
    assert!((table.bias_at(0.5, 0.5) - direct).abs() < 2e-3);
}
