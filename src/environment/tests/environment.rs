//! Environment maps (issue 15, the map side): the direction convention, texel solid angles,
//! rotation, the `.hdr`/`.exr` loader and writer and their bad-input rules, the built-ins,
//! the scene file's `[environment]`, `background` and `ibl_term`, and the `environment`
//! subcommand.

use std::f64::consts::PI;

use std::path::Path;

use std::sync::Arc;

use glam::{DVec2, DVec3};

use crate::environment::{
    self, builtin, direction_to_uv, uv_to_direction, Background, Builtin, EnvMap, Environment,
    IblTerm, MapStats, Source,
};

use crate::scene::{self, Scene};

use crate::pixels::temp_dir;

const BALL: &str = "[[ball]]\ngrid = [0, 0]\nradius = 35\nroughness = 0.5\nmaterial = { kind = \"metal\", f0 = [1, 1, 1] }\n";

/// A `w x h` map, black but texel `(i, j)` = `c`.
fn one_texel(w: u32, h: u32, i: u32, j: u32, c: f32) -> EnvMap {
    let mut t = vec![[0.0f32; 3]; (w * h) as usize];
    t[(j * w + i) as usize] = [c, c, c];
    EnvMap::new(w, h, t).unwrap()
}

fn centre(map: &EnvMap, i: u32, j: u32) -> DVec2 {
    DVec2::new(
        (i as f64 + 0.5) / map.width() as f64,
        (j as f64 + 0.5) / map.height() as f64,
    )
}

fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).abs().max_element() <= tol
}

/// A map with a smooth, distinct value per texel (for round trips).
fn ramp(w: u32, h: u32) -> EnvMap {
    let t = (0..w * h)
        .map(|k| {
            let (i, j) = ((k % w) as f32, (k / w) as f32);
            [0.01 + i * 0.37, 0.5 + j * 1.3, 100.0 / (1.0 + i + j)]
        })
        .collect();
    EnvMap::new(w, h, t).unwrap()
}

#[test]
fn a_bright_texel_is_read_along_its_centres_direction() {
    let map = one_texel(16, 8, 11, 2, 5.0);
    let d = uv_to_direction(centre(&map, 11, 2));
    assert!(close(map.radiance(d), DVec3::splat(5.0), 1e-9));
    // The neighbouring texel's centre reads black.
    let d = uv_to_direction(centre(&map, 12, 2));
    assert!(close(map.radiance(d), DVec3::ZERO, 1e-9));
}

#[test]
fn uv_convention_puts_minus_z_in_the_middle_and_plus_y_at_the_top() {
    let uv = direction_to_uv(-DVec3::Z);
    assert!((uv - DVec2::new(0.5, 0.5)).length() < 1e-12, "{uv}");
    assert!(direction_to_uv(DVec3::Y).y.abs() < 1e-12);
    assert!((direction_to_uv(-DVec3::Y).y - 1.0).abs() < 1e-12);
    let x = direction_to_uv(DVec3::X);
    assert!((x - DVec2::new(0.75, 0.5)).length() < 1e-12, "{x}");
    assert!(uv_to_direction(DVec2::new(0.5, 0.5)).distance(-DVec3::Z) < 1e-12);
    assert!(uv_to_direction(DVec2::new(0.3, 0.0)).distance(DVec3::Y) < 1e-12);
}

#[test]
fn direction_to_uv_inverts_uv_to_direction() {
    for a in 1..40 {
        for b in 1..20 {
            let uv = DVec2::new(a as f64 / 40.0, b as f64 / 20.0);
            let back = direction_to_uv(uv_to_direction(uv));
            assert!((back - uv).length() < 1e-9, "{uv} -> {back}");
            assert!((uv_to_direction(uv).length() - 1.0).abs() < 1e-12);
        }
    }
}

#[test]
fn texel_solid_angles_sum_to_four_pi() {
    for (w, h) in [(2, 1), (16, 8), (1024, 512)] {
        let map = EnvMap::uniform(DVec3::ONE, w, h);
        let sum: f64 = (0..h).map(|j| map.texel_solid_angle(j) * w as f64).sum();
        assert!((sum - 4.0 * PI).abs() < 1e-9, "{w}x{h}: {sum}");
        // Rows near the poles are smaller than rows at the equator.
        if h >= 8 {
            assert!(map.texel_solid_angle(0) < map.texel_solid_angle(h / 2));
        }
    }
}

#[test]
fn bilinear_of_a_constant_map_is_the_constant() {
    let c = DVec3::new(0.25, 1.5, 3.0);
    let map = EnvMap::uniform(c, 8, 4);
    for a in -3..=43 {
        for b in -2..=22 {
            let uv = DVec2::new(a as f64 / 40.0, b as f64 / 20.0);
            assert!(close(map.bilinear(uv), c, 1e-6), "{uv}");
        }
    }
}

#[test]
fn rotation_turns_a_feature_at_minus_z_towards_minus_x() {
    // A 4x2 map has texel centres at azimuths -135, -45, 45, 135 (u = 1/8, 3/8, ...): a
    // 64x32 map with a bright block around -z is easier to read.
    let (w, h) = (64, 32);
    let mut t = vec![[0.0f32; 3]; (w * h) as usize];
    for j in 14..18 {
        for i in 30..34 {
            t[(j * w + i) as usize] = [1.0, 1.0, 1.0];
        }
    }
    let map = Arc::new(EnvMap::new(w, h, t).unwrap());
    let env = |rotation_deg| Environment {
        source: Source::Builtin(Builtin::White),
        map: map.clone(),
        rotation_deg,
        intensity: 2.0,
    };
    assert!(close(env(0.0).radiance(-DVec3::Z), DVec3::splat(2.0), 1e-9));
    let turned = env(90.0);
    assert!(turned.to_map(-DVec3::X).distance(-DVec3::Z) < 1e-12);
    assert!(close(turned.radiance(-DVec3::X), DVec3::splat(2.0), 1e-9));
    assert!(close(turned.radiance(-DVec3::Z), DVec3::ZERO, 1e-9));
    assert!(close(turned.radiance(DVec3::X), DVec3::ZERO, 1e-9));
}

#[test]
fn exr_round_trips_exactly_and_hdr_within_rgbe_precision() {
    let dir = temp_dir("env-roundtrip");
    let map = ramp(32, 16);
    let exr = dir.join("ramp.exr");
    environment::save(&map, &exr).unwrap();
    let (back, stats) = environment::load(&exr).unwrap();
    assert_eq!(stats, MapStats::default());
    assert_eq!(back, map);
    let hdr = dir.join("ramp.hdr");
    environment::save(&map, &hdr).unwrap();
    let (back, _) = environment::load(&hdr).unwrap();
    assert_eq!((back.width(), back.height()), (32, 16));
    for (a, b) in map.texels().iter().zip(back.texels()) {
        for k in 0..3 {
            // RGBE shares one exponent: each channel is within 1 % of the largest.
            let largest = a.iter().cloned().fold(0.0f32, f32::max);
            assert!((a[k] - b[k]).abs() <= 0.01 * largest, "{a:?} vs {b:?}");
        }
    }
    // No temporary file is left beside them.
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    assert!(names.iter().all(|n| !n.contains(".tmp-")), "{names:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A `.hdr` whose magic names another program (`#?RGBE`, what Mitsuba and others write)
/// loads as the same map as with Radiance's own `#?RADIANCE`; a first line that is no
/// magic at all is still refused.
#[test]
fn hdr_with_an_rgbe_magic_line_loads() {
    let dir = temp_dir("env-rgbe");
    let map = ramp(32, 16);
    let radiance = dir.join("radiance.hdr");
    environment::save(&map, &radiance).unwrap();
    let bytes = std::fs::read(&radiance).unwrap();
    assert!(bytes.starts_with(b"#?RADIANCE\n"), "the writer's magic");
    let (want, _) = environment::load(&radiance).unwrap();
    for magic in [&b"#?RGBE\n"[..], b"#?Mitsuba 3\n"] {
        let other = dir.join("other.hdr");
        let mut renamed = magic.to_vec();
        renamed.extend_from_slice(&bytes[b"#?RADIANCE\n".len()..]);
        std::fs::write(&other, renamed).unwrap();
        let (got, _) = environment::load(&other)
            .unwrap_or_else(|e| panic!("{}: {e}", String::from_utf8_lossy(magic)));
        assert_eq!(got, want);
    }
    let bad = dir.join("bad.hdr");
    let mut renamed = b"P6 RADIANCE\n".to_vec();
    renamed.extend_from_slice(&bytes[b"#?RADIANCE\n".len()..]);
    std::fs::write(&bad, renamed).unwrap();
    assert!(environment::load(&bad).is_err());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The loader's error for `path`, checked to be one line naming the path.
fn load_error(path: &Path) -> String {
    let e = environment::load(path).expect_err("the map should be refused");
    let msg = e.to_string();
    println!("{msg}");
    assert!(msg.contains(&path.display().to_string()), "{msg}");
    assert!(!msg.contains('\n'), "{msg}");
    msg
}

#[test]
fn bad_map_files_are_one_clear_line_each() {
    let dir = temp_dir("env-bad");
    // Missing.
    let msg = load_error(&dir.join("missing.hdr"));
    assert!(msg.contains("No such file"), "{msg}");
    // Wrong extension.
    let png = dir.join("map.png");
    std::fs::write(&png, b"not used").unwrap();
    assert!(load_error(&png).contains(".hdr"));
    // A folder.
    let folder = dir.join("folder.exr");
    std::fs::create_dir_all(&folder).unwrap();
    assert!(load_error(&folder).contains("folder"));
    // Truncated: a valid .hdr cut in the middle of its pixels.
    let hdr = dir.join("whole.hdr");
    environment::save(&ramp(64, 32), &hdr).unwrap();
    let bytes = std::fs::read(&hdr).unwrap();
    let cut = dir.join("cut.hdr");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    assert!(load_error(&cut).contains("truncated"));
    // Garbage, as either format.
    for name in ["garbage.hdr", "garbage.exr"] {
        let p = dir.join(name);
        std::fs::write(&p, [0x5au8; 3000]).unwrap();
        let msg = load_error(&p);
        assert!(
            msg.contains("corrupt") || msg.contains("truncated"),
            "{msg}"
        );
    }
    // Not 2:1.
    let small = dir.join("three_by_two.exr");
    environment::save(&EnvMap::uniform(DVec3::ONE, 3, 2), &small).unwrap();
    let msg = load_error(&small);
    assert!(
        msg.contains("3x2") && msg.contains("twice the height"),
        "{msg}"
    );
    // A header claiming 16384x8192, with no pixels: the size error, nothing allocated.
    let huge = dir.join("huge.hdr");
    std::fs::write(
        &huge,
        b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8192 +X 16384\n\x02\x02",
    )
    .unwrap();
    let msg = load_error(&huge);
    assert!(
        msg.contains("16384x8192") && msg.contains("8192x4096"),
        "{msg}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn nan_infinite_and_negative_channels_are_clamped_and_counted() {
    let dir = temp_dir("env-nan");
    let (w, h) = (8u32, 4u32);
    let mut data = vec![0.5f32; (w * h * 3) as usize];
    data[0] = f32::NAN;
    data[1] = f32::NAN;
    data[5] = -2.0;
    data[9] = f32::INFINITY;
    data[10] = f32::NEG_INFINITY;
    data[20] = 7.0; // the largest finite value
    let image = image::Rgb32FImage::from_raw(w, h, data).unwrap();
    let path = dir.join("bad_values.exr");
    image.save(&path).unwrap();
    let (map, stats) = environment::load(&path).unwrap();
    assert_eq!(
        stats,
        MapStats {
            nan: 2,
            infinite: 2,
            negative: 1
        }
    );
    let t = map.texels();
    assert_eq!(t[0], [0.0, 0.0, 0.5]);
    assert_eq!(t[1][2], 0.0);
    assert_eq!(t[3], [7.0, 0.0, 0.5]);
    assert_eq!(t[6][2], 7.0);
    assert!(t.iter().flatten().all(|c| c.is_finite() && *c >= 0.0));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn built_ins_are_finite_non_negative_and_the_asked_size() {
    for b in Builtin::ALL {
        let map = b.generate(256);
        assert_eq!((map.width(), map.height()), (256, 128), "{b}");
        assert!(
            map.texels()
                .iter()
                .flatten()
                .all(|c| c.is_finite() && *c >= 0.0),
            "{b}"
        );
        let mean = builtin::mean_luminance(&map);
        println!("{b}: mean radiance {mean}");
        assert!((0.3..=2.0).contains(&mean), "{b}: mean {mean}");
        assert_eq!(b.name().parse::<Builtin>().unwrap(), b);
    }
    assert_eq!(Builtin::White.generate(7).width(), 6);
    assert_eq!(Builtin::White.generate(100_000).width(), 8192);
    let sky = Builtin::Sky.generate(512);
    assert!((builtin::mean_luminance(&sky) - 1.0).abs() < 1e-3);
}

#[test]
fn studio_key_light_outshines_its_gradient_and_lights_the_front_left() {
    let key = builtin::studio_key_direction();
    // Front (towards the camera, +z), left (-x) and up.
    assert!(key.z > 0.5 && key.x < -0.3 && key.y > 0.3, "{key}");
    let map = Builtin::Studio.generate(1024);
    let at_key = builtin::luminance(map.radiance(key));
    let gradient = builtin::luminance(builtin::studio_gradient(key));
    assert!(at_key > 50.0 * gradient, "{at_key} vs {gradient}");
    assert!((5.0..=20.0).contains(&at_key), "{at_key}");
    // Straight down and straight behind the camera are the dim gradient.
    assert!(builtin::luminance(map.radiance(-DVec3::Y)) < 0.05);
    assert!(builtin::luminance(map.radiance(DVec3::new(0.0, -0.3, 1.0).normalize())) < 0.1);
    // The edges are soft: between inside and outside the key there are in-between values.
    let row = map.height() / 3;
    let lums: Vec<f64> = (0..map.width())
        .map(|i| builtin::luminance(map.texel(i, row)))
        .collect();
    let middling = lums.iter().filter(|&&l| l > 1.0 && l < 10.0).count();
    assert!(middling >= 4, "{middling}");
}

#[test]
fn the_skys_brightest_texel_is_its_sun() {
    let map = Builtin::Sky.generate(1024);
    let (mut best, mut at) = (0.0, (0, 0));
    let mut zenith = 0.0;
    for j in 0..map.height() {
        for i in 0..map.width() {
            let l = builtin::luminance(map.texel(i, j));
            if l > best {
                best = l;
                at = (i, j);
            }
        }
    }
    let uv = DVec2::new(
        (at.0 as f64 + 0.5) / map.width() as f64,
        (at.1 as f64 + 0.5) / map.height() as f64,
    );
    let angle = uv_to_direction(uv)
        .dot(builtin::sun_direction())
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees();
    assert!(
        angle <= builtin::SUN_RADIUS_DEG + 0.5,
        "{angle} degrees off"
    );
    for i in 0..map.width() {
        zenith += builtin::luminance(map.texel(i, 0)) / map.width() as f64;
    }
    let ratio = best / zenith;
    println!("sun / zenith {ratio}");
    assert!((50.0..=250.0).contains(&ratio), "{ratio}");
    // The sky is blue at the zenith, the ground dim and grey below the horizon.
    let z = map.radiance(DVec3::Y);
    assert!(z.z > z.x, "{z}");
    let ground = map.radiance(-DVec3::Y);
    assert!(
        builtin::luminance(ground) < builtin::luminance(z),
        "{ground}"
    );
}

/// The guided search both shaders run (`luminance_partition`: a CDF's guide, then a search
/// between two of its entries) finds the index a binary search over the whole CDF finds,
/// for uniform numbers on a grid finer than any bucket and at and beside every value of the
/// tables: the Monte Carlo's and the lobe mode's tables of the studio and the sky (long runs
/// of zero-weight texels in the latter) and of a small map whose sides are not powers of
/// two, with black rows.
#[test]
fn the_guided_search_finds_what_a_binary_search_finds() {
    use crate::environment::sampler::{luminance_partition, LuminanceCdf};
    // 12 x 6: rows 2 and 3 black (the sampler's weights take each texel's neighbours).
    let mut texels = vec![[0.0; 3]; 72];
    texels[1] = [2.0; 3];
    texels[4] = [5.0; 3];
    texels[5] = [0.1; 3];
    texels[5 * 12 + 7] = [1.0; 3];
    let small = Environment {
        map: Arc::new(EnvMap::new(12, 6, texels).unwrap()),
        ..Environment::builtin(Builtin::White)
    };
    let check = |what: &str, cdf: &[f32], guide: &[f32]| -> usize {
        let mut xs: Vec<f32> = (0..1 << 14).map(|i| i as f32 / (1 << 14) as f32).collect();
        for &c in cdf {
            xs.extend([c.next_down(), c, c.next_up()]);
        }
        let mut checked = 0;
        for x in xs.into_iter().filter(|x| (0.0..1.0).contains(x)) {
            let expected = cdf.partition_point(|&c| c <= x);
            assert_eq!(
                luminance_partition(cdf, guide, x),
                expected,
                "{what}: x = {x:e}"
            );
            checked += 1;
        }
        checked
    };
    let mut tables = 0;
    for env in [
        Environment::builtin(Builtin::Studio),
        Environment::builtin(Builtin::Sky),
        small,
    ] {
        let (w, h) = (env.map.width(), env.map.height());
        let start = std::time::Instant::now();
        let compensated = LuminanceCdf::compensated(&env);
        println!(
            "{w}x{h}: the lobe mode's tables and guides in {:.1} ms",
            start.elapsed().as_secs_f64() * 1e3
        );
        for (kind, cdf) in [
            ("plain", LuminanceCdf::of(&env)),
            ("compensated", compensated),
        ] {
            let cdf = cdf.unwrap();
            let what = format!("{w}x{h} {kind}");
            if w == 12 {
                for j in [2, 3] {
                    assert!(cdf.row(j).0.iter().all(|&c| c == 0.0), "{what}: row {j}");
                }
            }
            let mut checked = check(
                &format!("{what}, marginal"),
                &cdf.marginal,
                &cdf.marginal_guide,
            );
            for j in 0..h as usize {
                let (row, guide) = cdf.row(j);
                checked += check(&format!("{what}, row {j}"), row, guide);
            }
            println!("{what}: {checked} searches agree");
            tables += 1;
        }
    }
    assert_eq!(tables, 6);
}

/// The lobe mode's tables (`LuminanceCdf::compensated`) are the Monte Carlo's less their
/// mean: a texel's probability is `max(p - m, 0)` renormalised, `p` its probability in
/// `LuminanceCdf::of`'s tables and `m` the mean's share of it (its solid angle over the
/// sphere's); the dim texels are left to the other strategies, the bright ones kept in
/// their proportions. A constant map has no tables either way.
#[test]
fn the_lobe_modes_tables_keep_what_stands_above_the_mean() {
    use crate::environment::sampler::LuminanceCdf;
    for b in [Builtin::Studio, Builtin::Sky] {
        let env = Environment::builtin(b);
        let plain = LuminanceCdf::of(&env).unwrap();
        let kept = LuminanceCdf::compensated(&env).unwrap();
        let (w, h) = (plain.width as usize, plain.height as usize);
        assert_eq!((kept.width as usize, kept.height as usize), (w, h));
        let omega: Vec<f64> = (0..h)
            .map(|j| env.map.texel_solid_angle(j as u32))
            .collect();
        let sphere = w as f64 * omega.iter().sum::<f64>();
        let above: Vec<f64> = (0..w * h)
            .map(|k| (f64::from(plain.texel[k]) - omega[k / w] / sphere).max(0.0))
            .collect();
        let sum: f64 = above.iter().sum();
        // Each kept probability against its share of what stands above the mean, the
        // error relative to the texel's own probability (`above` is a difference of f32
        // probabilities, exact to their rounding, not to its own size).
        let mut worst = 0.0f64;
        for (k, &a) in above.iter().enumerate() {
            let p = f64::from(kept.texel[k]);
            if a == 0.0 {
                assert!(p == 0.0, "{b}: texel {k} at or below the mean kept at {p}");
            } else {
                worst = worst.max((p * sum - a).abs() / f64::from(plain.texel[k]));
            }
        }
        let total: f64 = kept.texel.iter().map(|&p| f64::from(p)).sum();
        let share = above.iter().filter(|&&a| a > 0.0).count() as f64 / (w * h) as f64;
        println!(
            "{b}: {:.1} % of the texels kept, {:.1} % of the luminance above the mean, \
             worst relative error {worst:.1e}",
            100.0 * share,
            100.0 * sum
        );
        assert!(
            worst < 1e-5,
            "{b}: kept texels off their proportion by {worst}"
        );
        assert!(
            (total - 1.0).abs() < 1e-4,
            "{b}: probabilities sum to {total}"
        );
        assert!(share > 0.0 && share < 1.0, "{b}: {share}");
        assert_eq!(kept.marginal.last().copied(), Some(1.0), "{b}");
    }
    let constant = Environment {
        map: Arc::new(EnvMap::new(4, 2, vec![[0.5; 3]; 8]).unwrap()),
        ..Environment::builtin(Builtin::White)
    };
    assert!(LuminanceCdf::compensated(&constant).is_none());
}

#[test]
fn generating_a_built_in_is_fast() {
    for b in Builtin::ALL {
        let _ = b.generate(64); // starts rayon's threads
        let start = std::time::Instant::now();
        let map = b.generate(1024);
        let ms = start.elapsed().as_secs_f64() * 1e3;
        println!("{b}: {ms:.1} ms");
        assert_eq!(map.width(), 1024);
        // The aim is well under 100 ms; the bound allows a loaded 2-core machine.
        assert!(ms < 400.0, "{b}: {ms} ms");
    }
}

fn parse(text: &str, path: &Path) -> Result<Scene, String> {
    scene::parse(text, path).map_err(|e| e.to_string())
}

fn scene_error(text: &str) -> String {
    let msg = parse(text, Path::new("bad.toml")).expect_err("the scene should be refused");
    println!("{msg}");
    assert!(msg.contains("bad.toml") && msg.contains("line") && msg.contains("column"));
    msg
}

#[test]
fn scene_environment_takes_exactly_one_source() {
    for body in [
        "map = \"x.hdr\"\nbuiltin = \"sky\"\n",
        "radiance = [1, 1, 1]\nbuiltin = \"sky\"\n",
        "radiance = [1, 1, 1]\nmap = \"x.exr\"\n",
        "intensity = 2\n",
    ] {
        let msg = scene_error(&format!("[environment]\n{body}{BALL}"));
        assert!(msg.contains("exactly one of"), "{msg}");
        assert!(msg.contains("line 1, column 1"), "{msg}");
    }
    let msg = scene_error(&format!("[environment]\nbuiltin = \"forest\"\n{BALL}"));
    assert!(msg.contains("studio, sky, white"), "{msg}");
    assert!(msg.contains("line 2"), "{msg}");
    let msg = scene_error(&format!(
        "[environment]\nbuiltin = \"sky\"\nintensity = -1\n{BALL}"
    ));
    assert!(msg.contains("intensity"), "{msg}");
    let msg = scene_error(&format!(
        "[environment]\nbuiltin = \"sky\"\nrotation_deg = nan\n{BALL}"
    ));
    assert!(msg.contains("rotation_deg"), "{msg}");
}

#[test]
fn scene_environment_builtin_radiance_and_intensity() {
    let s = parse(
        &format!(
            "[environment]\nbuiltin = \"studio\"\nrotation_deg = -30\nintensity = 0.5\n{BALL}"
        ),
        Path::new("s.toml"),
    )
    .unwrap();
    assert_eq!(s.environment, DVec3::ZERO);
    let env = s.environment_map.expect("a map");
    assert_eq!(env.source, Source::Builtin(Builtin::Studio));
    assert_eq!((env.rotation_deg, env.intensity), (-30.0, 0.5));
    assert_eq!(env.map.width(), builtin::DEFAULT_BUILTIN_WIDTH);
    assert_eq!(
        *env.map,
        Builtin::Studio.generate(builtin::DEFAULT_BUILTIN_WIDTH)
    );
    let s = parse(
        &format!("[environment]\nradiance = [1, 2, 3]\nintensity = 2\n{BALL}"),
        Path::new("s.toml"),
    )
    .unwrap();
    assert_eq!(s.environment, DVec3::new(2.0, 4.0, 6.0));
    assert!(s.environment_map.is_none());
    // Defaults.
    let s = parse(BALL, Path::new("s.toml")).unwrap();
    assert_eq!(s.background, Background::Environment);
    assert_eq!(s.term(), IblTerm::KullaConty);
    assert!(s.environment_map.is_none());
}

#[test]
fn scene_background_and_ibl_term() {
    let bg = |v: &str| {
        parse(&format!("background = {v}\n{BALL}"), Path::new("s.toml")).map(|s| s.background)
    };
    assert_eq!(bg("\"black\"").unwrap(), Background::Black);
    assert_eq!(bg("\"environment\"").unwrap(), Background::Environment);
    assert_eq!(
        bg("[0.1, 0.2, 3]").unwrap(),
        Background::Colour(DVec3::new(0.1, 0.2, 3.0))
    );
    for bad in ["\"white\"", "[1, 2]", "[1, -1, 1]", "3"] {
        let msg = scene_error(&format!("background = {bad}\n{BALL}"));
        assert!(msg.contains("background"), "{bad}: {msg}");
    }
    for t in IblTerm::ALL {
        let s = parse(&format!("ibl_term = \"{t}\"\n{BALL}"), Path::new("s.toml")).unwrap();
        assert_eq!(s.term(), t);
    }
    let msg = scene_error(&format!("ibl_term = \"split-sum\"\n{BALL}"));
    assert!(msg.contains("turquin, fdez-aguera, kulla-conty"), "{msg}");
}

#[test]
fn scene_map_paths_are_relative_to_the_scene_file() {
    let dir = temp_dir("env-scene");
    let maps = dir.join("maps");
    std::fs::create_dir_all(&maps).unwrap();
    let map = ramp(16, 8);
    environment::save(&map, &maps.join("ramp.exr")).unwrap();
    let scene_path = dir.join("scene.toml");
    let text = format!("[environment]\nmap = \"maps/ramp.exr\"\nrotation_deg = 90\n{BALL}");
    std::fs::write(&scene_path, &text).unwrap();
    let s = scene::load(&scene_path).unwrap();
    let env = s.environment_map.unwrap();
    assert_eq!(*env.map, map);
    assert_eq!(env.source, Source::File(maps.join("ramp.exr")));
    assert_eq!(env.rotation_deg, 90.0);
    // The same text read from another folder does not find the map: the error names the
    // map's path, why, and where in the scene file.
    let msg = parse(&text, Path::new("elsewhere/scene.toml")).unwrap_err();
    println!("{msg}");
    assert!(
        msg.contains("elsewhere/maps/ramp.exr")
            && msg.contains("No such file")
            && msg.contains("line 2"),
        "{msg}"
    );
    // A map that is there but broken.
    std::fs::write(maps.join("broken.hdr"), b"#?RADIANCE\n").unwrap();
    let broken = format!("[environment]\nmap = \"maps/broken.hdr\"\n{BALL}");
    std::fs::write(&scene_path, broken).unwrap();
    let msg = scene::load(&scene_path).unwrap_err().to_string();
    assert!(
        msg.contains("broken.hdr") && msg.contains("truncated"),
        "{msg}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_studio_scene_is_the_reference_balls_under_the_studio_map() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/studio.toml");
    let s = scene::load(&path).unwrap();
    let reference = Scene::reference();
    assert_eq!(s.balls, reference.balls);
    assert_eq!(s.camera, reference.camera);
    assert!(s.lights.is_empty());
    assert_eq!(s.environment, DVec3::ZERO);
    assert_eq!(
        s.environment_map.unwrap().source,
        Source::Builtin(Builtin::Studio)
    );
}

#[test]
fn render_and_view_flags_override_the_scenes_environment() {
    use crate::cli::RenderArgs;
    use clap::{Args, FromArgMatches};
    let parse = |argv: &[&str]| {
        let cmd = RenderArgs::augment_args(clap::Command::new("render"));
        let m = cmd.try_get_matches_from(argv).map_err(|e| e.to_string())?;
        RenderArgs::from_arg_matches(&m).map_err(|e| e.to_string())
    };
    let furnace = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/furnace.toml");
    let args = parse(&[
        "render",
        "--scene",
        furnace.to_str().unwrap(),
        "--environment",
        "sky",
        "--ibl-term",
        "turquin",
        "--background",
        "black",
    ])
    .unwrap();
    let s = args.scene.load().unwrap();
    assert_eq!(s.environment, DVec3::ZERO);
    assert_eq!(
        s.environment_map.as_ref().unwrap().source,
        Source::Builtin(Builtin::Sky)
    );
    assert_eq!(s.term(), IblTerm::Turquin);
    assert_eq!(s.background, Background::Black);
    // No flags: the scene's own.
    let s = parse(&["render", "--scene", furnace.to_str().unwrap()])
        .unwrap()
        .scene
        .load()
        .unwrap();
    assert_eq!(s.environment, DVec3::ONE);
    assert!(s.environment_map.is_none());
    // A file, and a name that is neither.
    let dir = temp_dir("env-flags");
    let file = dir.join("white.hdr");
    environment::save(&Builtin::White.generate(16), &file).unwrap();
    let s = parse(&["render", "--environment", file.to_str().unwrap()])
        .unwrap()
        .scene
        .load()
        .unwrap();
    assert_eq!(
        s.environment_map.unwrap().source,
        Source::File(file.clone())
    );
    let e = parse(&["render", "--environment", "forest"])
        .unwrap()
        .scene
        .load()
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("'forest'") && e.contains("studio, sky, white"),
        "{e}"
    );
    assert!(parse(&["render", "--ibl-term", "split-sum"]).is_err());
    assert!(parse(&["render", "--background", "white"]).is_err());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `ibl_method` and `ibl_samples`: each method by name, the samples in 1..=256, and a bad
/// value of either one line naming the key (with its line and column: scene_error).
#[test]
fn scene_ibl_method_and_samples() {
    use crate::environment::{IblMethod, DEFAULT_IBL_SAMPLES, MAX_IBL_SAMPLES};
    let s = parse(BALL, Path::new("s.toml")).unwrap();
    assert_eq!(
        (s.ibl_method, s.ibl_samples),
        (IblMethod::SplitSum, DEFAULT_IBL_SAMPLES)
    );
    for m in IblMethod::ALL {
        let s = parse(
            &format!("ibl_method = \"{m}\"\n{BALL}"),
            Path::new("s.toml"),
        )
        .unwrap();
        assert_eq!(s.ibl_method, m);
    }
    for n in [1, 64, MAX_IBL_SAMPLES] {
        let s = parse(&format!("ibl_samples = {n}\n{BALL}"), Path::new("s.toml")).unwrap();
        assert_eq!(s.ibl_samples, n);
    }
    let msg = scene_error(&format!("ibl_method = \"lobes\"\n{BALL}"));
    assert!(
        msg.contains("split-sum, lobe") && !msg.contains('\n'),
        "{msg}"
    );
    for bad in ["0", "257", "-3", "1.5", "\"16\""] {
        let msg = scene_error(&format!("ibl_samples = {bad}\n{BALL}"));
        assert!(!msg.contains('\n'), "{bad}: {msg}");
        if !bad.contains('.') && !bad.contains('"') {
            assert!(
                msg.contains("ibl_samples") && msg.contains("1..=256"),
                "{bad}: {msg}"
            );
        }
    }
}

/// A mip chain built ahead (`Renderer::offer_mip_chain`, as `render` builds it while the
/// device opens) is used for its own map only: the same pictures as a renderer that builds
/// its own, whether the next map prepared is that map or another (whose picture a wrong
/// chain would change).
#[test]
fn a_chain_built_ahead_serves_its_own_map_only() {
    let scene_of = |b: Builtin| {
        let mut s = Scene::reference();
        s.lights.clear();
        s.environment = DVec3::ZERO;
        s.environment_map = Some(Environment::builtin(b));
        s
    };
    let (studio, sky) = (scene_of(Builtin::Studio), scene_of(Builtin::Sky));
    let (w, h) = (160, 90);
    let draw = |r: &mut crate::Renderer, s: &Scene| r.render_hdr(s, w, h).unwrap().rgba;
    let mut fresh = crate::pixels::vulkan();
    let want_studio = draw(&mut fresh, &studio);
    let want_sky = draw(&mut fresh, &sky);
    assert_ne!(want_studio, want_sky);
    let chain_of = |s: &Scene| {
        let e = s.environment_map.as_ref().unwrap();
        (e.map.clone(), crate::environment::MipChain::new(&e.map))
    };
    // The studio's chain offered, the sky prepared first: the sky builds its own.
    let mut r = crate::pixels::vulkan();
    let (map, chain) = chain_of(&studio);
    r.offer_mip_chain(map, chain);
    assert_eq!(draw(&mut r, &sky), want_sky);
    // The sky's chain offered, the sky drawn from it.
    let mut r = crate::pixels::vulkan();
    let (map, chain) = chain_of(&sky);
    r.offer_mip_chain(map, chain);
    assert_eq!(draw(&mut r, &sky), want_sky);
    assert_eq!(draw(&mut r, &studio), want_studio);
}

/// The lobe mode's cosine samples follow the share of the map's light below its mean: the
/// studio's panels stand above it (0.16), the sky's light mostly does not (0.72), so the
/// studio's frame of 16 draws 4 cosine samples and the sky's 16, a map between a quarter
/// and a half of its light below its mean 8; a constant map is all "below" (its mean), a
/// map dark but for one texel almost none of it; odd counts round up.
#[test]
fn the_cosine_keeps_its_samples_where_the_maps_light_is_below_its_mean() {
    use crate::environment::lobe::{cosine_samples, COSINE_FULL_SHARE, COSINE_HALF_SHARE};
    let studio = Environment::builtin(Builtin::Studio).map.light_below_mean();
    let sky = Environment::builtin(Builtin::Sky).map.light_below_mean();
    assert!((0.1..0.2).contains(&studio), "studio {studio}");
    assert!((0.65..0.8).contains(&sky), "sky {sky}");
    let constant = EnvMap::new(4, 2, vec![[0.5; 3]; 8]).unwrap();
    assert!((constant.light_below_mean() - 1.0).abs() < 1e-12);
    let black = EnvMap::new(4, 2, vec![[0.0; 3]; 8]).unwrap();
    assert_eq!(black.light_below_mean(), 1.0);
    let mut texels = vec![[0.0; 3]; 64 * 32];
    texels[16 * 64 + 10] = [100.0; 3];
    let one = EnvMap::new(64, 32, texels).unwrap().light_below_mean();
    // Its mean is its light over 4 pi; the texel's share of that is its solid angle's.
    assert!(one > 0.0 && one < 1e-3, "{one}");
    assert_eq!(cosine_samples(16, studio), 4);
    assert_eq!(cosine_samples(16, sky), 16);
    assert_eq!(cosine_samples(16, 0.3), 8);
    assert_eq!(cosine_samples(5, 0.0), 2);
    assert_eq!(cosine_samples(5, COSINE_HALF_SHARE), 3);
    assert_eq!(cosine_samples(1, 0.0), 1);
    assert_eq!(cosine_samples(16, COSINE_FULL_SHARE), 16);
    let mut scene = Scene::reference();
    scene.environment_map = Some(Environment::builtin(Builtin::Studio));
    scene.ibl_samples = 16;
    assert_eq!(scene.cosine_samples(), 4);
    scene.environment_map = None;
    assert_eq!(scene.cosine_samples(), 16);
}

#[test]
fn a_dielectric_halves_its_lobe_only_where_the_cosine_draws_fewer() {
    use crate::environment::lobe::lobe_samples;
    // Under the studio (the cosine at 4 of 16) or a map of half (8): a dielectric's lobe
    // halves, a metal's and a partial metal's do not.
    assert_eq!(lobe_samples(16, 4, 0.0), 8);
    assert_eq!(lobe_samples(16, 8, 0.0), 8);
    assert_eq!(lobe_samples(16, 4, 1.0), 16);
    assert_eq!(lobe_samples(16, 4, 0.5), 16);
    assert_eq!(lobe_samples(16, 4, 1e-6), 16);
    // Under the sky, or without a map (every cosine sample kept): all of them.
    assert_eq!(lobe_samples(16, 16, 0.0), 16);
    // Odd counts round up; one sample stays one.
    assert_eq!(lobe_samples(5, 3, 0.0), 3);
    assert_eq!(lobe_samples(1, 1, 0.0), 1);
}
