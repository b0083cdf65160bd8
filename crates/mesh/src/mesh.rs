//! The half-edge polygon mesh with sharpness, holes, groups and scheme options: the [`Mesh`]
//! type, its counts and property accessors. Construction (validation and topology, one step
//! per submodule) lives in `build`, and the counter-clockwise vertex-ring traversal in `traverse`.

mod build;
mod instance;
mod traverse;

use glam::Vec3;

use crate::error::MeshError;
use crate::handle::{EdgeId, FaceId, HalfedgeId, VertexId};
use crate::options::SchemeOptions;
use crate::soup::PolygonSoup;

pub use traverse::Outgoing;

/// Whether two sharpness arrays hold the same values, bit for bit.
fn same_bits(a: &[f32], b: &[f32]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

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
/// - boundary edges carry infinite sharpness; with
///   [`BoundaryInterpolation::EdgeAndCorner`](crate::BoundaryInterpolation::EdgeAndCorner)
///   boundary vertices with a single face carry infinite vertex sharpness (as in OpenSubdiv);
/// - with [`BoundaryInterpolation::None`](crate::BoundaryInterpolation::None) the faces
///   OpenSubdiv hides are holes (every face at a vertex with a boundary edge not tagged
///   infinitely sharp), so every tessellator hides the same faces by hiding holes.
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
    uv: Option<crate::FaceVarying>,
    /// The primvars beside the positions and `uv` ([`Mesh::primvars`]).
    primvars: Vec<crate::Primvar>,
    /// [`Mesh::whole_vertex_edges`]: sorted semi-sharp values, by vertex; empty for almost
    /// every mesh.
    whole_edges: std::collections::BTreeMap<u32, Vec<f32>>,
    /// [`Mesh::crease_ends`], by vertex.
    crease_ends: std::collections::BTreeMap<u32, [HalfedgeId; 2]>,
    /// [`Mesh::is_fvar_corner`]: sorted vertices; empty for almost every mesh.
    fvar_corners: Vec<u32>,
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
        build::build(soup)
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
    /// Whether `other` is this mesh but for its positions: the same faces, sharpness, holes,
    /// options, face-varying data and groups (a cage that moved, such as an animated cage's
    /// next frame), so that what was set up for one (a tessellation layout) serves the other.
    pub fn same_topology(&self, other: &Mesh) -> bool {
        // Destructured so that a new field cannot be forgotten here.
        let Mesh {
            positions: _,
            vertex_sharpness,
            vertex_out,
            he_to,
            he_next,
            he_prev,
            he_face,
            edge_sharpness,
            face_offsets,
            face_verts,
            face_he,
            face_hole,
            face_group,
            groups,
            options,
            uv,
            primvars: _,
            whole_edges,
            crease_ends,
            fvar_corners,
        } = self;
        self.positions.len() == other.positions.len()
            && *face_offsets == other.face_offsets
            && *face_verts == other.face_verts
            && *vertex_out == other.vertex_out
            && *he_to == other.he_to
            && *he_next == other.he_next
            && *he_prev == other.he_prev
            && *he_face == other.he_face
            && *face_he == other.face_he
            && same_bits(vertex_sharpness, &other.vertex_sharpness)
            && same_bits(edge_sharpness, &other.edge_sharpness)
            && *face_hole == other.face_hole
            && *face_group == other.face_group
            && *groups == other.groups
            && *options == other.options
            && *uv == other.uv
            && *whole_edges == other.whole_edges
            && *crease_ends == other.crease_ends
            && *fvar_corners == other.fvar_corners
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
    /// The semi-sharp edge sharpness of the *whole vertex* that `v` is a copy of, where `v` is
    /// one of several copies of a non-manifold crease vertex holding semi-sharp edges
    /// ([`PolygonSoup::split_nonmanifold`](crate::PolygonSoup::split_nonmanifold)); `None`
    /// elsewhere. OpenSubdiv decides the vertex's rule, its fractional weight and the Chaikin
    /// decay of its edges over all the vertex's edges, every copy's together: every vertex
    /// rule reads these values in place of the semi-sharp edges of `v`'s own ring (the values
    /// are sorted, positive and below infinity, so every copy sums them alike, to the bit).
    #[inline]
    pub fn whole_vertex_edges(&self, v: VertexId) -> Option<&[f32]> {
        if self.whole_edges.is_empty() {
            return None;
        }
        self.whole_edges.get(&v.0).map(Vec::as_slice)
    }
    /// Every vertex with [`Mesh::whole_vertex_edges`], in vertex order.
    pub fn whole_vertex_edges_all(&self) -> impl Iterator<Item = (VertexId, &[f32])> + '_ {
        self.whole_edges
            .iter()
            .map(|(&v, s)| (VertexId(v), s.as_slice()))
    }
    /// Where `v` is a copy of a non-manifold crease vertex whose ring lacks one or both of the
    /// vertex's two non-manifold edges (a closed fan touching the vertex, or a fan that leaves
    /// and returns through the same non-manifold edge): those two edges, as half-edges leaving
    /// copies of the vertex (other copies than `v`). OpenSubdiv's crease rule reads their far
    /// ends, which `v`'s ring lacks, so `v`'s points are the crease rule's over them at every
    /// level (see [`PolygonSoup::split_nonmanifold`](crate::PolygonSoup::split_nonmanifold)).
    /// `None` elsewhere.
    #[inline]
    pub fn crease_ends(&self, v: VertexId) -> Option<[HalfedgeId; 2]> {
        if self.crease_ends.is_empty() {
            return None;
        }
        self.crease_ends.get(&v.0).copied()
    }
    /// The copy holding both edges of [`Mesh::crease_ends`] where one does (`None` where they
    /// leave different copies, or `v` is no crease copy).
    #[inline]
    pub fn crease_copy_of(&self, v: VertexId) -> Option<VertexId> {
        let [a, b] = self.crease_ends(v)?;
        (self.from(a) == self.from(b)).then(|| self.from(a))
    }
    /// Every `(copy, crease ends)` of [`Mesh::crease_ends`], in vertex order.
    pub fn crease_ends_all(&self) -> impl Iterator<Item = (VertexId, [HalfedgeId; 2])> + '_ {
        self.crease_ends.iter().map(|(&v, &h)| (VertexId(v), h))
    }
    /// Whether `v` is a copy of a non-manifold vertex whose face-varying values differ, which
    /// OpenSubdiv keeps in place at every level: every value there is a corner
    /// ([`PolygonSoup::split_nonmanifold`](crate::PolygonSoup::split_nonmanifold)). Refinement
    /// keeps the set (a vertex's child has its number).
    #[inline]
    pub fn is_fvar_corner(&self, v: VertexId) -> bool {
        !self.fvar_corners.is_empty() && self.fvar_corners.binary_search(&v.0).is_ok()
    }
    /// The vertices of [`Mesh::is_fvar_corner`], sorted.
    pub fn fvar_corners(&self) -> &[u32] {
        &self.fvar_corners
    }
    /// Sets the vertices of [`Mesh::is_fvar_corner`] (those out of range are dropped).
    pub fn set_fvar_corners(&mut self, vertices: &[u32]) {
        let n = self.num_vertices() as u32;
        self.fvar_corners = vertices.iter().copied().filter(|&v| v < n).collect();
        self.fvar_corners.sort_unstable();
        self.fvar_corners.dedup();
    }
    /// Sets [`Mesh::crease_ends`] of `v` (`None` removes it).
    pub fn set_crease_ends(&mut self, v: VertexId, ends: Option<[HalfedgeId; 2]>) {
        match ends {
            Some(h) => {
                self.crease_ends.insert(v.0, h);
            }
            None => {
                self.crease_ends.remove(&v.0);
            }
        }
    }
    /// Sets [`Mesh::whole_vertex_edges`] of `v`: the values that are semi-sharp, sorted (none
    /// removes them).
    pub fn set_whole_vertex_edges(&mut self, v: VertexId, values: &[f32]) {
        let mut s: Vec<f32> = values
            .iter()
            .copied()
            .filter(|&x| crate::sharpness::is_semi_sharp(x))
            .collect();
        if s.is_empty() {
            self.whole_edges.remove(&v.0);
        } else {
            s.sort_unstable_by(f32::total_cmp);
            self.whole_edges.insert(v.0, s);
        }
    }
    /// The scheme options.
    #[inline]
    pub fn options(&self) -> SchemeOptions {
        self.options
    }
    /// The face-varying channel (UVs), if the mesh has one.
    #[inline]
    pub fn uv(&self) -> Option<&crate::FaceVarying> {
        self.uv.as_ref()
    }
    /// Drops the face-varying channel.
    pub fn clear_uv(&mut self) {
        self.uv = None;
    }
    /// Replaces the face-varying channel (texture coordinates), checked: one index per face
    /// corner, each naming a value; `None` drops it. The positions, topology and options stay.
    pub fn set_uv(&mut self, uv: Option<crate::FaceVarying>) -> Result<(), MeshError> {
        if let Some(fv) = &uv {
            let corners = self.face_verts.len();
            if fv.indices.len() != corners {
                return Err(MeshError::UvCount {
                    indices: fv.indices.len() as u64,
                    corners: corners as u64,
                });
            }
            if let Some(&i) = fv.indices.iter().find(|&&i| i as usize >= fv.values.len()) {
                return Err(MeshError::Primvar {
                    name: "st".into(),
                    msg: format!("index {i} is outside the {} values", fv.values.len()),
                });
            }
            if !fv.dependence.is_empty() && fv.dependence.len() != fv.values.len() {
                return Err(MeshError::Primvar {
                    name: "st".into(),
                    msg: format!(
                        "{} dependence tags for {} values",
                        fv.dependence.len(),
                        fv.values.len()
                    ),
                });
            }
        }
        self.uv = uv;
        Ok(())
    }
    /// Sets the face-varying channel's [`crate::Dependence`] (one per value; empty: a cage's,
    /// from its topology). Does nothing without a channel.
    pub fn set_uv_dependence(
        &mut self,
        dependence: Vec<crate::Dependence>,
    ) -> Result<(), MeshError> {
        let Some(fv) = &mut self.uv else {
            return Ok(());
        };
        if !dependence.is_empty() && dependence.len() != fv.values.len() {
            return Err(MeshError::Primvar {
                name: "st".into(),
                msg: format!(
                    "{} dependence tags for {} values",
                    dependence.len(),
                    fv.values.len()
                ),
            });
        }
        fv.dependence = dependence;
        Ok(())
    }
    /// The primvars other than the positions and the texture coordinates ([`Mesh::uv`]).
    pub fn primvars(&self) -> &[crate::Primvar] {
        &self.primvars
    }
    /// Drops the primvars (the texture coordinates stay).
    pub fn clear_primvars(&mut self) {
        self.primvars.clear();
    }
    /// The primvar named `name`.
    pub fn primvar(&self, name: &str) -> Option<&crate::Primvar> {
        self.primvars.iter().find(|p| p.name == name)
    }
    /// Sets the face-varying option (how face-varying data is interpolated).
    pub fn set_fvar_option(&mut self, fvar: crate::FVarLinearInterpolation) {
        self.options.fvar = fvar;
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
    /// The half-edges of face `f` in order, from its first ([`Mesh::face_halfedge`]): side `k`
    /// starts at the face's corner `k`.
    pub fn face_halfedges(&self, f: FaceId) -> impl Iterator<Item = HalfedgeId> + '_ {
        let first = self.face_halfedge(f);
        std::iter::successors(Some(first), move |&h| Some(self.next(h))).take(self.face_size(f))
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
    /// `true` if the surface is closed: no boundary edge and no hole, so its back side can be
    /// seen from nowhere outside it.
    pub fn is_closed(&self) -> bool {
        self.edges().all(|e| !self.is_boundary_edge(e)) && self.faces().all(|f| !self.is_hole(f))
    }

    // ---- vertices ----

    /// The first outgoing half-edge of `v` in counter-clockwise order (its leading boundary edge
    /// for a boundary vertex), or [`HalfedgeId::NONE`] for an isolated vertex.
    #[inline]
    pub fn vertex_halfedge(&self, v: VertexId) -> HalfedgeId {
        self.vertex_out[v.idx()]
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
    /// The face normal of `f` (Newell's method relative to a corner, [`crate::newell_normal`]),
    /// normalised; zero for a degenerate face.
    pub fn face_normal(&self, f: FaceId) -> Vec3 {
        crate::newell_normal(
            self.face_vertices(f)
                .iter()
                .map(|v| self.positions[v.idx()]),
        )
    }
    /// The centroid of face `f`.
    pub fn face_centroid(&self, f: FaceId) -> Vec3 {
        let vs = self.face_vertices(f);
        vs.iter().map(|v| self.positions[v.idx()]).sum::<Vec3>() / vs.len() as f32
    }
    /// Axis-aligned bounding box `(min, max)` of all vertices.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        crate::point_bounds(self.positions.iter().copied())
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

#[cfg(test)]
mod split_tests;
#[cfg(test)]
mod tests;
