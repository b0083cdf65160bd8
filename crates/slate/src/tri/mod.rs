//! Loop on triangular slates: the design of Settgast et al. §3.2 for the box-spline patches of
//! Loop subdivision.
//!
//! Every cage triangle is a patch. Its 1-neighbourhood (the triangle, the vertex beyond each of
//! its sides and the full ring of each corner) is gathered into a triangular slate of
//! `(2^d + 1)(2^d + 2) / 2` points plus the ring around them (`worker`), subdivided level by
//! level into the other slate, and the limit points and normals of the last level are evaluated
//! (`limit`).
//!
//! - **Regular interior** (every point not a corner, along smooth interior sides too): Loop's
//!   box-spline rules in their fastest form (`subdiv_rules::loop_scheme::regular_vertex_point`,
//!   `smooth_edge_point`, `regular_limit`), one pass over the whole child triangle.
//! - **Corners** of any valence: a smooth interior corner refines its ring in `f32` with the
//!   smooth rules; every other corner (boundary, crease, dart, corner tag, vertex sharpness) is
//!   a `subdiv_rules::Ring`, refined and evaluated exactly (semi-sharp creases included).
//! - **Creased and boundary sides**: the general vertex and edge rules of `subdiv-rules`
//!   (`VertexRules`, `edge_crease_weight`, uniform and Chaikin decay) at the side's points; their
//!   limits by `Ring::limit_sided`, exact for semi-sharp creases.
//!
//! **Invariants:** the cage is never modified; every output point has exactly one owner patch
//! (`layout`), which alone writes it; the output is identical for any thread count.

mod layout;
mod limit;
mod patch;
mod tessellate;
mod worker;

pub use layout::{TriLayout, TriPatch, TriSide};
pub use patch::{tri_lattice_index, tri_lattice_len, tri_patch_lattice};
pub use tessellate::{tessellate_tri, tessellate_tri_layout_into, tri_slate_bytes_per_thread};
