//! Time every view of every registry model at its default resolution on one thread (the explorer's and
//! `benchmarks/bench_views.py`'s budget is 20 ms per view).
use brdf_core::views::{Incidence, albedo, lobe, polar, slice, sphere};
use brdf_core::{MODEL_SPECS, Model};
use std::time::Instant;

fn best<T>(mut f: impl FnMut() -> T) -> f64 {
    (0..5)
        .map(|_| {
            let t = Instant::now();
            std::hint::black_box(f());
            t.elapsed().as_secs_f64() * 1e3
        })
        .fold(f64::MAX, f64::min)
}

fn main() {
    rayon::ThreadPoolBuilder::new().num_threads(1).build_global().ok();
    let inc = Incidence::new(0.5, 0.0).unwrap();
    let thetas: Vec<f64> = (0..31).map(|k| (f64::from(k) * 3.0).min(89.0).to_radians()).collect();
    println!("{:22} {:>7} {:>7} {:>7} {:>7} {:>7}", "model", "polar", "lobe", "slice", "albedo", "sphere");
    for s in MODEL_SPECS {
        let m = Model::build(s.name, &[]).unwrap();
        let p = best(|| polar::polar(&m, inc, 360, false).unwrap());
        let l =
            best(|| lobe::lobe(&m, inc, 64, 128, lobe::Radius::BrdfCos, lobe::Channel::Luminance).unwrap());
        let sl = best(|| slice::half_diff_slice(&m, std::f64::consts::FRAC_PI_2, 512, 512).unwrap());
        let a = best(|| albedo::albedo_curve(&m, &thetas, &albedo::VIEW_QUADRATURE).unwrap());
        let sp = best(|| sphere::lit_sphere(&m, &sphere::SphereOptions::default()).unwrap());
        println!("{:22} {p:7.2} {l:7.2} {sl:7.2} {a:7.2} {sp:7.2}", s.name);
    }
}
