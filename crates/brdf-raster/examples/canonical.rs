//! Render SCENE.md's canonical scene, print the median frame time at 1 and 2 threads, write a PPM.
//!
//! `cargo run --release -p brdf-raster --example canonical -- [level] [width] [height] [frames] [out.ppm]`
//! (defaults: 7 1920 1080 10 canonical.ppm). View the PPM with any image viewer, or convert it with
//! `python -c "from PIL import Image; Image.open('canonical.ppm').save('canonical.png')"`.

use std::time::Instant;

use brdf_raster::scene::{canonical_camera, canonical_scene};
use brdf_raster::{RenderOptions, render};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: &str| args.get(i).cloned().unwrap_or_else(|| default.to_string());
    let level: u32 = arg(0, "7").parse()?;
    let width: u32 = arg(1, "1920").parse()?;
    let height: u32 = arg(2, "1080").parse()?;
    let frames: usize = arg(3, "10").parse()?;
    let out = arg(4, "canonical.ppm");

    let scene = canonical_scene(level)?;
    let camera = canonical_camera();
    let options = RenderOptions::new(width, height);
    println!("icosphere({level}): {} triangles, {width}×{height}", scene.face_count());

    let mut last = None;
    for threads in [1usize, 2] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build()?;
        let times = pool.install(|| -> Result<Vec<f64>, brdf_raster::RasterError> {
            // One warm-up frame, then `frames` timed ones.
            render(&scene, &camera, &options)?;
            (0..frames)
                .map(|_| {
                    let t = Instant::now();
                    let frame = render(&scene, &camera, &options)?;
                    let dt = t.elapsed().as_secs_f64() * 1e3;
                    last = Some(frame);
                    Ok(dt)
                })
                .collect()
        })?;
        let mut sorted = times.clone();
        sorted.sort_by(f64::total_cmp);
        println!(
            "{threads} thread(s): median {:.1} ms (min {:.1}, max {:.1}) over {frames} frames",
            sorted[sorted.len() / 2],
            sorted[0],
            sorted[sorted.len() - 1]
        );
    }
    if let Some(frame) = last {
        let (cx, cy) = (width / 2, height / 2);
        println!("centre pixel {:?}, covered pixels {}", frame.rgb8_at(cx, cy), frame.covered_pixels());
        std::fs::write(&out, frame.to_ppm())?;
        println!("wrote {out}");
    }
    Ok(())
}
