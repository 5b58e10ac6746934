//! Generators of scene files for the fuzz tests: structured files, either clean (every
//! value valid) or noisy (each field sometimes an edge value, a wrong type, missing,
//! repeated or unknown); those files mutated and truncated at random; and garbage.

use proptest::prelude::*;
use proptest::sample::select;

/// A TOML float for any f64 (`nan`, `inf`, `-inf` for the specials).
fn toml_float(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf" } else { "-inf" }.into()
    } else {
        format!("{x:?}")
    }
}

/// A number in `[lo, hi]`; with `noise`, sometimes anything a file could hold there.
fn number(lo: f64, hi: f64, noise: bool) -> impl Strategy<Value = String> {
    prop_oneof![
        if noise { 8 } else { 1 } => (lo..=hi).prop_map(toml_float),
        noise as u32 => select(vec![
            "0", "1", "-1", "-0.0", "0.02", "1e12", "1.0000000000000002e12", "-1e12", "1e13", "1e300",
            "1e-300", "5e-324", "nan", "-nan", "inf", "-inf", "1e999", "0x10", "1_000", "180", "3.4e38",
        ])
        .prop_map(String::from),
        noise as u32 => any::<f64>().prop_map(toml_float),
        noise as u32 => select(vec!["\"1\"", "true", "[1, 2]", "{ a = 1 }", "1979-05-27", "'x'", "[]"]).prop_map(String::from),
    ]
}

/// `[x, y, z]`; with `noise`, sometimes 2 or 4 components, or a scalar.
fn vec3(lo: f64, hi: f64, noise: bool) -> impl Strategy<Value = String> {
    let n = move || number(lo, hi, noise);
    let w = noise as u32;
    prop_oneof![
        8 => (n(), n(), n()).prop_map(|(a, b, c)| format!("[{a}, {b}, {c}]")),
        w => (n(), n()).prop_map(|(a, b)| format!("[{a}, {b}]")),
        w => (n(), n()).prop_map(|(a, b)| format!("[{a}, {b}, {a}, {b}]")),
        w => n(),
    ]
}

fn name(valid: &'static [&'static str], noise: bool) -> impl Strategy<Value = String> {
    prop_oneof![
        6 => select(valid).prop_map(|v| format!("\"{v}\"")),
        noise as u32 => select(vec!["\"bogus\"", "\"\"", "1", "\"METAL\""]).prop_map(String::from),
    ]
}

/// `true` or `false`; with `noise`, sometimes not a boolean.
fn flag(noise: bool) -> impl Strategy<Value = String> {
    prop_oneof![
        6 => select(vec!["true", "false"]).prop_map(String::from),
        noise as u32 => select(vec!["\"yes\"", "1", "\"true\"", "[true]"]).prop_map(String::from),
    ]
}

/// `key = value` lines of a table; with `noise`, a field is sometimes missing or repeated,
/// and the table sometimes has an unknown key.
fn fields(all: Vec<BoxedStrategy<String>>, noise: bool) -> impl Strategy<Value = String> {
    let n = all.len();
    let keep = if noise { 0..10u8 } else { 1..9u8 };
    let extra = if noise { 0..20u8 } else { 1..2u8 };
    (all, prop::collection::vec(keep, n), extra).prop_map(|(lines, keep, extra)| {
        let mut s = String::new();
        for (line, k) in lines.iter().zip(keep) {
            if k > 0 {
                s += line;
                s.push('\n');
            }
            if k == 9 {
                s += line; // repeated key
                s.push('\n');
            }
        }
        if extra == 0 {
            s += "colour = 1\n";
        }
        s
    })
}

fn kv(key: &'static str, value: impl Strategy<Value = String> + 'static) -> BoxedStrategy<String> {
    value.prop_map(move |v| format!("{key} = {v}")).boxed()
}

fn material(noise: bool) -> impl Strategy<Value = String> {
    let kind = name(&["metal", "metal", "dielectric"], noise);
    let colour = move || vec3(0.0, 1.0, noise).prop_map(Some);
    let which = if noise { 0..4u8 } else { 0..2u8 };
    (kind, colour(), colour(), which).prop_map(|(kind, albedo, f0, which)| {
        let mut parts = vec![format!("kind = {kind}")];
        match which {
            0 => parts.extend(albedo.map(|a| format!("albedo = {a}"))),
            1 => parts.extend(f0.map(|f| format!("f0 = {f}"))),
            _ => {
                parts.extend(albedo.map(|a| format!("albedo = {a}")));
                parts.extend(f0.map(|f| format!("f0 = {f}")));
            }
        }
        format!("{{ {} }}", parts.join(", "))
    })
}

fn ball(noise: bool) -> impl Strategy<Value = String> {
    let w = noise as u32;
    let grid = prop_oneof![
        6 => (0u32..3, 0u32..6).prop_map(|(r, c)| format!("[{r}, {c}]")),
        w => select(vec!["[-1, 0]", "[4294967295, 4294967295]", "[4294967296, 0]", "[0]", "[0.5, 1]"]).prop_map(String::from),
    ];
    let place = prop_oneof![
        1 => kv("grid", grid),
        1 => kv("position", vec3(-200.0, 200.0, noise)),
        w => vec3(-200.0, 200.0, noise).prop_map(|p| format!("position = {p}\ngrid = [0, 0]")),
    ];
    let bools = if noise {
        vec!["true", "false", "1"]
    } else {
        vec!["true", "false"]
    };
    fields(
        vec![
            place.boxed(),
            kv("radius", number(1e-3, 60.0, noise)),
            kv("roughness", number(0.0, 1.0, noise)),
            kv("multiple_scattering", select(bools).prop_map(String::from)),
            kv("material", material(noise)),
        ],
        noise,
    )
    .prop_map(|f| format!("[[ball]]\n{f}"))
}

fn light(noise: bool) -> impl Strategy<Value = String> {
    let fields_ = vec![
        kv("direction", vec3(-1.0, 1.0, noise)),
        kv("radiance", vec3(0.0, 10.0, noise)),
    ];
    fields(fields_, noise).prop_map(|f| format!("[[light]]\n{f}"))
}

fn camera(noise: bool) -> impl Strategy<Value = String> {
    fields(
        vec![
            kv("position", vec3(-400.0, 400.0, noise)),
            kv("target", vec3(-10.0, 10.0, noise)),
            kv("vfov_deg", number(1.0, 179.0, noise)),
        ],
        noise,
    )
    .prop_map(|f| format!("[camera]\n{f}"))
}

/// A structured scene file: clean (every value valid) a third of the time, else noisy.
pub fn scene_text() -> impl Strategy<Value = String> {
    prop_oneof![1 => structured(false), 2 => structured(true)]
}

fn structured(noise: bool) -> impl Strategy<Value = String> {
    let top = fields(
        vec![
            kv("preset", name(&["accurate", "games202"], noise)),
            kv(
                "geometry",
                name(&["schlick", "smith", "smith-correlated"], noise),
            ),
            kv("exposure", number(0.1, 4.0, noise)),
            kv("labels", flag(noise)),
        ],
        noise,
    );
    let environment = fields(vec![kv("radiance", vec3(0.0, 2.0, noise))], noise)
        .prop_map(|f| format!("[environment]\n{f}"));
    let balls = if noise { 0..5usize } else { 1..5usize };
    (
        top,
        prop::option::of(camera(noise)),
        prop::option::of(environment),
        prop::collection::vec(light(noise), 0..3),
        prop::collection::vec(ball(noise), balls),
    )
        .prop_map(|(top, camera, env, lights, balls)| {
            let mut s = top;
            for t in camera.into_iter().chain(env).chain(lights).chain(balls) {
                s += &t;
            }
            s
        })
}

/// A structured scene with 1 to 6 edits: a range deleted, a token inserted, a range
/// duplicated (positions as fractions of the text, on character boundaries).
pub fn mutated() -> impl Strategy<Value = String> {
    let token = select(vec![
        "[",
        "]",
        "[[",
        "]]",
        "{",
        "}",
        "=",
        ",",
        "\"",
        "'",
        "'''",
        "\"\"\"",
        "#",
        "\n",
        "\\",
        ".",
        "-",
        "nan",
        "inf",
        "1e999",
        "[[ball]]",
        "[camera]",
        "radius",
        "= =",
        "\u{0}",
        "\u{feff}",
        "\u{1F600}",
    ]);
    let edit = (0.0..1.0f64, 0.0..1.0f64, 0..3u8, token);
    (scene_text(), prop::collection::vec(edit, 1..6)).prop_map(|(text, edits)| {
        let mut chars: Vec<char> = text.chars().collect();
        for (a, b, op, token) in edits {
            let n = chars.len();
            let (i, j) = ((a * n as f64) as usize, (b * n as f64) as usize);
            let (i, j) = (i.min(j), i.max(j).min(n));
            match op {
                0 => {
                    chars.drain(i..j.min(i + 40));
                }
                1 => {
                    let t: Vec<char> = token.chars().collect();
                    chars.splice(i..i, t);
                }
                _ => {
                    let copy: Vec<char> = chars[i..j.min(i + 80)].to_vec();
                    chars.splice(j..j, copy);
                }
            }
        }
        chars.into_iter().collect()
    })
}

/// A structured scene cut at a random character.
pub fn truncated() -> impl Strategy<Value = String> {
    (scene_text(), 0.0..1.0f64).prop_map(|(text, at)| {
        let cut = (at * text.chars().count() as f64) as usize;
        text.chars().take(cut).collect()
    })
}

/// Random text, random bytes (lossily decoded), and random TOML-ish token soup.
pub fn garbage() -> impl Strategy<Value = String> {
    let soup = prop::collection::vec(
        select(vec![
            "[[ball]]", "\n", "radius", "=", "1", "[", "]", "{", "}", ",", "\"", "kind", "metal",
            "nan", " ",
        ]),
        0..60,
    )
    .prop_map(|t| t.concat());
    prop_oneof![
        any::<String>(),
        prop::collection::vec(any::<u8>(), 0..400)
            .prop_map(|b| String::from_utf8_lossy(&b).into_owned()),
        soup,
    ]
}
