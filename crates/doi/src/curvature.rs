//! A vertex-valued DoI: how much the surface bends at each vertex.
//!
//! The paper's framework takes DoI values "for each vertex, edge, or face"; vertex values reach
//! the faces by the maximum (the paper's default), the average or the minimum over the face's
//! corners (§3). This DoI gives such vertex values.

use glam::Vec3;
use subdiv_mesh::{Mesh, vertex_normals};

use crate::framework::{Doi, DoiContext, Domain};
use crate::{DoiError, DoiKind};

/// Per vertex, the largest angle (degrees) between the vertex normal (area-weighted) and the
/// normals of the faces around it: 0 where the surface is flat around the vertex, about half the
/// dihedral angle at a fold, large at a spike. It is a discrete, scale-free measure of curvature
/// at the vertex (the normal's turn over the one-ring), the vertex counterpart of the dihedral
/// DoI (eq. (3)) and compared with the same kind of threshold: default 15° (a fold of about 30°,
/// the dihedral figure's value). Static.
///
/// ```
/// use subdiv_doi::{Aggregate, Curvature, Doi, DoiContext, Domain, aggregate_to_faces};
/// use subdiv_mesh::{parse_obj, Mesh};
/// // Two triangles folded by 90° along the edge 1-2.
/// let m = Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 -1\nf 1 2 3\nf 2 1 4\n")?)?;
/// let mut v = Vec::new();
/// Curvature.evaluate(&m, &DoiContext::default(), &mut v)?;
/// assert_eq!(Curvature.domain(), Domain::Vertices);
/// assert!((v[0] - 45.0).abs() < 1e-3 && v[2] == 0.0); // on the fold / at a lone corner
/// let mut f = Vec::new();
/// aggregate_to_faces(&m, Domain::Vertices, &v, Aggregate::Min, &mut f);
/// assert_eq!(f, vec![0.0, 0.0]); // every face has a flat corner
/// aggregate_to_faces(&m, Domain::Vertices, &v, Aggregate::Max, &mut f);
/// assert!(f.iter().all(|&x| (x - 45.0).abs() < 1e-3)); // every face touches the fold
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Curvature;

impl Doi for Curvature {
    fn name(&self) -> &'static str {
        DoiKind::Curvature.name()
    }
    fn domain(&self) -> Domain {
        Domain::Vertices
    }
    fn is_view_dependent(&self) -> bool {
        false
    }
    fn default_threshold(&self) -> f32 {
        15.0
    }
    fn evaluate(&self, mesh: &Mesh, _ctx: &DoiContext, out: &mut Vec<f32>) -> Result<(), DoiError> {
        let normals = vertex_normals(mesh);
        out.clear();
        out.resize(mesh.num_vertices(), 0.0);
        for f in mesh.faces() {
            let n = mesh.face_normal(f);
            if n == Vec3::ZERO {
                continue;
            }
            for v in mesh.face_vertices(f) {
                let nv = normals[v.idx()];
                if nv != Vec3::ZERO {
                    let a = nv.dot(n).clamp(-1.0, 1.0).acos().to_degrees();
                    out[v.idx()] = out[v.idx()].max(a);
                }
            }
        }
        Ok(())
    }
}
