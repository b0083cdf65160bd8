//! The fast path of the common face: a quad (Loop: triangle) whose corners are smooth interior
//! vertices of the regular valence with nothing sharp around them is one B-spline (box spline)
//! patch of the cage's own points; which points is found once per cage ([`regular_plans`]),
//! so evaluating such a face reads 16 (12) positions and no ring. The points are those
//! [`crate::patch::RegularPatch`] takes from the corner rings, in the same slots.

use rayon::prelude::*;
use subdiv_mesh::{FaceId, HalfedgeId, Mesh};
use subdiv_rules::Scheme;

/// No vertex in a slot (the four unused slots of a box spline patch).
pub(crate) const NONE: u32 = u32::MAX;

/// The control points of face `f` if it is a fully regular patch.
fn plan(mesh: &Mesh, scheme: Scheme, f: FaceId) -> Option<[u32; 16]> {
    let (n, valence) = match scheme {
        Scheme::CatmullClark => (4, 4),
        Scheme::Loop => (3, 6),
        Scheme::Bilinear => {
            unreachable!("bilinear faces are their corners' patches (FaceSurface::load)")
        }
    };
    if mesh.face_size(f) != n || mesh.is_hole(f) {
        return None;
    }
    let mut out = [NONE; 16];
    // Counter-clockwise next outgoing half-edge, as `Mesh::outgoing` steps.
    let ccw = |h: HalfedgeId| mesh.prev(h).twin();
    let mut h = mesh.face_halfedge(f);
    for k in 0..n {
        let v = mesh.from(h);
        if mesh.is_boundary_vertex(v)
            || mesh.vertex_sharpness(v) != 0.0
            || mesh.whole_vertex_edges(v).is_some()
            || mesh.crease_ends(v).is_some()
        {
            return None;
        }
        let mut count = 0;
        for g in mesh.outgoing(v) {
            count += 1;
            if count > valence
                || mesh.edge_sharpness(g.edge()) != 0.0
                || mesh.face_size(mesh.face(g)) != n
            {
                return None;
            }
        }
        if count != valence {
            return None;
        }
        let out_d = |d: usize| (0..d).fold(h, |g, _| ccw(g));
        match scheme {
            Scheme::CatmullClark => {
                // `RegularPatch::quad`'s slots: the corner, edge neighbours 2 and 3, the quad
                // after edge 2.
                const AT: [[usize; 4]; 4] =
                    [[5, 4, 1, 0], [6, 2, 7, 3], [10, 11, 14, 15], [9, 13, 8, 12]];
                out[AT[k][0]] = v.0;
                out[AT[k][1]] = mesh.to(out_d(2)).0;
                out[AT[k][2]] = mesh.to(out_d(3)).0;
                out[AT[k][3]] = mesh.to(mesh.next(out_d(2))).0;
            }
            Scheme::Loop => {
                const AT: [[usize; 4]; 3] = [[4, 3, 0, 1], [5, 2, 6, 9], [8, 11, 10, 7]];
                out[AT[k][0]] = v.0;
                for d in 3..6 {
                    out[AT[k][d - 2]] = mesh.to(out_d(d)).0;
                }
            }
            Scheme::Bilinear => {
                unreachable!("bilinear faces are their corners' patches (FaceSurface::load)")
            }
        }
        h = mesh.next(h);
    }
    Some(out)
}

/// [`plan`] of every face, `None` where the face takes the general path.
pub(crate) fn regular_plans(mesh: &Mesh, scheme: Scheme) -> Vec<Option<[u32; 16]>> {
    (0..mesh.num_faces() as u32)
        .into_par_iter()
        .map(|f| plan(mesh, scheme, FaceId(f)))
        .collect()
}
