//! Obscurance and shadows in rendered images (`RenderOptions::ao`, `RenderOptions::shadows`): a unit
//! sphere resting on a plane, seen from straight above by an orthographic camera, so that pixel
//! `(col, row)` shows the plane point `x = −3 + (col + ½)·6/W`, `z = −3 + (row + ½)·6/H`.

use std::sync::Arc;

use brdf_core::lights::Light;
use brdf_core::{Input, Model};
use brdf_raster::ao::{AoOptions, Obscurance};
use brdf_raster::bvh::Bvh;
use brdf_raster::procedural::{icosphere, plane};
use brdf_raster::{Camera, Material, Mesh, RenderOptions, Scene, ShadingMode, render};
use glam::{Mat4, Vec3};

const W: u32 = 96;

fn lambert(c: f64) -> Model {
    Model::build("lambert_classic", &[("kd".to_string(), Input::Number(c))]).unwrap()
}

/// Plane 8×8 at y = 0 and a unit sphere centred at (0, 1, 0); ambient reflectance `ka`, `I_a` = 1.
fn scene(ka: f32, lights: Vec<Light>, with_sphere: bool) -> Scene {
    let mut s = Scene::new();
    let m = Material::new(lambert(0.8)).with_ambient(Vec3::splat(ka));
    s.add(Arc::new(plane(8.0, 32).unwrap()), m.clone(), Mat4::IDENTITY);
    if with_sphere {
        s.add(Arc::new(icosphere(4).unwrap()), m, Mat4::from_translation(Vec3::Y));
    }
    s.lights = lights;
    s
}

fn camera() -> Camera {
    Camera::orthographic(Vec3::new(0.0, 6.0, 0.0), Vec3::ZERO, -Vec3::Z, 6.0, 0.1, 20.0).unwrap()
}

/// The pixel showing plane point (x, 0, z).
fn pixel(x: f32, z: f32) -> (u32, u32) {
    (((x + 3.0) / 6.0 * W as f32) as u32, ((z + 3.0) / 6.0 * W as f32) as u32)
}

fn options(ao: Option<AoOptions>, shadows: bool) -> RenderOptions {
    RenderOptions { shading: ShadingMode::Phong, ao, shadows, ..RenderOptions::new(W, W) }
}

/// The plane point at the centre of pixel (col, row).
fn pixel_centre(c: u32, r: u32) -> Vec3 {
    Vec3::new(-3.0 + (c as f32 + 0.5) * 6.0 / W as f32, 0.0, -3.0 + (r as f32 + 0.5) * 6.0 / W as f32)
}

#[test]
fn ambient_obscurance_darkens_the_plane_next_to_the_sphere_per_vertex_and_per_pixel() {
    let s = scene(1.0, vec![], true);
    let open = render(&s, &camera(), &options(None, false)).unwrap();
    let (xn, zn) = pixel(1.15, 0.0);
    let (xf, zf) = pixel(2.8, 2.8);
    // Without obscurance, the ambient term is k_a·I_a = 1 everywhere.
    assert!((open.hdr_at(xn, zn) - Vec3::ONE).abs().max_element() < 1e-6);
    // The obscurance the image should show there, estimated directly with many rays.
    let ao = AoOptions { tau: 1.0, d_max: 1.0, samples: 64, seed: 1, ..AoOptions::default() };
    let meshes: Vec<(&Mesh, Mat4)> = s.instances.iter().map(|i| (&*i.mesh, i.transform)).collect();
    let bvh = Bvh::from_instances(&meshes).unwrap();
    let fine = Obscurance::new(&bvh, &AoOptions { samples: 4096, ..ao }).unwrap();
    let want = fine.at(pixel_centre(xn, zn), Vec3::Y, 0);
    assert!(want < 0.97, "the test point must be visibly obscured: {want}");
    for per_pixel in [false, true] {
        let f = render(&s, &camera(), &options(Some(AoOptions { per_pixel, ..ao }), false)).unwrap();
        let (near, far) = (f.hdr_at(xn, zn).x, f.hdr_at(xf, zf).x);
        // Far from the sphere (more than d_max away) the plane is fully open; next to it, the image
        // shows w (per pixel: a 64-ray estimate; per vertex: interpolated from the 0.25-spaced grid).
        assert!((far - 1.0).abs() < 1e-5, "per_pixel={per_pixel}: far from the sphere w = {far}");
        assert!((near - want).abs() < 0.03, "per_pixel={per_pixel}: near the contact {near}, direct {want}");
        // The top of the sphere (image centre) is open too.
        assert!((f.hdr_at(W / 2, W / 2).x - 1.0).abs() < 1e-3, "per_pixel={per_pixel}");
    }
}

#[test]
fn shadows_fall_where_the_light_projects_the_sphere() {
    // Light travelling along (1, −1, 0): the sphere's shadow is the ellipse centred at (1, 0, 0) with
    // semi-axes √2 (x) and 1 (z) on the plane.
    let sun = Light::directional(Vec3::new(1.0, -1.0, 0.0), Vec3::ONE).unwrap();
    let s = scene(0.0, vec![sun], true);
    let lit_value = 0.8 * std::f32::consts::FRAC_1_SQRT_2;
    let plain = render(&s, &camera(), &options(None, false)).unwrap();
    let shadowed = render(&s, &camera(), &options(None, true)).unwrap();
    for (x, z, in_shadow) in [
        (2.2, 0.0, true),
        (1.6, -0.6, true),
        (2.0, 0.5, true),
        (-2.0, 0.0, false),
        (1.0, 1.5, false),
        (0.0, -1.4, false),
    ] {
        if x * x + z * z < 1.2 {
            continue; // covered by the sphere in this view
        }
        let (c, r) = pixel(x, z);
        assert!((plain.hdr_at(c, r).x - lit_value).abs() < 1e-4, "no shadows: lit at ({x},{z})");
        let want = if in_shadow { 0.0 } else { lit_value };
        assert!((shadowed.hdr_at(c, r).x - want).abs() < 1e-4, "({x},{z}): {}", shadowed.hdr_at(c, r).x);
    }
}

#[test]
fn shadows_and_obscurance_are_per_sample_whatever_the_shading_mode() {
    // A floor of two triangles (their centroids and vertices all far from the shadow) under a
    // slanted sun: flat and Gouraud shading evaluate the model per face / per vertex, which on a flat
    // floor under a directional light is the same colour everywhere, but the shadow and the per-pixel
    // obscurance must still fall per sample, exactly where Phong shading puts them. (They used to be
    // computed at the centroid / vertices: no shadow on the floor at all.)
    let sun = Light::directional(Vec3::new(1.0, -1.0, 0.0), Vec3::ONE).unwrap();
    let mut s = Scene::new();
    let m = Material::new(lambert(0.8)).with_ambient(Vec3::splat(0.25));
    s.add(Arc::new(plane(8.0, 1).unwrap()), m.clone(), Mat4::IDENTITY);
    s.add(Arc::new(icosphere(3).unwrap()), m, Mat4::from_translation(Vec3::Y));
    s.lights = vec![sun];
    for ao in [None, Some(AoOptions { d_max: 1.5, samples: 16, per_pixel: true, ..AoOptions::default() })] {
        let at = |mode| {
            let o = RenderOptions { shading: mode, ..options(ao, true) };
            render(&s, &camera(), &o).unwrap()
        };
        let phong = at(ShadingMode::Phong);
        let floor: Vec<usize> = (0..phong.hdr.len()).filter(|&i| phong.triangle_id[i] < 2).collect();
        let shadowed = floor.iter().filter(|&&i| phong.hdr[i].x < 0.3).count();
        assert!(shadowed > 400, "{shadowed} shadowed floor pixels");
        for mode in [ShadingMode::Flat, ShadingMode::Gouraud] {
            let f = at(mode);
            for &i in &floor {
                let (a, b) = (f.hdr[i], phong.hdr[i]);
                assert!(
                    (a - b).abs().max_element() < 2e-6,
                    "{mode:?}, ao {}: pixel {i}: {a} vs {b}",
                    ao.is_some()
                );
            }
        }
    }
}

#[test]
fn combined_mode_adds_the_lights_diffuse_irradiance_to_the_obscured_ambient_term() {
    // Plane alone, light from straight above with E = 1: I_d = 1 and w = 1 on the open plane, so eq.
    // 12.75 gives [k_a·I_a + k_a·I_d]·w + k_d·I_d = (0.1 + 0.1) + 0.8 (k_d of the indirect term is k_a).
    let sun = Light::directional(-Vec3::Y, Vec3::ONE).unwrap();
    let s = scene(0.1, vec![sun], false);
    let ao = AoOptions { d_max: 1.0, samples: 16, combined: true, ..AoOptions::default() };
    let f = render(&s, &camera(), &options(Some(ao), true)).unwrap();
    let (c, r) = pixel(0.3, -0.7);
    assert!((f.hdr_at(c, r).x - 1.0).abs() < 1e-5, "{}", f.hdr_at(c, r));
    let plain = render(&s, &camera(), &options(Some(AoOptions { combined: false, ..ao }), true)).unwrap();
    assert!((plain.hdr_at(c, r).x - 0.9).abs() < 1e-5, "{}", plain.hdr_at(c, r));
}

#[test]
fn invalid_ao_options_are_refused_by_render() {
    let s = scene(1.0, vec![], false);
    let bad = AoOptions { samples: 0, ..AoOptions::default() };
    let e = render(&s, &camera(), &options(Some(bad), false)).unwrap_err().to_string();
    assert!(e.starts_with("samples"), "{e}");
}

#[test]
fn renders_with_obscurance_and_shadows_do_not_depend_on_the_thread_count() {
    let sun = Light::directional(Vec3::new(1.0, -1.0, 0.3), Vec3::ONE).unwrap();
    let s = scene(0.2, vec![sun], true);
    let ao = AoOptions { d_max: 1.0, samples: 16, per_pixel: true, ..AoOptions::default() };
    let run = |t: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(t).build().unwrap();
        pool.install(|| render(&s, &camera(), &options(Some(ao), true)).unwrap().hdr)
    };
    assert_eq!(run(1), run(3));
}

#[test]
fn a_real_mesh_renders_with_obscurance_and_shadows_darker_only_where_occluded() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/assets/meshes/garland_cow.ply");
    if !path.exists() {
        eprintln!("skipped: {} is absent", path.display());
        return;
    }
    let cow = Arc::new(brdf_raster::io::load_mesh(&path).unwrap());
    let mut s = Scene::new();
    let m = Material::new(lambert(0.7)).with_ambient(Vec3::splat(0.3));
    // The cow is about 1 unit long; stand it on a floor at its lowest point.
    let floor_y = cow.positions.iter().map(|p| p.y).fold(f32::INFINITY, f32::min);
    s.add(cow, m.clone(), Mat4::IDENTITY);
    s.add(Arc::new(plane(4.0, 8).unwrap()), m, Mat4::from_translation(Vec3::new(0.0, floor_y, 0.0)));
    s.lights = vec![Light::directional(Vec3::new(-0.3, -1.0, -0.4), Vec3::ONE).unwrap()];
    let cam = Camera::perspective(Vec3::new(1.2, 0.8, 1.6), Vec3::ZERO, Vec3::Y, 0.8, 0.1, 20.0).unwrap();
    let ao = AoOptions { d_max: 0.3, samples: 16, ..AoOptions::default() };
    let base = RenderOptions { ..RenderOptions::new(64, 48) };
    let plain = render(&s, &cam, &base).unwrap();
    let shaded = render(&s, &cam, &RenderOptions { ao: Some(ao), shadows: true, ..base }).unwrap();
    let (mut darker, mut covered) = (0, 0);
    for (a, b) in plain.hdr.iter().zip(&shaded.hdr) {
        assert!(b.is_finite() && b.min_element() >= 0.0);
        // Obscurance and shadows only ever remove light.
        assert!(b.max_element() <= a.max_element() + 1e-5, "{b} brighter than {a}");
        covered += usize::from(a.max_element() > 0.0);
        darker += usize::from(b.max_element() < a.max_element() - 1e-3);
    }
    assert!(covered > 1000, "the scene fills the frame: {covered}");
    assert!(darker > 50 && darker < covered, "{darker} of {covered} covered pixels darker");
}

#[test]
fn stored_per_vertex_obscurance_is_interpolated_for_its_instance_and_checked() {
    use brdf_raster::occlusion::SceneOcclusion;
    use brdf_raster::render_with;
    let s = scene(1.0, vec![], true);
    let nv = s.instances[0].mesh.positions.len();
    let ao = AoOptions { d_max: 1.0, samples: 16, ..AoOptions::default() };
    // The plane stores w = 0.5 everywhere; the sphere gets its own estimate.
    let occ = SceneOcclusion::with_stored(&s, Some(ao), false, vec![Some(vec![0.5; nv]), None]).unwrap();
    assert!(occ.vertex_obscurance(0).iter().all(|&w| w == 0.5));
    assert_eq!(occ.vertex_obscurance(1).len(), s.instances[1].mesh.positions.len());
    let f = render_with(&s, &camera(), &options(Some(ao), false), &occ, None).unwrap();
    let (c, r) = pixel(2.8, -2.8);
    assert!((f.hdr_at(c, r).x - 0.5).abs() < 1e-6, "{}", f.hdr_at(c, r));
    // Wrong lengths and values outside [0, 1] are refused, naming the argument.
    for bad in [vec![Some(vec![0.5; nv - 1]), None], vec![Some(vec![1.5; nv]), None], vec![None]] {
        let e = SceneOcclusion::with_stored(&s, Some(ao), false, bad).err().expect("refused").to_string();
        assert!(e.starts_with("obscurance"), "{e}");
    }
}

#[test]
fn the_occlusion_cache_reuses_the_bvh_and_obscurance_only_while_the_geometry_is_unchanged() {
    use brdf_raster::occlusion::OcclusionCache;
    use brdf_raster::render::render_with;
    let sun = Light::directional(Vec3::new(1.0, -1.0, 0.3), Vec3::ONE).unwrap();
    let mut s = scene(0.2, vec![sun], true);
    let opts = AoOptions { d_max: 1.0, samples: 8, ..AoOptions::default() };
    let ao = Some(opts);
    let mut cache = OcclusionCache::new();
    let stored = |s: &Scene| vec![None; s.instances.len()];
    // A cached render is the render, bit for bit, whatever was cached before it.
    let check = |cache: &mut OcclusionCache, s: &Scene, ao: Option<AoOptions>, want: (u64, u64)| {
        let occ = cache.get(s, ao, true, stored(s)).unwrap();
        let frame = render_with(s, &camera(), &options(ao, true), &occ, None).unwrap();
        assert_eq!(frame, render(s, &camera(), &options(ao, true)).unwrap());
        assert_eq!(cache.stats(), want);
    };
    check(&mut cache, &s, ao, (0, 1));
    check(&mut cache, &s, ao, (1, 1));
    // Lights and materials are not part of the key.
    s.lights.push(Light::directional(Vec3::new(-1.0, -1.0, 0.0), Vec3::splat(0.5)).unwrap());
    s.instances[0].material.ambient = Vec3::splat(0.3);
    check(&mut cache, &s, ao, (2, 1));
    // A moved instance, another mesh (even with the same content), other options: prepared again.
    s.instances[1].transform = Mat4::from_translation(Vec3::new(0.5, 1.0, 0.0));
    check(&mut cache, &s, ao, (2, 2));
    s.instances[1].mesh = Arc::new((*s.instances[1].mesh).clone());
    check(&mut cache, &s, ao, (2, 3));
    check(&mut cache, &s, Some(AoOptions { samples: 9, ..opts }), (2, 4));
    check(&mut cache, &s, None, (2, 5));
    // Stored obscurance is part of the key.
    let w = vec![0.5; s.instances[0].mesh.positions.len()];
    let occ = cache.get(&s, ao, true, vec![Some(w), None]).unwrap();
    assert_eq!(occ.vertex_obscurance(0)[0], 0.5);
    assert_eq!(cache.stats(), (2, 6));
    // Data made for another scene is refused.
    let other = scene(0.2, vec![], false);
    let data = std::sync::Arc::clone(occ.data());
    assert!(brdf_raster::occlusion::SceneOcclusion::from_data(&other, data).is_err());
}
