//! Shadow-ray and obscurance-ray packets against one ray at a time (not a test): rays from the points of
//! a regular grid on a floor under an icosphere, toward a point light (coherent, like the shadow rays of
//! neighbouring pixels) and in cosine-weighted directions (the 64 obscurance rays of each point), traced
//! with `Bvh::any_hit` / `Bvh::closest_hit` one by one and with `Bvh::any_hit_each` /
//! `Bvh::closest_t_each` in packets, on one thread. Also checks that the answers are the same.
//!
//! ```text
//! cargo run --release -p brdf-raster --example bench_packets [-- LEVEL]
//! ```

use std::time::Instant;

use brdf_raster::bvh::{Bvh, Ray};
use brdf_raster::procedural::{icosphere, plane};
use glam::{Mat4, Vec3};

fn best_of(reps: usize, mut f: impl FnMut()) -> f64 {
    (0..reps)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let level: u32 = std::env::args().nth(1).map_or(Ok(6), |s| s.parse())?;
    let sphere = icosphere(level)?;
    let floor = plane(8.0, 64)?;
    let bvh = Bvh::from_instances(&[(&sphere, Mat4::from_translation(Vec3::Y)), (&floor, Mat4::IDENTITY)])?;
    println!("icosphere({level}) on a floor: {} triangles", bvh.triangle_count());
    let light = Vec3::new(2.0, 4.0, 1.0);
    let n = 512;
    let points: Vec<Vec3> = (0..n * n)
        .map(|i| {
            Vec3::new(-3.0 + 6.0 * (i % n) as f32 / n as f32, 1e-3, -3.0 + 6.0 * (i / n) as f32 / n as f32)
        })
        .collect();
    let shadow: Vec<Ray> = points
        .iter()
        .map(|&p| {
            let d = light - p;
            Ray::segment(p, d / d.length(), 0.0, d.length())
        })
        .collect();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    pool.install(|| {
        let mut one = vec![false; shadow.len()];
        let mut each = vec![false; shadow.len()];
        let t1 = best_of(3, || one.iter_mut().zip(&shadow).for_each(|(o, r)| *o = bvh.any_hit(r)));
        let t2 = best_of(3, || {
            for (r, o) in shadow.chunks(64).zip(each.chunks_mut(64)) {
                bvh.any_hit_each(r, o);
            }
        });
        assert_eq!(one, each);
        let hits = one.iter().filter(|&&h| h).count();
        let m = shadow.len() as f64 / 1e6;
        println!(
            "shadow rays ({} % blocked): one by one {:.1} M/s, packets {:.1} M/s ({:.2}×)",
            100 * hits / shadow.len(),
            m / t1,
            m / t2,
            t1 / t2
        );
        // 64 cosine-weighted directions per point (a fixed spiral), segments of 1.
        let ao: Vec<Ray> = points
            .iter()
            .step_by(16)
            .flat_map(|&p| {
                (0..64).map(move |k| {
                    let u1 = (k as f32 + 0.5) / 64.0;
                    let phi = k as f32 * 2.399_963;
                    let r = u1.sqrt();
                    Ray::segment(p, Vec3::new(r * phi.cos(), (1.0 - u1).sqrt(), r * phi.sin()), 0.0, 1.0)
                })
            })
            .collect();
        let mut one = vec![0f32; ao.len()];
        let mut each = vec![0f32; ao.len()];
        let t1 = best_of(3, || {
            one.iter_mut().zip(&ao).for_each(|(o, r)| *o = bvh.closest_hit(r).map_or(f32::INFINITY, |h| h.t))
        });
        let t2 = best_of(3, || {
            for (r, o) in ao.chunks(64).zip(each.chunks_mut(64)) {
                bvh.closest_t_each(r, o);
            }
        });
        assert!(one.iter().zip(&each).all(|(a, b)| a.to_bits() == b.to_bits()));
        let m = ao.len() as f64 / 1e6;
        println!(
            "obscurance rays: one by one {:.1} M/s, packets {:.1} M/s ({:.2}×)",
            m / t1,
            m / t2,
            t1 / t2
        );
    });
    Ok(())
}
