//! Face-varying data (UVs) through adaptive Loop refinement.
//!
//! A pass refines the mesh's face-varying channel ([`Mesh::uv`]) with the same selection and
//! closure as the positions and with the rules of uniform refinement
//! ([`subdiv_rules::refine_face_varying_part`], OpenSubdiv's face-varying rules and linear
//! interpolation options, seams kept): the values of the moved vertices are refined (each
//! sibling of a seam on its own), every split edge gets its edge value (one per side of a seam
//! or linear edge), and every other corner keeps its value. As for the positions, a balanced
//! pass reads every value at the level it refines ([`AdaptiveMesh::previous_uv`] for the values
//! of vertices one level ahead), leaves the edges inside green families out of a vertex's ring,
//! and reads a merged family's parent corner opposite a parent edge: with every face selected
//! the channel is exactly [`subdiv_rules::refine_uniform`]'s. Green triangles take the values of
//! their parent's corners and of the split edge's midpoint on their side, so values are
//! continuous across every edge that is not a seam.

use glam::Vec2;
use subdiv_mesh::{Dependence, EdgeId, FaceId, FaceVarying, HalfedgeId, Mesh, VertexId};
use subdiv_rules::{FVarChildren, FVarRegion, RefineKernel, refine_face_varying_part};

use crate::RedGreenError;
use crate::pass::{inside_family, opposite, vertex_levels};
use crate::red_green::{Assembly, Closure, FamilyFaces, NO_FAMILY};
use crate::step::AdaptiveMesh;

/// The region one pass refines: its moved vertices and split edges.
struct PassRegion<'a> {
    cur: &'a AdaptiveMesh,
    closure: &'a Closure,
    families: &'a FamilyFaces,
    by_level: bool,
}

impl FVarRegion for PassRegion<'_> {
    #[inline]
    fn refines_vertex(&self, v: VertexId) -> bool {
        self.closure.moves[v.idx()]
    }
    #[inline]
    fn splits_edge(&self, e: EdgeId) -> bool {
        self.closure.split_edge[e.idx()]
    }
    #[inline]
    fn skips(&self, h: HalfedgeId) -> bool {
        self.by_level && inside_family(&self.cur.mesh, &self.cur.green, h)
    }
    fn opposite(&self, h: HalfedgeId) -> HalfedgeId {
        let mesh = &self.cur.mesh;
        let o = opposite(self.cur, &self.closure.merged, h);
        let prev = mesh.prev(h);
        if mesh.from(prev) == o {
            return prev;
        }
        // An edge of a merged family's parent: the family face holding the parent's corner.
        let fam = self.cur.green.family_of_face[mesh.face(h).idx()];
        if fam == NO_FAMILY {
            return prev;
        }
        for &g in self.families.of(fam) {
            let h0 = mesh.face_halfedge(FaceId(g));
            for k in [h0, mesh.next(h0), mesh.prev(h0)] {
                if mesh.from(k) == o {
                    return k;
                }
            }
        }
        prev
    }
}

/// The refined channel of one pass: the values and the value of every corner of the assembled
/// triangles, and each value's previous-level value.
pub(crate) struct PassUvs {
    /// The values (unused ones dropped).
    pub values: Vec<Vec2>,
    /// The value of every triangle corner, in the assembly's order.
    pub indices: Vec<i64>,
    /// Per value: its value one level before ([`AdaptiveMesh::previous_uv`]).
    pub previous: Vec<Vec2>,
    /// Per value: its [`Dependence`] ([`FaceVarying::dependence`]).
    pub dependence: Vec<Dependence>,
}

/// The channel `fv` of `a` with every value at level `l`: the previous value for values of
/// vertices one level ahead (as [`crate::pass::level_positions`] does for positions).
fn level_uvs(a: &AdaptiveMesh, fv: &FaceVarying, l: u8) -> FaceVarying {
    let mesh = &a.mesh;
    let top = vertex_levels(mesh, &a.level);
    let mut at = fv.clone();
    let (offsets, indices) = mesh.face_lists();
    for f in mesh.faces() {
        for c in offsets[f.idx()] as usize..offsets[f.idx() + 1] as usize {
            if top[indices[c].idx()] > l {
                let i = fv.indices[c] as usize;
                at.values[i] = a.previous_uv[i];
            }
        }
    }
    at
}

/// Refines the UVs of `cur` (`None` without UVs) in the pass of `closure` read at `level`
/// (`None`: the current values, the paper's plain closure). `kernel` has computed the vertex
/// points of the pass (moved vertices and the ends of split edges); `edge_mid` and `asm` are
/// the pass's midpoints and triangles.
pub(crate) fn pass_uvs(
    kernel: &mut RefineKernel<'_>,
    cur: &AdaptiveMesh,
    closure: &Closure,
    level: Option<u8>,
    edge_mid: &[VertexId],
    asm: &Assembly,
) -> Result<Option<PassUvs>, RedGreenError> {
    let mesh = &cur.mesh;
    let Some(fv) = mesh.uv() else {
        return Ok(None);
    };
    let families = cur.green.family_faces()?;
    let region = PassRegion {
        cur,
        closure,
        families: &families,
        by_level: level.is_some(),
    };
    let at = level.map(|l| level_uvs(cur, fv, l));
    let mut values = fv.values.clone();
    let mut children =
        refine_face_varying_part(kernel, at.as_ref().unwrap_or(fv), &region, &mut values);

    // Previous values: a refined vertex's new value was its corner's value; an edge value
    // has none before it.
    let old = fv.values.len();
    let mut previous = cur.previous_uv.clone();
    previous.extend_from_slice(&values[old..]);
    let (offsets, vertices) = mesh.face_lists();
    for f in mesh.faces() {
        let h0 = mesh.face_halfedge(f);
        for h in [h0, mesh.next(h0), mesh.prev(h0)] {
            let i = children.vertex_child[h.idx()] as usize;
            if i >= old && i < values.len() {
                let r = offsets[f.idx()] as usize..offsets[f.idx() + 1] as usize;
                let k = vertices[r.clone()].iter().position(|&x| x == mesh.from(h));
                previous[i] = fv.corner(r.start + k.unwrap_or(0));
            }
        }
    }

    let mut indices = Vec::with_capacity(asm.triangles.len() * 3);
    for (t, &src) in asm.triangles.iter().zip(&asm.source_face) {
        let fam = cur.green.family_of_face[src as usize];
        let faces = if fam != NO_FAMILY && closure.merged[fam as usize] {
            families.of(fam)
        } else {
            std::slice::from_ref(&src)
        };
        for &x in t {
            let i = corner_value(mesh, faces, VertexId(x), &children, edge_mid).ok_or(
                RedGreenError::UvCorner {
                    face: src,
                    vertex: x,
                },
            )?;
            indices.push(i64::from(i));
        }
    }
    let dependence = std::mem::take(&mut children.dependence);
    Ok(Some(compact(values, indices, previous, dependence)))
}

/// The child value of the corner at `x` of a triangle made from `faces` (one face, or the
/// faces of a merged family): a parent corner's value, or a split edge's midpoint value on
/// the side of those faces.
fn corner_value(
    mesh: &Mesh,
    faces: &[u32],
    x: VertexId,
    children: &FVarChildren,
    edge_mid: &[VertexId],
) -> Option<u32> {
    let old = x.idx() < mesh.num_vertices();
    for &g in faces {
        let h0 = mesh.face_halfedge(FaceId(g));
        for h in [h0, mesh.next(h0), mesh.prev(h0)] {
            let i = if old && mesh.from(h) == x {
                children.vertex_child[h.idx()]
            } else if !old && edge_mid[h.edge().idx()] == x {
                children.edge_child[h.idx()]
            } else {
                continue;
            };
            return (i != u32::MAX).then_some(i);
        }
    }
    None
}

/// Drops the values no corner uses, keeping the order of the others.
fn compact(
    values: Vec<Vec2>,
    mut indices: Vec<i64>,
    previous: Vec<Vec2>,
    dependence: Vec<Dependence>,
) -> PassUvs {
    let mut map = vec![i64::MAX; values.len()];
    for &i in &indices {
        map[i as usize] = 0;
    }
    let (mut kept, mut prev, mut dep) = (Vec::new(), Vec::new(), Vec::new());
    for (k, m) in map.iter_mut().enumerate() {
        if *m == 0 {
            *m = kept.len() as i64;
            kept.push(values[k]);
            prev.push(previous[k]);
            dep.push(dependence.get(k).copied().unwrap_or_default());
        }
    }
    for i in &mut indices {
        *i = map[*i as usize];
    }
    PassUvs {
        values: kept,
        indices,
        previous: prev,
        dependence: dep,
    }
}
