//! Step 1 of the red-green closure: what one adaptive step refines.

use subdiv_mesh::{EdgeId, FaceId, Mesh, VertexId};

use super::green::{FamilyFaces, GreenState, NO_FAMILY};
use crate::RedGreenError;
use crate::error::check_len;

/// The result of [`close`]: what one adaptive step refines.
#[derive(Clone, Debug, PartialEq)]
pub struct Closure {
    /// Per face: refined (red) in this step. Includes every face of a merged family.
    pub red_face: Vec<bool>,
    /// Per family of the input [`GreenState`]: merged back into its parent, which is refined.
    pub merged: Vec<bool>,
    /// Per edge: gets a new midpoint in this step.
    pub split_edge: Vec<bool>,
    /// Per vertex: a corner of a triangle refined in this step (selected, promoted, or the parent
    /// of a merged family). These are the vertices Loop's vertex rule moves.
    pub moves: Vec<bool>,
}

impl Closure {
    /// Number of edges that get a midpoint.
    pub fn num_split_edges(&self) -> usize {
        self.split_edge.iter().filter(|&&s| s).count()
    }
}

struct Marker<'a> {
    mesh: &'a Mesh,
    state: &'a GreenState,
    families: FamilyFaces,
    c: Closure,
    queue: Vec<EdgeId>,
}

impl Marker<'_> {
    #[inline]
    fn split(&mut self, e: EdgeId) {
        if !self.c.split_edge[e.idx()] {
            self.c.split_edge[e.idx()] = true;
            self.queue.push(e);
        }
    }

    fn mark_face(&mut self, f: FaceId) {
        if self.c.red_face[f.idx()] {
            return;
        }
        self.c.red_face[f.idx()] = true;
        let h0 = self.mesh.face_halfedge(f);
        let hs = [h0, self.mesh.next(h0), self.mesh.prev(h0)];
        for h in hs {
            self.c.moves[self.mesh.from(h).idx()] = true;
            self.split(h.edge());
        }
    }

    fn mark_family(&mut self, fam: u32) -> Result<(), RedGreenError> {
        let k = fam as usize;
        if self.c.merged[k] {
            return Ok(());
        }
        self.c.merged[k] = true;
        for &f in self.families.of(fam) {
            self.c.red_face[f as usize] = true;
        }
        let fam_rec = self.state.families[k];
        for j in 0..3 {
            let a = fam_rec.parent[j];
            let b = fam_rec.parent[(j + 1) % 3];
            self.c.moves[a.idx()] = true;
            if fam_rec.mids[j] == VertexId::NONE {
                let h = self
                    .mesh
                    .find_halfedge(a, b)
                    .ok_or(RedGreenError::BrokenFamily {
                        family: fam,
                        a: a.0,
                        b: b.0,
                    })?;
                self.split(h.edge());
            }
        }
        Ok(())
    }

    fn mark_unit(&mut self, f: FaceId) -> Result<(), RedGreenError> {
        match self.state.family_of_face[f.idx()] {
            NO_FAMILY => {
                self.mark_face(f);
                Ok(())
            }
            fam => self.mark_family(fam),
        }
    }
}

/// Computes the red-green closure of the selection `selected` (one flag per face of `mesh`).
///
/// Selected faces are refined; a selected green face merges its family back, and the parent is
/// refined. Then, until nothing changes: a green face with a split edge merges its family, and a
/// non-green face with three split edges is refined. Faces left with one or two split edges are
/// closed green by [`assemble`](super::assemble).
///
/// ```
/// use subdiv_mesh::{Mesh, PolygonSoup, glam::Vec3};
/// use subdiv_redgreen::red_green::{close, GreenState};
/// // A fan of three triangles around vertex 0; refining the middle one splits the edges it
/// // shares with the other two.
/// let p = vec![Vec3::ZERO, Vec3::X, Vec3::new(0.0, 1.0, 0.0), Vec3::new(-1.0, 0.0, 0.0), Vec3::new(0.0, -1.0, 0.0)];
/// let mesh = Mesh::from_soup(&PolygonSoup::from_faces(p, &[[0u32, 1, 2], [0, 2, 3], [0, 3, 4]]))?;
/// let c = close(&mesh, &GreenState::new(3), &[false, true, false])?;
/// assert_eq!(c.red_face, vec![false, true, false]);
/// assert!(c.moves[0] && c.moves[2] && c.moves[3] && !c.moves[1]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn close(mesh: &Mesh, state: &GreenState, selected: &[bool]) -> Result<Closure, RedGreenError> {
    let nf = mesh.num_faces();
    check_len("selection", selected.len(), nf)?;
    check_len("green family_of_face", state.family_of_face.len(), nf)?;
    mesh.check_triangles()?;
    let nfam = state.families.len();
    let families = state.family_faces()?;
    let mut m = Marker {
        mesh,
        state,
        families,
        c: Closure {
            red_face: vec![false; nf],
            merged: vec![false; nfam],
            split_edge: vec![false; mesh.num_edges()],
            moves: vec![false; mesh.num_vertices()],
        },
        queue: Vec::new(),
    };
    for f in mesh.faces() {
        if selected[f.idx()] {
            m.mark_unit(f)?;
        }
    }
    while let Some(e) = m.queue.pop() {
        for side in 0..2 {
            let g = mesh.face(e.halfedge(side));
            if g == FaceId::NONE || m.c.red_face[g.idx()] {
                continue;
            }
            if state.family_of_face[g.idx()] != NO_FAMILY {
                m.mark_unit(g)?;
                continue;
            }
            let h0 = mesh.face_halfedge(g);
            let n = [h0, mesh.next(h0), mesh.prev(h0)]
                .iter()
                .filter(|h| m.c.split_edge[h.edge().idx()])
                .count();
            if n == 3 {
                m.mark_face(g);
            }
        }
    }
    Ok(m.c)
}
