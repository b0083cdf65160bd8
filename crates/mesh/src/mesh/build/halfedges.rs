//! Step 2: half-edge linking. Pairs the sides of the faces into edges — an edge may have at most
//! two faces, which traverse it in opposite directions — and links each face's half-edges into
//! a next/prev cycle.

use std::collections::HashMap;

use super::{Cycles, Edges, FaceLists};
use crate::error::MeshError;
use crate::handle::{FaceId, HalfedgeId, VertexId};
use crate::soup::PolygonSoup;

/// Creates the edges of all faces, in face order, refusing the first side that would make an
/// edge non-manifold or inconsistently oriented.
pub(super) fn pair_edges(soup: &PolygonSoup, faces: &FaceLists) -> Result<Edges, MeshError> {
    let ncorners = faces.verts.len();
    let mut edges = Edges {
        map: HashMap::with_capacity(ncorners),
        he_to: Vec::with_capacity(ncorners + ncorners / 4),
        he_face: Vec::with_capacity(ncorners + ncorners / 4),
        corner_he: Vec::with_capacity(ncorners),
    };
    for fi in 0..faces.num_faces() {
        let c = faces.corners(fi);
        let (s, n) = (c.start, c.len());
        for k in 0..n {
            let a = faces.verts[s + k].0;
            let b = faces.verts[s + (k + 1) % n].0;
            let key = (a.min(b), a.max(b));
            let h = match edges.map.get(&key) {
                None => edges.open(key, a, b, fi),
                Some(&eidx) => edges.close(soup, eidx, key, (a, b), fi)?,
            };
            edges.corner_he.push(h);
        }
    }
    Ok(edges)
}

impl Edges {
    /// A new edge for side `a -> b` of face `fi`; returns its half-edge `2e` (from `a` to `b`).
    fn open(&mut self, key: (u32, u32), a: u32, b: u32, fi: usize) -> HalfedgeId {
        let eidx = (self.he_to.len() / 2) as u32;
        self.map.insert(key, eidx);
        self.he_to.push(VertexId(b));
        self.he_to.push(VertexId(a));
        self.he_face.push(FaceId(fi as u32));
        self.he_face.push(FaceId::NONE);
        HalfedgeId(eidx * 2)
    }

    /// Gives existing edge `eidx` its second face `fi` (side `a -> b`); returns half-edge
    /// `2e + 1`, or the error if the edge already has two faces or `fi` runs the same way as
    /// the first face.
    fn close(
        &mut self,
        soup: &PolygonSoup,
        eidx: u32,
        key: (u32, u32),
        (a, b): (u32, u32),
        fi: usize,
    ) -> Result<HalfedgeId, MeshError> {
        let h0 = HalfedgeId(eidx * 2);
        let h1 = h0.twin();
        let f0 = self.he_face[h0.idx()];
        let f1 = self.he_face[h1.idx()];
        if f1.is_some() {
            return Err(MeshError::NonManifoldEdge {
                a: key.0,
                b: key.1,
                faces: vec![f0.0, f1.0, fi as u32],
                line: soup.face_line(fi),
            });
        }
        if self.he_to[h0.idx()].0 == b {
            return Err(same_direction_error(soup, key, (a, b), fi, f0));
        }
        self.he_face[h1.idx()] = FaceId(fi as u32);
        Ok(h1)
    }
}

/// Face `fi` runs edge `a -> b` in the same direction as the edge's first face `first`. A later
/// face might still make the edge non-manifold, so look ahead to give the more useful error.
fn same_direction_error(
    soup: &PolygonSoup,
    key: (u32, u32),
    (a, b): (u32, u32),
    fi: usize,
    first: FaceId,
) -> MeshError {
    let mut users = vec![first.0, fi as u32];
    for fj in fi + 1..soup.num_faces() {
        let g = soup.face(fj);
        let m = g.len();
        if (0..m).any(|t| {
            let (x, y) = (g[t] as u32, g[(t + 1) % m] as u32);
            (x.min(y), x.max(y)) == key
        }) {
            users.push(fj as u32);
        }
    }
    if users.len() > 2 {
        return MeshError::NonManifoldEdge {
            a: key.0,
            b: key.1,
            faces: users,
            line: soup.face_line(fi),
        };
    }
    MeshError::InconsistentOrientation {
        a,
        b,
        face: fi as u32,
        other: first.0,
        line: soup.face_line(fi),
    }
}

/// Links the half-edges of every face into a cycle; boundary half-edges stay unlinked.
pub(super) fn link_faces(faces: &FaceLists, edges: &Edges) -> Cycles {
    let nh = edges.he_to.len();
    let nf = faces.num_faces();
    let mut cycles = Cycles {
        he_next: vec![HalfedgeId::NONE; nh],
        he_prev: vec![HalfedgeId::NONE; nh],
        face_he: Vec::with_capacity(nf),
    };
    for fi in 0..nf {
        let c = faces.corners(fi);
        let (s, n) = (c.start, c.len());
        for k in 0..n {
            let h = edges.corner_he[s + k];
            let hn = edges.corner_he[s + (k + 1) % n];
            cycles.he_next[h.idx()] = hn;
            cycles.he_prev[hn.idx()] = h;
        }
        cycles.face_he.push(edges.corner_he[s]);
    }
    cycles
}
