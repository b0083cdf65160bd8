//! `subdiv-slate`: the per-patch Catmull-Clark tessellator with two static slates.
//!
//! Settgast, Müller, Fünfzig and Fellner, "Adaptive Tessellation of Subdivision Surfaces",
//! Section 3.2: every face of the cage is tessellated on its own. Its 1-neighbourhood is gathered
//! into a statically sized *slate*; `tessellate(depth, slate i)` subdivides it once into the
//! other slate and recurses, and the limit points and limit normals of the `(2^d + 1)^2` grid are
//! computed from the last slate. The cage is never modified.
//!
//! Beyond the paper: every rule of `subdiv-rules` applies inside the slate (boundaries, sharp and
//! semi-sharp creases with the uniform or Chaikin rule, darts, corners), valences are limited only
//! by memory (the corner arrays are sized from the mesh), n-gons and quads next to them are
//! tessellated through their level-1 quads, limits are exact for semi-sharp creases, patches run
//! in parallel with one pair of slates per thread (kept between calls, see [`thread_worker`]), and shared points are written by one owner
//! patch so the output is bit-identical for any thread count (see [`PatchLayout`]).
//!
//! ```
//! use subdiv_mesh::read_obj;
//! # let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/reference/shapes");
//! let mesh = read_obj(dir.join("catmark_pawn.obj")).unwrap();
//! let t = subdiv_slate::tessellate(&mesh, 2).unwrap();
//! assert_eq!(t.num_faces(), 588 * 16);
//! ```

mod gather;
mod layout;
mod limit;
mod patches;
mod pool;
mod step;
mod table;
mod tessellate;
mod worker;

pub use layout::PatchLayout;
pub use patches::{PatchRef, PatchSet, Unit};
pub use pool::{KEEP_MAXSD, WorkerGuard, thread_worker};
pub use tessellate::{
    DEFAULT_MAXSD, MAX_DEPTH, MAX_POINTS, SlateError, slate_bytes_per_thread, tessellate,
    tessellate_layout, tessellate_layout_into,
};
pub use worker::Worker;
