//! Step 3: boundary loops. Every half-edge without a face is linked to the boundary half-edge
//! leaving its end vertex, which must be unique: a vertex where two boundary loops meet (a
//! bow-tie) is non-manifold. Then every vertex gets its out half-edge.

use super::{Cycles, Edges, FaceLists};
use crate::error::MeshError;
use crate::handle::HalfedgeId;
use crate::soup::PolygonSoup;

/// Links the boundary half-edges into loops. Returns, per vertex, the boundary half-edge
/// leaving it ([`HalfedgeId::NONE`] for interior and isolated vertices).
pub(super) fn link_loops(
    soup: &PolygonSoup,
    nv: u32,
    edges: &Edges,
    cycles: &mut Cycles,
) -> Result<Vec<HalfedgeId>, MeshError> {
    let (he_to, he_face) = (&edges.he_to, &edges.he_face);
    let nh = he_to.len();
    let mut boundary_out = vec![HalfedgeId::NONE; nv as usize];
    for h in 0..nh {
        if !he_face[h].is_some() {
            let from = he_to[h ^ 1];
            if boundary_out[from.idx()].is_some() {
                return Err(MeshError::NonManifoldVertex {
                    vertex: from.0,
                    fans: 2,
                    line: soup.vertex_line(from.idx()),
                });
            }
            boundary_out[from.idx()] = HalfedgeId(h as u32);
        }
    }
    for h in 0..nh {
        if !he_face[h].is_some() {
            let to = he_to[h];
            let n = boundary_out[to.idx()];
            cycles.he_next[h] = n;
            cycles.he_prev[n.idx()] = HalfedgeId(h as u32);
        }
    }
    Ok(boundary_out)
}

/// The out half-edge of every vertex — for a boundary vertex its leading edge (the twin of the
/// boundary half-edge arriving there), otherwise the half-edge of its first face corner — and
/// the number of face corners at each vertex. Isolated vertices get [`HalfedgeId::NONE`].
pub(super) fn vertex_out(
    nv: u32,
    faces: &FaceLists,
    edges: &Edges,
    cycles: &Cycles,
    boundary_out: &[HalfedgeId],
) -> (Vec<HalfedgeId>, Vec<u32>) {
    let mut vertex_out = vec![HalfedgeId::NONE; nv as usize];
    let mut corner_count = vec![0u32; nv as usize];
    for (k, v) in faces.verts.iter().enumerate() {
        corner_count[v.idx()] += 1;
        if !vertex_out[v.idx()].is_some() {
            vertex_out[v.idx()] = edges.corner_he[k];
        }
    }
    for v in 0..nv as usize {
        let b = boundary_out[v];
        if b.is_some() {
            vertex_out[v] = cycles.he_prev[b.idx()].twin();
        }
    }
    (vertex_out, corner_count)
}
