//! The mean linear radiance, per channel, over the pixels of each `.exr` that are not black:
//! one ball rendered with `background = "black"` and `--aa off`, so that the same pixels
//! count in every picture (docs/design/coat.md, "The lobe mode": a coated ball by the split
//! sum, the Monte Carlo, the lobe mode and the truth).
//!
//! ```text
//! cargo run --release -p shadeballs-lab --example ball_mean -- A.exr [B.exr ...]
//! ```

use anyhow::{bail, Context, Result};

fn main() -> Result<()> {
    let paths: Vec<String> = std::env::args().skip(1).collect();
    if paths.is_empty() {
        bail!("usage: ball_mean A.exr [B.exr ...]");
    }
    for path in &paths {
        let image = image::open(path)
            .with_context(|| format!("cannot read '{path}'"))?
            .to_rgb32f();
        let covered: Vec<&image::Rgb<f32>> = image.pixels().filter(|p| p.0 != [0.0; 3]).collect();
        if covered.is_empty() {
            bail!("'{path}' has no pixel that is not black");
        }
        let n = covered.len() as f64;
        let mean = [0, 1, 2].map(|c| covered.iter().map(|p| f64::from(p.0[c])).sum::<f64>() / n);
        println!(
            "{path}: {} pixels, mean {:.5} {:.5} {:.5}",
            covered.len(),
            mean[0],
            mean[1],
            mean[2]
        );
    }
    Ok(())
}
