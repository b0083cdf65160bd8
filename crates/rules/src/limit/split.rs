//! Derived forms of a [`LimitMesh`]: one normal (and one UV) per vertex, the form glTF and PLY
//! store; that form with every corner's normal on its face's side, the form the renderer draws;
//! and the referenced vertices only.

use std::collections::HashMap;

use super::params::VertexParams;
use super::{LimitChannel, LimitMesh};

/// What makes a vertex of the split form: the vertex, its one-sided normal (bits), its UV
/// index and its corner channels' values (an interned tuple).
type SplitKey = (u32, Option<[u32; 3]>, u32, u32);

impl LimitMesh {
    /// Triangulates the polygons (a fan per polygon) and gives every face corner with a
    /// one-sided normal (creases, corners) a vertex of its own per distinct normal, so that
    /// each vertex has one normal: the result has no one-sided corner normals. Positions and
    /// scalars of the copies are those of the vertex, bit for bit (the surface stays
    /// watertight).
    ///
    /// Without `uvs` (or without face-varying data), every vertex keeps its index (edges and
    /// silhouettes of `self` apply to the result) and the copies follow them; the result has no
    /// UVs. With `uvs` and face-varying data, each vertex is also split by its distinct values
    /// (seams keep their texture coordinates on both sides): the result's vertices are the
    /// distinct (vertex, one-sided normal, UV) of the corners in order of first use, with one
    /// UV each (`uv_indices` equal to `face_indices`).
    pub fn split_sided(&self, uvs: bool) -> LimitMesh {
        // Channels with a value per corner split like UVs (and are dropped without `uvs`).
        let corner_channels: Vec<&LimitChannel> =
            self.channels.iter().filter(|c| !c.per_vertex()).collect();
        let by_uv = uvs && (!self.uv_indices.is_empty() || !corner_channels.is_empty());
        let with_uv = by_uv && !self.uv_indices.is_empty();
        let keep = |v: &[[f32; 3]]| if by_uv { Vec::new() } else { v.to_vec() };
        let mut out = LimitMesh {
            positions: keep(&self.positions),
            normals: keep(&self.normals),
            scalar: self
                .scalar
                .as_ref()
                .map(|(k, v)| (*k, if by_uv { Vec::new() } else { v.clone() })),
            params: self.params.as_ref().map(|p| {
                if by_uv {
                    VertexParams::default()
                } else {
                    p.clone()
                }
            }),
            ..LimitMesh::default()
        };
        // The output's channels, one value per vertex: the input's per-vertex channels (copied
        // when not split by corner), and its per-corner ones when split.
        let mut channels: Vec<(&LimitChannel, LimitChannel)> = self
            .channels
            .iter()
            .filter(|c| c.per_vertex() || by_uv)
            .map(|c| {
                let values = if by_uv || !c.per_vertex() {
                    Vec::new()
                } else {
                    c.values.clone()
                };
                (
                    c,
                    LimitChannel {
                        name: c.name.clone(),
                        width: c.width,
                        values,
                        indices: Vec::new(),
                    },
                )
            })
            .collect();
        // Corner-channel value tuples, interned (the part of the split key they make).
        let mut tuples: HashMap<Vec<u32>, u32> = HashMap::new();
        let mut tuple = Vec::new();
        let mut copies: HashMap<SplitKey, u32> = HashMap::new();
        let mut sided = self.corner_normals.iter().peekable();
        let mut corner = Vec::new();
        let mut triangles = Vec::new();
        for f in 0..self.num_faces() {
            corner.clear();
            for c in self.face_offsets[f]..self.face_offsets[f + 1] {
                let v = self.face_indices[c as usize];
                let n = sided.next_if(|&&(k, _)| k == c).map(|&(_, n)| n);
                if !by_uv && n.is_none() {
                    corner.push(v);
                    continue;
                }
                let uv = if with_uv {
                    self.uv_indices[c as usize]
                } else {
                    0
                };
                let t = if corner_channels.is_empty() || !by_uv {
                    0
                } else {
                    tuple.clear();
                    tuple.extend(corner_channels.iter().map(|ch| ch.indices[c as usize]));
                    let next = tuples.len() as u32;
                    *tuples.entry(tuple.clone()).or_insert(next)
                };
                let key = (v, n.map(|n| n.map(f32::to_bits)), uv, t);
                let id = *copies.entry(key).or_insert_with(|| {
                    out.positions.push(self.positions[v as usize]);
                    out.normals.push(n.unwrap_or(self.normals[v as usize]));
                    if with_uv {
                        out.uvs.push(self.uvs[uv as usize]);
                    }
                    if let (Some((_, dst)), Some((_, src))) = (out.scalar.as_mut(), &self.scalar) {
                        dst.push(src[v as usize]);
                    }
                    for (src, dst) in &mut channels {
                        let value = if src.per_vertex() {
                            src.value(v as usize)
                        } else {
                            src.value(src.indices[c as usize] as usize)
                        };
                        dst.values.extend_from_slice(value);
                    }
                    if let (Some(dst), Some(src)) = (out.params.as_mut(), &self.params) {
                        dst.push_from(src, v as usize);
                    }
                    out.positions.len() as u32 - 1
                });
                corner.push(id);
            }
            for k in 1..corner.len().saturating_sub(1) {
                triangles.extend_from_slice(&[corner[0], corner[k], corner[k + 1]]);
            }
        }
        out.face_offsets = (0..=triangles.len() as u32 / 3).map(|i| i * 3).collect();
        if with_uv {
            out.uv_indices.clone_from(&triangles);
        }
        out.face_indices = triangles;
        out.channels = channels.into_iter().map(|(_, c)| c).collect();
        out
    }
}

impl LimitMesh {
    /// This surface (one normal per vertex, no one-sided corner normals: the
    /// [`LimitMesh::split_sided`] form) with every face corner whose normal points away from its
    /// face given a vertex of its own with the normal reversed; the form the renderer draws.
    /// Positions, scalars and per-vertex channel values of the copies are those of the vertex,
    /// bit for bit; per-corner channels follow their corners; every other
    /// vertex keeps its index, the copies follow them.
    ///
    /// A limit normal can point against the faces around it: OpenSubdiv's normal is the cross
    /// product of the limit tangents as the masks give them, whose sign at a vertex of valence 2
    /// (where the tangents are its two edges) or at a non-manifold vertex follows the order of
    /// the edges, not the faces; and a coarse tessellation of a folded cage has faces turned
    /// against the normals at their corners. Interpolated across such a face, the normal passes
    /// through zero and turns over within the face, and a renderer's two-sided lighting shows a
    /// dot or a sliver of the wrong side there. Whether a corner points away is judged against
    /// its face's area vector (a corner exactly in the face's plane is kept).
    pub fn normals_facing_faces(&self) -> LimitMesh {
        let mut out = LimitMesh {
            positions: self.positions.clone(),
            normals: self.normals.clone(),
            scalar: self.scalar.clone(),
            face_offsets: self.face_offsets.clone(),
            face_indices: self.face_indices.clone(),
            corner_normals: self.corner_normals.clone(),
            uvs: self.uvs.clone(),
            uv_indices: self.uv_indices.clone(),
            // Per-corner channels follow the corners; per-vertex ones gain the copies' values.
            channels: self.channels.clone(),
            ..LimitMesh::default()
        };
        let mut reversed: HashMap<u32, u32> = HashMap::new();
        let position = |v: u32| glam::Vec3::from(self.positions[v as usize]);
        for f in 0..self.num_faces() {
            let corners = self.face_offsets[f] as usize..self.face_offsets[f + 1] as usize;
            let face = &self.face_indices[corners.clone()];
            // The face's area vector (Newell's, as a fan from its first corner).
            let first = position(face[0]);
            let area = face
                .windows(2)
                .skip(1)
                .map(|w| (position(w[0]) - first).cross(position(w[1]) - first))
                .sum::<glam::Vec3>();
            for c in corners {
                let v = self.face_indices[c];
                if glam::Vec3::from(self.normals[v as usize]).dot(area) >= 0.0 {
                    continue;
                }
                let copy = *reversed.entry(v).or_insert_with(|| {
                    let n = self.normals[v as usize];
                    out.positions.push(self.positions[v as usize]);
                    out.normals.push([-n[0], -n[1], -n[2]]);
                    if let Some((_, s)) = out.scalar.as_mut() {
                        s.push(s[v as usize]);
                    }
                    for c in out.channels.iter_mut().filter(|c| c.per_vertex()) {
                        let w = c.width;
                        c.values
                            .extend_from_within(v as usize * w..(v as usize + 1) * w);
                    }
                    out.positions.len() as u32 - 1
                });
                out.face_indices[c] = copy;
            }
        }
        out
    }

    /// The same surface with the vertices no face references left out, the others renumbered
    /// in order of first use (their scalar carried), and the face-varying values no corner
    /// references dropped ([`LimitMesh::compact_uvs`]).
    pub fn referenced_only(&self) -> LimitMesh {
        let mut map = vec![u32::MAX; self.positions.len()];
        let mut out = LimitMesh {
            face_offsets: self.face_offsets.clone(),
            face_indices: Vec::with_capacity(self.face_indices.len()),
            // Corners index the same face list.
            corner_normals: self.corner_normals.clone(),
            uvs: self.uvs.clone(),
            uv_indices: self.uv_indices.clone(),
            scalar: self.scalar.as_ref().map(|(k, _)| (*k, Vec::new())),
            // Per-corner channels follow the corners, which keep their order.
            channels: self
                .channels
                .iter()
                .map(|c| LimitChannel {
                    values: if c.per_vertex() {
                        Vec::new()
                    } else {
                        c.values.clone()
                    },
                    ..c.clone()
                })
                .collect(),
            params: self.params.as_ref().map(|_| VertexParams::default()),
            ..LimitMesh::default()
        };
        for &i in &self.face_indices {
            let m = &mut map[i as usize];
            if *m == u32::MAX {
                *m = out.positions.len() as u32;
                out.positions.push(self.positions[i as usize]);
                out.normals.push(self.normals[i as usize]);
                if let (Some((_, dst)), Some((_, src))) = (out.scalar.as_mut(), &self.scalar) {
                    dst.push(src[i as usize]);
                }
                for (dst, src) in out.channels.iter_mut().zip(&self.channels) {
                    if src.per_vertex() {
                        dst.values.extend_from_slice(src.value(i as usize));
                    }
                }
                if let (Some(dst), Some(src)) = (out.params.as_mut(), &self.params) {
                    dst.push_from(src, i as usize);
                }
            }
            out.face_indices.push(*m);
        }
        out.compact_uvs();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::VertexScalar;

    /// A unit cube of six quads, each corner with its face's normal as one-sided normal.
    fn sided_cube() -> LimitMesh {
        let p: Vec<[f32; 3]> = (0..8)
            .map(|i| [(i & 1) as f32, (i >> 1 & 1) as f32, (i >> 2 & 1) as f32])
            .collect();
        // Six quads, counter-clockwise seen from outside.
        let quads: [u32; 24] = [
            0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5,
        ];
        let faces: Vec<&[u32]> = quads.chunks(4).collect();
        let idx = quads.to_vec();
        let offsets = (0..=6).map(|i| i * 4).collect();
        let mut m = LimitMesh::new(p.clone(), vec![[0.0, 0.0, 1.0]; 8], offsets, idx).unwrap();
        let pv = |i: u32| glam::Vec3::from(p[i as usize]);
        let sided = (0..24u32)
            .map(|c| {
                let f = faces[(c / 4) as usize];
                let n = (pv(f[1]) - pv(f[0])).cross(pv(f[2]) - pv(f[1])).normalize();
                (c, n.to_array())
            })
            .collect();
        m.set_corner_normals(sided).unwrap();
        m.set_scalar(VertexScalar::Depth, vec![1.0; 8]).unwrap();
        m
    }

    #[test]
    fn corners_with_one_sided_normals_get_their_own_vertices() {
        // All 24 corners are split; corners sharing a vertex and a normal share the copy.
        let limit = sided_cube();
        let m = limit.split_sided(false);
        assert_eq!(m.positions().len(), 8 + 24);
        assert_eq!(m.face_indices().len(), 6 * 2 * 3);
        assert!(m.face_indices().iter().all(|&i| i >= 8));
        assert!(m.corner_normals().is_empty());
        for t in m.face_indices().chunks(3) {
            let n: Vec<[f32; 3]> = t.iter().map(|&i| m.normals()[i as usize]).collect();
            assert!(n[0] == n[1] && n[1] == n[2], "{n:?}");
            for &i in t {
                assert!(limit.positions().contains(&m.positions()[i as usize]));
            }
        }
        assert_eq!(m.scalar().map(|(_, s)| s.len()), Some(m.positions().len()));
        // Without one-sided normals nothing is split.
        let mut flat = limit.clone();
        flat.set_corner_normals(Vec::new()).unwrap();
        assert_eq!(flat.split_sided(false).positions().len(), 8);
    }

    #[test]
    fn with_uvs_each_distinct_corner_is_a_vertex() {
        let mut limit = sided_cube();
        // One UV per face: every corner is a distinct (vertex, normal, UV).
        let uvs = (0..6).map(|f| [f as f32, 0.0]).collect();
        let idx = (0..24).map(|c| c / 4).collect();
        limit.set_uvs(uvs, idx).unwrap();
        let m = limit.split_sided(true);
        assert_eq!(m.positions().len(), 24);
        assert_eq!(m.uvs().len(), 24);
        assert_eq!(m.uv_indices(), m.face_indices());
        assert_eq!(m.uvs()[m.face_indices()[6] as usize], [1.0, 0.0]);
        // Without `uvs` the face-varying data is left out.
        assert!(limit.split_sided(false).uvs().is_empty());
    }

    #[test]
    fn corners_pointing_away_from_their_face_get_the_reversed_normal() {
        // Two triangles of the z = 0 plane, counter-clockwise seen from +z (area along +z),
        // sharing the edge 1-2; vertex 1's normal points down.
        let up = [0.0, 0.0, 1.0];
        let mut m = LimitMesh::from_triangles(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [1.0, 1.0, 0.0],
            ],
            vec![up, [0.0, 0.6, -0.8], up, up],
            vec![0, 1, 2, 2, 1, 3],
        )
        .unwrap();
        m.set_scalar(VertexScalar::Depth, vec![0.0, 1.0, 2.0, 3.0])
            .unwrap();
        let d = m.normals_facing_faces();
        // One copy of vertex 1, used by both triangles, its normal reversed; the rest kept.
        assert_eq!(d.positions().len(), 5);
        assert_eq!(d.positions()[4], m.positions()[1]);
        assert_eq!(d.normals()[4], [-0.0, -0.6, 0.8]);
        assert_eq!(d.face_indices(), [0, 4, 2, 2, 4, 3]);
        assert_eq!(d.scalar().unwrap().1[4], 1.0);
        assert_eq!(&d.normals()[..4], m.normals());
        d.check().unwrap();
        // Wound the other way (area along -z) with the normals along -z, vertex 1's normal is
        // on its faces' side: nothing changes.
        let flipped = LimitMesh::from_triangles(
            m.positions().to_vec(),
            vec![
                [0.0, 0.0, -1.0],
                [0.0, 0.6, -0.8],
                [0.0, 0.0, -1.0],
                [0.0, 0.0, -1.0],
            ],
            vec![0, 2, 1, 2, 3, 1],
        )
        .unwrap();
        assert_eq!(flipped.normals_facing_faces(), flipped);
    }

    #[test]
    fn referenced_only_keeps_used_vertices_in_first_use_order() {
        let p = |x: f32| [x, 0.0, 0.0];
        let mut m = LimitMesh::from_triangles(
            vec![p(0.0), p(1.0), p(2.0), p(3.0), p(4.0)],
            vec![p(10.0), p(11.0), p(12.0), p(13.0), p(14.0)],
            vec![3, 1, 4, 4, 1, 3],
        )
        .unwrap();
        m.set_scalar(VertexScalar::Depth, vec![0.0, 1.0, 2.0, 3.0, 4.0])
            .unwrap();
        m.set_uvs(vec![[0.0; 2], [1.0; 2]], vec![1; 6]).unwrap();
        let r = m.referenced_only();
        assert_eq!(r.positions(), [p(3.0), p(1.0), p(4.0)]);
        assert_eq!(r.normals(), [p(13.0), p(11.0), p(14.0)]);
        assert_eq!(r.face_indices(), [0, 1, 2, 2, 1, 0]);
        assert_eq!(
            r.scalar(),
            Some((VertexScalar::Depth, &[3.0, 1.0, 4.0][..]))
        );
        assert_eq!((r.uvs(), r.uv_indices()), (&[[1.0; 2]][..], &[0; 6][..]));
        r.check().unwrap();
    }
}
