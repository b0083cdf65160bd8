//! The Degree-of-Interest framework (Isenberg, Hartmann & König 2003, §3).
//!
//! "Before every subdivision step, the application computes the DoI function for each vertex,
//! edge, or face on the triangle mesh. [...] If the DoI is bigger than the threshold t the face is
//! subdivided [...]. If DoI values are computed for edges or vertices instead, [...] the DoI value
//! for a triangle is derived from the maximum of all the DoIs of the vertices or edges adjacent
//! to this triangle. However, averaging or taking the minimum [...] may also produce interesting
//! results."

use glam::Vec3;
use subdiv_mesh::{Camera, HalfedgeId, Mesh};

use crate::DoiError;

/// The mesh elements a DoI assigns values to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Domain {
    /// One value per face.
    Faces,
    /// One value per edge.
    Edges,
    /// One value per vertex.
    Vertices,
}

impl Domain {
    /// "faces", "edges" or "vertices".
    pub fn plural(self) -> &'static str {
        match self {
            Domain::Faces => "faces",
            Domain::Edges => "edges",
            Domain::Vertices => "vertices",
        }
    }

    /// "face", "edge" or "vertex".
    pub fn singular(self) -> &'static str {
        match self {
            Domain::Faces => "face",
            Domain::Edges => "edge",
            Domain::Vertices => "vertex",
        }
    }

    /// Number of elements of this kind in `mesh`.
    pub fn count(self, mesh: &Mesh) -> usize {
        match self {
            Domain::Faces => mesh.num_faces(),
            Domain::Edges => mesh.num_edges(),
            Domain::Vertices => mesh.num_vertices(),
        }
    }
}

/// How edge or vertex values become a face value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Aggregate {
    /// The largest value around the face (the paper's default).
    #[default]
    Max,
    /// The mean of the values around the face.
    Avg,
    /// The smallest value around the face.
    Min,
}

impl Aggregate {
    /// The aggregate of `values` (at least one, none `NaN`): their largest, mean or smallest.
    ///
    /// ```
    /// use subdiv_doi::Aggregate;
    /// assert_eq!(Aggregate::Avg.of([1.0, 2.0, 6.0]), 3.0);
    /// assert_eq!(Aggregate::Min.of([1.0, 2.0, 6.0]), 1.0);
    /// ```
    #[inline]
    pub fn of(self, values: impl IntoIterator<Item = f32>) -> f32 {
        let (mut lo, mut hi, mut sum, mut n) = (f32::INFINITY, f32::NEG_INFINITY, 0.0f32, 0u32);
        for x in values {
            lo = lo.min(x);
            hi = hi.max(x);
            sum += x;
            n += 1;
        }
        match self {
            Aggregate::Max => hi,
            Aggregate::Min => lo,
            Aggregate::Avg => sum / n as f32,
        }
    }
}

impl std::str::FromStr for Aggregate {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "max" => Ok(Aggregate::Max),
            "avg" | "average" | "mean" => Ok(Aggregate::Avg),
            "min" => Ok(Aggregate::Min),
            _ => Err(format!(
                "unknown aggregate '{s}' (expected max, avg or min)"
            )),
        }
    }
}

/// What a DoI may depend on besides the mesh: the view, the haptic interaction point, and which
/// step of how many is about to be taken.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DoiContext {
    /// The camera (view-dependent DoIs).
    pub camera: Option<Camera>,
    /// The haptic interaction point.
    pub hip: Option<Vec3>,
    /// The step about to be taken (0-based).
    pub step: u32,
    /// The number of steps of the whole refinement.
    pub steps: u32,
}

impl DoiContext {
    /// A context with a camera.
    pub fn with_camera(camera: Camera) -> DoiContext {
        DoiContext {
            camera: Some(camera),
            ..Default::default()
        }
    }

    /// The camera, or [`DoiError::NeedsCamera`] naming `doi`.
    pub fn camera_for(&self, doi: &'static str) -> Result<&Camera, DoiError> {
        self.camera.as_ref().ok_or(DoiError::NeedsCamera { doi })
    }
}

/// A Degree-of-Interest function: values on the faces, edges or vertices of a triangle mesh.
///
/// Larger values are more interesting; a face is refined when its (aggregated) value exceeds
/// the threshold. Implementations are plain data (their parameters) plus [`Doi::evaluate`].
///
/// ```
/// use subdiv_doi::{Doi, DoiContext, Dihedral, Domain};
/// use subdiv_mesh::{parse_obj, Mesh};
/// let tet = Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n")?)?;
/// let mut v = Vec::new();
/// Dihedral.evaluate(&tet, &DoiContext::default(), &mut v)?;
/// assert_eq!((Dihedral.domain(), v.len()), (Domain::Edges, 6));
/// assert!(v.iter().all(|&a| a > 50.0));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub trait Doi {
    /// Short name (as on the command line).
    fn name(&self) -> &'static str;
    /// Which elements get values.
    fn domain(&self) -> Domain;
    /// `true` when the values depend on the view or another per-frame input, so they must be
    /// re-evaluated every frame; `false` for static DoIs, whose refinement can be cached.
    fn is_view_dependent(&self) -> bool;
    /// The threshold the paper uses in its figures.
    fn default_threshold(&self) -> f32;
    /// Writes one value per element of [`Doi::domain`] of `mesh` into `out` (cleared first).
    fn evaluate(&self, mesh: &Mesh, ctx: &DoiContext, out: &mut Vec<f32>) -> Result<(), DoiError>;

    /// Writes one value per face into `out`: [`Doi::evaluate`] (its values checked: one per
    /// element, no `NaN`), then edge or vertex values combined around each face with `agg`
    /// ([`aggregate_to_faces`]). A DoI whose face value combines terms of several domains
    /// overrides this to aggregate its edge or vertex terms with `agg` (the haptic DoI: per-edge
    /// G¹ errors, per-face one-side test). `scratch` holds element values.
    fn evaluate_faces(
        &self,
        mesh: &Mesh,
        ctx: &DoiContext,
        agg: Aggregate,
        scratch: &mut Vec<f32>,
        out: &mut Vec<f32>,
    ) -> Result<(), DoiError> {
        self.evaluate(mesh, ctx, scratch)?;
        check_values(self.name(), self.domain(), mesh, scratch)?;
        aggregate_to_faces(mesh, self.domain(), scratch, agg, out);
        Ok(())
    }
}

impl<D: Doi + ?Sized> Doi for Box<D> {
    fn name(&self) -> &'static str {
        (**self).name()
    }
    fn domain(&self) -> Domain {
        (**self).domain()
    }
    fn is_view_dependent(&self) -> bool {
        (**self).is_view_dependent()
    }
    fn default_threshold(&self) -> f32 {
        (**self).default_threshold()
    }
    fn evaluate(&self, mesh: &Mesh, ctx: &DoiContext, out: &mut Vec<f32>) -> Result<(), DoiError> {
        (**self).evaluate(mesh, ctx, out)
    }
    fn evaluate_faces(
        &self,
        mesh: &Mesh,
        ctx: &DoiContext,
        agg: Aggregate,
        scratch: &mut Vec<f32>,
        out: &mut Vec<f32>,
    ) -> Result<(), DoiError> {
        (**self).evaluate_faces(mesh, ctx, agg, scratch, out)
    }
}

/// Face values from element values of `domain`: face values are copied, edge and vertex values
/// are combined around each face with `agg`. `out` is cleared first.
///
/// ```
/// use subdiv_doi::{aggregate_to_faces, Aggregate, Domain};
/// use subdiv_mesh::{parse_obj, Mesh};
/// let m = Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")?)?;
/// let mut f = Vec::new();
/// aggregate_to_faces(&m, Domain::Vertices, &[1.0, 2.0, 6.0], Aggregate::Avg, &mut f);
/// assert_eq!(f, vec![3.0]);
/// aggregate_to_faces(&m, Domain::Vertices, &[1.0, 2.0, 6.0], Aggregate::Min, &mut f);
/// assert_eq!(f, vec![1.0]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn aggregate_to_faces(
    mesh: &Mesh,
    domain: Domain,
    values: &[f32],
    agg: Aggregate,
    out: &mut Vec<f32>,
) {
    out.clear();
    if domain == Domain::Faces {
        out.extend_from_slice(values);
        return;
    }
    out.reserve(mesh.num_faces());
    for f in mesh.faces() {
        let h0 = mesh.face_halfedge(f);
        let mut h = h0;
        out.push(agg.of(std::iter::from_fn(|| {
            if h == HalfedgeId::NONE {
                return None;
            }
            let x = match domain {
                Domain::Edges => values[h.edge().idx()],
                _ => values[mesh.from(h).idx()],
            };
            h = mesh.next(h);
            if h == h0 {
                h = HalfedgeId::NONE;
            }
            Some(x)
        })));
    }
}

/// Checks that `values` holds one value per element of `domain` of `mesh` and no `NaN`.
fn check_values(
    doi: &'static str,
    domain: Domain,
    mesh: &Mesh,
    values: &[f32],
) -> Result<(), DoiError> {
    let want = domain.count(mesh);
    if values.len() != want {
        return Err(DoiError::ValueCount {
            doi,
            got: values.len(),
            want,
            domain: domain.plural(),
        });
    }
    if let Some(i) = values.iter().position(|x| x.is_nan()) {
        return Err(DoiError::NanValue {
            doi,
            domain: domain.singular(),
            index: i as u32,
        });
    }
    Ok(())
}

/// Evaluates `doi` on `mesh` and returns its face values (aggregated with `agg`), checking the
/// value count and that no value is NaN. `scratch` holds the element values.
pub fn face_values(
    doi: &dyn Doi,
    mesh: &Mesh,
    ctx: &DoiContext,
    agg: Aggregate,
    scratch: &mut Vec<f32>,
    out: &mut Vec<f32>,
) -> Result<(), DoiError> {
    doi.evaluate_faces(mesh, ctx, agg, scratch, out)?;
    check_values(doi.name(), Domain::Faces, mesh, out)
}

/// The faces to refine: `value > threshold`.
#[inline]
pub fn select(face_values: &[f32], threshold: f32, out: &mut Vec<bool>) {
    out.clear();
    out.extend(face_values.iter().map(|&v| v > threshold));
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::parse_obj;

    #[test]
    fn aggregation_over_edges() {
        let m = Mesh::from_soup(
            &parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n").unwrap(),
        )
        .unwrap();
        // Only the shared edge (1-2 zero-based) is interesting.
        let shared = m
            .find_halfedge(subdiv_mesh::VertexId(1), subdiv_mesh::VertexId(2))
            .unwrap()
            .edge();
        let mut e = vec![0.0f32; m.num_edges()];
        e[shared.idx()] = 3.0;
        let mut f = Vec::new();
        aggregate_to_faces(&m, Domain::Edges, &e, Aggregate::Max, &mut f);
        assert_eq!(f, vec![3.0, 3.0]);
        aggregate_to_faces(&m, Domain::Edges, &e, Aggregate::Avg, &mut f);
        assert_eq!(f, vec![1.0, 1.0]);
        aggregate_to_faces(&m, Domain::Edges, &e, Aggregate::Min, &mut f);
        assert_eq!(f, vec![0.0, 0.0]);
        let mut s = Vec::new();
        select(&[0.5, 1.5], 1.0, &mut s);
        assert_eq!(s, vec![false, true]);
        assert_eq!("avg".parse::<Aggregate>(), Ok(Aggregate::Avg));
        assert!(
            "median"
                .parse::<Aggregate>()
                .unwrap_err()
                .contains("max, avg or min")
        );
    }
}
