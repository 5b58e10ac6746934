//! The mean linear radiance, per channel, over the pixels of each `.exr` that are not black:
//! one ball rendered with `background = "black"` and `--aa off`, so that the same pixels
//! count in every picture (docs/design/coat.md, "The lobe mode": a coated ball by the split
//! sum, the Monte Carlo, the lobe mode and the truth). With `--mask M.exr` the pixels that
//! count are those not black in `M` (the same ball under a uniform light), for pictures
//! where part of the ball is black: lit by one light, or by a map that is black but for a
//! sun (docs/design/coat.md, "Under a sun").
//!
//! ```text
//! cargo run --release -p shadeballs-lab --example ball_mean -- [--mask M.exr] A.exr [B.exr ...]
//! ```

use anyhow::{bail, Context, Result};

fn main() -> Result<()> {
    let mut paths: Vec<String> = std::env::args().skip(1).collect();
    let mask = match paths.iter().position(|a| a == "--mask") {
        Some(k) if k + 1 < paths.len() => {
            let m = read(&paths[k + 1])?;
            paths.drain(k..k + 2);
            Some(m)
        }
        Some(_) => bail!("--mask needs a picture: ball_mean [--mask M.exr] A.exr [B.exr ...]"),
        None => None,
    };
    if paths.is_empty() {
        bail!("usage: ball_mean [--mask M.exr] A.exr [B.exr ...]");
    }
    for path in &paths {
        let image = read(path)?;
        if let Some(m) = &mask {
            if m.dimensions() != image.dimensions() {
                bail!(
                    "'{path}' is {:?}, the mask {:?}",
                    image.dimensions(),
                    m.dimensions()
                );
            }
        }
        let counts = |k: usize| match &mask {
            Some(m) => m.as_raw()[3 * k..3 * k + 3] != [0.0; 3],
            None => image.as_raw()[3 * k..3 * k + 3] != [0.0; 3],
        };
        let counted: Vec<usize> = (0..image.as_raw().len() / 3)
            .filter(|&k| counts(k))
            .collect();
        if counted.is_empty() {
            bail!("'{path}' has no pixel that counts (none is not black)");
        }
        let n = counted.len() as f64;
        let sum = |raw: &[f32], c: usize, f: fn(f64) -> f64| {
            counted
                .iter()
                .map(|&k| f(f64::from(raw[3 * k + c])))
                .sum::<f64>()
        };
        let mean = [0, 1, 2].map(|c| sum(image.as_raw(), c, |x| x) / n);
        // A Monte Carlo picture's per-pixel standard errors, beside it: the mean's.
        let errors = path
            .strip_suffix(".exr")
            .map(|stem| format!("{stem}.stderr.exr"))
            .filter(|e| std::path::Path::new(e).exists());
        let se = match errors {
            Some(e_path) => {
                let e = read(&e_path)?;
                if e.dimensions() != image.dimensions() {
                    bail!("'{e_path}' is not the size of '{path}'");
                }
                let se = [0, 1, 2].map(|c| sum(e.as_raw(), c, |x| x * x).sqrt() / n);
                format!(", standard error {:.5} {:.5} {:.5}", se[0], se[1], se[2])
            }
            None => String::new(),
        };
        println!(
            "{path}: {} pixels, mean {:.5} {:.5} {:.5}{se}",
            counted.len(),
            mean[0],
            mean[1],
            mean[2]
        );
    }
    Ok(())
}

/// The linear picture at `path`.
fn read(path: &str) -> Result<image::Rgb32FImage> {
    Ok(image::open(path)
        .with_context(|| format!("cannot read '{path}'"))?
        .to_rgb32f())
}
