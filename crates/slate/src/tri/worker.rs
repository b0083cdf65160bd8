//! A thread's two triangular slates and the pipeline of one patch: gather, step.
//!
//! A slate holds the patch's lattice points `(i, j)`, `i, j >= -1`, `i + j <= n + 1` (the patch
//! triangle `i, j, n - i - j >= 0` plus the ring of points just outside its sides) in a square
//! table of side `n + 3`; the three far corners `(-1, -1)`, ... are never read. Corner `c` of the
//! patch sees the lattice in its own frame (`u` towards corner `c + 1`, `v` towards corner
//! `c + 2`): in it, its ring is `(1, 0), (0, 1), (-1, 1)`, the points beyond, `(1, -1)`, of which
//! only the first three and the last are lattice points of the table; the others (the valence
//! minus four *extras*) live in the corner's own array.

use glam::{DVec3, Vec3A};
use subdiv_mesh::{CreaseMethod, Mesh, VertexId};

use super::layout::{TriLayout, TriPatch};
use subdiv_rules::crease::{VertexRules, edge_crease_weight, is_semi_sharp};
use subdiv_rules::loop_scheme::{
    beta, edge_point, regular_vertex_point, smooth_edge_point, smooth_vertex_point, vertex_point,
};
use subdiv_rules::{Ring, Scheme};

/// A corner of the patch at the current level.
#[derive(Clone, Debug, Default)]
pub(crate) struct Corner {
    /// `true` for a smooth interior vertex (no sharpness at it or its edges): refined in `f32`
    /// from `center` and `edges`; otherwise by the exact `ring` of `subdiv-rules`.
    pub fast: bool,
    /// Number of edges.
    pub valence: usize,
    /// Ring index of the edge towards the patch's next corner (general corners).
    pub r0: usize,
    /// Fast corners: the centre and the ring in patch order (edge 0 towards the next corner),
    /// relative to the patch origin.
    pub center: Vec3A,
    /// See `center`.
    pub edges: Vec<Vec3A>,
    tmp: Vec<Vec3A>,
    /// General corners: the ring (absolute, `f64`).
    pub ring: Ring,
    /// Child sharpness of the two patch sides at this corner (towards corner `c + 1`, `c + 2`).
    child_sides: [f32; 2],
    child: Vec<f32>,
}

/// A side of the patch at the current level.
#[derive(Clone, Debug, Default)]
pub(crate) struct Side {
    /// A triangle lies beyond the side (its ring row exists).
    pub interior: bool,
    /// Interior and no sharpness on any segment: the regular rules apply along it.
    pub smooth: bool,
    /// Sharpness of each of the `n` segments, from the side's first corner; after a step on a
    /// smooth side empty instead of `n` zeros (read it through [`Side::segment`]).
    pub sharp: Vec<f32>,
    tmp: Vec<f32>,
}

impl Side {
    /// Sharpness of segment `k`: 0 on a smooth side.
    #[inline]
    pub(crate) fn segment(&self, k: usize) -> f32 {
        if self.smooth { 0.0 } else { self.sharp[k] }
    }
}

/// One thread's slates and corner arrays for triangular patches.
#[derive(Clone, Debug, Default)]
pub struct TriWorker {
    tables: [Vec<Vec3A>; 2],
    cur: usize,
    /// Current grid size (`2^level`).
    pub(crate) n: u32,
    pub(crate) method: CreaseMethod,
    /// The patch origin (corner 0's cage position); tables hold positions relative to it.
    pub(crate) origin: Vec3A,
    pub(crate) corners: [Corner; 3],
    pub(crate) sides: [Side; 3],
    betas: Vec<f64>,
}

impl TriWorker {
    /// An empty worker (tables grow on first use).
    pub fn new() -> TriWorker {
        TriWorker::default()
    }

    /// Bytes of table memory for depth `depth` (two tables of side `2^depth + 3`).
    pub fn table_bytes(depth: subdiv_rules::Depth) -> usize {
        let w = (1usize << depth) + 3;
        2 * w * w * std::mem::size_of::<Vec3A>()
    }

    /// Table index of global lattice point `(i, j)` at grid size `n`.
    #[inline(always)]
    fn gidx(n: u32, i: i32, j: i32) -> usize {
        ((j + 1) as usize) * (n as usize + 3) + (i + 1) as usize
    }

    /// Global lattice coordinates of corner `c`'s local point `(a, b)` at grid size `n`.
    #[inline(always)]
    pub(crate) fn local(n: u32, c: usize, a: i32, b: i32) -> (i32, i32) {
        let n = n as i32;
        match c {
            0 => (a, b),
            1 => (n - a - b, a),
            _ => (b, n - a - b),
        }
    }

    /// Corner `c`'s frame at grid size `n` as index arithmetic: its local point `(a, b)` lies at
    /// table index `base + a * da + b * db` (the index [`TriWorker::lidx`] computes), returned
    /// as `(base, da, db)`. Walks along a side step by `da` instead of mapping every point.
    #[inline(always)]
    pub(crate) fn frame(n: u32, c: usize) -> (isize, isize, isize) {
        let w = n as isize + 3;
        let n = n as isize;
        match c {
            // (i, j) = (a, b): (b + 1) w + a + 1.
            0 => (w + 1, 1, w),
            // (i, j) = (n - a - b, a): (a + 1) w + n - a - b + 1.
            1 => (w + n + 1, w - 1, -1),
            // (i, j) = (b, n - a - b): (n - a - b + 1) w + b + 1.
            _ => ((n + 1) * w + 1, -w, 1 - w),
        }
    }

    /// Table index of corner `c`'s local point `(a, b)`.
    #[inline(always)]
    fn lidx(n: u32, c: usize, a: i32, b: i32) -> usize {
        let (i, j) = Self::local(n, c, a, b);
        Self::gidx(n, i, j)
    }

    /// The current level's point at corner `c`'s local `(a, b)`.
    #[inline(always)]
    pub(crate) fn at_local(&self, c: usize, a: i32, b: i32) -> Vec3A {
        self.tables[self.cur][Self::lidx(self.n, c, a, b)]
    }

    /// The current table.
    #[inline(always)]
    pub(crate) fn table(&self) -> &[Vec3A] {
        &self.tables[self.cur]
    }

    fn ensure(&mut self, n: u32) {
        let w = (n as usize + 3) * (n as usize + 3);
        for t in &mut self.tables {
            if t.len() < w {
                t.resize(w, Vec3A::ZERO);
            }
        }
    }

    fn beta(&mut self, valence: usize) -> f64 {
        if self.betas.len() <= valence {
            let k = self.betas.len();
            self.betas.extend((k..=valence).map(beta));
        }
        self.betas[valence]
    }

    /// Collects the level-0 patch `p` of `layout`: its corners, the vertices beyond its sides, the
    /// corner rings and the sides' sharpness.
    pub fn gather(&mut self, mesh: &Mesh, layout: &TriLayout, p: &TriPatch, max_n: u32) {
        self.ensure(max_n);
        if cfg!(debug_assertions) {
            // Debug builds poison the slates: a point read before it is written shows as NaN.
            for t in &mut self.tables {
                t.fill(Vec3A::NAN);
            }
        }
        self.cur = 0;
        self.n = 1;
        self.method = mesh.options().crease;
        let positions = mesh.positions();
        self.origin = positions[p.corners[0] as usize].into();
        let origin = self.origin;
        let pos = |v: u32| Vec3A::from(positions[v as usize]) - origin;
        for c in 0..3 {
            let t = &mut self.tables[0];
            t[Self::lidx(1, c, 0, 0)] = pos(p.corners[c]);
            let side = &mut self.sides[c];
            side.interior = p.beyond[c] != u32::MAX;
            if side.interior {
                t[Self::lidx(1, c, 1, -1)] = pos(p.beyond[c]);
            }
            let s = mesh.edge_sharpness(p.edges[c]);
            side.sharp.clear();
            side.sharp.push(s);
            side.smooth = side.interior && s <= 0.0;
        }
        for c in 0..3 {
            let v = p.corners[c];
            let ring = layout.ring(v);
            let corner = &mut self.corners[c];
            let valence = ring.len();
            corner.valence = valence;
            corner.r0 = p.r0[c] as usize;
            corner.fast = layout.is_fast(v);
            if corner.fast {
                corner.center = pos(v);
                corner.edges.clear();
                let (a, b) = ring.split_at(corner.r0);
                corner.edges.extend(b.iter().map(|&w| pos(w)));
                corner.edges.extend(a.iter().map(|&w| pos(w)));
            } else {
                corner.ring.load(mesh, VertexId(v), Scheme::Loop);
            }
        }
    }

    /// One subdivision step into the other table (grid size `n` to `2n`).
    pub fn step(&mut self) {
        self.step_with([true; 3], [CornerNeed::Ring; 3]);
    }

    /// [`TriWorker::step`] that may skip the child ring row beyond a smooth side `c` with
    /// `rows[c] == false` and, at a fast corner `c`, all of its refinement but the table points
    /// `corners[c]` asks for: the last step of a patch whose limits will not read the rest (the
    /// points left stale are read by no later stage, so the output is that of `step`).
    pub(crate) fn step_with(&mut self, rows: [bool; 3], corners: [CornerNeed; 3]) {
        let n = self.n;
        let n2 = 2 * n;
        let mut tables = std::mem::take(&mut self.tables);
        let [t0, t1] = &mut tables;
        let (src, dst) = if self.cur == 0 {
            (&*t0, t1)
        } else {
            (&*t1, t0)
        };
        regular_step(src, dst, n);
        // Ring rows beyond the interior sides.
        for (c, side) in self.sides.iter().enumerate() {
            if side.interior && (rows[c] || !side.smooth) {
                ring_row(src, dst, n, c);
            }
        }
        // Child sharpness of the sides at the corners, then the general sides.
        let method = self.method;
        for corner in &mut self.corners {
            if corner.fast {
                corner.child_sides = [0.0; 2];
            } else {
                let v = corner.valence;
                corner.ring.child_edge_sharpness(&mut corner.child);
                corner.child_sides = [corner.child[corner.r0], corner.child[(corner.r0 + 1) % v]];
            }
        }
        for c in 0..3 {
            let ends = [
                self.corners[c].child_sides[0],
                self.corners[(c + 1) % 3].child_sides[1],
            ];
            let side = &mut self.sides[c];
            if side.smooth {
                // Its `n2` segments are all 0 (`Side::segment`): nothing to store.
                side.sharp.clear();
            } else {
                general_side(src, dst, n, c, side, method, ends);
            }
        }
        // Corners last: their points replace whatever the passes above wrote there.
        for c in 0..3 {
            let need = corners[c];
            if self.corners[c].fast && need == CornerNeed::Nothing {
                continue;
            }
            let b = if self.corners[c].fast {
                let v = self.corners[c].valence;
                self.beta(v)
            } else {
                0.0
            };
            let origin = self.origin;
            let interior_next = self.sides[c].interior;
            let interior_prev = self.sides[(c + 2) % 3].interior;
            let corner = &mut self.corners[c];
            let v = corner.valence;
            if corner.fast && need == CornerNeed::Table {
                // Only the corner's three table points: the centre and the two ring points
                // beyond the sides, as `refine_fast_corner` computes them (the ring itself is
                // left at the old level; no later stage reads it).
                let (cp, e) = (corner.center, &corner.edges[..v]);
                dst[Self::lidx(n2, c, 0, 0)] = smooth_vertex_point(cp, e, b);
                if interior_prev {
                    let next = if v > 3 { e[3] } else { e[0] };
                    dst[Self::lidx(n2, c, -1, 1)] = smooth_edge_point(cp, e[2], next, e[1]);
                }
                if interior_next {
                    let last = smooth_edge_point(cp, e[v - 1], e[0], e[v - 2]);
                    dst[Self::lidx(n2, c, 1, -1)] = last;
                }
                continue;
            }
            let (center, first, last) = if corner.fast {
                refine_fast_corner(corner, b);
                (corner.center, corner.edges[2], corner.edges[v - 1])
            } else {
                corner.ring.refine();
                let r = &corner.ring;
                let rel = |p: DVec3| p.as_vec3a() - origin;
                (
                    rel(r.center()),
                    if interior_prev {
                        rel(r.edge((corner.r0 + 2) % v))
                    } else {
                        Vec3A::ZERO
                    },
                    if interior_next {
                        rel(r.edge((corner.r0 + v - 1) % v))
                    } else {
                        Vec3A::ZERO
                    },
                )
            };
            dst[Self::lidx(n2, c, 0, 0)] = center;
            if interior_prev {
                dst[Self::lidx(n2, c, -1, 1)] = first;
            }
            if interior_next {
                dst[Self::lidx(n2, c, 1, -1)] = last;
            }
        }
        self.tables = tables;
        self.cur = 1 - self.cur;
        self.n = n2;
    }
}

/// Refines a fast corner's ring in place: the smooth vertex point of the centre and the smooth
/// edge point of every edge (opposites: the neighbouring edges).
fn refine_fast_corner(corner: &mut Corner, b: f64) {
    let v = corner.valence;
    let (c, e) = (corner.center, &corner.edges[..v]);
    // Edge `t` with its neighbours `t + 1` and `t - 1` around the ring (valence 3 or more): the
    // first and last apart, the others through windows, without a bounds check per edge.
    corner.tmp.resize(v, Vec3A::ZERO);
    let out = &mut corner.tmp[..v];
    out[0] = smooth_edge_point(c, e[0], e[1], e[v - 1]);
    for (o, w) in out[1..v - 1].iter_mut().zip(e.windows(3)) {
        *o = smooth_edge_point(c, w[1], w[2], w[0]);
    }
    out[v - 1] = smooth_edge_point(c, e[v - 1], e[0], e[v - 2]);
    corner.center = smooth_vertex_point(c, e, b);
    std::mem::swap(&mut corner.edges, &mut corner.tmp);
}

/// What the last step must compute of a corner (`TriWorker::step_with`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum CornerNeed {
    /// The whole refined ring (the corner's limit reads it, or a later step).
    Ring,
    /// Only its three table points (a side's limit reads them).
    Table,
    /// Nothing (no limit reads the corner's table points).
    Nothing,
}

/// The regular rules over the whole child triangle `i', j' >= 0, i' + j' <= 2n` (Loop's box
/// spline: vertex points `5/8 v + 1/16 sum`, edge points `3/8 (a + b) + 1/8 (c + d)`), but for
/// the three corners, whose points the corner pass writes (or, at a last step, no limit reads).
/// Non-smooth sides are overwritten afterwards.
fn regular_step(src: &[Vec3A], dst: &mut [Vec3A], n: u32) {
    let w = n as usize + 3;
    let w2 = 2 * n as usize + 3;
    let n = n as usize;
    // Parent (a, b) is `mid[a + 1]` with `mid` the table row of `b` (from column -1), `lo` and
    // `hi` the rows of `b - 1` and `b + 1` (`lo` from column 0): each point's neighbours come as
    // windows of those rows, so the loops index without a bounds check per point. The sums are
    // those of the point-by-point form, in its order. Row `b = n` is corner 2 alone.
    for b in 0..n {
        let len = n - b;
        let lo = &src[b * w + 1..][..len + 2];
        let mid = &src[(b + 1) * w..][..len + 3];
        let hi = &src[(b + 2) * w..][..len + 2];
        let vertex = |m: &[Vec3A], h: &[Vec3A], l: &[Vec3A]| {
            regular_vertex_point(m[1], m[2] + h[1] + h[0] + m[0] + l[0] + l[1])
        };
        // Even child row 2b: vertex points at even i', edge points of (a, b)-(a + 1, b) at odd;
        // on row 0 the vertex points at a = 0 and a = n are corners 0 and 1.
        let even = &mut dst[(2 * b + 1) * w2 + 1..][..2 * len + 1];
        let (pairs, last) = even.split_at_mut(2 * len);
        let mut around = mid.windows(3).zip(hi.windows(2)).zip(lo.windows(2));
        for (a, (o, ((m, h), l))) in pairs.chunks_exact_mut(2).zip(&mut around).enumerate() {
            if a > 0 || b > 0 {
                o[0] = vertex(m, h, l);
            }
            o[1] = smooth_edge_point(m[1], m[2], h[1], l[1]);
        }
        if b > 0
            && let Some(((m, h), l)) = around.next()
        {
            last[0] = vertex(m, h, l);
        }
        // Odd child row 2b + 1: edges (a, b)-(a, b + 1) at even i', (a + 1, b)-(a, b + 1) at odd.
        let odd = &mut dst[(2 * b + 2) * w2 + 1..][..2 * len];
        for ((o, m), h) in odd
            .chunks_exact_mut(2)
            .zip(mid.windows(3))
            .zip(hi.windows(3))
        {
            o[0] = smooth_edge_point(m[1], h[1], h[0], m[2]);
            o[1] = smooth_edge_point(m[2], h[1], m[1], h[2]);
        }
    }
}

/// The child ring row beyond side `c` (corner `c`'s local `(i', -1)`, `2 <= i' <= 2n - 1`):
/// smooth edge points of the edges from side points to ring points (inside the next cage
/// triangle). `(1, -1)` and `(2n, -1)` belong to the corners.
fn ring_row(src: &[Vec3A], dst: &mut [Vec3A], n: u32, c: usize) {
    let (sb, sa, sn) = TriWorker::frame(n, c);
    let (db, da, dn) = TriWorker::frame(2 * n, c);
    let s = |k: isize| src[k as usize];
    for a in 1..n as isize {
        // Source (a, 0) and the child (2a, -1).
        let k = sb + a * sa;
        let d = db + 2 * a * da - dn;
        // i' = 2a + 1: edge (a, 0)-(a + 1, -1), opposites (a + 1, 0), (a, -1).
        dst[(d + da) as usize] = smooth_edge_point(s(k), s(k + sa - sn), s(k + sa), s(k - sn));
        // i' = 2a: edge (a, 0)-(a, -1), opposites (a - 1, 0), (a + 1, -1).
        dst[d as usize] = smooth_edge_point(s(k), s(k - sn), s(k - sa), s(k + sa - sn));
    }
}

/// The ring of the side point at corner `c`'s local `(a, 0)`, `0 < a < n`, in ring order (edge 0
/// along the side towards corner `c + 1`), its edges' sharpness and, for the Chaikin rule, the
/// semi-sharp (sum, count) at their far ends; four edges on a boundary side.
#[allow(clippy::too_many_arguments)]
pub(crate) fn side_ring(
    table: &[Vec3A],
    n: u32,
    c: usize,
    a: i32,
    side: &Side,
    far_ends: [(f32, u32); 2],
    edges: &mut [Vec3A; 6],
    sharp: &mut [f32; 6],
    far: &mut [(f32, u32); 6],
) -> usize {
    let s = |x: i32, y: i32| table[TriWorker::lidx(n, c, x, y)];
    *edges = [
        s(a + 1, 0),
        s(a, 1),
        s(a - 1, 1),
        s(a - 1, 0),
        s(a, -1),
        s(a + 1, -1),
    ];
    let (ahead, behind) = (side.segment(a as usize), side.segment(a as usize - 1));
    *sharp = [ahead, 0.0, 0.0, behind, 0.0, 0.0];
    let semi = |x: f32| if is_semi_sharp(x) { (x, 1) } else { (0.0, 0) };
    let far_ahead = if a + 1 < n as i32 {
        semi(side.segment(a as usize + 1))
    } else {
        far_ends[1]
    };
    let far_behind = if a > 1 {
        semi(side.segment(a as usize - 2))
    } else {
        far_ends[0]
    };
    *far = [
        far_ahead,
        (0.0, 0),
        (0.0, 0),
        far_behind,
        (0.0, 0),
        (0.0, 0),
    ];
    if side.interior { 6 } else { 4 }
}

/// The general rules along side `c`: vertex points of its inner points and edge points of its
/// segments by `subdiv-rules` (creases, boundaries, fractional and Chaikin sharpness); the
/// side's child sharpness. `ends` holds the child sharpness of the first and last segment at
/// the corners.
fn general_side(
    src: &[Vec3A],
    dst: &mut [Vec3A],
    n: u32,
    c: usize,
    side: &mut Side,
    method: CreaseMethod,
    ends: [f32; 2],
) {
    let n2 = 2 * n;
    side.tmp.clear();
    side.tmp.resize(n2 as usize, 0.0);
    side.tmp[0] = ends[0];
    side.tmp[n2 as usize - 1] = ends[1];
    let mut edges = [Vec3A::ZERO; 6];
    let mut sharp = [0.0f32; 6];
    let mut far = [(0.0f32, 0u32); 6];
    let mut cs = [0.0f32; 6];
    for a in 1..n as i32 {
        let k = side_ring(
            src,
            n,
            c,
            a,
            side,
            [(0.0, 0); 2],
            &mut edges,
            &mut sharp,
            &mut far,
        );
        let rules = VertexRules::new(method, 0.0, &sharp[..k], &mut cs[..k]);
        dst[TriWorker::lidx(n2, c, 2 * a, 0)] =
            vertex_point(src[TriWorker::lidx(n, c, a, 0)], &edges[..k], &rules);
        side.tmp[2 * a as usize] = cs[0];
        side.tmp[2 * a as usize - 1] = cs[3];
    }
    for k in 0..n as i32 {
        let s = side.sharp[k as usize];
        let w = edge_crease_weight(s, [side.tmp[2 * k as usize], side.tmp[2 * k as usize + 1]]);
        let a = src[TriWorker::lidx(n, c, k, 0)];
        let b = src[TriWorker::lidx(n, c, k + 1, 0)];
        let inside = src[TriWorker::lidx(n, c, k, 1)];
        let p = if side.interior {
            edge_point(a, b, &[inside, src[TriWorker::lidx(n, c, k + 1, -1)]], w)
        } else {
            edge_point(a, b, &[inside], w)
        };
        dst[TriWorker::lidx(n2, c, 2 * k + 1, 0)] = p;
    }
    std::mem::swap(&mut side.sharp, &mut side.tmp);
    side.smooth = side.interior && side.sharp.iter().all(|&s| s <= 0.0);
}

#[cfg(test)]
mod tests {
    use super::TriWorker;

    #[test]
    fn frame_steps_reach_the_points_lidx_maps() {
        for n in [1u32, 2, 4, 8, 32] {
            for c in 0..3 {
                let (base, da, db) = TriWorker::frame(n, c);
                for b in -1..=1i32 {
                    for a in -1..=n as i32 + 1 {
                        let (i, j) = TriWorker::local(n, c, a, b);
                        if i < -1 || j < -1 || i + j > n as i32 + 1 {
                            continue;
                        }
                        let k = base + a as isize * da + b as isize * db;
                        assert_eq!(
                            k as usize,
                            TriWorker::lidx(n, c, a, b),
                            "n {n} c {c} ({a}, {b})"
                        );
                    }
                }
            }
        }
    }
}
