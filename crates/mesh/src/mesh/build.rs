//! [`Mesh::from_soup`]: validates a polygon soup and builds the half-edge mesh, one step per
//! submodule. The steps run in this order, which fixes the error reported for a soup with
//! several defects:
//!
//! 1. `validate`: element counts, finite positions, then each face's size, index range and
//!    repeated vertices;
//! 2. `halfedges`: pairs face sides into edges (refusing edges with more than two faces and
//!    inconsistently oriented neighbours) and links each face's half-edges into a cycle;
//! 3. `boundary`: links the boundary half-edges into loops (refusing vertices where two boundary
//!    loops meet) and picks every vertex's out half-edge;
//! 4. `manifold`: checks that every vertex's faces form a single fan;
//! 5. `tags`: applies crease, corner and hole tags, then sharpens the boundary.

mod boundary;
mod halfedges;
mod manifold;
mod tags;
mod validate;

use std::collections::HashMap;
use std::ops::Range;

use super::Mesh;
use crate::error::MeshError;
use crate::handle::{FaceId, HalfedgeId, VertexId};
use crate::soup::PolygonSoup;

/// Validated faces in compressed form: face `f` uses `verts[offsets[f]..offsets[f + 1]]`.
struct FaceLists {
    offsets: Vec<u32>,
    verts: Vec<VertexId>,
}

impl FaceLists {
    fn num_faces(&self) -> usize {
        self.offsets.len() - 1
    }
    /// The corners of face `f` (indices into `verts`).
    fn corners(&self, f: usize) -> Range<usize> {
        self.offsets[f] as usize..self.offsets[f + 1] as usize
    }
}

/// The edges found by pairing face sides. Edge `e` owns half-edges `2e` (running in the
/// direction of the first face that uses it) and `2e + 1`.
struct Edges {
    /// `(min, max)` vertex pair -> edge index.
    map: HashMap<(u32, u32), u32>,
    he_to: Vec<VertexId>,
    /// Face of each half-edge; [`FaceId::NONE`] while it is (so far) a boundary half-edge.
    he_face: Vec<FaceId>,
    /// The half-edge of each face corner, leaving that corner's vertex.
    corner_he: Vec<HalfedgeId>,
}

/// Next/previous links of every half-edge, and the first half-edge of each face.
struct Cycles {
    he_next: Vec<HalfedgeId>,
    he_prev: Vec<HalfedgeId>,
    face_he: Vec<HalfedgeId>,
}

pub(super) fn build(soup: &PolygonSoup) -> Result<Mesh, MeshError> {
    let nv = validate::check_counts(soup)?;
    validate::check_positions(soup)?;
    let faces = validate::face_lists(soup, nv)?;

    let edges = halfedges::pair_edges(soup, &faces)?;
    let mut cycles = halfedges::link_faces(&faces, &edges);

    let boundary_out = boundary::link_loops(soup, nv, &edges, &mut cycles)?;
    let (vertex_out, corner_count) =
        boundary::vertex_out(nv, &faces, &edges, &cycles, &boundary_out);

    let Edges {
        map: edge_map,
        he_to,
        he_face,
        ..
    } = edges;
    let uv = validate::face_varying(soup)?;
    let corners = faces.verts.len();
    for p in &soup.primvars {
        p.check(nv as usize, faces.num_faces(), corners)
            .map_err(|msg| MeshError::Primvar {
                name: p.name.clone(),
                msg,
            })?;
    }
    let mut mesh = assemble(soup, faces, he_to, he_face, cycles, vertex_out);
    mesh.uv = uv;
    mesh.primvars = soup.primvars.clone();

    manifold::check_vertex_fans(&mesh, &corner_count, soup)?;
    tags::apply_tags(&mut mesh, soup, &edge_map)?;
    tags::hide_boundary_none(&mut mesh);
    tags::sharpen_boundary(&mut mesh, &corner_count);
    Ok(mesh)
}

/// The mesh from its validated topology, with default properties (no sharpness, no holes) and
/// the soup's positions, groups and options.
fn assemble(
    soup: &PolygonSoup,
    faces: FaceLists,
    he_to: Vec<VertexId>,
    he_face: Vec<FaceId>,
    cycles: Cycles,
    vertex_out: Vec<HalfedgeId>,
) -> Mesh {
    let nv = soup.positions.len();
    let nf = faces.num_faces();
    let ne = he_to.len() / 2;
    Mesh {
        positions: soup.positions.clone(),
        vertex_sharpness: vec![0.0; nv],
        vertex_out,
        he_to,
        he_next: cycles.he_next,
        he_prev: cycles.he_prev,
        he_face,
        edge_sharpness: vec![0.0; ne],
        face_offsets: faces.offsets,
        face_verts: faces.verts,
        face_he: cycles.face_he,
        face_hole: vec![false; nf],
        face_group: if soup.face_groups.len() == nf {
            soup.face_groups.clone()
        } else {
            vec![u32::MAX; nf]
        },
        groups: soup.groups.clone(),
        options: soup.options,
        uv: None,
        primvars: Vec::new(),
        whole_edges: Default::default(),
        crease_ends: Default::default(),
        fvar_corners: Vec::new(),
    }
}
