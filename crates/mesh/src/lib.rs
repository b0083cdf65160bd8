//! `subdiv-mesh`: the polygon mesh every other subdiv crate works on.
//!
//! A [`Mesh`] is a validated, manifold, consistently oriented half-edge mesh with faces of any
//! size, plus what subdivision needs beyond connectivity: edge and vertex sharpness (creases and
//! corners), holes, face groups and the scheme options (boundary interpolation, crease method,
//! triangle rule).
//! Properties are plain arrays indexed by typed handles ([`VertexId`], [`HalfedgeId`],
//! [`EdgeId`], [`FaceId`]).
//!
//! Invariants of every [`Mesh`]:
//! - **built only through validation**: [`Mesh::from_soup`] is the only constructor, and its
//!   fields are private; afterwards the topology is fixed (the setters change positions,
//!   sharpness, holes and groups only);
//! - **edge-manifold**: every edge has one or two faces;
//! - **vertex-manifold**: the faces around every vertex with faces form a single fan;
//! - **consistently oriented**: two faces sharing an edge traverse it in opposite directions;
//! - **explicit boundary half-edges**: every edge has two half-edges; the side without a face is
//!   a boundary half-edge ([`FaceId::NONE`]), linked into closed boundary loops;
//! - **properties as arrays indexed by handle**: `handle.idx()` indexes every per-element array.
//! - **`interpolateboundary none` as holes**: the faces OpenSubdiv hides under
//!   [`BoundaryInterpolation::None`] are hole faces of the mesh (one rule, applied when the mesh
//!   is built), so no tessellator has a rule of its own for them.
//! - **face-varying data** ([`FaceVarying`], OBJ `vt`): when present, one value index per face
//!   corner in face order, every index in range (a bad `vt` index is a [`MeshError`] with its line).
//!
//! Meshes are built from a [`PolygonSoup`] — usually read from an OBJ file with OpenSubdiv's
//! crease/corner/hole tags by [`read_obj`], or from the `UsdGeomMesh` prims of a USD stage by
//! [`read_usd`] ([`read_cage`] picks by extension) — and every defect of the input is a [`MeshError`]
//! naming the face, vertex or tag and its line. Non-manifold cages (fins, bow-ties) are cut by
//! the readers into manifold pieces that refine to OpenSubdiv's surface
//! ([`PolygonSoup::split_nonmanifold`]); [`Mesh::from_soup`] itself refuses them. That cut
//! needs OpenSubdiv's sharpness arithmetic (decay, transition weights), so its one home is
//! here too ([`sharpness`], re-exported by `subdiv-rules`).
//!
//! ```
//! use subdiv_mesh::{parse_obj, Mesh, VertexId};
//! let soup = parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nt crease 2/1/0 0 1 3\n")?;
//! let mesh = Mesh::from_soup(&soup)?;
//! assert_eq!(mesh.num_edges(), 4);
//! assert!(mesh.is_boundary_vertex(VertexId(0)));
//! assert_eq!(mesh.valence(VertexId(0)), 2);
//! # Ok::<(), subdiv_mesh::MeshError>(())
//! ```

mod cage;
mod camera;
mod error;
mod fvar;
mod geometry;
mod handle;
mod mesh;
mod obj;
mod options;
mod primvar;
mod sector_normals;
pub mod sharpness;
mod soup;
mod stats;
mod tags;
mod union_find;
mod usd;

pub use cage::{Cage, CageError, CageOptions, read_cage};
pub use camera::Camera;
pub use error::{MeshError, ObjError, UsdError};
pub use fvar::{Dependence, FVarLinearInterpolation, FaceVarying};
pub use geometry::{
    Vector3, closest_point_on_triangle, face_normals, newell_area, newell_normal, point_bounds,
    sway, triangulate, vertex_normals,
};
pub use handle::{EdgeId, FaceId, HalfedgeId, VertexId};
pub use mesh::{Mesh, Outgoing};
pub use obj::{
    ObjData, ReadOptions, format_mesh_obj, format_obj, parse_obj, read_obj, read_obj_soup,
    read_obj_with, read_obj_with_report, read_obj_with_warnings, write_mesh_obj, write_obj,
};
pub use options::{
    BoundaryInterpolation, CreaseMethod, SHARPNESS_INFINITE, SchemeOptions, TriangleSubdivision,
};
pub use primvar::{Primvar, PrimvarInterpolation};
pub use sector_normals::sector_corner_normals;
pub use soup::{CornerTag, CreaseTag, HoleTag, NonManifold, PolygonSoup};
pub use stats::MeshStats;
pub use tags::{IgnoredTagKind, TagWarning};
pub use union_find::UnionFind;
pub use usd::{
    FaceVaryingLinear, StageTime, UsdCage, UsdMesh, UsdReadOptions, UsdScheme, UsdStageReader,
    is_usd_path, read_usd, read_usd_soup,
};

pub use glam;
