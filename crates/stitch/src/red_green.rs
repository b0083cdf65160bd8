//! Red-green closure of adaptive Loop subdivision.
//!
//! Adaptive Loop subdivision (Isenberg, Hartmann & König, "Interest Value Driven Adaptive
//! Subdivision", SimVis 2003, §3 and Fig. 1, after Amresh & Farin 2002) splits the selected
//! triangles 1-to-4 ("red"). A triangle that is not selected but has refined neighbours gets new
//! vertices on 1, 2 or 3 of its edges and is split into 2, 3 or 4 triangles so that the mesh
//! stays conforming ("green"). Green triangles are remembered as a [`GreenFamily`] (the parent
//! triangle and the midpoints on its split edges); when a green triangle must be refined in a
//! later step, or gets a new vertex on one of its edges, its family is first merged back into the
//! parent, which is then refined regularly (red). Green triangles are therefore never split
//! again, and triangle quality does not decay over the steps.
//!
//! This module is topology only; where the new vertices go is the caller's business (the
//! adaptive Loop step of `subdiv-doi`). One step is:
//!
//! 1. [`close`]: from the selected faces, find every face refined in this step (selected faces,
//!    families merged back, triangles whose three edges are split) and every edge that gets a
//!    new midpoint;
//! 2. the caller computes the new vertex positions and numbers the midpoints;
//! 3. [`assemble`]: the triangles of the refined, conforming mesh and the new [`GreenState`].
//!
//! A face whose three edges are split is refined (red), not green. A triangle with two split
//! edges is cut into the corner triangle and a quadrilateral, which is split along its shorter
//! diagonal.

use glam::Vec3;
use subdiv_mesh::{EdgeId, FaceId, HalfedgeId, Mesh, VertexId};
use thiserror::Error;

/// `family_of_face` value of a face that is not green.
pub const NO_FAMILY: u32 = u32::MAX;

/// The triangles of one green closure: the parent triangle they replace and the midpoints of its
/// split edges.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GreenFamily {
    /// The parent triangle's corners, counter-clockwise.
    pub parent: [VertexId; 3],
    /// `mids[k]` is the vertex on edge `parent[k]`-`parent[k+1]`, or [`VertexId::NONE`] when
    /// that edge is not split.
    pub mids: [VertexId; 3],
}

impl GreenFamily {
    /// Number of split parent edges (1 or 2 for a green family).
    #[inline]
    pub fn num_splits(&self) -> usize {
        self.mids.iter().filter(|m| m.is_some()).count()
    }
}

/// Which faces of a mesh are green, and their families.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GreenState {
    /// Per face: index into [`GreenState::families`], or [`NO_FAMILY`].
    pub family_of_face: Vec<u32>,
    /// The green families.
    pub families: Vec<GreenFamily>,
}

impl GreenState {
    /// No green faces in a mesh of `num_faces` faces (a cage, or a uniformly refined mesh).
    pub fn new(num_faces: usize) -> GreenState {
        GreenState {
            family_of_face: vec![NO_FAMILY; num_faces],
            families: Vec::new(),
        }
    }

    /// The family of face `f`, if it is green.
    #[inline]
    pub fn family(&self, f: FaceId) -> Option<&GreenFamily> {
        self.families
            .get(*self.family_of_face.get(f.idx())? as usize)
    }

    /// Number of green faces.
    pub fn num_green_faces(&self) -> usize {
        self.family_of_face
            .iter()
            .filter(|&&x| x != NO_FAMILY)
            .count()
    }
}

/// Inconsistent input to the closure.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum StitchError {
    /// Red-green closure works on triangles.
    #[error("face {face} has {size} vertices; red-green closure needs a triangle mesh")]
    NotTriangle {
        /// The face.
        face: u32,
        /// Its vertex count.
        size: u32,
    },
    /// A per-element array does not match the mesh.
    #[error("{what} has {got} entries but the mesh has {want}")]
    LengthMismatch {
        /// Which array.
        what: &'static str,
        /// Its length.
        got: usize,
        /// The expected length.
        want: usize,
    },
    /// A face names a family that does not exist.
    #[error("face {face} belongs to green family {family}, but there are only {count} families")]
    FamilyOutOfRange {
        /// The face.
        face: u32,
        /// The family index.
        family: u32,
        /// Number of families.
        count: u32,
    },
    /// A family's unsplit parent edge is not an edge of the mesh.
    #[error("green family {family}: parent edge {a}-{b} is not an edge of the mesh")]
    BrokenFamily {
        /// The family.
        family: u32,
        /// Endpoint.
        a: u32,
        /// Endpoint.
        b: u32,
    },
    /// A split edge has no midpoint, or a midpoint is not a vertex.
    #[error("edge {edge}: midpoint {mid} is missing or not among the {count} vertices")]
    BadMidpoint {
        /// The edge.
        edge: u32,
        /// The midpoint given (u32::MAX when missing).
        mid: u32,
        /// Number of vertex positions.
        count: u32,
    },
    /// A face that is kept unchanged has a split edge (the closure was not computed by [`close`]).
    #[error("face {face} is kept but its edge {edge} is split; the closure is inconsistent")]
    Inconsistent {
        /// The face.
        face: u32,
        /// The split edge.
        edge: u32,
    },
}

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
    fam_start: Vec<u32>,
    fam_faces: Vec<u32>,
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

    fn mark_family(&mut self, fam: u32) -> Result<(), StitchError> {
        let k = fam as usize;
        if self.c.merged[k] {
            return Ok(());
        }
        self.c.merged[k] = true;
        for i in self.fam_start[k]..self.fam_start[k + 1] {
            self.c.red_face[self.fam_faces[i as usize] as usize] = true;
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
                    .ok_or(StitchError::BrokenFamily {
                        family: fam,
                        a: a.0,
                        b: b.0,
                    })?;
                self.split(h.edge());
            }
        }
        Ok(())
    }

    fn mark_unit(&mut self, f: FaceId) -> Result<(), StitchError> {
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
/// closed green by [`assemble`].
///
/// ```
/// use subdiv_mesh::{Mesh, PolygonSoup, glam::Vec3};
/// use subdiv_stitch::red_green::{close, GreenState};
/// // A fan of three triangles around vertex 0; refining the middle one splits the edges it
/// // shares with the other two.
/// let p = vec![Vec3::ZERO, Vec3::X, Vec3::new(0.0, 1.0, 0.0), Vec3::new(-1.0, 0.0, 0.0), Vec3::new(0.0, -1.0, 0.0)];
/// let mesh = Mesh::from_soup(&PolygonSoup::from_faces(p, &[[0u32, 1, 2], [0, 2, 3], [0, 3, 4]]))?;
/// let c = close(&mesh, &GreenState::new(3), &[false, true, false])?;
/// assert_eq!(c.red_face, vec![false, true, false]);
/// assert!(c.moves[0] && c.moves[2] && c.moves[3] && !c.moves[1]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn close(mesh: &Mesh, state: &GreenState, selected: &[bool]) -> Result<Closure, StitchError> {
    let nf = mesh.num_faces();
    check_len("selection", selected.len(), nf)?;
    check_len("green family_of_face", state.family_of_face.len(), nf)?;
    check_triangles(mesh)?;
    let nfam = state.families.len();
    // Faces of each family, by counting sort.
    let mut fam_start = vec![0u32; nfam + 1];
    for (f, &fam) in state.family_of_face.iter().enumerate() {
        if fam != NO_FAMILY {
            if fam as usize >= nfam {
                return Err(StitchError::FamilyOutOfRange {
                    face: f as u32,
                    family: fam,
                    count: nfam as u32,
                });
            }
            fam_start[fam as usize + 1] += 1;
        }
    }
    for k in 0..nfam {
        fam_start[k + 1] += fam_start[k];
    }
    let mut fill = fam_start.clone();
    let mut fam_faces = vec![0u32; fam_start[nfam] as usize];
    for (f, &fam) in state.family_of_face.iter().enumerate() {
        if fam != NO_FAMILY {
            fam_faces[fill[fam as usize] as usize] = f as u32;
            fill[fam as usize] += 1;
        }
    }
    let mut m = Marker {
        mesh,
        state,
        fam_start,
        fam_faces,
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

/// The refined mesh's triangles, as produced by [`assemble`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Assembly {
    /// Triangles (vertex indices into the caller's new positions), counter-clockwise.
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle: the face of the input mesh it comes from (for groups and hole flags).
    pub source_face: Vec<u32>,
    /// Green families of the new mesh.
    pub state: GreenState,
}

/// Splits triangle `tri` with midpoints `mids` (`mids[k]` on edge `tri[k]`-`tri[k+1]`, or
/// [`VertexId::NONE`]) into 1, 2, 3 or 4 triangles appended to `out`, counter-clockwise.
///
/// Returns the green family for one or two split edges, `None` otherwise. With two split
/// edges the quadrilateral left beside the corner triangle is cut along its shorter diagonal
/// (positions from `positions`).
///
/// ```
/// use subdiv_mesh::{VertexId, glam::Vec3};
/// use subdiv_stitch::red_green::split_triangle;
/// let p = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(0.5, 0.0, 0.0)];
/// let mut out = Vec::new();
/// let fam = split_triangle([VertexId(0), VertexId(1), VertexId(2)], [VertexId(3), VertexId::NONE, VertexId::NONE], &p, &mut out);
/// assert_eq!(out, vec![[0, 3, 2], [3, 1, 2]]);
/// assert_eq!(fam.unwrap().num_splits(), 1);
/// ```
#[inline]
pub fn split_triangle(
    tri: [VertexId; 3],
    mids: [VertexId; 3],
    positions: &[Vec3],
    out: &mut Vec<[u32; 3]>,
) -> Option<GreenFamily> {
    let n = mids.iter().filter(|m| m.is_some()).count();
    let [a, b, c] = tri.map(|v| v.0);
    match n {
        0 => {
            out.push([a, b, c]);
            None
        }
        1 => {
            // Rotate so that the split edge is tri[r]-tri[r+1].
            let r = mids.iter().position(|m| m.is_some()).unwrap_or(0);
            let (x, y, z) = (tri[r].0, tri[(r + 1) % 3].0, tri[(r + 2) % 3].0);
            let m = mids[r].0;
            out.push([x, m, z]);
            out.push([m, y, z]);
            Some(GreenFamily { parent: tri, mids })
        }
        2 => {
            // Rotate so that the unsplit edge is tri[r+2]-tri[r].
            let r = (mids.iter().position(|m| *m == VertexId::NONE).unwrap_or(2) + 1) % 3;
            let (x, y, z) = (tri[r].0, tri[(r + 1) % 3].0, tri[(r + 2) % 3].0);
            let (m0, m1) = (mids[r].0, mids[(r + 1) % 3].0);
            out.push([m0, y, m1]);
            let d_xm1 = pos(positions, x).distance_squared(pos(positions, m1));
            let d_m0z = pos(positions, m0).distance_squared(pos(positions, z));
            if d_xm1 <= d_m0z {
                out.push([x, m0, m1]);
                out.push([x, m1, z]);
            } else {
                out.push([x, m0, z]);
                out.push([m0, m1, z]);
            }
            Some(GreenFamily { parent: tri, mids })
        }
        _ => {
            let [m0, m1, m2] = mids.map(|v| v.0);
            out.extend([[a, m0, m2], [b, m1, m0], [c, m2, m1], [m0, m1, m2]]);
            None
        }
    }
}

#[inline]
fn pos(positions: &[Vec3], v: u32) -> Vec3 {
    positions.get(v as usize).copied().unwrap_or(Vec3::ZERO)
}

/// Builds the triangles of the refined mesh from the closure of [`close`] and the midpoint of
/// every split edge (`edge_mid[e]`, [`VertexId::NONE`] for unsplit edges).
///
/// Faces are emitted in the order of the input faces: a red triangle becomes its four Loop
/// children in the order of `subdiv_rules::refine_uniform` (corner children of the first,
/// second and third vertex, then the middle triangle), so refining every face gives exactly the
/// uniform mesh. A merged family emits its parent's four children at the position of its first
/// face; corner children of a merged parent whose outer half-edges were split again are closed
/// green. Green faces of unmerged families are kept with their family.
pub fn assemble(
    mesh: &Mesh,
    state: &GreenState,
    closure: &Closure,
    edge_mid: &[VertexId],
    positions: &[Vec3],
) -> Result<Assembly, StitchError> {
    let nf = mesh.num_faces();
    check_len("green family_of_face", state.family_of_face.len(), nf)?;
    check_len("closure red_face", closure.red_face.len(), nf)?;
    check_len(
        "closure split_edge",
        closure.split_edge.len(),
        mesh.num_edges(),
    )?;
    check_len("edge midpoints", edge_mid.len(), mesh.num_edges())?;
    check_len("closure merged", closure.merged.len(), state.families.len())?;
    for (e, (&s, &m)) in closure.split_edge.iter().zip(edge_mid).enumerate() {
        if s && (m == VertexId::NONE || m.idx() >= positions.len()) {
            return Err(StitchError::BadMidpoint {
                edge: e as u32,
                mid: m.0,
                count: positions.len() as u32,
            });
        }
    }
    let mid_of = |h: HalfedgeId| edge_mid[h.edge().idx()];
    let nfam = state.families.len();
    let mut out = Assembly {
        triangles: Vec::with_capacity(nf * 2),
        source_face: Vec::with_capacity(nf * 2),
        state: GreenState::default(),
    };
    let mut fam_map = vec![NO_FAMILY; nfam];
    let mut emitted = vec![false; nfam];
    for f in mesh.faces() {
        let h0 = mesh.face_halfedge(f);
        let hs = [h0, mesh.next(h0), mesh.prev(h0)];
        let corners = hs.map(|h| mesh.from(h));
        let fam = state.family_of_face[f.idx()];
        if fam != NO_FAMILY {
            let k = fam as usize;
            if closure.merged[k] {
                if emitted[k] {
                    continue;
                }
                emitted[k] = true;
                let g = state.families[k];
                let p = g.parent;
                let mut m = [VertexId::NONE; 3];
                for j in 0..3 {
                    m[j] = if g.mids[j].is_some() {
                        g.mids[j]
                    } else {
                        let h = mesh.find_halfedge(p[j], p[(j + 1) % 3]).ok_or(
                            StitchError::BrokenFamily {
                                family: fam,
                                a: p[j].0,
                                b: p[(j + 1) % 3].0,
                            },
                        )?;
                        mid_of(h)
                    };
                }
                // Outer halves of pre-split parent edges may have been split again.
                let half_mid = |a: VertexId, b: VertexId, pre: bool| -> VertexId {
                    if !pre {
                        return VertexId::NONE;
                    }
                    match mesh.find_halfedge(a, b) {
                        Some(h) => mid_of(h),
                        None => VertexId::NONE,
                    }
                };
                for j in 0..3 {
                    let jp = (j + 2) % 3;
                    let tri = [p[j], m[j], m[jp]];
                    let mids = [
                        half_mid(p[j], m[j], g.mids[j].is_some()),
                        VertexId::NONE,
                        half_mid(m[jp], p[j], g.mids[jp].is_some()),
                    ];
                    emit_closed(&mut out, tri, mids, f.0, positions);
                }
                out.triangles.push([m[0].0, m[1].0, m[2].0]);
                out.state.family_of_face.push(NO_FAMILY);
                out.source_face.push(f.0);
            } else {
                for h in hs {
                    if closure.split_edge[h.edge().idx()] {
                        return Err(StitchError::Inconsistent {
                            face: f.0,
                            edge: h.edge().0,
                        });
                    }
                }
                if fam_map[k] == NO_FAMILY {
                    out.state.families.push(state.families[k]);
                    fam_map[k] = (out.state.families.len() - 1) as u32;
                }
                out.triangles.push(corners.map(|v| v.0));
                out.state.family_of_face.push(fam_map[k]);
                out.source_face.push(f.0);
            }
        } else if closure.red_face[f.idx()] {
            let [a, b, c] = corners.map(|v| v.0);
            let [ea, eb, ec] = hs.map(|h| mid_of(h).0);
            out.triangles
                .extend([[a, ea, ec], [b, eb, ea], [c, ec, eb], [ea, eb, ec]]);
            out.state.family_of_face.extend([NO_FAMILY; 4]);
            out.source_face.extend([f.0; 4]);
        } else {
            let mids = hs.map(|h| {
                if closure.split_edge[h.edge().idx()] {
                    mid_of(h)
                } else {
                    VertexId::NONE
                }
            });
            emit_closed(&mut out, corners, mids, f.0, positions);
        }
    }
    Ok(out)
}

/// Appends `tri` closed green where `mids` says, recording its family and source face.
#[inline]
fn emit_closed(
    out: &mut Assembly,
    tri: [VertexId; 3],
    mids: [VertexId; 3],
    source: u32,
    positions: &[Vec3],
) {
    let before = out.triangles.len();
    let id = match split_triangle(tri, mids, positions, &mut out.triangles) {
        Some(g) => {
            out.state.families.push(g);
            (out.state.families.len() - 1) as u32
        }
        None => NO_FAMILY,
    };
    for _ in before..out.triangles.len() {
        out.state.family_of_face.push(id);
        out.source_face.push(source);
    }
}

fn check_len(what: &'static str, got: usize, want: usize) -> Result<(), StitchError> {
    if got != want {
        return Err(StitchError::LengthMismatch { what, got, want });
    }
    Ok(())
}

fn check_triangles(mesh: &Mesh) -> Result<(), StitchError> {
    match mesh.faces().find(|&f| mesh.face_size(f) != 3) {
        Some(f) => Err(StitchError::NotTriangle {
            face: f.0,
            size: mesh.face_size(f) as u32,
        }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::PolygonSoup;

    /// A regular triangle strip grid of `n x n` quads cut into triangles, in the plane z = 0.
    fn grid(n: u32) -> Mesh {
        let mut p = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                p.push(Vec3::new(i as f32, j as f32, 0.0));
            }
        }
        let id = |i: u32, j: u32| j * (n + 1) + i;
        let mut f = Vec::new();
        for j in 0..n {
            for i in 0..n {
                f.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                f.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        Mesh::from_soup(&PolygonSoup::from_faces(p, &f)).unwrap()
    }

    /// Midpoints for every split edge, appended after the existing vertices.
    fn midpoints(mesh: &Mesh, c: &Closure) -> (Vec<VertexId>, Vec<Vec3>) {
        let mut pos = mesh.positions().to_vec();
        let mut mid = vec![VertexId::NONE; mesh.num_edges()];
        for e in mesh.edges() {
            if c.split_edge[e.idx()] {
                let [a, b] = mesh.edge_vertices(e);
                mid[e.idx()] = VertexId(pos.len() as u32);
                pos.push((mesh.position(a) + mesh.position(b)) * 0.5);
            }
        }
        (mid, pos)
    }

    fn step(mesh: &Mesh, state: &GreenState, sel: &[bool]) -> (Mesh, GreenState, Closure) {
        let c = close(mesh, state, sel).unwrap();
        let (mid, pos) = midpoints(mesh, &c);
        let a = assemble(mesh, state, &c, &mid, &pos).unwrap();
        let m = Mesh::from_soup(&PolygonSoup::from_faces(pos, &a.triangles)).unwrap();
        (m, a.state, c)
    }

    fn boundary_edges(m: &Mesh) -> usize {
        m.edges().filter(|&e| m.is_boundary_edge(e)).count()
    }

    #[test]
    fn one_two_three_split_closures() {
        let mesh = grid(3);
        let area: f32 = 9.0;
        // Select a single interior triangle: its three neighbours each get one split edge.
        let sel: Vec<bool> = mesh.faces().map(|f| f.0 == 8).collect();
        let (m, st, c) = step(&mesh, &GreenState::new(mesh.num_faces()), &sel);
        assert_eq!(c.red_face.iter().filter(|&&r| r).count(), 1);
        assert_eq!(m.num_faces(), 18 - 1 + 4 + 3);
        assert_eq!(st.families.len(), 3);
        assert!(st.families.iter().all(|g| g.num_splits() == 1));
        assert_eq!(
            boundary_edges(&m),
            12,
            "conforming: only the outer boundary"
        );
        let total: f32 = m.faces().map(|f| tri_area(&m, f)).sum();
        assert!((total - area).abs() < 1e-4);
        // Face with two split edges: select two triangles around one non-selected one.
        let p = vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(0.5, 1.0, 0.0),
            Vec3::new(1.5, 1.0, 0.0),
            Vec3::new(-0.5, 1.0, 0.0),
        ];
        let mesh = Mesh::from_soup(&PolygonSoup::from_faces(
            p,
            &[[0u32, 1, 2], [1, 3, 2], [0, 2, 4]],
        ))
        .unwrap();
        let (m, st, _) = step(&mesh, &GreenState::new(3), &[false, true, true]);
        assert_eq!(m.num_faces(), 4 + 4 + 3);
        assert_eq!(st.families.len(), 1);
        assert_eq!(st.families[0].num_splits(), 2);
        assert_eq!(
            boundary_edges(&m),
            9,
            "the five outer edges, four of them halved"
        );
    }

    fn tri_area(m: &Mesh, f: FaceId) -> f32 {
        let v = m.face_vertices(f);
        let (a, b, c) = (m.position(v[0]), m.position(v[1]), m.position(v[2]));
        (b - a).cross(c - a).length() * 0.5
    }

    #[test]
    fn three_split_edges_promote_to_red() {
        let mesh = grid(3);
        // Neighbours of face 8 on all three sides: faces sharing an edge with it.
        let h0 = mesh.face_halfedge(FaceId(8));
        let nb: Vec<u32> = [h0, mesh.next(h0), mesh.prev(h0)]
            .iter()
            .map(|h| mesh.face(h.twin()).0)
            .collect();
        let sel: Vec<bool> = mesh.faces().map(|f| nb.contains(&f.0)).collect();
        let c = close(&mesh, &GreenState::new(mesh.num_faces()), &sel).unwrap();
        assert!(c.red_face[8], "a face with three split edges is refined");
        assert_eq!(c.red_face.iter().filter(|&&r| r).count(), 4);
    }

    #[test]
    fn green_faces_merge_back_and_never_nest() {
        let mut mesh = grid(4);
        let mut state = GreenState::new(mesh.num_faces());
        // Refine around a point that moves across the grid; greens next to it must merge.
        let min_angle = |m: &Mesh| {
            let mut worst = 180.0f32;
            for f in m.faces() {
                let v = m.face_vertices(f);
                for k in 0..3 {
                    let a = m.position(v[k]);
                    let b = m.position(v[(k + 1) % 3]);
                    let c = m.position(v[(k + 2) % 3]);
                    worst = worst.min((b - a).angle_between(c - a).to_degrees());
                }
            }
            worst
        };
        for s in 0..4 {
            let target = Vec3::new(1.3 + 0.4 * s as f32, 1.7, 0.0);
            let sel: Vec<bool> = mesh
                .faces()
                .map(|f| mesh.face_centroid(f).distance(target) < 0.9)
                .collect();
            let (m, st, c) = step(&mesh, &state, &sel);
            if s > 0 {
                assert!(c.merged.iter().any(|&x| x), "step {s} merges a family back");
            }
            // Conforming: every boundary edge lies on the grid's outer square.
            for e in m.edges().filter(|&e| m.is_boundary_edge(e)) {
                let [a, b] = m.edge_vertices(e);
                let (a, b) = (m.position(a), m.position(b));
                let on = |x: f32| x == 0.0 || x == 4.0;
                assert!(
                    (on(a.x) && a.x == b.x) || (on(a.y) && a.y == b.y),
                    "step {s}: crack at {a} {b}"
                );
            }
            // Every green face's parent is a real triangle of the mesh's surface: no nesting,
            // so no face is thinner than half the original angles split twice.
            assert!(min_angle(&m) > 10.0, "step {s}: {}", min_angle(&m));
            for g in &st.families {
                assert!(g.num_splits() == 1 || g.num_splits() == 2);
            }
            mesh = m;
            state = st;
        }
    }

    #[test]
    fn bad_input() {
        let mesh = grid(1);
        assert!(matches!(
            close(&mesh, &GreenState::new(2), &[true]),
            Err(StitchError::LengthMismatch { want: 2, .. })
        ));
        let quad = Mesh::from_soup(&PolygonSoup::from_faces(
            vec![Vec3::ZERO, Vec3::X, Vec3::ONE, Vec3::Y],
            &[[0u32, 1, 2, 3]],
        ))
        .unwrap();
        let e = close(&quad, &GreenState::new(1), &[true]).unwrap_err();
        assert_eq!(e, StitchError::NotTriangle { face: 0, size: 4 });
        assert!(e.to_string().contains("face 0 has 4 vertices"));
        let c = close(&mesh, &GreenState::new(2), &[true, false]).unwrap();
        let mid = vec![VertexId::NONE; mesh.num_edges()];
        assert!(matches!(
            assemble(&mesh, &GreenState::new(2), &c, &mid, mesh.positions()),
            Err(StitchError::BadMidpoint { .. })
        ));
        let bad = GreenState {
            family_of_face: vec![0, NO_FAMILY],
            families: vec![],
        };
        assert!(matches!(
            close(&mesh, &bad, &[false, false]),
            Err(StitchError::FamilyOutOfRange {
                face: 0,
                family: 0,
                ..
            })
        ));
    }
}
