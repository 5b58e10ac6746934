//! "Save scene": the viewer's [`Scene`] as a scene file (the TOML of `scene::parse`) that
//! loads back to the same scene, value for value, so that `shadeballs render` of it draws
//! the viewer's picture. Every number is written with Rust's shortest round-trip form; a
//! value the file stores through a curve (an sRGB colour, a light's direction, which the
//! parser normalises) is written as the input that the parser's own curve maps to the
//! value exactly, found by searching the nearest doubles. What has no exact form is an
//! error naming it, never a file that renders another picture.

use std::fmt::Write as _;

use glam::DVec3;

use crate::environment::{Background, Source};
use crate::scene::{gamma22_decode, srgb_decode, Ball, Light, Material, Scene, DEFAULT_IOR};

/// How many doubles either side of a curve's inverse the search for an exact input tries:
/// the inverse (`powf` of the reciprocal exponent) is within a few ulps of an input that
/// maps exactly, where one exists (the sRGB decode's slope is at most 2.3, so inputs one ulp
/// apart map at most 3 ulps apart).
const SEARCH_ULPS: u64 = 64;

/// The scene file text of `scene`: a header comment (what saved it, and the `render`
/// command that draws the viewer's scene area), then every key, `size` the scene area's
/// (which `render` draws and `view` opens beside its panel when no flag sets a size).
pub(crate) fn scene_toml(scene: &Scene, size: (u32, u32)) -> Result<String, String> {
    let mut out = String::new();
    let (w, h) = size;
    // `write!` into a String cannot fail.
    let _ = writeln!(
        out,
        "# Saved by `shadeballs view`: `shadeballs render --scene <this file>` draws the \
         viewer's scene area ({w} x {h}, the `size` key)."
    );
    top_level(&mut out, scene);
    let _ = writeln!(out, "size = [{w}, {h}]");
    let c = &scene.camera;
    let _ = writeln!(
        out,
        "\n[camera]\nposition = {}\ntarget = {}\nvfov_deg = {}",
        vec3(c.position),
        vec3(c.target),
        num(c.vfov_deg)
    );
    if let Some(a) = c.min_aspect {
        let _ = writeln!(out, "min_aspect = {}", num(a));
    }
    environment(&mut out, scene)?;
    for (i, light) in scene.lights.iter().enumerate() {
        self::light(&mut out, light).map_err(|e| format!("light {}: {e}", i + 1))?;
    }
    for (i, b) in scene.balls.iter().enumerate() {
        ball(&mut out, b).map_err(|e| format!("ball {}: {e}", i + 1))?;
    }
    Ok(out)
}

/// `scene` as its file, saved at scene area `size`, loads back: a map file's path made
/// absolute, as the file names it (issue 38, 3: a relative path from `--environment` or a
/// relative scene's `map`), and `size` its size (the `size` key, issue 39).
pub(crate) fn as_written(scene: &Scene, size: (u32, u32)) -> Scene {
    let mut scene = scene.clone();
    scene.size = Some(size);
    if let Some(e) = &mut scene.environment_map {
        if let Source::File(path) = &e.source {
            if let Ok(absolute) = std::path::absolute(path) {
                e.source = Source::File(absolute);
            }
        }
    }
    scene
}

/// The keys before the first table.
fn top_level(out: &mut String, scene: &Scene) {
    let _ = writeln!(out, "preset = {}", string(scene.preset.name()));
    let _ = writeln!(out, "geometry = {}", string(scene.geometry.name()));
    let _ = writeln!(out, "layering = {}", string(scene.layering.name()));
    let _ = writeln!(out, "coat_form = {}", string(scene.coat_form.name()));
    let _ = writeln!(out, "base_reading = {}", string(scene.base_reading.name()));
    let _ = writeln!(out, "exposure = {}", num(scene.exposure));
    let background = match scene.background {
        Background::Environment => string("environment"),
        Background::Black => string("black"),
        Background::Colour(c) => vec3(c),
    };
    let _ = writeln!(out, "background = {background}");
    let _ = writeln!(out, "ibl_method = {}", string(scene.ibl_method.name()));
    let _ = writeln!(out, "ibl_samples = {}", scene.ibl_samples);
    let _ = writeln!(out, "labels = {}", scene.labels);
    let _ = writeln!(out, "antialias = {}", scene.antialias);
    if let Some(t) = scene.tone_map {
        let _ = writeln!(out, "tone_map = {}", string(t.name()));
    }
    if let Some(t) = scene.transfer {
        let _ = writeln!(out, "transfer = {}", string(t.name()));
    }
}

/// `[environment]`: the uniform radiance, or the map (a built-in's name, a file's
/// absolute path), turned and scaled. None for black.
fn environment(out: &mut String, scene: &Scene) -> Result<(), String> {
    let Some(e) = &scene.environment_map else {
        if scene.environment != DVec3::ZERO {
            let _ = writeln!(
                out,
                "\n[environment]\nradiance = {}",
                vec3(scene.environment)
            );
        }
        return Ok(());
    };
    if scene.environment != DVec3::ZERO {
        return Err(
            "the environment is a uniform radiance and a map at once, which a scene file \
             cannot hold (it takes one of them)"
                .into(),
        );
    }
    let source = match &e.source {
        Source::Builtin(b) => format!("builtin = {}", string(b.name())),
        Source::File(path) => {
            let path = std::path::absolute(path)
                .map_err(|err| format!("the map '{}': {err}", path.display()))?;
            let path = path
                .to_str()
                .ok_or_else(|| format!("the map's path '{}' is not UTF-8 text", path.display()))?;
            format!("map = {}", string(path))
        }
    };
    let _ = writeln!(
        out,
        "\n[environment]\n{source}\nrotation_deg = {}\nintensity = {}",
        num(e.rotation_deg),
        num(e.intensity)
    );
    Ok(())
}

fn light(out: &mut String, light: &Light) -> Result<(), String> {
    let direction = direction_input(light.direction)
        .ok_or("its direction has no input that normalises to it exactly")?;
    let _ = writeln!(
        out,
        "\n[[light]]\ndirection = {}\nradiance = {}",
        vec3(direction),
        vec3(light.radiance)
    );
    Ok(())
}

fn ball(out: &mut String, b: &Ball) -> Result<(), String> {
    let material = emissive(
        anisotropic(material(&b.material)?, &b.material),
        &b.material,
    );
    let label = b.label.map_or(String::new(), |l| {
        format!("label = {}\n", string(l.as_str()))
    });
    let _ = writeln!(
        out,
        "\n[[ball]]\nposition = {}\nradius = {}\nroughness = {}\nmodel = {}\n{label}material = {material}",
        vec3(b.center),
        num(b.radius),
        num(b.roughness),
        string(b.model.name())
    );
    Ok(())
}

/// The inline table `table` with the material's anisotropy keys where its lobe is
/// anisotropic.
fn anisotropic(table: String, m: &Material) -> String {
    if !m.is_anisotropic() {
        return table;
    }
    let keys = format!(
        ", anisotropy = {}, anisotropy_rotation = {} }}",
        num(m.anisotropy),
        num(m.anisotropy_rotation)
    );
    match table.strip_suffix(" }") {
        Some(head) => head.to_string() + &keys,
        None => table,
    }
}

/// The inline table `table` with the material's `emission` where it emits.
fn emissive(table: String, m: &Material) -> String {
    if m.emission == DVec3::ZERO {
        return table;
    }
    match table.strip_suffix(" }") {
        Some(head) => format!("{head}, emission = {} }}", vec3(m.emission)),
        None => table,
    }
}

/// The material's inline table, colours as they were written where an input with the
/// fewest decimals decodes to them exactly: a metal by the `albedo` whose `pow 2.2` is its
/// `f0` (the homework's copper: `[0.7216, 0.451, 0.2]`), else by its linear `f0`; the
/// engines' material by an sRGB `base_color` that decodes to it exactly; a dielectric by an
/// `albedo` whose `pow 2.2` is its base exactly.
fn material(m: &Material) -> Result<String, String> {
    let text = material_base(m)?;
    let c = m.clearcoat;
    if !c.is_on() {
        return Ok(text);
    }
    let body = text.trim_end_matches('}').trim_end();
    Ok(format!(
        "{body}, clearcoat = {}, clearcoat_roughness = {}, clearcoat_ior = {} }}",
        num(c.weight),
        num(c.roughness),
        num(c.ior)
    ))
}

/// [`material`] without its clear coat.
fn material_base(m: &Material) -> Result<String, String> {
    let pow = |c: f64| gamma22_decode([c; 3]).x;
    if m.metallic == 1.0 && m.diffuse == DVec3::ZERO && m.ior == DEFAULT_IOR {
        return Ok(match short3(m.f0, pow, |d| d.powf(1.0 / 2.2)) {
            Some(albedo) => format!("{{ kind = \"metal\", albedo = {} }}", vec3(albedo)),
            None => format!("{{ kind = \"metal\", f0 = {} }}", vec3(m.f0)),
        });
    }
    let decode = |c: f64| srgb_decode([c; 3]).x;
    if m.f0 == m.diffuse {
        if let Some(base) = invert3(m.f0, decode, srgb_encode_guess) {
            return Ok(format!(
                "{{ base_color = {}, metallic = {}, ior = {} }}",
                vec3(base),
                num(m.metallic),
                num(m.ior)
            ));
        }
    }
    if m.f0 == m.diffuse {
        // Not every linear value is the sRGB decode of a double (the decode's slope is
        // above 1 there): the linear value itself.
        return Ok(format!(
            "{{ base_color_linear = {}, metallic = {}, ior = {} }}",
            vec3(m.f0),
            num(m.metallic),
            num(m.ior)
        ));
    }
    if m.metallic == 0.0 && m.f0 == DVec3::ZERO {
        if let Some(albedo) = invert3(m.diffuse, pow, |d| d.powf(1.0 / 2.2)) {
            return Ok(format!(
                "{{ kind = \"dielectric\", albedo = {}, ior = {} }}",
                vec3(albedo),
                num(m.ior)
            ));
        }
    }
    Err(format!(
        "its material (metallic {}, F0 {:?}, base {:?}, IOR {}) has no exact scene-file form",
        m.metallic,
        m.f0.to_array(),
        m.diffuse.to_array(),
        m.ior
    ))
}

/// The sRGB encoding (IEC 61966-2-1), the starting guess for the decode's exact input.
fn srgb_encode_guess(d: f64) -> f64 {
    if d <= 0.0031308 {
        d * 12.92
    } else {
        1.055 * d.powf(1.0 / 2.4) - 0.055
    }
}

/// Per channel, an input in `[0, 1]` that `forward` maps to `target`'s channel exactly,
/// searched around `guess` of it.
fn invert3(
    target: DVec3,
    forward: impl Fn(f64) -> f64,
    guess: impl Fn(f64) -> f64,
) -> Option<DVec3> {
    let one = |t: f64| {
        let g = guess(t).clamp(0.0, 1.0);
        // The fewest decimals first: a colour typed as 0.7216 is written back as typed.
        let short = (1..=17)
            .filter_map(|digits| format!("{g:.digits$}").parse::<f64>().ok())
            .find(|&c| (0.0..=1.0).contains(&c) && forward(c) == t);
        if short.is_some() {
            return short;
        }
        (0..=SEARCH_ULPS)
            .flat_map(|k| [step(g, k as i64), step(g, -(k as i64))])
            .filter(|c| (0.0..=1.0).contains(c))
            .find(|&c| forward(c) == t)
    };
    Some(DVec3::new(one(target.x)?, one(target.y)?, one(target.z)?))
}

/// Most decimals of a colour written as typed ([`short3`]): more, and the linear value is
/// the plainer form.
const TYPED_DIGITS: usize = 6;

/// Per channel, an input in `[0, 1]` of at most [`TYPED_DIGITS`] decimals that `forward`
/// maps to `target`'s channel exactly (a colour as a person types it), near `guess` of it.
fn short3(
    target: DVec3,
    forward: impl Fn(f64) -> f64,
    guess: impl Fn(f64) -> f64,
) -> Option<DVec3> {
    let one = |t: f64| {
        let g = guess(t).clamp(0.0, 1.0);
        (1..=TYPED_DIGITS)
            .filter_map(|digits| format!("{g:.digits$}").parse::<f64>().ok())
            .find(|&c| (0.0..=1.0).contains(&c) && forward(c) == t)
    };
    Some(DVec3::new(one(target.x)?, one(target.y)?, one(target.z)?))
}

/// The double `k` steps from the non-negative `x` (towards +infinity for positive `k`).
fn step(x: f64, k: i64) -> f64 {
    f64::from_bits(x.to_bits().saturating_add_signed(k))
}

/// A direction that normalises (as the parser does) to `d` exactly: `d` itself where it
/// is its own normalisation, else `d` scaled (by 1 to 17 in steps of 1/16) with each
/// component moved up to [`DIRECTION_ULPS`] doubles, the first that does (each such try
/// rounds anew, so a few hundred find one).
fn direction_input(d: DVec3) -> Option<DVec3> {
    let n = DIRECTION_ULPS as i64;
    let nudges =
        (-n..=n).flat_map(move |i| (-n..=n).flat_map(move |j| (-n..=n).map(move |k| [i, j, k])));
    (0..=256)
        .map(|s| 1.0 + s as f64 / 16.0)
        .flat_map(|s| nudges.clone().map(move |n| (s, n)))
        .map(|(s, n)| {
            let v = (d * s).to_array();
            DVec3::from_array([0, 1, 2].map(|c| step_signed(v[c], n[c])))
        })
        .filter(|v| v.is_finite() && v.length_squared() > 0.0)
        .find(|v| v.normalize() == d)
}

/// How many doubles either way [`direction_input`] moves each component.
const DIRECTION_ULPS: u64 = 2;

/// The double `k` steps from `x` away from zero (towards it for negative `k`); zero stays.
fn step_signed(x: f64, k: i64) -> f64 {
    if x == 0.0 {
        return x;
    }
    f64::from_bits(x.to_bits().wrapping_add_signed(k))
}

/// A number in Rust's shortest round-trip form, which TOML reads as the same double
/// (`35.0`, `1e-7`, `1e300`).
fn num(v: f64) -> String {
    format!("{v:?}")
}

fn vec3(v: DVec3) -> String {
    format!("[{}, {}, {}]", num(v.x), num(v.y), num(v.z))
}

/// A TOML basic string.
fn string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if c.is_control() => {
                let _ = write!(out, "\\u{:04X}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}
