//! Step 1: index validation. Checks that the soup fits 32-bit handles, has a face and finite
//! positions, and that every face has at least three distinct, in-range vertices.

use super::FaceLists;
use crate::error::MeshError;
use crate::handle::VertexId;
use crate::soup::PolygonSoup;

/// `n` as a handle-sized count (`u32::MAX` is reserved for "none").
fn to_u32(n: usize, what: &str) -> Result<u32, MeshError> {
    u32::try_from(n)
        .ok()
        .filter(|&x| x != u32::MAX)
        .ok_or_else(|| MeshError::TooLarge {
            what: format!("{n} {what}"),
        })
}

/// Checks the vertex and face counts; returns the number of vertices.
pub(super) fn check_counts(soup: &PolygonSoup) -> Result<u32, MeshError> {
    let nv = to_u32(soup.positions.len(), "vertices")?;
    let nf = soup.num_faces();
    to_u32(nf, "faces")?;
    if nf == 0 {
        return Err(MeshError::Empty);
    }
    Ok(nv)
}

/// Refuses the first vertex with a NaN or infinite coordinate.
pub(super) fn check_positions(soup: &PolygonSoup) -> Result<(), MeshError> {
    for (i, p) in soup.positions.iter().enumerate() {
        if !p.is_finite() {
            return Err(MeshError::NonFinite {
                vertex: i as u32,
                x: p.x,
                y: p.y,
                z: p.z,
                line: soup.vertex_line(i),
            });
        }
    }
    Ok(())
}

/// Checks every face (in order) and converts the faces to vertex handles.
pub(super) fn face_lists(soup: &PolygonSoup, nv: u32) -> Result<FaceLists, MeshError> {
    let nf = soup.num_faces();
    let mut offsets = Vec::with_capacity(nf + 1);
    let mut verts: Vec<VertexId> = Vec::with_capacity(soup.face_indices.len());
    offsets.push(0u32);
    let mut scratch: Vec<u32> = Vec::new();
    for fi in 0..nf {
        let f = soup.face(fi);
        check_face(fi, f, nv, soup.face_line(fi), &mut scratch)?;
        verts.extend(f.iter().map(|&i| VertexId(i as u32)));
        offsets.push(to_u32(verts.len(), "face corners")?);
    }
    to_u32(verts.len() * 2, "half-edges")?;
    Ok(FaceLists { offsets, verts })
}

/// Face `fi` must have at least three vertices, all in `0..nv`, none repeated.
fn check_face(
    fi: usize,
    f: &[i64],
    nv: u32,
    line: Option<u32>,
    scratch: &mut Vec<u32>,
) -> Result<(), MeshError> {
    if f.len() < 3 {
        return Err(MeshError::FaceTooSmall {
            face: fi as u32,
            len: f.len() as u32,
            line,
        });
    }
    for &i in f {
        if i < 0 || i >= nv as i64 {
            return Err(MeshError::IndexOutOfRange {
                face: fi as u32,
                index: i,
                count: nv,
                line,
            });
        }
    }
    scratch.clear();
    scratch.extend(f.iter().map(|&i| i as u32));
    scratch.sort_unstable();
    if let Some(w) = scratch.windows(2).find(|w| w[0] == w[1]) {
        return Err(MeshError::RepeatedVertex {
            face: fi as u32,
            vertex: w[0],
            line,
        });
    }
    Ok(())
}

/// The face-varying channel of the soup, if it has one: one index per face corner, each naming
/// one of its finite values.
pub(super) fn face_varying(soup: &PolygonSoup) -> Result<Option<crate::FaceVarying>, MeshError> {
    if soup.uv_indices.is_empty() {
        return Ok(None);
    }
    if soup.uv_indices.len() != soup.face_indices.len() {
        return Err(MeshError::UvCount {
            indices: soup.uv_indices.len() as u64,
            corners: soup.face_indices.len() as u64,
        });
    }
    let count = to_u32(soup.uvs.len(), "texture coordinates")?;
    let mut indices = Vec::with_capacity(soup.uv_indices.len());
    for f in 0..soup.num_faces() {
        let start = soup.face_offsets[f] as usize;
        for (k, &i) in soup.face(f).iter().enumerate() {
            let index = soup.uv_indices[start + k];
            if index < 0 || index >= i64::from(count) {
                return Err(MeshError::UvIndexOutOfRange {
                    face: f as u32,
                    vertex: i,
                    index,
                    count,
                    line: soup.face_line(f),
                });
            }
            indices.push(index as u32);
        }
    }
    if let Some(u) = soup.uvs.iter().position(|p| !p.is_finite()) {
        return Err(MeshError::NonFiniteUv {
            index: u as u32,
            u: soup.uvs[u].x,
            v: soup.uvs[u].y,
        });
    }
    Ok(Some(crate::FaceVarying {
        values: soup.uvs.clone(),
        indices,
        dependence: Vec::new(),
    }))
}
