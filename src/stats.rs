//! Small statistics shared by the viewer's readouts and the lab's measurements.

/// The median of `v` (the upper of the two middle values for an even count; NaN when
/// empty), sorting it.
pub fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}
