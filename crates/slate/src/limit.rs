//! Limit points and normals of the final grid of a patch.
//!
//! Interior points always take the regular limit masks (separable form, [`Worker::limit_interior`]);
//! border points take them where their neighbourhood is plain, and otherwise (creases,
//! boundaries) the exact limit of their ring, through a [`QuadRingStencil`] kept per sharpness
//! configuration — [`Ring::limit`](subdiv_rules::Ring::limit) precomputed, so a semi-sharp crease
//! still gets its true limit at any depth.

use glam::{DVec3, Vec3A};
use subdiv_mesh::CreaseMethod;
use subdiv_rules::QuadRingStencil;
use subdiv_rules::catmark;
use subdiv_rules::crease::is_infinite;

use crate::table::{DI, DJ, far_info};
use crate::wide::{self, InteriorOut};
use crate::worker::Worker;

/// Most configurations a worker keeps stencils for (beyond, the oldest are replaced). Real cages
/// meet few: catmark_pawn 2, catmark_helmet 3 (one per crease direction and sharpness left).
pub(crate) const MAX_STENCILS: usize = 16;

/// A table ring's configuration: what its limit stencil depends on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct StencilKey {
    method: CreaseMethod,
    boundary: bool,
    valence: u8,
    diag: u8,
    sharp: [u32; 4],
    far: [(u32, u32); 4],
}

/// The ring of a table point for [`Worker::limit_general`], on the stack: its edge directions
/// (counter-clockwise, from after a missing one), edge neighbours with their sharpness and far-end
/// information, and diagonals (`m` edges, `nd` diagonals; at most 4 of each).
#[derive(Clone, Copy, Default)]
struct TableRing {
    dirs: [usize; 4],
    edges: [DVec3; 4],
    sharp: [f32; 4],
    far: [(f32, u32); 4],
    diag: [DVec3; 4],
    m: usize,
    nd: usize,
}

/// Which corner of a grid of size `n` the point `(i, j)` is, if any.
#[inline]
fn grid_corner(i: i32, j: i32, n: i32) -> Option<usize> {
    match (i, j) {
        (0, 0) => Some(0),
        (i, 0) if i == n => Some(1),
        (i, j) if i == n && j == n => Some(2),
        (0, j) if j == n => Some(3),
        _ => None,
    }
}

impl Worker {
    /// Limit position and normal of grid point `(i, j)` of the current slate. Each point is
    /// evaluated once per patch (corner arrays are consumed by their evaluation).
    #[inline]
    pub(crate) fn limit(&mut self, i: i32, j: i32) -> (Vec3A, Vec3A) {
        let (p, n, _) = self.limit_sided(i, j, false);
        (p, n)
    }

    /// [`Worker::limit`], and with `sided` where the limit surface has a crease or a corner at
    /// the point, the one-sided normal of the patch's side (the side of the grid cell towards
    /// the patch's interior). Only border points can have one: the edges inside a patch are
    /// never sharp.
    pub(crate) fn limit_sided(
        &mut self,
        i: i32,
        j: i32,
        sided: bool,
    ) -> (Vec3A, Vec3A, Option<Vec3A>) {
        let n = self.t[self.cur].grid_size as i32;
        if let Some(k) = grid_corner(i, j, n)
            && self.corners[k].active
        {
            // Corner arrays hold world positions (in f64). The patch's face is ring face
            // `ih` (the face of the patch's outgoing half-edge at the corner).
            let mut faces = std::mem::take(&mut self.sided);
            let c = &mut self.corners[k];
            let (p, nrm) = if sided {
                c.ring.limit_sided(&mut faces)
            } else {
                faces.clear();
                c.ring.limit()
            };
            let side = faces.get(c.ih).map(|f| Vec3A::from(f.as_vec3()));
            self.sided = faces;
            return (Vec3A::from(p.as_vec3()), Vec3A::from(nrm.as_vec3()), side);
        }
        self.limit_table(i, j, sided)
    }

    /// [`Worker::limit_sided`] at a grid point of the table, not a corner with a corner array:
    /// what the points along a patch's sides (`0 < i < n` or `0 < j < n`) take directly.
    #[inline]
    pub(crate) fn limit_table(
        &mut self,
        i: i32,
        j: i32,
        sided: bool,
    ) -> (Vec3A, Vec3A, Option<Vec3A>) {
        let t = &self.t[self.cur];
        let n = t.grid_size as i32;
        if self.regular || t.is_plain(i, j) {
            let k = t.at(i, j);
            let s = t.stride;
            let p = &t.positions;
            let e = [p[k + 1], p[k + s], p[k - 1], p[k - s]];
            let dg = [p[k + s + 1], p[k + s - 1], p[k - s - 1], p[k - s + 1]];
            // `catmark::limit` of a smooth valence-4 ring is this.
            let (pos, t1, t2) = catmark::limit_regular(p[k], e, dg);
            let nrm = t1.cross(t2);
            let len = nrm.length();
            // `len > 0.0 && len.is_finite()` in one unsigned compare (as the interior's).
            if len.to_bits().wrapping_sub(1) < 0x7f7f_ffff {
                return (pos + self.origin32, nrm / len, None);
            }
        }
        // The cell towards the patch's interior: its i and j directions.
        let side = sided.then_some((if i < n { 0 } else { 2 }, if j < n { 1 } else { 3 }));
        self.limit_general(i, j, side)
    }

    /// `true` if grid point `(i, j)` (on the border) may have one-sided normals: exactly where
    /// [`Worker::limit_sided`] would give one, so that a patch that does not own the point can
    /// skip its evaluation.
    ///
    /// A table point has them when the limit stencil of its ring's configuration is sided (the
    /// stencil is looked up, not applied). A corner array's ring is refined until no semi-sharp
    /// feature is left before its limit masks apply (`Ring::limit`), and boundary edges are
    /// infinitely sharp, so it can only have them with an infinitely sharp edge or vertex: a
    /// semi-sharp crease (the pawn's) smooths out and has one tangent plane in the limit.
    pub(crate) fn may_be_sided(&mut self, i: i32, j: i32) -> bool {
        let n = self.t[self.cur].grid_size as i32;
        if let Some(k) = grid_corner(i, j, n) {
            let c = &self.corners[k];
            if c.active {
                let r = &c.ring;
                // A crease copy's limit is the other copy's, without sides of its own.
                return !r.has_master()
                    && (is_infinite(r.vertex_sharpness())
                        || (0..r.valence()).any(|e| is_infinite(r.edge_sharpness(e))));
            }
        }
        if self.regular {
            return false;
        }
        // A ring with all four edges and none infinitely sharp is smooth in the limit (its
        // semi-sharp edges decay, table points carry no vertex sharpness): one tangent plane,
        // without looking up its stencil. (A grid point's neighbours lie inside the table.)
        let t = &self.t[self.cur];
        let (k, s) = (t.at(i, j), t.stride);
        let (ex, hs, vs) = (&t.exists, &t.horizontal_sharpness, &t.vertical_sharpness);
        if ex[k] && ex[k + 1] && ex[k + s] && ex[k - 1] && ex[k - s] {
            let sharp = [hs[k], vs[k], hs[k - 1], vs[k - s]];
            if !sharp.iter().any(|&x| is_infinite(x)) {
                return false;
            }
        }
        let mut r = TableRing::default();
        let boundary = self.table_ring_config(i, j, &mut r);
        let idx = self.stencil_index(&r, boundary);
        self.stencils[idx].1.is_sided()
    }

    /// Limits of all interior grid points `(i, j)`, `1 <= i, j <= n - 1`, of the current slate,
    /// written to `out` (see [`InteriorOut`]; panics if they do not fit).
    ///
    /// Off the band every point is plain (see [`band`](crate::table::band)), general table or
    /// not, so the regular limit masks apply to every interior point; they are evaluated in their
    /// separable form (`catmark::limit_row_sums` once per table row, shared by the three output
    /// rows around it): eight points at a time where the CPU has AVX2 and a row has at least
    /// seven points ([`wide`](crate::wide), the same bits), otherwise one at a time.
    #[inline]
    pub(crate) fn limit_interior(&mut self, out: &mut InteriorOut<'_>) {
        let t = &self.t[self.cur];
        let n = t.grid_size;
        if n < 2 {
            return;
        }
        assert!(out.fits(n), "interior output out of range");
        debug_assert!(
            (1..n as i32).all(|j| (1..n as i32).all(|i| t.is_plain(i, j))),
            "interior points of a slate must be plain"
        );
        let mut bad = std::mem::take(&mut self.bad);
        bad.clear();
        if n >= 8 && wide::available() {
            let mut scratch = std::mem::take(&mut self.wide);
            if scratch.len() < wide::scratch_len(n) {
                scratch.resize(wide::scratch_len(n), 0.0);
            }
            let t = &self.t[self.cur];
            wide::interior_rows(
                &t.positions,
                t.stride,
                n,
                self.origin32,
                &mut scratch,
                out,
                &mut bad,
            );
            self.wide = scratch;
        } else {
            self.limit_interior_scalar(out, &mut bad);
        }
        // Degenerate tangents: those points exactly, through a ring.
        for &(i, j) in &bad {
            let (pos, nrm) = self.limit(i, j);
            let k = out.first + (j - 1) as usize * out.stride + (i - 1) as usize;
            out.pos[k] = pos.to_array();
            out.nrm[k] = nrm.to_array();
        }
        self.bad = bad;
    }

    /// [`Worker::limit_interior`] one point at a time, but for the points with degenerate
    /// tangents, which it pushes onto `bad` (row by row) and leaves unwritten.
    pub(crate) fn limit_interior_scalar(
        &mut self,
        out: &mut InteriorOut<'_>,
        bad: &mut Vec<(i32, i32)>,
    ) {
        let t = &self.t[self.cur];
        let n = t.grid_size;
        let cnt = n - 1;
        assert!(out.fits(n), "interior output out of range");
        // Row sums of table rows 0..=n in a three-row rolling buffer.
        if self.sum_b.len() < 3 * cnt {
            self.sum_b.resize(3 * cnt, Vec3A::ZERO);
            self.sum_a.resize(3 * cnt, Vec3A::ZERO);
        }
        let (b0, rest) = self.sum_b[..3 * cnt].split_at_mut(cnt);
        let (b1, b2) = rest.split_at_mut(cnt);
        let (a0, rest) = self.sum_a[..3 * cnt].split_at_mut(cnt);
        let (a1, a2) = rest.split_at_mut(cnt);
        // Slots of table rows j - 1, j and j + 1, rotated after each output row.
        let mut sb: [&mut [Vec3A]; 3] = [b0, b1, b2];
        let mut sa: [&mut [Vec3A]; 3] = [a0, a1, a2];
        let sums = |j: i32, b: &mut [Vec3A], a: &mut [Vec3A]| {
            let base = t.at(0, j);
            catmark::limit_row_sums(&t.positions[base..base + cnt + 2], b, a);
        };
        sums(0, sb[0], sa[0]);
        sums(1, sb[1], sa[1]);
        let o = self.origin32;
        for j in 1..n {
            sums(j as i32 + 1, sb[2], sa[2]);
            let row = out.first + (j - 1) * out.stride;
            let (prow, nrow) = (&mut out.pos[row..row + cnt], &mut out.nrm[row..row + cnt]);
            let b = sb[0].iter().zip(sb[1].iter()).zip(sb[2].iter());
            let a = sa[0].iter().zip(sa[1].iter()).zip(sa[2].iter());
            let dst = prow.iter_mut().zip(nrow.iter_mut());
            for (x, ((((&bs, &b0), &bn), ((&as_, &a0), &an)), (p, q))) in
                b.zip(a).zip(dst).enumerate()
            {
                let (pos, t1, t2) = catmark::limit_regular_from_sums([bs, b0, bn], [as_, a0, an]);
                let nrm = t1.cross(t2);
                let len2 = nrm.length_squared();
                // `len2 > 0.0 && len2.is_finite()` in one compare: the positive finite
                // floats are exactly the bit patterns 1..=0x7f7f_ffff (+0 wraps to u32::MAX;
                // negatives, infinities and NaNs lie above).
                if len2.to_bits().wrapping_sub(1) < 0x7f7f_ffff {
                    *p = (pos + o).to_array();
                    *q = (nrm * len2.sqrt().recip()).to_array();
                } else {
                    bad.push((x as i32 + 1, j as i32));
                }
            }
            sb.rotate_left(1);
            sa.rotate_left(1);
        }
    }

    /// Limit through a ring built from the table (creases, boundaries, degenerate tangents), and
    /// with `side` (the directions of a grid cell at the point) the one-sided normal of that
    /// cell's face where the limit has more than one.
    fn limit_general(
        &mut self,
        i: i32,
        j: i32,
        side: Option<(usize, usize)>,
    ) -> (Vec3A, Vec3A, Option<Vec3A>) {
        let mut r = TableRing::default();
        let boundary = self.table_ring(i, j, &mut r);
        let t = &self.t[self.cur];
        let center = t.positions[t.at(i, j)].as_dvec3();
        let idx = self.stencil_index(&r, boundary);
        let st = &self.stencils[idx].1;
        let mut faces = std::mem::take(&mut self.sided);
        faces.clear();
        let (p, nrm) = match side {
            Some(_) if st.is_sided() => {
                st.limit_sided(center, &r.edges[..r.m], &r.diag[..r.nd], &mut faces)
            }
            _ => st.limit(center, &r.edges[..r.m], &r.diag[..r.nd]),
        };
        // Ring face `k` lies between directions `dirs[k]` and `dirs[k + 1]`.
        let one_sided = side.and_then(|(di, dj)| {
            let m = r.m;
            (0..faces.len())
                .find(|&k| {
                    let (a, b) = (r.dirs[k], r.dirs[(k + 1) % m]);
                    (a == di && b == dj) || (a == dj && b == di)
                })
                .map(|k| Vec3A::from(faces[k].as_vec3()))
        });
        self.sided = faces;
        (
            Vec3A::from((p + self.origin).as_vec3()),
            Vec3A::from(nrm.as_vec3()),
            one_sided,
        )
    }

    /// The ring of grid point `(i, j)` (`0 <= i, j <= n`) of the current slate into `r`, and
    /// whether it is a boundary ring (an edge missing).
    #[inline]
    fn table_ring(&self, i: i32, j: i32, r: &mut TableRing) -> bool {
        let boundary = self.table_ring_config(i, j, r);
        let t = &self.t[self.cur];
        for k in 0..r.m {
            let d = r.dirs[k];
            r.edges[k] = t.positions[t.at(i + DI[d], j + DJ[d])].as_dvec3();
            if !boundary || k + 1 < r.m {
                let d2 = (d + 1) % 4;
                r.diag[k] = t.positions[t.at(i + DI[d] + DI[d2], j + DJ[d] + DJ[d2])].as_dvec3();
            }
        }
        boundary
    }

    /// [`Worker::table_ring`] without the points: what its stencil depends on (directions,
    /// sharpness, far-end information, counts). A grid point's four neighbours lie inside the
    /// table, so an edge exists where both its ends do.
    #[inline]
    fn table_ring_config(&self, i: i32, j: i32, r: &mut TableRing) -> bool {
        let t = &self.t[self.cur];
        debug_assert!(
            (0..=t.grid_size as i32).contains(&i) && (0..=t.grid_size as i32).contains(&j)
        );
        let (k, s) = (t.at(i, j), t.stride);
        // Neighbours and edge sharpness in direction order (E, N, W, S).
        let nb = [k + 1, k + s, k - 1, k - s];
        let sharp = [
            t.horizontal_sharpness[k],
            t.vertical_sharpness[k],
            t.horizontal_sharpness[k - 1],
            t.vertical_sharpness[k - s],
        ];
        let here = t.exists[k];
        let present: [bool; 4] = std::array::from_fn(|d| here && t.exists[nb[d]]);
        // Counter-clockwise directions, starting after a missing one (boundary).
        let start = (0..4)
            .find(|&d| !present[(d + 3) % 4] && present[d])
            .unwrap_or(0);
        r.m = 0;
        for k in 0..4 {
            let d = (start + k) % 4;
            if present[d] {
                r.dirs[r.m] = d;
                r.m += 1;
            }
        }
        let boundary = r.m < 4;
        let chaikin = self.method == CreaseMethod::Chaikin;
        for k in 0..r.m {
            let d = r.dirs[k];
            r.sharp[k] = sharp[d];
            // Far-end information only matters to the Chaikin rule.
            r.far[k] = if chaikin {
                far_info(t, &self.corners, i + DI[d], j + DJ[d], (d + 2) % 4)
            } else {
                (0.0, 0)
            };
        }
        // A diagonal after every edge but the last of a boundary ring.
        r.nd = if boundary { r.m.saturating_sub(1) } else { r.m };
        boundary
    }

    /// Index in the stencil cache of the limit stencil of the table ring `r`, computed and cached
    /// on first use.
    ///
    /// The ring's limit is linear in its points with weights fixed by its configuration: one
    /// stencil per configuration, computed by the ring's own refinement on first use.
    fn stencil_index(&mut self, r: &TableRing, boundary: bool) -> usize {
        let mut key = StencilKey {
            method: self.method,
            boundary,
            valence: r.m as u8,
            diag: r.nd as u8,
            sharp: [0; 4],
            far: [(0, 0); 4],
        };
        for (k, (&s, &(fs, fc))) in r.sharp[..r.m].iter().zip(&r.far[..r.m]).enumerate() {
            key.sharp[k] = s.to_bits();
            key.far[k] = (fs.to_bits(), fc);
        }
        let hit = match self.stencils.get(self.last_stencil) {
            Some((k, _)) if *k == key => Some(self.last_stencil),
            _ => self.stencils.iter().position(|(k, _)| *k == key),
        };
        let idx = hit.unwrap_or_else(|| {
            let st =
                QuadRingStencil::new(self.method, boundary, &r.sharp[..r.m], &r.far[..r.m], r.nd);
            if self.stencils.len() < MAX_STENCILS {
                self.stencils.push((key, st));
                self.stencils.len() - 1
            } else {
                let slot = (self.last_stencil + 1) % MAX_STENCILS;
                self.stencils[slot] = (key, st);
                slot
            }
        });
        self.last_stencil = idx;
        idx
    }
}
