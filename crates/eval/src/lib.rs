//! `subdiv-eval`: the exact Catmull-Clark, Loop and bilinear limit surface at any parameter
//! point of any cage face — position, first and second derivatives, and UVs — one point at a
//! time, a face at a time, or many points in parallel.
//!
//! # Parameterisation
//! A point is `(face, u, v)`: the cage face (0-based, in file order) and `(u, v)` in its
//! [`Domain`], named as OpenSubdiv 3.5's `Bfr::Parameterization` names them: a Catmull-Clark
//! quad is the unit square (`u` along its first edge), a Loop triangle the barycentric
//! triangle, and any other Catmull-Clark face a row-major set of quad sub-face tiles
//! `[x, x + 1/2] x [y, y + 1/2]`, one per corner ([`Domain`] has the details). Derivatives are
//! with respect to these `(u, v)`.
//!
//! # Method
//! The bilinear scheme's surface is the cage's own bilinear patches (a quad's; any other
//! face's sub-faces, its level-1 quads), its UVs linear (`bilinear` module). For the others:
//! exact means the limit surface itself, not an approximating patch. A face's surface
//! ([`FaceSurface`]) starts from the rings of its corners (`subdiv_rules::Ring`: each corner
//! with its whole neighbourhood, creases, Chaikin information and non-manifold copies) and is
//! refined locally, only where a point falls, until the point's sub-patch is regular: then it
//! is the bicubic B-spline (Catmull-Clark) or quartic box spline (Loop) patch of its control
//! points, with phantom points reflected across infinitely sharp edges (boundaries, creases,
//! corners), which reproduces the crease rules exactly. Semi-sharp creases (uniform or
//! Chaikin) are refined until they have decayed, n-gons one level, and around an
//! extraordinary vertex the patches shrink towards it; at the vertex itself the ring's limit
//! masks give the exact limit (refined further where OpenSubdiv's masks are not the limit:
//! darts, valence 2). Every rule and mask is `subdiv-rules`'; this crate writes none.
//!
//! UVs are the limit surface of the *UV cage* (the cage cut along its seams, at its values,
//! with OpenSubdiv's face-varying options as boundary rules: `uv` module docs), evaluated the
//! same way.
//!
//! # Invariants
//! - The cage is never modified; an [`Evaluator`] only reads it.
//! - Every query is checked (face in range, not a hole, `(u, v)` in the domain) before
//!   anything is computed; errors are typed ([`EvalError`]) and name the face.
//! - Results do not depend on the thread count or on which other points are evaluated with
//!   them: a face's refinement is a function of the face alone.
//! - Nothing is allocated per point: a face's refinement is grown once per depth reached and
//!   reused by all its points.
//!
//! ```
//! use subdiv_mesh::{parse_obj, Mesh};
//! use subdiv_rules::Scheme;
//! use subdiv_eval::{Derivatives, Evaluator, Query};
//! let cube = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
//!             f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
//! let mesh = Mesh::from_soup(&parse_obj(cube)?)?;
//! let eval = Evaluator::new(&mesh, Scheme::CatmullClark)?;
//! // The centre of the bottom face lies below the cube's centre, with a downward normal.
//! let s = eval.evaluate(Query::new(0, 0.5, 0.5), Derivatives::First)?;
//! assert!((s.position.x - 0.5).abs() < 1e-12 && s.position.z > 0.0 && s.normal().z < -0.999);
//! let mut out = vec![Default::default(); 2];
//! eval.evaluate_many(&[Query::new(1, 0.0, 0.0), Query::new(2, 0.25, 0.75)], Derivatives::Second, &mut out)?;
//! assert!(eval.evaluate(Query::new(0, 1.5, 0.0), Derivatives::First).is_err());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod basis;
mod bilinear;
mod corner;
mod dice;
mod domain;
mod evaluator;
mod lattice;
mod patch;
mod plan;
mod primvars;
mod surface;
mod tess;
mod uv;

pub use dice::{
    CURVE_SEGMENTS, DEFAULT_DICING_FLATNESS, DEFAULT_OFFSCREEN_DICING_SCALE, Dicing, dice,
    dicing_rates,
};
pub use domain::Domain;
pub use evaluator::{Derivatives, Evaluator, Query, Sample, UvSample, random_queries};
pub use lattice::refined_faces;
pub use primvars::tessellation_primvars;
pub use surface::FaceSurface;
pub use tess::{EdgeRates, ForeignCorner, MAX_RATE, OnCage, Tessellation, tessellate_rates};

use thiserror::Error;

/// Errors of evaluation.
#[derive(Debug, Error)]
pub enum EvalError {
    /// A face index beyond the cage's faces.
    #[error("face {face} does not exist (the cage has {faces} faces)")]
    FaceOutOfRange {
        /// The face asked for.
        face: u32,
        /// The cage's face count.
        faces: u32,
    },
    /// A hole face: it has no limit surface.
    #[error("face {face} is a hole: it has no limit surface")]
    Hole {
        /// The face.
        face: u32,
    },
    /// `(u, v)` outside the face's domain.
    #[error("(u, v) = ({u}, {v}) is outside face {face}'s domain, {domain}")]
    OutsideDomain {
        /// The face.
        face: u32,
        /// First parameter.
        u: f64,
        /// Second parameter.
        v: f64,
        /// The domain, in words.
        domain: String,
    },
    /// The cage cannot be refined under the scheme (Loop needs triangles, no doubled
    /// triangles; coordinates within `subdiv_rules::MAX_COORDINATE`).
    #[error(transparent)]
    Rules(#[from] subdiv_rules::RulesError),
    /// A tessellation's output failed its own checks (a bug).
    #[error("internal error: {0}")]
    Internal(String),
    /// The UV cage (the cage cut along its seams) is not a valid mesh.
    #[error("the UVs' cage (cut along its seams) is invalid: {0}")]
    UvCage(subdiv_mesh::MeshError),
}

#[cfg(test)]
mod bilinear_tests;
#[cfg(test)]
mod tests;
