//! Level balancing: a selection closure applied before the red-green closure.
//!
//! Every face carries a refinement level: 0 in the cage, `l + 1` for the four children of a
//! level-`l` triangle refined red, `l` for the green triangles closing a level-`l` triangle
//! (they stand in for their parent). [`balance`] extends a selection until, after the step, the
//! levels of any two faces sharing a vertex differ by at most one (2:1 balance across vertices,
//! as in restricted quadtrees and the classic red-green refinement of Bank, Sherman & Weiser).
//!
//! Why: Loop's vertex rule moves a vertex by about `β` times the length of its ring's edges. When
//! a vertex's ring mixes a fine side and a side several levels coarser, the long coarse edges
//! pull the vertex by a large multiple of the fine triangles' size at every step, and the fine
//! triangles beside it get thin (on the bunny with the view-angle DoI the smallest angle fell
//! from 13° to 0.4° in five unbalanced steps). With balanced levels every ring's edges are within
//! a factor of about two of each other, which bounds the distortion per step as in uniform Loop.
//!
//! It also refines red every triangle that would get two split edges (the classic rule of Bank,
//! Sherman & Weiser: green closure only for one hanging vertex), so every green triangle is a
//! median bisection of a red one. The paper's Fig. 1(b) closes two split edges with two
//! triangulation edges; that cut along the quadrilateral's diagonal can make angles well below
//! half the parent's.
//!
//! This knows nothing of DoIs; it only grows a face selection.

use subdiv_mesh::Mesh;

use super::close::{Closure, close};
use super::green::GreenState;
use crate::LoopError;
use crate::error::check_len;

/// Grows `selected` (one flag per face of `mesh`, with levels `level`) until the red-green
/// closure of the selection leaves the levels 2:1 balanced across vertices (for every face `f`
/// refined in the step, new level `level[f] + 1`, every face sharing a vertex with `f` has level
/// at least `level[f]` afterwards) and no face is left with two split edges. Returns the grown selection and its closure; the number of
/// faces added is the cost of balancing.
///
/// If the levels are balanced before the step they are balanced after it. With every face (or
/// no face) selected the selection is returned unchanged.
///
/// ```
/// use subdiv_mesh::{Mesh, PolygonSoup, glam::Vec3};
/// use subdiv_loop::red_green::{balance, GreenState};
/// // A fan of three triangles around vertex 0; face 1 is one level finer than its neighbours.
/// let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(-1.0, 0.0, 0.0), Vec3::new(0.0, -1.0, 0.0)];
/// let mesh = Mesh::from_soup(&PolygonSoup::from_faces(p, &[[0u32, 1, 2], [0, 2, 3], [0, 3, 4]]))?;
/// let (sel, _) = balance(&mesh, &GreenState::new(3), &[0, 1, 0], &[false, true, false])?;
/// // Refining face 1 to level 2 needs its vertex-neighbours at level 1 at least.
/// assert_eq!(sel, vec![true, true, true]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn balance(
    mesh: &Mesh,
    state: &GreenState,
    level: &[u8],
    selected: &[bool],
) -> Result<(Vec<bool>, Closure), LoopError> {
    check_len("face levels", level.len(), mesh.num_faces())?;
    let mut sel = selected.to_vec();
    let mut top = vec![0u8; mesh.num_vertices()];
    loop {
        let c = close(mesh, state, &sel)?;
        // The highest level around every vertex after the step.
        top.iter_mut().for_each(|t| *t = 0);
        for f in mesh.faces() {
            let l = level[f.idx()].saturating_add(u8::from(c.red_face[f.idx()]));
            for v in mesh.face_vertices(f) {
                top[v.idx()] = top[v.idx()].max(l);
            }
        }
        let mut grown = false;
        for f in mesh.faces() {
            let i = f.idx();
            if c.red_face[i] || sel[i] {
                continue;
            }
            let limit = level[i].saturating_add(1);
            let h0 = mesh.face_halfedge(f);
            let splits = [h0, mesh.next(h0), mesh.prev(h0)]
                .iter()
                .filter(|h| c.split_edge[h.edge().idx()])
                .count();
            if splits >= 2 || mesh.face_vertices(f).iter().any(|v| top[v.idx()] > limit) {
                sel[i] = true;
                grown = true;
            }
        }
        if !grown {
            return Ok((sel, c));
        }
    }
}
