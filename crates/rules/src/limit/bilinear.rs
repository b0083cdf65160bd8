//! The limit surface of the bilinear scheme (OpenSubdiv's `SCHEME_BILINEAR`): every point of a
//! refinement is its own limit, and the surface is the bilinear patch of each quad of the cage
//! and of each level-1 quad of its other faces, the patches joined with kinks along their edges.
//!
//! Normals are the patches' own. At a corner of a level-N quad inside a patch the patch's
//! derivatives are exactly the quad's two edges there (a bilinear patch restricted to a
//! sub-rectangle is the bilinear patch of that rectangle's corners), so the patch's normal is
//! the quad's corner normal. OpenSubdiv's `PrimvarRefiner::Limit` takes the same differences
//! (its bilinear tangent masks are the vertex's first two edges, those of its first face), so
//! inside a patch the normals agree. A point on the edge or corner of patches has one normal per
//! patch (one-sided corner normals, as on a crease) and their mean as its own.

use glam::DVec3;
use subdiv_mesh::{FaceId, Mesh, VertexId};

use super::{LimitMesh, TopologyStamp};
use crate::Depth;

/// The bilinear patch of every face of the uniform level-`depth` refinement of `cage` (in
/// [`crate::refine_uniform`]'s face order), numbered: cage face `f` for the descendants of a
/// quad of the cage (one patch: its bilinear patch), `cage.num_faces() + k` for the
/// descendants of the `k`-th level-1 quad of the cage's other faces. At depth 0 every face is
/// its own patch.
pub fn bilinear_patches(cage: &Mesh, depth: Depth) -> Vec<u32> {
    let mut patch: Vec<u32> = (0..cage.num_faces() as u32).collect();
    if depth == 0 {
        return patch;
    }
    let mut next = cage.num_faces() as u32;
    patch = cage
        .faces()
        .flat_map(|f| {
            let n = cage.face_size(f);
            let own = (0..n as u32).map(|k| next + k).collect::<Vec<_>>();
            if n == 4 {
                vec![f.0; 4]
            } else {
                next += n as u32;
                own
            }
        })
        .collect();
    for _ in 1..depth {
        // Every face of level 1 and beyond is a quad with four children, in order.
        patch = patch.iter().flat_map(|&p| [p; 4]).collect();
    }
    patch
}

/// The bilinear limit surface of `mesh` (a refinement of a cage) with the positions `pos` and
/// the patch of every face `patch` ([`bilinear_patches`]): the points themselves, the patches'
/// normals, the visible faces (holes left out).
pub(super) fn bilinear_limit(mesh: &Mesh, pos: &[DVec3], patch: &[u32]) -> LimitMesh {
    let n = mesh.num_vertices();
    let positions: Vec<[f32; 3]> = pos.iter().map(|p| p.as_vec3().to_array()).collect();
    let mut normals = vec![[0.0f32; 3]; n];
    // The patch normal at each (vertex, face) of a vertex on two patches or more.
    let mut sided: Vec<(u32, u32, [f32; 3])> = Vec::new();
    let mut around: Vec<(u32, DVec3, FaceId)> = Vec::new();
    for v in mesh.vertices() {
        around.clear();
        for h in mesh.outgoing(v) {
            let f = mesh.face(h);
            // A hole is not part of the surface: its normals count nowhere.
            if !f.is_some() || mesh.is_hole(f) {
                continue;
            }
            // The face's corner at `v`: its edges to the next and the previous corner.
            let p = pos[v.idx()];
            let next = pos[mesh.to(h).idx()];
            let prev = pos[mesh.from(mesh.prev(h)).idx()];
            let c = (next - p).cross(prev - p).normalize_or_zero();
            around.push((patch[f.idx()], c, f));
        }
        let patch_normal = |id: u32| {
            around
                .iter()
                .filter(|a| a.0 == id)
                .map(|a| a.1)
                .sum::<DVec3>()
                .normalize_or_zero()
        };
        let one = around
            .first()
            .is_none_or(|a| around.iter().all(|b| b.0 == a.0));
        if one {
            if let Some(a) = around.first() {
                normals[v.idx()] = patch_normal(a.0).as_vec3().to_array();
            }
            continue;
        }
        let mut sum = DVec3::ZERO;
        for (k, a) in around.iter().enumerate() {
            let pn = patch_normal(a.0);
            if around[..k].iter().all(|b| b.0 != a.0) {
                sum += pn;
            }
            sided.push((v.0, a.2.0, pn.as_vec3().to_array()));
        }
        normals[v.idx()] = sum.normalize_or_zero().as_vec3().to_array();
    }
    sided.sort_unstable_by_key(|&(v, f, _)| (v, f));
    let limit_uv = crate::limit_face_varying(mesh, crate::Scheme::Bilinear);
    let (offsets, _) = mesh.face_lists();
    let mut face_offsets = vec![0u32];
    let mut face_indices = Vec::with_capacity(mesh.face_lists().1.len());
    let mut corner_normals = Vec::new();
    let mut uv_indices = Vec::new();
    for f in mesh.faces().filter(|&f| !mesh.is_hole(f)) {
        if let Some(fv) = &limit_uv {
            let r = offsets[f.idx()] as usize..offsets[f.idx() + 1] as usize;
            uv_indices.extend_from_slice(&fv.indices[r]);
        }
        for &v in mesh.face_vertices(f) {
            let key = (v.0, f.0);
            if let Ok(k) = sided.binary_search_by_key(&key, |&(v, f, _)| (v, f)) {
                corner_normals.push((face_indices.len() as u32, sided[k].2));
            }
            face_indices.push(v.0);
        }
        face_offsets.push(face_indices.len() as u32);
    }
    LimitMesh {
        positions,
        normals,
        face_offsets,
        face_indices,
        corner_normals,
        uvs: limit_uv
            .map(|fv| fv.values.iter().map(|t| t.to_array()).collect())
            .unwrap_or_default(),
        uv_indices,
        scalar: None,
        channels: Vec::new(),
        params: None,
        topology: TopologyStamp::default(),
        uniform_faces: 0,
    }
}

/// Whether `v` of a refinement with patches `patch` lies inside one patch (not on the edge or
/// corner of two): where the bilinear surface is smooth.
pub fn inside_one_patch(mesh: &Mesh, patch: &[u32], v: VertexId) -> bool {
    let mut ids = mesh
        .outgoing(v)
        .map(|h| mesh.face(h))
        .filter(|&f| f.is_some() && !mesh.is_hole(f))
        .map(|f| patch[f.idx()]);
    match ids.next() {
        Some(first) => ids.all(|p| p == first),
        None => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::{PolygonSoup, parse_obj};

    #[test]
    fn patches_follow_quads_and_level1_quads() {
        // A quad next to a triangle.
        let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nf 1 2 3 4\nf 2 5 3\n";
        let m = Mesh::from_soup(&parse_obj(obj).unwrap()).unwrap();
        assert_eq!(bilinear_patches(&m, 0), [0, 1]);
        assert_eq!(bilinear_patches(&m, 1), [0, 0, 0, 0, 2, 3, 4]);
        let l2 = bilinear_patches(&m, 2);
        assert_eq!(l2.len(), 28);
        assert_eq!(l2[16..20], [2; 4]);
    }

    #[test]
    fn a_nonplanar_quad_is_its_bilinear_patch_with_its_normals() {
        // z = x y over the unit square: the bilinear patch of these corners.
        let soup = PolygonSoup::from_faces(
            vec![
                glam::Vec3::new(0.0, 0.0, 0.0),
                glam::Vec3::new(1.0, 0.0, 0.0),
                glam::Vec3::new(1.0, 1.0, 1.0),
                glam::Vec3::new(0.0, 1.0, 0.0),
            ],
            &[vec![0u32, 1, 2, 3]],
        );
        let m = Mesh::from_soup(&soup).unwrap();
        let t = crate::tessellate_uniform(&m, crate::Scheme::Bilinear, 3).unwrap();
        assert_eq!(t.num_faces(), 64);
        for (p, n) in t.positions().iter().zip(t.normals()) {
            let [x, y, z] = p.map(f64::from);
            assert!((z - x * y).abs() < 1e-6, "{p:?}");
            // (1, 0, y) x (0, 1, x) = (-y, -x, 1).
            let want = DVec3::new(-y, -x, 1.0).normalize();
            let got = glam::Vec3::from(*n).as_dvec3();
            assert!(got.dot(want) > 1.0 - 1e-6, "{p:?}: {got} vs {want}");
        }
    }
}
