//! The framing rule ([`framing_box`]) and the camera conversions between
//! [`subdiv_mesh::Camera`] (what the tessellators see) and the renderer's [`View`] /
//! [`OrbitCamera`], so the viewer shows exactly what a headless render draws.

use glam::{Quat, Vec3};
use subdiv_mesh::{Camera, Mesh};
use subdiv_vk::{OrbitCamera, View};

/// The box a view of `cage` is framed on: the cage's axis-aligned bounding box (every cage
/// vertex). It is known before anything is tessellated, so the same camera flags give the same
/// camera, and the same near and far planes ([`view_for`]), for every surface made from the
/// cage: uniform at any depth, adaptive, DoI-refined, Catmull-Clark or Loop. (The limit
/// surface lies in the cage's convex hull, its points being convex combinations of cage
/// vertices under the standard rules; the near and far planes keep a box radius of margin
/// besides.)
///
/// ```
/// use subdiv::{framing_box, mesh::{Mesh, parse_obj, glam::Vec3}};
/// let quad = Mesh::from_soup(&parse_obj("v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nf 1 2 3 4\n")?)?;
/// assert_eq!(framing_box(&quad), (Vec3::ZERO, Vec3::new(2.0, 1.0, 0.0)));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn framing_box(cage: &Mesh) -> (Vec3, Vec3) {
    cage.bounds()
}

/// Half the diagonal of the box `lo..hi` as seen from `target`: the largest distance from
/// `target` to a corner.
pub fn radius_about(lo: Vec3, hi: Vec3, target: Vec3) -> f32 {
    (0..8)
        .map(|i| {
            let c = Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            );
            (c - target).length()
        })
        .fold(0.0, f32::max)
        .max(1e-6)
}

/// The viewer's orbit camera for `camera`, orbiting about the camera's up vector (the model's
/// up: `--up`), and whether it reproduces the camera (a view direction within 89° of the up
/// plane). Near and far planes enclose the box `lo..hi`.
pub fn orbit_camera(camera: &Camera, lo: Vec3, hi: Vec3) -> (OrbitCamera, bool) {
    let offset = camera.eye - camera.target;
    let distance = offset.length().max(1e-6);
    let dir = offset / distance;
    let up = camera.up.normalize_or(Vec3::Y);
    // The direction in the orbit's frame, where `up` is +Y.
    let local = if up == Vec3::Y {
        dir
    } else {
        Quat::from_rotation_arc(Vec3::Y, up).inverse() * dir
    };
    let limit = 89f32.to_radians();
    let pitch = local.y.clamp(-1.0, 1.0).asin();
    let orbit = OrbitCamera {
        target: camera.target,
        distance,
        yaw: local.x.atan2(local.z),
        pitch: pitch.clamp(-limit, limit),
        fov_y: camera.fov_y_deg.to_radians(),
        radius: radius_about(lo, hi, camera.target),
        up,
    };
    let exact = camera.up.length_squared() > 0.0 && pitch.abs() <= limit;
    (orbit, exact)
}

/// The renderer's view for `camera` with near and far planes around the box `lo..hi`. +Y-up
/// cameras the viewer can orbit go through [`OrbitCamera`], so `subdiv view` shows exactly what
/// `subdiv render` draws; others use the camera's own matrix (the viewer's orbit about another
/// up axis gives the same view up to rounding).
pub fn view_for(camera: &Camera, lo: Vec3, hi: Vec3) -> View {
    let (orbit, exact) = orbit_camera(camera, lo, hi);
    if exact && orbit.up == Vec3::Y {
        return orbit.view(camera.aspect());
    }
    let distance = orbit.distance;
    let near = (distance - 2.0 * orbit.radius)
        .max(distance * 1e-3)
        .max(1e-6);
    let far = (distance + 2.0 * orbit.radius).max(near * 2.0);
    View {
        view: camera.view_matrix(),
        proj: View::perspective(camera.fov_y_deg.to_radians(), camera.aspect(), near, far),
        eye: camera.eye,
    }
}

/// The [`Camera`] of a renderer view at `size` pixels (the viewer's cameras back into the
/// tessellators' terms).
pub fn camera_from_view(view: &View, size: [u32; 2]) -> Camera {
    let inv = view.view.inverse();
    let up = inv.y_axis.truncate().normalize_or(Vec3::Y);
    let forward = view.forward();
    // Vulkan projection: |proj[1][1]| = 1 / tan(fov_y / 2).
    let fov = 2.0 * (1.0 / view.proj.y_axis.y.abs().max(1e-6)).atan();
    Camera::new(
        view.eye,
        view.eye + forward,
        up,
        fov.to_degrees(),
        size[0].max(1),
        size[1].max(1),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_camera_goes_through_the_orbit_camera() {
        let (lo, hi) = (Vec3::splat(-1.0), Vec3::splat(1.0));
        let cam = Camera::eye_relative(lo, hi, Vec3::new(0.8, 0.5, 2.2), 45.0, 320, 240);
        let (orbit, exact) = orbit_camera(&cam, lo, hi);
        assert!(exact);
        assert!((orbit.eye() - cam.eye).length() < 1e-5);
        let view = view_for(&cam, lo, hi);
        assert_eq!(view, orbit.view(320.0 / 240.0));
        // The same view as the camera's own matrix, and the box lies between near and far.
        let m = cam.view_matrix();
        for (a, b) in view.view.to_cols_array().iter().zip(m.to_cols_array()) {
            assert!((a - b).abs() < 1e-5);
        }
        for corner in [lo, hi, Vec3::new(-1.0, 1.0, -1.0)] {
            let ndc = view.view_proj().project_point3(corner);
            assert!(ndc.z > 0.0 && ndc.z < 1.0, "{ndc}");
        }
        // Looking straight down with +Z up orbits about +Z; renders use the camera's matrix.
        let top = Camera::eye_relative(lo, hi, Vec3::new(0.0, 3.0, 0.0), 45.0, 320, 240);
        assert_eq!(view_for(&top, lo, hi).view, top.view_matrix());
        // A Z-up camera is reproduced by the orbit about +Z.
        let zup = Camera::new(
            Vec3::new(2.0, -3.0, 1.5),
            Vec3::ZERO,
            Vec3::Z,
            40.0,
            320,
            240,
        );
        let (orbit, exact) = orbit_camera(&zup, lo, hi);
        assert!(exact && orbit.up == Vec3::Z);
        assert!((orbit.eye() - zup.eye).length() < 1e-4);
        let m = orbit.view(320.0 / 240.0).view;
        for (a, b) in m
            .to_cols_array()
            .iter()
            .zip(zup.view_matrix().to_cols_array())
        {
            assert!((a - b).abs() < 1e-4, "{m} vs {}", zup.view_matrix());
        }
        // Looking along the up axis cannot be an orbit view.
        let down = Camera::new(
            Vec3::new(0.0, 0.0, 3.0),
            Vec3::ZERO,
            Vec3::Z,
            40.0,
            320,
            240,
        );
        assert!(!orbit_camera(&down, lo, hi).1);
    }

    #[test]
    fn camera_from_view_inverts_view_for() {
        let (lo, hi) = (Vec3::splat(-1.0), Vec3::splat(1.0));
        let cam = Camera::eye_relative(lo, hi, Vec3::new(0.8, 0.5, 2.2), 45.0, 320, 240);
        let back = camera_from_view(&view_for(&cam, lo, hi), [320, 240]);
        assert!((back.eye - cam.eye).length() < 1e-4);
        assert!((back.forward() - cam.forward()).length() < 1e-4);
        assert!((back.fov_y_deg - 45.0).abs() < 1e-3);
        assert_eq!((back.width, back.height), (320, 240));
        assert!((radius_about(lo, hi, Vec3::ZERO) - 3f32.sqrt()).abs() < 1e-6);
    }
}
