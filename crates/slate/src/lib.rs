//! `subdiv-slate`: the per-patch Catmull-Clark tessellator with two static slates.
//!
//! The crate's job: given a cage [`Mesh`](subdiv_mesh::Mesh) and a depth `d`, produce the
//! uniform level-`d` tessellation of its Catmull-Clark limit surface (every quad of the
//! level-`d` refinement, with exact limit points and limit normals as vertices) without
//! refining the whole mesh: each face is tessellated on its own, in parallel.
//!
//! Settgast, Müller, Fünfzig and Fellner, "Adaptive Tessellation of Subdivision Surfaces",
//! Section 3.2: every face of the cage is tessellated on its own. Its 1-neighbourhood is gathered
//! into a statically sized *slate*; `tessellate(depth, slate i)` subdivides it once into the
//! other slate and recurses, and the limit points and limit normals of the `(2^d + 1)^2` grid are
//! computed from the last slate.
//!
//! # Invariants
//!
//! - **The cage is never modified.** Patches only read the mesh (or a local level-1 refinement
//!   built beside it, for n-gons and their neighbours); all refinement happens in the slates.
//! - **One owner per output point.** A point shared by several patches (a cage vertex, a point
//!   on a cage edge, ...) is numbered once and written by exactly one *owner* patch; the others
//!   only reference it (see [`PatchLayout`]). No two tasks write the same output element.
//! - **Output identical for any thread count.** Every point is computed by its owner alone from
//!   that patch's own gather, in a fixed order, and a worker's reuse between patches cannot
//!   change results (see [`PatchGrids`]), so the output is bit-identical whether it runs on
//!   one thread or many.
//! - **The same bits with or without SIMD.** Where the CPU has AVX2 (detected at run time), the
//!   interior limits run eight points per register and the regular step two (`wide`); every
//!   lane performs the scalar path's IEEE operations in its order, without fused multiply-add,
//!   so the output does not depend on the path taken.
//! - **Faces are written once per layout.** The quads (Loop: triangles) and their offsets are a
//!   function of the layout alone; each layout has a process-unique key (a clone another), the
//!   output records the key its faces were written for, and a call with the same layout and
//!   face-list lengths keeps them (`LimitMesh::topology_written` reports it). No other layout,
//!   depth, hole set or cage can match a key.
//! - **UVs are a function of the cage but for its positions.** A cage's face-varying values
//!   (`uv`) depend on its topology, UVs, sharpness, options and holes only; a layout keeps those
//!   of its first tessellation with UVs and hands them to later calls on the same cage, bit for
//!   bit what a fresh tessellation gives.
//! - **The copies of a non-manifold edge agree to the bit.** A non-manifold cage is tessellated
//!   as manifold pieces, each with its own copy of the edge; the points on those copies (and
//!   their end vertices) are written from the edge's crease chain by
//!   [`SeamCurves`](subdiv_rules::SeamCurves), identically in every copy, piece and depth.
//!
//! # Beyond the paper
//!
//! Every rule of `subdiv-rules` applies inside the slate (boundaries, sharp and semi-sharp
//! creases with the uniform or Chaikin rule, darts, corners), valences are limited only by memory
//! (the corner arrays are sized from the mesh), n-gons and quads next to them are tessellated
//! through their level-1 quads, limits are exact for semi-sharp creases, and patches run in
//! parallel with one pair of slates per thread (kept between calls, see [`PatchGrids`]).
//!
//! # Modules
//!
//! Loop runs on triangular slates by the same design (module `tri`, see [`tessellate_tri`]).
//!
//! `table` (a slate's storage), `gather` (a patch's 1-neighbourhood into slate 0), `step` (one
//! subdivision step), `limit` (limit points and normals; `wide` its interior loop eight points at a time), `worker` (a thread's slates and the
//! pipeline of one patch), `pool` (the per-thread workers, and [`PatchGrids`]: single patches at
//! chosen depths for the adaptive assembler and the pixel-error mode), `patches` and `layout` (per-mesh
//! set-up and output numbering), `tessellate` (the parallel driver).
//!
//! ```
//! use subdiv_mesh::read_obj;
//! # let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/reference/shapes");
//! let mesh = read_obj(dir.join("catmark_pawn.obj")).unwrap();
//! let t = subdiv_slate::tessellate(&mesh, 2).unwrap();
//! assert_eq!(t.num_faces(), 588 * 16);
//! ```

mod bilinear;
mod gather;
mod grid;
mod layout;
mod limit;
mod moving;
mod params;
mod patches;
mod pool;
mod primvars;
mod size;
mod step;
mod table;
mod tessellate;
#[cfg(test)]
mod test_meshes;
mod tri;
mod uv;
mod wide;
mod worker;

pub use bilinear::{
    BilinearLayout, bilinear_patch_corners, tessellate_bilinear, tessellate_bilinear_into,
};
pub use grid::side_point;
pub use layout::PatchLayout;
pub use moving::UniformTessellator;
pub use patches::{PatchRef, PatchSet, Unit};
pub use pool::PatchGrids;
pub use primvars::tessellate_primvars;
pub use subdiv_rules::{Depth, MAX_DEPTH};
pub use tessellate::{
    DEFAULT_MAX_DEPTH, MAX_POINTS, SlateError, slate_bytes_per_thread, tessellate,
    tessellate_layout, tessellate_layout_into,
};
pub use tri::{
    TriLayout, TriPatch, TriSide, tessellate_tri, tessellate_tri_layout_into, tri_lattice_index,
    tri_lattice_len, tri_patch_lattice, tri_slate_bytes_per_thread,
};
pub use uv::LevelUvs;
pub use wide::set_simd;
