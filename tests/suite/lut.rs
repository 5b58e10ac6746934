use shadeballs::brdf::Geometry;
use shadeballs::lut::*;

#[test]
fn scratch() {
    for &(mu, r) in &[(0.0, 0.0), (1e-6, 0.02), (1e-5, 0.02), (1e-4, 0.02), (2.5e-4, 0.02), (1e-3, 0.02), (0.01, 0.02), (0.0, 0.5), (1e-4, 0.5), (1.0, 1.0), (0.5, 1.0), (0.1, 1.0), (0.01, 0.5), (0.5, 0.5), (1.0, 0.5), (0.1, 0.2)] {
        let t = std::time::Instant::now();
        let re = e_reference(mu, r, Geometry::Schlick);
        let dt = t.elapsed();
        let q: Vec<String> = [8usize, 16, 32, 64].iter().map(|&n| format!("{:.2e}", Estimator::new(Method::Quadrature, PointSet::Sobol, n).e(mu, r, Geometry::Schlick, 0) - re)).collect();
        let mut v = Estimator::new(Method::Vndf, PointSet::Sobol, 1 << 16);
        let vv = v.e(mu, r, Geometry::Schlick, 0);
        println!("mu={mu} r={r} ref={re:.8} ({dt:?}) quad-ref={q:?} vndf64k={vv:.8}");
    }
}

