//! Spherical harmonics (`environment::harmonics`): the basis, projection of a map, the
//! Funk-Hecke factors of a zonal kernel and the convolution they give; and the lab's
//! comparison of harmonics with a convolved map per roughness (issue 15).

use std::f64::consts::PI;

use glam::{DVec2, DVec3};
use shadeballs::environment::harmonics::{
    convolve_eval, index, project, sh_basis, zonal_coefficients,
};
use shadeballs::environment::prefilter::{kernels, CONVOLVED_WIDTH};
use shadeballs::environment::{uv_to_direction, EnvMap, MipChain, Prefiltered};
use shadeballs_lab::bench::harmonics::{
    convolved_layers, harmonics_sweep, kc_kernel, random_normals,
};

/// Directions and weights of a product rule exact for the harmonics of `bands` bands:
/// Gauss-Legendre in `z`, uniform in azimuth.
fn sphere_rule(bands: usize) -> Vec<(DVec3, f64)> {
    let (nodes, weights) = shadeballs::lut::gauss_legendre_unit(bands + 4);
    let azimuths = 2 * bands + 4;
    let mut out = Vec::new();
    for (&u, &w) in nodes.iter().zip(&weights) {
        let z = 2.0 * u - 1.0;
        let s = (1.0 - z * z).sqrt();
        for k in 0..azimuths {
            let phi = 2.0 * PI * k as f64 / azimuths as f64;
            let d = DVec3::new(s * phi.cos(), s * phi.sin(), z);
            out.push((d, 2.0 * w * 2.0 * PI / azimuths as f64));
        }
    }
    out
}

/// `<Y_i, Y_j> = delta_ij` for the 25 harmonics of 5 bands, by a quadrature exact for them.
#[test]
fn harmonics_basis_is_orthonormal() {
    let bands = 5;
    let count = bands * bands;
    let mut gram = vec![0.0; count * count];
    let mut y = vec![0.0; count];
    for (d, w) in sphere_rule(2 * bands) {
        sh_basis(d, bands, &mut y);
        for i in 0..count {
            for j in 0..count {
                gram[i * count + j] += w * y[i] * y[j];
            }
        }
    }
    for i in 0..count {
        for j in 0..count {
            let delta = if i == j { 1.0 } else { 0.0 };
            let g = gram[i * count + j];
            assert!((g - delta).abs() < 1e-3, "<Y_{i}, Y_{j}> = {g}");
        }
    }
}

/// The first bands equal their closed forms (Sloan 2008, appendix, without the
/// Condon-Shortley phase), here and at the poles.
#[test]
fn harmonics_match_closed_forms() {
    let mut y = vec![0.0; 9];
    let mut dirs = random_normals(20, 7);
    dirs.push(DVec3::Z);
    dirs.push(-DVec3::Z);
    for d in dirs {
        sh_basis(d, 3, &mut y);
        let (x, yy, z) = (d.x, d.y, d.z);
        let c1 = (3.0 / (4.0 * PI)).sqrt();
        let expected = [
            (index(0, 0), 0.5 / PI.sqrt()),
            (index(1, -1), c1 * yy),
            (index(1, 0), c1 * z),
            (index(1, 1), c1 * x),
            (index(2, -2), (15.0 / (4.0 * PI)).sqrt() * x * yy),
            (index(2, -1), (15.0 / (4.0 * PI)).sqrt() * yy * z),
            (
                index(2, 0),
                (5.0 / (16.0 * PI)).sqrt() * (3.0 * z * z - 1.0),
            ),
            (index(2, 1), (15.0 / (4.0 * PI)).sqrt() * x * z),
            (index(2, 2), (15.0 / (16.0 * PI)).sqrt() * (x * x - yy * yy)),
        ];
        for (i, e) in expected {
            assert!((y[i] - e).abs() < 1e-12, "{d}: Y[{i}] = {} not {e}", y[i]);
        }
    }
}

fn known(d: DVec3) -> f64 {
    1.0 + 0.5 * d.y + 0.25 * (d.x * d.x - d.z * d.z)
}

/// A map of `1 + y / 2 + (x^2 - z^2) / 4` (bands 0 to 2) projects on nothing above band 2
/// and its first three bands reconstruct it.
#[test]
fn harmonics_project_a_quadratic_map_on_three_bands() {
    let (w, h) = (256, 128);
    let mut texels = Vec::new();
    for j in 0..h {
        for i in 0..w {
            let uv = DVec2::new((i as f64 + 0.5) / w as f64, (j as f64 + 0.5) / h as f64);
            let v = known(uv_to_direction(uv)) as f32;
            texels.push([v, v, v]);
        }
    }
    let map = EnvMap::new(w, h, texels).unwrap();
    let coeffs = project(&map, 6);
    for (i, c) in coeffs.iter().enumerate().skip(9) {
        assert!(c.abs().max_element() < 1e-3, "coefficient {i}: {c}");
    }
    let mut y = vec![0.0; 9];
    for d in random_normals(200, 11) {
        sh_basis(d, 3, &mut y);
        let r: DVec3 = coeffs[..9].iter().zip(&y).map(|(c, b)| *c * *b).sum();
        let e = known(d);
        assert!(
            (r - DVec3::splat(e)).abs().max_element() < 1e-3,
            "{d}: {r} vs {e}"
        );
    }
}

/// The clamped cosine's Funk-Hecke factors: pi, 2 pi / 3, pi / 4, 0, -pi / 24
/// (Ramamoorthi & Hanrahan 2001).
#[test]
fn harmonics_cosine_kernel_factors() {
    let k = zonal_coefficients(|t| t, 5);
    let expected = [PI, 2.0 * PI / 3.0, PI / 4.0, 0.0, -PI / 24.0];
    for (l, (a, b)) in k.iter().zip(expected).enumerate() {
        assert!((a - b).abs() < 1e-6, "band {l}: {a} vs {b}");
    }
}

/// Under a uniform map of radiance 1 the Kulla-Conty lobe integral is pi (1 - E_avg) at every
/// normal, whatever the band count (bands above 0 project on nothing).
#[test]
fn harmonics_uniform_map_gives_the_kulla_conty_furnace() {
    let tables = shadeballs::lut::bake(&Default::default());
    let map = EnvMap::uniform(DVec3::ONE, 256, 128);
    let coeffs = project(&map, 9);
    for r in [0.0, 0.3, 0.5, 0.75, 1.0] {
        let expected = PI * tables.lut_loss_avg(r as f32) as f64;
        for bands in [1, 2, 3, 5, 9] {
            let zonal = zonal_coefficients(kc_kernel(&tables, r), bands);
            for n in random_normals(20, 3) {
                let c = convolve_eval(&coeffs[..bands * bands], &zonal, n);
                assert!(
                    (c - DVec3::splat(expected)).abs().max_element() < 1e-3,
                    "roughness {r}, {bands} bands, {n}: {c} vs {expected}"
                );
            }
        }
    }
}

/// The lab's convolved layers at the renderer's width are the renderer's own.
#[test]
fn harmonics_lab_layers_match_prefiltered() {
    let map = shadeballs::environment::Builtin::Studio.generate(128);
    let chain = MipChain::new(&map);
    let tables = shadeballs::lut::bake(&Default::default());
    let kern = kernels(&tables);
    let pre = Prefiltered::new(&chain, &kern, tables.config.geometry);
    let source = &chain.levels[chain.convolution_source() as usize];
    assert_eq!(
        convolved_layers(source, &kern, CONVOLVED_WIDTH),
        pre.convolved
    );
}

/// The measured table of docs/design/environment.md, "Harmonics or a map per roughness":
/// `cargo test --release -p shadeballs-lab --test lab harmonics_sweep_table -- --ignored --nocapture`
/// (the plots go to the temporary folder).
#[test]
#[ignore]
fn harmonics_sweep_table() {
    let started = std::time::Instant::now();
    let sweep = harmonics_sweep(false).unwrap();
    for t in &sweep.tables {
        println!("{}", t.markdown());
    }
    for g in &sweep.goals {
        println!("- {}: {} (met: {})", g.what, g.figure, g.met);
    }
    println!("sweep wall time {:.1} s", started.elapsed().as_secs_f64());
    for (stem, plot) in &sweep.plots {
        let path = std::env::temp_dir().join(format!("{stem}.png"));
        shadeballs_lab::plot::write_plot(plot, &path).unwrap();
        println!("plot: {}", path.display());
    }
}

/// The quick sweep runs and states both goals.
#[test]
fn harmonics_quick_sweep_states_its_goals() {
    let _turn = crate::quick_bench_turn();
    let sweep = harmonics_sweep(true).unwrap();
    assert_eq!(sweep.tables.len(), 1);
    assert_eq!(sweep.tables[0].rows.len(), 2 * 4 * (6 + 3));
    assert_eq!(sweep.goals.len(), 2);
    assert_eq!(sweep.plots.len(), 2);
}
