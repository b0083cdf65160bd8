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
//! | [`eval`] | exact evaluation at any `(face, u, v)`: position, derivatives, UVs |
//! | [`depth`] | per-patch depths: curvature, classification, projected size, pixel error, frame-rate control |
//! | [`stitch`] | gap-free fans between patch depths |
//! | [`redgreen`] | adaptive Loop refinement of a face selection, red-green closure |
//! | [`doi`] | Degree-of-Interest functions |
//! | [`vk`] | the Vulkan renderer (plain buffers) |
//!
//! What lives here is wiring only — everything the `subdiv` command, the viewer and the figures
//! share; the algorithms live in the concern crates (the pixel-error mode's measurement and the
//! seam depths in [`depth`], silhouettes in [`rules`], sector normals in [`mesh`]; image quality
//! in the `subdiv-quality` crate, which renders through this one):
//! - `dynamic.rs`: [`DynamicSubdivision`] (the paper's per-frame `DynamicSubdivisionCC` node);
//! - `refine.rs`: DoI-driven refinement ([`refine_adaptive`], [`Refiner`]);
//! - `doi_setup.rs`: from a DoI choice and its options ([`doi::DoiKind`]) to a [`Doi`](doi::Doi) and a ready
//!   refinement ([`DoiOptions`], [`DoiSetup`], [`doi_face_depths`]);
//! - `scene.rs`: the uniform tessellation ([`uniform_limit`]) and [`Scene`], the drawing helper
//!   that holds a [`LimitMesh`] in the form the renderer draws (split at one-sided normals) with
//!   its edges, silhouettes and lines; `scene_primvar.rs`: a scene showing a primvar
//!   ([`Scene::show_primvar`], [`PrimvarDisplay`]);
//! - `frame.rs`: summaries of adaptive frames ([`depth_histogram`]);
//! - `camera.rs`: the framing rule ([`framing_box`]: the cage's bounding box, in every mode),
//!   [`Camera`](mesh::Camera) to and from the renderer's [`View`](vk::View) and
//!   [`OrbitCamera`](vk::OrbitCamera) ([`view_for`], [`orbit_camera`], [`camera_from_view`]);
//! - `frame_sources.rs`: the viewer's [`FrameSource`](vk::viewer::FrameSource)s
//!   ([`UniformSource`], [`AdaptiveSource`], [`DoiSource`]); `animated_source.rs`:
//!   [`AnimatedSource`], an animated stage read at each frame's time code, and its playback
//!   ([`stage_playback`]);
//! - `builtin.rs`: built-in scenes ([`BuiltinScene`], [`helmet40`], the paper's Fig. 12);
//! - `export.rs`, `export/`: surface output by extension ([`write_surface`]).
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
//! use subdiv::{refine_adaptive, Balance, RefineOptions};
//! use subdiv::doi::{Aggregate, Dihedral, DoiContext};
//! use subdiv::mesh::{parse_obj, Mesh};
//! let tet = Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n\
//!     f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n")?)?;
//! let opts = RefineOptions { threshold: 30.0, steps: 2, aggregate: Aggregate::Max, balance: Balance::Vertex };
//! let refined = refine_adaptive(&tet, &Dihedral, &DoiContext::default(), &opts)?;
//! assert!(refined.mesh.mesh.num_faces() <= 4 * 16);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Resource limits
//! Every entry point that can produce large output estimates it before allocating
//! ([`rules::budget`]: exact for a uniform depth, a bound for the adaptive path at its maximum
//! depth and for DoI-driven refinement) and refuses a request beyond this machine's memory with
//! [`rules::OutputTooLarge`], which states the size asked for: in
//! [`SceneError::Slate`]/[`SceneError::Rules`] ([`uniform_limit`], [`Scene::uniform`]),
//! [`slate::SlateError::OutputTooLarge`], [`stitch::AssemblyError::OutputTooLarge`]
//! ([`DynamicSubdivision`]), [`RefineError::OutputTooLarge`] ([`refine_adaptive`],
//! [`Refiner`]) and [`rules::RulesError::OutputTooLarge`]. A caller's own limit (the CLI's
//! `--max-triangles`) is a [`rules::Budget`] checked first:
//! ```
//! use subdiv::{mesh::parse_obj, mesh::Mesh, rules::{Budget, Request, Scheme}};
//! let cube = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
//!             f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
//! let mesh = Mesh::from_soup(&parse_obj(cube)?)?;
//! let request = Request::Uniform { scheme: Scheme::CatmullClark, depth: 3 };
//! let size = Budget::machine().with_max_triangles(Some(768)).check(&mesh, request)?;
//! assert_eq!((size.faces, size.triangles, size.vertices), (384, 768, 386));
//! let e = Budget::machine().with_max_triangles(Some(767)).check(&mesh, request).unwrap_err();
//! assert!(e.to_string().ends_with("the limit is 767 triangles"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Rendering a result
//! A [`Scene`] holds a tessellation in the form the renderer draws (per-vertex scalars, crease
//! normals);
//! [`view_for`] turns the tessellator's camera, framed on the cage ([`framing_box`]), into the
//! renderer's view. (`no_run`: rendering needs a Vulkan driver.)
//! ```no_run
//! use subdiv::{Scene, framing_box, view_for, mesh::{Camera, parse_obj, Mesh, glam::Vec3}, rules::Scheme};
//! use subdiv::vk::{RenderOptions, Renderer, Shading, write_png};
//! let cube = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
//!             f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
//! let cage = Mesh::from_soup(&parse_obj(cube)?)?;
//! let mut scene = Scene::uniform(&cage, Scheme::CatmullClark, 3)?;
//! let (lo, hi) = framing_box(&cage);
//! let camera = Camera::eye_relative(lo, hi, Vec3::new(0.8, 0.5, 2.2), 45.0, 320, 240);
//! let view = view_for(&camera, lo, hi);
//! scene.set_lines(Some(scene.silhouette_lines(view.eye)));
//! let options = RenderOptions { shading: Shading::Depth, show_lines: true, ..Default::default() };
//! let mut renderer = Renderer::new()?;
//! let image = renderer.render(&scene.render_mesh(), &view, [320, 240], &options)?;
//! write_png("cube.png", &image)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod animated_source;
mod builtin;
mod camera;
mod doi_setup;
mod dynamic;
mod export;
mod frame;
mod frame_sources;
mod refine;
mod scene;
mod scene_primvar;

pub use animated_source::{AnimatedSource, stage_playback};
pub use builtin::{BuiltinError, BuiltinScene, GRID_COLUMNS, helmet, helmet40, instance_grid};
pub use camera::{camera_from_view, framing_box, orbit_camera, radius_about, view_for};
pub use doi_setup::{
    DoiOptions, DoiSetup, DoiSetupError, check_doi_options, doi_face_depths, make_doi,
};
pub use dynamic::{Control, DynamicSubdivision};
pub use export::{ExportError, OutputFormat, write_surface};
pub use frame::depth_histogram;
pub use frame_sources::{AdaptiveSource, DoiSource, UniformSource};
pub use refine::{Balance, RefineError, RefineOptions, Refined, Refiner, refine_adaptive};
pub use scene::{Scene, SceneError, uniform_limit};
pub use scene_primvar::PrimvarDisplay;
pub use subdiv_rules::{LimitMesh, VertexScalar};

pub use subdiv_depth as depth;
pub use subdiv_doi as doi;
pub use subdiv_eval as eval;
pub use subdiv_mesh as mesh;
pub use subdiv_redgreen as redgreen;
pub use subdiv_rules as rules;
pub use subdiv_slate as slate;
pub use subdiv_stencil as stencil;
pub use subdiv_stitch as stitch;
pub use subdiv_vk as vk;
