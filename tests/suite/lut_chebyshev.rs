//! The Chebyshev bake (`src/lut/chebyshev.rs`): its series interpolates E at any texel of
//! any layout, for every geometry term, within the bounds its documentation states.
use shadeballs::brdf::Geometry;
use shadeballs::lut::accuracy::ReferenceTables;
use shadeballs::lut::{self, BakeConfig, ChebyshevSurface, Layout, LayoutKind, Method};

/// With precise values at the points (48 nodes a segment), the default 25 x 17 grid
/// interpolates E within 1.9e-7 (Schlick), 6.0e-7 (Smith), 1.9e-6 (height-correlated) at
/// every texel of the 64 x 64 default and the homework's 128 x 128 layout.
#[test]
fn series_interpolates_e_at_every_texel() {
    let bounds = [2e-7, 7e-7, 2e-6];
    for (g, bound) in Geometry::ALL.into_iter().zip(bounds) {
        let surface =
            ChebyshevSurface::with_grid(g, 48, lut::CHEBYSHEV_MU_NODES, lut::CHEBYSHEV_R_NODES);
        let mut worst: f64 = 0.0;
        for layout in [Layout::default(), Layout::of_kind(LayoutKind::Games202)] {
            let reference = ReferenceTables::new(layout, g);
            for j in 0..layout.r_size {
                let row = surface.texel_row(&layout, j);
                for (i, e) in row.iter().enumerate() {
                    worst = worst.max((e - reference.e[j * layout.mu_size + i]).abs());
                }
            }
        }
        println!("{g}: series within {worst:.2e} of the reference");
        assert!(worst <= bound, "{g}: {worst:.2e} > {bound:.1e}");
    }
}

/// The default bake on layouts it was not tuned on: as accurate as the per-texel quadrature
/// with the same nodes, to within 1e-5 (the interpolation's share), and both within 2e-5
/// of the reference.
#[test]
fn chebyshev_bake_matches_the_quadrature_on_other_layouts() {
    for layout in [
        Layout::of_kind(LayoutKind::SqrtMu).with_size(48, 32),
        Layout::default().with_size(200, 7),
        Layout::default().with_size(2, 2),
    ] {
        for g in Geometry::ALL {
            let reference = ReferenceTables::new(layout, g);
            let error = |method| {
                let tables = lut::bake(&BakeConfig {
                    geometry: g,
                    layout,
                    method,
                    ..BakeConfig::default()
                });
                reference.bake_error(&tables).0
            };
            let (cheb, quad) = (error(Method::Chebyshev), error(Method::Quadrature));
            println!(
                "{g} {}x{} {}: chebyshev {:.2e} at {:?}, quadrature {:.2e} at {:?}",
                layout.mu_size,
                layout.r_size,
                layout.kind,
                cheb.max,
                cheb.worst_at,
                quad.max,
                quad.worst_at
            );
            assert!(
                cheb.max <= quad.max.max(1e-5) + 1e-5,
                "{g} {layout:?}: {cheb:?} vs {quad:?}"
            );
        }
    }
}
