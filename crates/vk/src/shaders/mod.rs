//! SPIR-V compiled from the GLSL sources in this folder by `build.rs` (naga).

use std::io::Cursor;

use crate::error::{Result, VkError};

/// Triangle vertex shader.
pub(crate) const MESH_VERT: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/mesh.vert.spv"));
/// Triangle fragment shader (colour + auxiliary targets).
pub(crate) const MESH_FRAG: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/mesh.frag.spv"));
/// Triangle fragment shader, colour target only (the multisampled pass).
pub(crate) const MESH_COLOR_FRAG: &[u8] =
    include_bytes!(concat!(env!("OUT_DIR"), "/mesh_color.frag.spv"));
/// Line vertex shader.
pub(crate) const LINE_VERT: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/line.vert.spv"));
/// Line fragment shader.
pub(crate) const LINE_FRAG: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/line.frag.spv"));

/// Overlay (HUD, legend) vertex shader.
pub(crate) const OVERLAY_VERT: &[u8] =
    include_bytes!(concat!(env!("OUT_DIR"), "/overlay.vert.spv"));
/// Overlay fragment shader.
pub(crate) const OVERLAY_FRAG: &[u8] =
    include_bytes!(concat!(env!("OUT_DIR"), "/overlay.frag.spv"));

/// The SPIR-V words of an embedded shader.
pub(crate) fn words(bytes: &[u8]) -> Result<Vec<u32>> {
    ash::util::read_spv(&mut Cursor::new(bytes)).map_err(|e| VkError::Io {
        path: "embedded SPIR-V".into(),
        source: e,
    })
}
