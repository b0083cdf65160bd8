//! Plain input data for the renderer: mesh, view, shading options, and the
//! CPU-side packing of a mesh into one vertex/index upload.
//!
//! Nothing here touches Vulkan; these are plain values the renderer and the
//! viewer read.

mod camera;
mod mesh;
mod options;
mod pack;

pub use camera::{OrbitCamera, View};
pub use mesh::RenderMesh;
pub use options::{RenderOptions, Shading};
pub(crate) use pack::{
    COLOR_STRIDE, Layout, VERTEX_STRIDE, covers, line_push_constants, mesh_push_constants,
    overlay_push_constants, pack, pack_from, pack_vertices, scalar_range,
};
