//! GPU failures that can be provoked here (issue 6): no adapter (a missing Vulkan driver),
//! a destroyed device, a frame beyond the device's limits. Each is an error with a clear
//! message, never a panic.

use shadeballs::scene::Scene;

use crate::bad_input::{fails_with_one_line, run};
use crate::cli::temp_dir;
use crate::pixels::vulkan;

#[test]
fn no_adapter_is_a_clear_error_or_a_stated_fallback() {
    let dir = temp_dir("no-adapter");
    let out = dir.join("x.png");
    let out = out.to_str().unwrap();
    let no_driver = [
        ("VK_DRIVER_FILES", "/nonexistent/icd.json"),
        ("WGPU_BACKEND", "vulkan"),
    ];
    let small = ["--width", "16", "--height", "9", "--out", out];
    let mut vulkan_only = vec!["render", "--backend", "vulkan"];
    vulkan_only.extend(small);
    fails_with_one_line(&vulkan_only, &no_driver, "mesa-vulkan-drivers");
    // The probe has no CPU fallback: one error line, no warning announcing one.
    let csv = dir.join("x.csv");
    for backend in ["vulkan", "auto"] {
        fails_with_one_line(
            &[
                "probe",
                "--backend",
                backend,
                "--out",
                csv.to_str().unwrap(),
            ],
            &no_driver,
            "mesa-vulkan-drivers",
        );
    }
    // `auto` falls back to the CPU renderer, and says so on one line.
    let mut auto = vec!["render"];
    auto.extend(small);
    let (ok, stderr) = run(&auto, &no_driver, false);
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("falling back to the CPU reference renderer")
            && stderr.contains("mesa-vulkan-drivers"),
        "{stderr}"
    );
    assert!(image::open(out).is_ok());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_destroyed_device_gives_errors_not_panics() {
    let mut r = vulkan();
    let scene = Scene::reference();
    assert!(r.render_ldr(&scene, 16, 16).is_ok());
    r.gpu().device.destroy();
    for _ in 0..2 {
        let errors = [
            r.render_ldr(&scene, 16, 16).err(),
            r.render_hdr(&scene, 16, 16).err(),
            r.probe(shadeballs::brdf::Geometry::Smith, 9).err(),
        ];
        for e in errors {
            let msg = e.expect("a destroyed device must fail").to_string();
            println!("{msg}");
            assert!(msg.contains("GPU error") && !msg.contains('\n'), "{msg}");
        }
    }
    // The renderer states the cause once the device reports it lost.
    let msg = r.render_hdr(&scene, 16, 16).err().unwrap().to_string();
    assert!(msg.contains("destroyed"), "{msg}");
}

#[test]
fn a_frame_beyond_the_device_limits_is_an_error() {
    let mut r = vulkan();
    let max = r.gpu().device.limits().max_texture_dimension_2d;
    for (w, h) in [(max + 1, 8), (8, max + 1), (max, max)] {
        let e = r
            .render_hdr(&Scene::reference(), w, h)
            .err()
            .expect("too large");
        println!("{w}x{h}: {e}");
        assert!(e.to_string().contains("image size"), "{e}");
    }
    // The device stays usable.
    assert!(r.render_hdr(&Scene::reference(), 8, 8).is_ok());
}
