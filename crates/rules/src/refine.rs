//! Uniform whole-mesh refinement `M^l -> M^(l+1)`.
//!
//! Vertex numbering of the refined mesh: first the children of the parent's vertices (so vertex
//! `i` of every level descends from cage vertex `i`), then for Catmull-Clark one point per face,
//! then one point per edge. Faces: Catmull-Clark splits an n-gon into n quads
//! `(v_k, e_k, f, e_(k-1))`; Loop splits a triangle into four. Child edges inherit decayed
//! sharpness, child faces the hole flag and group of their parent.

use glam::Vec3;
use subdiv_mesh::{Mesh, PolygonSoup, VertexId};

use crate::crease::{VertexRules, decrement, edge_crease_weight, is_sharp};
use crate::{RulesError, Scheme, catmark, loop_scheme};

/// One uniform refinement step of the whole mesh.
///
/// ```
/// use subdiv_mesh::{parse_obj, Mesh};
/// use subdiv_rules::{refine_uniform, Scheme};
/// let quad = Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")?)?;
/// let level1 = refine_uniform(&quad, Scheme::CatmullClark).unwrap();
/// assert_eq!((level1.num_vertices(), level1.num_faces()), (9, 4));
/// # Ok::<(), subdiv_mesh::MeshError>(())
/// ```
pub fn refine_uniform(mesh: &Mesh, scheme: Scheme) -> Result<Mesh, RulesError> {
    if scheme == Scheme::Loop {
        check_triangles(mesh)?;
    }
    let nv = mesh.num_vertices();
    let ne = mesh.num_edges();
    let method = mesh.options().crease;
    let pos = mesh.positions();

    let fp: Vec<Vec3> = if scheme == Scheme::CatmullClark {
        mesh.faces().map(|f| mesh.face_centroid(f)).collect()
    } else {
        Vec::new()
    };

    // Vertex points, and the child sharpness of each edge at each end (indexed by the half-edge
    // leaving that end).
    let mut child_sharp = vec![0.0f32; mesh.num_halfedges()];
    let mut positions: Vec<Vec3> = Vec::with_capacity(nv + fp.len() + ne);
    let mut edges: Vec<Vec3> = Vec::new();
    let mut faces: Vec<Vec3> = Vec::new();
    let mut sharp: Vec<f32> = Vec::new();
    let mut cs: Vec<f32> = Vec::new();
    let mut hs = Vec::new();
    for v in mesh.vertices() {
        if mesh.is_isolated(v) {
            positions.push(pos[v.idx()]);
            continue;
        }
        hs.clear();
        hs.extend(mesh.outgoing(v));
        edges.clear();
        faces.clear();
        sharp.clear();
        for &h in &hs {
            edges.push(pos[mesh.to(h).idx()]);
            sharp.push(mesh.edge_sharpness(h.edge()));
            let f = mesh.face(h);
            if f.is_some() && scheme == Scheme::CatmullClark {
                faces.push(fp[f.idx()]);
            }
        }
        cs.clear();
        cs.resize(hs.len(), 0.0);
        let rules = VertexRules::new(method, mesh.vertex_sharpness(v), &sharp, &mut cs);
        for (k, &h) in hs.iter().enumerate() {
            child_sharp[h.idx()] = cs[k];
        }
        let p = match scheme {
            Scheme::CatmullClark => catmark::vertex_point(pos[v.idx()], &edges, &faces, &rules),
            Scheme::Loop => loop_scheme::vertex_point(pos[v.idx()], &edges, &rules),
        };
        positions.push(p);
    }
    positions.extend_from_slice(&fp);

    // Edge points.
    let edge_base = positions.len() as u32;
    for e in mesh.edges() {
        let h0 = e.halfedge(0);
        let h1 = e.halfedge(1);
        let a = pos[mesh.from(h0).idx()];
        let b = pos[mesh.to(h0).idx()];
        let s = mesh.edge_sharpness(e);
        let w = edge_crease_weight(method, s, [child_sharp[h0.idx()], child_sharp[h1.idx()]]);
        let mut adj = [Vec3::ZERO; 2];
        let mut k = 0;
        for h in [h0, h1] {
            let f = mesh.face(h);
            if f.is_some() {
                adj[k] = match scheme {
                    Scheme::CatmullClark => fp[f.idx()],
                    // The vertex of the triangle opposite the edge.
                    Scheme::Loop => pos[mesh.to(mesh.next(h)).idx()],
                };
                k += 1;
            }
        }
        positions.push(match scheme {
            Scheme::CatmullClark => catmark::edge_point(a, b, &adj[..k], w),
            Scheme::Loop => loop_scheme::edge_point(a, b, &adj[..k], w),
        });
    }

    // Child faces.
    let mut soup = PolygonSoup {
        positions,
        options: mesh.options(),
        ..Default::default()
    };
    let mut holes = Vec::new();
    let mut groups = Vec::new();
    let ep = |h: subdiv_mesh::HalfedgeId| (edge_base + h.edge().0) as i64;
    for f in mesh.faces() {
        let h0 = mesh.face_halfedge(f);
        let n = mesh.face_size(f);
        match scheme {
            Scheme::CatmullClark => {
                let center = (nv + f.idx()) as i64;
                let mut h = h0;
                let mut hp = mesh.prev(h0);
                for _ in 0..n {
                    soup.push_face([mesh.from(h).0 as i64, ep(h), center, ep(hp)]);
                    hp = h;
                    h = mesh.next(h);
                }
                holes.extend(std::iter::repeat_n(mesh.is_hole(f), n));
                groups.extend(std::iter::repeat_n(mesh.face_group(f), n));
            }
            Scheme::Loop => {
                let (ha, hb, hc) = (h0, mesh.next(h0), mesh.prev(h0));
                let (a, b, c) = (
                    mesh.from(ha).0 as i64,
                    mesh.from(hb).0 as i64,
                    mesh.from(hc).0 as i64,
                );
                soup.push_face([a, ep(ha), ep(hc)]);
                soup.push_face([b, ep(hb), ep(ha)]);
                soup.push_face([c, ep(hc), ep(hb)]);
                soup.push_face([ep(ha), ep(hb), ep(hc)]);
                holes.extend([mesh.is_hole(f); 4]);
                groups.extend([mesh.face_group(f); 4]);
            }
        }
    }
    let mut child = Mesh::from_soup(&soup).map_err(RulesError::Internal)?;
    child.set_holes(holes);
    child.set_groups(mesh.groups().to_vec(), groups);

    // Sharpness of the child edges and vertices.
    for e in mesh.edges() {
        if !is_sharp(mesh.edge_sharpness(e)) || mesh.is_boundary_edge(e) {
            continue;
        }
        let m = VertexId(edge_base + e.0);
        for side in 0..2 {
            let h = e.halfedge(side);
            let s = child_sharp[h.idx()];
            if is_sharp(s) {
                let a = mesh.from(h);
                if let Some(ch) = child.find_halfedge(a, m) {
                    child.set_edge_sharpness(ch.edge(), s);
                }
            }
        }
    }
    for v in mesh.vertices() {
        let s = mesh.vertex_sharpness(v);
        if is_sharp(s) {
            child.set_vertex_sharpness(v, decrement(s).max(child.vertex_sharpness(v)));
        }
    }
    Ok(child)
}

/// Refines `depth` times.
pub fn refine_uniform_levels(mesh: &Mesh, scheme: Scheme, depth: u32) -> Result<Mesh, RulesError> {
    check_size(mesh, scheme, depth)?;
    let mut m = mesh.clone();
    for _ in 0..depth {
        m = refine_uniform(&m, scheme)?;
    }
    Ok(m)
}

/// Refuses Loop subdivision of a mesh with non-triangular faces.
pub fn check_triangles(mesh: &Mesh) -> Result<(), RulesError> {
    match mesh.faces().find(|&f| mesh.face_size(f) != 3) {
        Some(f) => Err(RulesError::NotTriangles {
            face: f.0,
            size: mesh.face_size(f) as u32,
        }),
        None => Ok(()),
    }
}

/// Maximum number of faces a uniform refinement may produce.
pub const MAX_REFINED_FACES: u64 = 1 << 26;

/// Number of faces of the uniform level-`depth` refinement.
pub fn refined_face_count(mesh: &Mesh, scheme: Scheme, depth: u32) -> u64 {
    if depth == 0 {
        return mesh.num_faces() as u64;
    }
    let per = 4u64.saturating_pow(depth - 1);
    match scheme {
        Scheme::CatmullClark => {
            let corners: u64 = mesh.faces().map(|f| mesh.face_size(f) as u64).sum();
            corners.saturating_mul(per)
        }
        Scheme::Loop => (mesh.num_faces() as u64).saturating_mul(per.saturating_mul(4)),
    }
}

fn check_size(mesh: &Mesh, scheme: Scheme, depth: u32) -> Result<(), RulesError> {
    let faces = refined_face_count(mesh, scheme, depth);
    if faces > MAX_REFINED_FACES {
        return Err(RulesError::TooDeep { depth, faces });
    }
    Ok(())
}
