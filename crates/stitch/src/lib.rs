//! `subdiv-stitch`: gap-free assembly of adaptively refined meshes.
//!
//! Adaptive refinement leaves neighbouring regions at different levels; this crate turns them
//! back into one conforming (crack-free) mesh.
//!
//! - [`red_green`]: the red-green closure of adaptive Loop subdivision (Amresh & Farin 2002, as
//!   used by Isenberg, Hartmann & König, "Interest Value Driven Adaptive Subdivision", 2003,
//!   §3 and Fig. 1): triangles next to refined ("red") triangles are split in 2, 3 or 4
//!   ("green"), and a green triangle that must be refined later is first merged back into its
//!   parent, which is then refined regularly.
//!
//! - [`DynamicSubdivision`]: the front door for view-dependent Catmull-Clark tessellation
//!   (the paper's `DynamicSubdivisionCC` node): cage, curvature depths, cache, parameters, and
//!   `update(&camera, last_frame_time)` per frame.
//! - [`fans`]: Catmull-Clark patches tessellated at different depths, closed by triangle fans
//!   (Settgast et al. 2004, Section 3.3), with per-patch caching across frames ([`Assembler`]).
//!
//! ```
//! use subdiv_mesh::{Mesh, PolygonSoup, glam::Vec3};
//! use subdiv_stitch::red_green::{close, GreenState};
//! // Two triangles sharing an edge; refining the first splits the shared edge, so the second
//! // needs a green closure (one split edge: bisected into two triangles).
//! let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)];
//! let mesh = Mesh::from_soup(&PolygonSoup::from_faces(p, &[[0u32, 1, 2], [1, 3, 2]]))?;
//! let closure = close(&mesh, &GreenState::new(2), &[true, false])?;
//! assert_eq!(closure.red_face, vec![true, false]);
//! assert_eq!(closure.split_edge.iter().filter(|&&s| s).count(), 3);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod dynamic;
pub mod fans;
pub mod red_green;

pub use dynamic::{DynamicSubdivision, chord_deviations};
pub use fans::{Assembler, FanMethod, FrameGeometry};

/// Errors of the Catmull-Clark assembly ([`Assembler`], [`DynamicSubdivision`]).
#[derive(Debug, thiserror::Error)]
pub enum AssemblyError {
    /// Set-up of the patches failed.
    #[error(transparent)]
    Rules(#[from] subdiv_rules::RulesError),
    /// The requested maximum depth exceeds what the slates support.
    #[error("maximum depth {depth} exceeds {max}")]
    TooDeep {
        /// Requested.
        depth: u32,
        /// Supported.
        max: u32,
    },
    /// The frame's patch blocks would not fit in memory.
    #[error(
        "this frame needs {points} cached limit points (limit {})",
        subdiv_slate::MAX_POINTS
    )]
    TooLarge {
        /// Points needed.
        points: u64,
    },
    /// A new vertex position is NaN or infinite.
    #[error("vertex {vertex} has a non-finite position")]
    NonFinite {
        /// The vertex.
        vertex: u32,
    },
    /// A per-unit array has the wrong length.
    #[error("{what} has {got} entries, the mesh has {want} faces")]
    Length {
        /// Which array.
        what: &'static str,
        /// Its length.
        got: usize,
        /// Expected.
        want: usize,
    },
}
