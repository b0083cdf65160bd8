//! One triangular patch's whole lattice, for callers that place the points themselves (the
//! adaptive Loop assembly of `subdiv-stitch`): the same gather, steps and limit evaluation as
//! [`super::tessellate_tri`], so every point equals the uniform tessellation's at that depth
//! when this patch is the point's owner in the [`TriLayout`].

use glam::Vec3A;
use subdiv_mesh::Mesh;
use subdiv_rules::{Depth, MAX_DEPTH};

use super::layout::{TriLayout, TriPatch, interior_offset};
use super::tessellate::tri_thread_worker;
use super::worker::TriWorker;

/// Number of lattice points of a patch at depth `depth`: `(n + 1)(n + 2) / 2`, `n = 2^depth`.
#[inline]
pub fn tri_lattice_len(depth: Depth) -> usize {
    let n = 1usize << depth;
    (n + 1) * (n + 2) / 2
}

/// Index of lattice point `(i, j)` (`i + j <= n`) in a patch lattice of side `n`: rows of `j`,
/// row `j` holding the `n + 1 - j` points `i = 0..=n - j`.
#[inline]
pub fn tri_lattice_index(n: u32, i: u32, j: u32) -> u32 {
    (j * (2 * n + 3) - j * j) / 2 + i
}

/// Evaluates patch `p` of `layout` (any layout of `mesh`: only its topology is read) at `depth`
/// (`0..=MAX_DEPTH`): the limit position and normal of every lattice point into `pos` and `nrm`
/// (resized to [`tri_lattice_len`], indexed by [`tri_lattice_index`]), and into `sided` the
/// patch's own one-sided normals at its corners and side points on creases, boundaries and
/// corners (lattice index, normal), ascending.
pub fn tri_patch_lattice(
    mesh: &Mesh,
    layout: &TriLayout,
    p: &TriPatch,
    depth: Depth,
    pos: &mut Vec<[f32; 3]>,
    nrm: &mut Vec<[f32; 3]>,
    sided: &mut Vec<(u32, [f32; 3])>,
) {
    let depth = depth.min(MAX_DEPTH);
    let n = 1u32 << depth;
    let len = tri_lattice_len(depth);
    pos.clear();
    pos.resize(len, [0.0; 3]);
    nrm.clear();
    nrm.resize(len, [0.0; 3]);
    sided.clear();
    let mut guard = tri_thread_worker();
    let (w, scratch) = &mut *guard;
    w.gather(mesh, layout, p, n);
    for _ in 0..depth {
        w.step();
    }
    let mut put = |i: i32, j: i32, q: Vec3A, m: Vec3A, one: Option<Vec3A>| {
        let k = tri_lattice_index(n, i as u32, j as u32);
        pos[k as usize] = q.to_array();
        nrm[k as usize] = m.to_array();
        if let Some(s) = one {
            sided.push((k, s.to_array()));
        }
    };
    for c in 0..3 {
        let (q, m, one) = w.limit_corner(scratch, c);
        let (i, j) = TriWorker::local(n, c, 0, 0);
        put(i, j, q, m, one);
    }
    for c in 0..3 {
        for a in 1..n {
            let (q, m, one) = w.limit_side(scratch, c, a);
            let (i, j) = TriWorker::local(n, c, a as i32, 0);
            put(i, j, q, m, one);
        }
    }
    if n > 2 {
        // `limit_interior` visits the inner points row by row: j = 1..n-1, i = 1..n-j.
        let (mut i, mut j) = (1u32, 1u32);
        w.limit_interior(|q, m| {
            debug_assert!(interior_offset(n, j) < (n - 1) * (n - 2) / 2);
            let k = tri_lattice_index(n, i, j) as usize;
            pos[k] = q.to_array();
            nrm[k] = m.to_array();
            i += 1;
            if i + j >= n {
                (i, j) = (1, j + 1);
            }
        });
    }
    sided.sort_unstable_by_key(|&(k, _)| k);
    // Points on seams from their chains: the copies of a non-manifold edge, in different
    // pieces, at any depth, agree to the bit (as `TriLayout::write_seam_points` in the uniform
    // tessellation).
    let seams = &layout.seams;
    if !seams.is_empty() {
        let hs = [p.halfedge, mesh.next(p.halfedge), mesh.prev(p.halfedge)];
        for (c, &h) in hs.iter().enumerate() {
            for a in 0..n {
                let q = if a == 0 {
                    seams.vertex_point(mesh, mesh.from(h))
                } else {
                    seams.point(mesh, h, a, depth)
                };
                if let Some(q) = q {
                    let (i, j) = TriWorker::local(n, c, a as i32, 0);
                    pos[tri_lattice_index(n, i as u32, j as u32) as usize] = q.to_array();
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tessellate_tri;

    #[test]
    fn owned_points_equal_the_uniform_tessellation_bitwise() {
        // An open fan with a boundary, a crease and an extraordinary vertex.
        let text = "v 0 0 0\nv 1 0 0\nv 0.3 0.95 0.1\nv -0.8 0.6 0.2\nv -0.8 -0.6 0\n\
                    v 0.3 -0.95 0.3\nv 2 1 0\nf 1 2 3\nf 1 3 4\nf 1 4 5\nf 1 5 6\nf 1 6 2\n\
                    f 2 7 3\nt crease 2/1/0 0 2 1.5\n";
        let mesh = Mesh::from_soup(&subdiv_mesh::parse_obj(text).unwrap()).unwrap();
        let layout = TriLayout::new(&mesh, 1).unwrap();
        let (mut pos, mut nrm, mut sided) = (Vec::new(), Vec::new(), Vec::new());
        for depth in 1..=4 {
            let uni = tessellate_tri(&mesh, depth).unwrap();
            let at = TriLayout::new(&mesh, depth).unwrap();
            let n = 1u32 << depth;
            for (p, q) in layout.patches.iter().zip(&at.patches) {
                tri_patch_lattice(&mesh, &layout, p, depth, &mut pos, &mut nrm, &mut sided);
                for j in 0..=n {
                    for i in 0..=n - j {
                        let (id, owned) = TriLayout::point_id(q, n, i, j);
                        let k = tri_lattice_index(n, i, j) as usize;
                        if owned {
                            assert_eq!(pos[k], uni.positions()[id as usize], "({i}, {j})");
                            assert_eq!(nrm[k], uni.normals()[id as usize], "({i}, {j})");
                        } else {
                            let d = glam::Vec3::from(pos[k])
                                - glam::Vec3::from(uni.positions()[id as usize]);
                            assert!(d.length() < 1e-5, "({i}, {j}) {d}");
                        }
                    }
                }
            }
            assert!(sided.windows(2).all(|w| w[0].0 < w[1].0));
        }
        // Depth 0: the corners' limit points, close to the whole-mesh path's.
        let uni = tessellate_tri(&mesh, 0).unwrap();
        for p in &layout.patches {
            tri_patch_lattice(&mesh, &layout, p, 0, &mut pos, &mut nrm, &mut sided);
            assert_eq!(pos.len(), 3);
            for (c, k) in [(0, 0), (1, 1), (2, 2)] {
                let d = glam::Vec3::from(pos[k])
                    - glam::Vec3::from(uni.positions()[p.corners[c] as usize]);
                assert!(d.length() < 1e-5, "corner {c}: {d}");
            }
        }
    }
}
