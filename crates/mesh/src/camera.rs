//! A pinhole camera shared by the view-dependent crates (depth, DoI, stitching) and the renderer.

use glam::{Mat4, Vec2, Vec3};

/// A perspective camera: position, look-at target, up vector, vertical field of view and the
/// viewport in pixels. Plain data; the renderer turns it into matrices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub eye: Vec3,
    /// Point looked at.
    pub target: Vec3,
    /// Up direction (need not be orthogonal to the view direction).
    pub up: Vec3,
    /// Vertical field of view in degrees.
    pub fov_y_deg: f32,
    /// Viewport width in pixels.
    pub width: u32,
    /// Viewport height in pixels.
    pub height: u32,
}

impl Camera {
    /// A camera at `eye` looking at `target`.
    pub fn new(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov_y_deg: f32,
        width: u32,
        height: u32,
    ) -> Camera {
        Camera {
            eye,
            target,
            up,
            fov_y_deg,
            width,
            height,
        }
    }

    /// A camera looking at the centre of the box `lo..hi` from `centre + rel * radius`, where the
    /// radius is half the box diagonal (the CLI's `--eye-relative X,Y,Z`). Up is +Y, or +Z when
    /// looking along Y.
    ///
    /// ```
    /// use subdiv_mesh::{Camera, glam::Vec3};
    /// let c = Camera::eye_relative(Vec3::splat(-1.0), Vec3::splat(1.0), Vec3::new(0.0, 0.0, 3.0), 45.0, 640, 480);
    /// assert!((c.eye - Vec3::new(0.0, 0.0, 3.0 * 3f32.sqrt())).length() < 1e-5);
    /// assert_eq!(c.target, Vec3::ZERO);
    /// ```
    pub fn eye_relative(
        lo: Vec3,
        hi: Vec3,
        rel: Vec3,
        fov_y_deg: f32,
        width: u32,
        height: u32,
    ) -> Camera {
        let centre = (lo + hi) * 0.5;
        let radius = ((hi - lo).length() * 0.5).max(f32::MIN_POSITIVE);
        let eye = centre + rel * radius;
        let dir = (centre - eye).normalize_or_zero();
        let up = if dir.cross(Vec3::Y).length_squared() < 1e-6 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        Camera {
            eye,
            target: centre,
            up,
            fov_y_deg,
            width,
            height,
        }
    }

    /// Unit viewing direction.
    #[inline]
    pub fn forward(&self) -> Vec3 {
        (self.target - self.eye).normalize_or_zero()
    }

    /// Width / height.
    #[inline]
    pub fn aspect(&self) -> f32 {
        self.width.max(1) as f32 / self.height.max(1) as f32
    }

    /// Right-handed world-to-camera matrix (camera looks down -Z).
    pub fn view_matrix(&self) -> Mat4 {
        let f = self.forward();
        let s = f.cross(self.up).normalize_or_zero();
        let u = s.cross(f);
        Mat4::from_cols(
            s.extend(0.0),
            u.extend(0.0),
            (-f).extend(0.0),
            Vec3::ZERO.extend(1.0),
        )
        .transpose()
            * Mat4::from_translation(-self.eye)
    }

    /// Focal length in pixels: a length `l` at distance `d` in front of the camera covers
    /// `l * focal_pixels() / d` pixels.
    #[inline]
    pub fn focal_pixels(&self) -> f32 {
        self.height.max(1) as f32 * 0.5 / (self.fov_y_deg.to_radians() * 0.5).tan()
    }

    /// Depth of `p` along the viewing direction (positive in front of the camera).
    #[inline]
    pub fn depth_of(&self, p: Vec3) -> f32 {
        (p - self.eye).dot(self.forward())
    }

    /// Pixel coordinates of `p` (origin top-left, y down), or `None` behind the camera.
    pub fn project(&self, p: Vec3) -> Option<Vec2> {
        let c = self.view_matrix().transform_point3(p);
        if c.z >= 0.0 {
            return None;
        }
        let f = self.focal_pixels();
        Some(Vec2::new(
            self.width as f32 * 0.5 + f * c.x / -c.z,
            self.height as f32 * 0.5 - f * c.y / -c.z,
        ))
    }

    /// Unit ray from the eye to `p` (the paper's `camray`).
    #[inline]
    pub fn ray_to(&self, p: Vec3) -> Vec3 {
        (p - self.eye).normalize_or_zero()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_centre_and_scale() {
        let c = Camera::new(
            Vec3::new(0.0, 0.0, 10.0),
            Vec3::ZERO,
            Vec3::Y,
            90.0,
            200,
            100,
        );
        let p = c.project(Vec3::ZERO).unwrap();
        assert!((p - Vec2::new(100.0, 50.0)).length() < 1e-4);
        // fov 90: focal = h/2 = 50 px; a unit at distance 10 covers 5 px; +y goes up the image.
        let q = c.project(Vec3::new(1.0, 1.0, 0.0)).unwrap();
        assert!((q - Vec2::new(105.0, 45.0)).length() < 1e-4, "{q}");
        assert!(c.project(Vec3::new(0.0, 0.0, 20.0)).is_none());
        assert!((c.depth_of(Vec3::ZERO) - 10.0).abs() < 1e-6);
    }
}
