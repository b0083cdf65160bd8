//! The parallel driver for Loop: every cage triangle on its own worker's slates, results placed
//! by the [`TriLayout`].

use std::cell::Cell;

use glam::Vec3A;
use rayon::prelude::*;
use subdiv_mesh::Mesh;
use subdiv_rules::{
    Depth, LimitMesh, MAX_DEPTH, RulesError, Scheme, check_doubled_triangles, tessellate_uniform,
};

use super::layout::{TriLayout, TriPatch, interior_offset};
use super::limit::LimitScratch;
use super::worker::{CornerNeed, TriWorker};
use crate::tessellate::{SharedOut, SlateError};

/// Tessellates the Loop limit surface of `mesh` (triangles only) uniformly at `depth` with the
/// triangular slates: every triangle of the level-`depth` refinement, with the exact limit points
/// and limit normals as vertices. Runs on the current rayon pool; the output is bit-identical
/// for any thread count.
///
/// ```
/// use subdiv_mesh::{parse_obj, Mesh};
/// let tet = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
/// let mesh = Mesh::from_soup(&parse_obj(tet)?)?;
/// let t = subdiv_slate::tessellate_tri(&mesh, 3).unwrap();
/// assert_eq!(t.num_faces(), 4 * 64);
/// assert_eq!(t.positions().len(), 4 * 64 / 2 + 2);
/// # Ok::<(), subdiv_mesh::MeshError>(())
/// ```
pub fn tessellate_tri(mesh: &Mesh, depth: Depth) -> Result<LimitMesh, SlateError> {
    check_loop_cage(mesh)?;
    if depth == 0 {
        // The cage's own limit points.
        let mut out = tessellate_uniform(mesh, Scheme::Loop, 0)?;
        // The cage vertices on seams, the same bits in every copy (as at any depth).
        subdiv_rules::SeamCurves::new(mesh).write_uniform(mesh, 0, 0, out.positions_mut());
        return Ok(out);
    }
    // Refuse before allocating: beyond the slates, this machine's memory or `MAX_POINTS`.
    crate::size::check_uniform_size(mesh, Scheme::Loop, depth)?;
    let layout = TriLayout::new(mesh, depth)?;
    let mut out = LimitMesh::default();
    tessellate_tri_layout_into(mesh, &layout, &mut out)?;
    Ok(out)
}

/// What every Loop path refuses: non-triangles, doubled triangles, huge coordinates.
pub(crate) fn check_loop_cage(mesh: &Mesh) -> Result<(), RulesError> {
    subdiv_rules::check_coordinates(mesh)?;
    mesh.check_triangles()?;
    check_doubled_triangles(mesh)
}

/// [`tessellate_tri`] with a precomputed layout into a reused output (buffers are resized, not
/// reallocated, when the sizes match).
///
/// The triangles (`face_indices`, `face_offsets`) are a function of the layout alone: written
/// once per layout and output, kept by the calls that follow with the same layout (positions,
/// normals, one-sided corner normals and UVs are written every call), as in
/// [`crate::tessellate_layout_into`]: [`LimitMesh::topology_written`] says whether this call
/// wrote them.
pub fn tessellate_tri_layout_into(
    mesh: &Mesh,
    layout: &TriLayout,
    result: &mut LimitMesh,
) -> Result<(), SlateError> {
    let depth = layout.depth;
    // The topology was checked with the layout; the positions may have moved since.
    subdiv_rules::check_coordinates(mesh)?;
    if depth == 0 || depth > MAX_DEPTH {
        return Err(SlateError::TooDeep {
            depth,
            max: MAX_DEPTH,
        });
    }
    let n = 1u32 << depth;
    let np = layout.num_points();
    let per_patch = (n * n) as usize;
    let tris_of = |p: &TriPatch| if p.visible { per_patch } else { 0 };
    let total: usize = layout.patches.iter().map(tris_of).sum();
    // The triangles and their offsets depend on the layout alone: written once per layout,
    // kept by the calls that follow into the same output.
    let w = result.write_keyed(layout.key.0, np, total, 3)?;
    for &v in &layout.isolated {
        w.positions[v.idx()] = mesh.position(v).to_array();
        w.normals[v.idx()] = [0.0; 3];
    }
    let out = SharedOut {
        pos: w.positions.as_mut_ptr(),
        nrm: w.normals.as_mut_ptr(),
        len: np,
    };
    let write_faces = w.faces.is_some();
    // One chunk of the index buffer per patch (empty ones where the triangles are kept).
    let mut chunks: Vec<&mut [u32]> = Vec::with_capacity(layout.patches.len());
    let mut rest: &mut [u32] = w.faces.unwrap_or_default();
    for p in &layout.patches {
        let (a, b) = rest.split_at_mut(if write_faces { tris_of(p) * 3 } else { 0 });
        chunks.push(a);
        rest = b;
    }
    let sided: Vec<Vec<(u32, [f32; 3])>> = layout
        .patches
        .par_iter()
        .zip(chunks.into_par_iter())
        .with_min_len(16)
        .map_init(tri_thread_worker, |w, (p, tris)| {
            let (wk, scratch) = &mut **w;
            run_patch(wk, scratch, mesh, layout, p, depth, &out, tris)
        })
        .collect();
    let mut start = 0u32;
    result.write_corner_normals(layout.patches.iter().zip(sided).flat_map(|(p, slots)| {
        let s = start;
        start += 3 * tris_of(p) as u32;
        slots.into_iter().map(move |(k, nrm)| (s + k, nrm))
    }));
    // Points on seams from their chains: the copies of a non-manifold edge agree to the bit.
    layout.write_seam_points(mesh, result.positions_mut());
    // Face-varying limit values, only for a cage with UVs (`uv.rs`).
    crate::uv::tri_uvs(mesh, layout, result)
}

/// Gathers, subdivides and evaluates one patch; writes the points it owns and its triangles
/// (into `tris`, empty where they are kept), and returns the one-sided normals of its
/// triangles' corners (ascending) at crease points.
#[allow(clippy::too_many_arguments)]
fn run_patch(
    w: &mut TriWorker,
    scratch: &mut LimitScratch,
    mesh: &Mesh,
    layout: &TriLayout,
    p: &TriPatch,
    depth: Depth,
    out: &SharedOut,
    tris: &mut [u32],
) -> Vec<(u32, [f32; 3])> {
    let n = 1u32 << depth;
    w.gather(mesh, layout, p, n);
    for _ in 1..depth {
        w.step();
    }
    // The last step skips what no limit below reads: the ring row beyond a smooth side another
    // patch owns, and of a fast corner whose limit this patch does not evaluate (it does not
    // own it) all but the table points of the sides it evaluates.
    let rows: [bool; 3] = std::array::from_fn(|c| p.sides[c].owned || !w.sides[c].smooth);
    let corners = std::array::from_fn(|c| {
        if p.corner_owned[c] {
            CornerNeed::Ring
        } else if rows[c] || rows[(c + 2) % 3] {
            CornerNeed::Table
        } else {
            CornerNeed::Nothing
        }
    });
    w.step_with(rows, corners);
    let visible = p.visible;
    let mut sided: Vec<(u32, u32, Vec3A)> = Vec::new();
    for c in 0..3 {
        if p.corner_owned[c] || (visible && !w.corners[c].fast) {
            let (pos, nrm, side) = w.limit_corner(scratch, c);
            if p.corner_owned[c] {
                out.write(p.corners[c], pos, nrm);
            }
            if let (true, Some(s)) = (visible, side) {
                let (i, j) = TriWorker::local(n, c, 0, 0);
                sided.push((i as u32, j as u32, s));
            }
        }
    }
    for c in 0..3 {
        let side = p.sides[c];
        if !(side.owned || (visible && !w.sides[c].smooth)) {
            continue;
        }
        if w.sides[c].smooth {
            // Smooth: no one-sided normals; only the owner gets here.
            w.limit_smooth_side(c, |a, pos, nrm| out.write(side.id(n, a), pos, nrm));
            continue;
        }
        for a in 1..n {
            let (pos, nrm, one) = w.limit_side(scratch, c, a);
            if side.owned {
                out.write(side.id(n, a), pos, nrm);
            }
            if let (true, Some(s)) = (visible, one) {
                let (i, j) = TriWorker::local(n, c, a as i32, 0);
                sided.push((i as u32, j as u32, s));
            }
        }
    }
    if n > 2 {
        let m = ((n - 1) * (n - 2) / 2) as usize;
        let first = p.interior as usize;
        out.check_range(first, m);
        let (mut k, end) = (first, first + m);
        w.limit_interior(|pos, nrm| {
            // Called `m` times in the order of the interior ids (row by row).
            assert!(k < end, "interior points beyond the patch's range");
            // SAFETY: `k` lies in `first..first + m`, this patch's interior range (checked
            // above), which only this patch writes.
            unsafe { out.write_unchecked(k, pos, nrm) };
            k += 1;
        });
        debug_assert_eq!(k, end);
    }
    // Empty where the layout's triangles are kept (or the patch is hidden).
    if !tris.is_empty() {
        write_triangles(p, n, tris, &mut scratch.ids);
    }
    corner_slots(n, &sided)
}

/// Index of the triangle `up(a, b)` = `(a, b), (a + 1, b), (a, b + 1)` in a patch's list; the
/// triangle `down(a, b)` = `(a + 1, b), (a + 1, b + 1), (a, b + 1)` follows it. Rows of `b`,
/// up and down triangles interleaved.
#[inline]
fn up_index(n: u32, a: u32, b: u32) -> u32 {
    2 * n * b - b * b + 2 * a
}

/// Writes the `n^2` triangles of patch `p` (`ids`: scratch for the lattice's output ids).
fn write_triangles(p: &TriPatch, n: u32, tris: &mut [u32], ids: &mut Vec<u32>) {
    let nu = n as usize;
    // `TriLayout::point_id` row by row, its cases laid out: row 0 is corner 0, side 0 and
    // corner 1; row `j` side 2, the interior row and side 1; row `n` corner 2. Row `b` holds
    // `n + 1 - b` points; its inner points are runs of consecutive ids (the sides' ascending or
    // descending, `TriSide::id`).
    ids.resize((nu + 1) * (nu + 2) / 2, 0);
    let run = |out: &mut [u32], first: u32, down: bool| {
        for (k, x) in out.iter_mut().enumerate() {
            *x = if down {
                first - k as u32
            } else {
                first + k as u32
            };
        }
    };
    let (row0, rest) = ids.split_at_mut(nu + 1);
    row0[0] = p.corners[0];
    row0[nu] = p.corners[1];
    if n > 1 {
        run(&mut row0[1..nu], p.sides[0].id(n, 1), p.sides[0].reversed);
    }
    let mut rest = rest;
    for j in 1..n {
        let len = (n - j) as usize;
        let (row, tail) = std::mem::take(&mut rest).split_at_mut(len + 1);
        rest = tail;
        row[0] = p.sides[2].id(n, n - j);
        row[len] = p.sides[1].id(n, j);
        run(&mut row[1..len], p.interior + interior_offset(n, j), false);
    }
    rest[0] = p.corners[2];
    // Row `b` of triangles: `len - 1` (up, down) pairs, then the last up triangle; `lo` and `hi`
    // the first ids of lattice rows `b` and `b + 1`.
    let (mut out, mut lo) = (&mut tris[..], 0);
    for b in 0..nu {
        let len = nu - b;
        let hi = lo + len + 1;
        let (below, above) = (&ids[lo..hi], &ids[hi..hi + len]);
        let (row, tail) = std::mem::take(&mut out).split_at_mut(3 * (2 * len - 1));
        out = tail;
        let (pairs, last) = row.split_at_mut(6 * (len - 1));
        for ((t, d), u) in pairs
            .chunks_exact_mut(6)
            .zip(below.windows(2))
            .zip(above.windows(2))
        {
            t.copy_from_slice(&[d[0], d[1], u[0], d[1], u[1], u[0]]);
        }
        last.copy_from_slice(&[below[len - 1], below[len], above[len - 1]]);
        lo = hi;
    }
    debug_assert!(out.is_empty());
}

/// The triangle corners (index into the patch's `3 n^2` corners) at the lattice points of
/// `sided`, with their normals, ascending.
fn corner_slots(n: u32, sided: &[(u32, u32, Vec3A)]) -> Vec<(u32, [f32; 3])> {
    let mut slots = Vec::new();
    let up = |a: u32, b: u32| a + b < n;
    let down = |a: u32, b: u32| a + b + 1 < n;
    for &(i, j, nrm) in sided {
        // (triangle's lower-left lattice point, down triangle?, corner), where they exist.
        let (i, j) = (i as i64, j as i64);
        let cands = [
            (i, j, false, 0),
            (i - 1, j, false, 1),
            (i, j - 1, false, 2),
            (i - 1, j, true, 0),
            (i - 1, j - 1, true, 1),
            (i, j - 1, true, 2),
        ];
        for (a, b, is_down, corner) in cands {
            if a < 0 || b < 0 {
                continue;
            }
            let (a, b) = (a as u32, b as u32);
            let exists = if is_down { down(a, b) } else { up(a, b) };
            if exists {
                let t = up_index(n, a, b) + is_down as u32;
                slots.push((3 * t + corner, nrm.to_array()));
            }
        }
    }
    slots.sort_unstable_by_key(|&(k, _)| k);
    slots
}

thread_local! {
    static TRI_WORKER: Cell<Option<Box<(TriWorker, LimitScratch)>>> = const { Cell::new(None) };
}

/// A thread's triangular worker, lent by [`tri_thread_worker`] and returned on drop, so that
/// repeated tessellation allocates no slates.
pub(crate) struct TriGuard(Option<Box<(TriWorker, LimitScratch)>>);

impl std::ops::Deref for TriGuard {
    type Target = (TriWorker, LimitScratch);
    fn deref(&self) -> &Self::Target {
        self.0.as_deref().expect("worker present until drop")
    }
}

impl std::ops::DerefMut for TriGuard {
    fn deref_mut(&mut self) -> &mut Self::Target {
        self.0.as_deref_mut().expect("worker present until drop")
    }
}

impl Drop for TriGuard {
    fn drop(&mut self) {
        if let Some(w) = self.0.take() {
            let _ = TRI_WORKER.try_with(|c| c.set(Some(w)));
        }
    }
}

/// The calling thread's triangular worker (a fresh one when the thread's is lent out). Reuse
/// cannot change results: every patch starts with a fresh gather.
pub(crate) fn tri_thread_worker() -> TriGuard {
    let w = TRI_WORKER
        .with(|c| c.take())
        .unwrap_or_else(|| Box::new((TriWorker::new(), LimitScratch::default())));
    TriGuard(Some(w))
}

/// Bytes of slate memory one worker uses for Loop at depth `depth`: two tables and the three
/// corner arrays (fast: two rings of `f32` points; general: a `subdiv-rules` ring of about ten
/// `f64` values per edge), which grow with the largest valence.
pub fn tri_slate_bytes_per_thread(depth: Depth, max_valence: usize) -> usize {
    TriWorker::table_bytes(depth)
        + 3 * max_valence * (2 * std::mem::size_of::<Vec3A>() + 10 * std::mem::size_of::<f64>())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corner_slots_name_every_triangle_at_a_point() {
        let n = 4;
        let mut tris = vec![0u32; 3 * (n * n) as usize];
        let p = TriPatch {
            halfedge: subdiv_mesh::HalfedgeId(0),
            corners: [0, 1, 2],
            corner_owned: [true; 3],
            sides: [super::super::layout::TriSide {
                base: 3,
                reversed: false,
                owned: true,
            }; 3],
            interior: 100,
            visible: true,
            edges: [subdiv_mesh::EdgeId(0); 3],
            beyond: [u32::MAX; 3],
            r0: [0; 3],
        };
        write_triangles(&p, n, &mut tris, &mut Vec::new());
        for j in 0..=n {
            for i in 0..=n - j {
                let slots = corner_slots(n, &[(i, j, Vec3A::X)]);
                let id = TriLayout::point_id(&p, n, i, j).0;
                let want = tris.iter().filter(|&&x| x == id).count();
                // Sides share ids in this synthetic patch; interior points are unique.
                if i > 0 && j > 0 && i + j < n {
                    assert_eq!(slots.len(), want, "({i}, {j})");
                }
                for (k, _) in slots {
                    assert_eq!(tris[k as usize], id, "({i}, {j}) slot {k}");
                }
            }
        }
    }
}
