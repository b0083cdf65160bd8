//! Red-green closure of adaptive Loop subdivision.
//!
//! Adaptive Loop subdivision (Isenberg, Hartmann & König, "Interest Value Driven Adaptive
//! Subdivision", SimVis 2003, §3 and Fig. 1, after Amresh & Farin 2002) splits the selected
//! triangles 1-to-4 ("red"). A triangle that is not selected but has refined neighbours gets new
//! vertices on 1, 2 or 3 of its edges and is split into 2, 3 or 4 triangles so that the mesh
//! stays conforming ("green"). Green triangles are remembered as a [`GreenFamily`] (the parent
//! triangle and the midpoints on its split edges); when a green triangle must be refined in a
//! later step, or gets a new vertex on one of its edges, its family is first merged back into the
//! parent, which is then refined regularly (red). Green triangles are therefore never split
//! again: the topology never nests green splits. That alone does not keep the triangles' shape
//! over many steps, because Loop's vertex rule moves vertices whose rings mix levels and green
//! bisections halve angles; [`balance`] (on by default in [`crate::loop_step`]) keeps the levels
//! 2:1 balanced across vertices and refines red instead of bisecting a small angle green; with
//! it, and every vertex read at the level being refined ([`crate::loop_step`]), the smallest
//! angle stays above half of the cage's on the bunny and the teapot for every DoI over five
//! steps (measured in [`crate::loop_step`]).
//!
//! This module is topology only; where the new vertices go is the caller's business (the
//! adaptive Loop step, [`crate::loop_step`]). One step is:
//!
//! 0. [`balance`] (optional): grow the selection until the levels stay 2:1 balanced and no green
//!    bisection cuts a small angle;
//! 1. [`close`]: from the selected faces, find every face refined in this step (selected faces,
//!    families merged back, triangles whose three edges are split) and every edge that gets a
//!    new midpoint;
//! 2. the caller computes the new vertex positions and numbers the midpoints;
//! 3. [`assemble`]: the triangles of the refined, conforming mesh and the new [`GreenState`].
//!
//! A face whose three edges are split is refined (red), not green. A triangle with two split
//! edges is cut into the corner triangle and a quadrilateral, which is split along its shorter
//! diagonal.

mod assemble;
mod balance;
mod close;
mod green;
#[cfg(test)]
mod tests;

pub use assemble::{Assembly, assemble, split_triangle};
pub use balance::balance;
pub(crate) use balance::smallest_angle;
pub use close::{Closure, close};
pub(crate) use green::FamilyFaces;
pub use green::{GreenFamily, GreenState, NO_FAMILY};
