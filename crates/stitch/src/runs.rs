//! Runs of patches whose triangles a frame keeps from the last one: the index buffer of a
//! frame is emitted in runs of [`RUN_PATCHES`] consecutive patches, each run keeping its
//! triangles while the state they were emitted from (a key its assembler writes) stays.
//!
//! **Invariant.** A kept run's output is bit for bit what emitting it again would give: its
//! key holds everything its triangles read (the depths, activity and blocks of the faces
//! around its patches' corners, [`faces_around`]), and the blocks' computations where the run
//! copies one-sided normals from them.

use std::ops::Range;

use rayon::prelude::*;
use subdiv_mesh::{FaceId, Mesh};

/// Patches per run: enough work per task to amortise the task, small enough that two threads
/// share a frame of a few hundred patches evenly. (Runs of 8 or 16 patches keep no more of a
/// moving camera's frame on helmet40: its changes spread over many runs.)
pub(crate) const RUN_PATCHES: usize = 32;

/// A frame's (or a run's) triangles, one-sided corner normals and face-varying corner values.
pub(crate) type Emitted = (Vec<u32>, Vec<(u32, [f32; 3])>, Vec<u32>);

/// One run's triangles, one-sided corner normals (corner index within `tris`) and face-varying
/// corner values, and the key they were emitted from; kept between frames so that a frame
/// allocates nothing once the buffers have grown.
#[derive(Clone, Debug, Default)]
pub(crate) struct RunOut {
    pub(crate) tris: Vec<u32>,
    pub(crate) sided: Vec<(u32, [f32; 3])>,
    pub(crate) uv: Vec<u32>,
    key: Vec<u64>,
    next_key: Vec<u64>,
    keyed: bool,
}

impl RunOut {
    /// Whether the run keeps its output this frame. `write_key` (none: emit the run, and key
    /// it no more) writes the run's state into the cleared vector and returns the length of
    /// the part its triangles depend on; the rest (the computations of the blocks whose
    /// one-sided normals it copies) counts only when the run has some. A run that is not
    /// kept is cleared for emission.
    pub(crate) fn keep(&mut self, write_key: Option<impl FnOnce(&mut Vec<u64>) -> usize>) -> bool {
        match write_key {
            Some(write) => {
                let mut key = std::mem::take(&mut self.next_key);
                key.clear();
                let structure = write(&mut key);
                self.next_key = key;
                let n = if self.sided.is_empty() {
                    structure
                } else {
                    self.key.len()
                };
                let (old, new) = (&self.key, &self.next_key);
                if self.keyed && old.len() == new.len() && old[..n] == new[..n] {
                    return true;
                }
                std::mem::swap(&mut self.key, &mut self.next_key);
                self.keyed = true;
            }
            None => self.keyed = false,
        }
        self.tris.clear();
        self.sided.clear();
        self.uv.clear();
        false
    }
}

/// Emits `items` (patches or faces) in runs of [`RUN_PATCHES`] consecutive ones, in parallel,
/// into `slots` (grown as needed and kept by the caller between frames; `run_of` gives each
/// slot's [`RunOut`]). With `key` (`key(run, its items, key vector)`, as
/// [`RunOut::keep`]'s writer), a run whose key stayed keeps its output; every other run is
/// cleared and handed to `emit(its items, slot)`. Returns the runs used and the runs kept.
pub(crate) fn emit_runs<T, K, E>(
    slots: &mut Vec<T>,
    items: usize,
    run_of: impl Fn(&mut T) -> &mut RunOut + Sync,
    key: Option<K>,
    emit: E,
) -> (usize, usize)
where
    T: Default + Send,
    K: Fn(usize, Range<usize>, &mut Vec<u64>) -> usize + Sync,
    E: Fn(Range<usize>, &mut T) + Sync,
{
    let n = items.div_ceil(RUN_PATCHES);
    if slots.len() < n {
        slots.resize_with(n, T::default);
    }
    let kept = slots[..n]
        .par_iter_mut()
        .enumerate()
        .map(|(c, slot)| {
            let range = c * RUN_PATCHES..((c + 1) * RUN_PATCHES).min(items);
            let write = key.as_ref().map(|key| {
                let range = range.clone();
                move |v: &mut Vec<u64>| key(c, range, v)
            });
            if run_of(slot).keep(write) {
                return 1;
            }
            emit(range, slot);
            0
        })
        .sum();
    (n, kept)
}

/// The runs' outputs in order into the frame's buffers (cleared first), the one-sided normals'
/// corner indices rebased onto `out`.
pub(crate) fn concat<'a>(
    runs: impl Iterator<Item = &'a RunOut> + Clone,
    out: &mut Vec<u32>,
    corner_normals: &mut Vec<(u32, [f32; 3])>,
    uv_indices: &mut Vec<u32>,
) {
    out.clear();
    corner_normals.clear();
    uv_indices.clear();
    out.reserve(runs.clone().map(|r| r.tris.len()).sum());
    corner_normals.reserve(runs.clone().map(|r| r.sided.len()).sum());
    uv_indices.reserve(runs.clone().map(|r| r.uv.len()).sum());
    for r in runs {
        let start = out.len() as u32;
        corner_normals.extend(r.sided.iter().map(|&(c, n)| (start + c, n)));
        out.extend_from_slice(&r.tris);
        uv_indices.extend_from_slice(&r.uv);
    }
}

/// Per run of [`RUN_PATCHES`] of the `n` patches, the faces (ascending) its triangles read:
/// `around(p, deps)` pushes those of patch `p` (some repeated, in any order).
pub(crate) fn dependencies(n: usize, around: impl Fn(usize, &mut Vec<u32>)) -> Vec<Vec<u32>> {
    (0..n)
        .step_by(RUN_PATCHES)
        .map(|lo| {
            let mut deps: Vec<u32> = Vec::new();
            for p in lo..(lo + RUN_PATCHES).min(n) {
                around(p, &mut deps);
            }
            deps.sort_unstable();
            deps.dedup();
            deps
        })
        .collect()
}

/// Pushes the faces around every corner of `face` (itself among them): a patch's triangles
/// read its own face's depth and blocks, the depth and activity of the faces across its sides
/// (fans, edge owners) and around its corners (vertex owners), and the blocks of the owners of
/// its border points, all among these.
pub(crate) fn faces_around(mesh: &Mesh, face: FaceId, deps: &mut Vec<u32>) {
    for h in mesh.face_halfedges(face) {
        for g in mesh.outgoing(mesh.from(h)) {
            let f = mesh.face(g);
            if f.is_some() {
                deps.push(f.0);
            }
        }
    }
}
