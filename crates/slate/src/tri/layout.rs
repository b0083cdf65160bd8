//! Output numbering of the uniform Loop tessellation: one vertex per limit point and one owner
//! patch per shared point.
//!
//! Ids: cage vertices first (vertex `v` is id `v`), then `n - 1` points per cage edge (in the
//! direction of its even half-edge), then `(n - 1)(n - 2) / 2` interior points per cage triangle
//! (row by row), `n = 2^depth`. A cage vertex is owned by the face of its out half-edge (for a
//! boundary vertex its leading edge), a cage edge by the face of its even half-edge or, on the
//! boundary, by its one face; every triangle owns its interior.

use subdiv_mesh::{EdgeId, HalfedgeId, Mesh, VertexId};
use subdiv_rules::{Depth, RulesError, SeamCurves, TopologyKey};

/// One side of a triangular patch: the cage edge from corner `k` to corner `k + 1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TriSide {
    /// Id of the edge's first inner point (its even half-edge's direction).
    pub base: u32,
    /// `true` when the side runs against the edge's even half-edge.
    pub reversed: bool,
    /// `true` when this patch writes the side's points.
    pub owned: bool,
}

impl TriSide {
    /// Id of inner point `a` (`1..n`, counted from the side's first corner) of a side with `n`
    /// segments.
    #[inline]
    pub fn id(&self, n: u32, a: u32) -> u32 {
        if self.reversed {
            self.base + (n - 1 - a)
        } else {
            self.base + (a - 1)
        }
    }
}

/// One cage triangle's place in the output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TriPatch {
    /// The triangle's first half-edge (corner 0 to corner 1).
    pub halfedge: HalfedgeId,
    /// Ids of the three corners (cage vertex ids).
    pub corners: [u32; 3],
    /// Which corners this patch writes.
    pub corner_owned: [bool; 3],
    /// The three sides (corner `k` to corner `k + 1`).
    pub sides: [TriSide; 3],
    /// Id of the first interior point.
    pub interior: u32,
    /// `false` for a hole (with `interpolateboundary none` also the faces it hides, which
    /// `Mesh::from_soup` makes holes): its points are computed (where owned) but it has no
    /// triangles.
    pub visible: bool,
    /// The cage edge of each side.
    pub edges: [EdgeId; 3],
    /// The vertex beyond each side (of the triangle across it), `u32::MAX` on the boundary.
    pub beyond: [u32; 3],
    /// At each corner, the index in its [`TriLayout::ring`] of the edge along side `k`.
    pub r0: [u32; 3],
}

/// The numbering of the level-`depth` Loop tessellation of a cage of triangles. Read-only
/// once built: the triangles of its tessellation are a function of it alone, written once
/// per output ([`crate::tessellate_tri_layout_into`]).
#[derive(Clone, Debug)]
pub struct TriLayout {
    /// The subdivision depth.
    pub(crate) depth: Depth,
    /// One patch per cage face, in face order.
    pub(crate) patches: Vec<TriPatch>,
    /// Vertices in no face: output at their cage position with a zero normal.
    pub(crate) isolated: Vec<VertexId>,
    num_points: usize,
    ring_offsets: Vec<u32>,
    ring_verts: Vec<u32>,
    fast: Vec<bool>,
    /// The UVs of the first tessellation with UVs, for the calls that follow (`uv.rs`).
    pub(crate) uv_cache: crate::uv::UvCache,
    /// The cage's seams (copies of non-manifold edges), whose points are written from their
    /// chains ([`TriLayout::write_seam_points`], [`super::tri_patch_lattice`]).
    pub(crate) seams: SeamCurves,
    /// This layout's identity (a clone gets its own), kept by the outputs it wrote.
    pub(crate) key: LayoutKey,
}

/// A [`TopologyKey`] that a clone of its layout does not share.
#[derive(Debug)]
pub(crate) struct LayoutKey(pub(crate) TopologyKey);

impl Clone for LayoutKey {
    fn clone(&self) -> LayoutKey {
        LayoutKey(TopologyKey::fresh())
    }
}

impl TriLayout {
    /// The layout of `mesh` at `depth >= 1`; refuses what Loop cannot refine (faces that are not
    /// triangles, doubled triangles, huge coordinates).
    pub fn new(mesh: &Mesh, depth: Depth) -> Result<TriLayout, RulesError> {
        super::tessellate::check_loop_cage(mesh)?;
        let n = 1u32 << depth;
        let nv = mesh.num_vertices() as u32;
        let ne = mesh.num_edges() as u32;
        let per_face = (n - 1) * (n.saturating_sub(2)) / 2;
        let interior0 = nv + ne * (n - 1);
        // Every vertex's edge neighbours in `outgoing` order, and whether it is a smooth interior
        // vertex (no sharpness at it or its edges, valence >= 3).
        let mut ring_offsets = Vec::with_capacity(mesh.num_vertices() + 1);
        let mut ring_verts = Vec::with_capacity(2 * mesh.num_edges());
        let mut fast = Vec::with_capacity(mesh.num_vertices());
        ring_offsets.push(0);
        for v in mesh.vertices() {
            let mut smooth = mesh.vertex_sharpness(v) <= 0.0
                && !mesh.is_isolated(v)
                && mesh.crease_ends(v).is_none();
            for h in mesh.outgoing(v) {
                ring_verts.push(mesh.to(h).0);
                smooth &= mesh.edge_sharpness(h.edge()) <= 0.0 && mesh.face(h).is_some();
            }
            let valence = ring_verts.len() - *ring_offsets.last().expect("starts at 0") as usize;
            ring_offsets.push(ring_verts.len() as u32);
            fast.push(smooth && valence >= 3);
        }
        let mut patches = Vec::with_capacity(mesh.num_faces());
        for f in mesh.faces() {
            let h0 = mesh.face_halfedge(f);
            let hs = [h0, mesh.next(h0), mesh.prev(h0)];
            let corners = hs.map(|h| mesh.from(h).0);
            let corner_owned = hs.map(|h| mesh.face(mesh.vertex_halfedge(mesh.from(h))) == f);
            let sides = hs.map(|h| {
                let e = h.edge();
                let even = HalfedgeId(2 * e.0);
                let owner = if mesh.face(even).is_some() {
                    mesh.face(even)
                } else {
                    mesh.face(even.twin())
                };
                TriSide {
                    base: nv + e.0 * (n - 1),
                    reversed: h != even,
                    owned: owner == f,
                }
            });
            patches.push(TriPatch {
                halfedge: h0,
                corners,
                corner_owned,
                sides,
                interior: interior0 + f.0 * per_face,
                visible: !mesh.is_hole(f),
                edges: hs.map(|h| h.edge()),
                beyond: hs.map(|h| {
                    let t = h.twin();
                    if mesh.face(t).is_some() {
                        mesh.to(mesh.next(t)).0
                    } else {
                        u32::MAX
                    }
                }),
                r0: hs.map(|h| {
                    mesh.outgoing(mesh.from(h))
                        .position(|g| g == h)
                        .unwrap_or(0) as u32
                }),
            });
        }
        let isolated = mesh.vertices().filter(|&v| mesh.is_isolated(v)).collect();
        Ok(TriLayout {
            depth,
            patches,
            isolated,
            num_points: (interior0 + mesh.num_faces() as u32 * per_face) as usize,
            ring_offsets,
            ring_verts,
            fast,
            uv_cache: Default::default(),
            seams: SeamCurves::new(mesh),
            key: LayoutKey(TopologyKey::fresh()),
        })
    }

    /// The subdivision depth.
    pub fn depth(&self) -> Depth {
        self.depth
    }

    /// One patch per cage face, in face order.
    pub fn patches(&self) -> &[TriPatch] {
        &self.patches
    }

    /// Vertices in no face: output at their cage position with a zero normal.
    pub fn isolated(&self) -> &[VertexId] {
        &self.isolated
    }

    /// Overwrites the points on the cage's seams (the copies of a non-manifold edge and their
    /// end vertices) in a uniform tessellation at this layout's depth with [`SeamCurves`]'
    /// values, the same bits in every copy, so the pieces of a non-manifold cage meet exactly.
    pub(crate) fn write_seam_points(&self, mesh: &Mesh, positions: &mut [[f32; 3]]) {
        let edge_base = mesh.num_vertices() as u32;
        self.seams
            .write_uniform(mesh, self.depth, edge_base, positions);
    }

    /// The edge neighbours of cage vertex `v` in `Mesh::outgoing` order.
    #[inline]
    pub fn ring(&self, v: u32) -> &[u32] {
        let v = v as usize;
        &self.ring_verts[self.ring_offsets[v] as usize..self.ring_offsets[v + 1] as usize]
    }

    /// `true` for a smooth interior cage vertex (valence 3 or more, no sharpness at it or its
    /// edges): its corners are refined by the fast smooth rules.
    #[inline]
    pub fn is_fast(&self, v: u32) -> bool {
        self.fast[v as usize]
    }

    /// Number of output points.
    pub fn num_points(&self) -> usize {
        self.num_points
    }

    /// Output id of lattice point `(i, j)` of patch `p` (`i` along corner 0 to 1, `j` along
    /// corner 0 to 2, `i + j <= n`), and whether the patch owns it.
    #[inline]
    pub fn point_id(p: &TriPatch, n: u32, i: u32, j: u32) -> (u32, bool) {
        match (i, j) {
            (0, 0) => (p.corners[0], p.corner_owned[0]),
            (i, 0) if i == n => (p.corners[1], p.corner_owned[1]),
            (0, j) if j == n => (p.corners[2], p.corner_owned[2]),
            (i, 0) => (p.sides[0].id(n, i), p.sides[0].owned),
            (i, j) if i + j == n => (p.sides[1].id(n, j), p.sides[1].owned),
            (0, j) => (p.sides[2].id(n, n - j), p.sides[2].owned),
            (i, j) => (p.interior + interior_offset(n, j) + (i - 1), true),
        }
    }
}

/// Index of the first interior point of row `j` (`1 <= j <= n - 2`; row `j` holds `n - 1 - j`).
#[inline]
pub fn interior_offset(n: u32, j: u32) -> u32 {
    (j - 1) * (n - 1) - (j - 1) * j / 2
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_point_has_one_owner() {
        let text =
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 2 0 0\nv 5 5 5\nf 1 2 3\nf 2 4 3\nf 2 5 4\n";
        let mesh = Mesh::from_soup(&subdiv_mesh::parse_obj(text).unwrap()).unwrap();
        for depth in 1..=4 {
            let layout = TriLayout::new(&mesh, depth).unwrap();
            let n = 1u32 << depth;
            let mut count = vec![0u32; layout.num_points()];
            for v in &layout.isolated {
                count[v.idx()] += 1;
            }
            for p in &layout.patches {
                for j in 0..=n {
                    for i in 0..=n - j {
                        let (id, owned) = TriLayout::point_id(p, n, i, j);
                        if owned {
                            count[id as usize] += 1;
                        }
                    }
                }
            }
            assert!(count.iter().all(|&c| c == 1), "depth {depth}: {count:?}");
        }
    }
}
