//! Per-frame resolution and ownership of shared points: each cage edge's resolution (the
//! deepest of its active units) and owner unit, each cage vertex's owner, and the output id of
//! every grid point of a patch through those owners (so both sides of a border reference the
//! same vertex).

use subdiv_mesh::{HalfedgeId, Mesh, VertexId};
use subdiv_slate::{PatchRef, PatchSet};

use super::assembler::{Block, UnitTopo};
use super::grid::{side_of, side_point};
use crate::slots::Slots;

/// Per-frame data derived from the depths.
pub(super) struct Frame<'a> {
    pub(super) mesh: &'a Mesh,
    pub(super) set: &'a PatchSet,
    pub(super) units: &'a [UnitTopo],
    pub(super) depth: &'a [u8],
    /// Per edge: resolution (max depth of its active units) and owner unit.
    pub(super) edge_res: Vec<u8>,
    edge_owner: Vec<u32>,
    vertex_owner: Vec<(u32, u32)>,
    /// Per half-edge: its index in its unit's `hs` (its side of the unit).
    side: &'a [u8],
    pub(super) blocks: &'a [Block],
    pub(super) slots: &'a Slots,
}

/// Per half-edge of `mesh` with a face: its index in that face's `hs` (boundary half-edges: 0).
pub(super) fn halfedge_sides(mesh: &Mesh, units: &[UnitTopo]) -> Vec<u8> {
    let mut side = vec![0u8; 2 * mesh.num_edges()];
    for u in units {
        for (k, h) in u.hs.iter().enumerate() {
            side[h.idx()] = k as u8;
        }
    }
    side
}

impl<'a> Frame<'a> {
    #[allow(clippy::too_many_arguments)]
    pub(super) fn new(
        mesh: &'a Mesh,
        set: &'a PatchSet,
        units: &'a [UnitTopo],
        side: &'a [u8],
        depth: &'a [u8],
        active: &'a [bool],
        blocks: &'a [Block],
        slots: &'a Slots,
    ) -> Frame<'a> {
        let ne = mesh.num_edges();
        let mut edge_res = vec![0u8; ne];
        let mut edge_owner = vec![u32::MAX; ne];
        for e in mesh.edges() {
            // Canonical order: the face of half-edge 0 first.
            for side in 0..2 {
                let f = mesh.face(e.halfedge(side));
                if !f.is_some() || !active[f.idx()] {
                    continue;
                }
                let d = depth[f.idx()];
                if edge_owner[e.idx()] == u32::MAX || d > edge_res[e.idx()] {
                    edge_res[e.idx()] = d;
                    edge_owner[e.idx()] = f.0;
                }
            }
        }
        let mut vertex_owner = vec![(u32::MAX, 0u32); mesh.num_vertices()];
        for v in mesh.vertices() {
            for h in mesh.outgoing(v) {
                let f = mesh.face(h);
                if f.is_some() && active[f.idx()] {
                    vertex_owner[v.idx()] = (f.0, u32::from(side[h.idx()]));
                    break;
                }
            }
        }
        Frame {
            mesh,
            set,
            units,
            depth,
            edge_res,
            edge_owner,
            vertex_owner,
            side,
            blocks,
            slots,
        }
    }

    /// The patch's own subdivision depth (level-1 patches are one less than their unit).
    #[inline]
    pub(super) fn patch_depth(&self, p: &PatchRef) -> u32 {
        self.depth[p.unit as usize] as u32 - p.level as u32
    }

    /// For each side of a patch: does it border a deeper unit?
    pub(super) fn fans(&self, p: &PatchRef) -> [bool; 4] {
        let u = p.unit as usize;
        let d = self.depth[u];
        let hs = &self.units[u].hs;
        let mut f = [false; 4];
        if p.level == 0 {
            for k in 0..4 {
                f[k] = self.edge_res[hs[k].edge().idx()] > d;
            }
        } else {
            let n = hs.len();
            let k = p.sub as usize;
            f[0] = self.edge_res[hs[k].edge().idx()] > d;
            f[3] = self.edge_res[hs[(k + n - 1) % n].edge().idx()] > d;
        }
        f
    }

    /// The cage edge along side `k` of patch `p`, if that side lies on one (level-1 patches:
    /// sides 0 and 3).
    pub(super) fn side_edge(&self, p: &PatchRef, k: usize) -> Option<subdiv_mesh::EdgeId> {
        let hs = &self.units[p.unit as usize].hs;
        if p.level == 0 {
            return Some(hs[k].edge());
        }
        let (n, sub) = (hs.len(), p.sub as usize);
        match k {
            0 => Some(hs[sub].edge()),
            3 => Some(hs[(sub + n - 1) % n].edge()),
            _ => None,
        }
    }

    /// The one-sided normal of patch `pi` at its own block point `own` (an id from
    /// [`Frame::own`]), if it has one there.
    #[inline]
    pub(super) fn own_sided(&self, pi: usize, own: u32) -> Option<[f32; 3]> {
        let b = &self.blocks[pi];
        if b.sided.is_empty() {
            return None;
        }
        b.sided_at(own - self.slots.start(pi))
    }

    /// Whether patch `pi`'s block holds its depth-`d` grid.
    #[inline]
    pub(super) fn has_depth(&self, pi: usize, d: u32) -> bool {
        self.blocks[pi].depth.is_some_and(|c| u32::from(c) >= d)
    }

    /// Output id of point `(i, j)` of patch `pi`'s own block at depth-`d` grid coordinates,
    /// where `d` may be the patch depth or one more (for fan centres and subdivided edges):
    /// `scale` = 1 for patch-depth coordinates, 2 for one level finer.
    #[inline]
    pub(super) fn own(&self, pi: usize, i: u32, j: u32, d_coords: u32) -> u32 {
        let b = &self.blocks[pi];
        debug_assert!(
            b.depth.is_some_and(|c| u32::from(c) >= d_coords),
            "block too coarse"
        );
        let depth = u32::from(b.depth.unwrap_or_default());
        let stride = 1u32 << (depth - d_coords);
        let w = (1u32 << depth) + 1;
        self.slots.start(pi) + j * stride * w + i * stride
    }

    #[inline]
    pub(super) fn patch_index(&self, unit: usize, sub: usize) -> usize {
        (self.set.units()[unit].first_patch as usize) + sub
    }

    /// Id of cage vertex `v` (through its owner unit).
    fn vertex_id(&self, v: VertexId) -> u32 {
        let (f, k) = self.vertex_owner[v.idx()];
        let u = f as usize;
        let unit = &self.set.units()[u];
        if unit.irregular {
            let pi = self.patch_index(u, k as usize);
            return self.own(pi, 0, 0, 0);
        }
        let pi = self.patch_index(u, 0);
        let d = self.depth[u] as u32;
        let n = 1u32 << d;
        let (i, j) = [(0, 0), (n, 0), (n, n), (0, n)][k as usize];
        self.own(pi, i, j, d)
    }

    /// Id of the point at parameter `t / 2^res` along half-edge `h` (from its start), where
    /// `res` is at most the edge's resolution this frame; `t` in `0..=2^res`.
    pub(super) fn edge_point_id(&self, h: HalfedgeId, t: u32, res: u32) -> u32 {
        let mesh = self.mesh;
        if t == 0 {
            return self.vertex_id(mesh.from(h));
        }
        if t == 1 << res {
            return self.vertex_id(mesh.to(h));
        }
        let e = h.edge();
        let r = self.edge_res[e.idx()] as u32;
        debug_assert!(res <= r);
        let t = t << (r - res);
        let owner = self.edge_owner[e.idx()] as usize;
        let hs = &self.units[owner].hs;
        // The owner's half-edge of this edge, and the parameter along it.
        let (k, th) = if mesh.face(h).0 as usize == owner {
            (self.side[h.idx()] as usize, t)
        } else {
            (self.side[h.twin().idx()] as usize, (1 << r) - t)
        };
        let unit = &self.set.units()[owner];
        if !unit.irregular {
            let pi = self.patch_index(owner, 0);
            let n = 1u32 << r;
            let (i, j) = side_point(k, th, n);
            return self.own(pi, i, j, r);
        }
        let ns = 1u32 << (r - 1);
        let nsub = hs.len();
        if th <= ns {
            let pi = self.patch_index(owner, k);
            let (i, j) = side_point(0, th, ns);
            self.own(pi, i, j, r - 1)
        } else {
            let pi = self.patch_index(owner, (k + 1) % nsub);
            let (i, j) = side_point(3, th - ns, ns);
            self.own(pi, i, j, r - 1)
        }
    }

    /// Id of grid point `(i, j)` (patch-depth coordinates) of patch `p`, through the owners of
    /// shared points. `fine` > 0 means coordinates one level finer (only for points on fanned
    /// sides, which are owned by the deeper neighbour, or the patch's own interior).
    #[inline]
    pub(super) fn point_id(&self, pi: usize, p: &PatchRef, i: u32, j: u32) -> u32 {
        let d = self.patch_depth(p);
        let n = 1u32 << d;
        let interior = i > 0 && i < n && j > 0 && j < n;
        if interior {
            return self.own(pi, i, j, d);
        }
        let u = p.unit as usize;
        let hs = &self.units[u].hs;
        let (k, s) = side_of(i, j, n);
        if p.level == 0 {
            return self.edge_point_id(hs[k], s, d);
        }
        // Level-1 patch: sides 0 and 3 are halves of cage edges, 1 and 2 inner edges of the unit.
        let nsub = hs.len();
        let sub = p.sub as usize;
        let ud = d + 1;
        match k {
            0 => self.edge_point_id(hs[sub], s, ud),
            3 => self.edge_point_id(hs[(sub + nsub - 1) % nsub], n + s, ud),
            1 => {
                // Inner edge `sub`, owned by this patch (s from the edge point to the face point);
                // its start is the midpoint of cage edge `sub`, owned through that edge.
                if s == 0 {
                    self.edge_point_id(hs[sub], n, ud)
                } else if s == n {
                    self.face_point_id(u)
                } else {
                    self.own(pi, i, j, d)
                }
            }
            _ => {
                // Side 2 runs from the face point to the previous inner edge's edge point.
                if s == 0 {
                    return self.face_point_id(u);
                }
                let prev = self.patch_index(u, (sub + nsub - 1) % nsub);
                let (pi2, pj2) = side_point(1, n - s, n);
                self.own(prev, pi2, pj2, d)
            }
        }
    }

    fn face_point_id(&self, u: usize) -> u32 {
        let pi = self.patch_index(u, 0);
        let d = self.depth[u] as u32 - 1;
        let n = 1u32 << d;
        self.own(pi, n, n, d)
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::{cube, split_cube};
    use super::super::{AdaptiveFrame, Assembler};

    #[test]
    fn the_deeper_side_owns_an_edge_and_both_sides_see_the_same_points() {
        for (name, mesh) in [("cube", cube()), ("split", split_cube())] {
            let nf = mesh.num_faces();
            let mut depth = vec![1u8; nf];
            depth[0] = 3;
            depth[nf - 1] = 2;
            let active = vec![true; nf];
            let mut asm = Assembler::new(&mesh, 3).unwrap();
            asm.frame(&mesh, &depth, &active, &mut AdaptiveFrame::default())
                .unwrap();
            asm.with_frame(&mesh, &depth, &active, |fr| {
                for e in mesh.edges() {
                    let (h0, h1) = (e.halfedge(0), e.halfedge(1));
                    let (f0, f1) = (mesh.face(h0).idx(), mesh.face(h1).idx());
                    let r = fr.edge_res[e.idx()];
                    assert_eq!(r, depth[f0].max(depth[f1]), "{name} edge {}", e.idx());
                    let owner = fr.edge_owner[e.idx()] as usize;
                    assert!(owner == f0 || owner == f1);
                    assert_eq!(depth[owner], r, "{name}: the owner is the deeper side");
                    // Both directions of the edge give the same point ids.
                    let r = r as u32;
                    for t in 0..=1u32 << r {
                        assert_eq!(
                            fr.edge_point_id(h0, t, r),
                            fr.edge_point_id(h1, (1 << r) - t, r),
                            "{name} edge {} t {t}",
                            e.idx()
                        );
                        // Coarser queries sample the same points.
                        if t % 2 == 0 && r > 0 {
                            assert_eq!(
                                fr.edge_point_id(h0, t / 2, r - 1),
                                fr.edge_point_id(h0, t, r)
                            );
                        }
                    }
                }
            });
        }
    }

    #[test]
    fn inactive_faces_own_nothing() {
        let mesh = cube();
        let depth = [3u8, 1, 1, 1, 1, 1];
        let mut active = [true; 6];
        active[0] = false;
        let mut asm = Assembler::new(&mesh, 3).unwrap();
        asm.frame(&mesh, &depth, &active, &mut AdaptiveFrame::default())
            .unwrap();
        asm.with_frame(&mesh, &depth, &active, |fr| {
            for e in mesh.edges() {
                let owner = fr.edge_owner[e.idx()] as usize;
                assert_ne!(owner, 0);
                assert_eq!(fr.edge_res[e.idx()], 1);
            }
            for &(f, _) in &fr.vertex_owner {
                assert_ne!(f, 0);
                assert!(active[f as usize]);
            }
            // No patch fans towards the culled deeper face.
            for p in fr.set.patches() {
                assert_eq!(fr.fans(p), [false; 4]);
            }
        });
    }
}
