//! The ground-truth random walk (lab/src/truth): its single scattering is the baker's E with
//! height-correlated Smith G, its white albedo is 1, and `shadeballs-lab truth` writes
//! well-formed files.

use glam::DVec3;
use shadeballs::brdf::{f_micro, Geometry};
use shadeballs::lut::{self, adaptive, e_reference, gauss_legendre_unit, BakeConfig};
use shadeballs::scene::Scene;
use shadeballs_lab::truth::albedo::{self, FresnelKind, Grid};
use shadeballs_lab::truth::compare::Comparison;
use shadeballs_lab::truth::fresnel::{
    fresnel_conductor, gulbrandsen_ior, gulbrandsen_pair, Fresnel, Metal,
};
use shadeballs_lab::truth::microsurface::Microsurface;
use shadeballs_lab::truth::models::ModelTables;
use shadeballs_lab::truth::single::{phi_fresnel, single_albedo, Rules};
use shadeballs_lab::truth::walk::{self, incident};

use crate::cli::{lab, temp_dir};

#[test]
fn single_scattering_quadrature_matches_the_precise_reference() {
    let rule = Rules::default();
    let mut worst: f64 = 0.0;
    for &r in &[0.1, 0.3, 0.6, 1.0] {
        for &mu in &[0.02, 0.1, 0.4, 0.8, 1.0] {
            let got = single_albedo(&rule, mu, r, &[Fresnel::One], &Geometry::ALL);
            for (g, v) in Geometry::ALL.iter().zip(&got) {
                let err = (v[0] - e_reference(mu, r, *g)).abs();
                worst = worst.max(err);
            }
        }
    }
    // The azimuth rule alone against the closed form of int D dphi.
    let mut worst_phi: f64 = 0.0;
    for &r in &[0.02, 0.1, 0.5, 1.0] {
        let alpha = r * r;
        for &(mo, mi) in &[
            (0.5, 0.5),
            (0.9, 0.3),
            (0.05, 0.06),
            (1.0, 0.4),
            (0.3, 0.31),
        ] {
            let (so, si) = ((1.0f64 - mo * mo).sqrt(), (1.0f64 - mi * mi).sqrt());
            let mut out = [0.0];
            phi_fresnel(
                &rule,
                (so, mo),
                (si, mi),
                alpha,
                &[Fresnel::One],
                1.0,
                &mut out,
            );
            let exact = lut::phi_integral(mo, so, mi, si, alpha);
            worst_phi = worst_phi.max((out[0] / exact - 1.0).abs());
        }
    }
    println!("azimuth rule, max relative error {worst_phi:.2e}");
    println!("single-scattering quadrature, max |E - E_ref| = {worst:.2e}");
    assert!(worst < 1e-6 && worst_phi < 1e-8, "{worst} {worst_phi}");
}

#[test]
fn walk_single_scattering_is_the_bakers_e_with_height_correlated_smith() {
    let _turn = crate::quick_bench_turn();
    let config = BakeConfig {
        geometry: Geometry::SmithCorrelated,
        ..Default::default()
    };
    let tables = lut::bake(&config);
    let layout = tables.layout();
    let mut worst_sigma: f64 = 0.0;
    for j in [layout.r_size / 4, layout.r_size / 2, layout.r_size - 1] {
        for i in [2, layout.mu_size / 3, layout.mu_size - 1] {
            let mu = layout.mu_of_texel(i, j);
            let r = layout.roughness_of_texel(j);
            let e = tables.e[j * layout.mu_size + i];
            let a = walk::albedo(
                &Microsurface::new(r),
                mu,
                &[Fresnel::One],
                100_000,
                &[1, i as u64, j as u64],
            );
            let (m, se) = (a.single[0].mean(), a.single[0].stderr());
            println!("r {r:.3} mu {mu:.4}: walk {m:.5} +- {se:.1e}, baker {e:.5}");
            worst_sigma = worst_sigma.max((m - e).abs() / se);
            assert!(se < 2e-3);
        }
    }
    assert!(worst_sigma < 4.5, "{worst_sigma}");
}

#[test]
fn next_event_single_scattering_is_cook_torrance() {
    for &(r, mu) in &[(0.5, 0.7), (1.0, 0.3)] {
        let s = Microsurface::new(r);
        let wi = incident(mu);
        let outgoing: Vec<DVec3> = (0..9)
            .map(|k| {
                let t = (-80.0 + 20.0 * k as f64).to_radians();
                DVec3::new(t.sin(), 0.0, t.cos())
            })
            .collect();
        let lobe = walk::lobe(&s, wi, &outgoing, &[Fresnel::One], 100_000, &[2]);
        for (j, wo) in outgoing.iter().enumerate() {
            let h = (wi + *wo).normalize();
            let exact = f_micro(1.0, wo.z, wi.z, h.z, r, Geometry::SmithCorrelated) * wo.z;
            let st = lobe.single[j];
            println!(
                "r {r} mu {mu} wo.z {:.3}: {:.5} +- {:.1e} vs {exact:.5}",
                wo.z,
                st.mean(),
                st.stderr()
            );
            assert!((st.mean() - exact).abs() < 4.5 * st.stderr() + 1e-9);
        }
    }
}

/// Gauss-Legendre in `mu` times the trapezoidal rule in the azimuth, over the hemisphere.
fn hemisphere_rule(n_mu: usize, n_phi: usize) -> Vec<(DVec3, f64)> {
    let (x, w) = gauss_legendre_unit(n_mu);
    let mut rule = Vec::new();
    for (mu, wm) in x.iter().zip(&w) {
        for k in 0..n_phi {
            let phi = std::f64::consts::TAU * (k as f64 + 0.5) / n_phi as f64;
            let s = (1.0 - mu * mu).sqrt();
            rule.push((
                DVec3::new(s * phi.cos(), s * phi.sin(), *mu),
                wm * std::f64::consts::TAU / n_phi as f64,
            ));
        }
    }
    rule
}

#[test]
fn white_albedo_by_next_event_is_one() {
    let _turn = crate::quick_bench_turn();
    // An estimator independent of the escape tally: next-event estimates of f cos, summed
    // over a hemisphere rule (exact to 1e-9 on the single-scattering lobe, checked here).
    let rule = hemisphere_rule(24, 48);
    for &(r, mu) in &[(1.0, 0.2), (0.6, 0.7)] {
        let wi = incident(mu);
        let ss: f64 = rule
            .iter()
            .map(|(wo, w)| {
                let h = (wi + *wo).normalize();
                w * f_micro(1.0, wo.z, wi.z, h.z, r, Geometry::SmithCorrelated) * wo.z
            })
            .sum();
        let rule_error = (ss - e_reference(mu, r, Geometry::SmithCorrelated)).abs();
        let a =
            walk::albedo_next_event(&Microsurface::new(r), mu, &rule, Fresnel::One, 32768, &[3]);
        println!(
            "r {r} mu {mu}: next-event albedo {:.5} +- {:.1e} (rule error {rule_error:.1e})",
            a.mean(),
            a.stderr()
        );
        assert!(
            rule_error < 1e-6 && a.stderr() < 3e-3,
            "{rule_error} {}",
            a.stderr()
        );
        assert!((a.mean() - 1.0).abs() < 4.0 * a.stderr(), "{}", a.mean());
    }
}

#[test]
fn conductor_fresnel_and_the_artist_friendly_mapping() {
    // A dielectric (k = 0, n = 1.5): 4 % at normal incidence, 0 for p at Brewster's angle,
    // 1 at grazing.
    assert!((fresnel_conductor(1.5, 0.0, 1.0) - 0.04).abs() < 1e-12);
    let brewster = 1.5f64.atan().cos();
    let rs = ((brewster - 1.5 * (1.0 - (1.0 - brewster * brewster) / 2.25f64).sqrt())
        / (brewster + 1.5 * (1.0 - (1.0 - brewster * brewster) / 2.25f64).sqrt()))
    .powi(2);
    assert!((fresnel_conductor(1.5, 0.0, brewster) - rs / 2.0).abs() < 1e-12);
    assert!((fresnel_conductor(0.2, 3.0, 0.0) - 1.0).abs() < 1e-12);
    for metal in [Metal::copper(), Metal::gold()] {
        for c in 0..3 {
            let (r, g) = (metal.r[c], metal.g[c]);
            let (n, k) = gulbrandsen_ior(r, g);
            // Normal incidence gives back the reflectivity; the inverse gives back the pair.
            assert!(
                (fresnel_conductor(n, k, 1.0) - r).abs() < 1e-12,
                "{} {c}",
                metal.name
            );
            let (r2, g2) = gulbrandsen_pair(n, k);
            assert!(
                (r2 - r).abs() < 1e-12 && (g2 - g).abs() < 1e-9,
                "{} {c}",
                metal.name
            );
            // F_avg of the conductor by its own adaptive rule against a plain one.
            let avg = adaptive(
                &|mu: f64| 2.0 * fresnel_conductor(n, k, mu) * mu,
                0.0,
                1.0,
                1e-13,
            );
            assert!((metal.conductor(c).average() - avg).abs() < 1e-10);
        }
    }
}

#[test]
fn the_walk_is_deterministic_for_a_seed() {
    let s = Microsurface::new(0.8);
    let ch = [Fresnel::One, Fresnel::Schlick(0.3)];
    let a = walk::albedo(&s, 0.4, &ch, 20_000, &[9]);
    let b = walk::albedo(&s, 0.4, &ch, 20_000, &[9]);
    let c = walk::albedo(&s, 0.4, &ch, 20_000, &[10]);
    assert_eq!(a.multiple, b.multiple);
    assert_ne!(a.multiple, c.multiple);
    assert_eq!(a.truncated, 0);
}

#[test]
fn accurate_albedo_error_is_at_most_a_third_of_games202() {
    // The quick grid: the corners of the full study's grid (its largest errors sit at low
    // roughness and grazing mu) with fewer paths.
    let grid = Grid::quick();
    let channels = albedo::channels();
    let cells = albedo::compute(&grid, &channels);
    let tables = ModelTables::new();
    let accurate = Scene::reference().effective_geometry();
    let cmp = Comparison::new(&cells, &channels, &tables, accurate);
    let ids = cmp.channel_ids(FresnelKind::Schlick, None);
    let (acc, _, _) = cmp.max_error(&ids, |c, k| cmp.models(c, k)[1]);
    let (g202, _, _) = cmp.max_error(&ids, |c, k| cmp.models(c, k)[2]);
    println!(
        "largest albedo error: accurate ({accurate} G) {acc:.2e}, games202 {g202:.2e}, ratio {:.2}, walk stderr <= {:.1e}",
        acc / g202,
        cmp.max_stderr(&ids)
    );
    assert!(acc <= g202 / 3.0, "{acc} {g202}");
}

/// Rows of a CSV file: the header, then every row with as many fields, numbers finite.
fn check_csv(path: &std::path::Path, first: &str, rows: usize) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header[0], first, "{}", path.display());
    let mut n = 0;
    for line in lines {
        let fields: Vec<&str> = line.split(',').collect();
        assert_eq!(fields.len(), header.len(), "{}: {line}", path.display());
        for f in &fields {
            if let Ok(v) = f.parse::<f64>() {
                assert!(v.is_finite(), "{}: {line}", path.display());
            }
        }
        n += 1;
    }
    assert_eq!(n, rows, "{}", path.display());
}

#[test]
fn cli_truth_quick_writes_well_formed_files() {
    let dir = temp_dir("truth");
    let (ok, stderr) = lab(&["truth", "--quick", "--out", dir.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("accurate") && stderr.contains("games202"),
        "{stderr}"
    );
    let (grid, slices) = (Grid::quick(), shadeballs_lab::truth::lobes::Slices::quick());
    let cells = grid.roughness.len() * grid.mu.len();
    // White + 3 copper + 3 gold Schlick channels; 3 + 3 conductor channels.
    check_csv(&dir.join("albedo.csv"), "material", cells * 7);
    check_csv(&dir.join("albedo_conductor.csv"), "material", cells * 6);
    check_csv(&dir.join("ablation.csv"), "geometry", 12);
    let lobe_rows = slices.roughness.len() * slices.theta_i.len() * slices.theta_o.len() * 7;
    check_csv(&dir.join("lobes.csv"), "material", lobe_rows);
    let summary = std::fs::read_to_string(dir.join("summary.md")).unwrap();
    assert!(summary.contains("`accurate` / `games202` ="), "{summary}");
    for m in ["white", "copper", "gold"] {
        for stem in [
            "albedo_vs_mu",
            "albedo_error",
            "albedo_vs_roughness",
            "lobes",
            "lobes_ms",
        ] {
            let path = dir.join(format!("{stem}_{m}.png"));
            let img = image::open(&path).unwrap().to_rgb8();
            let inked = img.pixels().filter(|p| p.0 != [255, 255, 255]).count();
            assert!(img.width() > 400 && inked > 1000, "{}", path.display());
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn cli_truth_reports_an_unwritable_folder() {
    let (ok, stderr) = lab(&["truth", "--quick", "--out", "/proc/version/x"]);
    assert!(!ok);
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    assert!(
        stderr.starts_with("error:") && stderr.contains("/proc/version/x"),
        "{stderr}"
    );
}
