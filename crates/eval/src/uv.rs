//! Face-varying values (UVs) as a limit surface of their own.
//!
//! Where a vertex's values agree around it, OpenSubdiv refines and limits them with the
//! positions' rules (creases included); along a seam or boundary every side's values are
//! refined on their own as a boundary (crease or corner), the options of
//! [`FVarLinearInterpolation`] deciding which are corners. That is the subdivision surface of
//! the *UV cage*: the cage cut open along its seams (one vertex per vertex and value, one per
//! fan of faces where a value comes back), positioned at the values, with the cage's
//! sharpness on its uncut edges and vertices, seams and boundaries as its boundaries, and the
//! options as its boundary interpolation and corner tags:
//!
//! | option | UV cage |
//! |---|---|
//! | `none` | boundaries smooth (`edge-only`) |
//! | `cornersOnly` | values spanning one face are corners (`edge-and-corner`) |
//! | `cornersPlus1` | and every value of a vertex with three or more values |
//! | `cornersPlus2` | and both values of a two-value vertex where one is a corner, and the value of a seam's end inside the cage (a dart) |
//! | `boundaries` | every value on a seam or boundary is a corner (piecewise linear there) |
//!
//! `all` keeps every value and takes midpoints and centroids at every level: the values are
//! bilinear over each quad (a Catmull-Clark n-gon: over each sub-face's level-1 quad) and
//! linear over each Loop triangle ([`linear_uv`]), without a cage of their own.
//!
//! Its faces are the cage's faces in the same order and corner order, so a face's `(u, v)`
//! names the same point on both, and [`FaceSurface`](crate::FaceSurface) evaluates it exactly
//! like the positions. OpenSubdiv's *dependent* sharpness of `cornersPlus1`/`cornersPlus2` (a
//! value held by the other value's semi-sharp fan, or made a corner by an infinitely sharp
//! edge in the other's fan) is a corner tag of that value (`dependent_sharpness`), exact under
//! uniform decay.

use std::collections::HashMap;

use glam::{DVec2, Vec3};
use subdiv_mesh::{
    BoundaryInterpolation, CornerTag, CreaseTag, FVarLinearInterpolation, FaceId, HoleTag, Mesh,
    PolygonSoup, SHARPNESS_INFINITE, VertexId,
};
use subdiv_rules::Scheme;

use crate::EvalError;

/// How a cage's UVs are evaluated.
#[derive(Clone, Debug)]
pub(crate) enum Uvs {
    /// As the limit surface of the UV cage.
    Cage(Box<Mesh>),
    /// (Bi)linearly (`all`).
    Linear,
}

/// How `mesh`'s UVs are evaluated (`None` without UVs).
pub(crate) fn uvs(mesh: &Mesh) -> Result<Option<Uvs>, EvalError> {
    if mesh.uv().is_none() {
        return Ok(None);
    }
    if mesh.options().fvar == FVarLinearInterpolation::All {
        return Ok(Some(Uvs::Linear));
    }
    Ok(uv_cage(mesh)?.map(|m| Uvs::Cage(Box::new(m))))
}

/// The value and derivatives (normalised sub-face coordinates) of the `all` option at
/// `(sub, s, t)` of face `f` ([`crate::Domain::locate`]).
pub(crate) fn linear_uv(
    mesh: &Mesh,
    f: FaceId,
    scheme: Scheme,
    sub: usize,
    s: f64,
    t: f64,
) -> [DVec2; 3] {
    let Some(fv) = mesh.uv() else {
        return [DVec2::ZERO; 3];
    };
    let (offsets, _) = mesh.face_lists();
    let n = mesh.face_size(f);
    let c = |k: usize| fv.corner(offsets[f.idx()] as usize + k).as_dvec2();
    let [p, du, dv, _] = crate::bilinear::over_face(c, n, scheme == Scheme::Loop, sub, s, t);
    [p, du, dv]
}

/// The UV cage of `mesh` (`None` without UVs).
fn uv_cage(mesh: &Mesh) -> Result<Option<Mesh>, EvalError> {
    let Some(fv) = mesh.uv() else {
        return Ok(None);
    };
    let opts = mesh.options();
    let (offsets, corners) = mesh.face_lists();
    // One UV-cage vertex per (cage vertex, value).
    let mut id: HashMap<(u32, u32), u32> = HashMap::new();
    let mut soup = PolygonSoup::default();
    let mut vertex_of: Vec<VertexId> = Vec::new();
    let mut uv_index = Vec::with_capacity(corners.len());
    for (c, v) in corners.iter().enumerate() {
        let value = fv.indices[c];
        let next = id.len() as u32;
        let i = *id.entry((v.0, value)).or_insert(next);
        if i == next {
            let uv = fv.values[value as usize];
            soup.positions.push(Vec3::new(uv.x, uv.y, 0.0));
            vertex_of.push(*v);
        }
        uv_index.push(i);
    }
    for f in mesh.faces() {
        let (a, b) = (offsets[f.idx()] as usize, offsets[f.idx() + 1] as usize);
        soup.push_face(uv_index[a..b].iter().map(|&i| i64::from(i)));
        if mesh.is_hole(f) {
            soup.holes.push(HoleTag {
                f: f.0 as i64,
                line: None,
            });
        }
    }
    // Sharpness of uncut edges: an edge whose two sides name the same pair of values.
    let corner_of = |f: usize, k: usize| uv_index[offsets[f] as usize + k];
    let mut seam_ends = vec![false; mesh.num_vertices()];
    for f in mesh.faces() {
        let n = mesh.face_size(f);
        let mut h = mesh.face_halfedge(f);
        for k in 0..n {
            let e = h.edge();
            let s = mesh.edge_sharpness(e);
            let (a, b) = (corner_of(f.idx(), k), corner_of(f.idx(), (k + 1) % n));
            let g = mesh.face(h.twin());
            if g.is_some() {
                let gk = mesh.face_vertices(g).iter().position(|&w| w == mesh.to(h));
                let gn = mesh.face_size(g);
                let uncut = gk.is_some_and(|gk| {
                    corner_of(g.idx(), gk) == b && corner_of(g.idx(), (gk + 1) % gn) == a
                });
                if !uncut {
                    seam_ends[mesh.from(h).idx()] = true;
                }
                if uncut && s > 0.0 {
                    soup.creases.push(CreaseTag {
                        a: a.into(),
                        b: b.into(),
                        sharpness: s,
                        line: None,
                    });
                }
            }
            h = mesh.next(h);
        }
    }
    let (values_at, one_face_at) = count_values(&vertex_of, &uv_index, mesh.num_vertices());
    let linear = opts.fvar;
    let dependent_sharp = dependent_sharpness(mesh, &soup.creases, &vertex_of);
    for (i, v) in vertex_of.iter().enumerate() {
        let s = mesh.vertex_sharpness(*v);
        let (values, one_face) = (values_at[v.idx()], one_face_at[v.idx()]);
        let extra = match linear {
            FVarLinearInterpolation::CornersPlus1 => values >= 3,
            FVarLinearInterpolation::CornersPlus2 => {
                values >= 3 || (values == 1 && seam_ends[v.idx()]) || (values == 2 && one_face)
            }
            _ => false,
        };
        let dependent = matches!(
            linear,
            FVarLinearInterpolation::CornersPlus1 | FVarLinearInterpolation::CornersPlus2
        );
        let sharpness = if extra || mesh.is_fvar_corner(*v) {
            SHARPNESS_INFINITE
        } else if dependent && values == 2 && dependent_sharp[i] > 0.0 {
            dependent_sharp[i]
        } else {
            s
        };
        if sharpness > 0.0 {
            soup.corners.push(CornerTag {
                v: i as i64,
                sharpness,
                line: None,
            });
        }
    }
    soup.options = opts;
    soup.options.boundary = match linear {
        FVarLinearInterpolation::None => BoundaryInterpolation::EdgeOnly,
        _ => BoundaryInterpolation::EdgeAndCorner,
    };
    soup.split_nonmanifold_vertices();
    let mut cage = Mesh::from_soup(&soup).map_err(EvalError::UvCage)?;
    if linear == FVarLinearInterpolation::Boundaries {
        for v in cage.vertices() {
            if cage.is_boundary_vertex(v) {
                cage.set_vertex_sharpness(v, SHARPNESS_INFINITE);
            }
        }
    }
    Ok(Some(cage))
}

/// Per UV-cage vertex, the corner sharpness that reproduces OpenSubdiv's sharpening of one of
/// a vertex's two values by the other (`cornersPlus1`/`cornersPlus2`), 0 where none:
/// - an infinitely sharp edge inside either fan makes both values corners;
/// - *dependent sharpness* (`subdiv_mesh::Dependence`): of the two values at a vertex that is
///   not semi-sharp itself, the one whose fan has no semi-sharp edge is held in place while
///   the other's fan has one. Under uniform decay that is a corner of the other fan's greatest
///   semi-sharpness `s` (held while it lasts, blended by its last fraction), or of `ceil(s)`
///   where another edge of the vertex outlasts it (held one level more, then a plain crease).
///   Chaikin decay of those edges is not followed.
fn dependent_sharpness(mesh: &Mesh, creases: &[CreaseTag], vertex_of: &[VertexId]) -> Vec<f32> {
    let semi = |s: f32| s > 0.0 && s < SHARPNESS_INFINITE;
    // Per UV vertex: the greatest semi-sharpness of the uncut edges of its fan, and whether
    // one of them is infinitely sharp.
    let mut fan = vec![0.0f32; vertex_of.len()];
    let mut inf = vec![false; vertex_of.len()];
    for c in creases {
        for end in [c.a, c.b] {
            let Some(i) = usize::try_from(end).ok().filter(|&i| i < fan.len()) else {
                continue;
            };
            if semi(c.sharpness) {
                fan[i] = fan[i].max(c.sharpness);
            } else if c.sharpness >= SHARPNESS_INFINITE {
                inf[i] = true;
            }
        }
    }
    let mut values: HashMap<u32, Vec<usize>> = HashMap::new();
    for (i, v) in vertex_of.iter().enumerate() {
        values.entry(v.0).or_default().push(i);
    }
    let mut out = vec![0.0f32; vertex_of.len()];
    for (&v, ids) in &values {
        let v = VertexId(v);
        let [a, b] = ids[..] else { continue };
        if inf[a] || inf[b] {
            (out[a], out[b]) = (SHARPNESS_INFINITE, SHARPNESS_INFINITE);
            continue;
        }
        if semi(mesh.vertex_sharpness(v)) || (fan[a] > 0.0) == (fan[b] > 0.0) {
            continue;
        }
        let (free, other) = if fan[a] > 0.0 { (b, a) } else { (a, b) };
        let s = fan[other];
        let outlasted = mesh
            .outgoing(v)
            .map(|h| mesh.edge_sharpness(h.edge()))
            .any(|e| semi(e) && e > s.ceil());
        out[free] = if outlasted { s.ceil() } else { s };
    }
    out
}

/// How many values each cage vertex has, and whether one of them spans a single face.
fn count_values(vertex_of: &[VertexId], uv_index: &[u32], n: usize) -> (Vec<u32>, Vec<bool>) {
    let mut count = vec![0u32; n];
    for v in vertex_of {
        count[v.idx()] += 1;
    }
    let mut faces = vec![0u32; vertex_of.len()];
    for &i in uv_index {
        faces[i as usize] += 1;
    }
    let mut one_face = vec![false; n];
    for (i, v) in vertex_of.iter().enumerate() {
        one_face[v.idx()] |= faces[i] == 1;
    }
    (count, one_face)
}
