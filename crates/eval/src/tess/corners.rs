//! Each triangle corner's own parameter point, and the face-varying data that needs it.
//!
//! A point shared by two faces (on a cage edge or vertex) has one owner query, in the first
//! face around it; a corner of another face's triangle there is the same point in *its* face,
//! where a face-varying channel may have another value (a UV seam). Those corners are recorded
//! ([`Tessellation::corner_params`]) from where the point lies on the cage: corner `k` of the
//! face for a cage vertex, step `m` of `R` along its side `k` for an edge point, as the face's
//! own sides name them. A channel's value is evaluated once per point, at its owner query, and
//! again in the corner's own face only where the two faces' values differ there (a seam of
//! that channel): elsewhere both faces see one surface.

use subdiv_mesh::{FaceId, FaceVarying, Mesh, VertexId};
use subdiv_rules::LimitMesh;

use super::{Builder, NONE, Tessellation};
use crate::{Domain, EvalError, Evaluator, Query, UvSample};

/// Where a point that faces share lies on the cage.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OnCage {
    /// At a cage vertex.
    Vertex(u32),
    /// Inside a cage edge.
    Edge(u32),
}

/// A triangle corner whose vertex another face owns (on a shared cage edge or vertex).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForeignCorner {
    /// The corner (an index into the surface's face indices).
    pub corner: u32,
    /// Its own face (the triangle's).
    pub face: u32,
    /// Its parameter point in that face.
    pub uv: [f64; 2],
    /// Where the point lies on the cage.
    pub on: OnCage,
}

impl Builder<'_> {
    /// Every corner of face `faces[i]`'s triangles (corners `corners[i]..corners[i + 1]`)
    /// whose point another face owns, ascending.
    pub(super) fn foreign_corners(&self, faces: &[FaceId], corners: &[u32]) -> Vec<ForeignCorner> {
        let mesh = self.mesh;
        // Each edge point's edge and step along its half-edge 0.
        let mut point_edge = vec![(NONE, 0u32); self.points.len()];
        for e in mesh.edges() {
            let first = self.edge_first[e.idx()];
            if first != NONE {
                for m in 1..self.rate[e.idx()] {
                    point_edge[(first + m - 1) as usize] = (e.0, m);
                }
            }
        }
        let mut out = Vec::new();
        for (i, &f) in faces.iter().enumerate() {
            let domain = Domain::of(self.scheme, mesh.face_size(f));
            let hs: Vec<_> = mesh.face_halfedges(f).collect();
            for c in corners[i]..corners[i + 1] {
                let p = self.tris[c as usize] as usize;
                if self.points[p].face == f.0 {
                    continue;
                }
                let v = self.point_vertex[p];
                let (uv, on) = if v != NONE {
                    let k = hs.iter().position(|&h| mesh.from(h).0 == v);
                    (domain.corner(k.unwrap_or_default()), OnCage::Vertex(v))
                } else {
                    let (e, m) = point_edge[p];
                    let k = hs.iter().position(|h| h.edge().0 == e).unwrap_or_default();
                    let r = self.rate[e as usize];
                    let along = if hs[k] == hs[k].edge().halfedge(0) {
                        m
                    } else {
                        r - m
                    };
                    let t = f64::from(along) / f64::from(r);
                    (domain.edge_point(k, t), OnCage::Edge(e))
                };
                out.push(ForeignCorner {
                    corner: c,
                    face: f.0,
                    uv,
                    on,
                });
            }
        }
        out
    }
}

impl Tessellation {
    /// The parameter point of triangle corner `c` in its own face (where it differs from its
    /// vertex's, on a cage edge or vertex shared with the owner face, from
    /// [`Tessellation::corner_params`]).
    pub fn corner_param(&self, c: usize) -> (u32, [f64; 2]) {
        match self
            .corner_params
            .binary_search_by_key(&(c as u32), |x| x.corner)
        {
            Ok(i) => (self.corner_params[i].face, self.corner_params[i].uv),
            Err(_) => self.params[self.surface.face_indices()[c] as usize],
        }
    }
}

/// Whether faces `g` and `f` have the same face-varying value (index) at `on`: at a vertex, the
/// same value there; on an edge, the same at both ends (no seam between them).
fn same_value(mesh: &Mesh, fv: &FaceVarying, g: FaceId, f: FaceId, on: OnCage) -> bool {
    let (offsets, _) = mesh.face_lists();
    let value = |face: FaceId, v: VertexId| {
        let k = mesh.face_vertices(face).iter().position(|&w| w == v)?;
        fv.indices.get(offsets[face.idx()] as usize + k).copied()
    };
    let same = |v: VertexId| matches!((value(g, v), value(f, v)), (Some(a), Some(b)) if a == b);
    match on {
        OnCage::Vertex(v) => same(VertexId(v)),
        OnCage::Edge(e) => mesh
            .edge_vertices(subdiv_mesh::EdgeId(e))
            .iter()
            .all(|&v| same(v)),
    }
}

/// Distinct face-varying values and the value of every corner.
pub(crate) type CornerValues = (Vec<[f32; 2]>, Vec<u32>);

/// The face-varying values of `eval`'s cage on `t` (a tessellation of a cage of the same
/// topology): one per point, at its owner query, and one per corner on a seam of the channel,
/// in the corner's own face; `None` when the cage has none.
pub(crate) fn corner_values(
    eval: &Evaluator<'_>,
    t: &Tessellation,
) -> Result<Option<CornerValues>, EvalError> {
    let (mesh, Some(fv)) = (eval.mesh(), eval.mesh().uv()) else {
        return Ok(None);
    };
    let idx = t.surface.face_indices();
    let on_seam: Vec<&ForeignCorner> = t
        .corner_params
        .iter()
        .filter(|c| {
            let owner = t.params[idx[c.corner as usize] as usize].0;
            !same_value(mesh, fv, FaceId(owner), FaceId(c.face), c.on)
        })
        .collect();
    let queries: Vec<Query> = (t.params.iter().map(|&(f, [u, v])| Query::new(f, u, v)))
        .chain(on_seam.iter().map(|c| Query::new(c.face, c.uv[0], c.uv[1])))
        .collect();
    let mut samples = vec![UvSample::default(); queries.len()];
    if !eval.evaluate_uv_many(&queries, &mut samples)? {
        return Ok(None);
    }
    let values = samples.iter().map(|s| s.uv.as_vec2().to_array()).collect();
    let mut indices = idx.to_vec();
    for (j, c) in on_seam.iter().enumerate() {
        indices[c.corner as usize] = (t.params.len() + j) as u32;
    }
    Ok(Some((values, indices)))
}

/// Writes the cage's UVs (if it has any) onto `t`'s surface.
pub(super) fn write_uvs(eval: &Evaluator<'_>, t: &mut Tessellation) -> Result<(), EvalError> {
    if let Some((values, indices)) = corner_values(eval, t)? {
        set_uvs(&mut t.surface, values, indices)?;
    }
    Ok(())
}

fn set_uvs(surface: &mut LimitMesh, values: Vec<[f32; 2]>, idx: Vec<u32>) -> Result<(), EvalError> {
    surface
        .set_uvs(values, idx)
        .map_err(|e| EvalError::Internal(e.to_string()))
}
