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
//! the same weight, as the whole vertex does. Semi-sharp edges at a crease vertex make the
//! whole vertex a corner while they last (three sharp edges), then blend it into the crease by
//! the average of what runs out last (OpenSubdiv's fractional weight over all the vertex's
//! edges): that schedule is one vertex sharpness (`sharpness::crease_vertex_schedule`), given to
//! every copy whose own edges and tag do not already give it. Where a copy cannot be given the
//! whole vertex's rule at every level (Chaikin creases spread over several copies whose own
//! decay differs from the whole vertex's, which averages over all of them; semi-sharp edges in several copies whose own transition weights
//! differ from the whole vertex's; a crease vertex whose copy misses one of its two
//! non-manifold edges), the cage is refused with
//! [`MeshError::UnsupportedNonManifold`] naming the vertex, rather than refined differently.

use std::collections::HashMap;

use super::{CornerTag, CreaseTag, HoleTag, PolygonSoup, find_root};
use crate::error::MeshError;
use crate::options::{BoundaryInterpolation, BoundaryNoneRule, CreaseMethod, SHARPNESS_INFINITE};
use crate::sharpness::{child_edge_sharpness_around, crease_vertex_schedule};

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
        let mut parent: Vec<usize> = (0..self.face_indices.len()).collect();
        let mut nm_edges: HashMap<(i64, i64), u32> = HashMap::new();
        for (&(a, b), u) in &uses {
            if nonmanifold_edge(u) {
                nm_edges.insert((a, b), u.len() as u32);
            } else if u.len() == 2 {
                // A manifold edge joins the fans of its two faces at both ends.
                for (x, y) in [(u[0].corner, u[1].next), (u[0].next, u[1].corner)] {
                    let (rx, ry) = (find_root(&mut parent, x), find_root(&mut parent, y));
                    parent[rx.max(ry)] = rx.min(ry);
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
        let marks = self.nonmanifold_corners(&uses, &nm_edges, &found, &nm_count, &mut parent)?;
        let (remap, created) = self.copy_extra_fans(&mut parent);
        self.retag_copies(&remap, &created);
        // After the copied tags, which they replace (the last corner tag of a vertex holds).
        if !marks.vertex_sharpness.is_empty() {
            let mut copy_of: HashMap<(i64, usize), i64> = HashMap::new();
            for (c, &w) in remap.iter().enumerate() {
                copy_of.insert((self.face_indices[c], find_root(&mut parent, c)), w);
            }
            for &(v, root, sharpness) in &marks.vertex_sharpness {
                if let Some(&w) = copy_of.get(&(i64::from(v), root)) {
                    self.corners.push(CornerTag {
                        v: w,
                        sharpness,
                        line: None,
                    });
                }
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
        self.face_indices = remap;
        found.copies = created;
        Ok(found)
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
    fn fan_counts(&self, parent: &mut [usize], nv: usize) -> Vec<u32> {
        let mut roots: HashMap<(i64, usize), ()> = HashMap::new();
        let mut fans = vec![0u32; nv];
        for c in 0..self.face_indices.len() {
            let v = self.face_indices[c];
            if (0..nv as i64).contains(&v) && roots.insert((v, find_root(parent, c)), ()).is_none()
            {
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
        parent: &mut [usize],
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
        let mut at: HashMap<i64, Vec<(f32, bool, Vec<usize>)>> = found
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
                    let fans = u
                        .iter()
                        .map(|e| {
                            let c = if self.face_indices[e.corner] == v {
                                e.corner
                            } else {
                                e.next
                            };
                            find_root(parent, c)
                        })
                        .collect();
                    list.push((s, nm, fans));
                }
            }
        }
        let chaikin = self.options.crease == crate::options::CreaseMethod::Chaikin;
        let mut faces_at = vec![0usize; self.positions.len()];
        for &v in &self.face_indices {
            faces_at[v as usize] += 1;
        }
        let mut marks = NonManifoldMarks::default();
        for &(v, _) in &found.vertices {
            let edges = &at[&(v as i64)];
            let vs = vertex_sharp.get(&(v as i64)).copied().unwrap_or(0.0);
            let semi = |s: f32| s > 0.0 && s < SHARPNESS_INFINITE;
            let semi_edges: Vec<&(f32, bool, Vec<usize>)> =
                edges.iter().filter(|e| semi(e.0)).collect();
            // Chaikin's decay at the vertex averages its semi-sharp edges, all copies'
            // together, while each copy averages its own (a semi-sharp edge has one fan): they
            // must decay alike, as where all are in one copy.
            let mut semi_fans: Vec<usize> = semi_edges.iter().flat_map(|e| e.2.clone()).collect();
            semi_fans.sort_unstable();
            semi_fans.dedup();
            let by_copy: Vec<Vec<f32>> = semi_fans
                .iter()
                .map(|r| {
                    let of_r = semi_edges.iter().filter(|e| e.2.contains(r));
                    of_r.map(|e| e.0).collect()
                })
                .collect();
            if chaikin && by_copy.len() > 1 && !copies_decay_alike(&by_copy) {
                return Err(unsupported(
                    self,
                    v,
                    "Chaikin creases at a non-manifold vertex",
                ));
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
            // The crease rule along its two non-manifold edges, which every copy must hold.
            let nm: Vec<&Vec<usize>> = edges.iter().filter(|e| e.1).map(|e| &e.2).collect();
            let mut all: Vec<usize> = edges.iter().flat_map(|e| e.2.iter().copied()).collect();
            all.sort_unstable();
            all.dedup();
            if all.iter().any(|r| !nm.iter().all(|fans| fans.contains(r))) {
                return Err(unsupported(
                    self,
                    v,
                    "a copy without both non-manifold edges",
                ));
            }
            if semi_edges.is_empty() {
                // A semi-sharp vertex sharpness goes to every copy with its tag.
                continue;
            }
            // Semi-sharp edges make the whole vertex a corner while they last, then blend it
            // into the crease by the average of what runs out last: each copy gets the vertex
            // sharpness with that schedule (`crease_vertex_schedule`) unless its own edges
            // and tag already give it.
            let method = self.options.crease;
            let values: Vec<f32> = semi_edges.iter().map(|e| e.0).collect();
            let whole = crease_vertex_schedule(method, vs, &values);
            for &r in &all {
                let own: Vec<f32> = semi_edges
                    .iter()
                    .filter(|e| e.2.contains(&r))
                    .map(|e| e.0)
                    .collect();
                let gives =
                    |s: f32| crease_vertex_schedule(method, s, &own).to_bits() == whole.to_bits();
                if !own.is_empty() && gives(vs) {
                    continue;
                }
                let Some(s) = copy_vertex_sharpness(method, &own, whole, gives) else {
                    return Err(unsupported(
                        self,
                        v,
                        "semi-sharp creases at a non-manifold crease vertex that its copies cannot share",
                    ));
                };
                marks.vertex_sharpness.push((v, r, s));
            }
        }
        Ok(marks)
    }
}

/// What [`PolygonSoup::split_nonmanifold`] tags on the copies besides the sharp edges: the
/// vertices OpenSubdiv makes corners (every copy), and `(vertex, fan root, sharpness)` for the
/// copies of a crease vertex that carry its semi-sharp schedule as a vertex sharpness.
#[derive(Default)]
struct NonManifoldMarks {
    corners: Vec<u32>,
    vertex_sharpness: Vec<(u32, usize, f32)>,
}

/// The vertex sharpness that gives a copy of a crease vertex, holding the semi-sharp creases
/// `own`, the whole vertex's schedule `whole` (`gives` checks one, bit for bit): `whole` itself
/// where none of `own` runs out with the last (or their average is the whole vertex's);
/// otherwise `k + x` with `x` chosen so that the average of `x` and the copy's own creases
/// running out at level `k` is the whole vertex's weight `w`
/// (`x = w (1 + n) - sum`, which must lie in `(0, 1]`; the nearest values in `f32` are tried
/// until one gives the same bits). `None` where no vertex sharpness gives it.
fn copy_vertex_sharpness(
    method: CreaseMethod,
    own: &[f32],
    whole: f32,
    gives: impl Fn(f32) -> bool,
) -> Option<f32> {
    if gives(whole) {
        return Some(whole);
    }
    // whole = k + w with 0 < w <= 1; the copy's own creases at level k (their decay there is
    // the whole vertex's: `copies_decay_alike`), those still sharp running out with the last.
    let k = f64::from(whole).ceil() - 1.0;
    let w = f64::from(whole) - k;
    let mut at_k: Vec<f32> = own.to_vec();
    let mut next = vec![0.0f32; own.len()];
    for _ in 0..k as usize {
        child_edge_sharpness_around(method, &at_k, &mut next);
        std::mem::swap(&mut at_k, &mut next);
    }
    let last: Vec<f64> = at_k
        .iter()
        .filter(|&&s| s > 0.0)
        .map(|&s| f64::from(s))
        .collect();
    let x = w * (1.0 + last.len() as f64) - last.iter().sum::<f64>();
    if !(x > 0.0 && x <= 1.0) {
        return None;
    }
    let base = (k + x) as f32;
    (0..64i32)
        .map(|i| {
            f32::from_bits(
                (base.to_bits() as i32 + if i % 2 == 0 { i / 2 } else { -(i + 1) / 2 }) as u32,
            )
        })
        .find(|&c| c > k as f32 && gives(c))
}

/// Whether every copy's own Chaikin decay of its semi-sharp edges at a vertex (`by_copy`, one
/// list per copy) gives the whole vertex's at every level, within rounding: Chaikin averages
/// the other semi-sharp edges at the vertex, and a copy sees only its own (they agree where
/// the averages agree, or where the decay runs out either way).
fn copies_decay_alike(by_copy: &[Vec<f32>]) -> bool {
    let mut by_copy = by_copy.to_vec();
    for _ in 0..=SHARPNESS_INFINITE as u32 {
        let all = by_copy.concat();
        if all.iter().all(|&s| s <= 0.0) {
            return true;
        }
        let mut whole = vec![0.0f32; all.len()];
        child_edge_sharpness_around(CreaseMethod::Chaikin, &all, &mut whole);
        let mut k = 0;
        for own in &mut by_copy {
            let mut child = vec![0.0f32; own.len()];
            child_edge_sharpness_around(CreaseMethod::Chaikin, own, &mut child);
            let alike = |(a, b): (&f32, &f32)| (a - b).abs() <= 1e-6 * b.abs().max(1.0);
            if !child.iter().zip(&whole[k..k + own.len()]).all(alike) {
                return false;
            }
            k += own.len();
            *own = child;
        }
    }
    true
}

fn unsupported(soup: &PolygonSoup, vertex: u32, why: &'static str) -> MeshError {
    MeshError::UnsupportedNonManifold {
        vertex,
        why,
        line: soup.vertex_line(vertex as usize),
    }
}

#[cfg(test)]
mod tests;
