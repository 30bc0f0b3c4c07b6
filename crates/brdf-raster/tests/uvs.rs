//! Texture coordinates and tangents on meshes: OBJ `vt` read with the top-left origin, kept through
//! transforms, tangent handedness flipped by mirrors and winding flips, bad counts refused.

use brdf_raster::io::load_obj_bytes;
use glam::{Mat4, Vec2, Vec3, Vec4};

#[test]
fn obj_texture_coordinates_are_kept_with_the_top_left_origin() {
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n";
    let m = load_obj_bytes(text.as_bytes()).unwrap();
    assert_eq!(m.uvs.as_deref(), Some(&[Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 0.0)][..]));
    let plain = load_obj_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    assert!(plain.uvs.is_none());
}

#[test]
fn tangents_follow_transforms_and_winding_flips_and_bad_counts_are_refused() {
    let m = load_obj_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let t = m.clone().with_tangents(vec![Vec4::new(2.0, 0.0, 0.0, 1.0); 3]).unwrap();
    assert_eq!(t.tangents.as_ref().unwrap()[0], Vec4::new(1.0, 0.0, 0.0, 1.0), "normalised");
    let mirrored = t.transformed(&Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0))).unwrap();
    assert_eq!(mirrored.tangents.as_ref().unwrap()[0], Vec4::new(-1.0, 0.0, 0.0, -1.0));
    let mut flipped = t.clone();
    flipped.flip_winding();
    assert_eq!(flipped.tangents.as_ref().unwrap()[0].w, -1.0);
    assert!(m.clone().with_tangents(vec![Vec4::new(1.0, 0.0, 0.0, 0.5); 3]).is_err());
    assert!(m.clone().with_uvs(vec![Vec2::ZERO; 2]).is_err());
    assert!(m.with_uvs(vec![Vec2::new(f32::NAN, 0.0); 3]).is_err());
}
