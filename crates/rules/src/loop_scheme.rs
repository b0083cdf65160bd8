//! Loop rules: refinement points and limit masks.
//!
//! Refinement: C. Loop, "Smooth subdivision surfaces based on triangles", M.S. thesis, University
//! of Utah, 1987, with Warren's/Loop's weight `beta = (5/8 - (3/8 + 1/4 cos(2 pi/n))^2) / n`, plus
//! the crease rules of Hoppe et al. 1994 and DeRose et al. 1998 (see [`crate::crease`]).
//!
//! Limit masks: smooth position `chi = 1 / (n + 3/(8 beta))` and the cos/sin tangent masks
//! (Loop 1987; Halstead et al. 1993); crease and boundary curves are uniform cubic B-splines, so
//! their limit is `(1/6, 4/6, 1/6)`; cross-boundary tangents from Biermann et al. 2000 in the
//! scaling used by OpenSubdiv.

use std::f64::consts::PI;

use crate::crease::{Rule, VertexRules};
use crate::point::Point;

/// Loop's smooth vertex weight `beta` for valence `n` (each neighbour's weight).
#[inline]
pub fn beta(n: usize) -> f64 {
    if n == 6 {
        return 1.0 / 16.0;
    }
    let nf = n as f64;
    let c = 0.375 + 0.25 * (2.0 * PI / nf).cos();
    (0.625 - c * c) / nf
}

/// The edge point of edge `a`-`b` whose triangles have the opposite vertices `opposite` (one
/// for a boundary edge), with the crease weight from [`crate::crease::edge_crease_weight`].
#[inline]
pub fn edge_point<P: Point>(a: P, b: P, opposite: &[P], crease_weight: f32) -> P {
    let mid = a.add(b).scale(0.5);
    if crease_weight == 1.0 || opposite.len() < 2 {
        return mid;
    }
    let smooth = a
        .add(b)
        .scale(0.375)
        .add(opposite[0].add(opposite[1]).scale(0.125));
    if crease_weight <= 0.0 {
        smooth
    } else {
        let w = crease_weight as f64;
        mid.scale(w).add(smooth.scale(1.0 - w))
    }
}

/// The vertex point of `v` with edge neighbours `edges` (ring order) under `rules`.
#[inline]
pub fn vertex_point<P: Point>(v: P, edges: &[P], rules: &VertexRules) -> P {
    let p = apply_vertex_rule(v, edges, rules.parent);
    if rules.is_simple() {
        return p;
    }
    let c = apply_vertex_rule(v, edges, rules.child);
    let w = rules.parent_weight;
    p.scale(w).add(c.scale(1.0 - w))
}

/// The smooth vertex point of `v` with edge neighbours `edges` and Loop's weight `b`
/// (`beta(edges.len())`, passed in so that tessellators meeting one valence many times compute it
/// once): `(1 - n b) v + b sum`.
#[inline]
pub fn smooth_vertex_point<P: Point>(v: P, edges: &[P], b: f64) -> P {
    let mut s = P::ZERO;
    for e in edges {
        s = s.add(*e);
    }
    v.scale(1.0 - b * edges.len() as f64).add(s.scale(b))
}

#[inline]
fn apply_vertex_rule<P: Point>(v: P, edges: &[P], rule: Rule) -> P {
    match rule {
        Rule::Smooth | Rule::Dart => smooth_vertex_point(v, edges, beta(edges.len())),
        Rule::Crease([i, j]) => v.scale(0.75).add(edges[i].add(edges[j]).scale(0.125)),
        Rule::Corner => v,
    }
}

/// The smooth edge point of edge `a`-`b` with opposite vertices `c`, `d`: [`edge_point`] with
/// crease weight 0, in the form the slates' regular interiors use (`3/8 (a + b) + 1/8 (c + d)`).
#[inline(always)]
pub fn smooth_edge_point<P: Point>(a: P, b: P, c: P, d: P) -> P {
    a.add(b).scale(0.375).add(c.add(d).scale(0.125))
}

/// The smooth vertex point of a valence-6 vertex `v` whose six neighbours sum to `sum`:
/// [`vertex_point`] under the smooth rule with `beta(6) = 1/16` (`5/8 v + 1/16 sum`).
#[inline(always)]
pub fn regular_vertex_point<P: Point>(v: P, sum: P) -> P {
    v.scale(0.625).add(sum.scale(1.0 / 16.0))
}

/// [`limit`] of a smooth valence-6 vertex `v` with neighbours `e` (counter-clockwise): the
/// quartic box spline's limit `1/2 v + 1/12 sum`, and the cos/sin tangent masks with their
/// exact weights (`cos(k pi/3)` in `{1, 1/2, -1/2, -1, -1/2, 1/2}`, `sin(k pi/3)` in
/// `{0, s, s, 0, -s, -s}`, `s = sqrt(3)/2`), as sums instead of six trigonometric products.
#[inline(always)]
pub fn regular_limit<P: Point>(v: P, e: [P; 6]) -> (P, P, P) {
    let s01 = e[0].add(e[1]);
    let s23 = e[2].add(e[3]);
    let s45 = e[4].add(e[5]);
    let pos = v.scale(0.5).add(s01.add(s23).add(s45).scale(1.0 / 12.0));
    let t1 = e[0]
        .sub(e[3])
        .add(e[1].sub(e[2]).sub(e[4]).add(e[5]).scale(0.5));
    let t2 = e[1]
        .add(e[2])
        .sub(e[4])
        .sub(e[5])
        .scale(0.866_025_403_784_438_6);
    (pos, t1, t2)
}

/// Loop's smooth interior limit masks for one valence `n >= 3`: position weight
/// `chi = 1 / (n + 3/(8 beta))` and the tangent weights `cos(2 pi i/n)`, `sin(2 pi i/n)`, computed
/// once so that tessellators meeting a valence many times skip the trigonometry.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SmoothLimitMask {
    chi: f64,
    cos: Vec<f64>,
    sin: Vec<f64>,
}

impl SmoothLimitMask {
    /// The masks of valence `n`.
    pub fn new(n: usize) -> SmoothLimitMask {
        let b = beta(n);
        let th = 2.0 * PI / n as f64;
        let (sin, cos) = (0..n).map(|i| (th * i as f64).sin_cos()).unzip();
        SmoothLimitMask {
            chi: 1.0 / (n as f64 + 3.0 / (8.0 * b)),
            cos,
            sin,
        }
    }

    /// The valence the masks are for.
    #[inline]
    pub fn valence(&self) -> usize {
        self.cos.len()
    }

    /// Limit position and tangents of `v` with its `n` edge neighbours (counter-clockwise).
    #[inline]
    pub fn apply<P: Point>(&self, v: P, edges: &[P]) -> (P, P, P) {
        let mut pos = v.scale(1.0 - self.chi * edges.len() as f64);
        let mut t1 = P::ZERO;
        let mut t2 = P::ZERO;
        for ((e, &c), &s) in edges.iter().zip(&self.cos).zip(&self.sin) {
            pos = pos.madd(*e, self.chi);
            t1 = t1.madd(*e, c);
            t2 = t2.madd(*e, s);
        }
        (pos, t1, t2)
    }
}

/// Limit position and two tangents of vertex `v` with edge neighbours `edges` (counter-clockwise;
/// for a boundary vertex edge 0 and the last edge are the boundary) under its stationary `rule`.
pub fn limit<P: Point>(v: P, edges: &[P], rule: Rule, boundary: bool) -> (P, P, P) {
    let n = edges.len();
    match rule {
        Rule::Smooth | Rule::Dart if !boundary && n >= 3 => SmoothLimitMask::new(n).apply(v, edges),
        Rule::Crease([c0, c1]) => {
            let pos = v
                .scale(2.0 / 3.0)
                .add(edges[c0].add(edges[c1]).scale(1.0 / 6.0));
            let t1 = edges[c0].sub(edges[c1]).scale(1.5);
            let interior = c1 - c0 - 1;
            let t2 = match interior {
                0 => edges[c0].add(edges[c1]).scale(3.0).sub(v.scale(6.0)),
                1 => edges[c0 + 1].sub(v).scale(3.0),
                2 => {
                    let r3 = 3.0f64.sqrt();
                    let mut t = v.scale(-r3);
                    t = t.madd(edges[c0], -0.5 * r3).madd(edges[c1], -0.5 * r3);
                    t.madd(edges[c0 + 1], r3).madd(edges[c0 + 2], r3)
                }
                _ => {
                    let th = PI / (interior + 1) as f64;
                    let wc = -3.0 * th.sin();
                    let we = -3.0 * (2.0 * th.cos() - 2.0);
                    let mut t = edges[c0].add(edges[c1]).scale(wc);
                    for i in 1..=interior {
                        t = t.madd(edges[c0 + i], we * (i as f64 * th).sin());
                    }
                    t
                }
            };
            (pos, t1, t2)
        }
        _ => {
            let t1 = if n > 0 { edges[0].sub(v) } else { P::ZERO };
            let t2 = if n > 1 { edges[1].sub(v) } else { P::ZERO };
            (v, t1, t2)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    use subdiv_mesh::CreaseMethod;

    fn hex_ring(f: impl Fn(f64, f64) -> f64) -> (DVec3, Vec<DVec3>) {
        // Regular triangle lattice: neighbours at 60 degree steps, unit distance.
        let p = |x: f64, y: f64| DVec3::new(x, y, f(x, y));
        let e = (0..6)
            .map(|i| {
                let a = i as f64 * PI / 3.0;
                p(a.cos(), a.sin())
            })
            .collect();
        (p(0.0, 0.0), e)
    }

    #[test]
    fn regular_limit_is_box_spline() {
        // The quartic box spline at a lattice point: 1/2 centre + 1/12 each neighbour.
        let (v, e) = hex_ring(|x, y| x * x + y * y);
        let (p, t1, t2) = limit(v, &e, Rule::Smooth, false);
        assert!((p.z - 0.5).abs() < 1e-12);
        let n = t1.cross(t2).normalize();
        assert!((n.z.abs() - 1.0).abs() < 1e-12);
        // Linear functions are reproduced exactly, with the right slope.
        let (v, e) = hex_ring(|x, y| 3.0 * x - y + 1.0);
        let (p, t1, t2) = limit(v, &e, Rule::Smooth, false);
        assert!((p.z - 1.0).abs() < 1e-12);
        let n = t1.cross(t2).normalize();
        let want = DVec3::new(-3.0, 1.0, 1.0).normalize();
        assert!((n - want).length() < 1e-12 || (n + want).length() < 1e-12);
    }

    #[test]
    fn vertex_and_edge_points() {
        assert_eq!(beta(6), 1.0 / 16.0);
        assert!((beta(3) - 3.0 / 16.0).abs() < 1e-15);
        let (v, e) = hex_ring(|_, _| 0.0);
        let v = v + DVec3::Z;
        let mut c = [0.0; 6];
        let r = VertexRules::new(CreaseMethod::Uniform, 0.0, &[0.0; 6], &mut c);
        // 5/8 v + 1/16 sum e.
        assert!((vertex_point(v, &e, &r) - DVec3::new(0.0, 0.0, 0.625)).length() < 1e-15);
        let a = DVec3::ZERO;
        let b = DVec3::new(8.0, 0.0, 0.0);
        let o = [DVec3::new(4.0, 4.0, 8.0), DVec3::new(4.0, -4.0, 0.0)];
        assert_eq!(edge_point(a, b, &o, 0.0), DVec3::new(4.0, 0.0, 1.0));
        assert_eq!(edge_point(a, b, &o, 1.0), DVec3::new(4.0, 0.0, 0.0));
    }

    #[test]
    fn regular_forms_equal_the_general_rules() {
        let (v, e) = hex_ring(|x, y| (1.3 * x - 0.2).sin() + y * y * x + 0.1 * y);
        let (p, t1, t2) = limit(v, &e, Rule::Smooth, false);
        let (q, u1, u2) = regular_limit(v, [e[0], e[1], e[2], e[3], e[4], e[5]]);
        assert!((p - q).length() < 1e-14 && (t1 - u1).length() < 1e-14);
        assert!((t2 - u2).length() < 1e-14);
        let mut c = [0.0; 6];
        let r = VertexRules::new(CreaseMethod::Uniform, 0.0, &[0.0; 6], &mut c);
        let sum = e.iter().fold(DVec3::ZERO, |s, x| s + *x);
        assert!((vertex_point(v, &e, &r) - regular_vertex_point(v, sum)).length() < 1e-15);
        let smooth = smooth_edge_point(v, e[0], e[1], e[5]);
        assert!((edge_point(v, e[0], &[e[1], e[5]], 0.0) - smooth).length() < 1e-15);
    }

    #[test]
    fn boundary_limit() {
        let v = DVec3::ZERO;
        let e = [
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(0.5, 0.8, 0.0),
            DVec3::new(-0.5, 0.8, 0.0),
            DVec3::new(-1.0, 0.0, 1.0),
        ];
        let (p, t1, t2) = limit(v, &e, Rule::Crease([0, 3]), true);
        assert!((p - DVec3::new(0.0, 0.0, 1.0 / 3.0)).length() < 1e-15);
        assert!(t1.x > 0.0 && t2.y > 0.0);
    }
}
