//! `subdiv-doi`: Degree-of-Interest functions and their aggregation.
//!
//! After T. Isenberg, K. Hartmann and H. König, "Interest Value Driven Adaptive Subdivision",
//! Simulation und Visualisierung 2003 (all of §3 and §4).
//!
//! - The framework ([`Doi`], [`DoiContext`], [`Aggregate`], [`face_values`]): a DoI assigns
//!   values to the faces, edges or vertices of a triangle mesh; face values come directly, or
//!   from edges/vertices by max (default), average or min; a face is refined when its value
//!   exceeds the threshold. DoIs are evaluated before every step; static DoIs are cached across
//!   frames by `subdiv::Refiner`, view-dependent ones re-evaluated.
//! - The DoIs of the paper: [`ViewAngle`] (eq. 1), [`Silhouette`] (eq. 2), [`Dihedral`]
//!   (eq. 3), [`Haptic`] (Clough-Tocher G¹ error, eqs. 4–6, and the one-side criterion;
//!   [`HapticG1`] alone) and [`HapticPoint`], [`Focus`]
//!   (eq. 7); and a vertex-valued one, [`Curvature`] (the normal's turn at each vertex).
//! - [`DoiKind`]: the DoIs a program chooses by name, the one home of those names.
//!
//! This crate computes interest values only. What is refined with them lives elsewhere:
//! `subdiv-redgreen` refines a face selection adaptively, `subdiv-depth` maps face values to
//! per-patch Catmull-Clark depths, and the `subdiv` front door wires a DoI to either
//! (`subdiv::refine_adaptive`, `subdiv::Refiner`).
//!
//! **Invariants.** Every DoI returns exactly one finite-or-infinite, never NaN, value per
//! element of its [`Domain`] ([`face_values`] checks count and NaN); view-dependent DoIs refuse
//! a context without a camera; nothing here modifies a mesh.
//!
//! ```
//! use subdiv_doi::{face_values, select, Aggregate, DoiContext, Silhouette};
//! use subdiv_mesh::{parse_obj, Camera, Mesh, glam::Vec3};
//! let oct = Mesh::from_soup(&parse_obj("v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n\
//!     f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n")?)?;
//! let cam = Camera::new(Vec3::new(0.3, 0.2, 10.0), Vec3::ZERO, Vec3::Y, 30.0, 640, 480);
//! let ctx = DoiContext::with_camera(cam);
//! // Silhouette edges (eq. 2) are 1, others 0; a face takes the maximum of its edges. Seen
//! // almost along z, the silhouette runs round the equator, which every face touches.
//! let (mut scratch, mut values, mut selected) = (Vec::new(), Vec::new(), Vec::new());
//! face_values(&Silhouette, &oct, &ctx, Aggregate::Max, &mut scratch, &mut values)?;
//! select(&values, 0.5, &mut selected);
//! assert_eq!(selected, vec![true; 8]);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod clough_tocher;
mod curvature;
mod curve_skeleton;
mod dihedral;
mod error;
mod focus;
mod framework;
mod haptic;
mod kind;
mod skeleton;
mod view;

pub use clough_tocher::{CloughTocher, CubicTriangle, bezier_index, clough_tocher_patches};
pub use curvature::Curvature;
pub use curve_skeleton::{BANDS, curve_skeleton};
pub use dihedral::{Dihedral, dihedral_angle_deg};
pub use error::DoiError;
pub use focus::{Focus, FocusObject, FocusShape, FocusSpec};
pub use framework::{Aggregate, Doi, DoiContext, Domain, aggregate_to_faces, face_values, select};
pub use haptic::{
    Combination, DEGENERATE_G1_ERROR, Haptic, HapticG1, HapticPoint, barycentric_combination,
    closest_face, closest_surface_point, edge_g1_error, g1_error, mean_edge_length, plane_crossing,
};
pub use kind::DoiKind;
pub use skeleton::{
    parse_skeleton, polyline_distance, principal_axis_skeleton, read_skeleton, segment_distance,
    triangle_polyline_distance, triangle_segment_distance,
};
pub use view::{
    Silhouette, ViewAngle, is_silhouette, point_segment_distance, silhouette_distance,
    silhouette_segments, view_angle_deg,
};
