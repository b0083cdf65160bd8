//! Step 3 of the red-green closure: the conforming triangles and the new green families.

use glam::Vec3;
use subdiv_mesh::{HalfedgeId, Mesh, VertexId};

use super::close::Closure;
use super::green::{GreenFamily, GreenState, NO_FAMILY};
use crate::RedGreenError;
use crate::error::check_len;

/// The refined mesh's triangles, as produced by [`assemble`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Assembly {
    /// Triangles (vertex indices into the caller's new positions), counter-clockwise.
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle: the face of the input mesh it comes from (for groups and hole flags).
    pub source_face: Vec<u32>,
    /// Green families of the new mesh.
    pub state: GreenState,
}

/// Splits triangle `tri` with midpoints `mids` (`mids[k]` on edge `tri[k]`-`tri[k+1]`, or
/// [`VertexId::NONE`]) into 1, 2, 3 or 4 triangles appended to `out`, counter-clockwise.
///
/// Returns the green family for one or two split edges, `None` otherwise. With two split
/// edges the quadrilateral left beside the corner triangle is cut along its shorter diagonal
/// (positions from `positions`).
///
/// ```
/// use subdiv_mesh::{VertexId, glam::Vec3};
/// use subdiv_redgreen::red_green::split_triangle;
/// let p = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(0.5, 0.0, 0.0)];
/// let mut out = Vec::new();
/// let fam = split_triangle([VertexId(0), VertexId(1), VertexId(2)], [VertexId(3), VertexId::NONE, VertexId::NONE], &p, &mut out);
/// assert_eq!(out, vec![[0, 3, 2], [3, 1, 2]]);
/// assert_eq!(fam.unwrap().num_splits(), 1);
/// ```
#[inline]
pub fn split_triangle(
    tri: [VertexId; 3],
    mids: [VertexId; 3],
    positions: &[Vec3],
    out: &mut Vec<[u32; 3]>,
) -> Option<GreenFamily> {
    let n = mids.iter().filter(|m| m.is_some()).count();
    let [a, b, c] = tri.map(|v| v.0);
    match n {
        0 => {
            out.push([a, b, c]);
            None
        }
        1 => {
            // Rotate so that the split edge is tri[r]-tri[r+1].
            let r = mids.iter().position(|m| m.is_some()).unwrap_or(0);
            let (x, y, z) = (tri[r].0, tri[(r + 1) % 3].0, tri[(r + 2) % 3].0);
            let m = mids[r].0;
            out.push([x, m, z]);
            out.push([m, y, z]);
            Some(GreenFamily { parent: tri, mids })
        }
        2 => {
            // Rotate so that the unsplit edge is tri[r+2]-tri[r].
            let r = (mids.iter().position(|m| *m == VertexId::NONE).unwrap_or(2) + 1) % 3;
            let (x, y, z) = (tri[r].0, tri[(r + 1) % 3].0, tri[(r + 2) % 3].0);
            let (m0, m1) = (mids[r].0, mids[(r + 1) % 3].0);
            out.push([m0, y, m1]);
            let d_xm1 = pos(positions, x).distance_squared(pos(positions, m1));
            let d_m0z = pos(positions, m0).distance_squared(pos(positions, z));
            if d_xm1 <= d_m0z {
                out.push([x, m0, m1]);
                out.push([x, m1, z]);
            } else {
                out.push([x, m0, z]);
                out.push([m0, m1, z]);
            }
            Some(GreenFamily { parent: tri, mids })
        }
        _ => {
            let [m0, m1, m2] = mids.map(|v| v.0);
            out.extend([[a, m0, m2], [b, m1, m0], [c, m2, m1], [m0, m1, m2]]);
            None
        }
    }
}

#[inline]
fn pos(positions: &[Vec3], v: u32) -> Vec3 {
    positions.get(v as usize).copied().unwrap_or(Vec3::ZERO)
}

/// Builds the triangles of the refined mesh from the closure of [`close`](super::close) and the midpoint of
/// every split edge (`edge_mid[e]`, [`VertexId::NONE`] for unsplit edges).
///
/// Faces are emitted in the order of the input faces: a red triangle becomes its four Loop
/// children in the order of `subdiv_rules::refine_uniform` (corner children of the first,
/// second and third vertex, then the middle triangle), so refining every face gives exactly the
/// uniform mesh. A merged family emits its parent's four children at the position of its first
/// face; corner children of a merged parent whose outer half-edges were split again are closed
/// green. Green faces of unmerged families are kept with their family.
pub fn assemble(
    mesh: &Mesh,
    state: &GreenState,
    closure: &Closure,
    edge_mid: &[VertexId],
    positions: &[Vec3],
) -> Result<Assembly, RedGreenError> {
    let nf = mesh.num_faces();
    check_len("green family_of_face", state.family_of_face.len(), nf)?;
    check_len("closure red_face", closure.red_face.len(), nf)?;
    check_len(
        "closure split_edge",
        closure.split_edge.len(),
        mesh.num_edges(),
    )?;
    check_len("edge midpoints", edge_mid.len(), mesh.num_edges())?;
    check_len("closure merged", closure.merged.len(), state.families.len())?;
    for (e, (&s, &m)) in closure.split_edge.iter().zip(edge_mid).enumerate() {
        if s && (m == VertexId::NONE || m.idx() >= positions.len()) {
            return Err(RedGreenError::BadMidpoint {
                edge: e as u32,
                mid: m.0,
                count: positions.len() as u32,
            });
        }
    }
    let mid_of = |h: HalfedgeId| edge_mid[h.edge().idx()];
    let nfam = state.families.len();
    let mut out = Assembly {
        triangles: Vec::with_capacity(nf * 2),
        source_face: Vec::with_capacity(nf * 2),
        state: GreenState::default(),
    };
    let mut fam_map = vec![NO_FAMILY; nfam];
    let mut emitted = vec![false; nfam];
    for f in mesh.faces() {
        let h0 = mesh.face_halfedge(f);
        let hs = [h0, mesh.next(h0), mesh.prev(h0)];
        let corners = hs.map(|h| mesh.from(h));
        let fam = state.family_of_face[f.idx()];
        if fam != NO_FAMILY {
            let k = fam as usize;
            if closure.merged[k] {
                if emitted[k] {
                    continue;
                }
                emitted[k] = true;
                let g = state.families[k];
                let p = g.parent;
                let mut m = [VertexId::NONE; 3];
                for j in 0..3 {
                    m[j] = if g.mids[j].is_some() {
                        g.mids[j]
                    } else {
                        let h = mesh.find_halfedge(p[j], p[(j + 1) % 3]).ok_or(
                            RedGreenError::BrokenFamily {
                                family: fam,
                                a: p[j].0,
                                b: p[(j + 1) % 3].0,
                            },
                        )?;
                        mid_of(h)
                    };
                }
                // Outer halves of pre-split parent edges may have been split again.
                let half_mid = |a: VertexId, b: VertexId, pre: bool| -> VertexId {
                    if !pre {
                        return VertexId::NONE;
                    }
                    match mesh.find_halfedge(a, b) {
                        Some(h) => mid_of(h),
                        None => VertexId::NONE,
                    }
                };
                for j in 0..3 {
                    let jp = (j + 2) % 3;
                    let tri = [p[j], m[j], m[jp]];
                    let mids = [
                        half_mid(p[j], m[j], g.mids[j].is_some()),
                        VertexId::NONE,
                        half_mid(m[jp], p[j], g.mids[jp].is_some()),
                    ];
                    emit_closed(&mut out, tri, mids, f.0, positions);
                }
                out.triangles.push([m[0].0, m[1].0, m[2].0]);
                out.state.family_of_face.push(NO_FAMILY);
                out.source_face.push(f.0);
            } else {
                for h in hs {
                    if closure.split_edge[h.edge().idx()] {
                        return Err(RedGreenError::Inconsistent {
                            face: f.0,
                            edge: h.edge().0,
                        });
                    }
                }
                if fam_map[k] == NO_FAMILY {
                    out.state.families.push(state.families[k]);
                    fam_map[k] = (out.state.families.len() - 1) as u32;
                }
                out.triangles.push(corners.map(|v| v.0));
                out.state.family_of_face.push(fam_map[k]);
                out.source_face.push(f.0);
            }
        } else if closure.red_face[f.idx()] {
            let [a, b, c] = corners.map(|v| v.0);
            let [ea, eb, ec] = hs.map(|h| mid_of(h).0);
            out.triangles
                .extend([[a, ea, ec], [b, eb, ea], [c, ec, eb], [ea, eb, ec]]);
            out.state.family_of_face.extend([NO_FAMILY; 4]);
            out.source_face.extend([f.0; 4]);
        } else {
            let mids = hs.map(|h| {
                if closure.split_edge[h.edge().idx()] {
                    mid_of(h)
                } else {
                    VertexId::NONE
                }
            });
            emit_closed(&mut out, corners, mids, f.0, positions);
        }
    }
    Ok(out)
}

/// Appends `tri` closed green where `mids` says, recording its family and source face.
#[inline]
fn emit_closed(
    out: &mut Assembly,
    tri: [VertexId; 3],
    mids: [VertexId; 3],
    source: u32,
    positions: &[Vec3],
) {
    let before = out.triangles.len();
    let id = match split_triangle(tri, mids, positions, &mut out.triangles) {
        Some(g) => {
            out.state.families.push(g);
            (out.state.families.len() - 1) as u32
        }
        None => NO_FAMILY,
    };
    for _ in before..out.triangles.len() {
        out.state.family_of_face.push(id);
        out.source_face.push(source);
    }
}
