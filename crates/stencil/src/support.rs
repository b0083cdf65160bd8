//! Each face's *neighbourhood* `N(F)` (the vertices of every face that shares a vertex with
//! it: the support of its limit surface), in an order that is a function of the face's
//! neighbourhood alone, and a colouring of the cage that separates every neighbourhood's
//! vertices (`table.rs` probes one colour per coordinate).

use subdiv_mesh::{FaceId, HalfedgeId, Mesh};

/// Calls `visit` with the half-edge out of `h`'s origin of every face around it: counter-
/// clockwise from `h`'s face, then, where a boundary stopped the turn, clockwise from it.
fn around(mesh: &Mesh, h: HalfedgeId, mut visit: impl FnMut(HalfedgeId)) {
    let mut k = h;
    loop {
        visit(k);
        k = mesh.prev(k).twin();
        if k == h || !mesh.face(k).is_some() {
            break;
        }
    }
    if k == h {
        return;
    }
    // Clockwise from `h`: the face across the edge before, and on.
    let mut k = h.twin();
    while mesh.face(k).is_some() {
        let out = mesh.next(k);
        visit(out);
        k = out.twin();
        if k == h {
            break;
        }
    }
}

/// Every face's neighbourhood `N(F)`, each in the order its corners and the faces around them
/// are met from the face's first half-edge (so alike neighbourhoods list alike vertices at the
/// same places), and for every vertex the faces whose neighbourhood holds it.
pub(crate) struct Neighbourhoods {
    offsets: Vec<u32>,
    vertices: Vec<u32>,
}

impl Neighbourhoods {
    pub(crate) fn new(mesh: &Mesh) -> Neighbourhoods {
        let mut offsets = Vec::with_capacity(mesh.num_faces() + 1);
        let mut vertices = Vec::new();
        let mut stamp = vec![u32::MAX; mesh.num_vertices()];
        offsets.push(0);
        for f in mesh.faces() {
            let f: FaceId = f;
            let start = vertices.len();
            debug_assert!(start == vertices.len());
            for h in mesh.face_halfedges(f) {
                around(mesh, h, |g| {
                    // The face's vertices from the one it shares with `f`'s corner.
                    let mut k = g;
                    loop {
                        let w = mesh.from(k);
                        if stamp[w.idx()] != f.0 {
                            stamp[w.idx()] = f.0;
                            vertices.push(w.0);
                        }
                        k = mesh.next(k);
                        if k == g {
                            break;
                        }
                    }
                });
            }
            offsets.push(vertices.len() as u32);
        }
        Neighbourhoods { offsets, vertices }
    }

    pub(crate) fn of(&self, f: usize) -> &[u32] {
        &self.vertices[self.offsets[f] as usize..self.offsets[f + 1] as usize]
    }

    /// A colour per vertex such that no neighbourhood holds two vertices of one colour
    /// (greedy, in vertex order).
    pub(crate) fn colours(&self, num_vertices: usize) -> Vec<u32> {
        // The faces whose neighbourhood holds each vertex.
        let mut count = vec![0u32; num_vertices + 1];
        for &v in &self.vertices {
            count[v as usize + 1] += 1;
        }
        for v in 0..num_vertices {
            count[v + 1] += count[v];
        }
        let mut faces = vec![0u32; self.vertices.len()];
        let mut next = count.clone();
        for f in 0..self.offsets.len() - 1 {
            for &v in self.of(f) {
                faces[next[v as usize] as usize] = f as u32;
                next[v as usize] += 1;
            }
        }
        let mut colour = vec![u32::MAX; num_vertices];
        let mut taken: Vec<u32> = Vec::new();
        for v in 0..num_vertices {
            for &f in &faces[count[v] as usize..count[v + 1] as usize] {
                for &w in self.of(f as usize) {
                    let c = colour[w as usize];
                    if c != u32::MAX {
                        if taken.len() <= c as usize {
                            taken.resize(c as usize + 1, u32::MAX);
                        }
                        taken[c as usize] = v as u32;
                    }
                }
            }
            let c = (0..).find(|&c| taken.get(c).is_none_or(|&t| t != v as u32));
            colour[v] = c.unwrap_or(0) as u32;
        }
        colour
    }
}
