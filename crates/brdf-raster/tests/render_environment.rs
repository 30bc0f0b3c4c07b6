//! Environment lighting in rendered images (`Scene::environment`, `RenderOptions::environment`): white
//! furnaces in both modes, determinism of the Monte Carlo mode across thread counts, the background.

use std::sync::Arc;

use brdf_core::{Input, Model};
use brdf_raster::environment::{Environment, EnvironmentMode};
use brdf_raster::procedural::icosphere;
use brdf_raster::tiles::NO_TRI;
use brdf_raster::{Camera, Material, RenderOptions, Scene, render};
use glam::{Mat4, Vec3};

fn lambert(kd: f64) -> Model {
    Model::build("lambert", &[("kd".to_string(), Input::Number(kd))]).unwrap()
}

fn furnace(model: Model) -> Scene {
    let mut s = Scene::new();
    s.ambient_light = Vec3::ZERO;
    s.add(Arc::new(icosphere(4).unwrap()), Material::new(model), Mat4::IDENTITY);
    s.environment = Some(Environment::uniform(Vec3::ONE).unwrap());
    s
}

fn camera() -> Camera {
    Camera::perspective(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y, 0.8, 0.1, 100.0).unwrap()
}

fn lit(scene: &Scene, mode: EnvironmentMode) -> Vec<Vec3> {
    let options = RenderOptions { environment: mode, ..RenderOptions::new(48, 48) };
    let f = render(scene, &camera(), &options).unwrap();
    f.hdr.iter().zip(&f.triangle_id).filter(|(_, t)| **t != NO_TRI).map(|(c, _)| *c).collect()
}

#[test]
fn a_white_lambert_sphere_in_a_white_furnace_shows_one_in_both_modes() {
    let scene = furnace(lambert(1.0));
    for c in lit(&scene, EnvironmentMode::Fast) {
        assert!((c - Vec3::ONE).abs().max_element() < 2e-3, "{c}");
    }
    let mc = lit(&scene, EnvironmentMode::MonteCarlo { samples: 32, seed: 1 });
    let mean = mc.iter().copied().sum::<Vec3>() / mc.len() as f32;
    assert!((mean - Vec3::ONE).abs().max_element() < 5e-3, "{mean}");
    assert!(mc.iter().all(|c| c.is_finite()));
}

#[test]
fn the_monte_carlo_image_has_the_same_bits_at_any_thread_count() {
    let cu = Model::build(
        "cook_torrance",
        &[("metal".to_string(), Input::Text("cu".into())), ("roughness".to_string(), Input::Number(0.3))],
    )
    .unwrap();
    let mut scene = furnace(cu);
    scene.environment =
        Some(Environment::sky(Vec3::new(0.3, 0.5, 1.0), Vec3::ONE, Vec3::splat(0.2)).unwrap());
    let mode = EnvironmentMode::MonteCarlo { samples: 4, seed: 9 };
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let options = RenderOptions { environment: mode, ..RenderOptions::new(40, 32) };
            render(&scene, &camera(), &options).unwrap().hdr
        })
    };
    let (a, b) = (run(1), run(3));
    assert!(a.iter().zip(&b).all(|(x, y)| x.to_array().map(f32::to_bits) == y.to_array().map(f32::to_bits)));
}

#[test]
fn the_environment_is_the_background() {
    let mut scene = furnace(lambert(0.5));
    scene.instances[0].transform = Mat4::from_scale(Vec3::splat(0.1));
    scene.environment = Some(Environment::uniform(Vec3::new(0.25, 0.5, 0.75)).unwrap());
    let f = render(&scene, &camera(), &RenderOptions::new(16, 16)).unwrap();
    assert_eq!(f.hdr[0], Vec3::new(0.25, 0.5, 0.75));
}
