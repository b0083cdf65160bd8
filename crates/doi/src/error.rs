//! Errors of the DoI functions.

use thiserror::Error;

/// What can go wrong evaluating a DoI. Every variant names the face,
/// vertex, group, file or line at fault.
#[derive(Debug, Error)]
pub enum DoiError {
    /// A view-dependent DoI was evaluated without a camera.
    #[error("the {doi} DoI is view-dependent and needs a camera")]
    NeedsCamera {
        /// The DoI's name.
        doi: &'static str,
    },
    /// The haptic interaction point DoI was evaluated without a haptic interaction point.
    #[error("the {doi} DoI needs a haptic interaction point")]
    NeedsHip {
        /// The DoI's name.
        doi: &'static str,
    },
    /// A focus object name that is no group or object of the mesh.
    #[error("no group or object named '{name}' in the mesh; available: {}", list_or_none(.available))]
    UnknownFocus {
        /// The name asked for.
        name: String,
        /// The mesh's groups.
        available: Vec<String>,
    },
    /// The focus DoI got neither objects nor a skeleton.
    #[error("the focus DoI needs at least one focus object (group name) or a skeleton polyline")]
    NoFocus,
    /// A focus object given as `NAME=VALUE` could not be read.
    #[error("focus '{spec}': {msg}")]
    FocusSpec {
        /// What was given.
        spec: String,
        /// What is wrong.
        msg: String,
    },
    /// A named focus group has no faces.
    #[error("focus group '{name}' has no faces")]
    EmptyFocus {
        /// The group.
        name: String,
    },
    /// A skeleton file line that is not a point.
    #[error("{file}:{line}: {msg}")]
    Skeleton {
        /// The file.
        file: String,
        /// 1-based line (0 for the whole file).
        line: u32,
        /// What is wrong.
        msg: String,
    },
    /// A DoI returned the wrong number of values.
    #[error("the {doi} DoI returned {got} values for {want} {domain}")]
    ValueCount {
        /// The DoI's name.
        doi: &'static str,
        /// Values returned.
        got: usize,
        /// Elements in the domain.
        want: usize,
        /// "faces", "edges" or "vertices".
        domain: &'static str,
    },
    /// A DoI value that is NaN.
    #[error("the {doi} DoI gave NaN for {domain} {index}")]
    NanValue {
        /// The DoI's name.
        doi: &'static str,
        /// "face", "edge" or "vertex".
        domain: &'static str,
        /// The element.
        index: u32,
    },
    /// A non-finite threshold, context point or parameter.
    #[error("{what} must be finite (got {value})")]
    NonFinite {
        /// Which parameter.
        what: &'static str,
        /// Its value.
        value: f32,
    },
    /// The mesh is not what the DoI needs (a triangle mesh, for the haptic DoIs).
    #[error(transparent)]
    Mesh(#[from] subdiv_mesh::MeshError),
}

fn list_or_none(v: &[String]) -> String {
    if v.is_empty() {
        "(the mesh has no groups or objects)".to_string()
    } else {
        v.join(", ")
    }
}
