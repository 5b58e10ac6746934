//! The viewer in a real window: Xvfb (a virtual X server), the binary, and xdotool to send
//! keys, a resize and an unmap/map (what a window manager does on minimise) through the
//! window system. The window's scene area must equal the headless render of the same scene.
//! Also the viewer's pure scene edits (no window).

use std::sync::Arc;

use glam::DVec3;

use crate::environment::{Background, Builtin, Environment, IblTerm, Source};

use crate::scene::{Camera, Scene};

use crate::viewer::edit::{
    self, EnvironmentChoice, EnvironmentControl, Grid, LightControl, MaterialChoice,
};

use crate::viewer::orbit;

use crate::pixels::temp_dir;
use crate::pixels::vulkan;
use std::path::Path;

#[test]
fn orbit_keeps_a_valid_camera_and_zoom_stays_in_range() {
    let home = Camera::reference();
    let d0 = (home.position - home.target).length();
    let mut c = home;
    for _ in 0..1000 {
        c = orbit::orbit(&c, 0.37, 0.11);
        assert!(c.problem().is_none(), "{c:?}");
        let d = (c.position - c.target).length();
        assert!(
            (d - d0).abs() < 1e-9 * d0,
            "orbit changed the distance: {d}"
        );
    }
    let pitch = ((c.position - c.target).y / d0).asin().to_degrees();
    assert!(pitch <= orbit::MAX_PITCH_DEG + 1e-9, "{pitch}");
    for lines in [1e3, -1e3] {
        let z = orbit::zoom(&home, lines, d0);
        let d = (z.position - z.target).length();
        assert!(
            d >= d0 * orbit::ZOOM_RANGE.0 * (1.0 - 1e-12)
                && d <= d0 * orbit::ZOOM_RANGE.1 * (1.0 + 1e-12),
            "{d}"
        );
    }
}

#[test]
fn reference_grid_and_light_controls_reproduce_the_reference_scene() {
    let reference = Scene::reference();
    let material = reference.balls[0].material;
    let grid = Grid::REFERENCE.balls(material);
    assert_eq!(grid.len(), reference.balls.len());
    for (a, b) in grid.iter().zip(&reference.balls) {
        assert!((a.center - b.center).length() < 1e-12, "{a:?} {b:?}");
        assert!((a.roughness - b.roughness).abs() < 1e-12);
        assert_eq!(a.radius, b.radius);
        assert_eq!(a.model.has_term(), b.model.has_term());
    }
    let lights = LightControl::of(&reference).lights();
    assert_eq!(lights.len(), 1);
    assert!((lights[0].direction - reference.lights[0].direction).length() < 1e-12);
    assert_eq!(lights[0].radiance, reference.lights[0].radiance);
    // Many balls: still two rows, the row (edge to edge) no wider than the reference's.
    let wide = Grid {
        per_row: 32,
        low: 0.0,
        high: 1.0,
    }
    .balls(material);
    assert_eq!(wide.len(), 64);
    let span = |bs: &[crate::scene::Ball]| {
        let right = bs.iter().map(|b| b.center.x + b.radius);
        let left = bs.iter().map(|b| b.center.x - b.radius);
        right.fold(f64::MIN, f64::max) - left.fold(f64::MAX, f64::min)
    };
    assert!(span(&wide) <= span(&reference.balls) + 1e-9);
    assert_eq!(wide[0].roughness, 0.0);
    assert_eq!(wide[31].roughness, 1.0);
}

#[test]
fn term_rows_furnace_and_materials_edit_the_scene() {
    let mut scene = Scene::reference();
    let rows = edit::rows(&scene);
    assert_eq!(rows.len(), 2);
    assert!(edit::row_has_term(&scene, &rows[0]) && !edit::row_has_term(&scene, &rows[1]));
    edit::set_row_term(&mut scene, &rows[1], true);
    assert!(scene.balls.iter().all(|b| b.model.has_term()));
    edit::toggle_term(&mut scene);
    assert!(scene.balls.iter().all(|b| !b.model.has_term()));
    edit::toggle_term(&mut scene);
    assert!(scene.balls.iter().all(|b| b.model.has_term()));

    let mut saved = None;
    edit::set_furnace(&mut scene, true, &mut saved);
    assert!(edit::is_furnace(&scene) && scene.lights.is_empty());
    edit::set_furnace(&mut scene, true, &mut saved);
    assert_eq!(
        saved.as_ref().map(|s| s.lights.len()),
        Some(1),
        "turning it on twice must not lose the lights"
    );
    edit::set_furnace(&mut scene, false, &mut saved);
    assert!(!edit::is_furnace(&scene));
    assert_eq!(scene.lights, Scene::reference().lights);
    assert_eq!(scene.environment, DVec3::ZERO);
    // A coloured environment with lights is not the furnace, and comes back whole.
    let sky = DVec3::new(0.2, 0.3, 0.5);
    scene.environment = sky;
    assert!(!edit::is_furnace(&scene));
    edit::set_furnace(&mut scene, true, &mut saved);
    assert!(edit::is_furnace(&scene));
    edit::set_furnace(&mut scene, false, &mut saved);
    assert_eq!(scene.environment, sky);
    assert_eq!(scene.lights, Scene::reference().lights);
    // The furnace scene file turned off: no lights to restore, a black environment.
    let mut furnace = Scene::furnace();
    assert!(edit::is_furnace(&furnace));
    edit::set_furnace(&mut furnace, false, &mut None);
    assert!(furnace.lights.is_empty() && furnace.environment == DVec3::ZERO);

    assert_eq!(MaterialChoice::AsScene.material(), None);
    let originals: Vec<_> = scene.balls.iter().map(|b| b.material).collect();
    let white = MaterialChoice::White.material().unwrap();
    edit::set_material(&mut scene, white);
    assert!(scene.balls.iter().all(|b| b.material == white));
    edit::restore_materials(&mut scene, &originals);
    assert!(scene
        .balls
        .iter()
        .zip(&originals)
        .all(|(b, m)| b.material == *m));
    edit::set_material(&mut scene, white);
    let wild = MaterialChoice::Custom([2.0, -1.0, 0.5]).material().unwrap();
    assert_eq!(
        wild.f0.to_array(),
        [1.0, 0.0, 0.5],
        "F0 is clamped to [0, 1]"
    );
    assert_eq!(
        MaterialChoice::Copper.material().unwrap(),
        Scene::reference().balls[0].material
    );
}

/// The panel's environment picker: a built-in replaces the uniform radiance (kept for
/// "uniform" to restore), is generated once however often it is chosen, and keeps the
/// latest map's rotation and intensity; rotation and intensity edits keep the map's `Arc`
/// (the renderer knows a map by it: nothing is prefiltered again).
#[test]
fn environment_picker_switches_maps_and_keeps_them() {
    let mut scene = Scene::reference();
    let sky = DVec3::new(0.2, 0.3, 0.5);
    scene.environment = sky;
    let mut control = EnvironmentControl::of(&scene);
    assert_eq!(EnvironmentChoice::of(&scene), EnvironmentChoice::Uniform);
    assert_eq!(
        control.choices(),
        [
            EnvironmentChoice::Uniform,
            EnvironmentChoice::Builtin(Builtin::Studio),
            EnvironmentChoice::Builtin(Builtin::Sky),
            EnvironmentChoice::Builtin(Builtin::White),
        ],
        "no file without a scene map file"
    );
    // Nothing to pick without a file: no change.
    edit::set_environment(&mut scene, EnvironmentChoice::File, &mut control);
    assert!(scene.environment_map.is_none() && scene.environment == sky);

    let studio = EnvironmentChoice::Builtin(Builtin::Studio);
    edit::set_environment(&mut scene, studio, &mut control);
    let map = scene.environment_map.clone().expect("studio chosen");
    assert_eq!(map.source, Source::Builtin(Builtin::Studio));
    assert_eq!((map.rotation_deg, map.intensity), (0.0, 1.0));
    assert_eq!(scene.environment, DVec3::ZERO);
    assert_eq!(EnvironmentChoice::of(&scene), studio);
    assert_eq!(
        *map.map,
        Builtin::Studio.generate(crate::environment::builtin::DEFAULT_BUILTIN_WIDTH)
    );
    assert_eq!(scene.lights, Scene::reference().lights, "lights untouched");

    // Rotation and intensity change those fields alone, and keep the same map.
    let before = scene.clone();
    edit::set_map_rotation(&mut scene, -90.0);
    edit::set_map_intensity(&mut scene, 2.5);
    let e = scene.environment_map.as_ref().unwrap();
    assert!(
        Arc::ptr_eq(&e.map, &map.map),
        "rotation or intensity replaced the map"
    );
    assert_eq!((e.rotation_deg, e.intensity), (-90.0, 2.5));
    assert_eq!(e.source, map.source);
    let mut same = scene.clone();
    same.environment_map = before.environment_map.clone();
    assert_eq!(
        same, before,
        "only the map's rotation and intensity changed"
    );
    edit::set_map_intensity(&mut scene, -1.0);
    assert_eq!(scene.environment_map.as_ref().unwrap().intensity, 0.0);
    edit::set_map_intensity(&mut scene, 2.5);

    // Sky, then studio again: the first studio's map, turned and scaled as last set.
    edit::set_environment(
        &mut scene,
        EnvironmentChoice::Builtin(Builtin::Sky),
        &mut control,
    );
    let e = scene.environment_map.as_ref().unwrap();
    assert_eq!(e.source, Source::Builtin(Builtin::Sky));
    assert_eq!((e.rotation_deg, e.intensity), (-90.0, 2.5));
    edit::set_environment(&mut scene, studio, &mut control);
    assert!(Arc::ptr_eq(
        &scene.environment_map.as_ref().unwrap().map,
        &map.map
    ));
    assert_eq!(control.builtins_generated(), 2, "studio generated once");
    assert!(Arc::ptr_eq(&control.builtin_map(Builtin::Studio), &map.map));

    // Back to uniform: the scene's radiance, no map; studio again keeps its transform.
    edit::set_environment(&mut scene, EnvironmentChoice::Uniform, &mut control);
    assert!(scene.environment_map.is_none());
    assert_eq!(scene.environment, sky);
    edit::set_environment(&mut scene, studio, &mut control);
    let e = scene.environment_map.as_ref().unwrap();
    assert!(Arc::ptr_eq(&e.map, &map.map));
    assert_eq!((e.rotation_deg, e.intensity), (-90.0, 2.5));
    edit::set_environment(&mut scene, EnvironmentChoice::Uniform, &mut control);
    assert_eq!(scene.environment, sky);
    assert_eq!(control.builtins_generated(), 2);

    // A scene that came with a built-in: the picker starts from it, its map counts as
    // generated (chosen again, the same Arc).
    let mut scene = Scene::reference();
    scene.environment_map = Some(Environment::builtin(Builtin::White));
    let loaded = scene.environment_map.clone().unwrap();
    let mut control = EnvironmentControl::of(&scene);
    assert_eq!(
        EnvironmentChoice::of(&scene),
        EnvironmentChoice::Builtin(Builtin::White)
    );
    edit::set_environment(&mut scene, EnvironmentChoice::Uniform, &mut control);
    edit::set_environment(
        &mut scene,
        EnvironmentChoice::Builtin(Builtin::White),
        &mut control,
    );
    assert!(Arc::ptr_eq(
        &scene.environment_map.as_ref().unwrap().map,
        &loaded.map
    ));
    assert_eq!(control.builtins_generated(), 1);
}

/// A scene that came with a map file lists "file (as loaded)", which brings back that very
/// map (its Arc) after a built-in; "uniform" gives the scene's uniform radiance (black for
/// a scene with a map).
#[test]
fn environment_picker_offers_the_scene_map_file() {
    let dir = temp_dir("view-env-file");
    let path = dir.join("tiny.hdr");
    let map = Builtin::Sky.generate(32);
    crate::environment::save(&map, &path).unwrap();
    let mut scene = Scene::reference();
    let file = Environment {
        rotation_deg: 30.0,
        intensity: 0.5,
        ..Environment::from_file(&path).unwrap()
    };
    scene.environment_map = Some(file.clone());
    let mut control = EnvironmentControl::of(&scene);
    assert_eq!(EnvironmentChoice::of(&scene), EnvironmentChoice::File);
    assert_eq!(control.choices().last(), Some(&EnvironmentChoice::File));
    assert_eq!(EnvironmentChoice::File.name(), "file (as loaded)");
    edit::set_environment(
        &mut scene,
        EnvironmentChoice::Builtin(Builtin::Sky),
        &mut control,
    );
    let e = scene.environment_map.as_ref().unwrap();
    assert_eq!((e.rotation_deg, e.intensity), (30.0, 0.5));
    edit::set_environment(&mut scene, EnvironmentChoice::File, &mut control);
    let e = scene.environment_map.as_ref().unwrap();
    assert_eq!(e.source, file.source);
    assert!(Arc::ptr_eq(&e.map, &file.map));
    edit::set_environment(&mut scene, EnvironmentChoice::Uniform, &mut control);
    assert!(scene.environment_map.is_none() && scene.environment == DVec3::ZERO);
}

/// The furnace with a map: on, the map, lights and a black background are put away (a
/// uniform white environment shown as the background); off, they come back as they were,
/// the map the same Arc (not prefiltered again).
#[test]
fn furnace_round_trips_a_scene_with_a_map() {
    let mut scene = Scene::reference();
    scene.environment_map = Some(Environment {
        rotation_deg: 45.0,
        intensity: 3.0,
        ..Environment::builtin(Builtin::Studio)
    });
    scene.background = Background::Black;
    scene.set_term(IblTerm::Turquin);
    let original = scene.clone();
    let mut saved = None;
    assert!(!edit::is_furnace(&scene));
    edit::set_furnace(&mut scene, true, &mut saved);
    assert!(edit::is_furnace(&scene));
    assert!(scene.environment_map.is_none() && scene.lights.is_empty());
    assert_eq!(scene.environment, DVec3::ONE);
    assert_eq!(scene.background, Background::Environment);
    edit::set_furnace(&mut scene, true, &mut saved);
    assert!(
        saved.as_ref().unwrap().environment_map.is_some(),
        "on twice kept the map"
    );
    edit::set_furnace(&mut scene, false, &mut saved);
    assert_eq!(scene, original);
    assert!(Arc::ptr_eq(
        &scene.environment_map.as_ref().unwrap().map,
        &original.environment_map.as_ref().unwrap().map
    ));
    assert!(saved.is_none());
    // A uniform white environment with a map is not the furnace, nor one with a black
    // background.
    let mut white_map = original.clone();
    white_map.lights.clear();
    white_map.environment = DVec3::ONE;
    white_map.background = Background::Environment;
    assert!(!edit::is_furnace(&white_map));
    white_map.environment_map = None;
    assert!(edit::is_furnace(&white_map));
    white_map.background = Background::Black;
    assert!(!edit::is_furnace(&white_map));
}

/// The panel's map file field (and a file dropped on the window) loads a map as the
/// picker's file choice, keeping the latest map's rotation and intensity; a second file
/// replaces it; a missing file, or the furnace on, is an error that changes nothing.
#[test]
fn a_map_file_loads_from_the_panel() {
    let dir = temp_dir("view-map-file");
    let (sky, studio) = (dir.join("sky.hdr"), dir.join("studio.exr"));
    crate::environment::save(&Builtin::Sky.generate(32), &sky).unwrap();
    crate::environment::save(&Builtin::Studio.generate(32), &studio).unwrap();
    let mut scene = Scene::reference();
    let mut control = EnvironmentControl::of(&scene);
    edit::set_environment(
        &mut scene,
        EnvironmentChoice::Builtin(Builtin::White),
        &mut control,
    );
    edit::set_map_rotation(&mut scene, 40.0);
    edit::load_map_file(&mut scene, &sky, &mut control).unwrap();
    let e = scene.environment_map.clone().unwrap();
    assert_eq!(e.source, Source::File(sky.clone()));
    assert_eq!((e.rotation_deg, e.intensity), (40.0, 1.0));
    assert_eq!(EnvironmentChoice::of(&scene), EnvironmentChoice::File);
    assert_eq!(control.choices().last(), Some(&EnvironmentChoice::File));
    assert_eq!(
        *e.map,
        Environment::from_file(&sky).unwrap().map.as_ref().clone()
    );
    edit::load_map_file(&mut scene, &studio, &mut control).unwrap();
    let e2 = scene.environment_map.clone().unwrap();
    assert_eq!(e2.source, Source::File(studio.clone()));
    assert_eq!(e2.rotation_deg, 40.0);
    assert!(!Arc::ptr_eq(&e.map, &e2.map));
    let before = scene.clone();
    let err = edit::load_map_file(&mut scene, &dir.join("missing.hdr"), &mut control);
    assert!(err.unwrap_err().to_string().contains("missing.hdr"));
    assert_eq!(scene, before);
    let mut furnace = Scene::furnace();
    let mut control = EnvironmentControl::of(&furnace);
    let err = edit::load_map_file(&mut furnace, &sky, &mut control);
    assert!(err.unwrap_err().to_string().contains("furnace"));
    assert!(furnace.environment_map.is_none());
}

/// The blit that stands in for a copy where the window cannot be copied into (GL) gives the
/// window the frame image's exact bytes.
#[test]
fn blit_is_an_exact_copy() {
    use crate::gpu::readback::Readback;
    use crate::viewer::blit::Blit;
    let r = vulkan();
    let (device, queue) = (&r.gpu().device, &r.gpu().queue);
    let format = wgpu::TextureFormat::Bgra8Unorm;
    let (w, h) = (67u32, 45u32);
    let texture = |usage| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: None,
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    };
    let from = texture(wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST);
    let to = texture(wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC);
    // Every byte value, in a pattern that differs per texel and channel.
    let bytes: Vec<u8> = (0..w * h * 4).map(|i| (i * 37 % 256) as u8).collect();
    queue.write_texture(
        from.as_image_copy(),
        &bytes,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(4 * w),
            rows_per_image: Some(h),
        },
        from.size(),
    );
    let mut encoder = device.create_command_encoder(&Default::default());
    let view = to.create_view(&Default::default());
    Blit::new(device, format).encode(device, &mut encoder, &from, &view);
    let readback = Readback::new(device, format, (w, h)).unwrap();
    readback.record(&mut encoder, &to);
    queue.submit([encoder.finish()]);
    assert!(
        readback.read(device).unwrap() == bytes,
        "the blit changed the bytes"
    );
}

/// The saved scene file loads back as the very scene saved: the built-in and shipped
/// scenes, and scenes the panel makes (an orbited camera, the light control's direction, the
/// engines' material, a custom metal, a background colour). A scene file cannot hold a
/// uniform radiance and a map at once: that is an error, not a file of another scene.
#[test]
fn saved_scene_text_loads_back_as_the_same_scene() {
    use crate::viewer::save::scene_toml;
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes");
    let mut scenes = vec![Scene::reference(), Scene::showcase(), Scene::furnace()];
    for name in [
        "plastic.toml",
        "metallic_roughness.toml",
        "models_and_truth.toml",
    ] {
        scenes.push(crate::scene::load(&assets.join(name)).unwrap());
    }
    let mut edited = Scene::showcase();
    edited.camera = orbit::orbit(&edited.camera, 0.37, 0.11);
    edited.lights = LightControl {
        azimuth_deg: 33.3,
        elevation_deg: 21.7,
        intensity: 2.5,
    }
    .lights();
    edited.exposure = 0.37;
    edited.ibl_method = crate::environment::IblMethod::Lobe;
    edited.ibl_samples = 7;
    edited.background = Background::Colour(DVec3::new(0.1, 0.2, 0.3));
    edit::set_material(
        &mut edited,
        MaterialChoice::MetallicRoughness {
            base_color: [0.3, 0.6, 0.9],
            metallic: 0.4,
            ior: 1.7,
        }
        .material()
        .unwrap(),
    );
    edited.balls[0].material = MaterialChoice::Custom([0.9, 0.5, 0.1]).material().unwrap();
    edited.balls[1].material = MaterialChoice::Plastic.material().unwrap();
    edited.balls[2].material = MaterialChoice::Rubber.material().unwrap();
    scenes.push(edited);
    for (i, scene) in scenes.iter().enumerate() {
        let text = scene_toml(scene, (640, 360)).unwrap_or_else(|e| panic!("scene {i}: {e}"));
        let back = crate::scene::parse(&text, Path::new("saved.toml"))
            .unwrap_or_else(|e| panic!("scene {i}: {e}\n{text}"));
        // The scene area's size travels as the `size` key (issue 39), not only a comment.
        let sized = Scene {
            size: Some((640, 360)),
            ..scene.clone()
        };
        assert!(back == sized, "scene {i} came back another:\n{text}");
    }
    let mut both = Scene::reference();
    both.environment = DVec3::splat(0.5);
    both.environment_map = Some(Environment::builtin(Builtin::Sky));
    let e = scene_toml(&both, (640, 360)).unwrap_err();
    assert!(e.contains("uniform radiance and a map"), "{e}");
}

/// The comparison's sides edit the models alone, the split's column is rounded and
/// clamped, and `--compare`'s value is two names.
#[test]
fn comparison_sides_and_split() {
    use crate::scene::Model;
    use crate::viewer::compare::{parse_sides, Compare, Side};
    let scene = crate::scene::load(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/models_and_truth.toml"),
    )
    .unwrap();
    assert!(scene.balls.iter().any(|b| b.model == Model::Truth));
    assert_eq!(Side::Scene.apply(&scene), scene);
    for (side, model) in [
        (Side::Off, Model::None),
        (Side::Turquin, Model::Turquin),
        (Side::On, Model::from_term(scene.term())),
    ] {
        let s = side.apply(&scene);
        for (a, b) in s.balls.iter().zip(&scene.balls) {
            let want = if b.model == Model::Truth {
                Model::Truth
            } else {
                model
            };
            assert_eq!(a.model, want, "{side}");
            assert_eq!((a.center, a.material), (b.center, b.material));
        }
        assert_eq!(s.lights, scene.lights);
    }
    assert!(Side::Truth
        .apply(&scene)
        .balls
        .iter()
        .all(|b| b.model == Model::Truth));
    let mut c = Compare::new(Side::On, Side::Off);
    assert_eq!(c.split_px(981), 491);
    c.split = 7.0;
    assert_eq!(c.split_px(980), 980);
    c.split = f64::NAN;
    assert_eq!(c.split_px(980), 490);
    assert_eq!(Compare::split_at(-5.0, 980), 0.0);
    assert_eq!(parse_sides(" on , truth"), Ok((Side::On, Side::Truth)));
    for bad in ["on", "on,", "on,gold", ""] {
        let e = parse_sides(bad).unwrap_err();
        assert!(e.contains("scene, on, off"), "{bad}: {e}");
    }
}

/// `shaders/difference.wgsl`, composed, parses and validates, and its ramp's CPU mirror
/// starts at black and ends at its last stop.
#[test]
fn difference_shader_validates_and_its_ramp_spans_black_to_pale_yellow() {
    use crate::viewer::difference::{difference_colour, difference_pixel};
    let source = crate::gpu::shaders::difference_source();
    let module = naga::front::wgsl::parse_str(source).unwrap();
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .unwrap();
    assert!(source.contains("fn difference_colour("));
    assert_eq!(difference_colour(-1.0), [0.0; 3]);
    assert_eq!(difference_colour(0.0), [0.0; 3]);
    assert_eq!(difference_colour(5.0), [1.0, 1.0, 0.75]);
    assert_eq!(
        difference_pixel([9, 9, 9, 255], [9, 9, 9, 255], 64),
        [0, 0, 0, 255]
    );
    assert_eq!(
        difference_pixel([255, 0, 0, 255], [0, 0, 0, 255], 1),
        [255, 255, 191, 255]
    );
}
