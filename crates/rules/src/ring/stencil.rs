//! [`QuadRingStencil`]: [`Ring::limit`] of Catmull-Clark quad rings, precomputed per
//! configuration.

use glam::DVec3;
use subdiv_mesh::CreaseMethod;

use super::sided::{Sides, sided_normals};
use super::{LimitParts, Ring, finish_limit};

/// [`Ring::limit`] of a Catmull-Clark ring of quads, precomputed for one configuration (crease
/// method, boundary, valence, edge sharpness and far-end information; vertex sharpness 0).
///
/// The ring's refinement and its limit masks are linear in the ring's points, with weights that
/// depend only on the configuration. [`QuadRingStencil::new`] runs the ring once per three basis
/// points (one per coordinate) and keeps, for every ring point, its weight in the limit position,
/// the tangents, and the refined ring that orients the normal. [`QuadRingStencil::limit`] applies
/// them and forms the normal with the same code as [`Ring::limit`]; the result agrees with it up
/// to rounding. Tessellators keep one per configuration met (semi-sharp creases make few).
///
/// ```
/// use glam::DVec3;
/// use subdiv_mesh::CreaseMethod;
/// use subdiv_rules::{QuadRingStencil, Ring};
/// // A vertex on a crease of sharpness 1.5 (edges 0 and 2), valence 4.
/// let sharp = [1.5, 0.0, 1.5, 0.0];
/// let far = [(0.0, 0); 4];
/// let c = DVec3::new(0.0, 0.0, 0.2);
/// let e = [DVec3::X, DVec3::Y, -DVec3::X, -DVec3::Y];
/// let d = [DVec3::new(1.0, 1.0, 0.1), DVec3::new(-1.0, 1.0, 0.0), DVec3::new(-1.0, -1.0, 0.3), DVec3::new(1.0, -1.0, 0.0)];
/// let st = QuadRingStencil::new(CreaseMethod::Uniform, false, &sharp, &far, d.len());
/// let mut ring = Ring::new();
/// ring.load_quads(CreaseMethod::Uniform, c, 0.0, false, &e, &sharp, &far, &d);
/// let (p0, n0) = ring.limit();
/// let (p1, n1) = st.limit(c, &e, &d);
/// assert!((p0 - p1).length() < 1e-12 && (n0 - n1).length() < 1e-12);
/// ```
#[derive(Clone, Debug)]
pub struct QuadRingStencil {
    /// Edges and diagonals of the rings it applies to.
    m: usize,
    nd: usize,
    num_faces: usize,
    crease_sides: bool,
    sides: Sides,
    /// Rows of `1 + m + nd` weights (centre, edges, diagonals): position, t1, t2, u1, u2 (other
    /// crease side; zero rows otherwise), refined centre, refined edges `0..m`.
    w: Vec<f64>,
    /// `max_i sum_k |w_ik| + |w_ck|` over the refined edges' rows `i` and the refined centre's
    /// row `c`: bounds the refined ring's spread, `|e_i - c| <= spread * max_k |p_k|` (see
    /// [`QuadRingStencil::quick_normal`]).
    spread: f64,
}

impl QuadRingStencil {
    const POS: usize = 0;
    const FIXED_ROWS: usize = 6;

    /// Precomputes the limit of quad rings with edge sharpness `sharp`, far-end semi-sharp
    /// (sum, count) `far` (Chaikin only) and `num_diag` diagonals (`sharp.len()` for an interior
    /// vertex, one fewer on a boundary), as [`Ring::load_quads`] takes them.
    pub fn new(
        method: CreaseMethod,
        boundary: bool,
        sharp: &[f32],
        far: &[(f32, u32)],
        num_diag: usize,
    ) -> QuadRingStencil {
        let m = sharp.len();
        let nd = num_diag;
        let np = 1 + m + nd;
        let rows = Self::FIXED_ROWS + m;
        let mut w = vec![0.0; rows * np];
        let mut ring = Ring::new();
        let mut edges = vec![DVec3::ZERO; m];
        let mut diag = vec![DVec3::ZERO; nd];
        let mut crease_sides = false;
        let mut sides = Sides::One;
        let mut num_faces = 0;
        // Points q, q+1, q+2 at the x, y and z unit vectors: each output coordinate is one weight.
        for q in (0..np).step_by(3) {
            let basis = |k: usize| match k.checked_sub(q) {
                Some(0) => DVec3::X,
                Some(1) => DVec3::Y,
                Some(2) => DVec3::Z,
                _ => DVec3::ZERO,
            };
            let center = basis(0);
            for (i, e) in edges.iter_mut().enumerate() {
                *e = basis(1 + i);
            }
            for (i, d) in diag.iter_mut().enumerate() {
                *d = basis(1 + m + i);
            }
            ring.load_quads(method, center, 0.0, boundary, &edges, sharp, far, &diag);
            let parts = ring.limit_parts();
            crease_sides = parts.other.is_some();
            sides = parts.sides.clone();
            num_faces = ring.num_faces();
            let (u1, u2) = parts.other.unwrap_or((DVec3::ZERO, DVec3::ZERO));
            let mut put = |row: usize, v: DVec3| {
                for (c, x) in v.to_array().into_iter().enumerate() {
                    if q + c < np {
                        w[row * np + q + c] = x;
                    }
                }
            };
            put(Self::POS, parts.pos);
            put(1, parts.t1);
            put(2, parts.t2);
            put(3, u1);
            put(4, u2);
            put(5, ring.center);
            for i in 0..m {
                put(Self::FIXED_ROWS + i, ring.edges[i]);
            }
        }
        let abs_sum = |r: usize| w[r * np..(r + 1) * np].iter().map(|x| x.abs()).sum::<f64>();
        let centre = abs_sum(5);
        let spread = (0..m)
            .map(|i| abs_sum(Self::FIXED_ROWS + i) + centre)
            .fold(0.0, f64::max);
        QuadRingStencil {
            m,
            nd,
            num_faces,
            crease_sides,
            sides,
            w,
            spread,
        }
    }

    /// `true` when rings of this configuration have one-sided normals
    /// ([`QuadRingStencil::limit_sided`] fills its `faces`).
    pub fn is_sided(&self) -> bool {
        self.sides.is_sided()
    }

    /// Limit position and unit normal of the ring `center`, `edges`, `diag` (the configuration's
    /// sizes), like [`Ring::limit`] on the same ring.
    pub fn limit(&self, center: DVec3, edges: &[DVec3], diag: &[DVec3]) -> (DVec3, DVec3) {
        self.limit_sided(center, edges, diag, &mut Vec::new())
    }

    /// [`QuadRingStencil::limit`] with the one-sided normals of [`Ring::limit_sided`] in
    /// `faces` (empty unless [`QuadRingStencil::is_sided`]).
    pub fn limit_sided(
        &self,
        center: DVec3,
        edges: &[DVec3],
        diag: &[DVec3],
        faces: &mut Vec<DVec3>,
    ) -> (DVec3, DVec3) {
        self.evaluate(center, edges, diag, faces, true).0
    }

    /// [`QuadRingStencil::limit_sided`]; with `quick`, through [`QuadRingStencil::quick_normal`]
    /// where it decides (the same bits, checked by the tests against `quick == false`), and
    /// whether it did.
    fn evaluate(
        &self,
        center: DVec3,
        edges: &[DVec3],
        diag: &[DVec3],
        faces: &mut Vec<DVec3>,
        quick: bool,
    ) -> ((DVec3, DVec3), bool) {
        assert!(
            edges.len() == self.m && diag.len() == self.nd,
            "ring does not match the stencil's configuration"
        );
        let np = 1 + self.m + self.nd;
        // The ring's points in weight order, contiguous (a plain indexed loop per row: the same
        // sums in the same order as over the chained slices, at a fraction of the instructions).
        // A table ring has at most 4 edges and 4 diagonals: 9 points on the stack.
        let mut buf = [DVec3::ZERO; 9];
        let mut buf_vec = Vec::new();
        let pts: &mut [DVec3] = if np <= buf.len() {
            &mut buf[..np]
        } else {
            buf_vec.resize(np, DVec3::ZERO);
            &mut buf_vec
        };
        pts[0] = center;
        pts[1..1 + self.m].copy_from_slice(edges);
        pts[1 + self.m..].copy_from_slice(diag);
        let pts = &*pts;
        let row = |r: usize| {
            let w = &self.w[r * np..(r + 1) * np];
            if let (Ok(w), Ok(p)) = (<&[f64; 9]>::try_from(w), <&[DVec3; 9]>::try_from(pts)) {
                // The table's ring (4 edges, 4 diagonals): the same sum, unrolled.
                let mut acc = p[0] * w[0];
                for (pk, wk) in p[1..].iter().zip(&w[1..]) {
                    acc += *pk * *wk;
                }
                return acc;
            }
            let mut acc = pts[0] * w[0];
            for k in 1..np {
                acc += pts[k] * w[k];
            }
            acc
        };
        let parts = LimitParts {
            pos: row(Self::POS),
            t1: row(1),
            t2: row(2),
            other: self.crease_sides.then(|| (row(3), row(4))),
            sides: Sides::One,
        };
        if quick
            && !self.sides.is_sided()
            && let Some(normal) = self.quick_normal(&parts, pts)
        {
            faces.clear();
            return ((parts.pos, normal), true);
        }
        let mut refined = [DVec3::ZERO; 8];
        let mut refined_vec = Vec::new();
        let refined: &mut [DVec3] = if self.m <= refined.len() {
            &mut refined[..self.m]
        } else {
            refined_vec.resize(self.m, DVec3::ZERO);
            &mut refined_vec
        };
        for (i, e) in refined.iter_mut().enumerate() {
            *e = row(Self::FIXED_ROWS + i);
        }
        let c = row(5);
        sided_normals(&parts, &self.sides, c, refined, self.num_faces, faces);
        (finish_limit(&parts, c, refined, self.num_faces), false)
    }

    /// [`finish_limit`]'s normal without the refined ring, where that gives the same bits: the
    /// ring only orients degenerate tangents, and sets their threshold through its spread
    /// `scale = max_i |e_i - c|^2`. [`QuadRingStencil::spread`] bounds it from above (with a
    /// margin for rounding), so a tangent cross product longer than the threshold of the bound
    /// is longer than the threshold of `scale` too, and is normalised exactly as
    /// [`finish_limit`] does. `None` where the bound cannot decide (degenerate tangents): the
    /// caller takes the full path.
    #[inline]
    fn quick_normal(&self, parts: &LimitParts, pts: &[DVec3]) -> Option<DVec3> {
        let p2 = pts.iter().map(|p| p.length_squared()).fold(0.0, f64::max);
        let bound = 1.0201 * self.spread * self.spread * p2;
        let threshold = 1e-12 * bound.max(f64::MIN_POSITIVE);
        let unit = |n: DVec3| {
            let len = n.length();
            (len > threshold && len.is_finite()).then(|| n / len)
        };
        let mut normal = unit(parts.t1.cross(parts.t2))?;
        if let Some((u1, u2)) = parts.other {
            let sum = normal + unit(u1.cross(u2))?;
            if sum.length_squared() > 1e-12 {
                normal = sum.normalize();
            }
        }
        Some(normal)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use subdiv_test_support::Rng;

    /// A point in `[0, scale)^3`.
    fn point(rng: &mut Rng, scale: f64) -> DVec3 {
        DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) * scale
    }

    /// The stencil gives what the ring gives, for creases of every kind (integer, fractional,
    /// infinite, Chaikin with far-end information), boundaries and valences 2 to 6.
    #[test]
    fn stencil_matches_ring_limit() {
        let mut rng = Rng::xorshift(0x9e37_79b9_7f4a_7c15);
        let choices = [0.0f32, 0.0, 0.5, 1.0, 1.5, 2.0, 3.25, 10.0];
        let mut checked = 0;
        let mut sided = 0;
        for case in 0..400 {
            let method = if case % 2 == 0 {
                CreaseMethod::Uniform
            } else {
                CreaseMethod::Chaikin
            };
            let boundary = case % 5 == 0;
            let m = 2 + (rng.next_f64() * 5.0) as usize;
            if !boundary && m < 3 {
                continue;
            }
            let nd = if boundary { m - 1 } else { m };
            let sharp: Vec<f32> = (0..m)
                .map(|_| choices[(rng.next_f64() * choices.len() as f64) as usize])
                .collect();
            let far: Vec<(f32, u32)> = (0..m)
                .map(|_| {
                    let c = (rng.next_f64() * 3.0) as u32;
                    (c as f32 * (0.5 + rng.next_f64() as f32 * 2.0), c)
                })
                .collect();
            // A bumpy ring around the origin.
            let center = point(&mut rng, 0.3);
            let edges: Vec<DVec3> = (0..m)
                .map(|i| {
                    let a = std::f64::consts::TAU * i as f64 / m as f64;
                    DVec3::new(a.cos(), a.sin(), 0.0) + point(&mut rng, 0.2)
                })
                .collect();
            let diag: Vec<DVec3> = (0..nd)
                .map(|i| {
                    let a = std::f64::consts::TAU * (i as f64 + 0.5) / m as f64;
                    DVec3::new(a.cos(), a.sin(), 0.0) * 1.4 + point(&mut rng, 0.2)
                })
                .collect();
            let st = QuadRingStencil::new(method, boundary, &sharp, &far, nd);
            let mut ring = Ring::new();
            ring.load_quads(method, center, 0.0, boundary, &edges, &sharp, &far, &diag);
            let (mut f0, mut f1) = (Vec::new(), Vec::new());
            let (p0, n0) = ring.limit_sided(&mut f0);
            let (p1, n1) = st.limit_sided(center, &edges, &diag, &mut f1);
            assert!(
                (p0 - p1).length() < 1e-12 && (n0 - n1).length() < 1e-9,
                "case {case}: {method:?} boundary {boundary} sharp {sharp:?}: \
                 ring ({p0}, {n0}) stencil ({p1}, {n1})"
            );
            assert_eq!(f0.len(), f1.len(), "case {case}");
            assert_eq!(st.is_sided(), !f1.is_empty(), "case {case}");
            assert!(f0.iter().zip(&f1).all(|(a, b)| (*a - *b).length() < 1e-9));
            sided += usize::from(!f0.is_empty());
            checked += 1;
        }
        assert!(checked > 300);
        assert!(sided >= 20, "{sided} sided configurations");
    }

    /// The quick normal (no refined ring) gives the bits of the full path, on rings of every
    /// scale and offset and on degenerate ones (flat, collapsed), where it must hand over.
    #[test]
    fn quick_normal_keeps_every_bit() {
        let mut rng = Rng::xorshift(0x2545_f491_4f6c_dd1d);
        let choices = [0.0f32, 0.0, 0.5, 1.0, 2.0, 3.0, 6.0, 10.0];
        let (mut quick, mut full) = (Vec::new(), Vec::new());
        let mut decided = 0;
        for case in 0..600 {
            let method = if case % 3 == 0 {
                CreaseMethod::Chaikin
            } else {
                CreaseMethod::Uniform
            };
            let boundary = case % 7 == 0;
            let m = if case % 2 == 0 { 4 } else { 3 + case % 4 };
            let nd = if boundary { m - 1 } else { m };
            let sharp: Vec<f32> = (0..m)
                .map(|_| choices[(rng.next_f64() * choices.len() as f64) as usize])
                .collect();
            let far = vec![(0.0, 0); m];
            let st = QuadRingStencil::new(method, boundary, &sharp, &far, nd);
            // Scales from 1e-6 to 1e3, offsets from 1e-2 to 1e2, and every tenth ring flat or
            // collapsed.
            let scale = 10f64.powi((case % 10) as i32 - 6);
            let offset = point(&mut rng, 10f64.powi(((case / 10) % 5) as i32 - 2));
            let squash = match case % 10 {
                0 => DVec3::new(1.0, 1.0, 0.0),
                5 => DVec3::ZERO,
                _ => DVec3::ONE,
            };
            let pt = |rng: &mut Rng, a: f64, r: f64| {
                offset
                    + (DVec3::new(a.cos() * r, a.sin() * r, 0.0) + point(rng, 0.3)) * squash * scale
            };
            let center = pt(&mut rng, 0.0, 0.0);
            let edges: Vec<DVec3> = (0..m)
                .map(|i| pt(&mut rng, std::f64::consts::TAU * i as f64 / m as f64, 1.0))
                .collect();
            let diag: Vec<DVec3> = (0..nd)
                .map(|i| {
                    pt(
                        &mut rng,
                        std::f64::consts::TAU * (i as f64 + 0.5) / m as f64,
                        1.4,
                    )
                })
                .collect();
            let (a, used) = st.evaluate(center, &edges, &diag, &mut quick, true);
            let (b, _) = st.evaluate(center, &edges, &diag, &mut full, false);
            let bits = |v: DVec3| v.to_array().map(f64::to_bits);
            assert_eq!(
                (bits(a.0), bits(a.1)),
                (bits(b.0), bits(b.1)),
                "case {case}: {a:?} vs {b:?}"
            );
            assert_eq!(quick, full, "case {case}");
            decided += usize::from(used);
        }
        assert!(decided > 150, "{decided} rings through the quick normal");
    }

    #[test]
    #[should_panic(expected = "configuration")]
    fn stencil_refuses_a_ring_of_another_size() {
        let st = QuadRingStencil::new(CreaseMethod::Uniform, false, &[0.0; 4], &[(0.0, 0); 4], 4);
        st.limit(DVec3::ZERO, &[DVec3::X; 3], &[DVec3::Y; 3]);
    }
}
