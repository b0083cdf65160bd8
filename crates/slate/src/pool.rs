//! The per-thread worker pool: every thread keeps one [`Worker`] between tessellations, and
//! [`PatchGrids`], the public way to tessellate single patches with it.

use subdiv_mesh::Mesh;
use subdiv_rules::{Depth, Scheme};

use crate::patches::{PatchRef, PatchSet};
use crate::worker::Worker;

/// Deepest `max_depth` whose worker a thread keeps between tessellations (about 230 KB of tables
/// and scratch at 6); deeper workers (megabytes) are freed when their job ends.
pub(crate) const KEEP_MAX_DEPTH: Depth = 6;

thread_local! {
    static THREAD_WORKER: std::cell::Cell<Option<Box<Worker>>> = const { std::cell::Cell::new(None) };
}

/// The calling thread's reusable [`Worker`] for patches up to depth `max_depth`: the slates are
/// allocated on a thread's first use and then serve every later patch and every later
/// tessellation on that thread (per-frame updates included), so steady-state tessellation
/// allocates nothing. The worker goes back to the thread when the guard drops; a thread that
/// already holds one (a nested job started while the first guard is alive), or a request deeper
/// than [`KEEP_MAX_DEPTH`], gets a fresh worker that is freed at the end instead.
///
/// Reuse cannot change results: every patch starts with a fresh gather, and the worker's only
/// other state, its cache of limit stencils, is keyed by everything a stencil depends on.
pub(crate) fn thread_worker(max_depth: Depth) -> WorkerGuard {
    let maxn = 1usize << max_depth;
    let cached = THREAD_WORKER.with(|c| c.take());
    let w = match cached {
        Some(w) if w.maxn >= maxn => w,
        Some(w) => {
            // Too small for this request: put it back for later shallow jobs.
            THREAD_WORKER.with(|c| c.set(Some(w)));
            Box::new(Worker::new(max_depth))
        }
        None => Box::new(Worker::new(max_depth)),
    };
    WorkerGuard(Some(w))
}

/// A worker lent by [`thread_worker`]; derefs to [`Worker`] and returns it to the thread on drop.
#[derive(Debug)]
pub(crate) struct WorkerGuard(Option<Box<Worker>>);

impl std::ops::Deref for WorkerGuard {
    type Target = Worker;
    #[inline]
    fn deref(&self) -> &Worker {
        self.0.as_deref().expect("worker present until drop")
    }
}

impl std::ops::DerefMut for WorkerGuard {
    #[inline]
    fn deref_mut(&mut self) -> &mut Worker {
        self.0.as_deref_mut().expect("worker present until drop")
    }
}

impl Drop for WorkerGuard {
    fn drop(&mut self) {
        let Some(w) = self.0.take() else { return };
        if w.maxn > 1usize << KEEP_MAX_DEPTH {
            return;
        }
        // Keep the larger of the returned and the held worker (the other is freed).
        let _ = THREAD_WORKER.try_with(|c| {
            let held = c.take();
            c.set(match held {
                Some(h) if h.maxn >= w.maxn => Some(h),
                _ => Some(w),
            });
        });
    }
}

/// Single patches of a [`PatchSet`] tessellated at chosen depths into the caller's buffers: what
/// an adaptive assembler caches per patch and what the pixel-error mode samples. It holds the
/// calling thread's slates for patches up to its `max_depth` (lent by the thread's pool and
/// returned when it drops), so one per rayon task allocates nothing in steady state; the
/// points are the same bits whichever thread or task computes them.
///
/// ```
/// use subdiv_mesh::{parse_obj, Mesh};
/// use subdiv_slate::{PatchGrids, PatchSet};
/// let cube = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
///             f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
/// let mesh = Mesh::from_soup(&parse_obj(cube)?)?;
/// let set = PatchSet::new(&mesh)?;
/// let mut grids = PatchGrids::new(&mesh, &set, 5);
/// let (mut p, mut n, mut sided) = (vec![[0.0; 3]; 25], vec![[0.0; 3]; 25], Vec::new());
/// grids.grid(&set.patches()[0], 2, &mut p, &mut n, &mut sided);
/// assert!((p[12][2] - 0.0).abs() < 0.2); // the centre of face 0 (z = 0 side) lies near z = 0
/// assert!(sided.is_empty()); // a smooth cube has no one-sided normals
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct PatchGrids<'a> {
    mesh: &'a Mesh,
    set: &'a PatchSet,
    worker: WorkerGuard,
}

impl<'a> PatchGrids<'a> {
    /// Patch grids of `set` (built for `mesh`) up to depth `max_depth`.
    pub fn new(mesh: &'a Mesh, set: &'a PatchSet, max_depth: Depth) -> PatchGrids<'a> {
        PatchGrids {
            mesh,
            set,
            worker: thread_worker(max_depth),
        }
    }

    /// Tessellates patch `p` at `depth` (at most the `max_depth` this was made for) and writes
    /// the limit points and normals of its `(2^depth + 1)^2` grid into `pos` and `nrm`, row by
    /// row (`i` along the patch's first edge, `j` along its last edge reversed), and into
    /// `sided` (cleared first; grid index ascending) the one-sided limit normal of this patch's
    /// side at the border points where the limit surface has a crease or a corner (see
    /// `subdiv_rules::Ring::limit_sided`; `nrm` holds the averaged normal there). Points on the
    /// cage's seams are the slate's own; [`PatchSet::write_seam_points`] replaces them.
    ///
    /// A bilinear set's patches meet with a crease at every edge: every border point is
    /// one-sided, and `nrm` holds this patch's own normal there too.
    ///
    /// # Panics
    /// If `pos` or `nrm` is shorter than the grid or `depth` exceeds the slates' depth.
    pub fn grid(
        &mut self,
        p: &PatchRef,
        depth: Depth,
        pos: &mut [[f32; 3]],
        nrm: &mut [[f32; 3]],
        sided: &mut Vec<(u32, [f32; 3])>,
    ) {
        if self.set.scheme() == Scheme::Bilinear {
            crate::bilinear::patch_grid_sided(self.mesh, p, depth, pos, nrm, sided);
        } else {
            let source = self.set.source(self.mesh, p);
            self.worker
                .patch_grid_sided(source, p.src_face, depth, pos, nrm, sided);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3A;

    fn slates(w: &Worker) -> *const Vec3A {
        w.t[0].positions.as_ptr()
    }

    #[test]
    fn thread_worker_is_reused_and_deep_workers_are_not_kept() {
        // Run on a fresh thread so that other tests' workers are not involved.
        std::thread::spawn(|| {
            let a = thread_worker(5);
            let pa = slates(&a);
            // While `a` is lent, a nested request gets its own worker.
            let b = thread_worker(5);
            let pb = slates(&b);
            assert_ne!(pb, pa);
            // The first one returned is kept (`b`); `a`, as large, is freed.
            drop(b);
            drop(a);
            // The same slates serve the next requests, shallower ones too.
            assert_eq!(slates(&thread_worker(5)), pb);
            assert_eq!(slates(&thread_worker(3)), pb);
            // A deeper request than the held worker gets a bigger one, which replaces it.
            let c = thread_worker(KEEP_MAX_DEPTH);
            let pc = slates(&c);
            assert!(c.maxn == 1 << KEEP_MAX_DEPTH);
            drop(c);
            assert_eq!(slates(&thread_worker(2)), pc);
            // Past KEEP_MAX_DEPTH the worker is freed at the end; the kept one stays.
            let d = thread_worker(KEEP_MAX_DEPTH + 1);
            assert!(d.maxn == 1 << (KEEP_MAX_DEPTH + 1));
            drop(d);
            assert_eq!(slates(&thread_worker(2)), pc);
        })
        .join()
        .unwrap();
    }
}
