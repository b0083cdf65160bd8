//! Each triangle corner's own parameter point, and the face-varying data that needs it.
//!
//! A point shared by two faces (on a cage edge or vertex) has one owner query, in the first
//! face around it; a corner of another face's triangle there is the same point in *its* face,
//! where a face-varying channel may have another value (a UV seam). Those corners' own
//! parameter points are recorded ([`Tessellation::corner_params`]) from where the point lies on
//! the cage: corner `k` of the face for a cage vertex, step `m` of `R` along its side `k` for
//! an edge point, as the face's own sides name them.

use std::collections::HashMap;

use subdiv_mesh::FaceId;
use subdiv_rules::LimitMesh;

use super::{Builder, NONE, Tessellation};
use crate::{Domain, EvalError, Evaluator, Query, UvSample};

impl Builder<'_> {
    /// `(corner, its own query)` for every corner of face `faces[i]`'s triangles (corners
    /// `corners[i]..corners[i + 1]`) whose point another face owns, ascending.
    pub(super) fn foreign_corners(&self, faces: &[FaceId], corners: &[u32]) -> Vec<(u32, Query)> {
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
            let mut h = mesh.face_halfedge(f);
            let hs: Vec<_> = (0..mesh.face_size(f))
                .map(|_| {
                    let g = h;
                    h = mesh.next(h);
                    g
                })
                .collect();
            for c in corners[i]..corners[i + 1] {
                let p = self.tris[c as usize] as usize;
                if self.points[p].face == f.0 {
                    continue;
                }
                let v = self.point_vertex[p];
                let [u, w] = if v != NONE {
                    let k = hs.iter().position(|&h| mesh.from(h).0 == v);
                    domain.corner(k.unwrap_or_default())
                } else {
                    let (e, m) = point_edge[p];
                    let k = hs.iter().position(|h| h.edge().0 == e).unwrap_or_default();
                    let r = self.rate[e as usize];
                    let along = if hs[k] == hs[k].edge().halfedge(0) {
                        m
                    } else {
                        r - m
                    };
                    domain.edge_point(k, f64::from(along) / f64::from(r))
                };
                out.push((c, Query::new(f.0, u, w)));
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
            .binary_search_by_key(&(c as u32), |x| x.0)
        {
            Ok(i) => self.corner_params[i].1,
            Err(_) => self.params[self.surface.face_indices()[c] as usize],
        }
    }

    /// [`Tessellation::corner_param`] of every corner, as queries.
    pub fn corner_queries(&self) -> Vec<Query> {
        (0..self.surface.face_indices().len())
            .map(|c| {
                let (f, [u, v]) = self.corner_param(c);
                Query::new(f, u, v)
            })
            .collect()
    }
}

/// Distinct face-varying values and the value of every corner.
pub(crate) type CornerValues = (Vec<[f32; 2]>, Vec<u32>);

/// The face-varying values of `eval`'s cage at `queries` (each corner's own parameter point);
/// `None` when the cage has none.
pub(crate) fn corner_values(
    eval: &Evaluator<'_>,
    queries: &[Query],
) -> Result<Option<CornerValues>, EvalError> {
    let mut samples = vec![UvSample::default(); queries.len()];
    if !eval.evaluate_uv_many(queries, &mut samples)? {
        return Ok(None);
    }
    // Corners at one point of one face have one query, so equal values are equal bits.
    let mut ids: HashMap<[u32; 2], u32> = HashMap::new();
    let (mut values, mut indices) = (Vec::new(), Vec::with_capacity(queries.len()));
    for s in &samples {
        let t = s.uv.as_vec2().to_array();
        let next = values.len() as u32;
        let id = *ids.entry(t.map(f32::to_bits)).or_insert_with(|| {
            values.push(t);
            next
        });
        indices.push(id);
    }
    Ok(Some((values, indices)))
}

/// Writes the cage's UVs (if it has any) onto `surface` at each corner's own parameter point.
pub(super) fn write_uvs(
    eval: &Evaluator<'_>,
    queries: &[Query],
    surface: &mut LimitMesh,
) -> Result<(), EvalError> {
    if let Some((values, indices)) = corner_values(eval, queries)? {
        surface
            .set_uvs(values, indices)
            .map_err(|e| EvalError::Internal(e.to_string()))?;
    }
    Ok(())
}
