//! The illustration-focus DoI (Isenberg, Hartmann & König 2003, §4.3, eq. (7), Fig. 10).
//!
//! "The DoI functions for geometric primitives [...] are based on the weighted distance
//! `d(p, o)` of the primitives `p` to the dominant object(s) `o`": zero for the object's own
//! primitives, otherwise the distance to the centre of the object's bounding box, or the
//! smallest distance to the object's internal skeleton (a polyline). "The closer the triangles
//! are to the focus point the more subdivision steps are used."

use std::path::Path;

use glam::Vec3;
use subdiv_mesh::Mesh;

use crate::DoiError;
use crate::framework::{Doi, DoiContext, Domain};

/// How the distance to a focus object is measured.
#[derive(Clone, Debug, PartialEq)]
pub enum FocusShape {
    /// To the centre of the object's axis-aligned bounding box.
    BoundingCentre(Vec3),
    /// To the nearest point of a polyline (the object's internal skeleton); a single point is
    /// allowed.
    Skeleton(Vec<Vec3>),
}

impl FocusShape {
    /// Distance from `p` to the shape.
    #[inline]
    pub fn distance(&self, p: Vec3) -> f32 {
        match self {
            FocusShape::BoundingCentre(c) => p.distance(*c),
            FocusShape::Skeleton(pts) => polyline_distance(p, pts),
        }
    }
}

/// Distance from `p` to the polyline `pts` (infinite when empty).
#[inline]
pub fn polyline_distance(p: Vec3, pts: &[Vec3]) -> f32 {
    match pts {
        [] => f32::INFINITY,
        [a] => p.distance(*a),
        _ => pts
            .windows(2)
            .map(|s| {
                let d = s[1] - s[0];
                let l2 = d.length_squared();
                let t = if l2 > 0.0 {
                    ((p - s[0]).dot(d) / l2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                p.distance(s[0] + d * t)
            })
            .fold(f32::INFINITY, f32::min),
    }
}

/// A dominant object: the faces of a mesh group (or none, for a bare skeleton), how distance to
/// it is measured, and its own DoI (a weight; 1 by default).
#[derive(Clone, Debug, PartialEq)]
pub struct FocusObject {
    /// Group index into `Mesh::groups` whose faces are at distance 0, if any.
    pub group: Option<u32>,
    /// The distance measure.
    pub shape: FocusShape,
    /// The object's own DoI, `DoI(o)` in eq. (7): it scales the closeness.
    pub weight: f32,
}

/// Eq. (7): a face's interest is its closeness to the most interesting dominant object,
/// `max_o DoI(o) · max(0, 1 − d(f, o) / radius)` with `d` measured from the face centroid (0 for
/// the object's own faces). So that closer faces get more steps, the value compared with the
/// threshold before step `s` of `N` is the number of steps the face still wants:
/// `N · closeness − s`. With the default threshold 0 a face at distance `d` gets about
/// `N (1 − d / radius)` steps; faces of the focus objects get all `N`.
///
/// Static (view-independent): the refinement is cached across frames.
///
/// ```
/// use subdiv_doi::{Doi, DoiContext, Focus};
/// use subdiv_mesh::{parse_obj, Mesh};
/// let m = Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 0 0\nv 6 0 0\nv 5 1 0\n\
///     g bracelet\nf 1 2 3\ng arm\nf 4 5 6\n")?)?;
/// let focus = Focus::from_groups(&m, &["bracelet".to_string()], None, 4.0)?;
/// let mut v = Vec::new();
/// focus.evaluate(&m, &DoiContext { step: 0, steps: 3, ..Default::default() }, &mut v)?;
/// assert_eq!(v[0], 3.0); // the object's own face wants all three steps
/// assert_eq!(v[1], 0.0); // five units away, beyond the radius: none
/// let e = Focus::from_groups(&m, &["olaf".to_string()], None, 4.0).unwrap_err();
/// assert!(e.to_string().contains("available: bracelet, arm"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Focus {
    /// The dominant objects.
    pub objects: Vec<FocusObject>,
    /// Distance at which the closeness reaches 0.
    pub radius: f32,
}

impl Focus {
    /// Focus on the named groups/objects of `mesh` (by bounding-box centre, or by distance to
    /// `skeleton` when given); with no names, the skeleton alone is the focus. `radius` is the
    /// distance where interest fades to nothing (half the bounding-box diagonal of the mesh is a
    /// good default, see [`Focus::default_radius`]).
    pub fn from_groups(
        mesh: &Mesh,
        names: &[String],
        skeleton: Option<Vec<Vec3>>,
        radius: f32,
    ) -> Result<Focus, DoiError> {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(DoiError::NonFinite {
                what: "focus radius (positive)",
                value: radius,
            });
        }
        if names.is_empty() {
            return match skeleton {
                Some(s) if !s.is_empty() => Ok(Focus {
                    objects: vec![FocusObject {
                        group: None,
                        shape: FocusShape::Skeleton(s),
                        weight: 1.0,
                    }],
                    radius,
                }),
                _ => Err(DoiError::NoFocus),
            };
        }
        let mut objects = Vec::with_capacity(names.len());
        for name in names {
            let g = mesh
                .groups()
                .iter()
                .position(|x| x == name)
                .ok_or_else(|| DoiError::UnknownFocus {
                    name: name.clone(),
                    available: mesh.groups().to_vec(),
                })? as u32;
            let shape = match &skeleton {
                Some(s) if !s.is_empty() => FocusShape::Skeleton(s.clone()),
                _ => {
                    let (mut lo, mut hi) =
                        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
                    for f in mesh.faces().filter(|&f| mesh.face_group(f) == g) {
                        for &v in mesh.face_vertices(f) {
                            lo = lo.min(mesh.position(v));
                            hi = hi.max(mesh.position(v));
                        }
                    }
                    if lo.x > hi.x {
                        return Err(DoiError::EmptyFocus { name: name.clone() });
                    }
                    FocusShape::BoundingCentre((lo + hi) * 0.5)
                }
            };
            objects.push(FocusObject {
                group: Some(g),
                shape,
                weight: 1.0,
            });
        }
        Ok(Focus { objects, radius })
    }

    /// Half the diagonal of the mesh's bounding box.
    pub fn default_radius(mesh: &Mesh) -> f32 {
        let (lo, hi) = mesh.bounds();
        ((hi - lo).length() * 0.5).max(f32::MIN_POSITIVE)
    }

    /// The closeness of a face with centroid `c` in group `group`: eq. (7) without the step.
    #[inline]
    pub fn closeness(&self, c: Vec3, group: u32) -> f32 {
        let mut best = 0.0f32;
        for o in &self.objects {
            let d = if o.group == Some(group) {
                0.0
            } else {
                o.shape.distance(c)
            };
            best = best.max(o.weight * (1.0 - d / self.radius).max(0.0));
        }
        best
    }
}

impl Doi for Focus {
    fn name(&self) -> &'static str {
        "focus"
    }
    fn domain(&self) -> Domain {
        Domain::Faces
    }
    fn is_view_dependent(&self) -> bool {
        false
    }
    fn default_threshold(&self) -> f32 {
        0.0
    }
    fn evaluate(&self, mesh: &Mesh, ctx: &DoiContext, out: &mut Vec<f32>) -> Result<(), DoiError> {
        out.clear();
        let n = ctx.steps as f32;
        let s = ctx.step as f32;
        out.extend(
            mesh.faces()
                .map(|f| n * self.closeness(mesh.face_centroid(f), mesh.face_group(f)) - s),
        );
        Ok(())
    }
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
    use subdiv_mesh::parse_obj;

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
    fn closer_faces_want_more_steps() {
        // A strip of triangles along x in group "rest", with a focus group at x = 0.
        let mut obj = String::new();
        for i in 0..=10 {
            obj += &format!("v {i} 0 0\nv {i} 1 0\n");
        }
        obj += "g focus\nf 1 3 4\nf 1 4 2\ng rest\n";
        for i in 1..10 {
            let (a, b, c, d) = (2 * i + 1, 2 * i + 3, 2 * i + 4, 2 * i + 2);
            obj += &format!("f {a} {b} {c}\nf {a} {c} {d}\n");
        }
        let m = Mesh::from_soup(&parse_obj(&obj).unwrap()).unwrap();
        let focus = Focus::from_groups(&m, &["focus".into()], None, 8.0).unwrap();
        let mut v = Vec::new();
        focus
            .evaluate(
                &m,
                &DoiContext {
                    steps: 3,
                    ..Default::default()
                },
                &mut v,
            )
            .unwrap();
        assert_eq!(v[0], 3.0);
        for f in 2..m.num_faces() - 1 {
            assert!(
                v[f] >= v[f + 1] - 0.5,
                "interest falls with distance: {v:?}"
            );
        }
        assert!(v[2] > 2.0 && *v.last().unwrap() == 0.0);
        // Step s lowers every value by s: farther faces drop out first.
        let mut v1 = Vec::new();
        focus
            .evaluate(
                &m,
                &DoiContext {
                    step: 1,
                    steps: 3,
                    ..Default::default()
                },
                &mut v1,
            )
            .unwrap();
        assert!(v.iter().zip(&v1).all(|(a, b)| (a - b - 1.0).abs() < 1e-6));
        // A skeleton along y at x = 10 makes the far end interesting instead.
        let focus = Focus::from_groups(
            &m,
            &[],
            Some(vec![Vec3::new(10.0, 0.0, 0.0), Vec3::new(10.0, 1.0, 0.0)]),
            8.0,
        )
        .unwrap();
        focus
            .evaluate(
                &m,
                &DoiContext {
                    steps: 3,
                    ..Default::default()
                },
                &mut v,
            )
            .unwrap();
        assert!(v.last().unwrap() > &2.5 && v[0] == 0.0);
        assert!(matches!(
            Focus::from_groups(&m, &[], None, 1.0),
            Err(DoiError::NoFocus)
        ));
    }
}
