//! The UVs of a slate tessellation kept by its layout ([`crate::PatchLayout`],
//! [`crate::TriLayout`]) for the next call.
//!
//! The face-varying values of a uniform tessellation depend on the cage's topology, its UV
//! channel, sharpness, options and holes, never on its positions: a layout tessellated again
//! (the per-frame steady state, `subdiv bench tessellate`) with those unchanged gets the
//! values of its first call with UVs, bit for bit, instead of refining the channel again. The
//! first call's cage is kept as the key (compared value by value, floats by their bits); a call
//! with a different channel computes its UVs afresh and keeps nothing.

use std::sync::OnceLock;

use subdiv_mesh::{Mesh, SchemeOptions};
use subdiv_rules::LimitMesh;

/// What the values were computed from (floats as bits).
#[derive(Clone, Debug, PartialEq)]
struct UvKey {
    face_offsets: Vec<u32>,
    face_verts: Vec<u32>,
    values: Vec<[u32; 2]>,
    indices: Vec<u32>,
    edge_sharpness: Vec<u32>,
    vertex_sharpness: Vec<u32>,
    holes: Vec<bool>,
    options: SchemeOptions,
}

impl UvKey {
    /// The key of `mesh` (a cage with UVs).
    fn new(mesh: &Mesh) -> UvKey {
        let (offsets, verts) = mesh.face_lists();
        let fv = mesh.uv();
        let bits = |s: &[f32]| s.iter().map(|x| x.to_bits()).collect();
        UvKey {
            face_offsets: offsets.to_vec(),
            face_verts: verts.iter().map(|v| v.0).collect(),
            values: fv.map_or(Vec::new(), |fv| {
                fv.values
                    .iter()
                    .map(|t| [t.x.to_bits(), t.y.to_bits()])
                    .collect()
            }),
            indices: fv.map_or(Vec::new(), |fv| fv.indices.clone()),
            edge_sharpness: bits(mesh.edge_sharpnesses()),
            vertex_sharpness: bits(mesh.vertex_sharpnesses()),
            holes: mesh.holes().to_vec(),
            options: mesh.options(),
        }
    }

    /// Whether `mesh` is the cage this key was made from, but for its positions.
    fn matches(&self, mesh: &Mesh) -> bool {
        let (offsets, verts) = mesh.face_lists();
        let Some(fv) = mesh.uv() else {
            return false;
        };
        let same_bits = |a: &[u32], b: &[f32]| {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| *x == y.to_bits())
        };
        self.options == mesh.options()
            && self.face_offsets == offsets
            && self.face_verts.len() == verts.len()
            && self.face_verts.iter().zip(verts).all(|(a, b)| *a == b.0)
            && self.indices == fv.indices
            && self.values.len() == fv.values.len()
            && self
                .values
                .iter()
                .zip(&fv.values)
                .all(|(a, t)| *a == [t.x.to_bits(), t.y.to_bits()])
            && same_bits(&self.edge_sharpness, mesh.edge_sharpnesses())
            && same_bits(&self.vertex_sharpness, mesh.vertex_sharpnesses())
            && self.holes == mesh.holes()
    }
}

#[derive(Clone, Debug)]
struct Kept {
    key: UvKey,
    uvs: Vec<[f32; 2]>,
    uv_indices: Vec<u32>,
}

/// The UVs of a layout's first tessellation with UVs, for the calls that follow.
#[derive(Clone, Debug, Default)]
pub(crate) struct UvCache(OnceLock<Kept>);

impl UvCache {
    /// Writes the kept UVs into `uvs` and `idx` (empty) when `mesh` is the cage they were
    /// computed for, but for its positions; `false` otherwise.
    pub(crate) fn restore(&self, mesh: &Mesh, uvs: &mut Vec<[f32; 2]>, idx: &mut Vec<u32>) -> bool {
        match self.0.get() {
            Some(k) if k.key.matches(mesh) => {
                uvs.extend_from_slice(&k.uvs);
                idx.extend_from_slice(&k.uv_indices);
                true
            }
            _ => false,
        }
    }

    /// Keeps `out`'s UVs, computed for `mesh`, unless UVs are kept already.
    pub(crate) fn keep(&self, mesh: &Mesh, out: &LimitMesh) {
        if self.0.get().is_none() {
            let _ = self.0.set(Kept {
                key: UvKey::new(mesh),
                uvs: out.uvs().to_vec(),
                uv_indices: out.uv_indices().to_vec(),
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::{
        PatchLayout, TriLayout, tessellate, tessellate_layout_into, tessellate_tri,
        tessellate_tri_layout_into,
    };
    use subdiv_mesh::{Mesh, parse_obj};
    use subdiv_rules::LimitMesh;

    fn cage(name: &str) -> Mesh {
        let path = subdiv_test_support::fixture(&format!("meshes/fvar/{name}.obj"));
        Mesh::from_soup(&parse_obj(&std::fs::read_to_string(path).unwrap()).unwrap()).unwrap()
    }

    /// `m` with its positions scaled and one UV value moved (`uv`), or only the positions.
    fn edited(m: &Mesh, uv: bool) -> Mesh {
        let mut soup = parse_obj(&subdiv_mesh::format_mesh_obj(m)).unwrap();
        for p in &mut soup.positions {
            *p *= 1.5;
        }
        if uv {
            soup.uvs[0].x += 0.25;
        }
        Mesh::from_soup(&soup).unwrap()
    }

    fn uvs(t: &LimitMesh) -> (Vec<[f32; 2]>, Vec<u32>) {
        (t.uvs().to_vec(), t.uv_indices().to_vec())
    }

    #[test]
    fn kept_uvs_are_those_of_a_fresh_tessellation() {
        let cube = cage("cube_uv");
        let layout = PatchLayout::new(&cube, 3).unwrap();
        let mut out = LimitMesh::default();
        for m in [
            cube.clone(),
            edited(&cube, false),
            edited(&cube, true),
            cube.clone(),
        ] {
            tessellate_layout_into(&m, &layout, &mut out).unwrap();
            let fresh = tessellate(&m, 3).unwrap();
            assert!(!fresh.uv_indices().is_empty());
            assert_eq!(uvs(&out), uvs(&fresh));
        }
        let tri = cage("tri_seam");
        let layout = TriLayout::new(&tri, 3).unwrap();
        for m in [
            tri.clone(),
            edited(&tri, false),
            edited(&tri, true),
            tri.clone(),
        ] {
            tessellate_tri_layout_into(&m, &layout, &mut out).unwrap();
            let fresh = tessellate_tri(&m, 3).unwrap();
            assert!(!fresh.uv_indices().is_empty());
            assert_eq!(uvs(&out), uvs(&fresh));
        }
        // A cage without UVs after one with: none.
        let mut plain = cube.clone();
        plain.clear_uv();
        let layout = PatchLayout::new(&cube, 2).unwrap();
        tessellate_layout_into(&cube, &layout, &mut out).unwrap();
        tessellate_layout_into(&plain, &layout, &mut out).unwrap();
        assert!(out.uvs().is_empty() && out.uv_indices().is_empty());
    }
}
