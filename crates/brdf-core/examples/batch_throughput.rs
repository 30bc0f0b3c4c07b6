//! Throughput of `batch::evaluate` without Python (evals/s of the benchmarked models, one thread and
//! the rayon default). `cargo run --release -p brdf-core --example batch_throughput [N [MODEL [THREADS]]]`.

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
    let text = |k: &str, x: &str| (k.to_string(), Input::Text(x.into()));
    let models = [
        ("lambert", Model::build("lambert", &[]).unwrap()),
        ("blinn_phong", Model::build("blinn_phong", &[]).unwrap()),
        ("oren_nayar", Model::build("oren_nayar", &[]).unwrap()),
        (
            "cook_torrance",
            Model::build(
                "cook_torrance",
                &[text("distribution", "ggx"), text("masking", "smith"), text("fresnel", "schlick")],
            )
            .unwrap(),
        ),
    ];
    let (d, len) = Directions::new(&l, &v, &nn, None).unwrap();
    let mut out = vec![Vec3::ZERO; len];
    let only = std::env::args().nth(2).filter(|o| !o.is_empty() && o != "all");
    let thread_counts: Vec<usize> = match std::env::args().nth(3).and_then(|s| s.parse().ok()) {
        Some(t) => vec![t],
        None => vec![1, 0],
    };
    for (name, m) in models.iter().filter(|(name, _)| only.as_deref().is_none_or(|o| o == *name)) {
        // The same work one sample at a time through the scalar API (what the batch replaced).
        let t = Instant::now();
        for (i, o) in out.iter_mut().enumerate() {
            *o = d.geometry(i).map_or(Vec3::ZERO, |g| m.eval(&g));
        }
        println!(
            "{name:14} scalar     {:8.1} M evals/s wall (one pass)",
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
                "{name:14} threads={nt}  {:8.1} M evals/s wall (best of {reps}), {:6.2} ns CPU per eval (N={n})",
                n as f64 / best / 1e6,
                cpu / n as f64 * 1e9
            );
        }
    }
}
