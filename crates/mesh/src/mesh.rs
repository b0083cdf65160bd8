//! The half-edge polygon mesh with sharpness, holes, groups and scheme options.

use std::collections::HashMap;

use glam::Vec3;

use crate::error::MeshError;
use crate::handle::{EdgeId, FaceId, HalfedgeId, VertexId};
use crate::options::{BoundaryInterpolation, SHARPNESS_INFINITE, SchemeOptions};
use crate::soup::PolygonSoup;

/// A manifold, consistently oriented polygon mesh with faces of any size.
///
/// Topology is a half-edge structure with explicit boundary half-edges (whose face is
/// [`FaceId::NONE`]), so every half-edge has a twin and every boundary is a closed loop of
/// boundary half-edges. Properties are arrays indexed by handle. Faces are counter-clockwise seen
/// from outside.
///
/// Invariants established by [`Mesh::from_soup`]:
/// - every edge has one or two faces; every vertex with faces has a single fan of faces;
/// - the out half-edge of a boundary vertex is its *leading* edge: the first edge in
///   counter-clockwise order, whose twin is a boundary half-edge;
/// - boundary edges carry infinite sharpness; with [`BoundaryInterpolation::EdgeAndCorner`]
///   boundary vertices with a single face carry infinite vertex sharpness (as in OpenSubdiv).
#[derive(Clone, Debug)]
pub struct Mesh {
    positions: Vec<Vec3>,
    vertex_sharpness: Vec<f32>,
    vertex_out: Vec<HalfedgeId>,
    he_to: Vec<VertexId>,
    he_next: Vec<HalfedgeId>,
    he_prev: Vec<HalfedgeId>,
    he_face: Vec<FaceId>,
    edge_sharpness: Vec<f32>,
    face_offsets: Vec<u32>,
    face_verts: Vec<VertexId>,
    face_he: Vec<HalfedgeId>,
    face_hole: Vec<bool>,
    face_group: Vec<u32>,
    groups: Vec<String>,
    options: SchemeOptions,
}

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
    /// Builds and validates a mesh from a polygon soup.
    ///
    /// Every problem is reported with the face, vertex or tag at fault and its source line:
    /// out-of-range indices, faces with fewer than three vertices, repeated vertices, non-finite
    /// coordinates, edges with more than two faces, non-manifold vertices, inconsistent
    /// orientation, and tags naming missing elements or invalid sharpness.
    ///
    /// ```
    /// use subdiv_mesh::{Mesh, PolygonSoup, MeshError};
    /// use glam::Vec3;
    /// let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
    /// let err = Mesh::from_soup(&PolygonSoup::from_faces(p, &[vec![0, 1, 5]])).unwrap_err();
    /// assert!(matches!(err, MeshError::IndexOutOfRange { face: 0, index: 5, .. }));
    /// ```
    pub fn from_soup(soup: &PolygonSoup) -> Result<Mesh, MeshError> {
        build(soup)
    }

    // ---- counts ----

    /// Number of vertices.
    #[inline]
    pub fn num_vertices(&self) -> usize {
        self.positions.len()
    }
    /// Number of faces (holes included).
    #[inline]
    pub fn num_faces(&self) -> usize {
        self.face_he.len()
    }
    /// Number of edges.
    #[inline]
    pub fn num_edges(&self) -> usize {
        self.edge_sharpness.len()
    }
    /// Number of half-edges (twice the edges).
    #[inline]
    pub fn num_halfedges(&self) -> usize {
        self.he_to.len()
    }

    // ---- properties ----

    /// All vertex positions, indexed by [`VertexId`].
    #[inline]
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }
    /// Mutable positions (topology and sharpness stay fixed).
    #[inline]
    pub fn positions_mut(&mut self) -> &mut [Vec3] {
        &mut self.positions
    }
    /// Position of `v`.
    #[inline]
    pub fn position(&self, v: VertexId) -> Vec3 {
        self.positions[v.idx()]
    }
    /// Sharpness of vertex `v` (0 = smooth, >= 10 = infinitely sharp).
    #[inline]
    pub fn vertex_sharpness(&self, v: VertexId) -> f32 {
        self.vertex_sharpness[v.idx()]
    }
    /// All vertex sharpness values.
    #[inline]
    pub fn vertex_sharpnesses(&self) -> &[f32] {
        &self.vertex_sharpness
    }
    /// Sharpness of edge `e` (boundary edges are infinitely sharp).
    #[inline]
    pub fn edge_sharpness(&self, e: EdgeId) -> f32 {
        self.edge_sharpness[e.idx()]
    }
    /// All edge sharpness values.
    #[inline]
    pub fn edge_sharpnesses(&self) -> &[f32] {
        &self.edge_sharpness
    }
    /// Sets the sharpness of edge `e`.
    pub fn set_edge_sharpness(&mut self, e: EdgeId, s: f32) {
        self.edge_sharpness[e.idx()] = s;
    }
    /// Sets the sharpness of vertex `v`.
    pub fn set_vertex_sharpness(&mut self, v: VertexId, s: f32) {
        self.vertex_sharpness[v.idx()] = s;
    }
    /// The scheme options.
    #[inline]
    pub fn options(&self) -> SchemeOptions {
        self.options
    }
    /// `true` if face `f` is a hole.
    #[inline]
    pub fn is_hole(&self, f: FaceId) -> bool {
        self.face_hole[f.idx()]
    }
    /// Hole flags of all faces.
    #[inline]
    pub fn holes(&self) -> &[bool] {
        &self.face_hole
    }
    /// Group names (from OBJ `g`/`o` lines).
    #[inline]
    pub fn groups(&self) -> &[String] {
        &self.groups
    }
    /// Group index of face `f` (into [`Mesh::groups`]), or `u32::MAX` if the face has none.
    #[inline]
    pub fn face_group(&self, f: FaceId) -> u32 {
        self.face_group[f.idx()]
    }
    /// Group indices of all faces.
    #[inline]
    pub fn face_groups(&self) -> &[u32] {
        &self.face_group
    }

    // ---- faces ----

    /// The vertices of face `f`, counter-clockwise.
    #[inline]
    pub fn face_vertices(&self, f: FaceId) -> &[VertexId] {
        let s = self.face_offsets[f.idx()] as usize;
        let e = self.face_offsets[f.idx() + 1] as usize;
        &self.face_verts[s..e]
    }
    /// Number of vertices of face `f`.
    #[inline]
    pub fn face_size(&self, f: FaceId) -> usize {
        (self.face_offsets[f.idx() + 1] - self.face_offsets[f.idx()]) as usize
    }
    /// The half-edge of face `f` leaving its first vertex.
    #[inline]
    pub fn face_halfedge(&self, f: FaceId) -> HalfedgeId {
        self.face_he[f.idx()]
    }
    /// Iterator over all face handles.
    pub fn faces(&self) -> impl ExactSizeIterator<Item = FaceId> + use<> {
        (0..self.num_faces() as u32).map(FaceId)
    }
    /// Iterator over all vertex handles.
    pub fn vertices(&self) -> impl ExactSizeIterator<Item = VertexId> + use<> {
        (0..self.num_vertices() as u32).map(VertexId)
    }
    /// Iterator over all edge handles.
    pub fn edges(&self) -> impl ExactSizeIterator<Item = EdgeId> + use<> {
        (0..self.num_edges() as u32).map(EdgeId)
    }
    /// The face-vertex lists in compressed form: offsets (one per face plus one) and indices.
    pub fn face_lists(&self) -> (&[u32], &[VertexId]) {
        (&self.face_offsets, &self.face_verts)
    }

    // ---- half-edges ----

    /// The vertex half-edge `h` points to.
    #[inline]
    pub fn to(&self, h: HalfedgeId) -> VertexId {
        self.he_to[h.idx()]
    }
    /// The vertex half-edge `h` leaves.
    #[inline]
    pub fn from(&self, h: HalfedgeId) -> VertexId {
        self.he_to[h.twin().idx()]
    }
    /// The next half-edge around the same face (or boundary loop).
    #[inline]
    pub fn next(&self, h: HalfedgeId) -> HalfedgeId {
        self.he_next[h.idx()]
    }
    /// The previous half-edge around the same face (or boundary loop).
    #[inline]
    pub fn prev(&self, h: HalfedgeId) -> HalfedgeId {
        self.he_prev[h.idx()]
    }
    /// The face of `h`, or [`FaceId::NONE`] for a boundary half-edge.
    #[inline]
    pub fn face(&self, h: HalfedgeId) -> FaceId {
        self.he_face[h.idx()]
    }
    /// `true` if `h` has no face.
    #[inline]
    pub fn is_boundary_halfedge(&self, h: HalfedgeId) -> bool {
        !self.he_face[h.idx()].is_some()
    }
    /// The two endpoints of `e`.
    #[inline]
    pub fn edge_vertices(&self, e: EdgeId) -> [VertexId; 2] {
        [self.to(e.halfedge(1)), self.to(e.halfedge(0))]
    }
    /// `true` if `e` has a single face.
    #[inline]
    pub fn is_boundary_edge(&self, e: EdgeId) -> bool {
        self.is_boundary_halfedge(e.halfedge(0)) || self.is_boundary_halfedge(e.halfedge(1))
    }

    // ---- vertices ----

    /// The first outgoing half-edge of `v` in counter-clockwise order (its leading boundary edge
    /// for a boundary vertex), or [`HalfedgeId::NONE`] for an isolated vertex.
    #[inline]
    pub fn vertex_halfedge(&self, v: VertexId) -> HalfedgeId {
        self.vertex_out[v.idx()]
    }
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
    /// `true` if `v` lies on a boundary.
    #[inline]
    pub fn is_boundary_vertex(&self, v: VertexId) -> bool {
        let h = self.vertex_out[v.idx()];
        h.is_some() && self.is_boundary_halfedge(h.twin())
    }
    /// `true` if `v` has no faces.
    #[inline]
    pub fn is_isolated(&self, v: VertexId) -> bool {
        !self.vertex_out[v.idx()].is_some()
    }
    /// The half-edge from `a` to `b`, if they share an edge.
    pub fn find_halfedge(&self, a: VertexId, b: VertexId) -> Option<HalfedgeId> {
        self.outgoing(a).find(|&h| self.to(h) == b)
    }
    /// The face normal of `f` (Newell's method), normalised; zero for a degenerate face.
    pub fn face_normal(&self, f: FaceId) -> Vec3 {
        let vs = self.face_vertices(f);
        let mut n = Vec3::ZERO;
        for i in 0..vs.len() {
            let a = self.positions[vs[i].idx()];
            let b = self.positions[vs[(i + 1) % vs.len()].idx()];
            n += a.cross(b);
        }
        n.normalize_or_zero()
    }
    /// The centroid of face `f`.
    pub fn face_centroid(&self, f: FaceId) -> Vec3 {
        let vs = self.face_vertices(f);
        vs.iter().map(|v| self.positions[v.idx()]).sum::<Vec3>() / vs.len() as f32
    }
    /// Axis-aligned bounding box `(min, max)` of all vertices.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for p in &self.positions {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        (lo, hi)
    }
    /// Largest vertex valence (0 for a mesh without faces).
    pub fn max_valence(&self) -> usize {
        self.vertices().map(|v| self.valence(v)).max().unwrap_or(0)
    }
    /// Replaces the group names and per-face group indices (e.g. after refinement).
    pub fn set_groups(&mut self, groups: Vec<String>, face_group: Vec<u32>) {
        debug_assert_eq!(face_group.len(), self.num_faces());
        self.groups = groups;
        self.face_group = face_group;
    }
    /// Sets the hole flags of all faces.
    pub fn set_holes(&mut self, holes: Vec<bool>) {
        debug_assert_eq!(holes.len(), self.num_faces());
        self.face_hole = holes;
    }
}

fn to_u32(n: usize, what: &str) -> Result<u32, MeshError> {
    u32::try_from(n)
        .ok()
        .filter(|&x| x != u32::MAX)
        .ok_or_else(|| MeshError::TooLarge {
            what: format!("{n} {what}"),
        })
}

fn valid_sharpness(tag: &'static str, s: f32, line: Option<u32>) -> Result<f32, MeshError> {
    if s.is_finite() && s >= 0.0 {
        Ok(s.min(SHARPNESS_INFINITE))
    } else {
        Err(MeshError::BadSharpness {
            tag,
            value: s,
            line,
        })
    }
}

fn build(soup: &PolygonSoup) -> Result<Mesh, MeshError> {
    let nv = to_u32(soup.positions.len(), "vertices")?;
    let nf = soup.num_faces();
    to_u32(nf, "faces")?;
    if nf == 0 {
        return Err(MeshError::Empty);
    }
    for (i, p) in soup.positions.iter().enumerate() {
        if !p.is_finite() {
            return Err(MeshError::NonFinite {
                vertex: i as u32,
                x: p.x,
                y: p.y,
                z: p.z,
                line: soup.vertex_line(i),
            });
        }
    }

    // Faces: size, range, repeated vertices.
    let mut face_offsets = Vec::with_capacity(nf + 1);
    let mut face_verts: Vec<VertexId> = Vec::with_capacity(soup.face_indices.len());
    face_offsets.push(0u32);
    let mut scratch: Vec<u32> = Vec::new();
    for fi in 0..nf {
        let f = soup.face(fi);
        let line = soup.face_line(fi);
        if f.len() < 3 {
            return Err(MeshError::FaceTooSmall {
                face: fi as u32,
                len: f.len() as u32,
                line,
            });
        }
        for &i in f {
            if i < 0 || i >= nv as i64 {
                return Err(MeshError::IndexOutOfRange {
                    face: fi as u32,
                    index: i,
                    count: nv,
                    line,
                });
            }
        }
        scratch.clear();
        scratch.extend(f.iter().map(|&i| i as u32));
        scratch.sort_unstable();
        if let Some(w) = scratch.windows(2).find(|w| w[0] == w[1]) {
            return Err(MeshError::RepeatedVertex {
                face: fi as u32,
                vertex: w[0],
                line,
            });
        }
        face_verts.extend(f.iter().map(|&i| VertexId(i as u32)));
        face_offsets.push(to_u32(face_verts.len(), "face corners")?);
    }
    let ncorners = face_verts.len();
    to_u32(ncorners * 2, "half-edges")?;

    // Edges: key (min, max) -> edge index. Half-edge 2e runs in the direction of first use.
    let mut edge_map: HashMap<(u32, u32), u32> = HashMap::with_capacity(ncorners);
    let mut he_to: Vec<VertexId> = Vec::with_capacity(ncorners + ncorners / 4);
    let mut he_face: Vec<FaceId> = Vec::with_capacity(ncorners + ncorners / 4);
    let mut corner_he: Vec<HalfedgeId> = Vec::with_capacity(ncorners);
    for fi in 0..nf {
        let s = face_offsets[fi] as usize;
        let e = face_offsets[fi + 1] as usize;
        let n = e - s;
        for k in 0..n {
            let a = face_verts[s + k].0;
            let b = face_verts[s + (k + 1) % n].0;
            let key = (a.min(b), a.max(b));
            let h = match edge_map.get(&key) {
                None => {
                    let eidx = (he_to.len() / 2) as u32;
                    edge_map.insert(key, eidx);
                    he_to.push(VertexId(b));
                    he_to.push(VertexId(a));
                    he_face.push(FaceId(fi as u32));
                    he_face.push(FaceId::NONE);
                    HalfedgeId(eidx * 2)
                }
                Some(&eidx) => {
                    let h0 = HalfedgeId(eidx * 2);
                    let h1 = h0.twin();
                    let f0 = he_face[h0.idx()];
                    let f1 = he_face[h1.idx()];
                    if f1.is_some() {
                        return Err(MeshError::NonManifoldEdge {
                            a: key.0,
                            b: key.1,
                            faces: vec![f0.0, f1.0, fi as u32],
                            line: soup.face_line(fi),
                        });
                    }
                    if he_to[h0.idx()].0 == b {
                        // Same direction as the first face; a third face might still make it
                        // non-manifold, so look ahead to give the more useful error.
                        let mut users = vec![f0.0, fi as u32];
                        for fj in fi + 1..nf {
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
                            return Err(MeshError::NonManifoldEdge {
                                a: key.0,
                                b: key.1,
                                faces: users,
                                line: soup.face_line(fi),
                            });
                        }
                        return Err(MeshError::InconsistentOrientation {
                            a,
                            b,
                            face: fi as u32,
                            other: f0.0,
                            line: soup.face_line(fi),
                        });
                    }
                    he_face[h1.idx()] = FaceId(fi as u32);
                    h1
                }
            };
            corner_he.push(h);
        }
    }
    let nh = he_to.len();
    let ne = nh / 2;
    let mut he_next = vec![HalfedgeId::NONE; nh];
    let mut he_prev = vec![HalfedgeId::NONE; nh];
    let mut face_he = Vec::with_capacity(nf);
    for fi in 0..nf {
        let s = face_offsets[fi] as usize;
        let n = face_offsets[fi + 1] as usize - s;
        for k in 0..n {
            let h = corner_he[s + k];
            let hn = corner_he[s + (k + 1) % n];
            he_next[h.idx()] = hn;
            he_prev[hn.idx()] = h;
        }
        face_he.push(corner_he[s]);
    }

    // Boundary loops: the boundary half-edge leaving each boundary vertex must be unique.
    let mut boundary_out = vec![HalfedgeId::NONE; nv as usize];
    for h in 0..nh {
        if !he_face[h].is_some() {
            let from = he_to[h ^ 1];
            if boundary_out[from.idx()].is_some() {
                return Err(MeshError::NonManifoldVertex {
                    vertex: from.0,
                    fans: 2,
                    line: soup.vertex_line(from.idx()),
                });
            }
            boundary_out[from.idx()] = HalfedgeId(h as u32);
        }
    }
    for h in 0..nh {
        if !he_face[h].is_some() {
            let to = he_to[h];
            let n = boundary_out[to.idx()];
            he_next[h] = n;
            he_prev[n.idx()] = HalfedgeId(h as u32);
        }
    }

    // Vertex out half-edges: the leading edge for boundary vertices.
    let mut vertex_out = vec![HalfedgeId::NONE; nv as usize];
    let mut corner_count = vec![0u32; nv as usize];
    for (k, v) in face_verts.iter().enumerate() {
        corner_count[v.idx()] += 1;
        if !vertex_out[v.idx()].is_some() {
            vertex_out[v.idx()] = corner_he[k];
        }
    }
    for v in 0..nv as usize {
        let b = boundary_out[v];
        if b.is_some() {
            vertex_out[v] = he_prev[b.idx()].twin();
        }
    }

    let mut mesh = Mesh {
        positions: soup.positions.clone(),
        vertex_sharpness: vec![0.0; nv as usize],
        vertex_out,
        he_to,
        he_next,
        he_prev,
        he_face,
        edge_sharpness: vec![0.0; ne],
        face_offsets,
        face_verts,
        face_he,
        face_hole: vec![false; nf],
        face_group: if soup.face_groups.len() == nf {
            soup.face_groups.clone()
        } else {
            vec![u32::MAX; nf]
        },
        groups: soup.groups.clone(),
        options: soup.options,
    };

    // Every vertex must have exactly one fan: the counter-clockwise walk must meet all its faces.
    for v in 0..nv {
        let vid = VertexId(v);
        if corner_count[v as usize] == 0 {
            continue;
        }
        let mut faces_seen = 0u32;
        let limit = corner_count[v as usize] as usize + 2;
        let mut steps = 0usize;
        for h in mesh.outgoing(vid) {
            steps += 1;
            if mesh.he_face[h.idx()].is_some() {
                faces_seen += 1;
            }
            if steps > limit {
                break;
            }
        }
        if faces_seen != corner_count[v as usize] {
            let fans = if faces_seen == 0 {
                2
            } else {
                corner_count[v as usize].div_ceil(faces_seen.max(1)).max(2)
            };
            return Err(MeshError::NonManifoldVertex {
                vertex: v,
                fans,
                line: soup.vertex_line(v as usize),
            });
        }
    }

    // Tags.
    for t in &soup.creases {
        let s = valid_sharpness("crease", t.sharpness, t.line)?;
        for &x in &[t.a, t.b] {
            if x < 0 || x >= nv as i64 {
                return Err(MeshError::TagMissingVertex {
                    tag: "crease",
                    vertex: x,
                    count: nv,
                    line: t.line,
                });
            }
        }
        let (a, b) = (t.a as u32, t.b as u32);
        match edge_map.get(&(a.min(b), a.max(b))) {
            Some(&e) => mesh.edge_sharpness[e as usize] = s,
            None => return Err(MeshError::TagMissingEdge { a, b, line: t.line }),
        }
    }
    for t in &soup.corners {
        let s = valid_sharpness("corner", t.sharpness, t.line)?;
        if t.v < 0 || t.v >= nv as i64 {
            return Err(MeshError::TagMissingVertex {
                tag: "corner",
                vertex: t.v,
                count: nv,
                line: t.line,
            });
        }
        mesh.vertex_sharpness[t.v as usize] = s;
    }
    for t in &soup.holes {
        if t.f < 0 || t.f >= nf as i64 {
            return Err(MeshError::TagMissingFace {
                face: t.f,
                count: nf as u32,
                line: t.line,
            });
        }
        mesh.face_hole[t.f as usize] = true;
    }

    // Boundary sharpening, as OpenSubdiv does before refinement.
    for e in 0..ne {
        if mesh.is_boundary_edge(EdgeId(e as u32)) {
            mesh.edge_sharpness[e] = SHARPNESS_INFINITE;
        }
    }
    if mesh.options.boundary == BoundaryInterpolation::EdgeAndCorner {
        for v in 0..nv {
            let vid = VertexId(v);
            if mesh.is_boundary_vertex(vid) && corner_count[v as usize] == 1 {
                mesh.vertex_sharpness[v as usize] = SHARPNESS_INFINITE;
            }
        }
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::soup::{CornerTag, CreaseTag, HoleTag};

    fn grid(n: u32) -> PolygonSoup {
        let mut p = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                p.push(Vec3::new(i as f32, j as f32, 0.0));
            }
        }
        let mut faces = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let a = j * (n + 1) + i;
                faces.push(vec![a, a + 1, a + n + 2, a + n + 1]);
            }
        }
        PolygonSoup::from_faces(p, &faces)
    }

    fn cube() -> PolygonSoup {
        let p = (0..8)
            .map(|i| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32))
            .collect();
        let faces = [
            vec![0, 2, 3, 1],
            vec![4, 5, 7, 6],
            vec![0, 1, 5, 4],
            vec![2, 6, 7, 3],
            vec![0, 4, 6, 2],
            vec![1, 3, 7, 5],
        ];
        PolygonSoup::from_faces(p, &faces)
    }

    #[test]
    fn cube_topology() {
        let m = Mesh::from_soup(&cube()).unwrap();
        assert_eq!((m.num_vertices(), m.num_edges(), m.num_faces()), (8, 12, 6));
        for v in m.vertices() {
            assert_eq!(m.valence(v), 3);
            assert!(!m.is_boundary_vertex(v));
            // Ring order is counter-clockwise: consecutive outgoing edges share a face.
            let hs: Vec<_> = m.outgoing(v).collect();
            for (i, &h) in hs.iter().enumerate() {
                let n = hs[(i + 1) % hs.len()];
                assert_eq!(m.prev(h).twin(), n);
                assert_eq!(m.from(h), v);
            }
        }
        for e in m.edges() {
            assert!(!m.is_boundary_edge(e));
            assert_eq!(m.edge_sharpness(e), 0.0);
        }
    }

    #[test]
    fn grid_boundary_ring_order() {
        let m = Mesh::from_soup(&grid(2)).unwrap();
        assert_eq!((m.num_vertices(), m.num_edges(), m.num_faces()), (9, 12, 4));
        // Corner vertex 0: two edges, one face; leading edge first, boundary half-edge last.
        let hs: Vec<_> = m.outgoing(VertexId(0)).collect();
        assert_eq!(hs.len(), 2);
        assert!(m.is_boundary_halfedge(hs[0].twin()));
        assert!(m.is_boundary_halfedge(hs[1]));
        // Middle of an edge (vertex 1): three edges, two faces.
        let hs: Vec<_> = m.outgoing(VertexId(1)).collect();
        assert_eq!(hs.len(), 3);
        assert!(m.face(hs[0]).is_some() && m.face(hs[1]).is_some() && !m.face(hs[2]).is_some());
        // Centre vertex: valence 4, interior.
        assert_eq!(m.valence(VertexId(4)), 4);
        assert!(!m.is_boundary_vertex(VertexId(4)));
        let boundary = m.edges().filter(|&e| m.is_boundary_edge(e)).count();
        assert_eq!(boundary, 8);
        for e in m.edges() {
            let want = if m.is_boundary_edge(e) {
                SHARPNESS_INFINITE
            } else {
                0.0
            };
            assert_eq!(m.edge_sharpness(e), want);
        }
        // Boundary loop closes.
        let b0 = m.outgoing(VertexId(0)).last().unwrap();
        let mut h = b0;
        let mut n = 0;
        loop {
            h = m.next(h);
            n += 1;
            assert!(m.is_boundary_halfedge(h));
            if h == b0 || n > 100 {
                break;
            }
        }
        assert_eq!(n, 8);
    }

    #[test]
    fn edge_and_corner_sharpens_corners() {
        let mut s = grid(2);
        s.options.boundary = BoundaryInterpolation::EdgeAndCorner;
        let m = Mesh::from_soup(&s).unwrap();
        for v in [0, 2, 6, 8] {
            assert_eq!(m.vertex_sharpness(VertexId(v)), SHARPNESS_INFINITE);
        }
        assert_eq!(m.vertex_sharpness(VertexId(1)), 0.0);
    }

    #[test]
    fn tags_apply() {
        let mut s = cube();
        s.creases.push(CreaseTag {
            a: 0,
            b: 2,
            sharpness: 2.5,
            line: Some(3),
        });
        s.corners.push(CornerTag {
            v: 7,
            sharpness: 1.0,
            line: None,
        });
        s.holes.push(HoleTag { f: 1, line: None });
        let m = Mesh::from_soup(&s).unwrap();
        let h = m.find_halfedge(VertexId(2), VertexId(0)).unwrap();
        assert_eq!(m.edge_sharpness(h.edge()), 2.5);
        assert_eq!(m.vertex_sharpness(VertexId(7)), 1.0);
        assert!(m.is_hole(FaceId(1)) && !m.is_hole(FaceId(0)));
    }

    fn err(s: &PolygonSoup) -> MeshError {
        Mesh::from_soup(s).unwrap_err()
    }

    #[test]
    fn error_index_out_of_range() {
        let s = PolygonSoup::from_faces(vec![Vec3::ZERO; 3], &[vec![0, 1, 3]]);
        assert!(matches!(
            err(&s),
            MeshError::IndexOutOfRange {
                face: 0,
                index: 3,
                count: 3,
                ..
            }
        ));
        let mut s = PolygonSoup {
            positions: vec![Vec3::ZERO; 3],
            ..Default::default()
        };
        s.push_face([0, 1, -1]);
        assert!(matches!(
            err(&s),
            MeshError::IndexOutOfRange { index: -1, .. }
        ));
    }

    #[test]
    fn error_small_face() {
        let s = PolygonSoup::from_faces(vec![Vec3::ZERO; 3], &[vec![0, 1]]);
        assert!(matches!(
            err(&s),
            MeshError::FaceTooSmall {
                face: 0,
                len: 2,
                ..
            }
        ));
    }

    #[test]
    fn error_repeated_vertex() {
        let s = PolygonSoup::from_faces(vec![Vec3::ZERO; 3], &[vec![0, 1, 2, 1]]);
        assert!(matches!(
            err(&s),
            MeshError::RepeatedVertex {
                face: 0,
                vertex: 1,
                ..
            }
        ));
    }

    #[test]
    fn error_non_finite() {
        let mut s = cube();
        s.positions[5].y = f32::NAN;
        s.vertex_lines = (1..=8).collect();
        let e = err(&s);
        assert!(
            matches!(
                e,
                MeshError::NonFinite {
                    vertex: 5,
                    line: Some(6),
                    ..
                }
            ),
            "{e:?}"
        );
        s.positions[5].y = f32::INFINITY;
        assert!(matches!(err(&s), MeshError::NonFinite { vertex: 5, .. }));
    }

    #[test]
    fn error_non_manifold_edge() {
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z, Vec3::ONE];
        let s = PolygonSoup::from_faces(p, &[vec![0, 1, 2], vec![1, 0, 3], vec![0, 1, 4]]);
        let e = err(&s);
        assert!(
            matches!(e, MeshError::NonManifoldEdge { a: 0, b: 1, .. }),
            "{e:?}"
        );
    }

    #[test]
    fn error_non_manifold_vertex() {
        // Two triangles touching only at vertex 0 (a bow-tie).
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, -Vec3::X, -Vec3::Y];
        let s = PolygonSoup::from_faces(p, &[vec![0, 1, 2], vec![0, 3, 4]]);
        assert!(matches!(
            err(&s),
            MeshError::NonManifoldVertex { vertex: 0, .. }
        ));
        // Two closed cones sharing their apex: no boundary at the apex, two fans.
        let mut p = vec![Vec3::ZERO];
        let mut faces = Vec::new();
        for (k, z) in [(0u32, 1.0f32), (1, -1.0)] {
            let base = 1 + k * 3;
            for i in 0..3 {
                let a = i as f32 * 2.1;
                p.push(Vec3::new(a.cos(), a.sin(), z));
            }
            faces.push(vec![0, base, base + 1]);
            faces.push(vec![0, base + 1, base + 2]);
            faces.push(vec![0, base + 2, base]);
            faces.push(vec![base, base + 2, base + 1]);
        }
        let s = PolygonSoup::from_faces(p, &faces);
        assert!(matches!(
            err(&s),
            MeshError::NonManifoldVertex { vertex: 0, .. }
        ));
    }

    #[test]
    fn error_orientation() {
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ONE];
        let s = PolygonSoup::from_faces(p, &[vec![0, 1, 2], vec![0, 1, 3]]);
        assert!(matches!(
            err(&s),
            MeshError::InconsistentOrientation {
                a: 0,
                b: 1,
                face: 1,
                other: 0,
                ..
            }
        ));
    }

    #[test]
    fn error_tags() {
        let mut s = cube();
        s.creases.push(CreaseTag {
            a: 0,
            b: 7,
            sharpness: 1.0,
            line: Some(20),
        });
        assert!(matches!(
            err(&s),
            MeshError::TagMissingEdge {
                a: 0,
                b: 7,
                line: Some(20)
            }
        ));
        let mut s = cube();
        s.creases.push(CreaseTag {
            a: 0,
            b: 70,
            sharpness: 1.0,
            line: None,
        });
        assert!(matches!(
            err(&s),
            MeshError::TagMissingVertex { vertex: 70, .. }
        ));
        let mut s = cube();
        s.corners.push(CornerTag {
            v: 9,
            sharpness: 1.0,
            line: None,
        });
        assert!(matches!(
            err(&s),
            MeshError::TagMissingVertex {
                tag: "corner",
                vertex: 9,
                ..
            }
        ));
        let mut s = cube();
        s.holes.push(HoleTag { f: 6, line: None });
        assert!(matches!(err(&s), MeshError::TagMissingFace { face: 6, .. }));
        let mut s = cube();
        s.creases.push(CreaseTag {
            a: 0,
            b: 2,
            sharpness: f32::NAN,
            line: None,
        });
        assert!(matches!(err(&s), MeshError::BadSharpness { .. }));
        let mut s = cube();
        s.corners.push(CornerTag {
            v: 0,
            sharpness: -1.0,
            line: None,
        });
        assert!(matches!(err(&s), MeshError::BadSharpness { .. }));
    }

    #[test]
    fn error_empty() {
        let s = PolygonSoup {
            positions: vec![Vec3::ZERO],
            ..Default::default()
        };
        assert_eq!(err(&s), MeshError::Empty);
    }

    #[test]
    fn high_valence_fan() {
        // A disk with a valence-360 centre.
        let n = 360u32;
        let mut p = vec![Vec3::ZERO];
        for i in 0..n {
            let a = i as f32 / n as f32 * std::f32::consts::TAU;
            p.push(Vec3::new(a.cos(), a.sin(), 0.0));
        }
        let faces: Vec<Vec<u32>> = (0..n).map(|i| vec![0, 1 + i, 1 + (i + 1) % n]).collect();
        let m = Mesh::from_soup(&PolygonSoup::from_faces(p, &faces)).unwrap();
        assert_eq!(m.valence(VertexId(0)), 360);
        assert_eq!(m.max_valence(), 360);
    }
}

#[cfg(test)]
mod split_tests {
    use super::*;

    #[test]
    fn split_bowtie_and_cones() {
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, -Vec3::X, -Vec3::Y];
        let mut s = PolygonSoup::from_faces(p, &[vec![0, 1, 2], vec![0, 3, 4]]);
        s.corners.push(crate::soup::CornerTag {
            v: 0,
            sharpness: 2.0,
            line: None,
        });
        let created = s.split_nonmanifold_vertices();
        assert_eq!(created, vec![(0, 5)]);
        let m = Mesh::from_soup(&s).unwrap();
        assert_eq!(m.num_vertices(), 6);
        assert_eq!(m.position(VertexId(5)), Vec3::ZERO);
        assert_eq!(m.vertex_sharpness(VertexId(5)), 2.0);
        assert_eq!(m.face_vertices(FaceId(1))[0], VertexId(5));
        // A manifold soup is left alone.
        let mut s = PolygonSoup::from_faces(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[vec![0, 1, 2]]);
        assert!(s.split_nonmanifold_vertices().is_empty());
    }
}
