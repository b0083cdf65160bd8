//! Crack-free assembly of Catmull-Clark patches tessellated at different depths.
//!
//! Settgast, Müller, Fünfzig and Fellner, "Adaptive Tessellation of Subdivision Surfaces",
//! Section 3.3 and Figs. 4 and 10. Every cage face (a *unit*: one patch, or the level-1 quads of
//! an n-gon) has a depth per frame. Where a unit borders a deeper one, the chord quads along that
//! border are replaced by triangle fans around the limit point of the quad's face point one level
//! down, through the deeper side's own border points. If two neighbouring quads of the same patch
//! are replaced, their shared edge is subdivided too and its limit point joins both fans (the
//! extra step that prevents buckles; [`FanMethod::Simple`] leaves it out, reproducing the
//! paper's Fig. 10 comparison).
//!
//! Watertight to the bit: every point on a cage edge or vertex is referenced through one *owner*
//! patch (the deepest side of the edge), so both sides of a border use the same vertex.
//!
//! Caching (Section 4): each patch keeps its limit points in a block computed at some depth
//! `c`; while the patch's depth does not rise above `c` the block is reused (sampled with
//! stride `2^(c - d)`), and only the index buffer is rebuilt; in it, a run of patches whose
//! state (the depths and blocks of the faces around them) stayed keeps its triangles.
//!
//! The pieces: [`Assembler`] (the per-mesh patch structure and block cache, `assembler`),
//! [`AdaptiveFrame`] (what a frame produced: its surface and depths, `geometry`), per-edge resolution and owners and the
//! point ids derived from them (`edges`), index-buffer emission with plain quads and fans
//! ([`FanMethod`], `index`), and grid coordinates of patch sides (`grid`).

mod assembler;
mod edges;
mod geometry;
mod grid;
mod index;

#[cfg(test)]
mod bilinear_tests;
#[cfg(test)]
pub(crate) mod test_util;

pub(crate) use assembler::check_corners;
pub use assembler::{Assembler, MAX_ADAPTIVE_DEPTH};
pub(crate) use geometry::lap;
pub use geometry::{AdaptiveFrame, UpdateParts};
pub use index::FanMethod;
