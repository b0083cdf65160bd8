//! Depths from a Degree of Interest: face values to per-patch subdivision depths.

use crate::Depth;

/// Maps DoI face values to per-face (per-patch) subdivision depths for a depth-driven
/// tessellator such as the Catmull-Clark slates.
///
/// A face whose value does not exceed `threshold` (or is NaN) gets depth 0. Above it, depth
/// grows linearly with the value from 1 just above the threshold to `max_depth` at the largest
/// value: `ceil(max_depth · (v − t) / (v_max − t))`. A binary DoI (silhouette, haptic point)
/// therefore gives `max_depth` to every selected face, and a graded one (view angle, dihedral,
/// focus) gives the most interesting faces the most steps, like the adaptive Loop refinement.
///
/// ```
/// use subdiv_depth::depths_from_face_values;
/// assert_eq!(depths_from_face_values(&[0.0, 1.0, 0.2], 0.5, 4), vec![0, 4, 0]);
/// assert_eq!(depths_from_face_values(&[30.0, 40.0, 60.0, 90.0], 30.0, 3), vec![0, 1, 2, 3]);
/// assert_eq!(depths_from_face_values(&[f32::NAN, 2.0], 0.0, 2), vec![0, 2]);
/// ```
pub fn depths_from_face_values(values: &[f32], threshold: f32, max_depth: Depth) -> Vec<Depth> {
    let vmax = values
        .iter()
        .copied()
        .filter(|v| v.is_finite() && *v > threshold)
        .fold(f32::NEG_INFINITY, f32::max);
    let span = vmax - threshold;
    values
        .iter()
        .map(|&v| {
            if v.is_nan() || v <= threshold || max_depth == 0 {
                0
            } else if !v.is_finite() || span.is_nan() || span <= 0.0 {
                max_depth
            } else {
                let d = (max_depth as f32 * ((v - threshold) / span)).ceil();
                d.clamp(1.0, max_depth as f32) as Depth
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn monotone_and_bounded() {
        let v: Vec<f32> = (0..100).map(|i| i as f32).collect();
        let d = depths_from_face_values(&v, 10.0, 5);
        assert!(d.windows(2).all(|w| w[0] <= w[1]));
        assert_eq!(d[10], 0);
        assert_eq!(d[11], 1);
        assert_eq!(d[99], 5);
        assert!(
            depths_from_face_values(&v, 200.0, 5)
                .iter()
                .all(|&x| x == 0)
        );
        assert!(depths_from_face_values(&v, 50.0, 0).iter().all(|&x| x == 0));
        assert_eq!(depths_from_face_values(&[], 0.0, 3), Vec::<Depth>::new());
        assert_eq!(
            depths_from_face_values(&[f32::INFINITY, 1.0], 0.0, 3),
            vec![3, 3]
        );
    }
}
