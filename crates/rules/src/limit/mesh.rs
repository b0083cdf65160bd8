//! [`LimitMesh`]: the one output type of every tessellator, with its invariants kept by its
//! methods (the fields are private).

use glam::Vec3;
use subdiv_mesh::ObjData;

use super::params::VertexParams;
use super::topology::{TopologyKey, TopologyStamp};
use crate::OutOfMemory;
use crate::budget::{try_reserve, try_resize};

/// A tessellated limit surface: one limit point and unit normal per vertex, polygons, the
/// one-sided normals of the face corners where the surface has a crease or a corner,
/// face-varying values (UVs) per corner, and optionally one scalar per vertex (the subdivision
/// depth or the Degree of Interest, [`VertexScalar`]).
///
/// Every tessellator writes it (the slate tessellators, push-to-limit, the adaptive frame of
/// `subdiv-stitch`), the exporters write it to files and the renderer draws its
/// [`split_sided`](LimitMesh::split_sided) form.
///
/// Invariants, kept by every method: `normals` and the scalar have one entry per position; the
/// face offsets start at 0, never decrease and end at the number of corners; the one-sided corner
/// normals ascend by corner and name corners that exist; the UV indices are empty or one per
/// corner. Indices given to the checked constructors ([`LimitMesh::new`],
/// [`LimitMesh::set_uvs`]) are in range; the writers of [`LimitMesh::write_keyed`] write
/// indices in range by construction. Any change of the faces forgets which layout wrote them
/// ([`LimitMesh::topology_written`]).
#[derive(Clone, Debug, Default)]
pub struct LimitMesh {
    pub(super) positions: Vec<[f32; 3]>,
    /// Unit limit normals (zero only where the surface is fully degenerate). At a point on a
    /// crease or a corner this is the mean of its sides' normals; the corners there take
    /// theirs from `corner_normals`.
    pub(super) normals: Vec<[f32; 3]>,
    /// Start of each face in `face_indices`, plus a final end offset.
    pub(super) face_offsets: Vec<u32>,
    /// Vertex indices of all faces, counter-clockwise.
    pub(super) face_indices: Vec<u32>,
    /// One-sided unit normals of face corners, ascending by corner (index into
    /// `face_indices`).
    pub(super) corner_normals: Vec<(u32, [f32; 3])>,
    pub(super) uvs: Vec<[f32; 2]>,
    /// The value in `uvs` of every face corner (aligned with `face_indices`), or empty.
    pub(super) uv_indices: Vec<u32>,
    pub(super) scalar: Option<(VertexScalar, Vec<f32>)>,
    /// The cage's primvars on the surface ([`LimitMesh::channels`]).
    pub(super) channels: Vec<super::LimitChannel>,
    /// The parameter point of each vertex, when the tessellator knows it.
    pub(super) params: Option<VertexParams>,
    /// Which layout the faces were written for (bookkeeping, not content: ignored by `==`).
    pub(super) topology: TopologyStamp,
    /// `k > 0`: the face offsets are `0, k, 2k, ..`, written so by [`LimitMesh::write_keyed`] or
    /// [`LimitMesh::write_triangles`] (bookkeeping: ignored by `==`); 0: not known.
    pub(super) uniform_faces: u32,
}

/// What the per-vertex scalar of a [`LimitMesh`] is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VertexScalar {
    /// The subdivision depth of the vertex's patch.
    Depth,
    /// The Degree of Interest.
    Doi,
}

impl VertexScalar {
    /// The name of the glTF vertex attribute that stores it (`_DEPTH`, `_DOI`).
    pub fn gltf_attribute(self) -> &'static str {
        match self {
            VertexScalar::Depth => "_DEPTH",
            VertexScalar::Doi => "_DOI",
        }
    }

    /// The name of the PLY vertex property that stores it (`depth`, `doi`).
    pub fn ply_property(self) -> &'static str {
        match self {
            VertexScalar::Depth => "depth",
            VertexScalar::Doi => "doi",
        }
    }
}

/// Why data given to a [`LimitMesh`] breaks one of its invariants.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("invalid limit mesh: {0}")]
pub struct LimitMeshError(pub String);

impl PartialEq for LimitMesh {
    fn eq(&self, o: &LimitMesh) -> bool {
        // Destructured so that a new field cannot be forgotten here.
        let LimitMesh {
            positions,
            normals,
            face_offsets,
            face_indices,
            corner_normals,
            uvs,
            uv_indices,
            scalar,
            channels,
            params,
            topology: _,
            uniform_faces: _,
        } = self;
        *positions == o.positions
            && *normals == o.normals
            && *face_offsets == o.face_offsets
            && *face_indices == o.face_indices
            && *corner_normals == o.corner_normals
            && *uvs == o.uvs
            && *uv_indices == o.uv_indices
            && *scalar == o.scalar
            && *channels == o.channels
            && *params == o.params
    }
}

/// `Err` naming the first index of `indices` not below `n`. The common case, every index in
/// range, is one vectorised pass (the largest index); only a failure searches.
fn check_range(indices: &[u32], n: usize, what: &str) -> Result<(), LimitMeshError> {
    let largest = indices
        .chunks(4096)
        .map(|c| c.iter().copied().fold(0u32, u32::max))
        .max();
    if largest.is_none_or(|m| (m as usize) < n) {
        return Ok(());
    }
    match indices.iter().find(|&&i| i as usize >= n) {
        Some(i) => Err(LimitMeshError(format!("{what} index {i} for {n} values"))),
        None => Ok(()),
    }
}

/// `Err` unless `sided` ascends by corner and names corners below `corners`.
fn check_sided(sided: &[(u32, [f32; 3])], corners: usize) -> Result<(), LimitMeshError> {
    if sided.windows(2).any(|w| w[0].0 >= w[1].0)
        || sided.last().is_some_and(|&(c, _)| c as usize >= corners)
    {
        return Err(LimitMeshError(format!(
            "corner normals not ascending within {corners} corners"
        )));
    }
    Ok(())
}

/// `Err` unless `uv_indices` is empty or has one entry per corner, each below `values`.
fn check_uvs(uv_indices: &[u32], values: usize, corners: usize) -> Result<(), LimitMeshError> {
    if !uv_indices.is_empty() && uv_indices.len() != corners {
        return Err(LimitMeshError(format!(
            "{} UV indices for {corners} corners",
            uv_indices.len()
        )));
    }
    check_range(uv_indices, values, "UV")
}

/// The buffers a keyed tessellator writes ([`LimitMesh::write_keyed`]).
pub struct KeyedWrite<'a> {
    /// The positions, resized to the vertex count asked for.
    pub positions: &'a mut [[f32; 3]],
    /// The normals, one per position.
    pub normals: &'a mut [[f32; 3]],
    /// The corner indices to write, `None` where the faces of the layout are kept.
    pub faces: Option<&'a mut [u32]>,
}

/// Every buffer of a triangle-list [`LimitMesh`], for a writer that rebuilds it in place
/// ([`LimitMesh::write_triangles`]); the face offsets follow `triangles`.
pub struct TriangleBuffers<'a> {
    /// Positions.
    pub positions: &'a mut Vec<[f32; 3]>,
    /// Normals, one per position.
    pub normals: &'a mut Vec<[f32; 3]>,
    /// Triangle corners, three per triangle, each below the number of positions.
    pub triangles: &'a mut Vec<u32>,
    /// One-sided normals by corner, ascending.
    pub corner_normals: &'a mut Vec<(u32, [f32; 3])>,
    /// Face-varying values.
    pub uvs: &'a mut Vec<[f32; 2]>,
    /// The value of every corner, or empty.
    pub uv_indices: &'a mut Vec<u32>,
    /// The per-vertex scalar, one per position (or empty for none).
    pub scalar: &'a mut Vec<f32>,
}

impl LimitMesh {
    /// A surface of `positions`, `normals` (one per position) and polygons (`face_offsets`:
    /// the start of each face in `face_indices`, plus a final end offset), checked.
    pub fn new(
        positions: Vec<[f32; 3]>,
        normals: Vec<[f32; 3]>,
        face_offsets: Vec<u32>,
        face_indices: Vec<u32>,
    ) -> Result<LimitMesh, LimitMeshError> {
        let mesh = LimitMesh {
            positions,
            normals,
            face_offsets,
            face_indices,
            ..LimitMesh::default()
        };
        mesh.check()?;
        Ok(mesh)
    }

    /// [`LimitMesh::new`] for a triangle list (three corners per triangle).
    pub fn from_triangles(
        positions: Vec<[f32; 3]>,
        normals: Vec<[f32; 3]>,
        triangles: Vec<u32>,
    ) -> Result<LimitMesh, LimitMeshError> {
        if !triangles.len().is_multiple_of(3) {
            return Err(LimitMeshError(format!(
                "{} triangle corners",
                triangles.len()
            )));
        }
        let offsets = (0..=triangles.len() as u32 / 3).map(|i| i * 3).collect();
        LimitMesh::new(positions, normals, offsets, triangles)
    }

    /// Limit positions.
    #[inline]
    pub fn positions(&self) -> &[[f32; 3]] {
        &self.positions
    }
    /// Unit limit normals, one per position (zero only where the surface is fully degenerate).
    /// At a point on a crease or a corner of the limit surface this is the mean of its sides'
    /// normals; the faces there take theirs from [`LimitMesh::corner_normals`].
    #[inline]
    pub fn normals(&self) -> &[[f32; 3]] {
        &self.normals
    }
    /// Number of vertices.
    #[inline]
    pub fn num_vertices(&self) -> usize {
        self.positions.len()
    }
    /// Start of each face in [`LimitMesh::face_indices`], plus a final end offset.
    #[inline]
    pub fn face_offsets(&self) -> &[u32] {
        &self.face_offsets
    }
    /// Vertex indices of all faces, counter-clockwise.
    #[inline]
    pub fn face_indices(&self) -> &[u32] {
        &self.face_indices
    }
    /// One-sided unit normals of face corners, ascending by corner (index into
    /// [`LimitMesh::face_indices`]): the exact limit normal of the corner's face's side at a
    /// point where the limit surface has a crease (sharp, or semi-sharp still sharp at the
    /// limit) or a corner. Every other corner takes its vertex's normal.
    #[inline]
    pub fn corner_normals(&self) -> &[(u32, [f32; 3])] {
        &self.corner_normals
    }
    /// Face-varying values (UVs), when the cage has them: the face-varying *limit* at each
    /// limit point ([`limit_face_varying_exact`](crate::limit_face_varying_exact): OpenSubdiv's
    /// `LimitFaceVarying` once no semi-sharp feature is left), one per side of a seam; see
    /// [`LimitMesh::uv_indices`]. (Refined meshes, e.g. `subdiv refine`, carry refined values
    /// instead: they are not limit surfaces.)
    #[inline]
    pub fn uvs(&self) -> &[[f32; 2]] {
        &self.uvs
    }
    /// The value in [`LimitMesh::uvs`] of every face corner (aligned with
    /// [`LimitMesh::face_indices`]); empty when the cage has no face-varying data.
    #[inline]
    pub fn uv_indices(&self) -> &[u32] {
        &self.uv_indices
    }
    /// The per-vertex scalar and what it is, when one is set.
    #[inline]
    pub fn scalar(&self) -> Option<(VertexScalar, &[f32])> {
        self.scalar.as_ref().map(|(k, v)| (*k, v.as_slice()))
    }

    /// Sets one scalar per vertex (checked: one value per position).
    pub fn set_scalar(
        &mut self,
        kind: VertexScalar,
        values: Vec<f32>,
    ) -> Result<(), LimitMeshError> {
        if values.len() != self.positions.len() {
            return Err(LimitMeshError(format!(
                "{} scalars for {} positions",
                values.len(),
                self.positions.len()
            )));
        }
        self.scalar = Some((kind, values));
        Ok(())
    }

    /// Drops the per-vertex scalar.
    pub fn clear_scalar(&mut self) {
        self.scalar = None;
    }

    /// Sets the one-sided corner normals (checked: ascending, each naming a corner).
    pub fn set_corner_normals(
        &mut self,
        corner_normals: Vec<(u32, [f32; 3])>,
    ) -> Result<(), LimitMeshError> {
        check_sided(&corner_normals, self.face_indices.len())?;
        self.corner_normals = corner_normals;
        Ok(())
    }

    /// Replaces the one-sided corner normals by `sided` (capacity kept), which must ascend
    /// by corner and name corners that exist (asserted: the tessellators produce them so).
    pub fn write_corner_normals(&mut self, sided: impl Iterator<Item = (u32, [f32; 3])>) {
        self.corner_normals.clear();
        self.corner_normals.extend(sided);
        assert!(
            check_sided(&self.corner_normals, self.face_indices.len()).is_ok(),
            "one-sided corner normals must ascend within the corners"
        );
    }

    /// Sets the face-varying values and the value of every corner (checked: one index per
    /// corner, each naming a value; both empty for none).
    pub fn set_uvs(
        &mut self,
        uvs: Vec<[f32; 2]>,
        uv_indices: Vec<u32>,
    ) -> Result<(), LimitMeshError> {
        check_uvs(&uv_indices, uvs.len(), self.face_indices.len())?;
        self.uvs = uvs;
        self.uv_indices = uv_indices;
        Ok(())
    }

    /// Takes the face-varying buffers out (emptied, capacity kept) for a writer that refills
    /// them and hands them back with [`LimitMesh::set_uvs`].
    pub fn take_uvs(&mut self) -> (Vec<[f32; 2]>, Vec<u32>) {
        let (mut uvs, mut idx) = (
            std::mem::take(&mut self.uvs),
            std::mem::take(&mut self.uv_indices),
        );
        uvs.clear();
        idx.clear();
        (uvs, idx)
    }

    /// The positions, to move points in place (the count stays).
    #[inline]
    pub fn positions_mut(&mut self) -> &mut [[f32; 3]] {
        &mut self.positions
    }

    /// Removes every face (and with them the corner normals and UV indices); capacity kept.
    /// The next keyed tessellation into the mesh writes its faces again.
    pub fn clear_faces(&mut self) {
        self.uniform_faces = 0;
        self.face_offsets.clear();
        self.face_indices.clear();
        self.corner_normals.clear();
        self.uv_indices.clear();
        self.channels.clear();
        self.topology = TopologyStamp::default();
    }

    /// For tessellators whose faces are a function of the layout `key` alone, `faces` faces
    /// of `corners` corners each: resizes the vertex buffers to `vertices` (the scalar is
    /// dropped, the corner normals too when the faces change) and hands them out with, unless
    /// the faces written for `key` are still here, the corner index buffer (offsets written)
    /// to fill with indices below `vertices`.
    pub fn write_keyed(
        &mut self,
        key: TopologyKey,
        vertices: usize,
        faces: usize,
        corners: u32,
    ) -> Result<KeyedWrite<'_>, OutOfMemory> {
        let total = faces * corners as usize;
        let keep = self.topology.key() == Some(key)
            && self.face_offsets.len() == faces + 1
            && self.face_indices.len() == total;
        self.scalar = None;
        // Channels are evaluated on a surface once it is written (`push_channel`).
        self.channels.clear();
        self.params = None;
        // Until the faces are written, the mesh holds no layout's faces.
        self.topology = TopologyStamp::default();
        try_resize(&mut self.positions, vertices, [0.0; 3], "limit positions")?;
        try_resize(&mut self.normals, vertices, [0.0; 3], "limit normals")?;
        if !keep {
            self.corner_normals.clear();
            self.uv_indices.clear();
            try_resize(&mut self.face_indices, total, 0, "face indices")?;
            self.face_offsets.clear();
            try_reserve(&mut self.face_offsets, faces + 1, "face offsets")?;
            self.face_offsets
                .extend((0..=faces as u32).map(|i| i * corners));
            self.uniform_faces = corners;
        }
        self.topology = TopologyStamp::new(key, !keep);
        Ok(KeyedWrite {
            positions: &mut self.positions,
            normals: &mut self.normals,
            faces: (!keep).then_some(&mut self.face_indices[..]),
        })
    }

    /// Rebuilds the mesh as a triangle list in place: `write` gets every buffer (capacity kept;
    /// the scalar's, of kind `scalar`, empty when the mesh had none of that kind). Afterwards
    /// the face offsets follow the triangles and every invariant is checked; a mesh that breaks
    /// one is emptied and the error returned.
    pub fn write_triangles<R>(
        &mut self,
        scalar: VertexScalar,
        write: impl FnOnce(&mut TriangleBuffers<'_>) -> R,
    ) -> Result<R, LimitMeshError> {
        let mut values = match self.scalar.take() {
            Some((k, v)) if k == scalar => v,
            _ => Vec::new(),
        };
        self.channels.clear();
        let r = write(&mut TriangleBuffers {
            positions: &mut self.positions,
            normals: &mut self.normals,
            triangles: &mut self.face_indices,
            corner_normals: &mut self.corner_normals,
            uvs: &mut self.uvs,
            uv_indices: &mut self.uv_indices,
            scalar: &mut values,
        });
        self.topology = TopologyStamp::default();
        // Rewritten (capacity kept) unless they are the offsets of as many triangles already:
        // the old faces need not have been triangles.
        let tris = self.face_indices.len() as u32 / 3;
        if !(self.uniform_faces == 3 && self.face_offsets.len() == tris as usize + 1) {
            self.face_offsets.clear();
            self.face_offsets.extend((0..=tris).map(|i| i * 3));
            self.uniform_faces = 3;
        }
        if !values.is_empty() {
            self.scalar = Some((scalar, values));
        }
        match self.check() {
            Ok(()) => Ok(r),
            Err(e) => {
                *self = LimitMesh::default();
                Err(e)
            }
        }
    }

    /// Checks every invariant (see [`LimitMesh`]).
    pub fn check(&self) -> Result<(), LimitMeshError> {
        let n = self.positions.len();
        let corners = self.face_indices.len();
        let bad = |what: String| Err(LimitMeshError(what));
        if self.normals.len() != n {
            return bad(format!("{} normals for {n} positions", self.normals.len()));
        }
        if let Some((_, v)) = &self.scalar
            && v.len() != n
        {
            return bad(format!("{} scalars for {n} positions", v.len()));
        }
        if let Some(p) = &self.params
            && (p.face.len() != n || p.uv.len() != n)
        {
            return bad(format!(
                "{} parameter points for {n} positions",
                p.face.len()
            ));
        }
        let ends_right = self.face_offsets.first() == Some(&0)
            && self.face_offsets.last() == Some(&(corners as u32));
        // Offsets written as `0, k, 2k, ..` ascend by construction.
        let generated = self.uniform_faces > 0
            && self.face_offsets.len() == corners / self.uniform_faces as usize + 1;
        if !(ends_right || self.face_offsets.is_empty() && corners == 0)
            || !generated && self.face_offsets.windows(2).any(|w| w[0] > w[1])
        {
            return bad(format!(
                "face offsets do not cover the {corners} corners in order"
            ));
        }
        check_range(&self.face_indices, n, "vertex")?;
        check_sided(&self.corner_normals, corners)?;
        check_uvs(&self.uv_indices, self.uvs.len(), corners)?;
        for c in &self.channels {
            let ok = if c.per_vertex() {
                c.num_values() == n
            } else {
                c.indices.len() == corners
                    && c.indices.iter().all(|&i| (i as usize) < c.num_values())
            };
            if c.width == 0 || !ok {
                return bad(format!("channel {} does not fit the surface", c.name));
            }
        }
        Ok(())
    }

    /// Whether the last tessellation into this mesh wrote its faces (`true` for a mesh not
    /// written by a keyed tessellator, [`LimitMesh::write_keyed`]): a renderer uploads its
    /// index buffer again when this is `true` and may keep the one it has otherwise.
    #[inline]
    pub fn topology_written(&self) -> bool {
        self.topology.written()
    }

    /// Number of faces.
    #[inline]
    pub fn num_faces(&self) -> usize {
        self.face_offsets.len().saturating_sub(1)
    }
    /// The vertex indices of face `i`.
    #[inline]
    pub fn face(&self, i: usize) -> &[u32] {
        &self.face_indices[self.face_offsets[i] as usize..self.face_offsets[i + 1] as usize]
    }
    /// The normal of face corner `c` (an index into `face_indices`): its one-sided normal
    /// where it has one, its vertex's normal otherwise.
    pub fn corner_normal(&self, c: usize) -> [f32; 3] {
        match self
            .corner_normals
            .binary_search_by_key(&(c as u32), |&(k, _)| k)
        {
            Ok(k) => self.corner_normals[k].1,
            Err(_) => self.normals[self.face_indices[c] as usize],
        }
    }
    /// Triangle list (each polygon as a fan from its first vertex).
    pub fn triangles(&self) -> Vec<u32> {
        let mut t = Vec::with_capacity(self.face_indices.len() * 3);
        for i in 0..self.num_faces() {
            let f = self.face(i);
            for k in 1..f.len() - 1 {
                t.extend_from_slice(&[f[0], f[k], f[k + 1]]);
            }
        }
        t
    }
    /// The distinct polygon edges (for wireframes; no triangulation diagonals).
    pub fn edges(&self) -> Vec<[u32; 2]> {
        let mut e: Vec<[u32; 2]> = Vec::with_capacity(self.face_indices.len());
        for i in 0..self.num_faces() {
            let f = self.face(i);
            for k in 0..f.len() {
                let (a, b) = (f[k], f[(k + 1) % f.len()]);
                e.push([a.min(b), a.max(b)]);
            }
        }
        e.sort_unstable();
        e.dedup();
        e
    }
    /// Axis-aligned bounds `(min, max)`.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| {
                let p = Vec3::from(*p);
                (lo.min(p), hi.max(p))
            },
        )
    }
    /// Drops the values of `uvs` no corner references (renumbering `uv_indices` in order of
    /// first use).
    pub fn compact_uvs(&mut self) {
        let mut map = vec![u32::MAX; self.uvs.len()];
        let mut uvs = Vec::new();
        for i in &mut self.uv_indices {
            let m = &mut map[*i as usize];
            if *m == u32::MAX {
                *m = uvs.len() as u32;
                uvs.push(self.uvs[*i as usize]);
            }
            *i = *m;
        }
        self.uvs = uvs;
    }
    /// A view for [`subdiv_mesh::write_obj`].
    pub fn obj_data(&self) -> ObjData<'_> {
        ObjData {
            positions: &self.positions,
            normals: Some(&self.normals),
            face_offsets: &self.face_offsets,
            face_indices: &self.face_indices,
            corner_normals: &self.corner_normals,
            uvs: &self.uvs,
            uv_indices: &self.uv_indices,
            // OBJ's vertex colours: a display colour of one value per vertex.
            colours: self
                .channel("displayColor")
                .filter(|c| c.per_vertex() && c.width == 3)
                .map(|c| c.values.as_slice()),
        }
    }
}
