//! The display transform (src/display.rs, `screen.wgsl`): every tone mapper and transfer
//! curve on the GPU against its CPU twin, on Vulkan (lavapipe) and GL; an `Rgba8UnormSrgb`
//! host target against `Rgba8Unorm`; known values of each curve, monotony, and no NaN for
//! NaN, infinite or negative radiance; the presets' defaults and the scene key; bad values.
//!
//! Bound of the GPU comparisons: 1/255 per channel. The GPU computes in f32, the CPU twin in
//! f64 from the GPU's own f32 radiance (`render_hdr`), so the two display values differ by
//! f32 rounding (about 1e-6), and the 8-bit results by at most the one step where that
//! rounding crosses a rounding boundary.

use std::path::Path;

use glam::DVec3;

use crate::display::{
    self, apply_tone_map, decode_srgb, display_value, encode_srgb, DisplayTransform, ToneMap,
    Transfer, MAX_DISPLAY_RADIANCE,
};

use crate::environment::Background;

use crate::gpu::readback::Readback;

use crate::gpu::{Renderer, Target};

use crate::scene::{self, Preset, Scene};

use crate::pixels::{compare, renderer, vulkan};

const W: u32 = 160;

const H: u32 = 90;

/// Exposures that sweep each curve from its toe to its shoulder over the reference scene
/// (its highlights reach about 10, its dim edges 1e-3).
const EXPOSURES: [f64; 4] = [0.25, 1.0, 4.0, 32.0];

/// Every display transform: each tone mapper under each transfer curve.
fn every_display() -> Vec<DisplayTransform> {
    ToneMap::ALL
        .iter()
        .flat_map(|&tone_map| {
            Transfer::ALL
                .iter()
                .map(move |&transfer| DisplayTransform { tone_map, transfer })
        })
        .collect()
}

/// The reference scene (coloured copper, one light) over a coloured background, so the
/// clear colour and the cross-channel curves (AgX's matrices, Khronos Neutral's offset and
/// desaturation) are both compared.
fn scene_with(display: DisplayTransform, exposure: f64) -> Scene {
    Scene {
        background: Background::Colour(DVec3::new(0.9, 0.3, 0.05)),
        exposure,
        tone_map: Some(display.tone_map),
        transfer: Some(display.transfer),
        ..Scene::reference()
    }
}

fn gpu_matches_cpu_twin(r: &mut Renderer, backend: &str) {
    let hdr = r
        .render_hdr(&scene_with(DisplayTransform::HOMEWORK, 1.0), W, H)
        .unwrap();
    for display in every_display() {
        for exposure in EXPOSURES {
            let scene = scene_with(display, exposure);
            let gpu = r.render_ldr(&scene, W, H).unwrap().rgba;
            let cpu: Vec<u8> = hdr
                .rgba
                .chunks_exact(4)
                .flat_map(|p| {
                    let c = DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64);
                    display::to_rgba8_pixel(c, exposure, display)
                })
                .collect();
            let d = compare(&gpu, &cpu, W);
            let what = format!(
                "{backend} {} + {} at exposure {exposure}",
                display.tone_map, display.transfer
            );
            println!("{}", d.report(&what));
            // 1/255: see the module's bound.
            assert!(d.max <= 1, "{}", d.report(&what));
        }
    }
}

#[test]
fn every_tone_mapper_on_vulkan_matches_the_cpu_twin() {
    gpu_matches_cpu_twin(&mut vulkan(), "Vulkan");
}

#[test]
fn every_tone_mapper_on_gl_matches_the_cpu_twin() {
    gpu_matches_cpu_twin(&mut renderer(wgpu::Backends::GL), "GL");
}

/// `scene` drawn through the library into a host's own texture of `format`, read back.
fn render_into(r: &mut Renderer, scene: &Scene, format: wgpu::TextureFormat) -> Vec<u8> {
    let device = r.gpu().device.clone();
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("host target"),
        size: wgpu::Extent3d {
            width: W,
            height: H,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    let readback = Readback::new(&device, format, (W, H)).unwrap();
    let mut encoder = device.create_command_encoder(&Default::default());
    let target = Target {
        view: &view,
        format,
        width: W,
        height: H,
    };
    r.encode(scene, target, &mut encoder).unwrap();
    readback.record(&mut encoder, &texture);
    r.gpu().queue.submit([encoder.finish()]);
    readback.read(&device).unwrap()
}

/// Each tone mapper once, the transfer curves taken in turn so that both appear: the sRGB
/// target's decoding follows the whole display transform, which the twin tests above cover
/// in every combination; here a double encoding shows whatever comes before it (each pair is
/// two pipelines to compile, about half a second each on lavapipe).
fn each_tone_map_and_transfer() -> Vec<DisplayTransform> {
    ToneMap::ALL
        .iter()
        .zip(Transfer::ALL.iter().cycle())
        .map(|(&tone_map, &transfer)| DisplayTransform { tone_map, transfer })
        .collect()
}

fn srgb_target_matches_unorm(r: &mut Renderer, backend: &str) {
    for display in each_tone_map_and_transfer() {
        for exposure in [1.0, 8.0] {
            let scene = scene_with(display, exposure);
            let unorm = render_into(r, &scene, wgpu::TextureFormat::Rgba8Unorm);
            let srgb = render_into(r, &scene, wgpu::TextureFormat::Rgba8UnormSrgb);
            let d = compare(&srgb, &unorm, W);
            let what = format!(
                "{backend} Rgba8UnormSrgb against Rgba8Unorm, {} + {} at exposure {exposure}",
                display.tone_map, display.transfer
            );
            println!("{}", d.report(&what));
            // 1/255: the shader writes the display value decoded to linear, the hardware
            // encodes it again; the round trip in f32 rounds to the same byte or the next.
            // A double encoding (the bug this guards) lifts the dark copper by tens of steps.
            assert!(d.max <= 1, "{}", d.report(&what));
        }
    }
}

#[test]
fn an_srgb_host_target_on_vulkan_holds_the_unorm_bytes() {
    srgb_target_matches_unorm(&mut vulkan(), "Vulkan");
}

#[test]
fn an_srgb_host_target_on_gl_holds_the_unorm_bytes() {
    srgb_target_matches_unorm(&mut renderer(wgpu::Backends::GL), "GL");
}

#[test]
fn the_srgb_curve_is_continuous_and_its_own_inverse() {
    // The two pieces meet at 0.0031308 (IEC 61966-2-1): 12.92 v against the power law.
    let v: f64 = 0.0031308;
    let power = 1.055 * v.powf(1.0 / 2.4) - 0.055;
    // 1e-7: the standard's rounded constants leave the pieces 3e-9 apart there.
    assert!(
        (encode_srgb(v) - power).abs() < 1e-7,
        "{} {power}",
        encode_srgb(v)
    );
    assert_eq!(encode_srgb(0.0), 0.0);
    // 1e-12: f64 rounding of 1.055 - 0.055.
    assert!((encode_srgb(1.0) - 1.0).abs() < 1e-12);
    // 1.055 * 0.18^(1/2.4) - 0.055 = 0.46135612; 1e-6: the 7 digits written here.
    assert!(
        (encode_srgb(0.18) - 0.4613561).abs() < 1e-6,
        "{}",
        encode_srgb(0.18)
    );
    for k in 0..=1000 {
        let v = k as f64 / 1000.0;
        // 1e-12: f64 rounding through pow and its inverse.
        assert!((decode_srgb(encode_srgb(v)) - v).abs() < 1e-12, "{v}");
    }
}

#[test]
fn known_values_of_each_tone_mapper() {
    let grey = |v: f64| DVec3::splat(v);
    // Reinhard: c / (c + 1).
    assert_eq!(apply_tone_map(grey(1.0), ToneMap::Reinhard), grey(0.5));
    assert_eq!(apply_tone_map(grey(3.0), ToneMap::Reinhard), grey(0.75));
    // None: a clamp.
    assert_eq!(apply_tone_map(grey(0.3), ToneMap::None), grey(0.3));
    assert_eq!(apply_tone_map(grey(7.0), ToneMap::None), grey(1.0));
    // Khronos Neutral: a colour whose smallest channel is 0 (no offset) and whose peak is
    // below the start of compression K_s = 0.76 is left as it is.
    let c = DVec3::new(0.7, 0.3, 0.0);
    assert_eq!(apply_tone_map(c, ToneMap::KhronosNeutral), c);
    // Above x = 2 F90 = 0.08 the offset is F90 = 0.04; below K_s nothing more.
    let out = apply_tone_map(grey(0.5), ToneMap::KhronosNeutral);
    // 1e-12: f64 rounding of one subtraction.
    assert!((out - grey(0.46)).abs().max_element() < 1e-12, "{out}");
    // Highlights compress towards 1, desaturated to white: at (1e3, 10, 1) the peak is
    // p = 999.96, p_n = 1 - 0.0576 / (p - 0.52) = 0.99994 and the weight towards it
    // 1 - 1 / (0.15 (p - p_n) + 1) = 0.9934, so every channel is above 0.99.
    let hot = apply_tone_map(DVec3::new(1e3, 10.0, 1.0), ToneMap::KhronosNeutral);
    assert!(
        hot.min_element() > 0.99 && hot.max_element() <= 1.0,
        "{hot}"
    );
    // ACES (Hill's fit): black stays black (the fit's small negative value is clamped), a
    // bright white saturates to 1 (the fit tends to 1 / 0.983729 before the clamp).
    assert_eq!(apply_tone_map(grey(0.0), ToneMap::Aces), grey(0.0));
    assert_eq!(apply_tone_map(grey(1e4), ToneMap::Aces), grey(1.0));
    // AgX: black to 0; the top of its range (4.03 EV over 1) near white; grey stays grey
    // (the inset's rows sum to 1 within 1.4e-4, the outset's to 1 within 2e-4).
    assert_eq!(apply_tone_map(grey(0.0), ToneMap::Agx), grey(0.0));
    let top = apply_tone_map(grey(1e4), ToneMap::Agx);
    // 0.99: the sigmoid's top p(1) = 0.99858, through the outset (rows summing to 0.9998
    // to 1.0001) and pow 2.2, is 0.9965.
    assert!(top.min_element() > 0.99, "{top}");
    let mid = apply_tone_map(grey(0.18), ToneMap::Agx);
    // 1e-3: the matrices' row sums above, through the sigmoid's slope (below 2).
    assert!(mid.max_element() - mid.min_element() < 1e-3, "{mid}");
    // The homework's channel transform is Reinhard then 1/2.2.
    let homework = display::tone_map(1.0, 1.0);
    // 1e-15: f64 rounding.
    assert!((homework - 0.5f64.powf(1.0 / 2.2)).abs() < 1e-15);
}

#[test]
fn every_display_transform_rises_with_radiance() {
    for display in every_display() {
        let mut previous = display_value(DVec3::ZERO, 1.0, display);
        for k in 1..=4000 {
            // 1e-4 to 1e4, 1000 steps a decade.
            let c = 10f64.powf(-4.0 + k as f64 / 500.0);
            let v = display_value(DVec3::splat(c), 1.0, display);
            let fall = (previous - v).max_element();
            // 1e-12: f64 rounding; a curve that turns back falls by far more.
            assert!(
                fall < 1e-12,
                "{} + {} falls by {fall} at {c}",
                display.tone_map,
                display.transfer
            );
            previous = v;
        }
        // A colour's luminance rises too. AgX's excepted by at most 1e-5, 1/400 of an
        // 8-bit step: its outset matrix takes a little of the other channels off one that
        // has saturated (red falls by 5e-6 as green rises, its luminance by 1.4e-6 near an
        // exposed 100), so it is monotonic only where the inset channels are unsaturated.
        let slack = if display.tone_map == ToneMap::Agx {
            1e-5
        } else {
            1e-12
        };
        let luminance = |v: DVec3| v.dot(DVec3::new(0.2126, 0.7152, 0.0722));
        let mut previous = luminance(display_value(DVec3::ZERO, 1.0, display));
        for k in 1..=4000 {
            let c = 10f64.powf(-4.0 + k as f64 / 500.0);
            let v = luminance(display_value(
                DVec3::new(c, 0.4 * c, 0.05 * c),
                1.0,
                display,
            ));
            let fall = previous - v;
            assert!(
                fall < slack,
                "{} + {} falls by {fall} at {c} (a colour)",
                display.tone_map,
                display.transfer
            );
            previous = v;
        }
    }
}

#[test]
fn nan_infinite_and_negative_radiance_give_display_values() {
    let bad = [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        -1.0,
        -1e300,
        1e300,
    ];
    for display in every_display() {
        for &x in &bad {
            for c in [DVec3::splat(x), DVec3::new(x, 0.5, 0.2)] {
                for exposure in [1.0, 1e12] {
                    let v = display_value(c, exposure, display);
                    assert!(
                        v.is_finite() && v.min_element() >= 0.0 && v.max_element() <= 1.0,
                        "{} + {} of {c} at exposure {exposure}: {v}",
                        display.tone_map,
                        display.transfer
                    );
                }
            }
        }
        // NaN is black, infinity the brightest value taken.
        let black = display_value(DVec3::ZERO, 1.0, display);
        assert_eq!(display_value(DVec3::splat(f64::NAN), 1.0, display), black);
        let top = display_value(DVec3::splat(MAX_DISPLAY_RADIANCE), 1.0, display);
        assert_eq!(
            display_value(DVec3::splat(f64::INFINITY), 1.0, display),
            top
        );
    }
}

#[test]
fn the_presets_choose_the_display_and_a_scene_key_overrides_it() {
    let accurate = DisplayTransform {
        tone_map: ToneMap::KhronosNeutral,
        transfer: Transfer::Srgb,
    };
    assert_eq!(Scene::showcase().display(), accurate);
    let games202 = Scene {
        preset: Preset::Games202,
        ..Scene::showcase()
    };
    assert_eq!(games202.display(), DisplayTransform::HOMEWORK);
    // The homework's scenes keep their display whichever the preset.
    assert_eq!(Scene::reference().display(), DisplayTransform::HOMEWORK);
    let base = r#"
[[ball]]
grid = [0, 0]
radius = 35
roughness = 0.5
material = { kind = "metal", f0 = [1, 1, 1] }
"#;
    let load = |head: &str| scene::parse(&format!("{head}\n{base}"), Path::new("t.toml")).unwrap();
    assert_eq!(load("").display(), accurate);
    assert_eq!(
        load("preset = \"games202\"").display(),
        DisplayTransform::HOMEWORK
    );
    let agx = load("preset = \"games202\"\ntone_map = \"agx\"\ntransfer = \"srgb\"");
    assert_eq!(
        agx.display(),
        DisplayTransform {
            tone_map: ToneMap::Agx,
            transfer: Transfer::Srgb,
        }
    );
    for t in ToneMap::ALL {
        let s = load(&format!("tone_map = \"{}\"", t.name()));
        assert_eq!(s.display().tone_map, t);
    }
}

#[test]
fn the_viewer_picks_a_plain_surface_format_else_an_srgb_one() {
    use crate::viewer::surface_format;
    use wgpu::TextureFormat as F;
    assert_eq!(
        surface_format(&[F::Bgra8UnormSrgb, F::Bgra8Unorm]),
        Some(F::Bgra8Unorm)
    );
    assert_eq!(
        surface_format(&[F::Rgba16Float, F::Bgra8UnormSrgb]),
        Some(F::Bgra8UnormSrgb)
    );
    assert_eq!(surface_format(&[F::Rgba16Float]), None);
}
