//! The per-thread worker pool: every thread keeps one [`Worker`] between tessellations.

use subdiv_rules::Depth;

use crate::worker::Worker;

/// Deepest `max_depth` whose worker a thread keeps between tessellations (about 230 KB of tables
/// and scratch at 6); deeper workers (megabytes) are freed when their job ends.
pub const KEEP_MAX_DEPTH: Depth = 6;

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
///
/// ```
/// let mut w = subdiv_slate::thread_worker(5);
/// assert!(w.table_bytes() > 0);
/// drop(w); // returned to this thread: the next call reuses the same slates
/// let w2 = subdiv_slate::thread_worker(4);
/// assert!(w2.table_bytes() >= subdiv_slate::Worker::new(4).table_bytes());
/// ```
pub fn thread_worker(max_depth: Depth) -> WorkerGuard {
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
pub struct WorkerGuard(Option<Box<Worker>>);

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
