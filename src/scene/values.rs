//! Checked value types for the scene file: each rejects bad input while toml deserialises
//! it, so the error carries the value's line and column (and `file.rs` adds the key's
//! name). Numbers print in their shortest form, with an exponent from 1e6 up
//! (`super::short_number`): 1e30 and 1e13, not 31 or 14 digits.

use std::str::FromStr;

use glam::DVec3;
use serde::{Deserialize, Deserializer};

use super::{short_number, short_numbers, MAX_MAGNITUDE};

/// Exactly `N` numbers: an array with more or fewer is an error (serde's fixed-size arrays
/// ignore extra values in toml).
fn exactly<const N: usize, T: Copy + Default>(v: &[T]) -> Result<[T; N], String> {
    if v.len() != N {
        return Err(format!(
            "expected {N} values, found {} (an array of exactly {N})",
            v.len()
        ));
    }
    let mut out = [T::default(); N];
    out.copy_from_slice(v);
    Ok(out)
}

fn finite3(v: &[f64]) -> Result<DVec3, String> {
    let v: [f64; 3] = exactly(v)?;
    if !v.iter().all(|c| c.is_finite()) {
        return Err(format!(
            "{} has a NaN or infinite component",
            short_numbers(&v)
        ));
    }
    if v.iter().any(|c| c.abs() > MAX_MAGNITUDE) {
        return Err(format!(
            "{} has a component beyond {MAX_MAGNITUDE:e} in magnitude",
            short_numbers(&v)
        ));
    }
    Ok(DVec3::from_array(v))
}

/// Any finite 3-vector (a position).
#[derive(Deserialize, Clone, Copy, Debug)]
#[serde(try_from = "Vec<f64>")]
pub(crate) struct Finite3(pub DVec3);

impl TryFrom<Vec<f64>> for Finite3 {
    type Error = String;
    fn try_from(v: Vec<f64>) -> Result<Self, String> {
        finite3(&v).map(Finite3)
    }
}

/// A ball's `grid = [row, col]`: exactly two whole numbers.
#[derive(Deserialize, Clone, Copy, Debug)]
#[serde(try_from = "Vec<u32>")]
pub(crate) struct Grid(pub [u32; 2]);

impl TryFrom<Vec<u32>> for Grid {
    type Error = String;
    fn try_from(v: Vec<u32>) -> Result<Self, String> {
        exactly(&v).map(Grid)
    }
}

/// A non-zero finite direction, normalised.
#[derive(Deserialize, Clone, Copy, Debug)]
#[serde(try_from = "Vec<f64>")]
pub(crate) struct Direction(pub DVec3);

impl TryFrom<Vec<f64>> for Direction {
    type Error = String;
    fn try_from(v: Vec<f64>) -> Result<Self, String> {
        let d = finite3(&v)?;
        if d.length_squared() == 0.0 || !d.length_squared().is_finite() {
            return Err(format!(
                "{} has zero (or unrepresentable) length",
                short_numbers(&v)
            ));
        }
        Ok(Direction(d.normalize()))
    }
}

/// A colour with every channel in `[0, 1]`.
#[derive(Deserialize, Clone, Copy, Debug)]
#[serde(try_from = "Vec<f64>")]
pub(crate) struct Colour(pub DVec3);

impl TryFrom<Vec<f64>> for Colour {
    type Error = String;
    fn try_from(v: Vec<f64>) -> Result<Self, String> {
        let c = finite3(&v)?;
        if c.min_element() < 0.0 || c.max_element() > 1.0 {
            return Err(format!(
                "{} has a channel outside [0, 1]",
                short_numbers(&v)
            ));
        }
        Ok(Colour(c))
    }
}

/// A radiance: finite, non-negative channels.
#[derive(Deserialize, Clone, Copy, Debug)]
#[serde(try_from = "Vec<f64>")]
pub(crate) struct Radiance(pub DVec3);

impl TryFrom<Vec<f64>> for Radiance {
    type Error = String;
    fn try_from(v: Vec<f64>) -> Result<Self, String> {
        let c = finite3(&v)?;
        if c.min_element() < 0.0 {
            return Err(format!("{} has a negative channel", short_numbers(&v)));
        }
        Ok(Radiance(c))
    }
}

/// A finite number in `(0, MAX_MAGNITUDE]` (radius, exposure).
#[derive(Deserialize, Clone, Copy, Debug)]
#[serde(try_from = "f64")]
pub(crate) struct Positive(pub f64);

impl TryFrom<f64> for Positive {
    type Error = String;
    fn try_from(v: f64) -> Result<Self, String> {
        if v.is_finite() && v > 0.0 && v <= MAX_MAGNITUDE {
            Ok(Positive(v))
        } else {
            Err(format!(
                "{} must be a number greater than 0 and at most {MAX_MAGNITUDE:e}",
                short_number(v)
            ))
        }
    }
}

/// A roughness in `[0, 1]`.
#[derive(Deserialize, Clone, Copy, Debug)]
#[serde(try_from = "f64")]
pub(crate) struct Roughness(pub f64);

impl TryFrom<f64> for Roughness {
    type Error = String;
    fn try_from(v: f64) -> Result<Self, String> {
        if (0.0..=1.0).contains(&v) {
            Ok(Roughness(v))
        } else {
            Err(format!("roughness {} is outside [0, 1]", short_number(v)))
        }
    }
}

/// A metallic weight in `[0, 1]`.
#[derive(Deserialize, Clone, Copy, Debug)]
#[serde(try_from = "f64")]
pub(crate) struct Metallic(pub f64);

impl TryFrom<f64> for Metallic {
    type Error = String;
    fn try_from(v: f64) -> Result<Self, String> {
        if (0.0..=1.0).contains(&v) {
            Ok(Metallic(v))
        } else {
            Err(format!("metallic {} is outside [0, 1]", short_number(v)))
        }
    }
}

/// An anisotropy strength in `[0, 1]` (glTF's `anisotropyStrength`).
#[derive(Deserialize, Clone, Copy, Debug)]
#[serde(try_from = "f64")]
pub(crate) struct Anisotropy(pub f64);

impl TryFrom<f64> for Anisotropy {
    type Error = String;
    fn try_from(v: f64) -> Result<Self, String> {
        if (0.0..=1.0).contains(&v) {
            Ok(Anisotropy(v))
        } else {
            Err(format!("anisotropy {} is outside [0, 1]", short_number(v)))
        }
    }
}

/// An anisotropy rotation in radians, finite and within `[-2 pi, 2 pi]` (glTF's
/// `anisotropyRotation`; beyond a turn is a slip of units, degrees for radians).
#[derive(Deserialize, Clone, Copy, Debug)]
#[serde(try_from = "f64")]
pub(crate) struct AnisotropyRotation(pub f64);

impl TryFrom<f64> for AnisotropyRotation {
    type Error = String;
    fn try_from(v: f64) -> Result<Self, String> {
        let turn = std::f64::consts::TAU;
        if v.is_finite() && (-turn..=turn).contains(&v) {
            Ok(AnisotropyRotation(v))
        } else {
            Err(format!(
                "anisotropy_rotation {} is outside [-2 pi, 2 pi] (radians)",
                short_number(v)
            ))
        }
    }
}

/// A weight in `[0, 1]` (a clear coat's); its error names the key before it.
#[derive(Deserialize, Clone, Copy, Debug)]
#[serde(try_from = "f64")]
pub(crate) struct Unit(pub f64);

impl TryFrom<f64> for Unit {
    type Error = String;
    fn try_from(v: f64) -> Result<Self, String> {
        if (0.0..=1.0).contains(&v) {
            Ok(Unit(v))
        } else {
            Err(format!("{} is outside [0, 1]", short_number(v)))
        }
    }
}

/// An index of refraction in [`super::IOR_RANGE`].
#[derive(Deserialize, Clone, Copy, Debug)]
#[serde(try_from = "f64")]
pub(crate) struct Ior(pub f64);

impl TryFrom<f64> for Ior {
    type Error = String;
    fn try_from(v: f64) -> Result<Self, String> {
        let (lo, hi) = super::IOR_RANGE;
        if (lo..=hi).contains(&v) {
            Ok(Ior(v))
        } else {
            Err(format!("ior {} is outside [{lo}, {hi}]", short_number(v)))
        }
    }
}

/// A vertical field of view in degrees, in `(0, 180)`.
#[derive(Deserialize, Clone, Copy, Debug)]
#[serde(try_from = "f64")]
pub(crate) struct Fov(pub f64);

impl TryFrom<f64> for Fov {
    type Error = String;
    fn try_from(v: f64) -> Result<Self, String> {
        if v > 0.0 && v < 180.0 {
            Ok(Fov(v))
        } else {
            Err(format!("vfov_deg {} is outside (0, 180)", short_number(v)))
        }
    }
}

/// A picture's size in pixels, `[width, height]`, each in `1..=MAX_IMAGE_SIDE` (`size`).
#[derive(Deserialize, Clone, Copy, Debug)]
#[serde(try_from = "Vec<i64>")]
pub(crate) struct ImageSize(pub (u32, u32));

impl TryFrom<Vec<i64>> for ImageSize {
    type Error = String;
    fn try_from(v: Vec<i64>) -> Result<Self, String> {
        let max = super::MAX_IMAGE_SIDE;
        let side = |n: i64| u32::try_from(n).ok().filter(|n| (1..=max).contains(n));
        match v[..] {
            [w, h] => match (side(w), side(h)) {
                (Some(w), Some(h)) => Ok(ImageSize((w, h))),
                _ => Err(format!("size [{w}, {h}]: each side must be in 1..={max}")),
            },
            _ => Err(format!(
                "size has {} numbers: it is [width, height]",
                v.len()
            )),
        }
    }
}

/// A lobe sample count, `1..=MAX_IBL_SAMPLES` (`ibl_samples`).
#[derive(Deserialize, Clone, Copy, Debug)]
#[serde(try_from = "i64")]
pub(crate) struct IblSamples(pub u32);

impl TryFrom<i64> for IblSamples {
    type Error = String;
    fn try_from(v: i64) -> Result<Self, String> {
        let n = u32::try_from(v).unwrap_or(0);
        crate::environment::lobe::check_ibl_samples(n)
            .map(IblSamples)
            .map_err(|_| {
                format!(
                    "ibl_samples {v} is outside 1..={}",
                    crate::environment::MAX_IBL_SAMPLES
                )
            })
    }
}

/// A name parsed with the type's `FromStr` (the `named_enum!` names).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Named<T>(pub T);

impl<'de, T: FromStr<Err = crate::Error>> Deserialize<'de> for Named<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        s.parse().map(Named).map_err(serde::de::Error::custom)
    }
}

/// Any finite number within `MAX_MAGNITUDE` (an angle in degrees).
#[derive(Deserialize, Clone, Copy, Debug)]
#[serde(try_from = "f64")]
pub(crate) struct Finite(pub f64);

impl TryFrom<f64> for Finite {
    type Error = String;
    fn try_from(v: f64) -> Result<Self, String> {
        if v.is_finite() && v.abs() <= MAX_MAGNITUDE {
            Ok(Finite(v))
        } else {
            Err(format!(
                "{} must be a finite number at most {MAX_MAGNITUDE:e} in magnitude",
                short_number(v)
            ))
        }
    }
}

/// A finite number in `[0, MAX_MAGNITUDE]` (an intensity).
#[derive(Deserialize, Clone, Copy, Debug)]
#[serde(try_from = "f64")]
pub(crate) struct NonNegative(pub f64);

impl TryFrom<f64> for NonNegative {
    type Error = String;
    fn try_from(v: f64) -> Result<Self, String> {
        if v.is_finite() && (0.0..=MAX_MAGNITUDE).contains(&v) {
            Ok(NonNegative(v))
        } else {
            Err(format!(
                "{} must be a number of at least 0 and at most {MAX_MAGNITUDE:e}",
                short_number(v)
            ))
        }
    }
}

/// `background = "black" | "environment" | [r, g, b]` (a radiance).
#[derive(Clone, Copy, Debug)]
pub(crate) struct BackgroundValue(pub crate::environment::Background);

impl<'de> Deserialize<'de> for BackgroundValue {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use crate::environment::Background;
        use serde::de::{Error, SeqAccess, Visitor};
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = BackgroundValue;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("\"black\", \"environment\" or a radiance [r, g, b]")
            }
            fn visit_str<E: Error>(self, s: &str) -> Result<BackgroundValue, E> {
                match s {
                    "black" => Ok(BackgroundValue(Background::Black)),
                    "environment" => Ok(BackgroundValue(Background::Environment)),
                    _ => Err(E::custom(format!(
                        "unknown background '{s}': expected black, environment or a radiance \
                         [r, g, b]"
                    ))),
                }
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<BackgroundValue, A::Error> {
                let mut v = Vec::new();
                while let Some(c) = seq.next_element::<f64>()? {
                    v.push(c);
                }
                Radiance::try_from(v)
                    .map(|r| BackgroundValue(Background::Colour(r.0)))
                    .map_err(A::Error::custom)
            }
        }
        d.deserialize_any(V)
    }
}
