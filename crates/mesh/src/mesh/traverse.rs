//! Traversal of the half-edge structure: the counter-clockwise ring of half-edges around a
//! vertex and the queries built on it.

use super::Mesh;
use crate::handle::{HalfedgeId, VertexId};

/// Counter-clockwise iterator over the outgoing half-edges of a vertex.
pub struct Outgoing<'a> {
    mesh: &'a Mesh,
    start: HalfedgeId,
    cur: HalfedgeId,
    done: bool,
}

impl Iterator for Outgoing<'_> {
    type Item = HalfedgeId;
    #[inline]
    fn next(&mut self) -> Option<HalfedgeId> {
        if self.done {
            return None;
        }
        let h = self.cur;
        if self.mesh.he_face[h.idx()].is_some() {
            let n = self.mesh.he_prev[h.idx()].twin();
            if n == self.start {
                self.done = true;
            }
            self.cur = n;
        } else {
            self.done = true;
        }
        Some(h)
    }
}

impl Mesh {
    /// Outgoing half-edges of `v`, counter-clockwise. Face `i` of the vertex lies between
    /// outgoing edges `i` and `i + 1`; for a boundary vertex the last edge is the boundary
    /// half-edge (no face), so there is one edge more than faces.
    #[inline]
    pub fn outgoing(&self, v: VertexId) -> Outgoing<'_> {
        let h = self.vertex_out[v.idx()];
        Outgoing {
            mesh: self,
            start: h,
            cur: h,
            done: !h.is_some(),
        }
    }
    /// Number of edges incident to `v`.
    pub fn valence(&self, v: VertexId) -> usize {
        self.outgoing(v).count()
    }
    /// The half-edge from `a` to `b`, if they share an edge.
    pub fn find_halfedge(&self, a: VertexId, b: VertexId) -> Option<HalfedgeId> {
        self.outgoing(a).find(|&h| self.to(h) == b)
    }
}
