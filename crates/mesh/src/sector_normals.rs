//! Per-face-corner normals of a mesh drawn as refined (the DoI scenes): the faces around a
//! vertex fall into sectors separated by sharp edges (and the boundary), and each sector is
//! shaded with its own normal, so creases stay crisp without one-sided limit normals.

use glam::Vec3;

use crate::{HalfedgeId, Mesh, UnionFind, newell_normal};

/// A corner whose normal is further than this from its face's normal (cosine) is shaded with
/// the face normal: 45°, the rule smooth shading of creases used before the tessellators gave
/// one-sided limit normals, kept for meshes drawn as refined (a coarse polygonal corner is a
/// crease there, tagged or not).
const FLAT_COS: f32 = std::f32::consts::FRAC_1_SQRT_2;

/// The corners (index into `mesh.face_lists().1`, ascending) whose normal differs from the
/// vertex normal in `vertex_normals`, with their normal: at a vertex with two or more sectors
/// (bounded by edges of positive sharpness), the sector's normal (its faces' normals weighted
/// by their angle at the vertex); and at any corner whose normal is over 45° from its face's
/// normal, the face normal.
pub fn sector_corner_normals(mesh: &Mesh, vertex_normals: &[Vec3]) -> Vec<(u32, [f32; 3])> {
    let (offsets, verts) = mesh.face_lists();
    let nc = verts.len();
    // The corner at the start of each face half-edge.
    let mut start = vec![u32::MAX; mesh.num_halfedges()];
    let mut face_normal = vec![Vec3::ZERO; mesh.num_faces()];
    let mut weight = vec![0.0f32; nc];
    let pos = mesh.positions();
    for f in mesh.faces() {
        let (s, e) = (offsets[f.idx()] as usize, offsets[f.idx() + 1] as usize);
        let mut h = mesh.face_halfedge(f);
        for c in s..e {
            start[h.idx()] = c as u32;
            h = mesh.next(h);
        }
        let p = |k: usize| pos[verts[k].idx()];
        face_normal[f.idx()] = newell_normal((s..e).map(p));
        for (c, w) in weight.iter_mut().enumerate().take(e).skip(s) {
            let prev = if c == s { e - 1 } else { c - 1 };
            let next = if c + 1 == e { s } else { c + 1 };
            *w = (p(prev) - p(c)).angle_between(p(next) - p(c));
        }
    }
    // Corners of one vertex joined across its smooth interior edges.
    let mut parent = UnionFind::new(nc);
    let mut any_sharp = false;
    for h in (0..mesh.num_halfedges() as u32).map(HalfedgeId) {
        let t = h.twin();
        if start[h.idx()] == u32::MAX || start[t.idx()] == u32::MAX {
            continue;
        }
        if mesh.edge_sharpness(h.edge()) > 0.0 {
            any_sharp = true;
            continue;
        }
        // h runs a -> b in its face, t runs b -> a in the other.
        for (x, y) in [
            (start[h.idx()], start[mesh.next(t).idx()]),
            (start[mesh.next(h).idx()], start[t.idx()]),
        ] {
            parent.union(x as usize, y as usize);
        }
    }
    let face_of = |c: usize| offsets.partition_point(|&o| o as usize <= c) - 1;
    // Sector normals, and how many sectors each vertex has.
    let mut sector = vec![Vec3::ZERO; nc];
    let mut sectors = vec![0u32; mesh.num_vertices()];
    if any_sharp {
        for c in 0..nc {
            let r = parent.find(c);
            if r == c {
                sectors[verts[c].idx()] += 1;
            }
            sector[r] += face_normal[face_of(c)] * weight[c];
        }
    }
    let mut out = Vec::new();
    for f in mesh.faces() {
        let fnrm = face_normal[f.idx()];
        for c in offsets[f.idx()] as usize..offsets[f.idx() + 1] as usize {
            let v = verts[c].idx();
            let mut n = vertex_normals[v];
            let mut own = false;
            if sectors[v] > 1 {
                let s = sector[parent.find(c)].normalize_or_zero();
                if s != Vec3::ZERO {
                    (n, own) = (s, true);
                }
            }
            if fnrm != Vec3::ZERO && n.dot(fnrm) < FLAT_COS {
                (n, own) = (fnrm, true);
            }
            if own {
                out.push((c as u32, n.to_array()));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse_obj;

    /// A tent: two triangles each side of a sharp ridge, 30° slopes.
    fn tent(sharp: bool) -> Mesh {
        let h = 30f32.to_radians().tan();
        let mut s = format!(
            "v 0 0 0\nv 2 0 0\nv 0 1 {h}\nv 2 1 {h}\nv 0 2 0\nv 2 2 0\nf 1 2 4\nf 1 4 3\nf 3 4 6\nf 3 6 5\n"
        );
        if sharp {
            s.push_str("t crease 2/1/0 2 3 10\n");
        }
        Mesh::from_soup(&parse_obj(&s).unwrap()).unwrap()
    }

    #[test]
    fn a_sharp_ridge_splits_into_its_two_planes() {
        let m = tent(true);
        let vn = crate::vertex_normals(&m);
        let c = sector_corner_normals(&m, &vn);
        let (_, verts) = m.face_lists();
        // The ridge vertices (2, 3) have one corner per face: 2 faces each side, 2 vertices,
        // minus the corners of the triangles not touching one of them.
        let ridge: Vec<_> = c
            .iter()
            .filter(|&&(k, _)| verts[k as usize].0 >= 2 && verts[k as usize].0 <= 3)
            .collect();
        assert_eq!(ridge.len(), 6, "{c:?}");
        let (sin, cos) = 30f32.to_radians().sin_cos();
        for &&(k, n) in &ridge {
            let f = if (k as usize) < 6 { 1.0 } else { -1.0 };
            let want = Vec3::new(0.0, -f * sin, cos);
            assert!(
                Vec3::from(n).distance(want) < 1e-5,
                "corner {k}: {n:?} vs {want}"
            );
        }
        // Unmarked, the ridge (30° off each plane) is smooth.
        let m = tent(false);
        let vn = crate::vertex_normals(&m);
        assert!(sector_corner_normals(&m, &vn).is_empty());
    }
}
