//! The truth for plastics (src/walk/coating.rs): the dielectric Fresnel and its averages,
//! and the random walk through a rough dielectric coating over a Lambertian base held to
//! laws that can fail: the white furnace, no interface at IOR 1, the first event's single
//! scattering, and the smooth limit's closed form.

use crate::brdf::{
    f0_from_ior, f_avg_dielectric, f_avg_inside, f_schlick, fresnel_dielectric, Geometry,
};
use crate::walk::coating::{refract, smooth_coating_albedo, Coating};
use crate::walk::single::{single_albedo, Rules};
use crate::walk::{incident, Dielectric, Rng, MAX_CHANNELS};
use glam::DVec3;

/// Roughness values and relative indices of the furnace goal (issue 25's list).
const ROUGHNESS: [f64; 5] = [0.05, 0.25, 0.5, 0.75, 1.0];
const IOR: [f64; 5] = [1.1, 1.33, 1.5, 2.0, 2.5];

#[test]
fn dielectric_fresnel_meets_its_known_values() {
    // Normal incidence is Schlick's F0: ((eta - 1) / (eta + 1))^2, 0.04 at 1.5.
    for eta in IOR {
        assert!(
            (fresnel_dielectric(1.0, eta) - f0_from_ior(eta)).abs() < 1e-12,
            "{eta}"
        );
    }
    assert!((f0_from_ior(1.5) - 0.04).abs() < 1e-15);
    // No interface at eta = 1; grazing reflects everything; past the critical angle too.
    for c in [0.0, 0.3, 1.0] {
        assert!(fresnel_dielectric(c, 1.0).abs() < 1e-12 || c == 0.0);
    }
    assert!((fresnel_dielectric(0.0, 1.5) - 1.0).abs() < 1e-12);
    let critical = (1.0 - 1.0 / (1.5f64 * 1.5)).sqrt();
    assert_eq!(fresnel_dielectric(critical - 1e-6, 1.0 / 1.5), 1.0);
    assert!(fresnel_dielectric(critical + 1e-3, 1.0 / 1.5) < 1.0);
    // Brewster's angle: the p-polarised part vanishes, so F is half the s part there,
    // (cos_i - eta cos_t)^2 / (cos_i + eta cos_t)^2 / 2 (Born and Wolf).
    let eta: f64 = 1.5;
    let (ci, st) = (
        1.0 / (1.0 + eta * eta).sqrt(),
        eta / (1.0 + eta * eta).sqrt(),
    );
    let ct = (1.0 - st * st / (eta * eta)).sqrt();
    let rs = ((ci - eta * ct) / (ci + eta * ct)).powi(2);
    assert!((fresnel_dielectric(ci, eta) - 0.5 * rs).abs() < 1e-12);
    // Schlick's curve is an approximation of it: close at normal incidence, apart near
    // grazing (0.0226 at cos 0.03), both reaching 1 at cos 0.
    assert!((f_schlick(0.04, 0.9) - fresnel_dielectric(0.9, 1.5)).abs() < 1e-3);
    assert!((f_schlick(0.04, 0.03) - fresnel_dielectric(0.03, 1.5)).abs() > 0.01);
}

#[test]
fn dielectric_averages_are_reciprocal_and_meet_the_numbers() {
    // 0.09178 and 0.5963 at eta 1.5: numerical integrations of the exact Fresnel (the
    // design notes' figures, 4 digits).
    assert!(
        (f_avg_dielectric(1.5) - 0.09178).abs() < 5e-5,
        "{}",
        f_avg_dielectric(1.5)
    );
    assert!(
        (f_avg_inside(1.5) - 0.5963).abs() < 5e-5,
        "{}",
        f_avg_inside(1.5)
    );
    // The inside average by reciprocity, 1 - (1 - F_avg(eta)) / eta^2, against the
    // direct integral from the other side, which passes the critical angle: two
    // independent computations.
    for eta in IOR {
        let direct = f_avg_dielectric(1.0 / eta);
        assert!((f_avg_inside(eta) - direct).abs() < 1e-9, "{eta}: {direct}");
    }
    assert!(f_avg_dielectric(1.0).abs() < 1e-12);
}

#[test]
fn refraction_obeys_snell() {
    let m = DVec3::Z;
    for eta in [1.0 / 1.5, 1.33, 2.5] {
        for mu in [0.2, 0.6, 1.0] {
            let d = -incident(mu);
            let Some(t) = refract(d, m, eta) else {
                assert!(eta < 1.0);
                continue;
            };
            let sin_i = (1.0 - mu * mu).sqrt();
            let sin_t = (1.0 - t.z * t.z).sqrt();
            assert!((sin_i - eta * sin_t).abs() < 1e-12, "{eta} {mu}");
            assert!(t.z < 0.0 && (t.length() - 1.0).abs() < 1e-12);
        }
    }
}

/// The walk's albedo at `mu`, one channel.
fn albedo(roughness: f64, eta: f64, rho: f64, mu: f64, paths: u32, seed: u64) -> (f64, f64) {
    let mut rng = Rng::new(&[seed, (roughness * 1e3) as u64, (eta * 1e3) as u64]);
    let (mean, stderr) = Coating::new(roughness, eta).albedo(mu, &[rho], paths, &mut rng);
    (mean[0], stderr[0])
}

#[test]
fn white_base_under_a_lossless_coating_reflects_everything() {
    // The white furnace: every roughness and IOR of the goal, three angles, within three
    // standard errors of 1 (no other allowance; a lossless path weighs exactly 1, so any
    // path lost or cut shows).
    let mut worst: f64 = 0.0;
    for r in ROUGHNESS {
        for eta in IOR {
            for mu in [0.15, 0.6, 1.0] {
                let (mean, se) = albedo(r, eta, 1.0, mu, 4000, 1);
                assert!(
                    (mean - 1.0).abs() <= 3.0 * se,
                    "r {r} eta {eta} mu {mu}: {mean} +- {se}"
                );
                worst = worst.max((mean - 1.0).abs());
            }
        }
    }
    // And a control that can fail: a grey base loses energy.
    let (grey, se) = albedo(0.5, 1.5, 0.5, 0.6, 4000, 1);
    assert!(grey < 1.0 - 10.0 * se, "{grey} +- {se}");
    assert!(worst < 0.05, "{worst}");
}

#[test]
fn ior_one_is_a_bare_lambertian_base() {
    // No interface: each path reaches the base once and leaves, albedo rho exactly, and
    // the exit directions are Lambertian (mean cosine 2/3).
    let rho = 0.37;
    let coating = Coating::new(0.5, 1.0);
    let mut rng = Rng::new(&[7]);
    let (mut exits, mut cos_sum, mut n) = (0, 0.0, 0);
    for k in 0..20_000 {
        let mu = 0.1 + 0.9 * (k % 10) as f64 / 9.0;
        coating.trace(incident(mu), &[rho], u32::MAX, &mut rng, |_, dir, w| {
            // One visit of the base, no roulette (rho is above its threshold).
            assert!((w[0] - rho).abs() < 1e-15, "{}", w[0]);
            exits += 1;
            cos_sum += dir.z;
        });
        n += 1;
    }
    assert_eq!(exits, n);
    let mean_cos = cos_sum / n as f64;
    // Standard error of a cosine-distributed cosine: sqrt(1/2 - 4/9) / sqrt(20000).
    let se = (0.5f64 - 4.0 / 9.0).sqrt() / (n as f64).sqrt();
    assert!((mean_cos - 2.0 / 3.0).abs() < 4.0 * se, "{mean_cos}");
}

#[test]
fn first_event_is_the_interfaces_single_scattering() {
    // The walk cut after one interface event reflects exactly f_micro with the exact
    // dielectric Fresnel and height-correlated Smith G (quadrature, no noise): whatever
    // refracts needs a second event to leave.
    let rules = Rules::default();
    for (r, eta) in [(0.2, 1.5), (0.6, 1.33), (1.0, 2.5)] {
        for mu in [0.3, 0.9] {
            let exact = single_albedo(
                &rules,
                mu,
                r,
                &[Dielectric(eta)],
                &[Geometry::SmithCorrelated],
            )[0][0];
            let coating = Coating::new(r, eta);
            let mut rng = Rng::new(&[3]);
            let n = 40_000;
            let (mut s, mut s2) = (0.0, 0.0);
            for _ in 0..n {
                let mut p = 0.0;
                coating.trace(incident(mu), &[0.8], 1, &mut rng, |order, _, w| {
                    assert_eq!(order, 1);
                    p += w[0];
                });
                s += p;
                s2 += p * p;
            }
            let mean = s / n as f64;
            let se = ((s2 / n as f64 - mean * mean) / n as f64).sqrt();
            assert!(
                (mean - exact).abs() < 4.0 * se + 1e-6,
                "r {r} eta {eta} mu {mu}: {mean} +- {se} vs {exact}"
            );
        }
    }
}

#[test]
fn smooth_limit_is_the_closed_form() {
    // At the roughness clamp (alpha 4e-4) the interface is all but smooth: the walk's
    // albedo is the closed form of a smooth coating over a Lambertian base (Fresnel in
    // and out, the internal reflections' series), within 3 standard errors plus 2e-3 for
    // the residual roughness (the smooth form's own figures change by less between
    // neighbouring angles).
    for eta in [1.33, 1.5, 2.0] {
        for rho in [0.0, 0.5, 0.8] {
            for mu in [0.3, 0.8] {
                let (mean, se) = albedo(0.02, eta, rho, mu, 20_000, 5);
                let exact = smooth_coating_albedo(mu, eta, rho);
                assert!(
                    (mean - exact).abs() <= 3.0 * se + 2e-3,
                    "eta {eta} rho {rho} mu {mu}: {mean} +- {se} vs {exact}"
                );
            }
        }
    }
    // The closed form itself: lossless with a white base, F alone with a black one.
    for eta in IOR {
        assert!((smooth_coating_albedo(0.5, eta, 1.0) - 1.0).abs() < 1e-9);
        assert!(
            (smooth_coating_albedo(0.5, eta, 0.0) - fresnel_dielectric(0.5, eta)).abs() < 1e-12
        );
    }
}

/// The model's specular albedo of a coating: single scattering with the exact dielectric
/// Fresnel (quadrature) plus the Kulla-Conty term with the exact Fresnel's average,
/// `E_F(mu) + f_add (1 - E(mu))`, height-correlated Smith throughout.
fn e_spec(rules: &Rules, mu: f64, r: f64, eta: f64) -> f64 {
    let g = Geometry::SmithCorrelated;
    let single = single_albedo(rules, mu, r, &[Dielectric(eta)], &[g])[0][0];
    let e_avg = crate::lut::e_avg_reference(r, g);
    let f_add = crate::brdf::f_add_accurate(f_avg_dielectric(eta), e_avg);
    single + f_add * (1.0 - crate::lut::e_reference(mu, r, g))
}

/// `2 int_0^1 E_spec(mu) mu dmu` by Gauss-Legendre in `mu`.
fn e_spec_avg(rules: &Rules, r: f64, eta: f64) -> f64 {
    let (x, w) = crate::lut::gauss_legendre_unit(24);
    x.iter()
        .zip(&w)
        .map(|(&mu, wk)| 2.0 * wk * mu * e_spec(rules, mu, r, eta))
        .sum()
}

#[test]
fn layering_forms_in_the_white_furnace() {
    // A white base under a lossless coating: the view-only, reciprocal and physical forms
    // return what the specular lobe does not (E_spec(mu_o) + int f_base mu_i dw = 1, the
    // integral in closed form: 2 pi int g(mu) mu dmu over a form's (1 - E_spec(mu_i))
    // factor is (1 - E_spec_avg)); the constant one does not. Reciprocity: the two
    // reciprocal forms are symmetric in the directions, the view-only one is not.
    use crate::brdf::{
        f_base_constant, f_base_physical, f_base_reciprocal, f_base_view_only, substrate_albedo,
    };
    use std::f64::consts::PI;
    let rules = Rules::default();
    for (r, eta) in [(0.15, 1.5), (0.6, 1.33), (1.0, 2.5)] {
        let avg = e_spec_avg(&rules, r, eta);
        for mu in [0.2, 0.7] {
            let e_o = e_spec(&rules, mu, r, eta);
            // int (1 - e_i) mu_i dw_i / pi = 1 - avg, so each form's integral is its
            // factor in front of (1 - e_i) times pi (1 - avg).
            let over = |f_with_e_i_zero: f64| f_with_e_i_zero * PI * (1.0 - avg);
            let view_only = e_o + f_base_view_only(1.0, e_o) * PI;
            let reciprocal = e_o + over(f_base_reciprocal(1.0, e_o, 0.0, avg));
            let physical = e_o + over(f_base_physical(1.0, e_o, 0.0, avg, eta));
            for (name, total) in [
                ("view-only", view_only),
                ("reciprocal", reciprocal),
                ("physical", physical),
            ] {
                assert!(
                    (total - 1.0).abs() < 1e-12,
                    "{name} r {r} eta {eta} mu {mu}: {total}"
                );
            }
            let constant = e_o + f_base_constant(1.0, f_avg_dielectric(eta)) * PI;
            assert!(
                (constant - 1.0).abs() > 1e-3,
                "constant r {r} mu {mu}: {constant}"
            );
            // The physical form of the substrate that looks like `apparent` is the
            // reciprocal form of `apparent`.
            for apparent in [0.2, 0.8] {
                let rho = substrate_albedo(apparent, avg, eta);
                let (a, b) = (e_o, e_spec(&rules, 0.5, r, eta));
                let phys = f_base_physical(rho, a, b, avg, eta);
                let reci = f_base_reciprocal(apparent, a, b, avg);
                assert!((phys - reci).abs() < 1e-12 * reci.max(1.0), "{phys} {reci}");
                assert!((f_base_physical(rho, b, a, avg, eta) - phys).abs() < 1e-15);
            }
            assert!(
                (f_base_view_only(1.0, e_o) - f_base_view_only(1.0, 0.3)).abs() > 1e-6
                    || (e_o - 0.3).abs() < 1e-6
            );
        }
    }
}

#[test]
fn physical_form_against_the_walk() {
    // The model's albedo of a plastic (the coating's E_spec plus the physical form's
    // diffuse light) against the walk through the same coating (IOR 1.5). At roughness
    // 0.15, where the coating's own multiple scattering is small, within 5 % (the
    // materials goal's figure, here on albedos; measured: at most 1.0 %) for bases from
    // 0.1 to 0.8; rougher, where the Kulla-Conty term stands in for the dielectric
    // interface's multiple scattering, at least 4x closer than today's constant form
    // (measured: 5.4 % at worst, against 1.2x to 1.7x too bright). The report is printed
    // (`cargo test --release --test suite -- coating::physical --nocapture`).
    use crate::brdf::f_avg_schlick;
    let rules = Rules::default();
    let eta = 1.5;
    let mut report = String::new();
    for r in [0.15, 0.5, 0.9] {
        let avg = e_spec_avg(&rules, r, eta);
        let f_in = crate::brdf::coating_inside_reflectance(avg, eta);
        for rho in [0.8, 0.5, 0.3, 0.1] {
            for mu in [0.3, 0.6, 0.9] {
                let e_o = e_spec(&rules, mu, r, eta);
                let physical = e_o + (1.0 - e_o) * rho * (1.0 - f_in) / (1.0 - rho * f_in);
                let constant = e_o + rho * (1.0 - f_avg_schlick(0.04));
                let (truth, se) = albedo(r, eta, rho, mu, 40_000, 11);
                let rel = (physical - truth).abs() / truth;
                report += &format!(
                    "roughness {r} rho {rho} mu {mu}: truth {truth:.4} +- {se:.4}, physical \
                     {physical:.4} ({:+.2} %), constant {constant:.4} ({:.3}x)\n",
                    100.0 * (physical - truth) / truth,
                    constant / truth
                );
                if r == 0.15 {
                    assert!(rel < 0.05, "{report}");
                } else {
                    assert!(4.0 * rel < (constant - truth).abs() / truth, "{report}");
                }
            }
        }
    }
    eprintln!("{report}");
}

#[test]
fn next_event_estimation_integrates_to_the_albedo() {
    // The light estimator's f(wi, l) mu_l integrated over every direction outside (one
    // drawn uniformly on the hemisphere per walk) is the albedo that the exits count: two
    // estimators of one number, within 4 combined standard errors.
    use std::f64::consts::TAU;
    for (r, eta, rho, mu) in [
        (0.5, 1.5, 0.6, 0.7),
        (0.8, 2.0, 0.9, 0.3),
        (0.3, 1.33, 0.3, 0.9),
    ] {
        let coating = Coating::new(r, eta);
        let mut rng = Rng::new(&[13]);
        let n = 40_000;
        let (mut a, mut a2, mut b, mut b2) = (0.0, 0.0, 0.0, 0.0);
        for _ in 0..n {
            let mut exit = 0.0;
            let mut draws = Rng::new(&[rng.next_u64()]);
            let z = draws.uniform();
            let phi = TAU * draws.uniform();
            let s = (1.0 - z * z).sqrt();
            let l = DVec3::new(s * phi.cos(), s * phi.sin(), z);
            let mut towards = [[0.0; MAX_CHANNELS]; 1];
            coating.estimate(
                incident(mu),
                &[rho],
                &[l],
                &mut rng,
                &mut towards,
                |_, _, w| exit += w[0],
            );
            let nee = towards[0][0] * TAU;
            a += exit;
            a2 += exit * exit;
            b += nee;
            b2 += nee * nee;
        }
        let nf = n as f64;
        let (ma, mb) = (a / nf, b / nf);
        let se = ((a2 / nf - ma * ma) / nf + (b2 / nf - mb * mb) / nf).sqrt();
        assert!(
            (ma - mb).abs() < 4.0 * se,
            "r {r} eta {eta} rho {rho} mu {mu}: exits {ma} nee {mb} +- {se}"
        );
    }
}

#[test]
fn next_event_estimation_meets_the_smooth_closed_form() {
    // Smooth coating, light away from the mirror direction: the only light that reaches
    // the eye went through the base, and the smooth closed form gives it:
    // rho (1 - F(mu_i)) (1 - F(mu_o)) / (pi eta^2 (1 - rho F_in)) mu_i per unit radiance.
    use std::f64::consts::PI;
    let (eta, rho) = (1.5, 0.5);
    let f_in = crate::brdf::f_avg_inside(eta);
    let coating = Coating::new(0.02, eta);
    for (mu_o, mu_i) in [(0.8f64, 0.5f64), (0.4, 0.9)] {
        // Out of the plane of incidence (azimuth 73 degrees from the mirror side).
        let sin_i = (1.0 - mu_i * mu_i).sqrt();
        let phi = 73f64.to_radians();
        let l = DVec3::new(sin_i * phi.cos(), sin_i * phi.sin(), mu_i);
        let mut rng = Rng::new(&[17]);
        let n = 40_000;
        let (mut s, mut s2) = (0.0, 0.0);
        for _ in 0..n {
            let mut towards = [[0.0; MAX_CHANNELS]; 1];
            coating.estimate(
                incident(mu_o),
                &[rho],
                &[l],
                &mut rng,
                &mut towards,
                |_, _, _| {},
            );
            let v = towards[0][0];
            s += v;
            s2 += v * v;
        }
        let mean = s / n as f64;
        let se = ((s2 / n as f64 - mean * mean) / n as f64).sqrt();
        let (fo, fi) = (fresnel_dielectric(mu_o, eta), fresnel_dielectric(mu_i, eta));
        let exact = rho * (1.0 - fi) * (1.0 - fo) / (PI * eta * eta * (1.0 - rho * f_in)) * mu_i;
        // 3 standard errors, plus 1 % for the residual roughness's lobe shape.
        assert!(
            (mean - exact).abs() < 3.0 * se + 0.01 * exact,
            "mu_o {mu_o} mu_i {mu_i}: {mean} +- {se} vs {exact}"
        );
    }
}
