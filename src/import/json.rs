//! Reading a glTF document's values with their place in the file named in every error
//! (`materials[3].pbrMetallicRoughness.metallicFactor: ...`).

use serde_json::{Map, Value};

/// An error: `at: message`.
pub(crate) fn err(at: &str, message: impl std::fmt::Display) -> String {
    format!("{at}: {message}")
}

/// The object at `v` (`at` names it), or an error.
pub(crate) fn object<'a>(v: &'a Value, at: &str) -> Result<&'a Map<String, Value>, String> {
    v.as_object().ok_or_else(|| err(at, "is not a JSON object"))
}

/// The array under `key` of `obj` (empty when absent), or an error when it is no array.
pub(crate) fn array<'a>(
    obj: &'a Map<String, Value>,
    key: &str,
    at: &str,
) -> Result<&'a [Value], String> {
    match obj.get(key) {
        None => Ok(&[]),
        Some(Value::Array(a)) => Ok(a),
        Some(_) => Err(err(&format!("{at}.{key}"), "is not an array")),
    }
}

/// The number under `key` of `obj`, `default` when absent, within `[lo, hi]`.
pub(crate) fn number(
    obj: &Map<String, Value>,
    key: &str,
    at: &str,
    default: f64,
    (lo, hi): (f64, f64),
) -> Result<f64, String> {
    let at = format!("{at}.{key}");
    let Some(v) = obj.get(key) else {
        return Ok(default);
    };
    let x = v
        .as_f64()
        .ok_or_else(|| err(&at, format!("{v} is not a number")))?;
    if !(lo..=hi).contains(&x) {
        return Err(err(&at, format!("{x} is outside [{lo}, {hi}]")));
    }
    Ok(x)
}

/// The `N` numbers under `key` of `obj`, `default` when absent, each within `[lo, hi]`.
pub(crate) fn numbers<const N: usize>(
    obj: &Map<String, Value>,
    key: &str,
    at: &str,
    default: [f64; N],
    (lo, hi): (f64, f64),
) -> Result<[f64; N], String> {
    let at = format!("{at}.{key}");
    let Some(v) = obj.get(key) else {
        return Ok(default);
    };
    let a = v
        .as_array()
        .filter(|a| a.len() == N)
        .ok_or_else(|| err(&at, format!("is not an array of {N} numbers")))?;
    let mut out = [0.0; N];
    for (i, (o, x)) in out.iter_mut().zip(a).enumerate() {
        let x = x
            .as_f64()
            .ok_or_else(|| err(&format!("{at}[{i}]"), format!("{x} is not a number")))?;
        if !(lo..=hi).contains(&x) {
            return Err(err(
                &format!("{at}[{i}]"),
                format!("{x} is outside [{lo}, {hi}]"),
            ));
        }
        *o = x;
    }
    Ok(out)
}

/// The index under `key` of `obj` (`None` when absent) into a list of `len` items called
/// `what`.
pub(crate) fn index(
    obj: &Map<String, Value>,
    key: &str,
    at: &str,
    (what, len): (&str, usize),
) -> Result<Option<usize>, String> {
    let Some(v) = obj.get(key) else {
        return Ok(None);
    };
    let at = format!("{at}.{key}");
    let i = v
        .as_u64()
        .ok_or_else(|| err(&at, format!("{v} is not an index")))?;
    if i as usize >= len {
        return Err(err(
            &at,
            format!("refers to {what} {i}, but the file has {len} {what}s"),
        ));
    }
    Ok(Some(i as usize))
}

/// The string under `key` of `obj`, if any.
pub(crate) fn string<'a>(obj: &'a Map<String, Value>, key: &str) -> Option<&'a str> {
    obj.get(key).and_then(Value::as_str)
}
