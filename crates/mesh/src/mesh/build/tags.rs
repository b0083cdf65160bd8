//! Step 5: sharpness and tags. Applies the soup's crease, corner and hole tags (refusing tags
//! that name missing elements or carry invalid sharpness), hides the faces
//! `interpolateboundary none` hides, then sharpens the boundary as OpenSubdiv does before
//! refinement.

use std::collections::HashMap;

use crate::error::MeshError;
use crate::handle::{EdgeId, VertexId};
use crate::mesh::Mesh;
use crate::options::{BoundaryInterpolation, BoundaryNoneRule, SHARPNESS_INFINITE};
use crate::soup::PolygonSoup;

/// Applies crease, then corner, then hole tags, in that order; `edge_map` maps a `(min, max)`
/// vertex pair to its edge.
pub(super) fn apply_tags(
    mesh: &mut Mesh,
    soup: &PolygonSoup,
    edge_map: &HashMap<(u32, u32), u32>,
) -> Result<(), MeshError> {
    apply_creases(mesh, soup, edge_map)?;
    apply_corners(mesh, soup)?;
    apply_whole_vertex_edges(mesh, soup)?;
    apply_holes(mesh, soup)
}

/// The whole vertex's edge sharpness of the copies of a non-manifold vertex
/// ([`Mesh::whole_vertex_edges`]) and the copies that take another's points
/// ([`Mesh::crease_ends`]).
fn apply_whole_vertex_edges(mesh: &mut Mesh, soup: &PolygonSoup) -> Result<(), MeshError> {
    let nv = mesh.num_vertices() as u32;
    for (v, values) in &soup.whole_vertex_edges {
        if *v < 0 || *v >= nv as i64 {
            return Err(MeshError::TagMissingVertex {
                tag: "whole-vertex edges",
                vertex: *v,
                count: nv,
                line: None,
            });
        }
        for &s in values {
            valid_sharpness("whole-vertex edges", s, None)?;
        }
        mesh.set_whole_vertex_edges(VertexId(*v as u32), values);
    }
    for (v, ends) in &soup.crease_copies {
        let missing = |x: i64| MeshError::TagMissingVertex {
            tag: "crease copy",
            vertex: x,
            count: nv,
            line: None,
        };
        if *v < 0 || *v >= nv as i64 {
            return Err(missing(*v));
        }
        let mut hs = [crate::HalfedgeId(0); 2];
        for (h, &(a, b)) in hs.iter_mut().zip(ends) {
            let (Ok(a), Ok(b)) = (u32::try_from(a), u32::try_from(b)) else {
                return Err(missing(a.min(b)));
            };
            let (a, b) = (a as i64, b as i64);
            if a >= nv as i64 || b >= nv as i64 {
                return Err(missing(a.max(b)));
            }
            *h = mesh
                .find_halfedge(VertexId(a as u32), VertexId(b as u32))
                .ok_or(MeshError::TagMissingEdge {
                    a: a as u32,
                    b: b as u32,
                    line: None,
                })?;
        }
        mesh.set_crease_ends(VertexId(*v as u32), Some(hs));
    }
    if let Some(&v) = soup.fvar_corners.iter().find(|&&v| v < 0 || v >= nv as i64) {
        return Err(MeshError::TagMissingVertex {
            tag: "face-varying corner",
            vertex: v,
            count: nv,
            line: None,
        });
    }
    let corners: Vec<u32> = soup.fvar_corners.iter().map(|&v| v as u32).collect();
    mesh.set_fvar_corners(&corners);
    Ok(())
}

/// `s` clamped to [`SHARPNESS_INFINITE`], or the error if it is NaN, infinite or negative.
fn valid_sharpness(tag: &'static str, s: f32, line: Option<u32>) -> Result<f32, MeshError> {
    if s.is_finite() && s >= 0.0 {
        Ok(s.min(SHARPNESS_INFINITE))
    } else {
        Err(MeshError::BadSharpness {
            tag,
            value: s,
            line,
        })
    }
}

fn apply_creases(
    mesh: &mut Mesh,
    soup: &PolygonSoup,
    edge_map: &HashMap<(u32, u32), u32>,
) -> Result<(), MeshError> {
    let nv = mesh.num_vertices() as u32;
    for t in &soup.creases {
        let s = valid_sharpness("crease", t.sharpness, t.line)?;
        for &x in &[t.a, t.b] {
            if x < 0 || x >= nv as i64 {
                return Err(MeshError::TagMissingVertex {
                    tag: "crease",
                    vertex: x,
                    count: nv,
                    line: t.line,
                });
            }
        }
        let (a, b) = (t.a as u32, t.b as u32);
        match edge_map.get(&(a.min(b), a.max(b))) {
            Some(&e) => mesh.edge_sharpness[e as usize] = s,
            None => return Err(MeshError::TagMissingEdge { a, b, line: t.line }),
        }
    }
    Ok(())
}

fn apply_corners(mesh: &mut Mesh, soup: &PolygonSoup) -> Result<(), MeshError> {
    let nv = mesh.num_vertices() as u32;
    for t in &soup.corners {
        let s = valid_sharpness("corner", t.sharpness, t.line)?;
        if t.v < 0 || t.v >= nv as i64 {
            return Err(MeshError::TagMissingVertex {
                tag: "corner",
                vertex: t.v,
                count: nv,
                line: t.line,
            });
        }
        mesh.vertex_sharpness[t.v as usize] = s;
    }
    Ok(())
}

fn apply_holes(mesh: &mut Mesh, soup: &PolygonSoup) -> Result<(), MeshError> {
    let nf = mesh.num_faces();
    for t in &soup.holes {
        if t.f < 0 || t.f >= nf as i64 {
            return Err(MeshError::TagMissingFace {
                face: t.f,
                count: nf as u32,
                line: t.line,
            });
        }
        mesh.face_hole[t.f as usize] = true;
    }
    Ok(())
}

/// With [`BoundaryInterpolation::None`], the faces OpenSubdiv hides become holes
/// ([`BoundaryNoneRule`], from the tagged sharpness: call before [`sharpen_boundary`]).
pub(super) fn hide_boundary_none(mesh: &mut Mesh) {
    if mesh.options.boundary != BoundaryInterpolation::None {
        return;
    }
    let mut rule = BoundaryNoneRule::new(mesh.num_vertices());
    for e in mesh.edges() {
        let [a, b] = mesh.edge_vertices(e);
        let faces = if mesh.is_boundary_edge(e) { 1 } else { 2 };
        rule.edge(a.idx(), b.idx(), faces, mesh.edge_sharpness(e));
    }
    for f in 0..mesh.num_faces() {
        let vs = mesh.face_vertices(crate::handle::FaceId(f as u32));
        if rule.hides(vs.iter().map(|v| v.idx())) {
            mesh.face_hole[f] = true;
        }
    }
}

/// Boundary edges become infinitely sharp; with [`BoundaryInterpolation::EdgeAndCorner`] so do
/// boundary vertices with a single face (`corner_count` is the number of faces per vertex).
pub(super) fn sharpen_boundary(mesh: &mut Mesh, corner_count: &[u32]) {
    for e in 0..mesh.num_edges() {
        if mesh.is_boundary_edge(EdgeId(e as u32)) {
            mesh.edge_sharpness[e] = SHARPNESS_INFINITE;
        }
    }
    if mesh.options.boundary == BoundaryInterpolation::EdgeAndCorner {
        for v in 0..mesh.num_vertices() as u32 {
            let vid = VertexId(v);
            if mesh.is_boundary_vertex(vid) && corner_count[v as usize] == 1 {
                mesh.vertex_sharpness[v as usize] = SHARPNESS_INFINITE;
            }
        }
    }
}
