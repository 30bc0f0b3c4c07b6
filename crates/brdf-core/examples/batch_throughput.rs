//! Throughput of `batch::evaluate` without Python (evals/s of the benchmarked models, one thread and
//! the rayon default). `cargo run --release -p brdf-core --example batch_throughput [N [MODEL [THREADS]]]`;
//! MODEL is `all` (the default list, with every Cook-Torrance D/G/F choice), a registry name, or a
//! name with parameters, `cook_torrance:distribution=beckmann,masking=smith_separable,eta=0.14/0.38/1.44`
//! (numbers, colours as `a/b/c`, otherwise choice names). The CPU time per evaluation is the figure to
//! compare on a loaded machine (other processes inflate wall time, not this process's CPU time).

use std::time::Instant;

use brdf_core::Model;
use brdf_core::batch::{Directions, Quantity, evaluate};
use brdf_core::params::Input;
use glam::Vec3;

/// User + system CPU time of this process [s] (Linux `/proc/self/stat`, clock ticks of 10 ms).
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let fields: Vec<&str> = stat.rsplit(')').next().unwrap_or("").split_whitespace().collect();
    let ticks = |i: usize| fields.get(i).and_then(|f| f.parse::<f64>().ok()).unwrap_or(0.0);
    (ticks(11) + ticks(12)) / 100.0
}

fn main() {
    let n: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(1_000_000);
    let mut seed = 0x9e37_79b9_u32;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        seed as f32 / u32::MAX as f32 * 2.0 - 1.0
    };
    let mut dirs = || -> Vec<Vec3> { (0..n).map(|_| Vec3::new(rnd(), rnd(), rnd().abs() + 0.1)).collect() };
    let (l, v, nn) = (dirs(), dirs(), dirs());
    let build = |spec: &str| -> (String, Model) {
        let (name, rest) = spec.split_once(':').unwrap_or((spec, ""));
        let inputs: Vec<(String, Input)> = rest
            .split(',')
            .filter(|kv| !kv.is_empty())
            .map(|kv| {
                let (k, x) = kv.split_once('=').expect("parameters are k=v");
                let nums: Option<Vec<f64>> = x.split('/').map(|t| t.parse().ok()).collect();
                let input = match nums {
                    Some(v) if v.len() == 1 => Input::Number(v[0]),
                    Some(v) => Input::Numbers(v),
                    None => Input::Text(x.into()),
                };
                (k.to_string(), input)
            })
            .collect();
        (spec.to_string(), Model::build(name, &inputs).unwrap())
    };
    let au = "masking=smith_separable,fresnel=conductor,kd=0,roughness=0.3,eta=0.143036/0.375307/1.442045,k=3.982997/2.385556/1.603359";
    let defaults = [
        "lambert".to_string(),
        "cook_torrance".into(),
        "cook_torrance:distribution=beckmann".into(),
        "cook_torrance:distribution=gaussian".into(),
        "cook_torrance:distribution=blinn_phong".into(),
        "cook_torrance:masking=smith_separable".into(),
        "cook_torrance:masking=v_groove".into(),
        "cook_torrance:fresnel=dielectric".into(),
        "cook_torrance:fresnel=conductor".into(),
        "cook_torrance:fresnel=color_shift".into(),
        format!("cook_torrance:distribution=ggx,{au}"),
        format!("cook_torrance:distribution=beckmann,{au}"),
    ];
    let arg = std::env::args().nth(2).filter(|o| !o.is_empty() && o != "all");
    let models: Vec<(String, Model)> = match &arg {
        Some(spec) => vec![build(spec)],
        None => defaults.iter().map(|s| build(s)).collect(),
    };
    let (d, len) = Directions::new(&l, &v, &nn, None).unwrap();
    let mut out = vec![Vec3::ZERO; len];
    let thread_counts: Vec<usize> = match std::env::args().nth(3).and_then(|s| s.parse().ok()) {
        Some(t) => vec![t],
        None => vec![1, 0],
    };
    for (name, m) in &models {
        // The same work one sample at a time through the scalar API (what the batch replaced).
        let t = Instant::now();
        for (i, o) in out.iter_mut().enumerate() {
            *o = d.geometry(i).map_or(Vec3::ZERO, |g| m.eval(&g));
        }
        println!(
            "{name:40} scalar     {:8.1} M evals/s wall (one pass)",
            n as f64 / t.elapsed().as_secs_f64() / 1e6
        );
        for &threads in &thread_counts {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let mut best = f64::INFINITY;
            let reps = 20;
            let cpu0 = cpu_seconds();
            for _ in 0..reps {
                let t = Instant::now();
                pool.install(|| evaluate(m, &d, Quantity::Brdf, &mut out));
                best = best.min(t.elapsed().as_secs_f64());
            }
            // CPU time is what a loaded machine does not inflate (other processes take wall time).
            let cpu = (cpu_seconds() - cpu0) / reps as f64;
            let nt = pool.current_num_threads();
            println!(
                "{name:40} threads={nt}  {:8.1} M evals/s wall (best of {reps}), {:6.2} ns CPU per eval (N={n})",
                n as f64 / best / 1e6,
                cpu / n as f64 * 1e9
            );
        }
    }
}
