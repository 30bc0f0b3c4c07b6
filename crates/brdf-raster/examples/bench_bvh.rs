//! BVH and obscurance benchmark (not a test): build time, closest-hit and any-hit rays per second, and
//! per-vertex obscurance time at 64 samples per vertex, at 1 and 2 threads, on the real meshes in
//! `../shared/assets/meshes` (the Cyberware horse, ~97k triangles; the Newell teapot, ~516k) and on the
//! 70k Stanford bunny subdivided 1→4 twice (~1.1M triangles, generated here, build time only).
//!
//! ```text
//! cargo run --release -p brdf-raster --example bench_bvh [-- --quick] [--mesh horse] [--rays-only] [--threads 1] [--reps 5] [--rays 50000] [--unsorted]
//! ```
//!
//! `BRDFPY_ASSETS=dir` overrides the mesh directory; `--mesh` keeps only meshes whose file name contains
//! the given text; `--rays-only` skips the build and obscurance timings; `--threads` limits the thread
//! counts timed (default 1 and 2); `--unsorted` also times any-hit rays one by one in input order.
//!
//! Rays start at random points on random triangles, offset along the face normal, in cosine-weighted
//! directions around it (the obscurance pattern); "unbounded" rays run to infinity, "AO" rays stop at
//! `d_max` = 10% of the mesh's bounding-box diagonal. Every figure is the best of a few repetitions.

use std::path::PathBuf;
use std::time::Instant;

use brdf_raster::Mesh;
use brdf_raster::ao::{AoOptions, obscurance_per_vertex};
use brdf_raster::bvh::{Bvh, Ray};
use brdf_raster::io::load_mesh;
use glam::Vec3;

struct Rng(u64);
impl Rng {
    fn f32(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// `$BRDFPY_ASSETS` if set, else `../shared/assets/meshes` beside the workspace.
fn assets() -> PathBuf {
    std::env::var_os("BRDFPY_ASSETS")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/assets/meshes"))
}

/// CPU time of the calling thread [s] (Linux `/proc/thread-self/schedstat`; NaN elsewhere).
fn thread_cpu() -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next().and_then(|t| t.parse::<f64>().ok()))
        .map_or(f64::NAN, |ns| ns * 1e-9)
}

/// Best wall time and best CPU time (summed over the pool's threads) of `reps` runs of `f` in a pool
/// of `threads` threads [s]. On a machine shared with other work the wall time understates the speed;
/// the CPU time shows what the code itself costs. Both are minima over the runs, taken separately.
fn time<T: Send>(threads: usize, reps: usize, f: impl Fn() -> T + Sync) -> (f64, f64) {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("thread pool");
    let cpu = || pool.broadcast(|_| thread_cpu()).iter().sum::<f64>();
    (0..reps)
        .map(|_| {
            let c0 = cpu();
            let t0 = Instant::now();
            std::hint::black_box(pool.install(&f));
            let wall = t0.elapsed().as_secs_f64();
            (wall, cpu() - c0)
        })
        .fold((f64::INFINITY, f64::INFINITY), |a, b| (a.0.min(b.0), a.1.min(b.1)))
}

/// The 1-minute load average (Linux `/proc/loadavg`), to judge how far wall times are from the
/// machine's own speed: above the core count, other work shares the cores.
fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|s| s.split_whitespace().next().map(str::to_owned))
        .unwrap_or_else(|| "unknown".into())
}

fn surface_rays(mesh: &Mesh, n: usize, t_max: f32, seed: u64) -> Vec<Ray> {
    let mut rng = Rng(seed);
    let (lo, hi) = bounds(mesh);
    let eps = 1e-4 * (hi - lo).length();
    (0..n)
        .map(|_| {
            let f = ((rng.f32() * mesh.indices.len() as f32) as usize).min(mesh.indices.len() - 1);
            let [a, b, c] = mesh.triangle(f);
            let (mut u, mut v) = (rng.f32(), rng.f32());
            if u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            let p = a + (b - a) * u + (c - a) * v;
            let nrm = (b - a).cross(c - a).normalize_or(Vec3::Y);
            let (t, s) = nrm.any_orthonormal_pair();
            let (u1, u2) = (rng.f32(), rng.f32());
            let r = u1.sqrt();
            let phi = std::f32::consts::TAU * u2;
            let d = t * (r * phi.cos()) + s * (r * phi.sin()) + nrm * (1.0 - u1).sqrt();
            Ray::segment(p + nrm * eps, d, 0.0, t_max)
        })
        .collect()
}

fn bounds(mesh: &Mesh) -> (Vec3, Vec3) {
    mesh.positions.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)))
}

/// 1→4 midpoint subdivision (shape unchanged).
fn subdivide(mesh: &Mesh) -> Mesh {
    let mut p = mesh.positions.clone();
    let mut mid = std::collections::HashMap::new();
    let mut f = Vec::with_capacity(mesh.indices.len() * 4);
    for t in &mesh.indices {
        let mut m = [0u32; 3];
        for k in 0..3 {
            let (a, b) = (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]));
            m[k] = *mid.entry((a, b)).or_insert_with(|| {
                p.push((p[a as usize] + p[b as usize]) * 0.5);
                (p.len() - 1) as u32
            });
        }
        f.extend([[t[0], m[0], m[2]], [m[0], t[1], m[1]], [m[2], m[1], t[2]], [m[0], m[1], m[2]]]);
    }
    Mesh::new(p, f, None).expect("subdivided mesh")
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let quick = args.iter().any(|a| a == "--quick");
    let rays_only = args.iter().any(|a| a == "--rays-only");
    let unsorted = args.iter().any(|a| a == "--unsorted");
    let value = |flag: &str| args.iter().position(|a| a == flag).and_then(|i| args.get(i + 1)).cloned();
    let only = value("--mesh");
    let thread_counts: Vec<usize> = match value("--threads") {
        Some(t) => vec![t.parse().expect("--threads N")],
        None => vec![1, 2],
    };
    let n_rays =
        value("--rays").map_or(if quick { 200_000 } else { 1_000_000 }, |r| r.parse().expect("--rays N"));
    let reps = value("--reps").map_or(if quick { 1 } else { 3 }, |r| r.parse().expect("--reps N"));
    println!(
        "brdf-raster BVH benchmark ({n_rays} rays per query kind, best of {reps}; {} cores, load average {})",
        std::thread::available_parallelism().map_or(0, |n| n.get()),
        load_average()
    );
    for name in ["cyberware_horse.ply", "newell_teapot_n96.ply", "stanford_bunny_70k.ply"] {
        if only.as_ref().is_some_and(|m| !name.contains(m.as_str())) {
            continue;
        }
        let path = assets().join(name);
        let Ok(mesh) = load_mesh(&path) else {
            println!("{name}: not found under {}, skipped", assets().display());
            continue;
        };
        let big = name.starts_with("stanford_bunny");
        let mesh = if big { subdivide(&subdivide(&mesh)) } else { mesh };
        let label = if big { "stanford_bunny_70k ×16 (subdivided)" } else { name };
        println!("\n{label}: {} triangles, {} vertices", mesh.indices.len(), mesh.positions.len());
        for &threads in thread_counts.iter().filter(|_| !rays_only) {
            let (wall, cpu) = time(threads, reps, || Bvh::from_mesh(&mesh).expect("bvh"));
            println!("  build, {threads} thread(s): {wall:.3} s wall, {cpu:.3} s CPU");
        }
        if big {
            continue;
        }
        let bvh = Bvh::from_mesh(&mesh).expect("bvh");
        println!("  tree: {:?}", bvh.stats());
        let (lo, hi) = bounds(&mesh);
        let d_max = 0.1 * (hi - lo).length();
        let unbounded = surface_rays(&mesh, n_rays, f32::INFINITY, 1);
        let ao_rays = surface_rays(&mesh, n_rays, d_max, 2);
        let hit_share =
            |rays: &[Ray]| bvh.any_hits(rays).iter().filter(|&&h| h).count() as f64 / rays.len() as f64;
        println!(
            "  rays hitting: unbounded {:.0}%, AO (d_max = {d_max:.3}) {:.0}%",
            100.0 * hit_share(&unbounded),
            100.0 * hit_share(&ao_rays)
        );
        let m = |n: f64, t: f64| n / t / 1e6;
        for (kind, rays) in [("unbounded", &unbounded), ("AO", &ao_rays)] {
            let n = rays.len() as f64;
            let mut any_wall = vec![];
            for &threads in &thread_counts {
                let (cw, cc) = time(threads, reps, || bvh.closest_hits(rays));
                let (aw, ac) = time(threads, reps, || bvh.any_hits(rays));
                any_wall.push(aw);
                println!(
                    "  {kind:>9} {threads}T: closest {:.2} M/s wall ({:.2} M/s per CPU-s), any {:.2} M/s wall ({:.2} M/s per CPU-s)",
                    m(n, cw),
                    m(n, cc),
                    m(n, aw),
                    m(n, ac)
                );
            }
            if let [one, two] = any_wall[..] {
                println!("  {kind:>9} any-hit 2T/1T wall speed-up {:.2}x", one / two);
            }
            if unsorted {
                // The same rays one by one in input order (no Morton sort): what the sort buys.
                use rayon::prelude::*;
                let (aw, ac) = time(1, reps, || rays.par_iter().map(|r| bvh.any_hit(r)).collect::<Vec<_>>());
                println!(
                    "  {kind:>9} 1T any-hit in input order: {:.2} M/s wall ({:.2} M/s per CPU-s)",
                    m(n, aw),
                    m(n, ac)
                );
            }
        }
        if rays_only {
            continue;
        }
        let opts = AoOptions { tau: 2.0, d_max, samples: 64, ..AoOptions::default() };
        let rays = mesh.positions.len() as f64 * 64.0;
        let mut walls = vec![];
        for &threads in &thread_counts {
            let (wall, cpu) = time(threads, 1, || {
                obscurance_per_vertex(&bvh, &mesh.positions, &mesh.normals, &opts).expect("obscurance")
            });
            walls.push(wall);
            println!(
                "  per-vertex obscurance, 64 samples, {threads}T: {wall:.2} s wall ({:.2} M rays/s), {cpu:.2} s CPU ({:.2} M rays per CPU-s)",
                m(rays, wall),
                m(rays, cpu)
            );
        }
        if let [one, two] = walls[..] {
            println!("  per-vertex obscurance 2T/1T wall speed-up {:.2}x", one / two);
        }
    }
    println!("\nload average at the end: {}", load_average());
}
