//! Non-manifold cages as OpenSubdiv takes them ([`PolygonSoup::split_nonmanifold`]).
//!
//! OpenSubdiv 3.5 refines non-manifold cages as they are:
//! `Far::TopologyRefinerFactoryBase::prepareComponentTagsAndSharpness` (with its
//! `sharpenNonManFeatures`, fixed to `true`) makes every non-manifold edge (more than two faces,
//! or two faces using it the same way round) infinitely sharp, and every non-manifold vertex
//! (several fans of faces, or on a non-manifold edge) an infinitely sharp corner unless it lies
//! on an interior non-manifold crease (exactly two non-manifold edges, no boundary edge and
//! more faces than edges), where `DetermineVertexVertexRule` decides from all its sharp edges
//! (two: the crease rule along them; more: a corner). Bare vertices (no face) stay where they
//! are.
//!
//! subdiv's [`Mesh`](crate::Mesh) is manifold, so the cage is cut into manifold pieces that
//! refine to the same points: every fan of faces around a vertex gets its own copy of the vertex,
//! every piece its own copy of a non-manifold edge (tagged infinitely sharp), and every copy the
//! rule OpenSubdiv gives the whole vertex (an infinite corner tag where that is a corner). The
//! crease and corner masks read only the points along the sharp edges, which every copy has, so
//! each copy refines and takes its limit exactly where OpenSubdiv puts the one vertex; the copies
//! coincide. A semi-sharp vertex sharpness at a crease vertex is carried by every copy, so
//! every copy is a corner while it lasts and blends into the crease rule at the same level by
//! the same weight, as the whole vertex does. Semi-sharp edges at a non-manifold vertex enter
//! OpenSubdiv's rule (three sharp edges or more: a corner), its fractional weight (the average
//! of what runs out) and the Chaikin decay of each (the average of the others) over all the
//! vertex's edges, every copy's together: so every copy carries the values of all of them
//! ([`Mesh::whole_vertex_edges`](crate::Mesh::whole_vertex_edges)), and every vertex rule reads
//! those in place of the copy's own semi-sharp edges. A copy of a crease vertex that holds
//! neither or only one of its two non-manifold edges (a closed fan touching it, or a fan that
//! leaves and returns through the same edge) lacks the crease neighbours OpenSubdiv's rule
//! reads: its points are the crease rule's over those edges in the copies that hold them, at
//! every level ([`Mesh::crease_ends`](crate::Mesh::crease_ends)). Nothing is refused.

use std::collections::HashMap;

use super::{CornerTag, CreaseTag, HoleTag, PolygonSoup};
use crate::UnionFind;
use crate::error::MeshError;
use crate::options::{BoundaryInterpolation, BoundaryNoneRule, SHARPNESS_INFINITE};

/// What [`PolygonSoup::split_nonmanifold`] found (vertex indices of the cage as read, 0-based).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct NonManifold {
    /// Non-manifold edges `(a, b, faces)`, `a < b`: more than two faces, or two faces using the
    /// edge the same way round.
    pub edges: Vec<(u32, u32, u32)>,
    /// Non-manifold vertices `(vertex, fans)`: several fans of faces, or on a non-manifold edge.
    pub vertices: Vec<(u32, u32)>,
    /// Vertices no face uses.
    pub bare: Vec<u32>,
    /// `(original, copy)` for every vertex copy made.
    pub copies: Vec<(u32, u32)>,
}

impl NonManifold {
    /// Whether the cage was manifold (bare vertices aside).
    pub fn is_empty(&self) -> bool {
        self.edges.is_empty() && self.vertices.is_empty()
    }
}

/// One use of an undirected edge: the face corner at its first vertex (in face order) and
/// whether the face runs it from the smaller index to the larger.
#[derive(Clone, Copy)]
struct EdgeUse {
    corner: usize,
    next: usize,
    up: bool,
}

impl PolygonSoup {
    /// What the readers do before building a mesh: with `split_vertices` the opt-in repair
    /// [`PolygonSoup::split_nonmanifold_vertices`] (non-manifold edges stay refused), otherwise
    /// [`PolygonSoup::split_nonmanifold`], OpenSubdiv's surface.
    pub fn prepare_nonmanifold(&mut self, split_vertices: bool) -> Result<NonManifold, MeshError> {
        if split_vertices {
            self.split_nonmanifold_vertices();
            return Ok(NonManifold::default());
        }
        self.split_nonmanifold()
    }

    /// Cuts a non-manifold cage into manifold pieces that refine to OpenSubdiv's surface (see
    /// the module notes): vertex copies are appended after the existing vertices, crease tags
    /// follow their edge, corner tags apply to every copy, and OpenSubdiv's sharpening of
    /// non-manifold edges and vertices is added as tags. Returns what was non-manifold (empty
    /// for a manifold cage, which is left unchanged). A soup with a malformed face (fewer than
    /// three corners, an index out of range, a repeated vertex) is left unchanged for
    /// validation to report.
    ///
    /// ```
    /// use subdiv_mesh::{Mesh, PolygonSoup};
    /// use glam::Vec3;
    /// // Three quads on the edge 0-1 (a fin).
    /// let p = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    /// let mut soup = PolygonSoup::from_faces(
    ///     vec![p(0., 0., 0.), p(1., 0., 0.), p(1., 1., 0.), p(0., 1., 0.), p(1., 0., 1.),
    ///          p(0., 0., 1.), p(1., -1., 0.), p(0., -1., 0.)],
    ///     &[vec![0, 1, 2, 3], vec![1, 0, 5, 4], vec![0, 1, 6, 7]],
    /// );
    /// let found = soup.split_nonmanifold().unwrap();
    /// assert_eq!(found.edges, vec![(0, 1, 3)]);
    /// let mesh = Mesh::from_soup(&soup).unwrap();
    /// assert_eq!(mesh.num_vertices(), 8 + 4);
    /// ```
    pub fn split_nonmanifold(&mut self) -> Result<NonManifold, MeshError> {
        let nv = self.positions.len();
        let mut found = NonManifold::default();
        let mut used = vec![false; nv];
        for &v in &self.face_indices {
            if (0..nv as i64).contains(&v) {
                used[v as usize] = true;
            }
        }
        found.bare = (0..nv as u32).filter(|&v| !used[v as usize]).collect();
        if self.face_offsets.len() < 2 || self.has_malformed_face() {
            // Left for validation to report.
            return Ok(found);
        }
        let uses = self.edge_uses();
        let nonmanifold_edge = |u: &[EdgeUse]| u.len() > 2 || (u.len() == 2 && u[0].up == u[1].up);
        let mut parent = UnionFind::new(self.face_indices.len());
        let mut nm_edges: HashMap<(i64, i64), u32> = HashMap::new();
        for (&(a, b), u) in &uses {
            if nonmanifold_edge(u) {
                nm_edges.insert((a, b), u.len() as u32);
            } else if u.len() == 2 {
                // A manifold edge joins the fans of its two faces at both ends.
                for (x, y) in [(u[0].corner, u[1].next), (u[0].next, u[1].corner)] {
                    parent.union(x, y);
                }
            }
        }
        let fans = self.fan_counts(&mut parent, nv);
        found.edges = nm_edges
            .iter()
            .map(|(&(a, b), &n)| (a as u32, b as u32, n))
            .collect();
        found.edges.sort_unstable();
        let mut nm_count = vec![0u32; nv];
        for &(a, b, _) in &found.edges {
            nm_count[a as usize] += 1;
            nm_count[b as usize] += 1;
        }
        found.vertices = (0..nv)
            .filter(|&v| fans[v] > 1 || nm_count[v] > 0)
            .map(|v| (v as u32, fans[v]))
            .collect();
        if found.is_empty() {
            return Ok(found);
        }
        match self.options.boundary {
            BoundaryInterpolation::None => self.hide_boundary_faces(&uses),
            BoundaryInterpolation::EdgeAndCorner => self.tag_one_face_corners(),
            BoundaryInterpolation::EdgeOnly => {}
        }
        let fvar_corners = self.fvar_mismatched(&uses, &found);
        let marks = self.nonmanifold_corners(&uses, &nm_edges, &found, &nm_count, &mut parent)?;
        let (remap, created) = self.copy_extra_fans(&mut parent);
        self.retag_copies(&remap, &created);
        if !marks.crease_copies.is_empty() {
            let mut copy_of: HashMap<(i64, usize), i64> = HashMap::new();
            for (c, &w) in remap.iter().enumerate() {
                copy_of.insert((self.face_indices[c], parent.find(c)), w);
            }
            for &(v, r, ends) in &marks.crease_copies {
                if let Some(&w) = copy_of.get(&(i64::from(v), r)) {
                    self.crease_copies
                        .push((w, ends.map(|(c, f)| (remap[c], remap[f]))));
                }
            }
        }
        for (v, values) in &marks.whole {
            let copies = created.iter().filter(|c| c.0 == *v).map(|c| c.1);
            for w in std::iter::once(*v).chain(copies) {
                self.whole_vertex_edges.push((i64::from(w), values.clone()));
            }
        }
        // Every use of a non-manifold edge: an infinitely sharp boundary edge of its piece.
        for &(a, b, _) in &found.edges {
            for u in &uses[&(i64::from(a), i64::from(b))] {
                self.creases.push(CreaseTag {
                    a: remap[u.corner],
                    b: remap[u.next],
                    sharpness: SHARPNESS_INFINITE,
                    line: None,
                });
            }
        }
        for &v in &marks.corners {
            for w in std::iter::once(v).chain(created.iter().filter(|c| c.0 == v).map(|c| c.1)) {
                self.corners.push(CornerTag {
                    v: w as i64,
                    sharpness: SHARPNESS_INFINITE,
                    line: None,
                });
            }
        }
        for &v in &fvar_corners {
            for w in std::iter::once(v).chain(created.iter().filter(|c| c.0 == v).map(|c| c.1)) {
                self.fvar_corners.push(i64::from(w));
            }
        }
        self.face_indices = remap;
        found.copies = created;
        Ok(found)
    }

    /// The non-manifold vertices whose face-varying values OpenSubdiv keeps in place at every
    /// level (`Vtr::FVarLevel::completeTopologyFromFaceValues` makes every value of a
    /// non-manifold vertex with mismatched values a corner): those whose faces name more than
    /// one value, or at an end of an edge whose faces disagree at either end.
    fn fvar_mismatched(
        &self,
        uses: &HashMap<(i64, i64), Vec<EdgeUse>>,
        found: &NonManifold,
    ) -> Vec<u32> {
        if self.uv_indices.len() != self.face_indices.len() {
            return Vec::new();
        }
        let nonmanifold: HashMap<i64, ()> = found
            .vertices
            .iter()
            .map(|&(v, _)| (i64::from(v), ()))
            .collect();
        let mut out: HashMap<i64, ()> = HashMap::new();
        let mut first: HashMap<i64, i64> = HashMap::new();
        for (c, v) in self.face_indices.iter().enumerate() {
            if nonmanifold.contains_key(v) {
                let value = *first.entry(*v).or_insert(self.uv_indices[c]);
                if value != self.uv_indices[c] {
                    out.insert(*v, ());
                }
            }
        }
        for (&(a, b), u) in uses {
            let ends = [a, b].map(|x| nonmanifold.contains_key(&x));
            if u.len() < 2 || ends == [false, false] {
                continue;
            }
            let at = |e: &EdgeUse, x: i64| {
                let c = if self.face_indices[e.corner] == x {
                    e.corner
                } else {
                    e.next
                };
                self.uv_indices[c]
            };
            let differs = [a, b]
                .iter()
                .any(|&x| u.iter().any(|e| at(e, x) != at(&u[0], x)));
            if differs {
                for (x, nm) in [a, b].into_iter().zip(ends) {
                    if nm {
                        out.insert(x, ());
                    }
                }
            }
        }
        let mut out: Vec<u32> = out.into_keys().map(|v| v as u32).collect();
        out.sort_unstable();
        out
    }

    /// `interpolateboundary none` as OpenSubdiv 3.5 applies it to the whole cage
    /// ([`BoundaryNoneRule`], before the cut: a non-manifold vertex hides the faces of all its
    /// fans, and an edge with two faces the same way round is no boundary edge); the others
    /// are refined as with `EdgeOnly` (boundary edges are sharpened in every mode, and only
    /// `EdgeAndCorner` sharpens corners). Every copy of a non-manifold vertex is a boundary
    /// vertex of its piece, and the rule on the pieces could hide fewer faces than on the whole
    /// cage; so the hidden faces become holes here and the pieces take `EdgeOnly`.
    fn hide_boundary_faces(&mut self, uses: &HashMap<(i64, i64), Vec<EdgeUse>>) {
        let tagged: HashMap<(i64, i64), f32> = self
            .creases
            .iter()
            .map(|t| ((t.a.min(t.b), t.a.max(t.b)), t.sharpness))
            .collect();
        let mut rule = BoundaryNoneRule::new(self.positions.len());
        for (&(a, b), u) in uses {
            let s = tagged.get(&(a, b)).copied().unwrap_or(0.0);
            rule.edge(a as usize, b as usize, u.len(), s);
        }
        let mut hole = vec![false; self.num_faces()];
        for h in &self.holes {
            if let Some(x) = usize::try_from(h.f).ok().and_then(|f| hole.get_mut(f)) {
                *x = true;
            }
        }
        for (f, &already) in hole.iter().enumerate() {
            if !already && rule.hides(self.face(f).iter().map(|&v| v as usize)) {
                self.holes.push(HoleTag {
                    f: f as i64,
                    line: None,
                });
            }
        }
        self.options.boundary = BoundaryInterpolation::EdgeOnly;
    }

    /// `interpolateboundary edge-and-corner` as OpenSubdiv 3.5 applies it to the whole cage
    /// (before the cut): a vertex with a single face is an infinitely sharp corner. A copy of a
    /// non-manifold crease vertex may have a single face in its piece, where the piece's own
    /// rule would make it a corner; so those corners become tags here and the pieces take
    /// `EdgeOnly` (which otherwise refines the same).
    fn tag_one_face_corners(&mut self) {
        let mut faces_at = vec![0u32; self.positions.len()];
        for &v in &self.face_indices {
            faces_at[v as usize] += 1;
        }
        for (v, _) in faces_at.iter().enumerate().filter(|(_, n)| **n == 1) {
            self.corners.push(CornerTag {
                v: v as i64,
                sharpness: SHARPNESS_INFINITE,
                line: None,
            });
        }
        self.options.boundary = BoundaryInterpolation::EdgeOnly;
    }

    /// A face with fewer than three corners, an index out of range or a vertex used twice.
    fn has_malformed_face(&self) -> bool {
        let nv = self.positions.len() as i64;
        (0..self.num_faces()).any(|f| {
            let face = self.face(f);
            face.len() < 3
                || face.iter().any(|v| !(0..nv).contains(v))
                || (1..face.len()).any(|i| face[..i].contains(&face[i]))
        })
    }

    /// Every undirected in-range edge `(min, max)` and its uses, in face order.
    fn edge_uses(&self) -> HashMap<(i64, i64), Vec<EdgeUse>> {
        let nv = self.positions.len() as i64;
        let mut uses: HashMap<(i64, i64), Vec<EdgeUse>> = HashMap::new();
        for f in 0..self.num_faces() {
            let s = self.face_offsets[f] as usize;
            let n = self.face_offsets[f + 1] as usize - s;
            for k in 0..n {
                let (c, d) = (s + k, s + (k + 1) % n);
                let (a, b) = (self.face_indices[c], self.face_indices[d]);
                if a == b || !(0..nv).contains(&a) || !(0..nv).contains(&b) {
                    continue;
                }
                uses.entry((a.min(b), a.max(b))).or_default().push(EdgeUse {
                    corner: c,
                    next: d,
                    up: a < b,
                });
            }
        }
        uses
    }

    /// Number of fans (corner classes of `parent`) at every vertex.
    fn fan_counts(&self, parent: &mut UnionFind, nv: usize) -> Vec<u32> {
        let mut roots: HashMap<(i64, usize), ()> = HashMap::new();
        let mut fans = vec![0u32; nv];
        for c in 0..self.face_indices.len() {
            let v = self.face_indices[c];
            if (0..nv as i64).contains(&v) && roots.insert((v, parent.find(c)), ()).is_none() {
                fans[v as usize] += 1;
            }
        }
        fans
    }

    /// The non-manifold vertices OpenSubdiv makes corners and the vertex sharpness of crease
    /// copies, after checking that every copy can be given the whole vertex's rule (`Err` names
    /// the first that cannot).
    fn nonmanifold_corners(
        &self,
        uses: &HashMap<(i64, i64), Vec<EdgeUse>>,
        nm_edges: &HashMap<(i64, i64), u32>,
        found: &NonManifold,
        nm_count: &[u32],
        parent: &mut UnionFind,
    ) -> Result<NonManifoldMarks, MeshError> {
        let mut tagged: HashMap<(i64, i64), f32> = HashMap::new();
        for t in &self.creases {
            tagged.insert((t.a.min(t.b), t.a.max(t.b)), t.sharpness);
        }
        let mut vertex_sharp: HashMap<i64, f32> = HashMap::new();
        for t in &self.corners {
            vertex_sharp.insert(t.v, t.sharpness);
        }
        // Per non-manifold vertex: its edges' sharpness and, per edge, the fans that use it.
        // Per use, the face corners at the vertex and at the far end too.
        let mut at: HashMap<i64, Vec<AtEdge>> = found
            .vertices
            .iter()
            .map(|&(v, _)| (v as i64, Vec::new()))
            .collect();
        for (&(a, b), u) in uses {
            let nm = nm_edges.contains_key(&(a, b));
            let s = if nm || u.len() == 1 {
                SHARPNESS_INFINITE
            } else {
                tagged.get(&(a, b)).copied().unwrap_or(0.0)
            };
            for v in [a, b] {
                if let Some(list) = at.get_mut(&v) {
                    let corners: Vec<(usize, usize)> = u
                        .iter()
                        .map(|e| {
                            if self.face_indices[e.corner] == v {
                                (e.corner, e.next)
                            } else {
                                (e.next, e.corner)
                            }
                        })
                        .collect();
                    let fans = corners.iter().map(|c| parent.find(c.0)).collect();
                    list.push((s, nm, fans, corners));
                }
            }
        }
        let mut faces_at = vec![0usize; self.positions.len()];
        for &v in &self.face_indices {
            faces_at[v as usize] += 1;
        }
        let mut marks = NonManifoldMarks::default();
        for &(v, _) in &found.vertices {
            let edges = &at[&(v as i64)];
            let vs = vertex_sharp.get(&(v as i64)).copied().unwrap_or(0.0);
            // OpenSubdiv decides the rule, the fractional weight and the Chaikin decay over all
            // the vertex's semi-sharp edges, every copy's together: every copy carries them
            // (`Mesh::whole_vertex_edges`), and its vertex rules read them in place of its own.
            let semi: Vec<f32> = edges
                .iter()
                .map(|e| e.0)
                .filter(|&s| s > 0.0 && s < SHARPNESS_INFINITE)
                .collect();
            if !semi.is_empty() {
                marks.whole.push((v, semi));
            }
            // OpenSubdiv keeps a non-manifold vertex unsharpened only on an interior
            // non-manifold crease: exactly two non-manifold edges, no boundary edge (one face)
            // and more faces than edges (one more per extra fin). Three or more infinitely
            // sharp edges make a corner at every level, whatever else is sharp there.
            let boundary_edges = edges.iter().filter(|e| e.2.len() == 1).count();
            let interior_crease = nm_count[v as usize] == 2
                && boundary_edges == 0
                && faces_at[v as usize] > edges.len();
            let infinite = edges.iter().filter(|e| e.0 >= SHARPNESS_INFINITE).count();
            if !interior_crease || vs >= SHARPNESS_INFINITE || infinite > 2 {
                marks.corners.push(v);
                continue;
            }
            // The crease rule along its two non-manifold edges reads their far ends: a copy
            // whose ring lacks one takes the crease rule over the edges of copies that hold
            // them, one copy holding both where there is one.
            let mut nm: Vec<&AtEdge> = edges.iter().filter(|e| e.1).collect();
            // In the order of their far ends (the uses come in hash order).
            nm.sort_unstable_by_key(|e| self.face_indices[e.3[0].1]);
            let mut all: Vec<usize> = edges.iter().flat_map(|e| e.2.iter().copied()).collect();
            all.sort_unstable();
            all.dedup();
            let holds_both = |r: &usize| nm.iter().all(|e| e.2.contains(r));
            let master = all.iter().copied().find(holds_both);
            // The use of edge `e` in fan `master`, else in its first fan.
            let end = |e: &AtEdge| {
                let k = master.and_then(|m| e.2.iter().position(|&r| r == m));
                e.3[k.unwrap_or(0)]
            };
            if nm.len() == 2 {
                let ends = [end(nm[0]), end(nm[1])];
                for &r in all.iter().filter(|r| !holds_both(r)) {
                    marks.crease_copies.push((v, r, ends));
                }
            }
        }
        Ok(marks)
    }
}

/// What [`PolygonSoup::split_nonmanifold`] tags on the copies besides the sharp edges: the
/// vertices OpenSubdiv makes corners, and the semi-sharp edge values of the vertices holding
/// some (every copy of each).
#[derive(Default)]
struct NonManifoldMarks {
    corners: Vec<u32>,
    whole: Vec<(u32, Vec<f32>)>,
    /// `(vertex, fan root, the face corners (at the vertex, at the far end) of a use of each
    /// non-manifold edge)`: the copies lacking them.
    crease_copies: Vec<(u32, usize, [CornerPair; 2])>,
}

/// The face corners of a use of an edge: at the vertex, at the far end.
type CornerPair = (usize, usize);

/// An edge at a non-manifold vertex: its sharpness as OpenSubdiv takes it, whether it is
/// non-manifold, and per use the fan (corner class root) at the vertex and the face corners
/// at the vertex and at the far end.
type AtEdge = (f32, bool, Vec<usize>, Vec<CornerPair>);

#[cfg(test)]
mod tests;
