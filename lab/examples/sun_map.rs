//! Writes issue 37's generated sun map (`shadeballs_lab::bench::light::sun_environment`: a
//! radiance of 1e4 over 0.1 % of the sphere, over a dim sky) to a `.exr` or `.hdr` file, so
//! that a scene file can light a ball with it. With `--sun-only` the sky is black, and the
//! program prints the directional light that the sun's texels add up to (their irradiance
//! on a surface facing the sun): the truth, which takes no directional light through a
//! coat, walks under the map, and the renderers under the light (docs/design/coat.md,
//! "Under a sun").
//!
//! ```text
//! cargo run --release -p shadeballs-lab --example sun_map -- OUT.exr [--sun-only]
//! ```

use anyhow::{bail, Result};
use glam::DVec2;
use shadeballs::environment::{uv_to_direction, EnvMap};
use shadeballs_lab::bench::light::{sun_environment, SUN_RADIANCE};

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (path, sun_only) = match args.as_slice() {
        [path] => (path, false),
        [path, flag] if flag == "--sun-only" => (path, true),
        _ => bail!("usage: sun_map OUT.exr [--sun-only]"),
    };
    let map = sun_environment().map;
    let (w, h) = (map.width(), map.height());
    let is_sun = |t: &[f32; 3]| t[0] >= SUN_RADIANCE;
    // The sun's direction: the mean of its texels' directions weighted by solid angle.
    let mut axis = glam::DVec3::ZERO;
    for j in 0..h {
        for i in 0..w {
            if is_sun(&map.texels()[(j * w + i) as usize]) {
                axis += texel_direction(i, j, w, h) * map.texel_solid_angle(j);
            }
        }
    }
    if axis == glam::DVec3::ZERO {
        bail!("the generated map has no sun texel");
    }
    let sun = axis.normalize();
    // The sun's irradiance on a surface facing it: the sum of radiance x solid angle x cos.
    let mut irradiance = 0.0;
    let mut texels = Vec::with_capacity(map.texels().len());
    for j in 0..h {
        for i in 0..w {
            let t = map.texels()[(j * w + i) as usize];
            if is_sun(&t) {
                let cos = texel_direction(i, j, w, h).dot(sun).max(0.0);
                irradiance += f64::from(t[0]) * map.texel_solid_angle(j) * cos;
                texels.push(t);
            } else {
                texels.push(if sun_only { [0.0; 3] } else { t });
            }
        }
    }
    let out = EnvMap::new(w, h, texels)?;
    shadeballs::environment::save(&out, std::path::Path::new(path))?;
    println!(
        "wrote the sun map ({w}x{h}{}) to {path}",
        if sun_only { ", sun only" } else { "" }
    );
    println!("its sun as a directional light:");
    println!("[[light]]");
    println!("direction = [{:.6}, {:.6}, {:.6}]", sun.x, sun.y, sun.z);
    println!("radiance = [{irradiance:.6}, {irradiance:.6}, {irradiance:.6}]");
    Ok(())
}

/// The direction through texel `(i, j)`'s centre of a `w` x `h` map.
fn texel_direction(i: u32, j: u32, w: u32, h: u32) -> glam::DVec3 {
    uv_to_direction(DVec2::new(
        (f64::from(i) + 0.5) / f64::from(w),
        (f64::from(j) + 0.5) / f64::from(h),
    ))
}
