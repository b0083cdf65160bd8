//! Surface output in the format named by the file's extension: OBJ (`.obj`, through
//! [`subdiv_mesh::write_obj`]), glTF 2.0 (`.gltf` with a `.bin` beside it, or binary `.glb`;
//! written with `gltf-json`) and binary little-endian PLY (`.ply`).
//!
//! glTF and PLY hold triangles with one normal per vertex: the [`LimitMesh`] is written in its
//! [`split_sided`](LimitMesh::split_sided) form (fan-triangulated, a vertex of its own for each
//! face corner with a one-sided normal and each side of a UV seam), the split the renderer
//! draws. Per vertex they carry the position, the normal, texture coordinates when the surface
//! has them, and the surface's scalar when it has one: the subdivision depth or the Degree of
//! Interest ([`VertexScalar`](subdiv_rules::VertexScalar)), as the custom glTF attributes
//! `_DEPTH`/`_DOI` (`SCALAR` `FLOAT`) or the PLY properties `depth`/`doi`.
//! PLY texture coordinates are the properties `s` and `t`.

mod gltf;
mod ply;

use std::path::Path;

use subdiv_mesh::{ObjError, write_obj};
use subdiv_rules::LimitMesh;
use thiserror::Error;

/// An output file format, chosen by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputFormat {
    /// `.obj`: polygons with limit normals (and one-sided corner normals).
    Obj,
    /// `.gltf`: glTF 2.0 JSON, the binary data in a `.bin` file of the same stem.
    Gltf,
    /// `.glb`: binary glTF 2.0 (JSON and data in one file).
    Glb,
    /// `.ply`: binary little-endian PLY.
    Ply,
}

impl OutputFormat {
    /// The format named by `path`'s extension (any case).
    pub fn from_path(path: impl AsRef<Path>) -> Result<OutputFormat, ExportError> {
        let path = path.as_ref();
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("obj") => Ok(OutputFormat::Obj),
            Some("gltf") => Ok(OutputFormat::Gltf),
            Some("glb") => Ok(OutputFormat::Glb),
            Some("ply") => Ok(OutputFormat::Ply),
            _ => Err(ExportError::UnknownFormat {
                path: path.display().to_string(),
            }),
        }
    }
}

/// The triangles, one normal and UV per vertex, of `limit` that glTF and PLY store
/// ([`LimitMesh::split_sided`] with its UVs), checked for what the writers rely on.
fn split_for_writing(limit: &LimitMesh) -> Result<LimitMesh, String> {
    let s = limit.split_sided(true);
    if s.num_faces() == 0 {
        return Err("no triangles to write".into());
    }
    if u32::try_from(s.num_vertices()).is_err() {
        return Err(format!(
            "{} vertices do not fit 32-bit indices",
            s.num_vertices()
        ));
    }
    Ok(s)
}

/// The per-vertex texture coordinates of a split surface ([`LimitMesh::split_sided`]), when
/// it has them.
fn vertex_uvs(s: &LimitMesh) -> Option<&[[f32; 2]]> {
    (!s.uv_indices().is_empty()).then(|| s.uvs())
}

/// Where a channel of a split surface goes in glTF: `COLOR_0` for a display colour of 3 or 4
/// floats, `TEXCOORD_n` for 2 floats (`n` from 1 when the surface has texture coordinates,
/// `TEXCOORD_0`), else `_NAME` (the name upper-cased, other characters than letters and digits
/// as `_`), and for more than 4 floats `_NAME_0`, `_NAME_1`, ... of 4 floats each.
/// Returns `(semantic, channel, first float, floats)` in channel order.
fn gltf_attributes(s: &LimitMesh) -> Vec<(ChannelAttribute, usize, usize, usize)> {
    let mut texcoord = usize::from(vertex_uvs(s).is_some());
    let mut out = Vec::new();
    for (i, c) in s.channels().iter().enumerate() {
        if c.name == "displayColor" && (c.width == 3 || c.width == 4) {
            out.push((ChannelAttribute::Color, i, 0, c.width));
        } else if c.width == 2 {
            out.push((ChannelAttribute::TexCoord(texcoord), i, 0, 2));
            texcoord += 1;
        } else {
            let name: String = c
                .name
                .chars()
                .map(|ch| {
                    if ch.is_ascii_alphanumeric() {
                        ch.to_ascii_uppercase()
                    } else {
                        '_'
                    }
                })
                .collect();
            if c.width <= 4 {
                out.push((ChannelAttribute::Custom(name), i, 0, c.width));
            } else {
                for (k, first) in (0..c.width).step_by(4).enumerate() {
                    let n = 4.min(c.width - first);
                    out.push((ChannelAttribute::Custom(format!("{name}_{k}")), i, first, n));
                }
            }
        }
    }
    out
}

/// A glTF vertex attribute of a channel.
#[derive(Clone, Debug, PartialEq, Eq)]
enum ChannelAttribute {
    /// `COLOR_0`.
    Color,
    /// `TEXCOORD_n`.
    TexCoord(usize),
    /// `_NAME` (the name without its `_`).
    Custom(String),
}

/// The PLY property names of a channel: `red green blue [alpha]` for a display colour of 3 or
/// 4 floats, the name for 1 float, else `name_0`, `name_1`, ...
fn ply_properties(name: &str, width: usize) -> Vec<String> {
    if name == "displayColor" && (width == 3 || width == 4) {
        return ["red", "green", "blue", "alpha"][..width]
            .iter()
            .map(|s| s.to_string())
            .collect();
    }
    if width == 1 {
        return vec![name.to_string()];
    }
    (0..width).map(|k| format!("{name}_{k}")).collect()
}

/// An error writing a surface file.
#[derive(Debug, Error)]
pub enum ExportError {
    /// The extension names no output format.
    #[error("{path}: unknown output format (the extension must be .obj, .gltf, .glb or .ply)")]
    UnknownFormat {
        /// The file.
        path: String,
    },
    /// The file could not be written.
    #[error("{path}")]
    Io {
        /// The file.
        path: String,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// Writing OBJ.
    #[error(transparent)]
    Obj(#[from] ObjError),
    /// The data cannot be written (inconsistent lengths, too large for the format).
    #[error("{path}: {what}")]
    Invalid {
        /// The file.
        path: String,
        /// What is wrong.
        what: String,
    },
}

/// Writes a tessellation to `path` in the format of its extension, with its per-vertex scalar
/// (glTF and PLY only; OBJ has no place for it). Returns the format written.
pub fn write_surface(
    path: impl AsRef<Path>,
    limit: &LimitMesh,
) -> Result<OutputFormat, ExportError> {
    let path = path.as_ref();
    let format = OutputFormat::from_path(path)?;
    if format == OutputFormat::Obj {
        write_obj(path, &limit.obj_data())?;
        return Ok(format);
    }
    let s = split_for_writing(limit).map_err(|what| ExportError::Invalid {
        path: path.display().to_string(),
        what,
    })?;
    match format {
        OutputFormat::Gltf => gltf::write(path, &s, false)?,
        OutputFormat::Glb => gltf::write(path, &s, true)?,
        _ => ply::write(path, &s)?,
    }
    Ok(format)
}

/// Writes `bytes` to `path`.
fn write_file(path: &Path, bytes: &[u8]) -> Result<(), ExportError> {
    std::fs::write(path, bytes).map_err(|source| ExportError::Io {
        path: path.display().to_string(),
        source,
    })
}
