//! The static dihedral-angle DoI (Isenberg, Hartmann & König 2003, §4.1, eq. (3), Fig. 4).

use subdiv_mesh::{EdgeId, Mesh};

use crate::framework::{Doi, DoiContext, Domain};
use crate::{DoiError, DoiKind};

/// Eq. (3): `DoI_e = arccos(n_f1 · n_f2)`, the angle between the normals of the edge's two
/// faces, in degrees. Concave edges "are never silhouette edges" and get 0, as do boundary
/// edges. Static: depends on the geometry only. Default threshold 30° (Fig. 4).
///
/// ```
/// use subdiv_doi::{dihedral_angle_deg, Doi, DoiContext, Dihedral};
/// use subdiv_mesh::{parse_obj, Mesh};
/// // A triangulated unit cube: the 12 cube edges are 90°, the 6 face diagonals 0°.
/// let cube = Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
///   f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6\nf 1 6 5\nf 3 7 8\nf 3 8 4\nf 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 8 6\n")?)?;
/// let mut v = Vec::new();
/// Dihedral.evaluate(&cube, &DoiContext::default(), &mut v)?;
/// assert_eq!(v.iter().filter(|&&a| (a - 90.0).abs() < 1e-3).count(), 12);
/// assert_eq!(v.iter().filter(|&&a| a.abs() < 1e-3).count(), 6);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Dihedral;

impl Doi for Dihedral {
    fn name(&self) -> &'static str {
        DoiKind::Dihedral.name()
    }
    fn domain(&self) -> Domain {
        Domain::Edges
    }
    fn is_view_dependent(&self) -> bool {
        false
    }
    fn default_threshold(&self) -> f32 {
        30.0
    }
    fn evaluate(&self, mesh: &Mesh, _ctx: &DoiContext, out: &mut Vec<f32>) -> Result<(), DoiError> {
        let mut normals = Vec::new();
        subdiv_mesh::face_normals(mesh, &mut normals);
        out.clear();
        out.extend(mesh.edges().map(|e| dihedral_angle_deg(mesh, &normals, e)));
        Ok(())
    }
}

/// The DoI of eq. (3) for edge `e` given the face normals: the angle between the normals in
/// degrees, 0 for concave and boundary edges.
#[inline]
pub fn dihedral_angle_deg(mesh: &Mesh, normals: &[glam::Vec3], e: EdgeId) -> f32 {
    let h = e.halfedge(0);
    let (f1, f2) = (mesh.face(h), mesh.face(h.twin()));
    if !f1.is_some() || !f2.is_some() {
        return 0.0;
    }
    let (n1, n2) = (normals[f1.idx()], normals[f2.idx()]);
    // Concave when the far vertex of the second face lies in front of the first face's plane.
    let a = mesh.position(mesh.from(h));
    let d = mesh.position(mesh.to(mesh.next(h.twin())));
    let scale = (d - a).length();
    if n1.dot(d - a) > 1e-6 * scale {
        return 0.0;
    }
    // atan2 of sine and cosine keeps small angles accurate (acos near 1 does not in f32).
    n1.cross(n2).length().atan2(n1.dot(n2)).to_degrees()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use subdiv_mesh::PolygonSoup;

    fn grid(n: u32, height: impl Fn(f32, f32) -> f32) -> Mesh {
        let g = subdiv_test_support::height_grid(n, true, 0.0, height);
        let p = g.positions.into_iter().map(Vec3::from).collect();
        Mesh::from_soup(&PolygonSoup::from_faces(p, &g.faces)).unwrap()
    }

    #[test]
    fn flat_grid_is_zero_and_folds_are_convex_or_concave() {
        let mut v = Vec::new();
        let flat = grid(4, |_, _| 0.0);
        Dihedral
            .evaluate(&flat, &DoiContext::default(), &mut v)
            .unwrap();
        assert!(v.iter().all(|&a| a == 0.0), "{v:?}");
        // A ridge along x = 2 (roof, convex seen from +z, the side the normals face).
        let ridge = grid(4, |x, _| -(x - 2.0).abs());
        Dihedral
            .evaluate(&ridge, &DoiContext::default(), &mut v)
            .unwrap();
        let want = 90.0;
        let on_fold = |m: &Mesh, e: EdgeId| {
            let [a, b] = m.edge_vertices(e);
            m.position(a).x == 2.0 && m.position(b).x == 2.0
        };
        for e in ridge.edges() {
            if on_fold(&ridge, e) {
                assert!(
                    (v[e.idx()] - want).abs() < 1e-3,
                    "ridge edge {e}: {}",
                    v[e.idx()]
                );
            } else {
                assert!(
                    v[e.idx()].abs() < 1e-3,
                    "edge {e} {:?}: {}",
                    ridge.edge_vertices(e),
                    v[e.idx()]
                );
            }
        }
        // The same fold the other way (a valley) is concave: 0.
        let valley = grid(4, |x, _| (x - 2.0).abs());
        Dihedral
            .evaluate(&valley, &DoiContext::default(), &mut v)
            .unwrap();
        assert!(v.iter().all(|&a| a == 0.0));
    }
}
