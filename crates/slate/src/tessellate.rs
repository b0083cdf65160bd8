//! The parallel driver: every patch on its own worker's slates, results placed by the layout.

use glam::Vec3A;
use rayon::prelude::*;
use subdiv_mesh::Mesh;
use subdiv_rules::{
    Depth, LimitMesh, MAX_DEPTH, OutOfMemory, OutputTooLarge, RulesError, Scheme, limit_surface,
};

use crate::layout::{Patch, PatchLayout};
use crate::pool::thread_worker;
use crate::wide::InteriorOut;
use crate::worker::Worker;

/// Errors of the slate tessellator.
#[derive(Debug, thiserror::Error)]
pub enum SlateError {
    /// The requested depth exceeds what the slates support.
    #[error("depth {depth} exceeds the maximum slate depth {max}")]
    TooDeep {
        /// Requested depth.
        depth: Depth,
        /// Supported maximum.
        max: Depth,
    },
    /// The tessellation would not fit in memory.
    #[error("depth {depth} would produce {points} limit points (limit {MAX_POINTS})")]
    TooLarge {
        /// Requested depth.
        depth: Depth,
        /// Points it would produce.
        points: u64,
    },
    /// The tessellation would not fit in this machine's memory: refused before allocating, with
    /// the size asked for ([`subdiv_rules::budget`]).
    #[error(transparent)]
    OutputTooLarge(#[from] OutputTooLarge),
    /// An output buffer could not be allocated.
    #[error(transparent)]
    OutOfMemory(#[from] OutOfMemory),
    /// The output broke an invariant of [`LimitMesh`] (a tessellator bug, not the cage's).
    #[error(transparent)]
    Output(#[from] subdiv_rules::LimitMeshError),
    /// Set-up failed (local level-1 refinement).
    #[error(transparent)]
    Rules(#[from] RulesError),
}

/// Most limit points one tessellation may produce (about 3 GiB of positions and normals).
pub const MAX_POINTS: u64 = 1 << 27;

/// The default `max_depth` of the paper (Settgast et al. 2004: `maxsd = 5`), the one home of
/// that default (`subdiv_depth::DepthParams::default` reads it): slates are sized for at least
/// this depth.
pub const DEFAULT_MAX_DEPTH: Depth = 5;

/// Output pointers shared by the patch tasks. Each output point has exactly one owner patch
/// (see [`PatchLayout`]), so no two tasks ever write the same element.
pub(crate) struct SharedOut {
    pub(crate) pos: *mut [f32; 3],
    pub(crate) nrm: *mut [f32; 3],
    pub(crate) len: usize,
}
// SAFETY: the pointers are only written through `write`, `write_unchecked` and the slices of
// `range`, at indices below `len` (asserted, or checked by `check_range`), and the tasks sharing a
// `SharedOut` write disjoint indices (each output point has one owner patch in the layout); nothing reads through
// them while tasks run, and the buffers outlive the parallel loop that uses them.
unsafe impl Sync for SharedOut {}
// SAFETY: as for `Sync`: the raw pointers carry no thread affinity, and the only accesses are
// the disjoint, bounds-checked writes described there.
unsafe impl Send for SharedOut {}

impl SharedOut {
    #[inline]
    pub(crate) fn write(&self, id: u32, p: Vec3A, n: Vec3A) {
        let i = id as usize;
        assert!(i < self.len, "output index out of range");
        // SAFETY: in bounds (asserted); no other task writes index `i` (single owner).
        unsafe { self.write_unchecked(i, p, n) }
    }

    #[inline]
    pub(crate) fn check_range(&self, first: usize, count: usize) {
        assert!(first + count <= self.len, "output range out of bounds");
    }

    /// The elements `first..first + count` of both buffers as slices.
    ///
    /// # Safety
    /// `first + count <= len` (see [`SharedOut::check_range`]), no other task writes these
    /// indices while the slices live, and no other slice of them is alive.
    #[inline]
    #[allow(clippy::mut_from_ref)]
    pub(crate) unsafe fn range(
        &self,
        first: usize,
        count: usize,
    ) -> (&mut [[f32; 3]], &mut [[f32; 3]]) {
        // SAFETY: the range lies inside the `len`-element buffers (caller), which outlive the
        // tasks; the caller guarantees exclusive access to it, so the slices alias nothing.
        unsafe {
            (
                std::slice::from_raw_parts_mut(self.pos.add(first), count),
                std::slice::from_raw_parts_mut(self.nrm.add(first), count),
            )
        }
    }

    /// # Safety
    /// `i < len` (see [`SharedOut::check_range`]) and no other task writes index `i`.
    #[inline(always)]
    pub(crate) unsafe fn write_unchecked(&self, i: usize, p: Vec3A, n: Vec3A) {
        // SAFETY: the caller guarantees `i < len`, so both writes stay inside the `len`-element
        // buffers `pos` and `nrm` point to, and that no other task writes index `i`, so the
        // writes race with nothing.
        unsafe {
            *self.pos.add(i) = p.to_array();
            *self.nrm.add(i) = n.to_array();
        }
    }
}

/// Tessellates the Catmull-Clark limit surface of `mesh` uniformly at `depth` with the slate
/// tessellator: every quad of the level-`depth` refinement, with the exact limit points and limit
/// normals as vertices. Runs on the current rayon pool.
///
/// ```
/// use subdiv_mesh::{parse_obj, Mesh};
/// let cube = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
///             f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
/// let mesh = Mesh::from_soup(&parse_obj(cube)?)?;
/// let t = subdiv_slate::tessellate(&mesh, 3).unwrap();
/// assert_eq!(t.num_faces(), 6 * 64);
/// assert_eq!(t.positions().len(), 6 * 64 + 2);
/// # Ok::<(), subdiv_mesh::MeshError>(())
/// ```
pub fn tessellate(mesh: &Mesh, depth: Depth) -> Result<LimitMesh, SlateError> {
    // Coordinates near `f32::MAX` would overflow to infinite points.
    subdiv_rules::check_coordinates(mesh)?;
    if depth == 0 {
        let mut out = limit_surface(mesh, Scheme::CatmullClark);
        // The cage vertices on seams, the same bits in every copy (as at any depth).
        subdiv_rules::SeamCurves::new(mesh).write_uniform(mesh, 0, 0, out.positions_mut());
        return Ok(out);
    }
    // Refuse before allocating: beyond the slates, this machine's memory or `MAX_POINTS`.
    crate::size::check_uniform_size(mesh, Scheme::CatmullClark, depth)?;
    let layout = PatchLayout::new(mesh, depth)?;
    tessellate_layout(mesh, &layout)
}

/// [`tessellate`] with a precomputed layout (for repeated tessellation of the same mesh).
pub fn tessellate_layout(mesh: &Mesh, layout: &PatchLayout) -> Result<LimitMesh, SlateError> {
    let mut out = LimitMesh::default();
    tessellate_layout_into(mesh, layout, &mut out)?;
    Ok(out)
}

/// [`tessellate_layout`] into a reused output (its buffers are resized, not reallocated, when
/// the sizes match: the steady state of per-frame tessellation).
///
/// The quads (`face_indices`, `face_offsets`) are a function of the layout alone: they are
/// written once per layout and output, and kept by the calls that follow with the same layout
/// (the positions, normals, one-sided corner normals and UVs are written every call).
/// [`LimitMesh::topology_written`] tells the caller whether this call wrote them (a renderer
/// uploads its index buffer again only then). Another layout (another depth, another cage, a
/// hole changed: each a new layout, whose key no other layout has), or an output whose faces
/// another tessellator wrote or that changed since, gets its quads written. `mesh` is the cage
/// the layout was made for; after its positions moved, call [`PatchLayout::move_to`] first
/// (or use [`crate::UniformTessellator`], which does).
pub fn tessellate_layout_into(
    mesh: &Mesh,
    layout: &PatchLayout,
    result: &mut LimitMesh,
) -> Result<(), SlateError> {
    let depth = layout.depth;
    // The positions may have moved since the layout was made (with `PatchLayout::move_to`).
    subdiv_rules::check_coordinates(mesh)?;
    if depth > MAX_DEPTH {
        return Err(SlateError::TooDeep {
            depth,
            max: MAX_DEPTH,
        });
    }
    let max_depth = depth.max(DEFAULT_MAX_DEPTH);
    let np = layout.num_points();
    // Face ranges by prefix sum over visible patches.
    let quads_of = |p: &Patch| {
        if p.visible {
            1usize << (2 * (depth - p.level))
        } else {
            0
        }
    };
    let total: usize = layout.patches.iter().map(quads_of).sum();
    // The quads and their offsets depend on the layout alone: written once per layout, kept
    // by the calls that follow into the same output.
    let w = result.write_keyed(layout.key, np, total, 4)?;
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
    // Split the index buffer into one chunk per patch (empty ones where the quads are kept);
    // `starts[k]`: patch `k`'s first corner.
    let mut chunks: Vec<&mut [u32]> = Vec::with_capacity(layout.patches.len());
    let mut starts: Vec<u32> = Vec::with_capacity(layout.patches.len());
    let mut rest: &mut [u32] = w.faces.unwrap_or_default();
    let mut start = 0u32;
    for p in &layout.patches {
        let corners = quads_of(p) * 4;
        let (a, b) = rest.split_at_mut(if write_faces { corners } else { 0 });
        starts.push(start);
        start += corners as u32;
        chunks.push(a);
        rest = b;
    }
    let level1 = layout.level1.as_ref();
    // One-sided corner normals `(patch, corner in the patch's quads, normal)`, gathered per
    // rayon task (no allocation per patch), in patch order within a task and tasks in order.
    let sided: Vec<Vec<(u32, u32, [f32; 3])>> = layout
        .patches
        .par_iter()
        .zip(chunks.into_par_iter())
        .enumerate()
        .with_min_len(8)
        .fold(
            || (thread_worker(max_depth), Vec::new()),
            |(mut w, mut acc), (k, (p, quads))| {
                let src = if p.level == 0 {
                    mesh
                } else {
                    level1.expect("level-1 mesh for level-1 patches")
                };
                let visible = p.visible;
                let e = depth - p.level;
                w.gather_with(src, p.face, &layout.plans[k], &layout.plan_edges);
                let sided = visible && layout.plans[k].may_be_sided();
                run_patch(&mut w, p, e, &out, sided);
                if visible && write_faces {
                    write_quads(&mut w, p, 1 << e, quads);
                }
                if visible {
                    corner_slots(1 << e, &w.sided_points, k as u32, &mut acc);
                }
                (w, acc)
            },
        )
        .map(|(_, acc)| acc)
        .collect();
    // Corner normals in patch order: ascending, as each patch's are.
    result.write_corner_normals(
        sided
            .into_iter()
            .flatten()
            .map(|(k, slot, n)| (starts[k as usize] + slot, n)),
    );
    // Points on seams from their chains: the copies of a non-manifold edge agree to the bit.
    layout.write_seam_points(mesh, result.positions_mut());
    // Face-varying limit values, only for a cage with UVs (`uv.rs`).
    crate::uv::quad_uvs(mesh, layout, result)
}

/// Subdivides and evaluates one patch (gathered into the worker's slate 0); writes the points
/// it owns, and leaves in the worker's `sided_points` the grid points where the
/// limit surface has a crease or a corner, with the one-sided normal of this patch's side
/// (visible patches only). `may_sided`: the patch is visible and its plan says it may have
/// one-sided normals (`GatherPlan::may_be_sided`); otherwise the points it does not own are
/// not looked at.
fn run_patch(wk: &mut Worker, p: &Patch, e: Depth, out: &SharedOut, may_sided: bool) {
    let w = &mut *wk;
    for _ in 0..e {
        w.step();
    }
    let n = 1u32 << e;
    let visible = p.visible;
    // Grid points with a one-sided normal of this patch's side.
    let mut sided = std::mem::take(&mut w.sided_points);
    sided.clear();
    // Whether a point this patch does not own needs its limit for a one-sided normal (debug
    // builds check the plan's answer against the point's own where the plan says no).
    let look = |w: &mut Worker, i: u32, j: u32| -> bool {
        if may_sided {
            return w.may_be_sided(i as i32, j as i32);
        }
        debug_assert!(
            !visible || !w.may_be_sided(i as i32, j as i32),
            "plan without one-sided normals, but grid point ({i}, {j}) may have one"
        );
        false
    };
    // Corners and sides: where this patch is the owner, and for a visible patch wherever the
    // point may lie on a crease (its side's normal is its own, owner or not).
    for (k, (i, j)) in [(0, 0), (n, 0), (n, n), (0, n)].into_iter().enumerate() {
        if p.corner_owned[k] || look(w, i, j) {
            let (pos, nrm, side) = w.limit_sided(i as i32, j as i32, visible);
            if p.corner_owned[k] {
                out.write(p.corners[k], pos, nrm);
            }
            sided.extend(side.map(|s| (i, j, s)));
        }
    }
    for (k, side) in p.sides.iter().enumerate() {
        for s in 1..n {
            let (i, j) = crate::side_point(k, s, n);
            if side.owned || look(w, i, j) {
                // Not a grid corner: no corner array.
                let (pos, nrm, one) = w.limit_table(i as i32, j as i32, visible);
                if side.owned {
                    out.write(side.id(s), pos, nrm);
                }
                sided.extend(one.map(|o| (i, j, o)));
            }
        }
    }
    // Interior: contiguous output rows.
    if n > 1 {
        let m = (n - 1) as usize;
        let first = p.interior as usize;
        out.check_range(first, m * m);
        // SAFETY: the range is inside the buffers (checked above) and only this patch writes it.
        let (pos, nrm) = unsafe { out.range(first, m * m) };
        w.limit_interior(&mut InteriorOut {
            pos,
            nrm,
            first: 0,
            stride: m,
        });
    }
    w.sided_points = sided;
}

/// Appends to `slots` the corners of the quads of patch `patch` (row by row, corners
/// counter-clockwise from the cell's lowest) at the grid points of `sided`, with their normals,
/// ascending by corner.
fn corner_slots(
    n: u32,
    sided: &[(u32, u32, Vec3A)],
    patch: u32,
    slots: &mut Vec<(u32, u32, [f32; 3])>,
) {
    let first = slots.len();
    for &(i, j, nrm) in sided {
        for (ci, cj, corner) in [
            (i, j, 0),
            (i.wrapping_sub(1), j, 1),
            (i.wrapping_sub(1), j.wrapping_sub(1), 2),
            (i, j.wrapping_sub(1), 3),
        ] {
            if ci < n && cj < n {
                slots.push((patch, (cj * n + ci) * 4 + corner, nrm.to_array()));
            }
        }
    }
    slots[first..].sort_unstable_by_key(|&(_, k, _)| k);
}

/// Writes the quads of visible patch `p` (grid size `n`) into `quads`.
fn write_quads(wk: &mut Worker, p: &Patch, n: u32, quads: &mut [u32]) {
    // Ids of the whole grid once (border through the layout, interior contiguous), then quads.
    let w = (n + 1) as usize;
    let mut ids = std::mem::take(&mut wk.ids);
    ids.resize(w * w, 0);
    for j in 0..=n {
        if j == 0 || j == n {
            for i in 0..=n {
                ids[j as usize * w + i as usize] = point_id(p, n, i, j).0;
            }
        } else {
            let r = j as usize * w;
            ids[r] = point_id(p, n, 0, j).0;
            ids[r + w - 1] = point_id(p, n, n, j).0;
            let first = p.interior + (j - 1) * (n - 1);
            for (k, id) in ids[r + 1..r + w - 1].iter_mut().enumerate() {
                *id = first + k as u32;
            }
        }
    }
    for (j, qrow) in quads.chunks_exact_mut(4 * n as usize).enumerate() {
        let (lo, hi) = (&ids[j * w..(j + 1) * w], &ids[(j + 1) * w..(j + 2) * w]);
        for ((q, a), b) in qrow
            .chunks_exact_mut(4)
            .zip(lo.windows(2))
            .zip(hi.windows(2))
        {
            q.copy_from_slice(&[a[0], a[1], b[1], b[0]]);
        }
    }
    wk.ids = ids;
}

/// Output id of grid point `(i, j)` of a patch with grid size `n`, and whether the patch owns it.
#[inline]
fn point_id(p: &Patch, n: u32, i: u32, j: u32) -> (u32, bool) {
    let last = n;
    match (i, j) {
        (0, 0) => (p.corners[0], p.corner_owned[0]),
        (i, 0) if i == last => (p.corners[1], p.corner_owned[1]),
        (i, j) if i == last && j == last => (p.corners[2], p.corner_owned[2]),
        (0, j) if j == last => (p.corners[3], p.corner_owned[3]),
        (i, 0) => (p.sides[0].id(i), p.sides[0].owned),
        (i, j) if i == last => (p.sides[1].id(j), p.sides[1].owned),
        (i, j) if j == last => (p.sides[2].id(n - i), p.sides[2].owned),
        (0, j) => (p.sides[3].id(n - j), p.sides[3].owned),
        (i, j) => (p.interior + (j - 1) * (n - 1) + (i - 1), true),
    }
}

/// Bytes of slate memory one worker uses for depth `depth`, independent of the mesh size: two
/// tables, the worker's bounded scratch (rolling rows, dirty mask, at most 16 limit stencils) and
/// the four corner arrays, which grow with the largest valence (`2 * 2 * valence` points each).
pub fn slate_bytes_per_thread(depth: Depth, max_valence: usize) -> usize {
    let w = Worker::new(depth.max(DEFAULT_MAX_DEPTH));
    w.table_bytes()
        + w.scratch_bytes()
        + 4 * (4 * max_valence * std::mem::size_of::<glam::DVec3>() + 2 * max_valence * 4)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ownership_is_a_partition() {
        // Every output point is owned by exactly one patch (or is an isolated vertex).
        for (name, text) in [
            ("cube", subdiv_test_support::cube().obj().as_str()),
            (
                "tri+quad",
                "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 9 9 9\nf 1 2 3 4\nf 2 5 3\n",
            ),
        ] {
            let mesh = Mesh::from_soup(&subdiv_mesh::parse_obj(text).unwrap()).unwrap();
            for depth in 1..=3 {
                let layout = PatchLayout::new(&mesh, depth).unwrap();
                let mut count = vec![0u32; layout.num_points()];
                for v in &layout.isolated {
                    count[v.idx()] += 1;
                }
                for p in &layout.patches {
                    let n = 1u32 << (depth - p.level);
                    for j in 0..=n {
                        for i in 0..=n {
                            let (id, owned) = point_id(p, n, i, j);
                            if owned {
                                count[id as usize] += 1;
                            }
                        }
                    }
                }
                assert!(
                    count.iter().all(|&c| c == 1),
                    "{name} depth {depth}: {count:?}"
                );
            }
        }
    }

    /// Found by fuzzing: finite coordinates near `f32::MAX` gave infinite limit points (quads)
    /// or an internal error (n-gons, through the local level-1 mesh).
    #[test]
    fn huge_coordinates_are_refused() {
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nv 3 0 0\n\
                    f 1 2 3 4\nf 2 5 6 3\nf 5 7 6\n";
        let mut mesh = Mesh::from_soup(&subdiv_mesh::parse_obj(text).unwrap()).unwrap();
        let layout = PatchLayout::new(&mesh, 1).unwrap();
        mesh.positions_mut()[4].x = -3.4e38;
        for depth in [0, 1, 2] {
            let e = tessellate(&mesh, depth).unwrap_err();
            assert!(
                matches!(
                    e,
                    SlateError::Rules(RulesError::HugeCoordinate { vertex: 4, .. })
                ),
                "{e:?}"
            );
            assert!(
                e.to_string()
                    .starts_with("vertex 4 has a coordinate beyond"),
                "{e}"
            );
        }
        assert!(tessellate_layout(&mesh, &layout).is_err());
        mesh.positions_mut()[4].x = f32::NAN;
        for depth in [0, 2] {
            let e = tessellate(&mesh, depth).unwrap_err();
            assert!(
                matches!(
                    e,
                    SlateError::Rules(RulesError::NonFiniteCoordinate { vertex: 4, .. })
                ),
                "{e:?}"
            );
        }
        assert!(tessellate_layout(&mesh, &layout).is_err());
        mesh.positions_mut()[4].x = -subdiv_rules::MAX_COORDINATE;
        let t = tessellate(&mesh, 2).unwrap();
        assert!(
            t.positions()
                .iter()
                .chain(t.normals())
                .flatten()
                .all(|x| x.is_finite())
        );
    }
}
