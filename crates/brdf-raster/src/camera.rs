//! Look-at cameras with OpenGL conventions (those of the canonical benchmark scene): right-handed world,
//! the camera looks down its −z axis, `p_clip = P · V · p_world`, NDC z ∈ [−1, 1].
//!
//! The view matrix is glam's right-handed `look_at_mat4` (rows of `V` are the camera's x, y, z axes,
//! `z = normalize(eye − target)`, `x = normalize(up × z)`, `y = z × x`), the projections are glam's
//! OpenGL `perspective` (= `gluPerspective`) and `orthographic` (= `glOrtho`). The aspect ratio is not
//! part of the camera: it comes from the image size at render time.

use glam::{Mat4, Vec3};

use crate::RasterError;

/// Largest image aspect ratio `width / height` (and its inverse the smallest): that of the widest image
/// the renderer makes, [`crate::render::MAX_IMAGE_SIDE`] × 1.
pub const MAX_ASPECT: f32 = crate::render::MAX_IMAGE_SIDE as f32;

/// Check an aspect ratio `width / height`: finite, in `[1/MAX_ASPECT, MAX_ASPECT]`.
pub fn check_aspect(aspect: f32) -> Result<f32, RasterError> {
    if !(1.0 / MAX_ASPECT..=MAX_ASPECT).contains(&aspect) {
        return Err(RasterError::arg(
            "aspect",
            format!("must be a width/height ratio in [1/{MAX_ASPECT}, {MAX_ASPECT}], got {aspect}"),
        ));
    }
    Ok(aspect)
}

/// The projection of a [`Camera`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// Perspective with a vertical field of view in radians (`gluPerspective`).
    Perspective {
        /// Full vertical field of view, in (0, π) radians.
        fovy: f32,
    },
    /// Parallel projection of a view volume `height` world units tall (width = height · aspect).
    Orthographic {
        /// Height of the view volume in world units, > 0.
        height: f32,
    },
}

/// A look-at camera: position, target, up hint, projection and the near/far clip distances.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Eye position (world).
    pub eye: Vec3,
    /// Point looked at (world).
    pub target: Vec3,
    /// Up hint (world); need not be unit or orthogonal to the view direction, must not be parallel.
    pub up: Vec3,
    /// Perspective or orthographic.
    pub projection: Projection,
    /// Distance to the near clip plane (> 0 for perspective).
    pub near: f32,
    /// Distance to the far clip plane (> near).
    pub far: f32,
}

impl Camera {
    /// A perspective camera (the canonical scene's: eye (0,0,3), target 0, up +y, fovy 45°, near 0.1,
    /// far 100).
    pub fn perspective(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fovy_radians: f32,
        near: f32,
        far: f32,
    ) -> Result<Self, RasterError> {
        if !(fovy_radians > 0.0 && fovy_radians < std::f32::consts::PI) {
            return Err(RasterError::arg("fovy", format!("must lie in (0, π) radians, got {fovy_radians}")));
        }
        if !(near > 0.0) || !near.is_finite() {
            return Err(RasterError::arg("near", format!("must be finite and > 0, got {near}")));
        }
        let cam =
            Self { eye, target, up, projection: Projection::Perspective { fovy: fovy_radians }, near, far };
        cam.validate()?;
        Ok(cam)
    }

    /// An orthographic camera whose view volume is `height` world units tall, centred on the view axis.
    pub fn orthographic(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        height: f32,
        near: f32,
        far: f32,
    ) -> Result<Self, RasterError> {
        let cam = Self { eye, target, up, projection: Projection::Orthographic { height }, near, far };
        cam.validate()?;
        Ok(cam)
    }

    /// Check every field (finite, `eye ≠ target`, `up` not parallel to the view direction, ranges).
    pub fn validate(&self) -> Result<(), RasterError> {
        for (name, v) in [("eye", self.eye), ("target", self.target), ("up", self.up)] {
            if !v.is_finite() {
                return Err(RasterError::arg(name, format!("must be finite, got {v}")));
            }
        }
        let dir = self.target - self.eye;
        if !(dir.length_squared() > 0.0) {
            return Err(RasterError::arg("target", "must differ from eye"));
        }
        if !(self.up.length_squared() > 0.0) || dir.normalize().cross(self.up.normalize()).length() < 1e-6 {
            return Err(RasterError::arg(
                "up",
                format!("must be non-zero and not parallel to target − eye, got {}", self.up),
            ));
        }
        match self.projection {
            Projection::Perspective { fovy } => {
                if !(fovy > 0.0 && fovy < std::f32::consts::PI) {
                    return Err(RasterError::arg("fovy", format!("must lie in (0, π) radians, got {fovy}")));
                }
                if !(self.near > 0.0) {
                    return Err(RasterError::arg("near", format!("must be > 0, got {}", self.near)));
                }
            }
            Projection::Orthographic { height } => {
                if !(height > 0.0) || !height.is_finite() {
                    return Err(RasterError::arg("height", format!("must be finite and > 0, got {height}")));
                }
            }
        }
        if !self.near.is_finite() || !self.far.is_finite() || !(self.far > self.near) {
            return Err(RasterError::arg(
                "far",
                format!(
                    "near and far must be finite with far > near, got near {} and far {}",
                    self.near, self.far
                ),
            ));
        }
        Ok(())
    }

    /// The view matrix `V` (world → camera; glam's right-handed look-at).
    pub fn view(&self) -> Mat4 {
        glam::camera::rh::view::look_at_mat4(self.eye, self.target, self.up.normalize())
    }

    /// The projection matrix `P` for an image of aspect ratio `aspect = width / height` (OpenGL clip
    /// space, NDC z ∈ [−1, 1]).
    pub fn projection(&self, aspect: f32) -> Mat4 {
        use glam::camera::rh::proj::opengl;
        match self.projection {
            Projection::Perspective { fovy } => opengl::perspective(fovy, aspect, self.near, self.far),
            Projection::Orthographic { height } => {
                let (h, w) = (0.5 * height, 0.5 * height * aspect);
                opengl::orthographic(-w, w, -h, h, self.near, self.far)
            }
        }
    }

    /// [`Camera::projection`] after checking `aspect`: finite and within [`MAX_ASPECT`]`^±1` (the aspect
    /// of any image the renderer makes); beyond that `P` had infinite entries (`1/aspect` overflows).
    pub fn checked_projection(&self, aspect: f32) -> Result<Mat4, RasterError> {
        check_aspect(aspect)?;
        let p = self.projection(aspect);
        if !p.is_finite() {
            return Err(RasterError::arg(
                "aspect",
                format!("gives a non-finite projection with this camera: {p}"),
            ));
        }
        Ok(p)
    }

    /// `P · V`.
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }

    /// Unit vector from the camera's look direction's opposite: `normalize(eye − target)`.
    pub fn backward(&self) -> Vec3 {
        (self.eye - self.target).normalize()
    }

    /// Whether `v` toward the viewer is the same at every point (orthographic) — then
    /// [`Camera::backward`] is it; otherwise it is `normalize(eye − p)`.
    pub fn is_orthographic(&self) -> bool {
        matches!(self.projection, Projection::Orthographic { .. })
    }

    /// The unit direction from `p` toward the viewer: `normalize(eye − p)` for a perspective camera
    /// (OpenGL's convention), the constant `normalize(eye − target)` for an orthographic one (viewer at
    /// infinity).
    #[inline]
    pub fn view_vector(&self, p: Vec3) -> Vec3 {
        match self.projection {
            Projection::Perspective { .. } => (self.eye - p).normalize_or(self.backward()),
            Projection::Orthographic { .. } => self.backward(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    fn scene_camera() -> Camera {
        Camera::perspective(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y, 45f32.to_radians(), 0.1, 100.0)
            .unwrap()
    }

    #[test]
    fn the_canonical_camera_has_scene_md_matrices() {
        let cam = scene_camera();
        let v = cam.view();
        // V is the identity with a −3 z-translation.
        assert!(v.abs_diff_eq(Mat4::from_translation(Vec3::new(0.0, 0.0, -3.0)), 1e-6), "{v}");
        let p = cam.projection(1920.0 / 1080.0);
        let (n, f) = (0.1f32, 100.0f32);
        let fy = 1.0 / (22.5f32.to_radians()).tan();
        assert!((p.x_axis.x - 1.357995).abs() < 1e-5 && (p.y_axis.y - 2.414214).abs() < 1e-5);
        assert!((fy - 2.414214).abs() < 1e-5);
        assert!((p.z_axis.z - (f + n) / (n - f)).abs() < 1e-6);
        assert!((p.w_axis.z - 2.0 * f * n / (n - f)).abs() < 1e-5);
        assert_eq!(p.z_axis.w, -1.0);
        // The near plane maps to NDC z = −1 and the far plane to +1.
        for (d, z) in [(n, -1.0f32), (f, 1.0)] {
            let c = p * Vec4::new(0.0, 0.0, -d, 1.0);
            assert!((c.z / c.w - z).abs() < 1e-4, "{d}: {}", c.z / c.w);
        }
    }

    #[test]
    fn orthographic_camera_maps_its_volume_to_the_ndc_cube() {
        let cam = Camera::orthographic(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 4.0, 1.0, 9.0).unwrap();
        let m = cam.view_projection(2.0);
        let c = m * Vec4::new(4.0, 2.0, -4.0, 1.0);
        assert!((c.truncate() / c.w - Vec3::new(1.0, 1.0, 1.0)).abs().max_element() < 1e-6, "{c}");
        assert_eq!(cam.view_vector(Vec3::new(3.0, -1.0, 0.0)), Vec3::Z);
    }

    #[test]
    fn bad_cameras_are_refused_naming_the_argument() {
        let e = |r: Result<Camera, RasterError>| r.unwrap_err().to_string();
        assert!(e(Camera::perspective(Vec3::ZERO, Vec3::ZERO, Vec3::Y, 1.0, 0.1, 10.0)).contains("target"));
        assert!(e(Camera::perspective(Vec3::Z, Vec3::ZERO, Vec3::Z, 1.0, 0.1, 10.0)).contains("up"));
        assert!(e(Camera::perspective(Vec3::Z, Vec3::ZERO, Vec3::Y, 0.0, 0.1, 10.0)).contains("fovy"));
        assert!(e(Camera::perspective(Vec3::Z, Vec3::ZERO, Vec3::Y, 1.0, 0.0, 10.0)).contains("near"));
        assert!(e(Camera::perspective(Vec3::Z, Vec3::ZERO, Vec3::Y, 1.0, 1.0, 0.5)).contains("far"));
        assert!(e(Camera::orthographic(Vec3::Z, Vec3::ZERO, Vec3::Y, -1.0, 0.1, 10.0)).contains("height"));
        let nan = Vec3::new(f32::NAN, 0.0, 0.0);
        assert!(e(Camera::perspective(nan, Vec3::ZERO, Vec3::Y, 1.0, 0.1, 10.0)).contains("eye"));
    }
}
