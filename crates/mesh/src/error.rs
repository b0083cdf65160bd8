//! Typed errors for building and reading meshes. Every variant names the offending element and,
//! when the input came from a file, its 1-based source line.

use thiserror::Error;

/// A problem found while building a mesh from a polygon soup or reading an OBJ file.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MeshError {
    /// A syntax error in an OBJ line.
    #[error("{msg}")]
    Parse {
        /// 1-based line.
        line: u32,
        /// What is wrong.
        msg: String,
    },
    /// The mesh has no faces.
    #[error("the mesh has no faces")]
    Empty,
    /// A triangle mesh was needed (Loop subdivision, red-green closure, the triangle DoIs).
    #[error(
        "face {face} has {size} vertices; Loop subdivision needs a triangle mesh (triangulate it first)"
    )]
    NotTriangles {
        /// The first non-triangular face.
        face: u32,
        /// Its vertex count.
        size: u32,
    },
    /// A face refers to a vertex that does not exist.
    #[error("face {face}: vertex index {index} is out of range (the mesh has {count} vertices)")]
    IndexOutOfRange {
        /// Face index (0-based).
        face: u32,
        /// The bad index as written (0-based after OBJ conversion; negative OBJ indices are resolved).
        index: i64,
        /// Number of vertices.
        count: u32,
        /// 1-based line, if known.
        line: Option<u32>,
    },
    /// A face with fewer than three vertices.
    #[error("face {face} has {len} vertices; a face needs at least 3")]
    FaceTooSmall {
        /// Face index.
        face: u32,
        /// Its vertex count.
        len: u32,
        /// 1-based line, if known.
        line: Option<u32>,
    },
    /// A face that lists a vertex twice (degenerate).
    #[error("face {face} uses vertex {vertex} more than once (degenerate face)")]
    RepeatedVertex {
        /// Face index.
        face: u32,
        /// The repeated vertex.
        vertex: u32,
        /// 1-based line, if known.
        line: Option<u32>,
    },
    /// A vertex coordinate that is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate ({x}, {y}, {z})")]
    NonFinite {
        /// Vertex index.
        vertex: u32,
        /// Coordinates as read.
        x: f32,
        /// Coordinates as read.
        y: f32,
        /// Coordinates as read.
        z: f32,
        /// 1-based line, if known.
        line: Option<u32>,
    },
    /// An edge used by more than two faces.
    #[error(
        "edge {a}-{b} is shared by more than two faces (faces {faces:?}); non-manifold meshes are refused"
    )]
    NonManifoldEdge {
        /// Edge endpoint.
        a: u32,
        /// Edge endpoint.
        b: u32,
        /// The faces using it.
        faces: Vec<u32>,
        /// Line of the first face beyond the second, if known.
        line: Option<u32>,
    },
    /// A vertex whose incident faces do not form a single fan (e.g. two cones touching at a tip).
    #[error(
        "vertex {vertex} is non-manifold: its faces form {fans} separate fans; non-manifold meshes are refused (split such vertices with --split-nonmanifold)"
    )]
    NonManifoldVertex {
        /// The vertex.
        vertex: u32,
        /// Number of separate face fans around it.
        fans: u32,
        /// 1-based line of the vertex, if known.
        line: Option<u32>,
    },
    /// Two faces traverse their shared edge in the same direction.
    #[error(
        "faces {face} and {other} traverse edge {a}->{b} in the same direction (inconsistent orientation)"
    )]
    InconsistentOrientation {
        /// Edge start.
        a: u32,
        /// Edge end.
        b: u32,
        /// The later face.
        face: u32,
        /// The earlier face.
        other: u32,
        /// Line of the later face, if known.
        line: Option<u32>,
    },
    /// A crease tag naming two vertices that share no edge.
    #[error("crease tag names edge {a}-{b}, which is not an edge of the mesh")]
    TagMissingEdge {
        /// Endpoint.
        a: u32,
        /// Endpoint.
        b: u32,
        /// 1-based line of the tag, if known.
        line: Option<u32>,
    },
    /// A tag naming a vertex that does not exist.
    #[error("{tag} tag names vertex {vertex}, but the mesh has {count} vertices")]
    TagMissingVertex {
        /// Tag name.
        tag: &'static str,
        /// The vertex.
        vertex: i64,
        /// Number of vertices.
        count: u32,
        /// 1-based line of the tag, if known.
        line: Option<u32>,
    },
    /// A hole tag naming a face that does not exist.
    #[error("hole tag names face {face}, but the mesh has {count} faces")]
    TagMissingFace {
        /// The face.
        face: i64,
        /// Number of faces.
        count: u32,
        /// 1-based line of the tag, if known.
        line: Option<u32>,
    },
    /// A sharpness value that is NaN, infinite or negative.
    #[error("{tag} tag has invalid sharpness {value} (must be a finite number >= 0)")]
    BadSharpness {
        /// Tag name.
        tag: &'static str,
        /// The value.
        value: f32,
        /// 1-based line of the tag, if known.
        line: Option<u32>,
    },
    /// A face corner names a texture coordinate (`vt`) that does not exist.
    #[error(
        "face {face}: the texture index {index} of vertex {vertex} is out of range (the mesh has {count} texture coordinates)"
    )]
    UvIndexOutOfRange {
        /// Face index (0-based).
        face: u32,
        /// The vertex of the corner (0-based, as written).
        vertex: i64,
        /// The bad texture index (0-based).
        index: i64,
        /// Number of texture coordinates.
        count: u32,
        /// 1-based line, if known.
        line: Option<u32>,
    },
    /// Face-varying indices were given for some face corners but not all.
    #[error("{indices} face-varying indices for {corners} face corners (need one per corner)")]
    UvCount {
        /// Number of face-varying indices.
        indices: u64,
        /// Number of face corners.
        corners: u64,
    },
    /// A texture coordinate that is NaN or infinite.
    #[error("texture coordinate {index} is not finite ({u}, {v})")]
    NonFiniteUv {
        /// Its index (0-based).
        index: u32,
        /// As given.
        u: f32,
        /// As given.
        v: f32,
    },
    /// A primvar whose values do not fit the mesh (a count, an index, a value).
    #[error("primvar {name}: {msg}")]
    Primvar {
        /// The primvar's name.
        name: String,
        /// What is wrong.
        msg: String,
    },
    /// Too many elements for 32-bit handles.
    #[error("the mesh is too large: {what}")]
    TooLarge {
        /// What overflowed.
        what: String,
    },
}

impl MeshError {
    /// The 1-based source line the error refers to, when the input came from a file.
    pub fn line(&self) -> Option<u32> {
        match self {
            MeshError::Parse { line, .. } => Some(*line),
            MeshError::Empty
            | MeshError::TooLarge { .. }
            | MeshError::NotTriangles { .. }
            | MeshError::UvCount { .. }
            | MeshError::Primvar { .. }
            | MeshError::NonFiniteUv { .. } => None,
            MeshError::IndexOutOfRange { line, .. }
            | MeshError::FaceTooSmall { line, .. }
            | MeshError::RepeatedVertex { line, .. }
            | MeshError::NonFinite { line, .. }
            | MeshError::NonManifoldEdge { line, .. }
            | MeshError::NonManifoldVertex { line, .. }
            | MeshError::InconsistentOrientation { line, .. }
            | MeshError::TagMissingEdge { line, .. }
            | MeshError::TagMissingVertex { line, .. }
            | MeshError::TagMissingFace { line, .. }
            | MeshError::BadSharpness { line, .. }
            | MeshError::UvIndexOutOfRange { line, .. } => *line,
        }
    }
}

/// An error reading or writing a mesh file: I/O, or a [`MeshError`] located in the file.
///
/// Each cause is printed once: `Io` displays only the file and hands the I/O error out through
/// [`std::error::Error::source`] (print the chain, e.g. `anyhow`'s `{:#}`, to see it); `Invalid`
/// displays `FILE:LINE: what` in full and has no source.
#[derive(Debug, Error)]
pub enum ObjError {
    /// The file could not be read or written.
    #[error("{path}")]
    Io {
        /// The file.
        path: String,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The file's content is invalid.
    #[error("{path}:{}{err}", .err.line().map(|l| format!("{l}: ")).unwrap_or_else(|| " ".into()))]
    Invalid {
        /// The file.
        path: String,
        /// What is wrong, with its line.
        err: MeshError,
    },
}

/// An error reading a USD stage: every variant names the file, and the prim and attribute when
/// there is one. Each cause is printed once (`Io` hands the I/O error out as its source).
#[derive(Debug, Error)]
pub enum UsdError {
    /// The file could not be read.
    #[error("{path}")]
    Io {
        /// The file.
        path: String,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The stage could not be opened or composed (the `openusd` reader's message).
    #[error("{path}: cannot read the USD stage: {msg}")]
    Open {
        /// The file.
        path: String,
        /// What the reader said.
        msg: String,
    },
    /// The stage has no active `Mesh` prim.
    #[error("{path}: the stage has no Mesh prim")]
    NoMesh {
        /// The file.
        path: String,
    },
    /// The prim asked for is not a mesh of the stage.
    #[error("{path}: prim {prim}: {found} (meshes: {meshes})")]
    NoSuchMesh {
        /// The file.
        path: String,
        /// The prim asked for.
        prim: String,
        /// What is at that path.
        found: String,
        /// The mesh prims of the stage.
        meshes: String,
    },
    /// An attribute with a wrong type, an unsupported value or inconsistent counts.
    #[error("{path}: {prim}: {attr}: {msg}")]
    Attribute {
        /// The file.
        path: String,
        /// The prim.
        prim: String,
        /// The attribute.
        attr: String,
        /// What is wrong.
        msg: String,
    },
    /// The prim's topology or tags are refused by validation (faces and vertices are the
    /// prim's own).
    #[error("{path}: {prim}: {attr}: {err}")]
    Invalid {
        /// The file.
        path: String,
        /// The prim (the prims, space-separated, when the merged cage is refused).
        prim: String,
        /// The attribute the error is about.
        attr: &'static str,
        /// What is wrong.
        err: MeshError,
    },
    /// The `openusd` reader panicked on this file: a defect of the third-party parser, caught at
    /// this crate's boundary so that the caller gets an error instead of an unwinding thread.
    #[error("{path}: the USD reader failed while {doing}: {msg}")]
    ReaderPanic {
        /// The file.
        path: String,
        /// What was being read (`opening the stage`, `reading prim /World/Mesh`, ...).
        doing: String,
        /// The panic's message and where in the reader it was raised.
        msg: String,
    },
    /// A time code that is not a number (NaN or infinite).
    #[error("{path}: time {time} is not a finite time code")]
    Time {
        /// The file.
        path: String,
        /// The time asked for.
        time: f64,
    },
    /// Merged prims disagree on an attribute that subdiv keeps per mesh.
    #[error("{path}: {attr} differs between {a} and {b}; read one mesh with --prim")]
    Mixed {
        /// The file.
        path: String,
        /// The attribute.
        attr: &'static str,
        /// The first prim and its value.
        a: String,
        /// The disagreeing prim and its value.
        b: String,
    },
}
