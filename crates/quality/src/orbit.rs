//! Cameras around a model for measurements over several views.

use std::f32::consts::TAU;

use glam::{Quat, Vec3};
use subdiv::mesh::Camera;

/// `n` cameras evenly around `base.up` through `base.target`: camera `k` is `base` with its eye
/// turned by `k · 360° / n` about that axis. Distance to the target, elevation over the plane
/// normal to `up`, field of view and size stay those of `base`; camera 0 is `base` itself. With
/// the command line's `--eye-relative X,Y,Z --up U` the orbit keeps the eye's height along `U`
/// and walks around the model's `U` axis.
///
/// ```
/// use subdiv_quality::orbit_cameras;
/// use subdiv::mesh::{Camera, glam::Vec3};
/// let base = Camera::new(Vec3::new(2.0, 1.0, 0.0), Vec3::ZERO, Vec3::Y, 45.0, 64, 48);
/// let cams = orbit_cameras(&base, 4);
/// assert_eq!(cams[0].eye, base.eye);
/// assert!((cams[1].eye - Vec3::new(0.0, 1.0, -2.0)).length() < 1e-5); // a quarter turn about +Y
/// ```
pub fn orbit_cameras(base: &Camera, n: usize) -> Vec<Camera> {
    let axis = base.up.normalize_or(Vec3::Y);
    let offset = base.eye - base.target;
    (0..n)
        .map(|k| {
            let turn = Quat::from_axis_angle(axis, TAU * k as f32 / n as f32);
            Camera {
                eye: base.target + turn * offset,
                ..*base
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orbit_keeps_distance_and_elevation_and_closes_the_circle() {
        let base = Camera::new(
            Vec3::new(1.0, 0.5, 3.0),
            Vec3::new(0.5, 0.5, 0.0),
            Vec3::Z,
            45.0,
            320,
            240,
        );
        let cams = orbit_cameras(&base, 8);
        assert_eq!(cams.len(), 8);
        let off0 = base.eye - base.target;
        let mut sum = Vec3::ZERO;
        for c in &cams {
            let off = c.eye - c.target;
            assert!((off.length() - off0.length()).abs() < 1e-5);
            assert!((off.z - off0.z).abs() < 1e-5, "elevation along up");
            assert_eq!(
                (c.target, c.up, c.width),
                (base.target, base.up, base.width)
            );
            sum += off;
        }
        // Evenly spaced: the horizontal parts cancel.
        assert!((sum / 8.0 - Vec3::new(0.0, 0.0, off0.z)).length() < 1e-5);
        assert!(orbit_cameras(&base, 0).is_empty());
    }
}
