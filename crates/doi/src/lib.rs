//! `subdiv-doi`: Degree-of-Interest functions and DoI-driven adaptive Loop subdivision.
//!
//! After T. Isenberg, K. Hartmann and H. König, "Interest Value Driven Adaptive Subdivision",
//! Simulation und Visualisierung 2003 (all of §3 and §4).
//!
//! - The framework ([`Doi`], [`DoiContext`], [`Aggregate`], [`face_values`]): a DoI assigns
//!   values to the faces, edges or vertices of a triangle mesh; face values come directly, or
//!   from edges/vertices by max (default), average or min; a face is refined when its value
//!   exceeds the threshold. DoIs are evaluated before every step; static DoIs are cached across
//!   frames by [`Refiner`], view-dependent ones re-evaluated.
//! - The adaptive Loop step ([`loop_step`], [`refine_adaptive`]) with the red-green closure of
//!   `subdiv_stitch::red_green`: conforming output, and exactly uniform Loop when every face is
//!   selected.
//! - The DoIs of the paper: [`ViewAngle`] (eq. 1), [`Silhouette`] (eq. 2), [`Dihedral`]
//!   (eq. 3), [`HapticG1`] (Clough-Tocher G¹ error, eqs. 4–6) and [`HapticPoint`], [`Focus`]
//!   (eq. 7).
//! - [`depths_from_face_values`]: the same DoI driving per-patch Catmull-Clark depths.
//!
//! ```
//! use subdiv_doi::{refine_adaptive, Aggregate, DoiContext, RefineOptions, Silhouette};
//! use subdiv_mesh::{parse_obj, Camera, Mesh, glam::Vec3};
//! let oct = Mesh::from_soup(&parse_obj("v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n\
//!     f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n")?)?;
//! let cam = Camera::new(Vec3::new(0.3, 0.2, 10.0), Vec3::ZERO, Vec3::Y, 30.0, 640, 480);
//! let opts = RefineOptions { threshold: 0.5, steps: 3, aggregate: Aggregate::Max };
//! let r = refine_adaptive(&oct, &Silhouette, &DoiContext::with_camera(cam), &opts)?;
//! assert!(r.mesh.mesh.num_faces() < 8 * 64); // fewer than uniform Loop
//! assert!(r.mesh.mesh.edges().all(|e| !r.mesh.mesh.is_boundary_edge(e))); // still closed
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod adaptive;
mod depth;
mod dihedral;
mod error;
mod focus;
mod framework;
mod haptic;
mod triangulate;
mod view;

pub use adaptive::{
    AdaptiveMesh, MAX_TRIANGLES, RefineOptions, Refined, Refiner, StepStats, check_triangles,
    loop_step, refine_adaptive,
};
pub use depth::depths_from_face_values;
pub use dihedral::{Dihedral, dihedral_angle_deg};
pub use error::DoiError;
pub use focus::{Focus, FocusObject, FocusShape, parse_skeleton, polyline_distance, read_skeleton};
pub use framework::{Aggregate, Doi, DoiContext, Domain, aggregate_to_faces, face_values, select};
pub use haptic::{
    CloughTocher, CubicTriangle, HapticG1, HapticPoint, barycentric_combination, bezier_index,
    closest_face, closest_point_on_triangle, clough_tocher_patches, edge_g1_error, g1_error,
    vertex_normals,
};
pub use triangulate::triangulate;
pub use view::{
    Silhouette, ViewAngle, face_normals, is_silhouette, point_segment_distance,
    silhouette_distance, silhouette_segments, view_angle_deg,
};

/// The DoIs by command-line name, with their defaults.
pub const DOI_NAMES: [&str; 5] = ["view-angle", "silhouette", "dihedral", "haptic", "focus"];
