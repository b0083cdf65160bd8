//! Copies of a mesh side by side ([`Mesh::instanced`]): every property array repeated, the
//! handles of copy `k` offset by `k` times the mesh's counts, so each copy is numbered and
//! refined exactly as the mesh itself.

use glam::Vec3;

use super::Mesh;
use crate::error::MeshError;
use crate::handle::{FaceId, HalfedgeId, VertexId};

impl Mesh {
    /// One copy of the mesh per offset, copy `k` moved by `offsets[k]`: vertices, faces and
    /// half-edges of copy `k` are those of the mesh offset by `k` times their counts, with the
    /// same sharpness, holes, groups, options and face-varying data; the copies share no
    /// vertex. [`MeshError::TooLarge`] when a count would not fit 32 bits, and
    /// [`MeshError::Empty`] for no offsets.
    ///
    /// ```
    /// use subdiv_mesh::{Mesh, parse_obj, glam::Vec3};
    /// let quad = Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")?)?;
    /// let two = quad.instanced(&[Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0)])?;
    /// assert_eq!((two.num_vertices(), two.num_faces()), (8, 2));
    /// assert_eq!(two.positions()[5], Vec3::new(3.0, 0.0, 0.0));
    /// # Ok::<(), subdiv_mesh::MeshError>(())
    /// ```
    pub fn instanced(&self, offsets: &[Vec3]) -> Result<Mesh, MeshError> {
        let n = offsets.len();
        if n == 0 {
            return Err(MeshError::Empty);
        }
        let (nv, nh, nf) = (self.positions.len(), self.he_to.len(), self.face_he.len());
        let corners = self.face_verts.len();
        let uv_values = self.uv.as_ref().map_or(0, |u| u.values.len());
        for (count, what) in [
            (nv, "vertices"),
            (nh, "half-edges"),
            (nf, "faces"),
            (corners, "face corners"),
            (uv_values, "texture coordinates"),
        ] {
            if count.checked_mul(n).is_none_or(|c| c >= u32::MAX as usize) {
                return Err(MeshError::TooLarge {
                    what: format!("{n} copies of {count} {what}"),
                });
            }
        }
        let v = |k: usize, x: VertexId| VertexId(x.0 + (k * nv) as u32);
        let h = |k: usize, x: HalfedgeId| HalfedgeId(x.0 + (k * nh) as u32);
        let f = |k: usize, x: FaceId| {
            if x.is_some() {
                FaceId(x.0 + (k * nf) as u32)
            } else {
                x
            }
        };
        let repeat = |k: usize| k * nv;
        let mut m = Mesh {
            positions: Vec::with_capacity(n * nv),
            vertex_sharpness: self.vertex_sharpness.repeat(n),
            vertex_out: Vec::with_capacity(n * nv),
            he_to: Vec::with_capacity(n * nh),
            he_next: Vec::with_capacity(n * nh),
            he_prev: Vec::with_capacity(n * nh),
            he_face: Vec::with_capacity(n * nh),
            edge_sharpness: self.edge_sharpness.repeat(n),
            face_offsets: Vec::with_capacity(n * nf + 1),
            face_verts: Vec::with_capacity(n * corners),
            face_he: Vec::with_capacity(n * nf),
            face_hole: self.face_hole.repeat(n),
            face_group: self.face_group.repeat(n),
            groups: self.groups.clone(),
            options: self.options,
            uv: None,
            primvars: Vec::new(),
            whole_edges: Default::default(),
            crease_ends: Default::default(),
            fvar_corners: Vec::new(),
        };
        m.face_offsets.push(0);
        for (k, off) in offsets.iter().enumerate() {
            m.positions.extend(self.positions.iter().map(|p| *p + *off));
            m.vertex_out
                .extend(self.vertex_out.iter().map(|&x| h(k, x)));
            m.he_to.extend(self.he_to.iter().map(|&x| v(k, x)));
            m.he_next.extend(self.he_next.iter().map(|&x| h(k, x)));
            m.he_prev.extend(self.he_prev.iter().map(|&x| h(k, x)));
            m.he_face.extend(self.he_face.iter().map(|&x| f(k, x)));
            let base = (k * corners) as u32;
            m.face_offsets
                .extend(self.face_offsets[1..].iter().map(|&o| o + base));
            m.face_verts
                .extend(self.face_verts.iter().map(|&x| v(k, x)));
            m.face_he.extend(self.face_he.iter().map(|&x| h(k, x)));
            for (&vx, e) in &self.whole_edges {
                m.whole_edges.insert(vx + repeat(k) as u32, e.clone());
            }
            for (&vx, ends) in &self.crease_ends {
                m.crease_ends
                    .insert(vx + repeat(k) as u32, ends.map(|x| h(k, x)));
            }
            m.fvar_corners
                .extend(self.fvar_corners.iter().map(|&vx| vx + repeat(k) as u32));
        }
        if let Some(uv) = &self.uv {
            let mut out = crate::FaceVarying {
                values: uv.values.repeat(n),
                indices: Vec::with_capacity(n * uv.indices.len()),
                dependence: uv.dependence.repeat(n),
            };
            for k in 0..n {
                let base = (k * uv_values) as u32;
                out.indices.extend(uv.indices.iter().map(|&i| i + base));
            }
            m.uv = Some(out);
        }
        for p in &self.primvars {
            // A constant primvar is one value for every copy; the others repeat per copy.
            if p.interpolation == crate::PrimvarInterpolation::Constant {
                m.primvars.push(p.clone());
                continue;
            }
            let values = p.num_values() as u32;
            let mut out = crate::Primvar {
                values: p.values.repeat(n),
                indices: Vec::with_capacity(n * p.indices.len()),
                ..p.clone()
            };
            for k in 0..n as u32 {
                out.indices
                    .extend(p.indices.iter().map(|&i| i + k * values));
            }
            m.primvars.push(out);
        }
        Ok(m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse_obj;

    #[test]
    fn copies_are_the_mesh_built_from_the_instanced_soup() {
        // A creased cube with a hole and UVs, built twice: as copies of the mesh, and from the
        // soup instanced. Every array must agree, handle for handle.
        let cube = subdiv_test_support::cube();
        let mut obj = String::from("vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n");
        for p in &cube.positions {
            obj += &format!("v {} {} {}\n", p[0], p[1], p[2]);
        }
        for f in &cube.faces {
            let corners: Vec<String> = f
                .iter()
                .enumerate()
                .map(|(c, v)| format!("{}/{}", v + 1, c % 4 + 1))
                .collect();
            obj += &format!("f {}\n", corners.join(" "));
        }
        obj += "t crease 2/1/0 0 1 2.5\nt corner 1/1/0 5 3\nt hole 1/0/0 2\n";
        let soup = parse_obj(&obj).unwrap();
        let offsets = [
            Vec3::ZERO,
            Vec3::new(3.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, -3.0),
        ];
        let a = Mesh::from_soup(&soup).unwrap().instanced(&offsets).unwrap();
        let b = Mesh::from_soup(&soup.instanced(&offsets)).unwrap();
        assert_eq!(a.positions, b.positions);
        assert_eq!(a.vertex_sharpness, b.vertex_sharpness);
        assert_eq!(a.vertex_out, b.vertex_out);
        assert_eq!(a.he_to, b.he_to);
        assert_eq!(a.he_next, b.he_next);
        assert_eq!(a.he_prev, b.he_prev);
        assert_eq!(a.he_face, b.he_face);
        assert_eq!(a.edge_sharpness, b.edge_sharpness);
        assert_eq!(a.face_offsets, b.face_offsets);
        assert_eq!(a.face_verts, b.face_verts);
        assert_eq!(a.face_he, b.face_he);
        assert_eq!(a.face_hole, b.face_hole);
        // The soup's copies leave the texture coordinates out; the mesh's carry them.
        let (uv, one) = (a.uv.as_ref().unwrap(), Mesh::from_soup(&soup).unwrap());
        let one = one.uv.as_ref().unwrap();
        assert_eq!(uv.values, one.values.repeat(3));
        for (k, chunk) in uv.indices.chunks(one.indices.len()).enumerate() {
            let want: Vec<u32> = one.indices.iter().map(|&i| i + 4 * k as u32).collect();
            assert_eq!(chunk, want);
        }
        assert_eq!(a.num_edges(), 3 * 12);
        assert!(a.edge_sharpnesses().contains(&2.5));
    }

    #[test]
    fn no_copies_is_an_error() {
        let m = Mesh::from_soup(&parse_obj(&subdiv_test_support::cube().obj()).unwrap()).unwrap();
        assert!(matches!(m.instanced(&[]), Err(MeshError::Empty)));
    }
}
