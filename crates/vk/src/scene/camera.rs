//! Cameras: the [`View`] matrices a frame is drawn with and the [`OrbitCamera`]
//! that produces them.

use glam::{Mat4, Quat, Vec3};

use super::RenderMesh;

/// Camera matrices with Vulkan clip conventions: NDC y points down, depth 0..1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// World to camera (right-handed, camera looks down -z).
    pub view: Mat4,
    /// Camera to clip space (Vulkan conventions, see [`View::perspective`]).
    pub proj: Mat4,
    /// Eye position in world space.
    pub eye: Vec3,
}

impl View {
    /// A right-handed perspective projection for Vulkan: depth 0..1 and y flipped
    /// so that +y in camera space points up in the image.
    pub fn perspective(fov_y_radians: f32, aspect: f32, near: f32, far: f32) -> Mat4 {
        // Guard the preconditions of the glam constructor (it asserts in debug builds).
        let fov = if fov_y_radians.is_finite() {
            fov_y_radians.clamp(1e-3, std::f32::consts::PI - 1e-3)
        } else {
            1.0
        };
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        let near = if near.is_finite() && near > 0.0 {
            near
        } else {
            1e-3
        };
        let far = if far.is_finite() && far > near {
            far
        } else {
            near * 1e3
        };
        glam::camera::rh::proj::vulkan::perspective(fov, aspect, near, far)
    }

    /// A view from `eye` towards `target`.
    pub fn look_at(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov_y_radians: f32,
        aspect: f32,
        near: f32,
        far: f32,
    ) -> Self {
        View {
            view: glam::camera::rh::view::look_at_mat4(eye, target, up),
            proj: Self::perspective(fov_y_radians, aspect, near, far),
            eye,
        }
    }

    /// `proj * view`.
    pub fn view_proj(&self) -> Mat4 {
        self.proj * self.view
    }

    /// Unit viewing direction in world space.
    pub fn forward(&self) -> Vec3 {
        let inv = self.view.inverse();
        (-inv.z_axis.truncate()).normalize_or(Vec3::NEG_Z)
    }

    /// World-space direction towards the key light: up-left and behind the viewer.
    pub fn key_light(&self) -> Vec3 {
        let inv = self.view.inverse();
        inv.transform_vector3(Vec3::new(-0.45, 0.6, 0.65))
            .normalize_or(Vec3::Z)
    }

    /// The 12 edges of this view's frustum as 24 line endpoints (for drawing a
    /// frozen culling camera from another one).
    pub fn frustum_lines(&self) -> Vec<[f32; 3]> {
        let inv = self.view_proj().inverse();
        let corner = |x: f32, y: f32, z: f32| inv.project_point3(Vec3::new(x, y, z)).to_array();
        let c = [
            corner(-1.0, -1.0, 0.0),
            corner(1.0, -1.0, 0.0),
            corner(1.0, 1.0, 0.0),
            corner(-1.0, 1.0, 0.0),
            corner(-1.0, -1.0, 1.0),
            corner(1.0, -1.0, 1.0),
            corner(1.0, 1.0, 1.0),
            corner(-1.0, 1.0, 1.0),
        ];
        let edges = [
            (0, 1),
            (1, 2),
            (2, 3),
            (3, 0),
            (4, 5),
            (5, 6),
            (6, 7),
            (7, 4),
            (0, 4),
            (1, 5),
            (2, 6),
            (3, 7),
        ];
        edges.iter().flat_map(|&(a, b)| [c[a], c[b]]).collect()
    }
}

/// An orbiting camera around a target point; produces [`View`]s.
///
/// Yaw turns about the `up` axis (the model's up: +Y by default, +Z for Z-up
/// models), pitch tilts towards it. With `up` = +Y, yaw 0 and pitch 0 the eye
/// lies on +Z of the target.
///
/// The viewer and headless renders use the same camera, so a screenshot of the
/// viewer equals a headless render with the same camera and size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    /// Point the camera looks at.
    pub target: Vec3,
    /// Distance from eye to target.
    pub distance: f32,
    /// Rotation about `up`, radians.
    pub yaw: f32,
    /// Elevation, radians (clamped to just under ±90°).
    pub pitch: f32,
    /// Vertical field of view, radians.
    pub fov_y: f32,
    /// Radius of the scene around `target`; sets the near and far planes.
    pub radius: f32,
    /// The axis the camera orbits about, kept up in the image (unit length; +Y
    /// by default).
    pub up: Vec3,
}

impl OrbitCamera {
    /// A camera that frames the box `lo..hi`, seen from the front-right and above.
    pub fn framing(lo: Vec3, hi: Vec3) -> Self {
        let target = (lo + hi) * 0.5;
        let radius = ((hi - lo).length() * 0.5).max(1e-6);
        let fov_y = 35f32.to_radians();
        let distance = radius / (fov_y * 0.5).sin() * 1.05;
        OrbitCamera {
            target,
            distance,
            yaw: 0.6,
            pitch: 0.45,
            fov_y,
            radius,
            up: Vec3::Y,
        }
    }

    /// This camera orbiting about `up` instead (unit length is enforced; a zero
    /// or non-finite vector keeps the current axis). Yaw and pitch are kept:
    /// relative to the new axis.
    pub fn with_up(mut self, up: Vec3) -> Self {
        if up.is_finite() && up.length_squared() > 1e-12 {
            self.up = up.normalize();
        }
        self
    }

    /// The rotation taking +Y to `up` (the frame yaw and pitch are measured in).
    fn frame(&self) -> Quat {
        Quat::from_rotation_arc(Vec3::Y, self.up.normalize_or(Vec3::Y))
    }

    /// Unit vectors of the image plane in world space: (right, up).
    pub fn screen_axes(&self) -> (Vec3, Vec3) {
        let forward = (self.target - self.eye()).normalize_or(Vec3::NEG_Z);
        let right = forward.cross(self.up).normalize_or(Vec3::X);
        (right, right.cross(forward))
    }

    /// Moves the target (and the eye with it) by a drag of (`dx`, `dy`) pixels in an
    /// image `height` pixels high: points in the target plane follow the cursor.
    pub fn pan(&mut self, dx: f32, dy: f32, height: f32) {
        if !(dx.is_finite() && dy.is_finite() && height > 0.0) {
            return;
        }
        // World units per pixel in the plane through the target.
        let per_pixel = 2.0 * self.distance * (self.fov_y * 0.5).tan() / height;
        let (right, up) = self.screen_axes();
        self.target += (-right * dx + up * dy) * per_pixel;
    }

    /// [`OrbitCamera::framing`] for the bounds of `mesh`; a unit box if it is empty.
    pub fn framing_mesh(mesh: &RenderMesh<'_>) -> Self {
        let (lo, hi) = mesh
            .bounds()
            .unwrap_or((Vec3::splat(-1.0), Vec3::splat(1.0)));
        Self::framing(lo, hi)
    }

    /// Eye position.
    pub fn eye(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        let local = Vec3::new(cp * sy, sp, cp * cy);
        let dir = if self.up == Vec3::Y {
            local // bit-identical to the +Y orbit of earlier versions
        } else {
            self.frame() * local
        };
        self.target + self.distance * dir
    }

    /// The view for an image of the given aspect ratio (width / height).
    pub fn view(&self, aspect: f32) -> View {
        let near = (self.distance - 2.0 * self.radius)
            .max(self.distance * 1e-3)
            .max(1e-6);
        let far = (self.distance + 2.0 * self.radius).max(near * 2.0);
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        View::look_at(
            self.eye(),
            self.target,
            self.up,
            self.fov_y,
            aspect,
            near,
            far,
        )
    }

    /// Rotates by a mouse drag of (`dx`, `dy`) radians.
    pub fn rotate(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx;
        let limit = 89f32.to_radians();
        self.pitch = (self.pitch + dy).clamp(-limit, limit);
    }

    /// Multiplies the distance by `factor` (wheel zoom), within sane limits.
    pub fn zoom(&mut self, factor: f32) {
        if factor.is_finite() && factor > 0.0 {
            self.distance = (self.distance * factor).clamp(self.radius * 1e-3, self.radius * 1e3);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn camera_frames_the_box() {
        let cam = OrbitCamera::framing(Vec3::splat(-1.0), Vec3::splat(1.0));
        let view = cam.view(1.0);
        let centre = view.view_proj().project_point3(Vec3::ZERO);
        assert!(centre.x.abs() < 1e-5 && centre.y.abs() < 1e-5);
        assert!(centre.z > 0.0 && centre.z < 1.0);
        // +y in the world is up in the image, i.e. negative NDC y in Vulkan.
        let top = view.view_proj().project_point3(Vec3::new(0.0, 0.5, 0.0));
        assert!(top.y < 0.0);
    }

    #[test]
    fn orbit_about_z_keeps_z_up_and_pan_follows_the_cursor() {
        let cam = OrbitCamera::framing(Vec3::splat(-1.0), Vec3::splat(1.0)).with_up(Vec3::Z);
        let view = cam.view(1.0);
        // +Z is up in the image (negative NDC y), and yawing keeps the eye's height along z.
        let top = view.view_proj().project_point3(Vec3::new(0.0, 0.0, 0.5));
        assert!(top.y < 0.0 && top.x.abs() < 1e-5, "{top}");
        let mut turned = cam;
        turned.rotate(0.7, 0.0);
        assert!((turned.eye().z - cam.eye().z).abs() < 1e-5);
        assert!((turned.eye() - cam.eye()).length() > 0.1);
        // Pitch 0 looks horizontally: the eye is level with the target along z.
        let level = OrbitCamera { pitch: 0.0, ..cam };
        assert!((level.eye().z - level.target.z).abs() < 1e-5);
        // A drag of 40 px right and 30 px down moves the target's image 40 px right and
        // 30 px down in a 400 px high image.
        let px = |c: &OrbitCamera, p: Vec3| {
            let ndc = c.view(1.0).view_proj().project_point3(p);
            (ndc.x * 200.0, ndc.y * 200.0)
        };
        let point = cam.target;
        let mut panned = cam;
        panned.pan(40.0, 30.0, 400.0);
        let (x0, y0) = px(&cam, point);
        let (x1, y1) = px(&panned, point);
        assert!(
            (x1 - x0 - 40.0).abs() < 1e-2 && (y1 - y0 - 30.0).abs() < 1e-2,
            "{x1} {y1}"
        );
    }
}
