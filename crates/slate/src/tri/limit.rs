//! Limit points and normals of the last slate: the box spline's limit mask at regular points,
//! the exact ring limit of `subdiv-rules` (`Ring::limit_sided`) at corners and along creased or
//! boundary sides.

use glam::{DVec3, Vec3A};
use subdiv_rules::crease::semi_sharp_excluding;
use subdiv_rules::loop_scheme::{SmoothLimitMask, regular_limit};

use super::worker::{TriWorker, side_ring};

/// A limit point: position, unit normal and, where the limit surface has a crease or a corner,
/// the one-sided normal of this patch's side.
pub(crate) type LimitPoint = (Vec3A, Vec3A, Option<Vec3A>);

/// Scratch for the exact evaluations.
#[derive(Clone, Debug, Default)]
pub(crate) struct LimitScratch {
    ring: subdiv_rules::Ring,
    edges: Vec<DVec3>,
    faces: Vec<DVec3>,
    sharp: Vec<f32>,
    far: Vec<(f32, u32)>,
    masks: Vec<Option<SmoothLimitMask>>,
    /// Output ids of the patch's lattice points (row by row).
    pub(crate) ids: Vec<u32>,
}

#[inline(always)]
fn normal(t1: Vec3A, t2: Vec3A) -> Vec3A {
    t1.cross(t2).normalize_or_zero()
}

impl TriWorker {
    /// Calls `f(position, normal)` for every interior point (`i, j >= 1`, `i + j <= n - 1`) of
    /// the last level, row by row (`j`, then `i`): the order of the patch's interior ids. All are
    /// smooth valence-6 points.
    #[inline]
    pub(crate) fn limit_interior(&self, mut f: impl FnMut(Vec3A, Vec3A)) {
        let n = self.n as usize;
        let w = n + 3;
        let t = self.table();
        let o = self.origin;
        for j in 1..n.saturating_sub(1) {
            // Rows j - 1, j, j + 1 from column -1: point (i, j) is `mid[i + 1]`.
            let lo = &t[j * w..(j + 1) * w];
            let mid = &t[(j + 1) * w..(j + 2) * w];
            let hi = &t[(j + 2) * w..(j + 3) * w];
            for i in 1..n - j {
                let e = [mid[i + 2], hi[i + 1], hi[i], mid[i], lo[i + 1], lo[i + 2]];
                let (p, t1, t2) = regular_limit(mid[i + 1], e);
                f(p + o, normal(t1, t2));
            }
        }
    }

    /// Calls `f(a, position, normal)` for every inner point `a` (`0 < a < n`) of side `c`, which
    /// must be smooth (interior, no sharpness): [`TriWorker::limit_side`]'s regular path (the
    /// same ring, the same sums) with the ring read by index steps along the side.
    #[inline]
    pub(crate) fn limit_smooth_side(&self, c: usize, mut f: impl FnMut(u32, Vec3A, Vec3A)) {
        debug_assert!(self.sides[c].smooth);
        let t = self.table();
        let (base, da, db) = TriWorker::frame(self.n, c);
        let at = |k: isize| t[k as usize];
        for a in 1..self.n {
            let k = base + a as isize * da;
            // The ring of `side_ring`: (a+1, 0), (a, 1), (a-1, 1), (a-1, 0), (a, -1), (a+1, -1).
            let e = [
                at(k + da),
                at(k + db),
                at(k - da + db),
                at(k - da),
                at(k - db),
                at(k + da - db),
            ];
            let (p, t1, t2) = regular_limit(at(k), e);
            f(a, p + self.origin, normal(t1, t2));
        }
    }

    /// The limit of side `c`'s inner point `a` (`0 < a < n`).
    pub(crate) fn limit_side(&self, s: &mut LimitScratch, c: usize, a: u32) -> LimitPoint {
        let n = self.n;
        let side = &self.sides[c];
        let mut edges = [Vec3A::ZERO; 6];
        let mut sharp = [0.0f32; 6];
        let mut far = [(0.0f32, 0u32); 6];
        let ends = if side.smooth {
            [(0.0, 0); 2]
        } else {
            [self.far_at_corner(c, 0), self.far_at_corner((c + 1) % 3, 1)]
        };
        let k = side_ring(
            self.table(),
            n,
            c,
            a as i32,
            side,
            ends,
            &mut edges,
            &mut sharp,
            &mut far,
        );
        let center = self.at_local(c, a as i32, 0);
        if side.smooth {
            let (p, t1, t2) = regular_limit(center, edges);
            return (p + self.origin, normal(t1, t2), None);
        }
        s.edges.clear();
        s.edges.extend(edges[..k].iter().map(|e| e.as_dvec3()));
        s.ring.load_triangles(
            self.method,
            center.as_dvec3(),
            0.0,
            !side.interior,
            &s.edges,
            &sharp[..k],
            &far[..k],
        );
        let (p, nrm) = s.ring.limit_sided(&mut s.faces);
        // Face 0 (between the side and the patch's inside) is this patch's.
        let sided = s.faces.first().map(|f| f.as_vec3a());
        (p.as_vec3a() + self.origin, nrm.as_vec3a(), sided)
    }

    /// Semi-sharp (sum, count) at corner `c` of its edges other than the patch side `t`
    /// (0: towards corner `c + 1`, 1: towards corner `c + 2`), for the Chaikin rule.
    fn far_at_corner(&self, c: usize, t: usize) -> (f32, u32) {
        let corner = &self.corners[c];
        if corner.fast {
            return (0.0, 0);
        }
        let v = corner.valence;
        let skip = (corner.r0 + t) % v;
        let ring = &corner.ring;
        semi_sharp_excluding(&ring.edge_sharpnesses()[..v], skip, ring.whole())
    }

    /// The limit of corner `c`, after the last step (from a copy of its ring, which stays at the
    /// table's level for the sides' Chaikin far-end sharpness, `far_at_corner`).
    pub(crate) fn limit_corner(&mut self, s: &mut LimitScratch, c: usize) -> LimitPoint {
        let origin = self.origin.as_dvec3();
        let method = self.method;
        let corner = &mut self.corners[c];
        if corner.fast {
            let v = corner.valence;
            if s.masks.len() <= v {
                s.masks.resize(v + 1, None);
            }
            let mask = s.masks[v].get_or_insert_with(|| SmoothLimitMask::new(v));
            let (p, t1, t2) = mask.apply(corner.center, &corner.edges);
            let nrm = t1.cross(t2);
            // A degenerate ring falls through to the exact ring (its area fallback).
            if nrm.length_squared() > 1e-30 * (t1.length_squared() * t2.length_squared()) {
                return (p + self.origin, nrm.normalize(), None);
            }
        }
        let (p, nrm, sided) = if corner.fast {
            s.edges.clear();
            s.edges
                .extend(corner.edges.iter().map(|e| e.as_dvec3() + origin));
            let v = corner.valence;
            s.sharp.clear();
            s.sharp.resize(v, 0.0);
            s.far.clear();
            s.far.resize(v, (0.0, 0));
            s.ring.load_triangles(
                method,
                corner.center.as_dvec3() + origin,
                0.0,
                false,
                &s.edges,
                &s.sharp,
                &s.far,
            );
            let (p, nrm) = s.ring.limit();
            (p, nrm, None)
        } else {
            // On a copy: the ring stays at the table's level, where `far_at_corner` reads the
            // Chaikin rule's sharpness for the sides' limits.
            s.ring.clone_from(&corner.ring);
            let (p, nrm) = s.ring.limit_sided(&mut s.faces);
            let sided = s.faces.get(corner.r0).map(|f| f.as_vec3a());
            (p, nrm, sided)
        };
        (p.as_vec3a(), nrm.as_vec3a(), sided)
    }
}
