//! The contour term of the shading bound (beyond Settgast et al.): the pixels straddling a
//! silhouette, which the area elements of [`crate::shading`] do not see.
//!
//! A pixel on a contour shows the mean normal of the samples it covers. There the limit normal
//! is perpendicular to the line of sight, while the drawn surface's contour runs along edges of
//! its triangles, whose interpolated normals lean off edge-on by up to the turn of the normal
//! across one drawn triangle. For a smooth patch drawn with edges of length `h` whose chords sag
//! by `δ` from the limit surface (a parabola of curvature `κ`: `δ = κ h² / 8`), that turn is
//! `κ h = 8 δ / h`: it halves with every level (the silhouette's *position* error, `δ`, falls
//! by four), which is why the contour pixels set `shading_deg_p99` on scenes with many
//! silhouettes (helmet40, measured 2026-11-30, in the history of docs/performance.md: 15 % of
//! the covered pixels lie within a pixel of a contour, and they hold two thirds of the pixels
//! beyond uniform depth 4's p99). The turn
//! is view-independent and follows from the chord errors already measured
//! ([`PatchError::deviation`]); the pixels it applies to are the contour's length on screen.
//!
//! The chord errors of deeper depths can be set by features narrower than a triangle (a
//! semi-sharp crease's rounding sags the same at every depth), which do not turn the normals of
//! the triangles the contour runs through; so the turn at depth `d` is the least over shallower
//! depths `k` of `turn(k) / 2^(d - k)`, the smooth part's halving.

use crate::pixel_error::PatchError;

/// The normal turn across one drawn triangle of face `e` (radians) at each depth
/// `0..out.len()` (see the module documentation): `8 δ_d / h_d`, with `h_d` the edge length of
/// the face's grid at depth `d` — `sqrt(area / weight)` at depth 0, the side of a square of the
/// limit area drawn as two triangles (a quad patch; a Loop triangle's weight is 1/2), halved per
/// level — and never more than half the turn of the depth above. Zero for a face without area
/// elements.
pub fn contour_turns(e: &PatchError, out: &mut [f32]) {
    let area: f32 = e.shading.elements.iter().map(|el| el.area).sum();
    let h0 = (area / e.shading.weight.max(f32::MIN_POSITIVE)).sqrt();
    let mut prev = f32::INFINITY;
    for (d, o) in out.iter_mut().enumerate() {
        let h = h0 * (-(d as f32)).exp2();
        let sag = e.deviation.get(d).copied().unwrap_or(0.0);
        let turn = if h > 0.0 && sag.is_finite() {
            8.0 * sag / h
        } else if h > 0.0 {
            f32::INFINITY
        } else {
            0.0
        };
        *o = turn.min(0.5 * prev);
        prev = *o;
    }
}

/// The contour's length on screen through a face whose bounding sphere projects to a disc of
/// radius `radius` pixels (assumed to hold a contour): the side of the square the disc
/// circumscribes, `√2 · radius`, for a face about as wide as its sphere.
#[inline]
pub fn contour_pixels(radius: f32) -> f32 {
    std::f32::consts::SQRT_2 * radius
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pixel_error::NormalCone;
    use crate::shading::{AreaElement, ShadingError};
    use glam::Vec3;

    /// A unit-area quad face with these chord errors.
    fn face(deviation: Vec<f32>) -> PatchError {
        PatchError {
            deviation,
            shading: ShadingError {
                elements: vec![AreaElement {
                    centre: Vec3::ZERO,
                    normal: Vec3::Z,
                    area: 1.0,
                    cell: 0.01,
                }],
                outlier_area: vec![],
                scales: 1,
                weight: 1.0,
            },
            normals: NormalCone::ANY,
            outline: false,
        }
    }

    #[test]
    fn turn_of_a_circular_arc_is_its_angle_per_edge() {
        // A cylinder of radius 1 drawn with edges spanning angle `a`: chord sag `1 - cos(a/2)`,
        // edge length about `a`, normal turn per edge `a`. A unit square patch of it spans one
        // radian at depth 0.
        let dev: Vec<f32> = (0..5)
            .map(|d| 1.0 - (0.5 * (-(d as f32)).exp2()).cos())
            .collect();
        let mut t = [0.0f32; 5];
        contour_turns(&face(dev), &mut t);
        for (d, &turn) in t.iter().enumerate() {
            let a = (-(d as f32)).exp2();
            assert!(
                (turn / a - 1.0).abs() < 0.03,
                "depth {d}: {turn} against {a}"
            );
        }
    }

    #[test]
    fn a_sag_that_does_not_shrink_with_depth_does_not_raise_the_turn() {
        // Smooth part halving, then a crease rounding that sags 0.01 at every depth.
        let dev = vec![0.1, 0.025, 0.01, 0.01, 0.01];
        let mut t = [0.0f32; 5];
        contour_turns(&face(dev), &mut t);
        assert!((t[0] - 0.8).abs() < 1e-6 && (t[1] - 0.4).abs() < 1e-6);
        for d in 1..5 {
            assert!(t[d] <= 0.5 * t[d - 1] + 1e-7, "{t:?}");
        }
        // No area: no turn; an undrawable depth (infinite sag): infinite at first.
        let mut none = face(vec![0.1; 3]);
        none.shading.elements.clear();
        let mut z = [1.0f32; 3];
        contour_turns(&none, &mut z);
        assert_eq!(z, [0.0; 3]);
        let mut inf = [0.0f32; 2];
        contour_turns(&face(vec![f32::INFINITY, 0.01]), &mut inf);
        assert!(inf[0].is_infinite() && (inf[1] - 0.16).abs() < 1e-6);
    }

    #[test]
    fn contour_pixels_raise_a_silhouette_face_until_its_turn_is_within_the_tolerance() {
        use crate::pixel_error::PatchErrors;
        use crate::shading::raise_for_shading;
        use subdiv_mesh::Camera;
        let camera = Camera::new(
            Vec3::new(0.0, 0.0, 10.0),
            Vec3::ZERO,
            Vec3::Y,
            60.0,
            800,
            600,
        );
        // 101 unit faces facing the eye without interior outliers; face 100's chords sag so
        // that its contour turn is 0.8, 0.4, 0.2, 0.1, 0.05 rad at depths 0..=4.
        let mut faces: Vec<PatchError> = (0..101)
            .map(|i| {
                let mut f = face(vec![0.0; 5]);
                f.shading.elements[0].centre = Vec3::new(-1.0 + i as f32 * 0.02, 0.0, 0.0);
                f.shading.outlier_area = vec![0.0; 5];
                f
            })
            .collect();
        faces[100].deviation = vec![0.1, 0.025, 0.00625, 0.0016, 0.0004];
        let errors = |tolerance: f32| PatchErrors {
            faces: faces.clone(),
            closed: true,
            shading_tolerance: tolerance,
        };
        let active = vec![true; 101];
        // A contour far longer than the budget (half of 1 % of about 101 × 2,700 pixels).
        let mut contour = vec![0.0f32; 101];
        contour[100] = 5000.0;
        let mut depth = vec![0u8; 101];
        raise_for_shading(&camera, &errors(0.05), &active, &contour, &mut depth, 4);
        assert_eq!(depth[100], 4, "{depth:?}");
        assert!(depth[..100].iter().all(|&d| d == 0));
        // A looser tolerance needs less depth; silhouettes only (180°) or no contour: none.
        let mut depth = vec![0u8; 101];
        raise_for_shading(&camera, &errors(0.3), &active, &contour, &mut depth, 4);
        assert_eq!(depth[100], 2);
        let mut depth = vec![0u8; 101];
        raise_for_shading(
            &camera,
            &errors(std::f32::consts::PI),
            &active,
            &contour,
            &mut depth,
            4,
        );
        assert_eq!(depth[100], 0);
        let mut depth = vec![0u8; 101];
        raise_for_shading(&camera, &errors(0.05), &active, &[], &mut depth, 4);
        assert_eq!(depth[100], 0);
        // A short contour fits in the budget.
        contour[100] = 100.0;
        let mut depth = vec![0u8; 101];
        raise_for_shading(&camera, &errors(0.05), &active, &contour, &mut depth, 4);
        assert_eq!(depth[100], 0);
    }
}
