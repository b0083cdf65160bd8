//! `subdiv-rules`: the Catmull-Clark and Loop subdivision rules and exact limit surfaces.
//!
//! Every rule exists once, as a plain function over a vertex neighbourhood and generic over the
//! point type ([`Point`]): face, edge and vertex points ([`catmark`], [`loop_scheme`]), sharp and
//! semi-sharp creases with the uniform and Chaikin decay, dart/crease/corner vertex rules and
//! their fractional transitions ([`crease`]), and limit position and tangent masks. On top of
//! them sit the exact limit of a single vertex by local ring refinement ([`Ring`],
//! [`limit_point`]), the uniform whole-mesh refinement ([`refine_uniform`]), the uniform
//! depth-N limit tessellation ([`tessellate_uniform`]) and the points on the copies of a
//! non-manifold edge, bit-identical in every copy ([`SeamCurves`]); beside the tessellation's
//! output type ([`LimitMesh`]) its silhouette edges and contours for line drawing
//! ([`Silhouettes`]). [`budget`] estimates the size of every output (exact for uniform depth,
//! bounds for the adaptive paths) and refuses a request beyond this machine's memory with
//! [`OutputTooLarge`] before anything is allocated.
//!
//! Results agree with Pixar's OpenSubdiv 3.5 (boundaries, creases, corners, n-gons, any valence),
//! except that semi-sharp creases always give the true limit surface.
//!
//! ```
//! use subdiv_mesh::{parse_obj, Mesh};
//! use subdiv_rules::{tessellate_uniform, Scheme};
//! let cube = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
//!             f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
//! let mesh = Mesh::from_soup(&parse_obj(cube)?)?;
//! let t = tessellate_uniform(&mesh, Scheme::CatmullClark, 3).unwrap();
//! assert_eq!(t.num_faces(), 6 * 64);
//! # Ok::<(), subdiv_mesh::MeshError>(())
//! ```

pub mod budget;
pub mod catmark;
pub mod crease;
mod fvar;
mod limit;
pub mod loop_scheme;
mod point;
mod refine;
mod ring;
mod seam;
mod silhouettes;

pub use budget::{Budget, OutOfMemory, OutputSize, OutputTooLarge, Request};
pub use fvar::{
    FVarChildren, FVarRegion, face_uvs, limit_face_varying, limit_face_varying_exact,
    refine_face_varying_part, semi_sharp_levels,
};
pub use limit::{
    KeyedWrite, LimitChannel, LimitMesh, LimitMeshError, TopologyKey, TriangleBuffers,
    VertexParams, VertexScalar, bilinear_patches, face_varying_channel, inside_one_patch,
    limit_surface, stand_in_base, subface_tiles_per_row, tessellate_uniform, vertex_channel,
};
pub use point::{Point, centroid};
pub use refine::{
    MAX_COORDINATE, MAX_REFINED_FACES, RefineKernel, check_coordinates, check_doubled_triangles,
    refine_uniform, refine_uniform_levels, refine_uniform_levels_f64, refined_face_count,
};
pub use ring::{QuadRingStencil, Ring, limit_point, limit_point_with};
pub use seam::SeamCurves;
pub use silhouettes::Silhouettes;

use thiserror::Error;

/// A subdivision depth: how many subdivision steps a face, patch or whole mesh is refined by (0:
/// the cage itself). One type for this quantity across the workspace; "culled" is expressed
/// with `Option<Depth>` or a separate flag, never a sentinel value.
pub type Depth = u8;

/// The deepest tessellation any crate of the workspace produces (a slate table side of
/// `2^12 + 3`; uniform refinement is bounded by face count, [`MAX_REFINED_FACES`], well before).
pub const MAX_DEPTH: Depth = 12;

/// The subdivision scheme.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default, Hash)]
pub enum Scheme {
    /// Catmull-Clark (quads; any polygon input).
    #[default]
    CatmullClark,
    /// Loop (triangles only).
    Loop,
    /// Bilinear (OpenSubdiv's `SCHEME_BILINEAR`): faces split into quads as Catmull-Clark
    /// does, every point placed linearly (vertex points stay, edge points are midpoints, face
    /// points centroids), so the limit surface is the bilinear patch of every quad of the cage
    /// and of every level-1 quad of its other faces (`bilinear.rs`). Sharpness has no effect.
    Bilinear,
}

impl Scheme {
    /// The scheme of a USD mesh's `subdivisionScheme`; `None` for `none` (a polygon mesh, not
    /// a subdivision surface).
    pub fn from_usd(s: subdiv_mesh::UsdScheme) -> Option<Scheme> {
        match s {
            subdiv_mesh::UsdScheme::CatmullClark => Some(Scheme::CatmullClark),
            subdiv_mesh::UsdScheme::Loop => Some(Scheme::Loop),
            subdiv_mesh::UsdScheme::Bilinear => Some(Scheme::Bilinear),
            subdiv_mesh::UsdScheme::None => None,
        }
    }

    /// Whether a step splits every face into quads (Catmull-Clark, bilinear: an n-gon into `n`
    /// quads about a face point) rather than triangles into four (Loop).
    #[inline]
    pub fn splits_to_quads(self) -> bool {
        self != Scheme::Loop
    }
}

impl std::str::FromStr for Scheme {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "catmull-clark" | "catmark" | "cc" => Ok(Scheme::CatmullClark),
            "loop" => Ok(Scheme::Loop),
            "bilinear" => Ok(Scheme::Bilinear),
            _ => Err(format!(
                "unknown scheme '{s}' (expected catmull-clark, loop or bilinear)"
            )),
        }
    }
}

/// Errors of the refinement functions.
#[derive(Debug, Error)]
pub enum RulesError {
    /// Loop subdivision needs triangles ([`subdiv_mesh::MeshError::NotTriangles`]).
    #[error(transparent)]
    NotTriangles(#[from] subdiv_mesh::MeshError),
    /// The requested depth would produce too many faces.
    #[error("depth {depth} would produce {faces} faces (limit {MAX_REFINED_FACES})")]
    TooDeep {
        /// Requested depth.
        depth: Depth,
        /// Faces it would produce.
        faces: u64,
    },
    /// Two triangles on the same three vertices (a closed two-face pillow): Loop refinement would
    /// join their edge points by two parallel edges, which a mesh cannot hold.
    #[error(
        "faces {face} and {other} are triangles on the same three vertices; Loop subdivision cannot refine such a two-face pillow"
    )]
    DoubledTriangle {
        /// The later face.
        face: u32,
        /// The earlier face on the same vertices.
        other: u32,
    },
    /// A cage coordinate beyond [`MAX_COORDINATE`]: the `f32` sums of subdivision would
    /// overflow to infinite points.
    #[error(
        "vertex {vertex} has a coordinate beyond ±1e30 ({x}, {y}, {z}); subdivision would overflow (scale the model down)"
    )]
    HugeCoordinate {
        /// The vertex.
        vertex: u32,
        /// Its position.
        x: f32,
        /// Its position.
        y: f32,
        /// Its position.
        z: f32,
    },
    /// A cage coordinate that is not a number or infinite (a cage whose positions were
    /// rewritten after it was read: parsing refuses them).
    #[error("vertex {vertex} has a coordinate that is not a finite number ({x}, {y}, {z})")]
    NonFiniteCoordinate {
        /// The vertex.
        vertex: u32,
        /// Its position.
        x: f32,
        /// Its position.
        y: f32,
        /// Its position.
        z: f32,
    },
    /// The output would not fit in this machine's memory (or a caller's triangle limit): refused
    /// before allocating, with the size asked for ([`budget`]).
    #[error(transparent)]
    OutputTooLarge(#[from] OutputTooLarge),
    /// A big buffer could not be allocated.
    #[error(transparent)]
    OutOfMemory(#[from] OutOfMemory),
    /// A refined mesh failed validation (a bug: refinement of a valid mesh is valid).
    #[error("internal error: refined mesh is invalid: {0}")]
    Internal(subdiv_mesh::MeshError),
}
