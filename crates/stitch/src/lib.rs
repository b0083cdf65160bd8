//! `subdiv-stitch`: gap-free assembly of adaptively refined meshes.
//!
//! The Catmull-Clark patches of a frame are tessellated at different depths (Settgast et al.
//! 2004, §3.1); this crate closes the gaps between them with triangle fans (§3.3, Figs. 4 and
//! 10): quads next to a deeper neighbour are replaced by fans around the limit point of the next
//! level's face point, through the deeper side's own points, with the shared edge of two replaced
//! quads subdivided once more ([`FanMethod::Subdivided`]) or not ([`FanMethod::Simple`]).
//! [`Assembler`] keeps each patch's tessellation between frames and recomputes only patches whose
//! depth rose. Loop's triangular patches are joined the same way by [`TriAssembler`] (module
//! [`tri`]): fans from the coarser patch's lattice points through the finer side's points.
//! Bilinear patches (`Assembler::bilinear`) are the Catmull-Clark units' faces with bilinear
//! points, joined as those are, every cage edge a crease.
//! Both write an [`AdaptiveFrame`]: the frame's surface as a triangle-list
//! [`LimitMesh`](subdiv_rules::LimitMesh) (the output type of every tessellator, its scalar the
//! depth of each vertex's patch) and the depth of each cage face.
//!
//! **Invariants.** Watertight to the bit: every point shared by two patches is written by one
//! owner (the deeper side) and referenced through it, so after assembly every interior edge has
//! exactly two triangles and the only open edges are the cage's boundary (and its holes). The
//! cage is never modified. A frame's index buffer is emitted in runs of patches, and a run
//! whose state stayed keeps its triangles from the last frame, bit for bit what emitting it
//! again gives (module `runs`).

pub mod fans;
mod primvars;
mod runs;
mod slots;
pub mod tri;

pub use fans::{AdaptiveFrame, Assembler, FanMethod, MAX_ADAPTIVE_DEPTH, UpdateParts};
pub use primvars::frame_primvars;
pub use tri::TriAssembler;

/// Errors of the assembly ([`Assembler`], [`TriAssembler`]).
#[derive(Debug, thiserror::Error)]
pub enum AssemblyError {
    /// Set-up of the patches failed.
    #[error(transparent)]
    Rules(#[from] subdiv_rules::RulesError),
    /// The requested maximum depth exceeds what the slates support.
    #[error("maximum depth {depth} exceeds {max}")]
    TooDeep {
        /// Requested.
        depth: subdiv_slate::Depth,
        /// Supported.
        max: subdiv_slate::Depth,
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
    /// Every face at the maximum depth would not fit in this machine's memory: refused before
    /// allocating, with the size asked for ([`subdiv_rules::budget`]: an upper bound).
    #[error(transparent)]
    OutputTooLarge(#[from] subdiv_rules::OutputTooLarge),
    /// The frame broke an invariant of its surface (an assembler bug, not the cage's).
    #[error(transparent)]
    Output(#[from] subdiv_rules::LimitMeshError),
    /// A frame buffer could not be allocated.
    #[error(transparent)]
    OutOfMemory(#[from] subdiv_rules::OutOfMemory),
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
