//! Errors of adaptive Loop refinement.

use thiserror::Error;

/// What can go wrong in adaptive Loop refinement: input that is not a triangle mesh, a
/// selection or closure inconsistent with the mesh, or a result too large.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum RedGreenError {
    /// Adaptive Loop refinement works on triangles ([`subdiv_mesh::MeshError::NotTriangles`]).
    #[error(transparent)]
    Mesh(#[from] subdiv_mesh::MeshError),
    /// A per-element array does not match the mesh.
    #[error("{what} has {got} entries but the mesh has {want}")]
    LengthMismatch {
        /// Which array.
        what: &'static str,
        /// Its length.
        got: usize,
        /// The expected length.
        want: usize,
    },
    /// A face names a family that does not exist.
    #[error("face {face} belongs to green family {family}, but there are only {count} families")]
    FamilyOutOfRange {
        /// The face.
        face: u32,
        /// The family index.
        family: u32,
        /// Number of families.
        count: u32,
    },
    /// A family's unsplit parent edge is not an edge of the mesh.
    #[error("green family {family}: parent edge {a}-{b} is not an edge of the mesh")]
    BrokenFamily {
        /// The family.
        family: u32,
        /// Endpoint.
        a: u32,
        /// Endpoint.
        b: u32,
    },
    /// A split edge has no midpoint, or a midpoint is not a vertex.
    #[error("edge {edge}: midpoint {mid} is missing or not among the {count} vertices")]
    BadMidpoint {
        /// The edge.
        edge: u32,
        /// The midpoint given (u32::MAX when missing).
        mid: u32,
        /// Number of vertex positions.
        count: u32,
    },
    /// A face that is kept unchanged has a split edge (the closure was not computed by [`close`](crate::red_green::close)).
    #[error("face {face} is kept but its edge {edge} is split; the closure is inconsistent")]
    Inconsistent {
        /// The face.
        face: u32,
        /// The split edge.
        edge: u32,
    },
    /// The step would produce too many triangles.
    #[error("the step would produce {faces} triangles (limit {limit})")]
    TooLarge {
        /// Triangles it would produce.
        faces: u64,
        /// The limit ([`crate::MAX_TRIANGLES`]).
        limit: u64,
    },
    /// The step could not fit in this machine's memory (every triangle refined): refused before
    /// allocating, with the size asked for ([`subdiv_rules::budget`]).
    #[error(transparent)]
    OutputTooLarge(#[from] subdiv_rules::OutputTooLarge),
    /// A corner of a refined triangle has no face-varying value (a bug: every corner is a
    /// parent corner or a split edge's midpoint).
    #[error("internal error: corner at vertex {vertex} of a triangle from face {face} has no UV")]
    UvCorner {
        /// The face of the input mesh the triangle comes from.
        face: u32,
        /// The corner's vertex in the refined mesh.
        vertex: u32,
    },
    /// The pairs of floats of a face-varying primvar refined to different corners (a bug:
    /// every pair shares the primvar's seams and the pass's topology).
    #[error("internal error: primvar '{name}': its floats refined to different corners")]
    PrimvarCorners {
        /// The primvar.
        name: String,
    },
    /// A refined mesh failed validation (a bug: the closure keeps the mesh valid).
    #[error("internal error: the refined mesh is invalid: {0}")]
    Internal(subdiv_mesh::MeshError),
}

/// Refuses an array whose length differs from the mesh's element count.
pub(crate) fn check_len(what: &'static str, got: usize, want: usize) -> Result<(), RedGreenError> {
    if got != want {
        return Err(RedGreenError::LengthMismatch { what, got, want });
    }
    Ok(())
}
