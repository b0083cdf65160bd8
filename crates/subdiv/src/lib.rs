//! `subdiv`: the library front door of the subdiv workspace.
//!
//! Adaptive, view-dependent, crack-free tessellation of Catmull-Clark and Loop subdivision
//! surfaces, after Settgast, Müller, Fünfzig & Fellner, "Adaptive Tessellation of Subdivision
//! Surfaces" (2004), and Isenberg, Hartmann & König, "Interest Value Driven Adaptive
//! Subdivision" (2003). This crate wires the concern crates together for programs — the `subdiv`
//! command, the viewer, the figures — and re-exports them:
//!
//! | crate | concern |
//! |---|---|
//! | [`mesh`] | half-edge mesh, OBJ, camera, geometric helpers |
//! | [`rules`] | Catmull-Clark and Loop rules, the refinement kernel, exact limits |
//! | [`slate`] | per-patch two-slate tessellation |
//! | [`depth`] | per-patch depths: curvature, classification, projected size, pixel error, frame-rate control |
//! | [`stitch`] | gap-free fans between patch depths |
//! | [`adaptive_loop`] | adaptive Loop refinement of a face selection, red-green closure |
//! | [`doi`] | Degree-of-Interest functions |
//! | [`vk`] | the Vulkan renderer (plain buffers) |
//!
//! What lives here: [`DynamicSubdivision`] (the paper's per-frame `DynamicSubdivisionCC` node)
//! and [`chord_deviations`]; DoI-driven refinement ([`refine_adaptive`], [`Refiner`]).
//!
//! **Invariants.** Nothing here changes a cage the caller passed in; every frame's geometry is
//! watertight to the bit (shared points are referenced through one owner patch); errors are
//! typed and name the element at fault.
//!
//! # Uniform tessellation
//! ```
//! use subdiv::{mesh::parse_obj, mesh::Mesh, rules::Scheme, slate::tessellate};
//! let cube = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
//!             f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
//! let mesh = Mesh::from_soup(&parse_obj(cube)?)?;
//! let limit = tessellate(&mesh, 3)?; // exact limit points and normals, 6 * 64 quads
//! assert_eq!(limit.num_faces(), 6 * 64);
//! # let _ = Scheme::CatmullClark;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Per-frame adaptive tessellation
//! ```
//! use subdiv::{DynamicSubdivision, depth::DepthParams, mesh::{Camera, parse_obj, Mesh, glam::Vec3}};
//! let cube = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
//!             f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
//! let mut node = DynamicSubdivision::new(Mesh::from_soup(&parse_obj(cube)?)?, DepthParams::default())?;
//! let (lo, hi) = node.mesh().bounds();
//! let camera = Camera::eye_relative(lo, hi, Vec3::new(0.8, 0.5, 2.2), 45.0, 800, 600);
//! let frame = node.update(&camera, None)?; // back faces stay coarse, fans close the gaps
//! assert!(frame.num_triangles() < node.uniform_triangles());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # DoI-driven refinement
//! ```
//! use subdiv::{refine_adaptive, RefineOptions};
//! use subdiv::doi::{Aggregate, Dihedral, DoiContext};
//! use subdiv::mesh::{parse_obj, Mesh};
//! let tet = Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n\
//!     f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n")?)?;
//! let opts = RefineOptions { threshold: 30.0, steps: 2, aggregate: Aggregate::Max };
//! let refined = refine_adaptive(&tet, &Dihedral, &DoiContext::default(), &opts)?;
//! assert!(refined.mesh.mesh.num_faces() <= 4 * 16);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod dynamic;
pub mod quality;
mod refine;

pub use dynamic::{DynamicSubdivision, chord_deviations};
pub use refine::{RefineError, RefineOptions, Refined, Refiner, refine_adaptive};

pub use subdiv_depth as depth;
pub use subdiv_doi as doi;
pub use subdiv_loop as adaptive_loop;
pub use subdiv_mesh as mesh;
pub use subdiv_rules as rules;
pub use subdiv_slate as slate;
pub use subdiv_stitch as stitch;
pub use subdiv_vk as vk;
