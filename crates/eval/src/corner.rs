//! The limit at a corner no polynomial patch reaches: an extraordinary vertex, a dart, a
//! crease or corner vertex whose sector is not a regular half-plane, a copy of a non-manifold
//! vertex. The patches around such a vertex shrink towards it level by level; the point
//! itself is the vertex's limit from its ring (`subdiv-rules`' [`Ring`] limit masks, taken
//! once no semi-sharp feature is left). At a corner (the vertex stays put) the normal of the
//! face's side is that of its sector, spanned by the two sharp edges bounding it (their crease
//! curves start along them): OpenSubdiv's corner masks take the first two edges of the ring
//! instead, which are not the sector's where it has more than one face. Elsewhere the ring is
//! refined on until the masks' position and normal no longer change from one level to the next: where OpenSubdiv's masks are not the limit of the
//! rules it applies (a dart, a smooth vertex of valence 2, a crease or corner vertex whose
//! sector is not a regular half-plane: Biermann et al.'s tangent masks are those of their
//! modified rules), that is the limit of the level-by-level values, to rounding (the ring is
//! moved to its own centre after every level, so its relative precision holds at any depth).
//!
//! The parameterisation is singular there, so the derivatives are defined as: along the
//! patch's two sides, the limit tangents of those sides (at a smooth vertex the tangent masks
//! of the ring turned to start at that side, in the scale of a regular vertex's B-spline or box
//! spline derivative; elsewhere the side's vector at the deepest level used, projected into
//! the exact one-sided tangent plane). Their cross product is the exact limit normal of the
//! patch's side of the vertex. Second derivatives are zero there.

use glam::DVec3;
use subdiv_rules::crease::Rule;
use subdiv_rules::{Ring, Scheme, catmark, loop_scheme};

/// Most levels a corner is refined by to settle its limit.
const MAX_LEVELS: u32 = 160;

/// The corner's limit position and the derivatives along the patch's side towards the next
/// corner (`next`) and towards the previous one (`prev`), each for a side of length 1.
pub(crate) struct CornerLimit {
    pub position: DVec3,
    pub next: DVec3,
    pub prev: DVec3,
}

/// Position and the normal of the patch's side (face `f` of the ring).
fn sided(r: &mut Ring, f: usize, faces: &mut Vec<DVec3>) -> (DVec3, DVec3) {
    let (p, n) = r.limit_sided(faces);
    (p, faces.get(f).copied().unwrap_or(n))
}

/// The limit at corner ring `ring` of a patch that is its face `f`.
pub(crate) fn corner_limit(ring: &Ring, f: usize, scheme: Scheme) -> CornerLimit {
    // The ring is kept about its own centre, moved there after every level: its points
    // converge on the limit position, not on the cage vertex, so a ring left about the cage
    // vertex would lose its relative precision after some 50 levels (its spread below the
    // rounding of its distance from there) and give degenerate tangents.
    let mut r = ring.clone();
    let mut origin = DVec3::ZERO;
    recentre(&mut r, &mut origin);
    let mut levels = 0u32;
    while r.needs_refinement() && levels < MAX_LEVELS {
        r.refine();
        recentre(&mut r, &mut origin);
        levels += 1;
    }
    let size = (0..r.valence())
        .map(|i| r.edge(i).length())
        .fold(0.0, f64::max);
    let mut faces = Vec::new();
    let (mut position, mut normal) = sided(&mut r, f, &mut faces);
    let corner = Rule::determine(r.vertex_sharpness(), r.edge_sharpnesses()) == Rule::Corner;
    let sector = if corner && !r.has_master() {
        sector_normal(&r, f, position)
    } else {
        None
    };
    if let Some(n) = sector {
        normal = n;
    }
    while levels < MAX_LEVELS && sector.is_none() {
        let mut next = r.clone();
        next.refine();
        let mut shift = DVec3::ZERO;
        recentre(&mut next, &mut shift);
        // `p` is about the next ring's centre, `position` about this one's.
        let (p, n) = sided(&mut next, f, &mut faces);
        let moved = (p + shift - position).length();
        let settled = moved <= 1e-14 * size && (n - normal).length() <= 1e-14;
        (r, position, normal) = (next, p, n);
        origin += shift;
        levels += 1;
        if settled {
            break;
        }
    }
    let level_scale = 2f64.powi(levels as i32);
    let (next, prev) = side_tangents(&r, f, scheme, position, normal);
    let (next, prev) = facing(next, prev, normal);
    CornerLimit {
        position: position + origin,
        next: next * level_scale,
        prev: prev * level_scale,
    }
}

/// Moves ring `r` to its own centre, adding what it moved by to `origin`.
fn recentre(r: &mut Ring, origin: &mut DVec3) {
    let c = r.center();
    r.translate(-c);
    *origin += c;
}

/// At a corner (the vertex stays, its sharp edges' crease curves start along those edges):
/// the normal of the sector holding face `f`, spanned by the two sharp edges that bound it and
/// oriented like its faces; `None` where one sharp edge or none bounds it (a cone point).
fn sector_normal(r: &Ring, f: usize, p: DVec3) -> Option<DVec3> {
    let n = r.valence();
    let sharp = |i: usize| subdiv_rules::crease::is_infinite(r.edge_sharpnesses()[i % n]);
    let back = (0..n).map(|k| (f + n - k) % n).find(|&i| sharp(i))?;
    let ahead = (1..=n).map(|k| (f + k) % n).find(|&i| sharp(i))?;
    if back == ahead {
        return None;
    }
    let e = |i: usize| r.edge(i % n) - p;
    let mut area = DVec3::ZERO;
    let mut i = back;
    while i % n != ahead {
        area += e(i).cross(e(i + 1));
        i += 1;
    }
    let v = e(back).cross(e(ahead));
    let len = v.length();
    if len <= 1e-12 * e(back).length() * e(ahead).length() || !len.is_finite() {
        return None;
    }
    Some(if v.dot(area) < 0.0 { -v / len } else { v / len })
}

/// The tangents `next`, `prev` made to span the plane of `n` with `next x prev` along `n`:
/// kept where they do (to rounding), else `prev` replaced by `next` turned a quarter about `n`
/// (a folded or degenerate ring, or a copy of a non-manifold vertex whose limit is another
/// copy's), so that the derivatives' normal is the exact limit normal everywhere.
fn facing(next: DVec3, prev: DVec3, n: DVec3) -> (DVec3, DVec3) {
    let c = next.cross(prev);
    if n == DVec3::ZERO || c.dot(n) >= (1.0 - 1e-12) * c.length() && c.length() > 0.0 {
        return (next, prev);
    }
    let next = if next.cross(n).length_squared() > 0.0 {
        next - n * next.dot(n)
    } else {
        n.any_orthogonal_vector()
    };
    let len = prev.length().max(next.length());
    (next, n.cross(next).normalize_or_zero() * len)
}

/// The tangents along ring edges `f` and `f + 1` (see the module docs), for sides as long as
/// the ring's edges.
fn side_tangents(r: &Ring, f: usize, scheme: Scheme, p: DVec3, n: DVec3) -> (DVec3, DVec3) {
    let valence = r.valence();
    let rule = Rule::determine(r.vertex_sharpness(), r.edge_sharpnesses());
    let smooth = rule == Rule::Smooth && !r.is_boundary() && valence >= 3;
    let turned = |start: usize| -> DVec3 {
        let e: Vec<DVec3> = (0..valence)
            .map(|i| r.edge((start + i) % valence))
            .collect();
        match scheme {
            Scheme::CatmullClark => {
                let d: Vec<DVec3> = (0..valence)
                    .map(|i| r.diag((start + i) % valence))
                    .collect();
                catmark::limit(r.center(), &e, &d, Rule::Smooth).1 / 12.0
            }
            Scheme::Loop => loop_scheme::limit(r.center(), &e, Rule::Smooth, false).1 / 3.0,
            Scheme::Bilinear => {
                unreachable!("bilinear faces are their corners' patches (FaceSurface::load)")
            }
        }
    };
    let along = |i: usize| {
        let v = r.edge(i % valence) - p;
        v - n * v.dot(n)
    };
    if smooth && (scheme == Scheme::Loop || r.all_quads()) {
        (turned(f), turned((f + 1) % valence))
    } else {
        (along(f), along(f + 1))
    }
}
