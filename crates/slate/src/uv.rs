//! Face-varying values (UVs) of a uniform slate tessellation (issue 16).
//!
//! Design (the simple one the issue allows, kept apart from the slates so the position path is
//! untouched): the cage's channel is refined uniformly to the tessellation's depth by
//! `subdiv-rules` (`refine_uniform_levels`, OpenSubdiv's face-varying rules and options) and its
//! face-varying *limit* taken there (`limit_face_varying`, OpenSubdiv's `LimitFaceVarying`), so
//! every output corner gets the limit value of the corner of the level-`depth` face it is: the
//! values of `tessellate_uniform`, seams kept (a corner takes its own face's side). Each
//! output face is found by descending the child-face order of `refine_uniform` from its cage
//! face (Catmull-Clark child `k` of a face starts at its corner `k`, runs along its edge `k`, and
//! holds the quadrant there; Loop children `0..3` at the corners, `3` the middle), which is also
//! how a patch's grid lies on its face (grid corner `(0, 0)` at the face's first corner, `i`
//! along its first edge). Cost: one whole-mesh refinement per call, only for cages with UVs.

use subdiv_mesh::{FaceVarying, Mesh};
use subdiv_rules::{LimitMesh, Scheme, limit_face_varying, refine_uniform_levels};

use crate::layout::PatchLayout;
use crate::tessellate::SlateError;
use crate::tri::TriLayout;

/// The limit face-varying values of the level-`depth` refinement of `mesh` (which has UVs).
fn refined_limit(mesh: &Mesh, scheme: Scheme, depth: u8) -> Result<FaceVarying, SlateError> {
    let refined = refine_uniform_levels(mesh, scheme, depth)?;
    Ok(limit_face_varying(&refined, scheme).unwrap_or_default())
}

/// Sets `out.uvs` and `out.uv_indices` for the Catmull-Clark slate output of `layout` (cleared
/// when the cage has no UVs).
pub(crate) fn quad_uvs(
    mesh: &Mesh,
    layout: &PatchLayout,
    out: &mut LimitMesh,
) -> Result<(), SlateError> {
    out.uvs.clear();
    out.uv_indices.clear();
    if mesh.uv().is_none() {
        return Ok(());
    }
    let depth = layout.depth;
    let lim = refined_limit(mesh, Scheme::CatmullClark, depth)?;
    let (offsets, _) = mesh.face_lists();
    out.uv_indices.reserve(out.face_indices.len());
    let mut k = 0usize;
    for f in mesh.faces() {
        let p = &layout.patches[k];
        // A regular quad is one level-0 patch; any other face one level-1 patch per corner.
        let roots: Vec<(u32, bool)> = if p.level == 0 {
            vec![(f.0, true)]
        } else {
            (0..mesh.face_size(f) as u32)
                .map(|c| (offsets[f.idx()] + c, false))
                .collect()
        };
        for (root, at_cage) in roots {
            let p = &layout.patches[k];
            k += 1;
            if !p.visible {
                continue;
            }
            let n = 1u32 << (depth - p.level);
            for j in 0..n {
                for i in 0..n {
                    let (face, corners) = quad_cell(offsets, root, at_cage, n, i, j);
                    for c in corners {
                        out.uv_indices.push(lim.indices[4 * face as usize + c]);
                    }
                }
            }
        }
    }
    out.uvs = lim.values.iter().map(|v| v.to_array()).collect();
    Ok(())
}

/// The level-`depth` face holding cell `(i, j)` of an `n x n` grid on face `root` (of the cage
/// when `at_cage`, whose children start at `offsets[root]`; otherwise of a quad level, whose
/// children are `4 root + k`), and the corner of that face at each of the cell's corners
/// `(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)`.
fn quad_cell(
    offsets: &[u32],
    root: u32,
    at_cage: bool,
    n: u32,
    i: u32,
    j: u32,
) -> (u32, [usize; 4]) {
    // Doubled coordinates: the cell's centre is odd, so it never lies on a child's border.
    let mut size = 2 * n as i64;
    let (i, j) = (2 * i as i64, 2 * j as i64);
    let mut pts = [
        (i + 1, j + 1),
        (i, j),
        (i + 2, j),
        (i + 2, j + 2),
        (i, j + 2),
    ];
    let mut face = root;
    let mut first = at_cage;
    while size > 2 {
        let half = size / 2;
        let (cx, cy) = pts[0];
        let k = match (cx > half, cy > half) {
            (false, false) => 0,
            (true, false) => 1,
            (true, true) => 2,
            (false, true) => 3,
        };
        // Child `k`'s frame: origin at corner `k`, `s` towards corner `k + 1`, `t` towards
        // corner `k - 1`.
        for (x, y) in &mut pts {
            (*x, *y) = match k {
                0 => (*x, *y),
                1 => (*y, size - *x),
                2 => (size - *x, size - *y),
                _ => (size - *y, *x),
            };
        }
        face = if first {
            offsets[face as usize] + k
        } else {
            4 * face + k
        };
        first = false;
        size = half;
    }
    let corner = |(x, y): (i64, i64)| match (x > 0, y > 0) {
        (false, false) => 0,
        (true, false) => 1,
        (true, true) => 2,
        (false, true) => 3,
    };
    (
        face,
        [
            corner(pts[1]),
            corner(pts[2]),
            corner(pts[3]),
            corner(pts[4]),
        ],
    )
}

/// Sets `out.uvs` and `out.uv_indices` for the Loop slate output of `layout` (cleared when the
/// cage has no UVs).
pub(crate) fn tri_uvs(
    mesh: &Mesh,
    layout: &TriLayout,
    out: &mut LimitMesh,
) -> Result<(), SlateError> {
    out.uvs.clear();
    out.uv_indices.clear();
    if mesh.uv().is_none() {
        return Ok(());
    }
    let depth = layout.depth;
    let lim = refined_limit(mesh, Scheme::Loop, depth)?;
    let n = 1u32 << depth;
    out.uv_indices.reserve(out.face_indices.len());
    for (f, p) in layout.patches.iter().enumerate() {
        if !p.visible {
            continue;
        }
        // The order of the slate's triangles: rows `b`, up and down triangles interleaved.
        for b in 0..n {
            for a in 0..n - b {
                let mut emit = |up: bool| {
                    let (face, corners) = tri_cell(f as u32, n, a, b, up);
                    for c in corners {
                        out.uv_indices.push(lim.indices[3 * face as usize + c]);
                    }
                };
                emit(true);
                if a + 1 < n - b {
                    emit(false);
                }
            }
        }
    }
    out.uvs = lim.values.iter().map(|v| v.to_array()).collect();
    Ok(())
}

/// The level-`depth` face holding triangle `up(a, b)` = `(a, b), (a + 1, b), (a, b + 1)` (or
/// `down(a, b)` = `(a + 1, b), (a + 1, b + 1), (a, b + 1)`) of the lattice of side `n` on cage
/// triangle `root`, and the corner of that face at each of the triangle's corners.
fn tri_cell(root: u32, n: u32, a: u32, b: u32, up: bool) -> (u32, [usize; 3]) {
    // Tripled coordinates: the centroid is the sum of the corners, never on a child's border.
    let (a, b) = (3 * a as i64, 3 * b as i64);
    let corners = if up {
        [(a, b), (a + 3, b), (a, b + 3)]
    } else {
        [(a + 3, b), (a + 3, b + 3), (a, b + 3)]
    };
    let c = corners.iter().fold((0, 0), |s, p| (s.0 + p.0, s.1 + p.1));
    let c = (c.0 / 3, c.1 / 3);
    let mut pts = [c, corners[0], corners[1], corners[2]];
    let mut size = 3 * n as i64;
    let mut face = root;
    while size > 3 {
        let half = size / 2;
        let (cx, cy) = pts[0];
        let k = if cx + cy < half {
            0
        } else if cx > half {
            1
        } else if cy > half {
            2
        } else {
            3
        };
        // Child frames (`refine_uniform`): 0 `[a, ab, ca]`, 1 `[b, bc, ab]`, 2 `[c, ca, bc]`,
        // 3 `[ab, bc, ca]`, with `a = (0, 0)`, `b = (size, 0)`, `c = (0, size)`.
        for (x, y) in &mut pts {
            (*x, *y) = match k {
                0 => (*x, *y),
                1 => (*y, size - *x - *y),
                2 => (size - *x - *y, *x),
                _ => (*y - half + *x, half - *x),
            };
        }
        face = 4 * face + k;
        size = half;
    }
    let corner = |(x, y): (i64, i64)| match (x > 0, y > 0) {
        (false, false) => 0,
        (true, false) => 1,
        _ => 2,
    };
    (face, [corner(pts[1]), corner(pts[2]), corner(pts[3])])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quad_cells_of_one_level_are_the_children() {
        // Depth 1 on a cage quad: cell (i, j) is the child at that corner, and the cell's
        // corner at the quad's corner `k` is the child's corner 0.
        let offsets = [0u32, 4];
        let (f, c) = quad_cell(&offsets, 0, true, 2, 0, 0);
        assert_eq!((f, c), (0, [0, 1, 2, 3]));
        let (f, c) = quad_cell(&offsets, 0, true, 2, 1, 0);
        assert_eq!((f, c), (1, [3, 0, 1, 2]));
        let (f, c) = quad_cell(&offsets, 0, true, 2, 1, 1);
        assert_eq!((f, c), (2, [2, 3, 0, 1]));
        let (f, c) = quad_cell(&offsets, 0, true, 2, 0, 1);
        assert_eq!((f, c), (3, [1, 2, 3, 0]));
        // Two levels below a level-1 face 5: grandchildren 4 (4 * 5 + k) + k'.
        let (f, _) = quad_cell(&offsets, 5, false, 4, 3, 3);
        assert_eq!(f, 4 * (4 * 5 + 2));
    }

    #[test]
    fn tri_cells_of_one_level_are_the_children() {
        // up(0,0) is child 0, up(1,0) child 1, up(0,1) child 2, down(0,0) the middle child 3.
        assert_eq!(tri_cell(0, 2, 0, 0, true), (0, [0, 1, 2]));
        assert_eq!(tri_cell(0, 2, 1, 0, true), (1, [2, 0, 1]));
        assert_eq!(tri_cell(0, 2, 0, 1, true), (2, [1, 2, 0]));
        assert_eq!(tri_cell(0, 2, 0, 0, false), (3, [0, 1, 2]));
    }
}
