//! Quadrature rules: fixed Gauss-Legendre for the bake, adaptive Gauss-Kronrod for the
//! precise reference.

/// Gauss-Legendre nodes and weights on `[0, 1]` (Newton's iteration on the Legendre
/// recurrence, Press et al., Numerical Recipes 3rd ed., section 4.6.1).
pub fn gauss_legendre_unit(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut nodes = vec![0.0; n];
    let mut weights = vec![0.0; n];
    let nf = n as f64;
    for i in 0..n.div_ceil(2) {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (nf + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let kf = k as f64;
                let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
                p0 = p1;
                p1 = p2;
            }
            // p1 = P_n(x), p0 = P_{n-1}(x).
            dp = nf * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-15 {
                break;
            }
        }
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        // Map [-1, 1] to [0, 1].
        nodes[i] = 0.5 * (1.0 - x);
        nodes[n - 1 - i] = 0.5 * (1.0 + x);
        weights[i] = 0.5 * w;
        weights[n - 1 - i] = 0.5 * w;
    }
    (nodes, weights)
}

// Kronrod 15-point nodes and weights, and the embedded 7-point Gauss weights
// (Piessens et al. 1983, QUADPACK, routine QK15).
const XGK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
const WGK: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_18,
    0.140_653_259_715_525_92,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_727_83,
];
const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// One Gauss-Kronrod 7-15 panel: (Kronrod estimate, |Kronrod - Gauss|).
fn gk15<F: Fn(f64) -> f64>(f: &F, a: f64, b: f64) -> (f64, f64) {
    let c = 0.5 * (a + b);
    let h = 0.5 * (b - a);
    let fc = f(c);
    let mut k = fc * WGK[7];
    let mut g = fc * WG[3];
    for j in 0..7 {
        let x = h * XGK[j];
        let s = f(c - x) + f(c + x);
        k += WGK[j] * s;
        if j % 2 == 1 {
            g += WG[j / 2] * s;
        }
    }
    (k * h, ((k - g) * h).abs())
}

/// Most panels the adaptive rule keeps before it returns its best estimate.
const MAX_PANELS: usize = 4000;

/// Globally adaptive Gauss-Kronrod integral of `f` over `[a, b]` to absolute tolerance `tol`
/// (Piessens et al. 1983, QUADPACK's QAG strategy): keep every panel with its error
/// estimate and bisect the worst one until the summed error estimate is within `tol`.
/// Unlike bisecting with a halved tolerance, effort goes where the error is, so an
/// integrand with a tiny feature costs a few extra panels, not an exhaustive tree.
pub fn adaptive<F: Fn(f64) -> f64>(f: &F, a: f64, b: f64, tol: f64) -> f64 {
    if b <= a {
        return 0.0;
    }
    // (error, value, a, b) per panel.
    let (v, e) = gk15(f, a, b);
    let mut panels = vec![(e, v, a, b)];
    let mut total_err = e;
    while total_err > tol && panels.len() < MAX_PANELS {
        let worst = panels
            .iter()
            .enumerate()
            .max_by(|x, y| x.1 .0.total_cmp(&y.1 .0))
            .map(|(k, _)| k)
            .unwrap_or(0);
        let (err, _, pa, pb) = panels.swap_remove(worst);
        let m = 0.5 * (pa + pb);
        if m <= pa || m >= pb {
            // The panel cannot be split further in f64: keep it as it is.
            panels.push((0.0, gk15(f, pa, pb).0, pa, pb));
            total_err -= err;
            continue;
        }
        let (lv, le) = gk15(f, pa, m);
        let (rv, re) = gk15(f, m, pb);
        total_err += le + re - err;
        panels.push((le, lv, pa, m));
        panels.push((re, rv, m, pb));
    }
    panels.iter().map(|p| p.1).sum()
}
