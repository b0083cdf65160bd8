//! Catmull-Clark rules: refinement points and limit masks.
//!
//! Refinement: E. Catmull and J. Clark, "Recursively generated B-spline surfaces on arbitrary
//! topological meshes", Computer-Aided Design 10(6), 1978, in the form with face-point centroids
//! used by OpenSubdiv (vertex point `((n-2)/n) v + (1/n^2) sum e_i + (1/n^2) sum f_i`), with the
//! crease rules of Hoppe et al. 1994 and DeRose et al. 1998 (see [`crate::crease`]). Faces of any
//! size are allowed; an n-gon yields n quads.
//!
//! Limit masks: position and tangents for smooth vertices from Halstead, Kass and DeRose,
//! "Efficient, fair interpolation using Catmull-Clark surfaces", SIGGRAPH 1993; crease and
//! boundary tangents from Biermann, Levin and Zorin, "Piecewise smooth subdivision surfaces with
//! normal control", SIGGRAPH 2000. Limit masks need a ring of quads (any level >= 1).

use std::f64::consts::PI;

use subdiv_mesh::TriangleSubdivision;

use crate::crease::{Rule, VertexRules};
use crate::point::{Point, centroid};

/// The face point: the centroid of the face's vertices.
#[inline]
pub fn face_point<P: Point>(face: &[P]) -> P {
    if let [a, b, c, d] = face {
        return a.add(*b).add(c.add(*d)).scale(0.25);
    }
    centroid(face.iter().copied())
}

/// The edge point of edge `a`-`b` with adjacent face points `faces` (one for a boundary edge),
/// and the crease weight from [`crate::crease::edge_crease_weight`].
#[inline]
pub fn edge_point<P: Point>(a: P, b: P, faces: &[P], crease_weight: f32) -> P {
    edge_point_weighted(a, b, faces, crease_weight, 0.25)
}

/// OpenSubdiv's `CATMARK_SMOOTH_TRI_EDGE_WEIGHT` (sdc/catmarkScheme.h).
pub const SMOOTH_TRI_EDGE_WEIGHT: f64 = 0.470;

/// The weight of each face point in the smooth edge point of an edge between two faces of
/// `face_sizes` vertices: 1/4, except under [`TriangleSubdivision::Smooth`] next to a triangle,
/// where OpenSubdiv (`Sdc::Scheme<SCHEME_CATMARK>::assignSmoothMaskForEdge`) takes the mean of
/// [`SMOOTH_TRI_EDGE_WEIGHT`] per triangle and 1/4 per other face; the edge's ends then weigh
/// `(1 - 2 w) / 2` each. Only the edge rule changes (and only where a triangle is, so only at
/// level 0): face and vertex points keep the Catmull-Clark rules.
#[inline]
pub fn edge_face_weight(triangles: TriangleSubdivision, face_sizes: [usize; 2]) -> f64 {
    let tri = face_sizes.map(|n| n == 3);
    if triangles != TriangleSubdivision::Smooth || !(tri[0] || tri[1]) {
        return 0.25;
    }
    let w = tri.map(|t| if t { SMOOTH_TRI_EDGE_WEIGHT } else { 0.25 });
    0.5 * (w[0] + w[1])
}

/// [`edge_point`] with the weight of each of the two face points in the smooth rule
/// ([`edge_face_weight`]; 1/4 is the plain rule).
#[inline]
pub fn edge_point_weighted<P: Point>(
    a: P,
    b: P,
    faces: &[P],
    crease_weight: f32,
    face_weight: f64,
) -> P {
    let mid = a.add(b).scale(0.5);
    if crease_weight == 1.0 || faces.len() < 2 {
        return mid;
    }
    let smooth = if faces.len() == 2 && face_weight == 0.25 {
        a.add(b).add(faces[0]).add(faces[1]).scale(0.25)
    } else if faces.len() == 2 {
        let wv = 0.5 * (1.0 - 2.0 * face_weight);
        a.add(b)
            .scale(wv)
            .add(faces[0].add(faces[1]).scale(face_weight))
    } else {
        // Non-manifold edges never reach here (meshes are validated manifold); keep the
        // OpenSubdiv convention for completeness: half on the edge, half spread over the faces.
        mid.scale(0.5)
            .add(centroid(faces.iter().copied()).scale(0.5))
    };
    if crease_weight <= 0.0 {
        smooth
    } else {
        let w = crease_weight as f64;
        mid.scale(w).add(smooth.scale(1.0 - w))
    }
}

/// The vertex point of `v` with edge neighbours `edges` (ring order) and face points `faces`
/// (face `i` between edges `i` and `i+1`), under `rules`.
#[inline]
pub fn vertex_point<P: Point>(v: P, edges: &[P], faces: &[P], rules: &VertexRules) -> P {
    let p = apply_vertex_rule(v, edges, faces, rules.parent);
    if rules.is_simple() {
        return p;
    }
    let c = apply_vertex_rule(v, edges, faces, rules.child);
    let w = rules.parent_weight;
    p.scale(w).add(c.scale(1.0 - w))
}

#[inline]
fn apply_vertex_rule<P: Point>(v: P, edges: &[P], faces: &[P], rule: Rule) -> P {
    match rule {
        Rule::Smooth | Rule::Dart => {
            let n = edges.len();
            if n == 4 && faces.len() == 4 {
                // Regular: 1/2 v + 1/16 (sum e + sum f).
                let s = edges[0].add(edges[1]).add(edges[2]).add(edges[3]);
                let s = s.add(faces[0]).add(faces[1]).add(faces[2]).add(faces[3]);
                return v.scale(0.5).add(s.scale(1.0 / 16.0));
            }
            let nf = n as f64;
            let mut s = P::ZERO;
            for e in edges {
                s = s.add(*e);
            }
            for f in faces {
                s = s.add(*f);
            }
            v.scale((nf - 2.0) / nf).add(s.scale(1.0 / (nf * nf)))
        }
        Rule::Crease([i, j]) => v.scale(0.75).add(edges[i].add(edges[j]).scale(0.125)),
        Rule::Corner => v,
    }
}

/// The smooth regular rules in separable form, first half: one row of a regular grid split
/// along its length by the uniform cubic B-spline rules (Lane and Riesenfeld 1980): between each
/// two points their midpoint, at each interior point `(p[k-1] + 6 p[k] + p[k+1]) / 8`.
/// `out.len() == 2 * row.len() - 3` (from the first midpoint to the last).
///
/// On a regular quad grid Catmull-Clark's face, edge and vertex rules are the tensor products of
/// these two (`1/4 (1,1) x (1,1)`, `1/16 (1,1) x (1,6,1)`, `1/64 (1,6,1) x (1,6,1)`), so a grid is
/// refined by splitting its rows with this function, then combining the split rows with
/// [`split_rows_mid`] and [`split_rows_even`]: fewer operations than the three rules point by
/// point, the same points up to rounding.
///
/// ```
/// use glam::Vec3A;
/// use subdiv_rules::catmark::{edge_point, face_point, split_row, split_rows_even, split_rows_mid};
/// use subdiv_rules::catmark::vertex_point;
/// use subdiv_rules::crease::{Rule, VertexRules};
/// let p = |i: usize, j: usize| Vec3A::new(i as f32, j as f32, ((i * 5 + j * 3) % 4) as f32);
/// let rows: Vec<Vec<Vec3A>> = (0..3).map(|j| (0..3).map(|i| p(i, j)).collect()).collect();
/// let mut h = vec![vec![Vec3A::ZERO; 3]; 3];
/// for j in 0..3 {
///     split_row(&rows[j], &mut h[j]);
/// }
/// let (mut even, mut mid) = (vec![Vec3A::ZERO; 3], vec![Vec3A::ZERO; 3]);
/// split_rows_even(&h[0], &h[1], &h[2], &mut even);
/// split_rows_mid(&h[1], &h[2], &mut mid);
/// // mid[0]: face point of the quad (0,1)-(1,2); even[1]: vertex point of (1,1);
/// // mid[1]: edge point of the edge (1,1)-(1,2).
/// let f = |i: usize, j: usize| face_point(&[p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1)]);
/// assert!((mid[0] - f(0, 1)).length() < 1e-6);
/// assert!((mid[1] - edge_point(p(1, 1), p(1, 2), &[f(0, 1), f(1, 1)], 0.0)).length() < 1e-6);
/// let smooth = VertexRules { parent: Rule::Smooth, child: Rule::Smooth, parent_weight: 1.0 };
/// let v = vertex_point(p(1, 1), &[p(2, 1), p(1, 2), p(0, 1), p(1, 0)],
///     &[f(1, 1), f(0, 1), f(0, 0), f(1, 0)], &smooth);
/// assert!((even[1] - v).length() < 1e-6);
/// ```
#[inline]
pub fn split_row<P: Point>(row: &[P], out: &mut [P]) {
    let l = row.len();
    assert!(
        l >= 3 && out.len() + 3 == 2 * l,
        "split_row: output must hold 2 * len - 3 points"
    );
    for (o, w) in out.chunks_exact_mut(2).zip(row.windows(3)) {
        o[0] = w[0].add(w[1]).scale(0.5);
        o[1] = w[0].add(w[2]).madd(w[1], 6.0).scale(0.125);
    }
    out[2 * l - 4] = row[l - 2].add(row[l - 1]).scale(0.5);
}

/// [`split_row`]'s second half, across rows: the new row between split rows `a` and `b`
/// (their midpoints).
#[inline]
pub fn split_rows_mid<P: Point>(a: &[P], b: &[P], out: &mut [P]) {
    for ((o, a), b) in out.iter_mut().zip(a).zip(b) {
        *o = a.add(*b).scale(0.5);
    }
}

/// [`split_row`]'s second half, across rows: the new row at split row `b`, between `a` and `c`
/// (`(a + 6 b + c) / 8`).
#[inline]
pub fn split_rows_even<P: Point>(a: &[P], b: &[P], c: &[P], out: &mut [P]) {
    for (((o, a), b), c) in out.iter_mut().zip(a).zip(b).zip(c) {
        *o = a.add(*c).madd(*b, 6.0).scale(0.125);
    }
}

/// Limit position and two tangents of a vertex whose ring is made of quads.
///
/// `edges[i]` are the edge neighbours in counter-clockwise order and `diag[i]` the vertex of quad
/// `i` (between edges `i` and `i+1`) opposite `v`. For a boundary vertex there is one edge more
/// than quads, edge 0 and the last edge being the boundary. `rule` is the vertex's rule at this
/// level (with no semi-sharp feature left, it is its rule at every finer level too).
///
/// As in OpenSubdiv (`Sdc::Scheme<SCHEME_CATMARK>::assignSmoothLimitMask` and
/// `assignSmoothLimitTangentMasks`), a smooth or dart vertex of valence 2 takes the corner masks
/// ([`corner_limit`]): its "limit" is its own position at this level.
#[inline]
pub fn limit<P: Point>(v: P, edges: &[P], diag: &[P], rule: Rule) -> (P, P, P) {
    let n = edges.len();
    match rule {
        Rule::Smooth | Rule::Dart if n == 2 => corner_limit(v, edges),
        Rule::Smooth | Rule::Dart if n >= 3 && diag.len() == n => {
            let nf = n as f64;
            let (wv, we, wf) = if n == 4 {
                (4.0 / 9.0, 1.0 / 9.0, 1.0 / 36.0)
            } else {
                let wf = 1.0 / (nf * (nf + 5.0));
                (1.0 - nf * 5.0 * wf, 4.0 * wf, wf)
            };
            let mut pos = v.scale(wv);
            for i in 0..n {
                pos = pos.madd(edges[i], we).madd(diag[i], wf);
            }
            if n == 4 {
                return limit_regular(
                    v,
                    [edges[0], edges[1], edges[2], edges[3]],
                    [diag[0], diag[1], diag[2], diag[3]],
                );
            }
            // Tangents: sum A cos(2 pi i/n) e_i + (cos(2 pi i/n) + cos(2 pi (i+1)/n)) f_i, and
            // the same with sines; A = 1 + cos(2pi/n) + cos(pi/n) sqrt(2 (9 + cos(2pi/n))).
            let th = 2.0 * PI / nf;
            let a = 1.0 + th.cos() + (th * 0.5).cos() * (2.0 * (9.0 + th.cos())).sqrt();
            let mut t1 = P::ZERO;
            let mut t2 = P::ZERO;
            for i in 0..n {
                let (s0, c0) = (th * i as f64).sin_cos();
                let (s1, c1) = (th * (i + 1) as f64).sin_cos();
                t1 = t1.madd(edges[i], a * c0).madd(diag[i], c0 + c1);
                t2 = t2.madd(edges[i], a * s0).madd(diag[i], s0 + s1);
            }
            (pos, t1, t2)
        }
        Rule::Crease([c0, c1]) => {
            let pos = v
                .scale(2.0 / 3.0)
                .add(edges[c0].add(edges[c1]).scale(1.0 / 6.0));
            let t1 = edges[c0].sub(edges[c1]).scale(0.5);
            let t2 = crease_cross_tangent(v, edges, diag, c0, c1);
            (pos, t1, t2)
        }
        // Corners, and rings too small for their rule.
        _ => corner_limit(v, edges),
    }
}

/// The corner limit masks (OpenSubdiv `assignCornerLimitMask`, `assignCornerLimitTangentMasks`):
/// the vertex itself, tangents along its first two edges (`e0 - v`, `e1 - v`; zero where the ring
/// has fewer edges).
#[inline]
pub fn corner_limit<P: Point>(v: P, edges: &[P]) -> (P, P, P) {
    let t1 = edges.first().map_or(P::ZERO, |e| e.sub(v));
    let t2 = edges.get(1).map_or(P::ZERO, |e| e.sub(v));
    (v, t1, t2)
}

/// [`limit`] for a smooth regular (valence-4, interior) vertex: the bicubic B-spline at a knot.
/// Position `(16 v + 4 sum e + sum d) / 36`; tangents with `A = 4` and cosines `(1, 0, -1, 0)`.
#[inline(always)]
pub fn limit_regular<P: Point>(v: P, e: [P; 4], d: [P; 4]) -> (P, P, P) {
    let es = e[0].add(e[1]).add(e[2].add(e[3]));
    let ds = d[0].add(d[1]).add(d[2].add(d[3]));
    let pos = v
        .scale(4.0 / 9.0)
        .add(es.scale(1.0 / 9.0))
        .add(ds.scale(1.0 / 36.0));
    let d02 = d[0].sub(d[2]);
    let d13 = d[1].sub(d[3]);
    let t1 = e[0].sub(e[2]).scale(4.0).add(d02.sub(d13));
    let t2 = e[1].sub(e[3]).scale(4.0).add(d02.add(d13));
    (pos, t1, t2)
}

/// Row sums for the separable form of [`limit_regular`]: for each `k` in `1..row.len() - 1`,
/// `b[k - 1] = row[k - 1] + 4 row[k] + row[k + 1]` and `a[k - 1] = row[k + 1] - row[k - 1]`.
///
/// The bicubic B-spline's knot masks are tensor products of `(1, 4, 1)` and `(-1, 0, 1)`, so a
/// grid evaluates its rows' sums once and [`limit_regular_from_sums`] combines three rows of
/// them per point: each row's sums serve the three output rows around it.
///
/// ```
/// use glam::Vec3A;
/// use subdiv_rules::catmark::{limit_regular, limit_regular_from_sums, limit_row_sums};
/// let p = |i: usize, j: usize| Vec3A::new(i as f32, j as f32, ((i * 7 + j * 3) % 5) as f32);
/// let rows: Vec<Vec<Vec3A>> = (0..3).map(|j| (0..3).map(|i| p(i, j)).collect()).collect();
/// let (mut b, mut a) = ([[Vec3A::ZERO; 1]; 3], [[Vec3A::ZERO; 1]; 3]);
/// for j in 0..3 {
///     limit_row_sums(&rows[j], &mut b[j], &mut a[j]);
/// }
/// let (pos, t1, t2) = limit_regular_from_sums([b[0][0], b[1][0], b[2][0]], [a[0][0], a[1][0], a[2][0]]);
/// let e = [p(2, 1), p(1, 2), p(0, 1), p(1, 0)];
/// let d = [p(2, 2), p(0, 2), p(0, 0), p(2, 0)];
/// let (pos2, u1, u2) = limit_regular(p(1, 1), e, d);
/// assert!((pos - pos2).length() < 1e-6 && (t1 - u1).length() < 1e-5 && (t2 - u2).length() < 1e-5);
/// ```
#[inline]
pub fn limit_row_sums<P: Point>(row: &[P], b: &mut [P], a: &mut [P]) {
    for ((w, b), a) in row.windows(3).zip(b.iter_mut()).zip(a.iter_mut()) {
        *b = w[0].add(w[2]).madd(w[1], 4.0);
        *a = w[2].sub(w[0]);
    }
}

/// [`limit_regular`] from the [`limit_row_sums`] of the rows below, at and above the point
/// (`b[0]`, `b[1]`, `b[2]`, and likewise `a`): the same position and tangents (up to rounding).
#[inline(always)]
pub fn limit_regular_from_sums<P: Point>(b: [P; 3], a: [P; 3]) -> (P, P, P) {
    let pos = b[0].add(b[2]).madd(b[1], 4.0).scale(1.0 / 36.0);
    let t1 = a[0].add(a[2]).madd(a[1], 4.0);
    let t2 = b[2].sub(b[0]);
    (pos, t1, t2)
}

/// Tangent across a crease, over the quads between crease edges `c0 < c1` (Biermann et al. 2000;
/// the regular case is the uniform B-spline cross tangent).
fn crease_cross_tangent<P: Point>(v: P, edges: &[P], diag: &[P], c0: usize, c1: usize) -> P {
    let interior = c1 - c0 - 1;
    match interior {
        0 => edges[c0].add(edges[c1]).scale(3.0).sub(v.scale(6.0)),
        1 => {
            let mut t = v.scale(-4.0 / 6.0);
            t = t
                .madd(edges[c0], -1.0 / 6.0)
                .madd(edges[c0 + 1], 4.0 / 6.0)
                .madd(edges[c1], -1.0 / 6.0);
            t.madd(diag[c0], 1.0 / 6.0).madd(diag[c0 + 1], 1.0 / 6.0)
        }
        _ => {
            let k = (interior + 1) as f64;
            let th = PI / k;
            let (s, c) = th.sin_cos();
            let denom = 1.0 / (k * (3.0 + c));
            let r = (c + 1.0) / s;
            let mut t = v.scale(4.0 * r * (c - 1.0) * denom);
            let wc = -r * (1.0 + 2.0 * c) * denom;
            t = t.madd(edges[c0], wc).madd(edges[c1], wc);
            t = t.madd(diag[c0], s * denom);
            for i in 1..=interior {
                let si = (i as f64 * th).sin();
                let si1 = ((i + 1) as f64 * th).sin();
                t = t.madd(edges[c0 + i], 4.0 * si * denom);
                t = t.madd(diag[c0 + i], (si + si1) * denom);
            }
            t
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::crease::VertexRules;
    use glam::DVec3;
    use subdiv_mesh::CreaseMethod;

    fn rules(vs: f32, es: &[f32]) -> VertexRules {
        let mut c = vec![0.0; es.len()];
        VertexRules::new(CreaseMethod::Uniform, vs, es, &mut c)
    }

    /// Regular grid z = f(x, y) sampled at integers around the origin.
    fn regular_ring(f: impl Fn(f64, f64) -> f64) -> (DVec3, Vec<DVec3>, Vec<DVec3>) {
        let p = |x: f64, y: f64| DVec3::new(x, y, f(x, y));
        let e = vec![p(1., 0.), p(0., 1.), p(-1., 0.), p(0., -1.)];
        let d = vec![p(1., 1.), p(-1., 1.), p(-1., -1.), p(1., -1.)];
        (p(0., 0.), e, d)
    }

    #[test]
    fn regular_limit_is_bicubic_bspline() {
        // Uniform cubic B-spline at a knot: (1/6, 4/6, 1/6) tensor product. For z = x^2 the limit
        // at the centre is (1 + 1)/6 = 1/3; for z = x*y it is 0.
        let (v, e, d) = regular_ring(|x, _| x * x);
        let (p, t1, t2) = limit(v, &e, &d, Rule::Smooth);
        assert!((p.z - 1.0 / 3.0).abs() < 1e-12, "{p}");
        // The tangent plane of a symmetric bump at its centre is horizontal.
        let n = t1.cross(t2).normalize();
        assert!((n.z.abs() - 1.0).abs() < 1e-12);
        let (v, e, d) = regular_ring(|x, y| x * y + 2.0 * x);
        let (p, t1, t2) = limit(v, &e, &d, Rule::Smooth);
        assert!(p.z.abs() < 1e-12);
        // dz/dx = 2 at the origin: normal ~ (-2, 0, 1).
        let n = t1.cross(t2).normalize();
        let want = DVec3::new(-2.0, 0.0, 1.0).normalize();
        assert!(
            (n - want).length() < 1e-12 || (n + want).length() < 1e-12,
            "{n}"
        );
    }

    #[test]
    fn smooth_vertex_point_regular() {
        // Regular vertex: 1/2 v + 1/16 (sum e + sum f). Face points of the unit grid are the quad
        // centres.
        let v = DVec3::new(0.0, 0.0, 1.0);
        let e = [DVec3::X, DVec3::Y, -DVec3::X, -DVec3::Y];
        let f = [
            DVec3::new(0.5, 0.5, 0.0),
            DVec3::new(-0.5, 0.5, 0.0),
            DVec3::new(-0.5, -0.5, 0.0),
            DVec3::new(0.5, -0.5, 0.0),
        ];
        let p = vertex_point(v, &e, &f, &rules(0.0, &[0.0; 4]));
        assert!((p - DVec3::new(0.0, 0.0, 0.5)).length() < 1e-15);
        // Valence 3: (n-2)/n v + (sum e + sum f)/n^2.
        let p = vertex_point(v, &e[..3], &f[..3], &rules(0.0, &[0.0; 3]));
        let want = v / 3.0 + (e[0] + e[1] + e[2] + f[0] + f[1] + f[2]) / 9.0;
        assert!((p - want).length() < 1e-15);
    }

    #[test]
    fn crease_and_corner_vertex_points() {
        let v = DVec3::new(0.0, 0.0, 1.0);
        let e = [DVec3::X, DVec3::Y, -DVec3::X, -DVec3::Y];
        let f = [DVec3::ZERO; 4];
        let p = vertex_point(v, &e, &f, &rules(0.0, &[10.0, 0.0, 10.0, 0.0]));
        assert!((p - DVec3::new(0.0, 0.0, 0.75)).length() < 1e-15);
        let p = vertex_point(v, &e, &f, &rules(10.0, &[0.0; 4]));
        assert_eq!(p, v);
        // Half-sharp crease: average of crease and smooth point.
        let smooth = vertex_point(v, &e, &f, &rules(0.0, &[0.0; 4]));
        let p = vertex_point(v, &e, &f, &rules(0.0, &[0.5, 0.0, 0.5, 0.0]));
        assert!((p - (0.5 * smooth + 0.5 * DVec3::new(0.0, 0.0, 0.75))).length() < 1e-15);
    }

    #[test]
    fn edge_points() {
        let (a, b) = (DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0));
        let f = [DVec3::new(1.0, 1.0, 0.0), DVec3::new(1.0, -1.0, 4.0)];
        assert_eq!(edge_point(a, b, &f, 0.0), DVec3::new(1.0, 0.0, 1.0));
        assert_eq!(edge_point(a, b, &f, 1.0), DVec3::new(1.0, 0.0, 0.0));
        assert_eq!(edge_point(a, b, &f, 0.5), DVec3::new(1.0, 0.0, 0.5));
        assert_eq!(edge_point(a, b, &f[..1], 0.0), DVec3::new(1.0, 0.0, 0.0));
        assert_eq!(face_point(&[a, b, f[0]]), DVec3::new(1.0, 1.0 / 3.0, 0.0));
    }

    #[test]
    fn valence2_smooth_vertex_takes_the_corner_masks() {
        // Two quads sharing the vertex and both its edges (OpenSubdiv: corner masks). The general
        // masks would give (4 v + 4 sum e + sum d) / 14 instead.
        let v = DVec3::new(0.1, 0.2, 0.3);
        let e = [DVec3::new(1.0, 0.0, 0.0), DVec3::new(0.0, 1.0, 0.0)];
        let d = [DVec3::new(1.0, 1.0, 0.5), DVec3::new(1.0, 1.0, -0.5)];
        for rule in [Rule::Smooth, Rule::Dart] {
            let (p, t1, t2) = limit(v, &e, &d, rule);
            assert_eq!(p, v);
            assert_eq!(t1, e[0] - v);
            assert_eq!(t2, e[1] - v);
        }
        // Valence 3 still takes the smooth masks.
        let e3 = [e[0], e[1], DVec3::new(-1.0, -1.0, 0.0)];
        let d3 = [d[0], d[1], DVec3::new(0.0, -1.0, 0.2)];
        let (p, _, _) = limit(v, &e3, &d3, Rule::Smooth);
        assert_ne!(p, v);
        // A crease through a valence-2 vertex keeps the crease mask.
        let (p, _, _) = limit(v, &e, &d, Rule::Crease([0, 1]));
        assert!((p - (v * 2.0 / 3.0 + (e[0] + e[1]) / 6.0)).length() < 1e-15);
    }

    #[test]
    fn smooth_triangle_edge_weights() {
        use TriangleSubdivision::{Catmark, Smooth};
        // As sdc/catmarkScheme.h: face weight (f0 + f1) / 2 with 0.47 per triangle, ends
        // (1 - 2 w) / 2.
        assert_eq!(edge_face_weight(Catmark, [3, 3]), 0.25);
        assert_eq!(edge_face_weight(Smooth, [4, 4]), 0.25);
        assert_eq!(edge_face_weight(Smooth, [4, 5]), 0.25);
        assert_eq!(edge_face_weight(Smooth, [3, 3]), 0.47);
        assert_eq!(edge_face_weight(Smooth, [3, 4]), 0.5 * (0.47 + 0.25));
        assert_eq!(edge_face_weight(Smooth, [6, 3]), 0.5 * (0.25 + 0.47));
        let (a, b) = (DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0));
        let f = [DVec3::new(1.0, 1.0, 0.0), DVec3::new(1.0, -1.0, 4.0)];
        let p = edge_point_weighted(a, b, &f, 0.0, 0.47);
        let want = (a + b) * 0.03 + (f[0] + f[1]) * 0.47;
        assert!((p - want).length() < 1e-15, "{p} {want}");
        // The plain weight is the plain rule, bit for bit; creases and boundaries ignore it.
        assert_eq!(
            edge_point_weighted(a, b, &f, 0.0, 0.25),
            edge_point(a, b, &f, 0.0)
        );
        assert_eq!(edge_point_weighted(a, b, &f, 1.0, 0.47), (a + b) * 0.5);
        assert_eq!(edge_point_weighted(a, b, &f[..1], 0.0, 0.47), (a + b) * 0.5);
        let half = edge_point_weighted(a, b, &f, 0.5, 0.36);
        let smooth = edge_point_weighted(a, b, &f, 0.0, 0.36);
        assert!((half - ((a + b) * 0.25 + smooth * 0.5)).length() < 1e-15);
    }

    #[test]
    fn boundary_limit_is_cubic_bspline() {
        // Boundary vertex of a regular half-plane grid: limit on the boundary curve
        // (1/6, 4/6, 1/6); cross tangent points into the surface.
        let v = DVec3::new(0.0, 0.0, 0.0);
        let e = [
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(-1.0, 0.0, 1.0),
        ];
        let d = [DVec3::new(1.0, 1.0, 0.0), DVec3::new(-1.0, 1.0, 0.0)];
        let (p, t1, t2) = limit(v, &e, &d, Rule::Crease([0, 2]));
        assert!((p - DVec3::new(0.0, 0.0, 1.0 / 3.0)).length() < 1e-15);
        assert!(t1.y.abs() < 1e-15 && t1.x > 0.0);
        assert!(t2.y > 0.0);
    }
}
