//! The illustration-focus DoI (Isenberg, Hartmann & König 2003, §4.3, eq. (7), Fig. 10).
//!
//! "The DoI functions for geometric primitives [...] are based on the weighted distance
//! `d(p, o)` of the primitives `p` to the dominant object(s) `o`": zero for the object's own
//! primitives, otherwise the distance to the centre of the object's bounding object, or the
//! smallest distance to the object's internal skeleton. Every dominant object has its own
//! interest value `DoI(o)`. "The closer the triangles are to the focus point the more
//! subdivision steps are used."

use glam::Vec3;
use subdiv_mesh::{Mesh, closest_point_on_triangle};

use crate::curve_skeleton::curve_skeleton;
use crate::framework::{Doi, DoiContext, Domain};
use crate::skeleton::{polyline_distance, triangle_polyline_distance};
use crate::{DoiError, DoiKind};

/// How the distance to a focus object is measured.
#[derive(Clone, Debug, PartialEq)]
pub enum FocusShape {
    /// To the centre of the object's bounding object (for compact objects).
    BoundingCentre(Vec3),
    /// To the nearest point of a polyline, the object's internal skeleton (a single point is
    /// allowed).
    Skeleton(Vec<Vec3>),
    /// To the nearest point of a set of segments: a computed curve skeleton, which may branch
    /// and close loops ([`curve_skeleton`]; a zero-length segment is a point).
    Segments(Vec<[Vec3; 2]>),
}

impl FocusShape {
    /// Distance from the point `p` to the shape.
    #[inline]
    pub fn distance(&self, p: Vec3) -> f32 {
        match self {
            FocusShape::BoundingCentre(c) => p.distance(*c),
            FocusShape::Skeleton(pts) => polyline_distance(p, pts),
            FocusShape::Segments(segs) => segs
                .iter()
                .map(|s| polyline_distance(p, s))
                .fold(f32::INFINITY, f32::min),
        }
    }

    /// Distance from the triangle `tri` (its nearest point, not its centroid) to the shape.
    #[inline]
    pub fn face_distance(&self, tri: [Vec3; 3]) -> f32 {
        match self {
            FocusShape::BoundingCentre(c) => {
                c.distance(closest_point_on_triangle(*c, tri[0], tri[1], tri[2]))
            }
            FocusShape::Skeleton(pts) => triangle_polyline_distance(tri, pts),
            FocusShape::Segments(segs) => segs
                .iter()
                .map(|s| triangle_polyline_distance(tri, s))
                .fold(f32::INFINITY, f32::min),
        }
    }
}

/// A dominant object: the faces of a mesh group (or none, for a bare skeleton), how distance to
/// it is measured, and its own interest value.
#[derive(Clone, Debug, PartialEq)]
pub struct FocusObject {
    /// Group index into `Mesh::groups` whose faces are at distance 0, if any.
    pub group: Option<u32>,
    /// The distance measure.
    pub shape: FocusShape,
    /// The object's own interest, `DoI(o)` in eq. (7) (1 unless given).
    pub weight: f32,
}

/// A focus object as the user names it: `NAME` (interest 1) or `NAME=VALUE`, and optionally its
/// own skeleton.
#[derive(Clone, Debug, PartialEq)]
pub struct FocusSpec {
    /// Group or object name in the mesh.
    pub name: String,
    /// Its interest value `DoI(o)` (finite, not negative).
    pub value: f32,
    /// Its skeleton; `None`: the one shared by all objects, else computed
    /// ([`curve_skeleton`]).
    pub skeleton: Option<Vec<Vec3>>,
}

impl FocusSpec {
    /// Parses `NAME` or `NAME=VALUE`.
    ///
    /// ```
    /// use subdiv_doi::FocusSpec;
    /// assert_eq!(FocusSpec::parse("bracelet=2.5")?.value, 2.5);
    /// assert_eq!(FocusSpec::parse("arm")?.value, 1.0);
    /// assert!(FocusSpec::parse("arm=much").unwrap_err().to_string().contains("not a number"));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn parse(s: &str) -> Result<FocusSpec, DoiError> {
        let err = |msg: &str| DoiError::FocusSpec {
            spec: s.to_string(),
            msg: msg.to_string(),
        };
        let (name, value) = match s.rsplit_once('=') {
            None => (s, 1.0),
            Some((n, v)) => {
                let v: f32 = v
                    .trim()
                    .parse()
                    .map_err(|_| err("the value is not a number"))?;
                (n, v)
            }
        };
        if name.is_empty() {
            return Err(err("no name"));
        }
        if !(value.is_finite() && value >= 0.0) {
            return Err(err("the value must be finite and not negative"));
        }
        Ok(FocusSpec {
            name: name.to_string(),
            value,
            skeleton: None,
        })
    }
}

/// Eq. (7): a face's interest is its closeness to the most interesting dominant object,
/// `max_o DoI(o) · max(0, 1 − d(f, o) / radius)`, with `d` the distance from the face (its
/// nearest point) to the object's skeleton, 0 for the object's own faces.
///
/// The fall-off. The paper's eq. (7) combines the distance and `DoI(o)` without fixing how; it
/// asks that details "fade out with increasing distance". Linear in `d`, reaching 0 at `radius`,
/// is the simplest such fade that is bounded (faces beyond `radius` get nothing) and scale-free
/// (`radius` defaults to half the bounding-box diagonal). Combined with the step mapping below,
/// each unit of closeness is a number of halvings, so triangle size grows geometrically with the
/// distance, which is the fading level of detail of Fig. 10.
///
/// The step mapping. The paper compares a DoI with a fixed threshold before every step; a static
/// closeness compared that way would refine a face in every step or in none, and Fig. 10 needs
/// "the closer, the more steps". So the value before step `s` of `N` is the number of steps the
/// face still wants, `N · closeness − s`, and the threshold is 0: a face is refined in step `s`
/// exactly when `N · closeness > s`, i.e. in its first `⌈N · closeness⌉` steps. An object of
/// interest 1 gets all `N` steps, one of interest 0.5 half of them.
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
/// assert_eq!(v[1], 0.0); // four units away, at the radius: none
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
    /// Focus on the named groups of `mesh` (`NAME` or `NAME=VALUE`, see [`FocusSpec::parse`]),
    /// all measured from `skeleton` when given, else each from its own computed skeleton; with no
    /// names, the skeleton alone is the focus.
    pub fn from_groups(
        mesh: &Mesh,
        names: &[String],
        skeleton: Option<Vec<Vec3>>,
        radius: f32,
    ) -> Result<Focus, DoiError> {
        let specs = names
            .iter()
            .map(|n| FocusSpec::parse(n))
            .collect::<Result<Vec<_>, _>>()?;
        Focus::new(mesh, &specs, skeleton, radius)
    }

    /// Focus on the objects `specs` of `mesh`. An object's distance is measured from its own
    /// skeleton if it has one, else from `shared` if given, else from its computed curve
    /// skeleton ([`curve_skeleton`] of its triangles: the level-set diagram, which follows
    /// bends, branches and rings, where [`crate::principal_axis_skeleton`] is one straight
    /// segment). With no objects, `shared` alone
    /// is the focus (interest 1). `radius` is the distance where interest fades to nothing
    /// ([`Focus::default_radius`] is a good default).
    pub fn new(
        mesh: &Mesh,
        specs: &[FocusSpec],
        shared: Option<Vec<Vec3>>,
        radius: f32,
    ) -> Result<Focus, DoiError> {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(DoiError::NonFinite {
                what: "focus radius (positive)",
                value: radius,
            });
        }
        let shared = shared.filter(|s| !s.is_empty());
        if specs.is_empty() {
            return match shared {
                Some(s) => Ok(Focus {
                    objects: vec![FocusObject {
                        group: None,
                        shape: FocusShape::Skeleton(s),
                        weight: 1.0,
                    }],
                    radius,
                }),
                None => Err(DoiError::NoFocus),
            };
        }
        let mut objects = Vec::with_capacity(specs.len());
        for spec in specs {
            let g = mesh
                .groups()
                .iter()
                .position(|x| *x == spec.name)
                .ok_or_else(|| DoiError::UnknownFocus {
                    name: spec.name.clone(),
                    available: mesh.groups().to_vec(),
                })? as u32;
            let mut tris = Vec::new();
            for f in mesh.faces().filter(|&f| mesh.face_group(f) == g) {
                let v = mesh.face_vertices(f);
                tris.extend((1..v.len() - 1).map(|k| [v[0].0, v[k].0, v[k + 1].0]));
            }
            if tris.is_empty() {
                return Err(DoiError::EmptyFocus {
                    name: spec.name.clone(),
                });
            }
            let shape = match (&spec.skeleton, &shared) {
                (Some(s), _) | (None, Some(s)) if !s.is_empty() => FocusShape::Skeleton(s.clone()),
                _ => FocusShape::Segments(curve_skeleton(mesh.positions(), &tris)),
            };
            objects.push(FocusObject {
                group: Some(g),
                shape,
                weight: spec.value,
            });
        }
        Ok(Focus { objects, radius })
    }

    /// Half the diagonal of the mesh's bounding box.
    pub fn default_radius(mesh: &Mesh) -> f32 {
        let (lo, hi) = mesh.bounds();
        ((hi - lo).length() * 0.5).max(f32::MIN_POSITIVE)
    }

    /// The closeness of triangle `tri` in group `group`: eq. (7) without the step.
    #[inline]
    pub fn closeness(&self, tri: [Vec3; 3], group: u32) -> f32 {
        let mut best = 0.0f32;
        for o in &self.objects {
            let d = if o.group == Some(group) {
                0.0
            } else {
                o.shape.face_distance(tri)
            };
            best = best.max(o.weight * (1.0 - d / self.radius).max(0.0));
        }
        best
    }
}

impl Doi for Focus {
    fn name(&self) -> &'static str {
        DoiKind::Focus.name()
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
        mesh.check_triangles()?;
        out.clear();
        let n = ctx.steps as f32;
        let s = ctx.step as f32;
        out.extend(mesh.faces().map(|f| {
            let v = mesh.face_vertices(f);
            let tri = [0, 1, 2].map(|k| mesh.position(v[k]));
            n * self.closeness(tri, mesh.face_group(f)) - s
        }));
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::parse_obj;

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

    #[test]
    fn objects_have_their_own_interest_and_skeleton() {
        // Two separate triangles far apart and a third one between them.
        let m = Mesh::from_soup(
            &parse_obj(
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 10 0 0\nv 11 0 0\nv 10 1 0\nv 5 0 0\nv 6 0 0\nv 5 1 0\n\
                 g a\nf 1 2 3\ng b\nf 4 5 6\ng mid\nf 7 8 9\n",
            )
            .unwrap(),
        )
        .unwrap();
        let ctx = DoiContext {
            steps: 4,
            ..Default::default()
        };
        let focus = Focus::from_groups(&m, &["a=1".into(), "b=0.5".into()], None, 8.0).unwrap();
        let mut v = Vec::new();
        focus.evaluate(&m, &ctx, &mut v).unwrap();
        assert_eq!((v[0], v[1]), (4.0, 2.0), "own faces: N · DoI(o)");
        assert!(v[2] > 0.0 && v[2] < 2.0, "{v:?}");
        // A per-object skeleton (a point beside the middle triangle) moves the interest there.
        let mut specs = vec![FocusSpec::parse("b=0.5").unwrap()];
        specs[0].skeleton = Some(vec![Vec3::new(5.5, 0.2, 0.0)]);
        let focus = Focus::new(&m, &specs, Some(vec![Vec3::new(100.0, 0.0, 0.0)]), 8.0).unwrap();
        focus.evaluate(&m, &ctx, &mut v).unwrap();
        assert_eq!(
            v[2], 2.0,
            "the middle face touches b's skeleton: 0.5 of 4 steps"
        );
        assert!(v[0] < v[2]);
        let e = Focus::from_groups(&m, &["a=-1".into()], None, 1.0).unwrap_err();
        assert!(e.to_string().contains("not negative"), "{e}");
    }
}
