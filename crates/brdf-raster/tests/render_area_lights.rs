//! Area lights in rendered images (`Scene::area_lights`, `RenderOptions::area`): a sphere light over a
//! white Lambert floor against `E = π L sin²α`, and the same bits at any thread count.

use std::sync::Arc;

use brdf_core::{Input, Model};
use brdf_raster::area_light::AreaLight;
use brdf_raster::area_lighting::AreaSampling;
use brdf_raster::procedural::{icosphere, plane};
use brdf_raster::{Camera, Material, RenderOptions, Scene, render};
use glam::{Mat4, Vec3};

fn floor(light: AreaLight) -> Scene {
    let lambert = Model::build("lambert", &[("kd".to_string(), Input::Number(1.0))]).unwrap();
    let mut s = Scene::new();
    s.ambient_light = Vec3::ZERO;
    s.add(Arc::new(plane(4.0, 2).unwrap()), Material::new(lambert), Mat4::IDENTITY);
    s.add_area_light(light);
    s
}

/// Straight down at the floor, the pixel just under the camera at the origin.
fn camera() -> Camera {
    Camera::orthographic(Vec3::new(0.0, 0.5, 0.0), Vec3::ZERO, Vec3::NEG_Z, 0.02, 0.05, 10.0).unwrap()
}

#[test]
fn a_sphere_light_over_a_white_lambert_floor_reflects_l_sin2_alpha() {
    // L_o = ρ/π · π L sin²α = L (r/d)² straight below the centre: 8 · (0.5/2)² = 0.5.
    let scene = floor(AreaLight::sphere(Vec3::new(0.0, 2.0, 0.0), 0.5, Vec3::splat(8.0)).unwrap());
    let options = RenderOptions { area: AreaSampling { samples: 64, seed: 1 }, ..RenderOptions::new(8, 8) };
    let f = render(&scene, &camera(), &options).unwrap();
    let mean = f.hdr.iter().map(|c| f64::from(c.y)).sum::<f64>() / f.hdr.len() as f64;
    // 64 pixels × 64 MIS iterations of a 14.5° cone: well within 1 %.
    assert!((mean - 0.5).abs() < 5e-3, "{mean}");
}

#[test]
fn area_lights_render_the_same_bits_on_any_number_of_threads() {
    let mut scene = floor(AreaLight::rect(Vec3::Y, Vec3::X, Vec3::Z * 0.7, Vec3::splat(3.0), false).unwrap());
    scene.add(
        Arc::new(icosphere(2).unwrap()),
        scene.instances[0].material.clone(),
        Mat4::from_scale(Vec3::splat(0.3)),
    );
    scene.add_area_light(AreaLight::sphere(Vec3::new(0.5, 1.5, 0.5), 0.2, Vec3::splat(9.0)).unwrap());
    let cam = Camera::perspective(Vec3::new(0.0, 1.5, 2.5), Vec3::ZERO, Vec3::Y, 0.9, 0.1, 100.0).unwrap();
    let options = RenderOptions { area: AreaSampling { samples: 4, seed: 7 }, ..RenderOptions::new(40, 30) };
    let frames: Vec<Vec<Vec3>> = [1, 2, 3]
        .iter()
        .map(|&n| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(n).build().unwrap();
            pool.install(|| render(&scene, &cam, &options).unwrap().hdr)
        })
        .collect();
    assert!(frames[0].iter().all(|c| c.is_finite()) && frames[0].iter().any(|c| c.y > 0.0));
    assert_eq!(frames[0], frames[1]);
    assert_eq!(frames[0], frames[2]);
}
