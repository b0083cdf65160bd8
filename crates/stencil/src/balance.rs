//! Which face computes a shared point. A point on a cage edge or at a cage vertex lies on
//! every face around it, each of which can compute it (the same limit point, rounded its own
//! way, and computed once: the surface stays watertight to the bit). The kernel runs a face's
//! points eight at a time, so a face holding 9 points pays for 16: the points are moved between
//! the faces that share them so that faces fill their blocks.
//!
//! Only points of quads and triangles move (an n-gon's tiles keep theirs), and only where that
//! saves at least [`MIN_SAVING`] of the lanes: a layout whose faces already fill their blocks
//! keeps its points where they are, and with them the faces alike in their points (`share`).

use subdiv_eval::Domain;
use subdiv_mesh::{FaceId, HalfedgeId, Mesh};
use subdiv_rules::{Scheme, VertexParams};

use crate::table::LANES;

/// Least share of the lanes moving the points must save.
const MIN_SAVING: f64 = 0.1;

/// Where a point may go: a face and the point's `(u, v)` in it.
type Place = (u32, [f32; 2]);

/// `params` with shared points moved between faces to fill the faces' blocks, or `None` where
/// that saves less than [`MIN_SAVING`] of the lanes.
pub(crate) fn balance(mesh: &Mesh, scheme: Scheme, params: &VertexParams) -> Option<VertexParams> {
    let nf = mesh.num_faces();
    let mut count = vec![0usize; nf];
    let mut places: Vec<(usize, Vec<Place>)> = Vec::new();
    for (i, (&f, &uv)) in params.face.iter().zip(&params.uv).enumerate() {
        let p = shared_places(mesh, scheme, f, uv);
        if p.len() > 1 {
            places.push((i, p));
        } else {
            count[f as usize] += 1;
        }
    }
    let lanes = |c: &[usize]| c.iter().map(|&n| n.next_multiple_of(LANES)).sum::<usize>();
    let before = {
        let mut c = vec![0usize; nf];
        for &f in &params.face {
            c[f as usize] += 1;
        }
        lanes(&c)
    };
    // Points with fewer places first (edges before vertices); each goes where it fills a
    // started block best, else to the face with the fewest points.
    places.sort_by_key(|(_, p)| p.len());
    let mut out = VertexParams {
        face: params.face.clone(),
        uv: params.uv.clone(),
    };
    for (i, p) in &places {
        let room = |f: u32| (LANES - count[f as usize] % LANES) % LANES;
        let best = p
            .iter()
            .filter(|(f, _)| room(*f) > 0)
            .min_by_key(|(f, _)| room(*f))
            .or_else(|| p.iter().min_by_key(|(f, _)| count[*f as usize]));
        if let Some(&(f, uv)) = best {
            count[f as usize] += 1;
            out.face[*i] = f;
            out.uv[*i] = uv;
        }
    }
    let after = lanes(&count);
    ((after as f64) < (1.0 - MIN_SAVING) * before as f64).then_some(out)
}

/// Every place of the point at `uv` of face `f`: the face itself, and where the point lies on a
/// cage edge or at a cage vertex of a quad or a triangle, each other face (not a hole, not an
/// n-gon) around it with the point's `(u, v)` there. Just `f` otherwise.
fn shared_places(mesh: &Mesh, scheme: Scheme, f: u32, uv: [f32; 2]) -> Vec<Place> {
    let face = FaceId(f);
    let n = mesh.face_size(face);
    let here = vec![(f, uv)];
    let domain = Domain::of(scheme, n);
    if !matches!(domain, Domain::Quad | Domain::Triangle) {
        return here;
    }
    let hs: Vec<HalfedgeId> = mesh.face_halfedges(face).collect();
    let [u, v] = uv.map(f64::from);
    if let Some(k) = (0..n).find(|&k| domain.corner(k) == [u, v]) {
        // A cage vertex: every face around it, at its corner there.
        let mut out = here;
        let centre = mesh.from(hs[k]);
        for h in mesh.outgoing(centre) {
            let g = mesh.face(h);
            if !g.is_some() || g == face || !movable(mesh, scheme, g) {
                continue;
            }
            let kg = mesh.face_halfedges(g).position(|x| x == h);
            if let Some(kg) = kg {
                let c = Domain::of(scheme, mesh.face_size(g)).corner(kg);
                out.push((g.0, c.map(|x| x as f32)));
            }
        }
        return out;
    }
    let Some((k, t)) = on_edge(domain, u, v) else {
        return here;
    };
    let twin = hs[k].twin();
    let g = mesh.face(twin);
    if !g.is_some() || !movable(mesh, scheme, g) {
        return here;
    }
    let Some(kg) = mesh.face_halfedges(g).position(|x| x == twin) else {
        return here;
    };
    let p = Domain::of(scheme, mesh.face_size(g)).edge_point(kg, 1.0 - t);
    let mut out = here;
    out.push((g.0, p.map(|x| x as f32)));
    out
}

/// Whether points may move onto face `g`: a quad or triangle domain, not a hole.
fn movable(mesh: &Mesh, scheme: Scheme, g: FaceId) -> bool {
    !mesh.is_hole(g)
        && matches!(
            Domain::of(scheme, mesh.face_size(g)),
            Domain::Quad | Domain::Triangle
        )
}

/// The edge `k` of a quad or triangle domain that `(u, v)` lies inside, and its parameter
/// along it (`Domain::edge_point(k, t)` is the point).
fn on_edge(domain: Domain, u: f64, v: f64) -> Option<(usize, f64)> {
    let inside = |t: f64| (t > 0.0 && t < 1.0).then_some(t);
    match domain {
        Domain::Quad => {
            if v == 0.0 {
                inside(u).map(|t| (0, t))
            } else if u == 1.0 {
                inside(v).map(|t| (1, t))
            } else if v == 1.0 {
                inside(1.0 - u).map(|t| (2, t))
            } else if u == 0.0 {
                inside(1.0 - v).map(|t| (3, t))
            } else {
                None
            }
        }
        Domain::Triangle => {
            if v == 0.0 {
                inside(u).map(|t| (0, t))
            } else if u + v == 1.0 {
                inside(v).map(|t| (1, t))
            } else if u == 0.0 {
                inside(1.0 - v).map(|t| (2, t))
            } else {
                None
            }
        }
        Domain::SubFaces { .. } => None,
    }
}
