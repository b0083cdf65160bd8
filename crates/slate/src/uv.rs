//! Face-varying values (UVs) of a uniform slate tessellation.
//!
//! Design (the simple one the issue allows, kept apart from the slates so the position path is
//! untouched): the cage's channel is refined uniformly by `subdiv-rules`
//! (`refine_uniform_levels`, OpenSubdiv's face-varying rules and options) to the
//! tessellation's depth, or deeper while semi-sharp features remain, and its face-varying
//! *limit* taken there (`limit_face_varying`, OpenSubdiv's `LimitFaceVarying`) — see
//! [`LevelUvs`]. Every output corner gets the value of the corner of a face of that level at
//! the same point and inside the same patch, so seams keep both sides. Faces are found by
//! descending the child-face order of `refine_uniform` from the cage face (Catmull-Clark child
//! `k` of a face starts at its corner `k`, runs along its edge `k`, and holds the quadrant
//! there; Loop children `0..3` at the corners, `3` the middle), which is also how a patch's
//! grid lies on its face (grid point `(0, 0)` at the face's first corner, `i` along its first
//! edge). Cost: one whole-mesh refinement per layout, only for cages with UVs: the layout keeps
//! its first call's values ([`cache`]) and later calls with the same topology, UVs, sharpness
//! and options (positions may move) copy them; the no-UV path only clears two empty vectors.

use subdiv_mesh::{FaceId, Mesh};
use subdiv_rules::{
    Depth, LimitMesh, RulesError, Scheme, limit_face_varying, refine_uniform_levels,
    semi_sharp_levels,
};

mod cache;
pub(crate) use cache::UvCache;

use crate::layout::PatchLayout;
use crate::tessellate::SlateError;
use crate::tri::TriLayout;

/// Sets the UVs of the Catmull-Clark slate output of `layout` (cleared
/// when the cage has no UVs).
pub(crate) fn quad_uvs(
    mesh: &Mesh,
    layout: &PatchLayout,
    out: &mut LimitMesh,
) -> Result<(), SlateError> {
    let (mut uvs, mut idx) = out.take_uvs();
    if mesh.uv().is_none() {
        return Ok(());
    }
    if layout.uv_cache.restore(mesh, &mut uvs, &mut idx) {
        out.set_uvs(uvs, idx)?;
        return Ok(());
    }
    let depth = layout.depth;
    let Some(lev) = LevelUvs::new(mesh, Scheme::CatmullClark, depth)? else {
        return Ok(());
    };
    idx.reserve(out.face_indices().len());
    let mut k = 0usize;
    for f in mesh.faces() {
        // A regular quad is one level-0 patch; any other face one level-1 patch per corner.
        let count = if layout.patches[k].level == 0 {
            1
        } else {
            mesh.face_size(f) as u32
        };
        for sub in 0..count {
            let p = &layout.patches[k];
            k += 1;
            if !p.visible {
                continue;
            }
            let e = depth - p.level;
            let n = 1u32 << e;
            for j in 0..n {
                for i in 0..n {
                    for (x, y) in [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)] {
                        idx.push(lev.value_at(p.level, sub, f, x, y, e));
                    }
                }
            }
        }
    }
    out.set_uvs(lev.values, idx)?;
    out.compact_uvs();
    layout.uv_cache.keep(mesh, out);
    Ok(())
}

/// The face-varying limit values of a mesh's uniform refinement at one level, addressed by
/// the grid points of its patches: what the slates and the adaptive assembler
/// (`subdiv-stitch`) give every output corner, whatever the depth of the patch it belongs to.
/// The level is at least the deepest grid looked up and deep enough that no semi-sharp
/// feature is left ([`subdiv_rules::semi_sharp_levels`]); a point of a coarser grid is a
/// vertex there too, and the face-varying limit there does not depend on the level it is taken
/// at once no semi-sharp feature is left, so patches of different depths agree on the values of
/// the points they share (and with `tessellate_uniform`, which takes
/// [`subdiv_rules::limit_face_varying_exact`]).
#[derive(Clone, Debug, Default)]
pub struct LevelUvs {
    level: Depth,
    /// The distinct values.
    pub values: Vec<[f32; 2]>,
    /// The value of every corner of the level-`level` faces.
    indices: Vec<u32>,
    /// The cage's face offsets (its faces' first children, Catmull-Clark).
    offsets: Vec<u32>,
}

impl LevelUvs {
    /// The values of `mesh`'s UVs for grids down to level `level` (in cage terms); `None`
    /// without UVs. Errors when the level-`level` refinement is refused (too many faces).
    pub fn new(mesh: &Mesh, scheme: Scheme, level: Depth) -> Result<Option<LevelUvs>, RulesError> {
        if mesh.uv().is_none() {
            return Ok(None);
        }
        let want = level.max(1);
        let mut level = want.max(semi_sharp_levels(mesh));
        // Refused deeper levels (a high semi-sharpness on a large cage): OpenSubdiv's values
        // at the level asked for instead.
        let refined = match refine_uniform_levels(mesh, scheme, level) {
            Err(_) if level > want => {
                level = want;
                refine_uniform_levels(mesh, scheme, want)?
            }
            r => r?,
        };
        let lim = limit_face_varying(&refined, scheme).unwrap_or_default();
        Ok(Some(LevelUvs {
            level,
            values: lim.values.iter().map(|v| v.to_array()).collect(),
            indices: lim.indices,
            offsets: mesh.face_lists().0.to_vec(),
        }))
    }

    /// The level the values were taken at.
    pub fn level(&self) -> Depth {
        self.level
    }

    /// The value (index into `values`) at grid point `(i, j)` of the `2^e` grid of the
    /// Catmull-Clark patch on cage face `face` (`patch_level` 0: the face itself; 1: its
    /// level-1 quad `sub`), on that patch's side of any seam. `e + patch_level` must not
    /// exceed [`LevelUvs::level`].
    pub fn value_at(
        &self,
        patch_level: u8,
        sub: u32,
        face: FaceId,
        i: u32,
        j: u32,
        e: Depth,
    ) -> u32 {
        let lp = self.level - patch_level;
        debug_assert!(e <= lp, "grid level {e} beyond the values' level {lp}");
        let n = 1u32 << lp;
        let shift = lp.saturating_sub(e);
        let (x, y) = (i << shift, j << shift);
        let (ci, cj) = (x.min(n - 1), y.min(n - 1));
        let cell_corner = match (x > ci, y > cj) {
            (false, false) => 0,
            (true, false) => 1,
            (true, true) => 2,
            (false, true) => 3,
        };
        let (root, at_cage) = if patch_level == 0 {
            (face.0, true)
        } else {
            (self.offsets[face.idx()] + sub, false)
        };
        let (f, corners) = quad_cell(&self.offsets, root, at_cage, n, ci, cj);
        self.indices[4 * f as usize + corners[cell_corner]]
    }

    /// The value at lattice point `(i, j)` (`(0, 0)` at corner 0, `(2^e, 0)` at corner 1,
    /// `(0, 2^e)` at corner 2) of Loop cage triangle `face`, on its side of any seam.
    pub fn tri_value_at(&self, face: FaceId, i: u32, j: u32, e: Depth) -> u32 {
        debug_assert!(e <= self.level, "lattice level {e} beyond {}", self.level);
        let n = 1u32 << self.level;
        let shift = self.level.saturating_sub(e);
        let (x, y) = (i << shift, j << shift);
        // A triangle with the point as a corner: up(x, y) below the far side, else one of the
        // last row's.
        let (a, b, c) = if x + y < n {
            (x, y, 0)
        } else if x > 0 {
            (x - 1, y, 1)
        } else {
            (0, n - 1, 2)
        };
        let (f, corners) = tri_cell(face.0, n, a, b, true);
        self.indices[3 * f as usize + corners[c]]
    }
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

/// Sets the UVs of the Loop slate output of `layout` (cleared when the
/// cage has no UVs).
pub(crate) fn tri_uvs(
    mesh: &Mesh,
    layout: &TriLayout,
    out: &mut LimitMesh,
) -> Result<(), SlateError> {
    let (mut uvs, mut idx) = out.take_uvs();
    if mesh.uv().is_none() {
        return Ok(());
    }
    if layout.uv_cache.restore(mesh, &mut uvs, &mut idx) {
        out.set_uvs(uvs, idx)?;
        return Ok(());
    }
    let depth = layout.depth;
    let Some(lev) = LevelUvs::new(mesh, Scheme::Loop, depth)? else {
        return Ok(());
    };
    let n = 1u32 << depth;
    idx.reserve(out.face_indices().len());
    for (f, p) in mesh.faces().zip(&layout.patches) {
        if !p.visible {
            continue;
        }
        // The order of the slate's triangles: rows `b`, up and down triangles interleaved.
        let mut emit = |pts: [(u32, u32); 3]| {
            for (x, y) in pts {
                idx.push(lev.tri_value_at(f, x, y, depth));
            }
        };
        for b in 0..n {
            for a in 0..n - b {
                emit([(a, b), (a + 1, b), (a, b + 1)]);
                if a + 1 < n - b {
                    emit([(a + 1, b), (a + 1, b + 1), (a, b + 1)]);
                }
            }
        }
    }
    out.set_uvs(lev.values, idx)?;
    out.compact_uvs();
    layout.uv_cache.keep(mesh, out);
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
