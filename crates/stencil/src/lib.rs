//! `subdiv-stencil`: limit stencil tables, the uniform tessellation of a moving cage as fixed
//! linear maps of its points.
//!
//! The crate's job: where a cage moves and its topology stays (an animated character), the
//! limit points and derivatives of a uniform tessellation are the same linear functions of the
//! cage points every frame. [`StencilTable`] holds them: built once per topology from
//! `subdiv-eval`'s exact limit (probed, see `table`) and, at cage vertices, from the vertex's
//! ring as the slates take it (`ring`), applied per frame eight points at a time (`apply`). [`StencilTessellator`] is the per-frame product path: the slates lay the cage out
//! and give the first frame's faces, UVs and numbering; the table rewrites points and normals
//! in the same buffers each frame (OpenSubdiv's `LimitStencilTable` does the same, with
//! weights per point where these are shared by a face's points in blocks).
//!
//! # Invariants
//!
//! - **The same points as the slates.** A table is built for the slate layout's numbering
//!   ([`subdiv_slate::UniformTessellator::point_params`]): one stencil per output point,
//!   written by one lane of one block, so shared points are written once and the surface is
//!   watertight to the bit. Positions and normals agree with a fresh slate tessellation of the
//!   same cage to rounding (the tests bound them on deformed cages at `1e-6` of the cage's
//!   size and `1e-4` rad), not to the bit; the frame a layout is made with is the slates' own.
//! - **Output identical for any thread count.** Every point is a sum over its face's support
//!   in a fixed order; tasks only split the faces.
//! - **Nothing allocated per frame** but a task's support buffer.
//! - **Weights exactly as linear as the limit.** Each stencil's position weights sum to 1 and
//!   its derivative weights to 0 (checked when the table is built): a support the probes do
//!   not separate is an error, never a different surface.
//!
//! Where no table is made (holes, non-manifold seams, isolated vertices, primvars, one-sided
//! normals, the bilinear scheme, depth 0, depths beyond [`MAX_STENCIL_DEPTH`], a table beyond
//! [`MAX_TABLE_BYTES`]) the tessellator runs the slates every frame, as
//! [`subdiv_slate::UniformTessellator`] does.
//!
//! ```
//! use subdiv_mesh::{parse_obj, Mesh};
//! use subdiv_rules::Scheme;
//! use subdiv_stencil::StencilTessellator;
//! let cube = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
//!             f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
//! let mut mesh = Mesh::from_soup(&parse_obj(cube)?)?;
//! let mut t = StencilTessellator::new(&mesh, Scheme::CatmullClark, 2).unwrap();
//! assert!(t.stencils().is_some());
//! mesh.positions_mut()[7].z += 0.5; // the next frame
//! let surface = t.update(&mesh).unwrap();
//! assert!(!surface.topology_written()); // only points and normals were rewritten
//! # Ok::<(), subdiv_mesh::MeshError>(())
//! ```

mod apply;
mod balance;
mod moving;
mod ring;
mod share;
mod support;
mod table;

pub use moving::{MAX_STENCIL_DEPTH, StencilTessellator};
pub use table::{MAX_TABLE_BYTES, StencilTable};

/// What can go wrong making or applying a stencil table.
#[derive(Debug, thiserror::Error)]
pub enum StencilError {
    /// The slates refused the cage (its own error names the cause).
    #[error(transparent)]
    Slate(#[from] subdiv_slate::SlateError),
    /// The evaluator refused the cage or a parameter point.
    #[error(transparent)]
    Eval(#[from] subdiv_eval::EvalError),
    /// Parameter points or buffers that do not fit the table.
    #[error("stencil table: {0}")]
    Params(String),
    /// The table would hold more than [`MAX_TABLE_BYTES`] of weights (before faces alike
    /// share theirs).
    #[error("a stencil table of {bytes} bytes (more than {MAX_TABLE_BYTES})")]
    TooLarge {
        /// The weights' size.
        bytes: usize,
    },
    /// A point whose limit the table cannot hold: it is not linear in the cage points of its
    /// face's neighbourhood (checked on a moved cage when the table is built).
    #[error("the limit at point {point} is not a linear map of its face's neighbourhood")]
    Support {
        /// The output point.
        point: u32,
    },
}

#[cfg(test)]
mod tests;
