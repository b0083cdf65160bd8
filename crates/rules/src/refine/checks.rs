//! The checks every refinement path runs on a cage before refining it: doubled triangles
//! (Loop) and coordinates too large for `f32` sums.

use subdiv_mesh::Mesh;

use crate::RulesError;

/// Refuses two triangles on the same three vertices ([`RulesError::DoubledTriangle`]): Loop
/// refinement connects the edge points of every triangle, and for such a pair (a two-face
/// pillow) it would connect the same three edge points twice (parallel edges, which a [`Mesh`]
/// cannot hold). Such triangles always share an edge, so checking each face against its
/// neighbours finds them; refinement never creates new pairs. Every Loop path calls it before
/// refining.
pub fn check_doubled_triangles(mesh: &Mesh) -> Result<(), RulesError> {
    let sorted = |f| {
        let mut k: Vec<u32> = mesh.face_vertices(f).iter().map(|v| v.0).collect();
        k.sort_unstable();
        k
    };
    for f in mesh.faces() {
        let h0 = mesh.face_halfedge(f);
        for h in [h0, mesh.next(h0), mesh.prev(h0)] {
            let g = mesh.face(h.twin());
            if g.is_some() && g.0 < f.0 && sorted(f) == sorted(g) {
                return Err(RulesError::DoubledTriangle {
                    face: f.0,
                    other: g.0,
                });
            }
        }
    }
    Ok(())
}

/// Largest coordinate magnitude of a mesh to refine or tessellate ([`check_coordinates`]).
/// Subdivision sums weighted points in `f32`: near `f32::MAX` (3.4e38) they overflow to
/// infinity, while below this bound even a sum of a million weighted points stays finite.
pub const MAX_COORDINATE: f32 = 1e30;

/// Refuses the first vertex with a coordinate beyond [`MAX_COORDINATE`]
/// ([`RulesError::HugeCoordinate`]) or not finite ([`RulesError::NonFiniteCoordinate`]; a
/// largest magnitude alone would pass NaN, which `max` ignores). Checked on the cage by
/// [`refine_uniform_levels`] (and so [`tessellate_uniform`](crate::tessellate_uniform)) and
/// the slate tessellator, not on refined meshes, whose points may exceed a cage at the bound by
/// rounding.
///
/// [`refine_uniform_levels`]: crate::refine_uniform_levels
pub fn check_coordinates(mesh: &Mesh) -> Result<(), RulesError> {
    let pos = mesh.positions();
    let Some(v) = pos
        .iter()
        .position(|p| !p.is_finite() || p.abs().max_element() > MAX_COORDINATE)
    else {
        return Ok(());
    };
    let (vertex, p) = (v as u32, pos[v]);
    let (x, y, z) = (p.x, p.y, p.z);
    Err(if p.is_finite() {
        RulesError::HugeCoordinate { vertex, x, y, z }
    } else {
        RulesError::NonFiniteCoordinate { vertex, x, y, z }
    })
}
