//! A polygon soup: the unvalidated input from which a [`Mesh`](crate::Mesh) is built.

use std::collections::HashMap;

use glam::Vec3;

use crate::UnionFind;
use crate::options::SchemeOptions;

mod nonmanifold;
pub use nonmanifold::NonManifold;

/// A crease tag: the edge `a`-`b` gets `sharpness` (>= 10 is infinitely sharp).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CreaseTag {
    /// Endpoint (0-based vertex index).
    pub a: i64,
    /// Endpoint (0-based vertex index).
    pub b: i64,
    /// Sharpness.
    pub sharpness: f32,
    /// 1-based source line, if any.
    pub line: Option<u32>,
}

/// A corner tag: vertex `v` gets `sharpness`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CornerTag {
    /// Vertex (0-based).
    pub v: i64,
    /// Sharpness.
    pub sharpness: f32,
    /// 1-based source line, if any.
    pub line: Option<u32>,
}

/// A hole tag: face `f` is a hole (kept in the topology, never output).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HoleTag {
    /// Face (0-based, in input order).
    pub f: i64,
    /// 1-based source line, if any.
    pub line: Option<u32>,
}

/// Positions, faces and tags as read from a file or made in code.
///
/// Faces are stored compressed: face `i` uses `face_indices[face_offsets[i]..face_offsets[i+1]]`.
/// Indices are signed so that out-of-range input (e.g. a negative OBJ index that resolves below
/// zero) survives until validation reports it.
#[derive(Clone, Debug, Default)]
pub struct PolygonSoup {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Start of each face in `face_indices`, plus a final end offset (empty soups may leave it empty).
    pub face_offsets: Vec<u32>,
    /// Vertex indices of all faces, 0-based.
    pub face_indices: Vec<i64>,
    /// Edge sharpness tags.
    pub creases: Vec<CreaseTag>,
    /// Vertex sharpness tags.
    pub corners: Vec<CornerTag>,
    /// Hole tags.
    pub holes: Vec<HoleTag>,
    /// Scheme options.
    pub options: SchemeOptions,
    /// Group/object names; `face_groups[i]` indexes into this.
    pub groups: Vec<String>,
    /// Group of each face (empty means: all faces in no group).
    pub face_groups: Vec<u32>,
    /// 1-based source line of each vertex (empty when not from a file).
    pub vertex_lines: Vec<u32>,
    /// 1-based source line of each face (empty when not from a file).
    pub face_lines: Vec<u32>,
    /// Tag lines read but not applied, in file order (see [`crate::TagWarning`]).
    pub warnings: Vec<crate::TagWarning>,
    /// `(copy, values)`: the semi-sharp edge sharpness of the whole non-manifold vertex each
    /// copy stands for, set by [`PolygonSoup::split_nonmanifold`]
    /// ([`Mesh::whole_vertex_edges`](crate::Mesh::whole_vertex_edges)).
    pub whole_vertex_edges: Vec<(i64, Vec<f32>)>,
    /// `(copy, [(from, to); 2])`: copies of a non-manifold crease vertex whose ring lacks its
    /// two non-manifold edges, and those edges (leaving other copies), set by
    /// [`PolygonSoup::split_nonmanifold`]
    /// ([`Mesh::crease_ends`](crate::Mesh::crease_ends)).
    pub crease_copies: Vec<(i64, [(i64, i64); 2])>,
    /// Copies of non-manifold vertices whose face-varying values OpenSubdiv keeps in place,
    /// set by [`PolygonSoup::split_nonmanifold`]
    /// ([`Mesh::is_fvar_corner`](crate::Mesh::is_fvar_corner)).
    pub fvar_corners: Vec<i64>,
    /// Face-varying values (OBJ `vt`); see [`PolygonSoup::uv_indices`].
    pub uvs: Vec<glam::Vec2>,
    /// The value of every face corner (aligned with `face_indices`, 0-based, signed so that bad
    /// input survives until validation), or empty when the faces carry no face-varying data.
    pub uv_indices: Vec<i64>,
    /// The primvars beside the positions and the texture coordinates (USD `primvars:*`, OBJ
    /// vertex colours), checked by [`Mesh::from_soup`](crate::Mesh::from_soup).
    pub primvars: Vec<crate::Primvar>,
}

impl PolygonSoup {
    /// A soup from positions and faces given as index lists.
    ///
    /// ```
    /// use subdiv_mesh::{PolygonSoup, Mesh};
    /// use glam::Vec3;
    /// let soup = PolygonSoup::from_faces(
    ///     vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
    ///     &[vec![0, 1, 2, 3]],
    /// );
    /// let mesh = Mesh::from_soup(&soup).unwrap();
    /// assert_eq!(mesh.num_faces(), 1);
    /// ```
    pub fn from_faces<F: AsRef<[u32]>>(positions: Vec<Vec3>, faces: &[F]) -> Self {
        let mut soup = PolygonSoup {
            positions,
            ..Default::default()
        };
        for f in faces {
            soup.push_face(f.as_ref().iter().map(|&i| i as i64));
        }
        soup
    }

    /// Appends a face.
    pub fn push_face(&mut self, indices: impl IntoIterator<Item = i64>) {
        if self.face_offsets.is_empty() {
            self.face_offsets.push(0);
        }
        self.face_indices.extend(indices);
        self.face_offsets.push(self.face_indices.len() as u32);
    }

    /// Number of faces.
    pub fn num_faces(&self) -> usize {
        self.face_offsets.len().saturating_sub(1)
    }

    /// The vertex indices of face `i`.
    pub fn face(&self, i: usize) -> &[i64] {
        &self.face_indices[self.face_offsets[i] as usize..self.face_offsets[i + 1] as usize]
    }

    /// Source line of face `i`, if known.
    pub fn face_line(&self, i: usize) -> Option<u32> {
        self.face_lines.get(i).copied()
    }

    /// Source line of vertex `i`, if known.
    pub fn vertex_line(&self, i: usize) -> Option<u32> {
        self.vertex_lines.get(i).copied()
    }
}

impl PolygonSoup {
    /// Makes an edge-manifold soup vertex-manifold by giving every extra fan of faces around a
    /// vertex its own copy of that vertex (appended after the existing vertices, so existing
    /// indices keep their meaning). Crease tags follow their edge to the right copy; corner tags
    /// apply to every copy. Returns `(original, copy)` for every vertex created.
    ///
    /// Faces meeting only at a vertex (a bow-tie, two cones touching at their tips) are otherwise
    /// refused by [`Mesh::from_soup`](crate::Mesh::from_soup); after this repair the surface is
    /// open at that point. Out-of-range indices are left for validation to report.
    pub fn split_nonmanifold_vertices(&mut self) -> Vec<(u32, u32)> {
        if self.face_offsets.len() < 2 {
            return Vec::new();
        }
        let mut parent = self.corner_fans();
        let (remap, created) = self.copy_extra_fans(&mut parent);
        if created.is_empty() {
            return created;
        }
        self.retag_copies(&remap, &created);
        self.face_indices = remap;
        created
    }

    /// Union-find over face corners: two corners at the same vertex are in one fan when their
    /// faces share an edge at that vertex. Returns the forest.
    fn corner_fans(&self) -> UnionFind {
        let nc = self.face_indices.len();
        let mut parent = UnionFind::new(nc);
        let mut seen: HashMap<(i64, i64), usize> = HashMap::with_capacity(nc * 2);
        for f in 0..self.num_faces() {
            let s = self.face_offsets[f] as usize;
            let n = self.face_offsets[f + 1] as usize - s;
            for k in 0..n {
                let c = s + k;
                let v = self.face_indices[c];
                for w in [
                    self.face_indices[s + (k + n - 1) % n],
                    self.face_indices[s + (k + 1) % n],
                ] {
                    match seen.get(&(v, w)) {
                        Some(&o) => parent.union(o, c),
                        None => {
                            seen.insert((v, w), c);
                        }
                    }
                }
            }
        }
        parent
    }

    /// The fan holding a vertex's first corner keeps the vertex; every other fan gets a copy,
    /// appended to the positions. Returns the face indices remapped to the copies and the
    /// `(original, copy)` pairs. Out-of-range indices are left alone.
    fn copy_extra_fans(&mut self, parent: &mut UnionFind) -> (Vec<i64>, Vec<(u32, u32)>) {
        let nv = self.positions.len() as i64;
        let mut owner: HashMap<i64, usize> = HashMap::new();
        let mut copy_of_root: HashMap<usize, i64> = HashMap::new();
        let mut created = Vec::new();
        let mut remap: Vec<i64> = self.face_indices.clone();
        for (c, slot) in remap.iter_mut().enumerate() {
            let v = *slot;
            if v < 0 || v >= nv {
                continue;
            }
            let r = parent.find(c);
            let first = *owner.entry(v).or_insert(r);
            if first == r {
                continue;
            }
            let nvid = *copy_of_root.entry(r).or_insert_with(|| {
                let id = self.positions.len() as i64;
                self.positions.push(self.positions[v as usize]);
                if let Some(&l) = self.vertex_lines.get(v as usize) {
                    self.vertex_lines.push(l);
                }
                // A copy carries its vertex's primvar values.
                for p in &mut self.primvars {
                    let per_vertex = matches!(
                        p.interpolation,
                        crate::PrimvarInterpolation::Vertex | crate::PrimvarInterpolation::Varying
                    );
                    if let Some(&i) = p.indices.get(v as usize).filter(|_| per_vertex) {
                        p.indices.push(i);
                    }
                }
                created.push((v as u32, id as u32));
                id
            });
            *slot = nvid;
        }
        (remap, created)
    }

    /// Crease tags follow their edge to the copies that now carry it (`remap` is the new face
    /// indices); corner tags are repeated on every copy of their vertex.
    fn retag_copies(&mut self, remap: &[i64], created: &[(u32, u32)]) {
        let mut edge_map: HashMap<(i64, i64), (i64, i64)> = HashMap::new();
        for f in 0..self.num_faces() {
            let s = self.face_offsets[f] as usize;
            let n = self.face_offsets[f + 1] as usize - s;
            for k in 0..n {
                let (a, b) = (self.face_indices[s + k], self.face_indices[s + (k + 1) % n]);
                let (na, nb) = (remap[s + k], remap[s + (k + 1) % n]);
                edge_map.insert((a, b), (na, nb));
                edge_map.insert((b, a), (nb, na));
            }
        }
        for t in &mut self.creases {
            if let Some(&(a, b)) = edge_map.get(&(t.a, t.b)) {
                t.a = a;
                t.b = b;
            }
        }
        let mut extra = Vec::new();
        for t in &self.corners {
            for &(o, n) in created {
                if t.v == o as i64 {
                    extra.push(CornerTag { v: n as i64, ..*t });
                }
            }
        }
        self.corners.extend(extra);
    }
}

impl PolygonSoup {
    /// Copies of this soup translated by each offset, in one soup (tags, holes and groups carried
    /// over per copy; source lines dropped). Used to build test scenes such as the paper's
    /// 40-instance scene (Fig. 12).
    ///
    /// ```
    /// use subdiv_mesh::{PolygonSoup, Mesh, glam::Vec3};
    /// let quad = PolygonSoup::from_faces(vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y], &[vec![0, 1, 2, 3]]);
    /// let two = quad.instanced(&[Vec3::ZERO, Vec3::new(5.0, 0.0, 0.0)]);
    /// assert_eq!(Mesh::from_soup(&two).unwrap().num_faces(), 2);
    /// ```
    pub fn instanced(&self, offsets: &[glam::Vec3]) -> PolygonSoup {
        let nv = self.positions.len() as i64;
        let nf = self.num_faces() as i64;
        let mut out = PolygonSoup {
            options: self.options,
            groups: self.groups.clone(),
            ..Default::default()
        };
        for (k, off) in offsets.iter().enumerate() {
            let (bv, bf) = (k as i64 * nv, k as i64 * nf);
            out.positions
                .extend(self.positions.iter().map(|p| *p + *off));
            for f in 0..self.num_faces() {
                out.push_face(self.face(f).iter().map(|&i| i + bv));
            }
            out.face_groups.extend_from_slice(&self.face_groups);
            out.creases.extend(self.creases.iter().map(|t| CreaseTag {
                a: t.a + bv,
                b: t.b + bv,
                line: None,
                ..*t
            }));
            out.corners.extend(self.corners.iter().map(|t| CornerTag {
                v: t.v + bv,
                line: None,
                ..*t
            }));
            out.holes.extend(self.holes.iter().map(|t| HoleTag {
                f: t.f + bf,
                line: None,
            }));
            out.crease_copies.extend(
                self.crease_copies
                    .iter()
                    .map(|&(v, e)| (v + bv, e.map(|(a, b)| (a + bv, b + bv)))),
            );
            out.whole_vertex_edges.extend(
                self.whole_vertex_edges
                    .iter()
                    .map(|(v, s)| (v + bv, s.clone())),
            );
            out.fvar_corners
                .extend(self.fvar_corners.iter().map(|v| v + bv));
        }
        out
    }
}
