//! `subdiv-depth`: how deep to subdivide each patch.
//!
//! Settgast, Müller, Fünfzig and Fellner, "Adaptive Tessellation of Subdivision Surfaces",
//! Section 3.1: a curvature depth per cage vertex from the cone of normals, computed once per
//! mesh ([`VertexData`]); per frame a back/front/silhouette classification and a projected-size
//! adjustment ([`assign`]), or the least depth within a screen-space error ([`DepthParams::pixel_error`])
//! raised where shading needs it over the whole image ([`shading`], with the pixels along
//! silhouettes: [`contour`]) from what is measured once per cage on the slates' patches
//! ([`patch_errors`], [`patch_errors_tri`]: the one home of the pixel-error mode);
//! one depth for the faces on the copies of a non-manifold edge ([`Seams`]);
//! and frame-rate control by feedback ([`FrameRateController`]). A Degree of Interest can drive
//! the depths instead ([`depths_from_face_values`]).
//!
//! **Invariants.** Depths never exceed the caller's maximum depth; curvature data is computed
//! once per cage (and again only when the cage or the cone aperture changes); per-frame
//! assignment and the controller are pure functions of their inputs (deterministic, no
//! hidden state beyond the controller's own).
//!
//! ```
//! use subdiv_depth::{assign, face_spheres, DepthParams, VertexData};
//! use subdiv_mesh::{parse_obj, Camera, Mesh, glam::Vec3};
//! use subdiv_rules::Scheme;
//! let cube = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
//!             f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
//! let mesh = Mesh::from_soup(&parse_obj(cube)?)?;
//! let params = DepthParams::default();
//! let vd = VertexData::compute(&mesh, Scheme::CatmullClark, params.cone_aperture_deg, params.max_depth);
//! let spheres = face_spheres(&mesh, Scheme::CatmullClark);
//! let cam = Camera::new(Vec3::new(0.5, 0.5, 5.0), Vec3::splat(0.5), Vec3::Y, 45.0, 800, 600);
//! let a = assign(&mesh, &vd, &spheres, None, &cam, &params);
//! assert_eq!(a.depth.len(), 6);
//! // The face at z = 0 looks away from a camera at z = 5: it is not subdivided.
//! assert_eq!(a.depth[0], 0);
//! # Ok::<(), subdiv_mesh::MeshError>(())
//! ```

mod assign;
pub mod contour;
mod controller;
mod curvature;
mod doi;
mod frame_budget;
mod frame_model;
mod patch_error;
mod patch_error_tri;
pub mod pixel_error;
mod seams;
pub mod shading;
mod sphere;

pub use assign::{
    Assignment, Class, DEFAULT_CLASSIFIER_EPS, DEFAULT_CONE_APERTURE_DEG, DEFAULT_PROJECTED_SIZE,
    DEFAULT_SHADING_ERROR_DEG, DepthParams, adjust_projected, assign, classify_vertex, priority,
    projected_radius,
};
pub use controller::FrameRateController;
pub use curvature::{VertexData, bilinear_face_depths};
pub use doi::depths_from_face_values;
pub use frame_budget::{
    BIAS_BAND, BudgetController, Choice, FaceCost, HOLD, SILHOUETTE_PX, capped_back_faces,
    face_errors, silhouette_depths,
};
pub use frame_model::{FrameTimeModel, FrameWork};
pub use patch_error::{SAMPLE_LEVELS, patch_errors};
pub use patch_error_tri::patch_errors_tri;
pub use pixel_error::{
    NormalCone, PatchError, PatchErrors, outside_view, pixel_error_depth, screen_scale,
};
pub use seams::Seams;
pub use shading::{AreaElement, OutlierTable, ScreenArea, ShadingError, raise_for_shading};
pub use sphere::{FaceSpheres, SPHERE_FACE_BUDGET, SPHERE_LEVELS, Sphere, face_spheres};
pub use subdiv_rules::{Depth, MAX_DEPTH};
pub use subdiv_slate::DEFAULT_MAX_DEPTH;
