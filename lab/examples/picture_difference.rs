//! How far apart two pictures of the same size are, channel by channel: the mean absolute
//! difference in 1/255 and how many channels differ by more than 32/255 and 64/255. The
//! figure the docs quote for two seeds of a Monte Carlo render (its noise) or for a picture
//! against the same picture converged (docs/design/anisotropy.md, "Sampling the anisotropic
//! lobe"; docs/design/coat.md).
//!
//! ```text
//! cargo run --release -p shadeballs-lab --example picture_difference -- A.png B.png
//! ```

use anyhow::{bail, Context, Result};

fn main() -> Result<()> {
    let paths: Vec<String> = std::env::args().skip(1).collect();
    let [a, b] = paths.as_slice() else {
        bail!("usage: picture_difference A.png B.png");
    };
    let read = |path: &str| {
        image::open(path)
            .with_context(|| format!("cannot read '{path}'"))
            .map(|i| i.to_rgb8())
    };
    let (a, b) = (read(a)?, read(b)?);
    if a.dimensions() != b.dimensions() {
        bail!(
            "the pictures differ in size: {:?} and {:?}",
            a.dimensions(),
            b.dimensions()
        );
    }
    let differences: Vec<u32> = a
        .as_raw()
        .iter()
        .zip(b.as_raw())
        .map(|(x, y)| u32::from(x.abs_diff(*y)))
        .collect();
    let count = differences.len().max(1) as f64;
    let mean = differences.iter().map(|&d| f64::from(d)).sum::<f64>() / count;
    let over = |limit: u32| differences.iter().filter(|&&d| d > limit).count();
    println!(
        "mean {mean:.3}/255, channels > 32/255: {}, > 64/255: {}",
        over(32),
        over(64)
    );
    Ok(())
}
