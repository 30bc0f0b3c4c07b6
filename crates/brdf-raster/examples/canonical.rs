//! Render SCENE.md's canonical scene, print the median frame time at 1 and 2 threads, write a PPM.
//!
//! `cargo run --release -p brdf-raster --example canonical -- [level] [width] [height] [frames] [out.ppm] [threads,...] [shading] [outputs] [samples]`
//! (defaults: 7 1920 1080 10 canonical.ppm 1,2 phong buffers 1; shading: flat, gouraud, phong, quadratic;
//! samples per pixel: 1, 4, 9 or 16;
//! outputs: `buffers` (the Rust default: hdr, depth, normal, triangle_id) or names joined by commas,
//! e.g. `rgb,depth`, what a Python `Scene.render` writes by default). View the PPM with any image viewer, or convert it with
//! `python -c "from PIL import Image; Image.open('canonical.ppm').save('canonical.png')"`.

use std::time::Instant;

use brdf_raster::render::render_into;
use brdf_raster::scene::{canonical_camera, canonical_scene};
use brdf_raster::{RenderOptions, render};

/// CPU time (user + system) of this process in ms from `/proc/self/stat` (Linux; `None` elsewhere).
/// On a shared machine the wall-clock time includes waiting for the cores; CPU time per frame does not.
fn cpu_ms() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    let after = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = after.split_whitespace().collect();
    let ticks: f64 = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks * 10.0) // USER_HZ is 100 on Linux
}

/// CPU time (user + system, ms) of every thread of this process, by thread id, from
/// `/proc/self/task/*/stat` (Linux; empty elsewhere).
fn thread_cpu_ms() -> std::collections::BTreeMap<u64, f64> {
    let mut out = std::collections::BTreeMap::new();
    let Ok(dir) = std::fs::read_dir("/proc/self/task") else { return out };
    for entry in dir.flatten() {
        let Some(tid) = entry.file_name().to_str().and_then(|s| s.parse::<u64>().ok()) else { continue };
        let Ok(stat) = std::fs::read_to_string(entry.path().join("stat")) else { continue };
        let Some(close) = stat.rfind(')') else { continue };
        let f: Vec<&str> = stat[close + 2..].split_whitespace().collect();
        if let (Some(u), Some(s)) =
            (f.get(11).and_then(|x| x.parse::<f64>().ok()), f.get(12).and_then(|x| x.parse::<f64>().ok()))
        {
            out.insert(tid, (u + s) * 10.0);
        }
    }
    out
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: &str| args.get(i).cloned().unwrap_or_else(|| default.to_string());
    let level: u32 = arg(0, "7").parse()?;
    let width: u32 = arg(1, "1920").parse()?;
    let height: u32 = arg(2, "1080").parse()?;
    let frames: usize = arg(3, "10").parse()?;
    let out = arg(4, "canonical.ppm");
    let thread_counts: Vec<usize> = arg(5, "1,2").split(',').map(str::parse).collect::<Result<_, _>>()?;
    let shading = brdf_raster::ShadingMode::from_name(&arg(6, "phong"))?;
    let outputs = match arg(7, "buffers").as_str() {
        "buffers" => brdf_raster::render::Outputs::BUFFERS,
        names => brdf_raster::render::Outputs::from_names(names.split(','))?,
    };

    let samples_per_pixel: u32 = arg(8, "1").parse()?;

    let scene = canonical_scene(level)?;
    let camera = canonical_camera();
    let options = RenderOptions { shading, outputs, samples_per_pixel, ..RenderOptions::new(width, height) };
    println!("icosphere({level}): {} triangles, {width}×{height}", scene.face_count());

    // Each configuration: one warm-up frame, then `frames` timed ones, (a) `render` allocating a new
    // frame each time (what a Python call returns), (b) `render_into` redrawing one frame (as a GL
    // application redraws its framebuffer).
    let mut frame = render(&scene, &camera, &options)?;
    for &threads in &thread_counts {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build()?;
        for reuse in [false, true] {
            let times = pool.install(|| -> Result<Vec<f64>, brdf_raster::RasterError> {
                render_into(&scene, &camera, &options, &mut frame)?;
                let cpu0 = cpu_ms();
                let per_thread0 = thread_cpu_ms();
                let mut times = Vec::with_capacity(frames);
                for _ in 0..frames {
                    let t = Instant::now();
                    if reuse {
                        render_into(&scene, &camera, &options, &mut frame)?;
                    } else {
                        frame = render(&scene, &camera, &options)?;
                    }
                    times.push(t.elapsed().as_secs_f64() * 1e3);
                }
                // Work per thread: on a shared machine wall-clock speed-ups are meaningless, but the
                // split of CPU time between the threads bounds the speed-up an idle machine gives
                // (sum / max, if the threads run concurrently).
                let busy: Vec<f64> = thread_cpu_ms()
                    .into_iter()
                    .map(|(tid, t)| (t - per_thread0.get(&tid).copied().unwrap_or(0.0)) / frames as f64)
                    .filter(|&t| t > 0.5)
                    .collect();
                if threads > 1 && !busy.is_empty() {
                    let (sum, max) = (busy.iter().sum::<f64>(), busy.iter().copied().fold(0.0, f64::max));
                    println!(
                        "{threads} threads: CPU ms/frame per busy thread {:?} → balance bound on speed-up {:.2}×",
                        busy.iter().map(|t| (t * 10.0).round() / 10.0).collect::<Vec<_>>(),
                        sum / max
                    );
                }
                if let (Some(a), Some(b)) = (cpu0, cpu_ms()) {
                    times.push((b - a) / frames as f64);
                }
                Ok(times)
            })?;
            let cpu = if times.len() > frames {
                format!(", {:.1} ms CPU/frame", times[frames])
            } else {
                String::new()
            };
            let mut sorted = times[..frames].to_vec();
            sorted.sort_by(f64::total_cmp);
            println!(
                "{threads} thread(s), {}: median {:.1} ms (min {:.1}, max {:.1}) over {frames} frames{cpu}",
                if reuse { "render_into" } else { "render     " },
                sorted[sorted.len() / 2],
                sorted[0],
                sorted[sorted.len() - 1]
            );
        }
    }
    let last = Some(frame);
    if let Some(frame) = last {
        let (cx, cy) = (width / 2, height / 2);
        println!("centre pixel {:?}, covered pixels {}", frame.rgb8_at(cx, cy), frame.covered_pixels());
        std::fs::write(&out, frame.to_ppm())?;
        println!("wrote {out}");
    }
    Ok(())
}
