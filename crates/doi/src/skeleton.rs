//! Skeletons of focus objects (§4.3): polylines read from files or computed from an object's
//! vertices, and distances from faces to them.
//!
//! "Alternatively, one can also use the minimal Euclidean distance between the primitive p and a
//! point on the internal skeleton of o." The distance is taken from the whole triangle, not its
//! centroid: a large triangle that reaches close to a bone is close to it.

use std::path::Path;

use glam::{Mat3, Vec3};
use subdiv_mesh::closest_point_on_triangle;

use crate::DoiError;

/// Distance from `p` to the polyline `pts` (infinite when empty).
#[inline]
pub fn polyline_distance(p: Vec3, pts: &[Vec3]) -> f32 {
    match pts {
        [] => f32::INFINITY,
        [a] => p.distance(*a),
        _ => pts
            .windows(2)
            .map(|s| p.distance(closest_on_segment(p, s[0], s[1])))
            .fold(f32::INFINITY, f32::min),
    }
}

#[inline]
fn closest_on_segment(p: Vec3, a: Vec3, b: Vec3) -> Vec3 {
    let d = b - a;
    let l2 = d.length_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(d) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    a + d * t
}

/// Smallest distance between segments `p0 p1` and `q0 q1`.
pub fn segment_distance(p0: Vec3, p1: Vec3, q0: Vec3, q1: Vec3) -> f32 {
    let (d1, d2, r) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, e, f) = (d1.length_squared(), d2.length_squared(), d2.dot(r));
    let (s, t) = if a <= f32::EPSILON && e <= f32::EPSILON {
        (0.0, 0.0)
    } else if a <= f32::EPSILON {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else {
        let c = d1.dot(r);
        if e <= f32::EPSILON {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = d1.dot(d2);
            let denom = a * e - b * b;
            let mut s = if denom > 0.0 {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t = (b * s + f) / e;
            if t < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            }
            (s, t)
        }
    };
    (p0 + d1 * s).distance(q0 + d2 * t)
}

/// Smallest distance between the triangle `tri` and the segment `a b` (0 when they meet).
pub fn triangle_segment_distance(tri: [Vec3; 3], a: Vec3, b: Vec3) -> f32 {
    let [p, q, r] = tri;
    // Does the segment pierce the triangle?
    let n = (q - p).cross(r - p);
    let (da, db) = ((a - p).dot(n), (b - p).dot(n));
    if da * db <= 0.0 && (da - db).abs() > 0.0 {
        let x = a + (b - a) * (da / (da - db));
        if closest_point_on_triangle(x, p, q, r).distance_squared(x) <= 1e-12 * n.length() {
            return 0.0;
        }
    }
    let ends = [a, b].map(|x| x.distance(closest_point_on_triangle(x, p, q, r)));
    let edges = [(p, q), (q, r), (r, p)].map(|(u, v)| segment_distance(u, v, a, b));
    ends.into_iter().chain(edges).fold(f32::INFINITY, f32::min)
}

/// Smallest distance between the triangle `tri` and the polyline `pts` (a single point allowed;
/// infinite when empty).
pub fn triangle_polyline_distance(tri: [Vec3; 3], pts: &[Vec3]) -> f32 {
    match pts {
        [] => f32::INFINITY,
        [a] => a.distance(closest_point_on_triangle(*a, tri[0], tri[1], tri[2])),
        _ => pts
            .windows(2)
            .map(|s| triangle_segment_distance(tri, s[0], s[1]))
            .fold(f32::INFINITY, f32::min),
    }
}

/// A skeleton computed from an object's vertices: its principal-axis segment. The axis is the
/// eigenvector of the largest eigenvalue of the vertices' covariance through their mean; the
/// segment spans the vertices' projections on it, shortened at both ends by the vertices' mean
/// distance from the axis (the object's "radius"), so it runs inside the object as a medial
/// axis of a cylinder does. For an elongated object (a bone, a bracelet seen as a ring is not
/// elongated) this is the bone's axis; for a compact one it shrinks to the centre, which is
/// where the paper measures compact objects from. `None` without points.
///
/// ```
/// use subdiv_doi::principal_axis_skeleton;
/// use subdiv_mesh::glam::Vec3;
/// // A thin box along x from 0 to 10, 1 wide: the skeleton runs along its middle.
/// let mut pts = Vec::new();
/// for i in 0..=10 { for (y, z) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
///     pts.push(Vec3::new(i as f32, y, z));
/// } }
/// let s = principal_axis_skeleton(&pts).unwrap();
/// assert!((s[0].x.min(s[1].x) - 0.707).abs() < 0.01 && (s[0].x.max(s[1].x) - 9.293).abs() < 0.01);
/// assert!(s.iter().all(|p| p.y.abs() < 1e-4 && p.z.abs() < 1e-4));
/// ```
pub fn principal_axis_skeleton(pts: &[Vec3]) -> Option<Vec<Vec3>> {
    if pts.is_empty() {
        return None;
    }
    let mean = pts.iter().copied().sum::<Vec3>() / pts.len() as f32;
    let mut cov = Mat3::ZERO;
    for p in pts {
        let d = *p - mean;
        cov += Mat3::from_cols(d * d.x, d * d.y, d * d.z);
    }
    // Power iteration from the direction of largest extent.
    let mut axis = Vec3::X;
    let mut best = 0.0;
    for c in [Vec3::X, Vec3::Y, Vec3::Z] {
        let l = (cov * c).length();
        if l > best {
            (best, axis) = (l, c);
        }
    }
    for _ in 0..64 {
        let next = (cov * axis).normalize_or_zero();
        if next == Vec3::ZERO {
            break;
        }
        axis = next;
    }
    let (mut lo, mut hi, mut radial) = (f32::INFINITY, f32::NEG_INFINITY, 0.0f32);
    for p in pts {
        let d = *p - mean;
        let t = d.dot(axis);
        lo = lo.min(t);
        hi = hi.max(t);
        radial += (d - axis * t).length();
    }
    radial /= pts.len() as f32;
    let (a, b) = (lo + radial, hi - radial);
    Some(if a < b {
        vec![mean + axis * a, mean + axis * b]
    } else {
        vec![mean + axis * (0.5 * (lo + hi))]
    })
}

/// Reads a skeleton polyline: one point per line, as `v X Y Z` (OBJ vertices; other OBJ lines
/// are ignored), `X Y Z` or `X,Y,Z`; `#` starts a comment. Errors name the file and line.
pub fn read_skeleton(path: &Path) -> Result<Vec<Vec3>, DoiError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| DoiError::Skeleton {
        file: file.clone(),
        line: 0,
        msg: e.to_string(),
    })?;
    parse_skeleton(&text, &file)
}

/// [`read_skeleton`] on text; `file` names it in errors.
pub fn parse_skeleton(text: &str, file: &str) -> Result<Vec<Vec3>, DoiError> {
    let mut pts = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let body = if let Some(rest) = line.strip_prefix("v ") {
            rest
        } else if line.starts_with(|c: char| c.is_ascii_alphabetic()) {
            continue; // other OBJ statements (l, g, o, ...)
        } else {
            line
        };
        let err = |msg: String| DoiError::Skeleton {
            file: file.to_string(),
            line: i as u32 + 1,
            msg,
        };
        let xs: Vec<f32> = body
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|t| !t.is_empty())
            .map(|t| {
                t.parse::<f32>()
                    .map_err(|_| err(format!("'{t}' is not a number")))
            })
            .collect::<Result<_, _>>()?;
        if xs.len() != 3 || xs.iter().any(|x| !x.is_finite()) {
            return Err(err(format!("expected a point 'X Y Z', got '{line}'")));
        }
        pts.push(Vec3::new(xs[0], xs[1], xs[2]));
    }
    if pts.is_empty() {
        return Err(DoiError::Skeleton {
            file: file.to_string(),
            line: 0,
            msg: "no points".into(),
        });
    }
    Ok(pts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skeleton_distance_and_parsing() {
        let s = parse_skeleton("# bone\nv 0 0 0\nv 10 0 0\nl 1 2\n", "bone.obj").unwrap();
        assert_eq!(s.len(), 2);
        assert_eq!(polyline_distance(Vec3::new(5.0, 3.0, 4.0), &s), 5.0);
        assert_eq!(polyline_distance(Vec3::new(-3.0, 0.0, 4.0), &s), 5.0);
        assert_eq!(
            parse_skeleton("1,2,3\n", "x").unwrap(),
            vec![Vec3::new(1.0, 2.0, 3.0)]
        );
        let e = parse_skeleton("v 0 0 0\nv 1 two 3\n", "bone.obj").unwrap_err();
        assert_eq!(e.to_string(), "bone.obj:2: 'two' is not a number");
        assert!(
            parse_skeleton("# nothing\n", "e.txt")
                .unwrap_err()
                .to_string()
                .contains("no points")
        );
    }

    #[test]
    fn triangle_distances_use_the_whole_triangle() {
        let tri = [
            Vec3::ZERO,
            Vec3::new(4.0, 0.0, 0.0),
            Vec3::new(0.0, 4.0, 0.0),
        ];
        // A bone passing 1 above the triangle's corner region, far from its centroid.
        let bone = [Vec3::new(0.5, 0.5, 1.0), Vec3::new(0.5, 0.5, 5.0)];
        assert!((triangle_polyline_distance(tri, &bone) - 1.0).abs() < 1e-6);
        let c = (tri[0] + tri[1] + tri[2]) / 3.0;
        assert!(polyline_distance(c, &bone) > 1.2);
        // Piercing the triangle: 0.
        let pierce = [Vec3::new(1.0, 1.0, -1.0), Vec3::new(1.0, 1.0, 1.0)];
        assert_eq!(triangle_polyline_distance(tri, &pierce), 0.0);
        // Beside an edge: the edge-to-segment distance.
        let beside = [Vec3::new(2.0, -1.0, -3.0), Vec3::new(2.0, -1.0, 3.0)];
        assert!((triangle_polyline_distance(tri, &beside) - 1.0).abs() < 1e-6);
        assert!(
            (segment_distance(
                Vec3::ZERO,
                Vec3::X,
                Vec3::new(0.5, 1.0, -1.0),
                Vec3::new(0.5, 1.0, 1.0)
            ) - 1.0)
                .abs()
                < 1e-6
        );
        // A compact object's computed skeleton collapses to its centre.
        let cube: Vec<Vec3> = subdiv_test_support::cube()
            .positions
            .into_iter()
            .map(Vec3::from)
            .collect();
        let s = principal_axis_skeleton(&cube).unwrap();
        assert_eq!(s.len(), 1);
        assert!((s[0] - Vec3::splat(0.5)).length() < 1e-5);
    }
}
