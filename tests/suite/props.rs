//! Property tests (proptest) of the whole BRDF as the renderer evaluates it (`cpu::shade`,
//! the f64 model with the tables read as the shader reads them) over random
//! `(v, l, n, roughness, F0)`, with extra weight on the edges: grazing and below-horizon
//! directions, roughness 0 and 1, F0 0 and 1. Properties: finite, non-negative, reciprocal,
//! and with F = 1 the compensated BRDF keeps the furnace within its tolerance.
//!
//! Runs are deterministic (a fixed seed), so a failure reproduces; proptest shrinks it.
//! The f32 (shader) side of the same functions is in `gpu_stress.rs`.

use std::f64::consts::PI;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::OnceLock;

use glam::DVec3;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestRng, TestRunner};
use shadeballs::brdf::{f_ms, f_ms_norm, FAvgForm, Geometry, ROUGHNESS_MIN};
use shadeballs::cpu::shade;
use shadeballs::lut::TableSet;
use shadeballs::lut::{adaptive, bake, e_reference, BakeConfig, Tables};
use shadeballs::scene::{Ball, Light, Material, Model, Scene};

/// The default tables of each geometry, baked once for every test here.
fn tables(g: Geometry) -> &'static Tables {
    static T: OnceLock<Vec<Tables>> = OnceLock::new();
    let all = T.get_or_init(|| {
        Geometry::ALL
            .iter()
            .map(|&geometry| {
                bake(&BakeConfig {
                    geometry,
                    ..BakeConfig::default()
                })
            })
            .collect()
    });
    &all[Geometry::ALL.iter().position(|&x| x == g).unwrap()]
}

/// Runs `test` on `cases` values of `strategy` with a fixed seed, no regression files.
pub fn run<S: Strategy>(
    cases: u32,
    strategy: S,
    test: impl Fn(S::Value) -> Result<(), TestCaseError>,
) where
    S::Value: std::fmt::Debug,
{
    let config = Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    };
    let rng = TestRng::deterministic_rng(RngAlgorithm::ChaCha);
    if let Err(e) = TestRunner::new_with_rng(config, rng).run(&strategy, test) {
        panic!("{e}");
    }
}

/// A cosine: anywhere in [-1, 1], or at / near the horizon, or at the pole.
fn cosine() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -1.0..=1.0f64,
        1 => 0.0..1e-6f64,
        1 => -1e-6..0.0f64,
        1 => Just(0.0),
        1 => Just(1.0),
    ]
}

fn unit_interval() -> impl Strategy<Value = f64> {
    prop_oneof![4 => 0.0..=1.0f64, 1 => Just(0.0), 1 => Just(1.0), 1 => 0.0..ROUGHNESS_MIN]
}

/// A unit vector at cosine `mu` from `n`, azimuth `phi`.
fn around(n: DVec3, mu: f64, phi: f64) -> DVec3 {
    let (t, b) = n.any_orthonormal_pair();
    let s = (1.0 - mu * mu).max(0.0).sqrt();
    (n * mu + t * (s * phi.cos()) + b * (s * phi.sin())).normalize()
}

/// One random configuration: (n, v, l, roughness, F0, geometry index, games202 form?).
#[derive(Clone, Debug)]
pub struct Sample {
    n: DVec3,
    v: DVec3,
    l: DVec3,
    roughness: f64,
    f0: f64,
    geometry: usize,
    games202: bool,
}

fn sample() -> impl Strategy<Value = Sample> {
    let n = (-1.0..=1.0f64, 0.0..(2.0 * PI)).prop_map(|(z, p)| around(DVec3::Z, z, p));
    (
        n,
        (cosine(), 0.0..(2.0 * PI)),
        (cosine(), 0.0..(2.0 * PI)),
        unit_interval(),
        unit_interval(),
        0..3usize,
        any::<bool>(),
    )
        .prop_map(
            |(n, (mo, po), (mi, pi), roughness, f0, geometry, games202)| Sample {
                n,
                v: around(n, mo, po),
                l: around(n, mi, pi),
                roughness,
                f0,
                geometry,
                games202,
            },
        )
}

/// Outgoing radiance towards `v` at normal `n` from one unit light from `l` (no
/// environment), by the renderer's own `shade`: `f_r (v, l) mu_i` per channel.
fn radiance(s: &Sample, v: DVec3, l: DVec3) -> DVec3 {
    let g = Geometry::ALL[s.geometry];
    let ball = Ball {
        center: DVec3::ZERO,
        radius: 1.0,
        roughness: s.roughness,
        material: Material::metal(DVec3::splat(s.f0)),
        model: Model::KullaConty,
        label: None,
    };
    let scene = Scene {
        balls: Vec::new(),
        lights: vec![Light::new(l, DVec3::ONE)],
        environment: DVec3::ZERO,
        ..Scene::reference()
    };
    let form = if s.games202 {
        FAvgForm::Games202
    } else {
        FAvgForm::Accurate
    };
    shade(
        &scene,
        &ball,
        s.n,
        v,
        &TableSet::full(tables(g).clone()),
        form,
        g,
    )
}

/// Batches per case: proptest shrinks a failing batch to its smallest failing sample.
const BATCH: usize = 1000;
const CASES: u32 = 1000;

#[test]
fn brdf_is_finite_non_negative_and_reciprocal_over_a_million_random_evaluations() {
    let evaluations = AtomicU64::new(0);
    run(CASES, proptest::collection::vec(sample(), BATCH), |batch| {
        for s in &batch {
            let (mu_o, mu_i) = (s.n.dot(s.v), s.n.dot(s.l));
            // f_r (v, l) mu_i and f_r (l, v) mu_o: the same BRDF value times each cosine.
            let forward = radiance(s, s.v, s.l);
            let backward = radiance(s, s.l, s.v);
            evaluations.fetch_add(2, Ordering::Relaxed);
            for c in [forward, backward] {
                prop_assert!(c.is_finite() && c.min_element() >= 0.0, "{c:?} for {s:?}");
            }
            if mu_o > 0.0 && mu_i > 0.0 {
                let (f1, f2) = (forward / mu_i, backward / mu_o);
                let scale = f1.abs().max(f2.abs()).max_element().max(1e-300);
                let diff = (f1 - f2).abs().max_element() / scale;
                // v.h and l.h are equal but rounded apart by ~1e-16. Schlick's F depends
                // on 1 - v.h, so that is a large relative error when v and l are nearly
                // opposite (v.h -> 0) or nearly equal (1 - v.h -> 0, where F0 = 0 makes F
                // tiny): the tolerance follows that conditioning.
                let v_dot_h = s.v.dot((s.v + s.l).normalize());
                let tolerance = 1e-12
                    + 1e-14 / v_dot_h.abs().max(1e-300)
                    + 1e-14 / (1.0 - v_dot_h).abs().max(1e-300);
                prop_assert!(
                    diff <= tolerance,
                    "not reciprocal: {f1:?} vs {f2:?} ({diff:.1e}) for {s:?}"
                );
            } else {
                // Either direction at or below the horizon: no light reaches the eye.
                prop_assert!(forward == DVec3::ZERO && backward == DVec3::ZERO, "{s:?}");
            }
        }
        Ok(())
    });
    let n = evaluations.into_inner();
    println!(
        "random BRDF evaluations: {n}, 0 non-finite or negative, all reciprocal within 1e-12 \
         plus the rounding of v.h"
    );
    assert!(n >= 1_000_000, "{n}");
}

/// With F = 1 (`F_avg = 1`, so `f_add = 1`) the compensated BRDF reflects everything:
/// `int (f_micro + f_ms) mu_i dw_i = E(mu_o) + 2 pi int f_ms mu_i dmu_i = 1`. `E` is the
/// precise reference (the integral of `f_micro`, checked against an independent 2-D
/// integration in `lut.rs`); the lobe uses the tables as the shader reads them.
#[test]
fn compensated_brdf_with_f_equal_1_keeps_the_furnace_at_random_points() {
    const FURNACE_TOLERANCE: f64 = 1e-3;
    let worst = std::sync::Mutex::new(0.0f64);
    run(
        300,
        (cosine(), unit_interval(), 0..3usize),
        |(mu_o, roughness, geometry)| {
            let g = Geometry::ALL[geometry];
            let t = tables(g);
            let mu_o = mu_o.clamp(0.0, 1.0);
            let r = roughness as f32;
            let loss_avg = t.lut_loss_avg(r) as f64;
            let lobe = adaptive(
                &|mu: f64| {
                    2.0 * PI
                        * f_ms(
                            t.lut_loss(mu_o as f32, r) as f64,
                            t.lut_loss(mu as f32, r) as f64,
                            f_ms_norm(loss_avg),
                        )
                        * mu
                },
                0.0,
                1.0,
                1e-12,
            );
            let total = e_reference(mu_o, roughness, g) + lobe;
            let err = (total - 1.0).abs();
            let mut w = worst.lock().unwrap();
            *w = w.max(err);
            prop_assert!(
                err <= FURNACE_TOLERANCE,
                "{g} (mu, r) = ({mu_o}, {roughness}): {total}"
            );
            Ok(())
        },
    );
    println!(
        "furnace at 300 random (mu_o, roughness, G): max |energy - 1| = {:.2e}",
        worst.into_inner().unwrap()
    );
}

/// Table reads for any f32 roughness (NaN and infinities included) and any non-NaN mu.
#[test]
fn table_reads_are_in_range_for_any_f32() {
    run(
        20_000,
        (any::<f32>(), any::<f32>(), 0..3usize),
        |(mu, r, g)| {
            let mu = if mu.is_nan() { 0.5 } else { mu };
            let t = tables(Geometry::ALL[g]);
            for v in [
                t.lut_loss(mu, r),
                t.lut_e(mu, r),
                t.lut_loss_avg(r),
                t.lut_e_avg(r),
            ] {
                prop_assert!((0.0..=1.0).contains(&v), "({mu}, {r}) read {v}");
            }
            Ok(())
        },
    );
}
