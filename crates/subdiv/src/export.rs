//! Surface output in the format named by the file's extension: OBJ (`.obj`, through
//! [`subdiv_mesh::write_obj`]), glTF 2.0 (`.gltf` with a `.bin` beside it, or binary `.glb`;
//! written with `gltf-json`) and binary little-endian PLY (`.ply`).
//!
//! glTF and PLY hold triangles with one normal per vertex: a [`SurfaceExport`] is made from a
//! [`LimitMesh`] by fan-triangulating its polygons and giving each face corner with a one-sided
//! normal (creases, corners) a vertex of its own, as the renderer does. Per vertex they carry the
//! position, the normal, texture coordinates when the surface has them, and optionally one scalar:
//! the subdivision depth or the Degree of Interest ([`VertexScalar`]), as the custom glTF
//! attributes `_DEPTH`/`_DOI` (`SCALAR` `FLOAT`) or the PLY properties `depth`/`doi`.
//! PLY texture coordinates are the properties `s` and `t`.

mod gltf;
mod ply;

use std::collections::HashMap;
use std::path::Path;

use subdiv_mesh::{ObjError, write_obj};
use subdiv_rules::LimitMesh;
use subdiv_vk::OwnedMesh;
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

/// What the per-vertex scalar of a [`SurfaceExport`] is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VertexScalar {
    /// The subdivision depth of the vertex's patch (glTF `_DEPTH`, PLY `depth`).
    Depth,
    /// The Degree of Interest (glTF `_DOI`, PLY `doi`).
    Doi,
}

impl VertexScalar {
    /// The glTF attribute name (`_DEPTH`, `_DOI`).
    pub fn gltf_attribute(self) -> &'static str {
        match self {
            VertexScalar::Depth => "_DEPTH",
            VertexScalar::Doi => "_DOI",
        }
    }

    /// The PLY vertex property name (`depth`, `doi`).
    pub fn ply_property(self) -> &'static str {
        match self {
            VertexScalar::Depth => "depth",
            VertexScalar::Doi => "doi",
        }
    }
}

/// A triangulated surface with one normal per vertex, ready for glTF or PLY.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfaceExport {
    /// Positions.
    pub positions: Vec<[f32; 3]>,
    /// Unit normals, one per position.
    pub normals: Vec<[f32; 3]>,
    /// Texture coordinates, one per position, when the surface has them.
    pub uvs: Option<Vec<[f32; 2]>>,
    /// Triangles (counter-clockwise), three indices each.
    pub triangles: Vec<u32>,
    /// One scalar per position and what it is.
    pub scalar: Option<(VertexScalar, Vec<f32>)>,
}

impl SurfaceExport {
    /// Triangulates `limit` (a fan per polygon), a vertex of its own for every distinct
    /// one-sided corner normal (position and scalar copied), with `scalar` one per vertex of
    /// `limit`. When `limit` carries face-varying values (UVs), each vertex is also split by
    /// its distinct values, so seams keep their texture coordinates on both sides.
    pub fn from_limit(
        limit: &LimitMesh,
        scalar: Option<(VertexScalar, Vec<f32>)>,
    ) -> SurfaceExport {
        if !limit.uv_indices.is_empty() {
            return Self::from_limit_with_uvs(limit, scalar);
        }
        let (kind, values) = match scalar {
            Some((k, v)) => (Some(k), Some(v)),
            None => (None, None),
        };
        let mut m = OwnedMesh {
            positions: limit.positions.clone(),
            normals: limit.normals.clone(),
            triangles: Vec::new(),
            edges: None,
            scalars: values,
            lines: None,
        };
        crate::scene::split_sided_vertices(limit, &mut m);
        SurfaceExport {
            positions: m.positions,
            normals: m.normals,
            uvs: None,
            triangles: m.triangles,
            scalar: kind.zip(m.scalars),
        }
    }

    /// [`SurfaceExport::from_limit`] of a surface with UVs: one output vertex per distinct
    /// (vertex, one-sided normal, UV index) of the face corners.
    fn from_limit_with_uvs(
        limit: &LimitMesh,
        scalar: Option<(VertexScalar, Vec<f32>)>,
    ) -> SurfaceExport {
        let mut out = SurfaceExport {
            uvs: Some(Vec::new()),
            scalar: scalar.as_ref().map(|(k, _)| (*k, Vec::new())),
            ..SurfaceExport::default()
        };
        let mut copies: HashMap<(u32, Option<[u32; 3]>, u32), u32> = HashMap::new();
        let mut sided = limit.corner_normals.iter().peekable();
        let mut corner = Vec::new();
        for f in 0..limit.num_faces() {
            corner.clear();
            for c in limit.face_offsets[f]..limit.face_offsets[f + 1] {
                let v = limit.face_indices[c as usize];
                let n = sided.next_if(|&&(k, _)| k == c).map(|&(_, n)| n);
                let uv = limit.uv_indices[c as usize];
                let key = (v, n.map(|n| n.map(f32::to_bits)), uv);
                let id = *copies.entry(key).or_insert_with(|| {
                    out.positions.push(limit.positions[v as usize]);
                    out.normals.push(n.unwrap_or(limit.normals[v as usize]));
                    if let Some(uvs) = out.uvs.as_mut() {
                        uvs.push(limit.uvs[uv as usize]);
                    }
                    if let (Some((_, dst)), Some((_, src))) = (out.scalar.as_mut(), scalar.as_ref())
                    {
                        dst.push(src[v as usize]);
                    }
                    out.positions.len() as u32 - 1
                });
                corner.push(id);
            }
            for k in 1..corner.len().saturating_sub(1) {
                out.triangles
                    .extend_from_slice(&[corner[0], corner[k], corner[k + 1]]);
            }
        }
        out
    }

    /// Checks that every per-vertex array has one entry per position and every index is in
    /// range (what the writers rely on).
    pub fn check(&self) -> Result<(), String> {
        let n = self.positions.len();
        let lens = [
            ("normals", Some(self.normals.len())),
            ("texture coordinates", self.uvs.as_ref().map(Vec::len)),
            ("scalars", self.scalar.as_ref().map(|(_, v)| v.len())),
        ];
        for (what, len) in lens {
            if let Some(len) = len
                && len != n
            {
                return Err(format!("{len} {what} for {n} positions"));
            }
        }
        if self.triangles.is_empty() {
            return Err("no triangles to write".into());
        }
        if !self.triangles.len().is_multiple_of(3) {
            return Err(format!("{} triangle indices", self.triangles.len()));
        }
        if let Some(&i) = self.triangles.iter().find(|&&i| i as usize >= n) {
            return Err(format!("triangle index {i} for {n} positions"));
        }
        if u32::try_from(n).is_err() {
            return Err(format!("{n} vertices do not fit 32-bit indices"));
        }
        Ok(())
    }
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

/// Writes a tessellation to `path` in the format of its extension, with an optional scalar per
/// vertex of `limit` (glTF and PLY only; OBJ has no place for it). Returns the format written.
pub fn write_surface(
    path: impl AsRef<Path>,
    limit: &LimitMesh,
    scalar: Option<(VertexScalar, Vec<f32>)>,
) -> Result<OutputFormat, ExportError> {
    let path = path.as_ref();
    let format = OutputFormat::from_path(path)?;
    if format == OutputFormat::Obj {
        write_obj(path, &limit.obj_data())?;
    } else {
        write_export(path, &SurfaceExport::from_limit(limit, scalar))?;
    }
    Ok(format)
}

/// Writes a [`SurfaceExport`] as glTF (`.gltf`, `.glb`) or PLY (`.ply`), by extension.
pub fn write_export(path: impl AsRef<Path>, s: &SurfaceExport) -> Result<(), ExportError> {
    let path = path.as_ref();
    let invalid = |what: String| ExportError::Invalid {
        path: path.display().to_string(),
        what,
    };
    s.check().map_err(invalid)?;
    match OutputFormat::from_path(path)? {
        OutputFormat::Gltf => gltf::write(path, s, false),
        OutputFormat::Glb => gltf::write(path, s, true),
        OutputFormat::Ply => ply::write(path, s),
        OutputFormat::Obj => Err(invalid(
            "OBJ is written from the polygons (write_surface), not from a SurfaceExport".into(),
        )),
    }
}

/// Writes `bytes` to `path`.
fn write_file(path: &Path, bytes: &[u8]) -> Result<(), ExportError> {
    std::fs::write(path, bytes).map_err(|source| ExportError::Io {
        path: path.display().to_string(),
        source,
    })
}
