//! The BRDF maths: known values, limits, symmetry.
