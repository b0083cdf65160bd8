//! One refinement pass: the red-green closure of one level applied with Loop's rules, reading
//! every vertex at that level's position.
//!
//! A balanced step ([`crate::Balance::Vertex`]) refines faces of several levels; it runs one
//! pass per level, coarsest first, so that when a level-`l` face is refined every face around
//! its corners already has level `l` or more: the level-`l` one-ring of every vertex the pass
//! moves exists in the mesh. Each vertex keeps its position at its current level (the highest
//! level of the faces around it) and the one before ([`AdaptiveMesh::previous`]); a pass reads
//! the level-`l` position of every vertex, so the vertex and edge points it makes are exactly
//! those of uniform Loop at level `l + 1` wherever the level-`l` neighbourhood is that of
//! uniform Loop (Isenberg et al. §3 applies the rules to the current mesh, whose vertices mix
//! levels; the mixed rings are what made thin triangles, see [`crate::loop_step`]). Green
//! triangles stand for their parent: the edge from a green triangle's corner to the midpoint of
//! the opposite parent edge is left out of that corner's ring, and the edge point of a parent
//! edge reads the parent's opposite corner.

use glam::Vec3;
use subdiv_mesh::{HalfedgeId, Mesh, PolygonSoup, VertexId};
use subdiv_rules::{RefineKernel, Scheme};

use crate::RedGreenError;
use crate::red_green::{self, Closure, GreenState, NO_FAMILY};
use crate::step::{AdaptiveMesh, MAX_TRIANGLES};

/// Per vertex: the highest level of the faces around it (its position's level).
pub(crate) fn vertex_levels(mesh: &Mesh, level: &[u8]) -> Vec<u8> {
    let mut top = vec![0u8; mesh.num_vertices()];
    for f in mesh.faces() {
        for v in mesh.face_vertices(f) {
            top[v.idx()] = top[v.idx()].max(level[f.idx()]);
        }
    }
    top
}

/// Every vertex at level `l`: its current position when its level is `l` or less, the previous
/// one when it is one level ahead.
pub(crate) fn level_positions(a: &AdaptiveMesh, l: u8) -> Vec<Vec3> {
    level_values(a, l, a.mesh.positions(), &a.previous)
}

/// [`level_positions`] of any per-vertex field (`values` now, `previous` one level before: the
/// positions, or a vertex primvar's values standing in for them).
pub(crate) fn level_values(
    a: &AdaptiveMesh,
    l: u8,
    values: &[Vec3],
    previous: &[Vec3],
) -> Vec<Vec3> {
    let top = vertex_levels(&a.mesh, &a.level);
    values
        .iter()
        .zip(previous)
        .zip(&top)
        .map(|((&p, &q), &t)| if t > l { q } else { p })
        .collect()
}

/// Keeps the vertex rule to vertices at the level being refined: a vertex moves only when a
/// face refined in this pass has the highest level among the faces around it. As in uniform
/// Loop, every vertex is then smoothed once per level: a vertex whose finer side was refined
/// earlier is not smoothed again when the coarser side catches up.
pub(crate) fn once_per_level(mesh: &Mesh, level: &[u8], c: &mut Closure) {
    let top = vertex_levels(mesh, level);
    let mut keep = vec![false; mesh.num_vertices()];
    for f in mesh.faces().filter(|f| c.red_face[f.idx()]) {
        for v in mesh.face_vertices(f) {
            keep[v.idx()] |= level[f.idx()] == top[v.idx()];
        }
    }
    for (m, k) in c.moves.iter_mut().zip(keep) {
        *m &= k;
    }
}

/// Whether the edge of `h` joins a green triangle's corner to the midpoint of the opposite
/// parent edge (an edge inside the family, not one of its parent's level).
#[inline]
pub(crate) fn inside_family(mesh: &Mesh, green: &GreenState, h: HalfedgeId) -> bool {
    let (v, m) = (mesh.from(h), mesh.to(h));
    [h, h.twin()].iter().any(|&s| {
        let f = mesh.face(s);
        if !f.is_some() {
            return false;
        }
        match green.family_of_face[f.idx()] {
            NO_FAMILY => false,
            fam => {
                let g = &green.families[fam as usize];
                (0..3).any(|k| g.mids[k] == m && g.parent[(k + 2) % 3] == v)
            }
        }
    })
}

/// A pass's points of one per-vertex field (`values` now and `previous` one level before: the
/// positions, or a vertex primvar's values standing in for them), read by `kernel` (made on the
/// mesh with the field's values at the pass's level, `kpos`): moved vertices take the
/// vertex rule (the ends of split edges are ruled too, for their child sharpness), split edges
/// get their edge points after the existing vertices, in edge order. Returns the new values and
/// their previous ones.
pub(crate) fn field_points(
    (kernel, kpos): (&mut RefineKernel<'_>, &[Vec3]),
    cur: &AdaptiveMesh,
    closure: &Closure,
    by_level: bool,
    values: &[Vec3],
    previous: &[Vec3],
) -> (Vec<Vec3>, Vec<Vec3>) {
    let mesh = &cur.mesh;
    // Vertex rules for moved vertices and for the ends of split edges (their child edge
    // sharpness gives the crease weight of the edge point); only moved vertices move.
    let mut need = closure.moves.clone();
    for e in mesh.edges() {
        if closure.split_edge[e.idx()] {
            let [a, b] = mesh.edge_vertices(e);
            need[a.idx()] = true;
            need[b.idx()] = true;
        }
    }
    let mut out: Vec<Vec3> = Vec::with_capacity(mesh.num_vertices() + closure.num_split_edges());
    out.extend_from_slice(values);
    let mut prev = Vec::with_capacity(out.capacity());
    prev.extend_from_slice(previous);
    for v in mesh.vertices() {
        if need[v.idx()] {
            let skip = |h| by_level && inside_family(mesh, &cur.green, h);
            let mut p = kernel.vertex_point_without(v, &[], skip);
            if let Some(ends) = mesh.crease_ends(v) {
                // A copy lacking the crease's edges: the crease rule over them (its own rules
                // still gave its edges' child sharpness).
                p = kernel.crease_copy_point(v, ends);
            }
            if closure.moves[v.idx()] {
                prev[v.idx()] = out[v.idx()];
                out[v.idx()] = p;
            }
        }
    }
    for e in mesh.edges() {
        if closure.split_edge[e.idx()] {
            let p = kernel.edge_point(e, |h| kpos[opposite(cur, &closure.merged, h).idx()]);
            out.push(p);
            prev.push(p);
        }
    }
    (out, prev)
}

/// Applies `closure` to `cur`: vertex and edge points (and UVs, `crate::fvar`) read at
/// `level` (every vertex at that level, and rings without green-internal edges; `None`: the
/// current positions and rings, the paper's plain closure), moved vertices and new midpoints
/// written, the conforming triangles assembled. Returns the refined mesh and, per new face, the
/// face of `cur` it comes from.
pub(crate) fn pass(
    cur: &AdaptiveMesh,
    closure: &Closure,
    level: Option<u8>,
) -> Result<(AdaptiveMesh, Vec<u32>), RedGreenError> {
    let mesh = &cur.mesh;
    // Balanced passes read the level's ring (green-internal edges left out); the plain closure
    // reads the current mesh, as the paper does.
    let by_level = level.is_some();
    let shifted;
    let kmesh = match level.map(|l| level_positions(cur, l)) {
        Some(p) => {
            let mut m = mesh.clone();
            m.positions_mut().copy_from_slice(&p);
            shifted = m;
            &shifted
        }
        None => mesh,
    };
    let kpos = kmesh.positions();

    let mut kernel = RefineKernel::new(kmesh, Scheme::Loop);
    let (positions, previous) = field_points(
        (&mut kernel, kpos),
        cur,
        closure,
        by_level,
        mesh.positions(),
        &cur.previous,
    );

    // Edge points, numbered in edge order after the existing vertices.
    let mut edge_mid = vec![VertexId::NONE; mesh.num_edges()];
    let mut next = mesh.num_vertices() as u32;
    for e in mesh.edges() {
        if closure.split_edge[e.idx()] {
            edge_mid[e.idx()] = VertexId(next);
            next += 1;
        }
    }

    let asm = red_green::assemble(mesh, &cur.green, closure, &edge_mid, &positions)?;
    let faces = asm.triangles.len() as u64;
    if faces > MAX_TRIANGLES {
        return Err(RedGreenError::TooLarge {
            faces,
            limit: MAX_TRIANGLES,
        });
    }
    let uvs = crate::fvar::pass_uvs(&mut kernel, cur, closure, level, &edge_mid, &asm)?;
    let primvars = crate::primvars::pass_primvars(
        &mut kernel,
        &crate::primvars::Pass {
            cur,
            closure,
            level,
            edge_mid: &edge_mid,
            asm: &asm,
        },
    )?;
    let mut soup = PolygonSoup {
        positions,
        options: mesh.options(),
        primvars: primvars.primvars,
        ..Default::default()
    };
    let (mut previous_uv, mut uv_dependence) = (Vec::new(), Vec::new());
    if let Some(u) = uvs {
        (soup.uvs, soup.uv_indices) = (u.values, u.indices);
        (previous_uv, uv_dependence) = (u.previous, u.dependence);
    }
    soup.face_offsets.reserve(asm.triangles.len() + 1);
    soup.face_indices.reserve(asm.triangles.len() * 3);
    soup.face_offsets.push(0);
    for t in &asm.triangles {
        soup.face_indices.extend(t.iter().map(|&i| i as i64));
        soup.face_offsets.push(soup.face_indices.len() as u32);
    }
    let mut child = Mesh::from_soup(&soup).map_err(RedGreenError::Internal)?;
    child
        .set_uv_dependence(uv_dependence)
        .map_err(RedGreenError::Internal)?;
    // The old vertices keep their numbers.
    child.set_fvar_corners(mesh.fvar_corners());
    child.set_holes(
        asm.source_face
            .iter()
            .map(|&f| mesh.holes()[f as usize])
            .collect(),
    );
    child.set_groups(
        mesh.groups().to_vec(),
        asm.source_face
            .iter()
            .map(|&f| mesh.face_groups()[f as usize])
            .collect(),
    );

    // Sharpness: halves of split crease edges get the decayed value, kept edges keep theirs;
    // moved vertices decay, kept ones keep theirs.
    kernel.transfer_sharpness(
        &mut child,
        |e| Some(edge_mid[e.idx()]).filter(|m| m.is_some()),
        |v| closure.moves[v.idx()] || mesh.is_isolated(v),
    );

    let level = asm
        .source_face
        .iter()
        .map(|&f| cur.level[f as usize].saturating_add(u8::from(closure.red_face[f as usize])))
        .collect();
    Ok((
        AdaptiveMesh {
            mesh: child,
            green: asm.state,
            level,
            previous,
            previous_uv,
            previous_primvars: primvars.previous,
            primvar_dependence: primvars.dependence,
            cage_angle: cur.cage_angle,
        },
        asm.source_face,
    ))
}

/// The vertex opposite half-edge `h` in its face, or, for an edge of the parent of a merged
/// green family, the parent's opposite corner.
#[inline]
pub(crate) fn opposite(cur: &AdaptiveMesh, merged: &[bool], h: HalfedgeId) -> VertexId {
    let mesh = &cur.mesh;
    let f = mesh.face(h);
    let fam = cur.green.family_of_face[f.idx()];
    if fam != NO_FAMILY && merged[fam as usize] {
        let g = &cur.green.families[fam as usize];
        let (a, b) = (mesh.from(h), mesh.to(h));
        for k in 0..3 {
            if g.parent[k] == a && g.parent[(k + 1) % 3] == b {
                return g.parent[(k + 2) % 3];
            }
        }
    }
    mesh.to(mesh.next(h))
}
