//! Step 4: the vertex-manifold check. Every vertex with faces must have a single fan: the
//! counter-clockwise walk from its out half-edge must meet all of its faces.

use crate::error::MeshError;
use crate::handle::VertexId;
use crate::mesh::Mesh;
use crate::soup::PolygonSoup;

/// Refuses the first vertex whose ring walk misses some of its `corner_count` faces.
pub(super) fn check_vertex_fans(
    mesh: &Mesh,
    corner_count: &[u32],
    soup: &PolygonSoup,
) -> Result<(), MeshError> {
    for v in 0..mesh.num_vertices() as u32 {
        let corners = corner_count[v as usize];
        if corners == 0 {
            continue;
        }
        let faces_seen = faces_in_ring(mesh, VertexId(v), corners as usize + 2);
        if faces_seen != corners {
            let fans = if faces_seen == 0 {
                2
            } else {
                corners.div_ceil(faces_seen.max(1)).max(2)
            };
            return Err(MeshError::NonManifoldVertex {
                vertex: v,
                fans,
                line: soup.vertex_line(v as usize),
            });
        }
    }
    Ok(())
}

/// Faces met walking the ring of `v`; the walk stops after more than `limit` half-edges, a guard
/// against a ring that would not close.
fn faces_in_ring(mesh: &Mesh, v: VertexId, limit: usize) -> u32 {
    let mut faces_seen = 0u32;
    let mut steps = 0usize;
    for h in mesh.outgoing(v) {
        steps += 1;
        if mesh.face(h).is_some() {
            faces_seen += 1;
        }
        if steps > limit {
            break;
        }
    }
    faces_seen
}
