//! A slate's storage: the table of a patch's control points at one level, and the corner arrays
//! beside it.
//!
//! A slate's *table* holds the `(n + 3)^2` control points of a patch at level `l` (`n = 2^l`):
//! the patch's own `(n + 1)^2` grid and one ring of neighbours, at table coordinates
//! `(i, j)` with `-1 <= i, j <= n + 1` (Settgast et al., "Adaptive Tessellation of Subdivision
//! Surfaces", Section 3.2, Fig. 2). Alongside go the sharpness of every table edge and, for the
//! Chaikin rule, what is known of the crease beyond the outer ring.
//!
//! A corner whose vertex is not an interior valence-4 vertex (or carries a corner tag) keeps its
//! whole neighbourhood in a *corner array*: a [`Ring`] from `subdiv-rules`, holding all of its
//! `valence` edge neighbours and quads, creases and boundary included. The table covers what a
//! valence-4 corner would; the corner array provides the points the table cannot (the corner
//! itself and its neighbours beyond the table's quadrant).

use glam::Vec3A;
use subdiv_rules::Ring;
use subdiv_rules::crease::{is_semi_sharp, semi_sharp_excluding};

/// Direction index: 0 = +i (E), 1 = +j (N), 2 = -i (W), 3 = -j (S) — counter-clockwise.
pub(crate) const DI: [i32; 4] = [1, 0, -1, 0];
pub(crate) const DJ: [i32; 4] = [0, 1, 0, -1];

/// One slate's table.
#[derive(Clone, Debug, Default)]
pub(crate) struct Table {
    /// Patch grid size `n` (`2^level`).
    pub grid_size: usize,
    /// Row stride `n + 3`.
    pub stride: usize,
    /// Control point of every table position (relative to the worker's patch origin).
    pub positions: Vec<Vec3A>,
    /// Whether the control point at a table position exists (`false` beyond a boundary).
    pub exists: Vec<bool>,
    /// Sharpness of the horizontal edge `(i,j)-(i+1,j)`, stored at `(i,j)`.
    pub horizontal_sharpness: Vec<f32>,
    /// Sharpness of the vertical edge `(i,j)-(i,j+1)`, stored at `(i,j)`.
    pub vertical_sharpness: Vec<f32>,
    /// For each side, (sum, count) of the semi-sharp edges beyond the outer end of each crossing
    /// edge (Chaikin rule only), indexed by position along the side `0..=n`.
    pub far_semi_sharp: [Vec<(f32, u32)>; 4],
    /// Sharpness or existence flags may be non-default (set by a general step or gather).
    pub dirty: bool,
}

impl Table {
    pub(crate) fn with_capacity(maxn: usize) -> Table {
        let cap = (maxn + 3) * (maxn + 3);
        Table {
            grid_size: 0,
            stride: 0,
            positions: vec![Vec3A::ZERO; cap],
            exists: vec![false; cap],
            horizontal_sharpness: vec![0.0; cap],
            vertical_sharpness: vec![0.0; cap],
            far_semi_sharp: std::array::from_fn(|_| vec![(0.0, 0); maxn + 1]),
            dirty: true,
        }
    }

    /// Prepares the table for grid size `n`. A table for the regular step needs no clearing
    /// (it overwrites every point); sharpness is cleared only if a gather or general step left
    /// some (`dirty`), and then only on the band where it can be (see [`band`]; a table of grid
    /// 4 or less is cleared whole, it is nearly all band). The Chaikin far information is only
    /// read under the Chaikin rule (`chaikin`), and then cleared for every table.
    pub(crate) fn reset(&mut self, n: usize, regular: bool, chaikin: bool) {
        debug_assert!(
            (n + 3) * (n + 3) <= self.positions.len(),
            "slate too small for grid {n}"
        );
        if self.dirty && self.stride > 0 && self.grid_size <= 4 {
            // A small table is all band but its centre: cleared whole.
            let len = self.stride * self.stride;
            self.horizontal_sharpness[..len].fill(0.0);
            self.vertical_sharpness[..len].fill(0.0);
        } else if self.dirty && self.stride > 0 {
            // The band (see [`band`]), its rows as slices: rows -1, 0, n, n + 1 whole; columns
            // -1, 0, n, n + 1 of the rows between.
            let (n, s) = (self.grid_size, self.stride);
            for r in [0, 1, n + 1, n + 2] {
                self.horizontal_sharpness[r * s..(r + 1) * s].fill(0.0);
                self.vertical_sharpness[r * s..(r + 1) * s].fill(0.0);
            }
            for r in 2..=n {
                for c in [0, 1, n + 1, n + 2] {
                    self.horizontal_sharpness[r * s + c] = 0.0;
                    self.vertical_sharpness[r * s + c] = 0.0;
                }
            }
        }
        self.grid_size = n;
        self.stride = n + 3;
        if chaikin {
            for f in &mut self.far_semi_sharp {
                f[..=n].fill((0.0, 0));
            }
        }
        self.dirty = !regular;
    }

    #[inline(always)]
    pub(crate) fn at(&self, i: i32, j: i32) -> usize {
        (j + 1) as usize * self.stride + (i + 1) as usize
    }

    #[inline]
    pub(crate) fn inside(&self, i: i32, j: i32) -> bool {
        let n = self.grid_size as i32;
        (-1..=n + 1).contains(&i) && (-1..=n + 1).contains(&j)
    }

    /// Sharpness of the edge from `(i,j)` in direction `d`.
    #[inline(always)]
    pub(crate) fn edge_sharp(&self, i: i32, j: i32, d: usize) -> f32 {
        match d {
            0 => self.horizontal_sharpness[self.at(i, j)],
            1 => self.vertical_sharpness[self.at(i, j)],
            2 => self.horizontal_sharpness[self.at(i - 1, j)],
            _ => self.vertical_sharpness[self.at(i, j - 1)],
        }
    }

    #[inline]
    pub(crate) fn set_edge_sharp(&mut self, i: i32, j: i32, d: usize, s: f32) {
        let k = match d {
            0 => self.at(i, j),
            1 => self.at(i, j),
            2 => self.at(i - 1, j),
            _ => self.at(i, j - 1),
        };
        if d.is_multiple_of(2) {
            self.horizontal_sharpness[k] = s
        } else {
            self.vertical_sharpness[k] = s
        }
    }

    /// `true` if the edge from `(i,j)` in direction `d` exists (both ends inside and existing).
    #[inline]
    pub(crate) fn edge_exists(&self, i: i32, j: i32, d: usize) -> bool {
        let (a, b) = (i + DI[d], j + DJ[d]);
        self.inside(a, b) && self.exists[self.at(i, j)] && self.exists[self.at(a, b)]
    }

    /// `true` if `(i, j)` is an interior point whose 8 neighbours exist and whose 4 edges are
    /// smooth: the regular rules and limit masks apply there exactly.
    #[inline(always)]
    pub(crate) fn is_plain(&self, i: i32, j: i32) -> bool {
        let k = self.at(i, j);
        let s = self.stride;
        let (hs, vs, ex) = (
            &self.horizontal_sharpness,
            &self.vertical_sharpness,
            &self.exists,
        );
        hs[k] == 0.0
            && hs[k - 1] == 0.0
            && vs[k] == 0.0
            && vs[k - s] == 0.0
            && ex[k]
            && ex[k + 1]
            && ex[k - 1]
            && ex[k + s]
            && ex[k - s]
            && ex[k + s + 1]
            && ex[k + s - 1]
            && ex[k - s + 1]
            && ex[k - s - 1]
    }

    /// Marks the points whose rules are not the smooth regular ones: the ends of sharp edges and
    /// the neighbours of missing points, and lists the sharp edges in `sharp` (storage index of
    /// the edge's lower end and direction, 0 horizontal, 1 vertical). Returns `true` if any
    /// point is missing.
    ///
    /// Only the band can hold such points (see [`band`]), so only the band is scanned, line by
    /// line in [`band`]'s order; `list` remembers what was marked so that the next call clears
    /// just that.
    pub(crate) fn mark_dirty(
        &self,
        dirty: &mut Vec<bool>,
        list: &mut Vec<u32>,
        sharp: &mut Vec<(u32, u8)>,
    ) -> bool {
        #[cfg(debug_assertions)]
        self.check_band_invariant();
        if dirty.len() < self.positions.len() {
            dirty.resize(self.positions.len(), false);
        }
        for &k in list.iter() {
            dirty[k as usize] = false;
        }
        list.clear();
        sharp.clear();
        let (n, s) = (self.grid_size, self.stride);
        let (hs, vs, ex) = (
            &self.horizontal_sharpness[..s * s],
            &self.vertical_sharpness[..s * s],
            &self.exists[..s * s],
        );
        let mut missing = false;
        let lines = [0, 1, n + 1, n + 2];
        for r in lines {
            let row = r * s..(r + 1) * s;
            let cells = hs[row.clone()].iter().zip(&vs[row.clone()]).zip(&ex[row]);
            for (x, ((&h, &v), &e)) in cells.enumerate() {
                if h != 0.0 || v != 0.0 || !e {
                    missing |= self.mark_point(r * s + x, dirty, list, sharp);
                }
            }
        }
        for r in 2..=n {
            for c in lines {
                let k = r * s + c;
                if hs[k] != 0.0 || vs[k] != 0.0 || !ex[k] {
                    missing |= self.mark_point(k, dirty, list, sharp);
                }
            }
        }
        missing
    }

    /// [`Table::mark_dirty`] at one band point (storage index `k`) that has a sharp edge or is
    /// missing; returns `true` if it is missing. Out of line: most band points need nothing.
    #[inline(never)]
    fn mark_point(
        &self,
        k: usize,
        dirty: &mut [bool],
        list: &mut Vec<u32>,
        sharp: &mut Vec<(u32, u8)>,
    ) -> bool {
        let s = self.stride;
        let len = s * s;
        let mut set = |k: usize| {
            if !dirty[k] {
                dirty[k] = true;
                list.push(k as u32);
            }
        };
        if self.horizontal_sharpness[k] != 0.0 {
            sharp.push((k as u32, 0));
            set(k);
            if k + 1 < len {
                set(k + 1);
            }
        }
        if self.vertical_sharpness[k] != 0.0 {
            sharp.push((k as u32, 1));
            set(k);
            if k + s < len {
                set(k + s);
            }
        }
        if self.exists[k] {
            return false;
        }
        let (i, j) = ((k % s) as i32 - 1, (k / s) as i32 - 1);
        for dj in -1..=1 {
            for di in -1..=1 {
                if self.inside(i + di, j + dj) {
                    set(self.at(i + di, j + dj));
                }
            }
        }
        true
    }

    /// Checks what [`band`] relies on: every point off the band is plain (it exists, its eight
    /// neighbours exist and its four edges are smooth), so sharpness and missing points can only
    /// be found on the band.
    #[cfg(debug_assertions)]
    fn check_band_invariant(&self) {
        let n = self.grid_size as i32;
        for j in 1..n {
            for i in 1..n {
                assert!(
                    self.is_plain(i, j),
                    "slate band invariant broken at ({i}, {j}) of grid {n}"
                );
            }
        }
    }

    /// `true` if the quad with lower-left corner `(i,j)` exists.
    #[inline]
    pub(crate) fn face_exists(&self, i: i32, j: i32) -> bool {
        self.inside(i, j)
            && self.inside(i + 1, j + 1)
            && self.exists[self.at(i, j)]
            && self.exists[self.at(i + 1, j)]
            && self.exists[self.at(i, j + 1)]
            && self.exists[self.at(i + 1, j + 1)]
    }
}

/// The table points where sharp edges and missing points can be: the rows and columns
/// `-1, 0, n, n + 1` (the patch's sides and the outer ring). Gather fills a `4 x 4` table (all
/// band); a step only makes the children of band edges sharp, and only face and edge points of
/// the outer ring missing, so the band of level `l` refines into the band of level `l + 1`. Every
/// general-table loop runs over the band alone; debug builds check the invariant.
///
/// `band(n, f)` calls `f` with the storage index (`(j + 1) * (n + 3) + i + 1`) of every band point,
/// rows `j = -1, 0, n, n + 1` whole first, then columns `i = -1, 0, n, n + 1` of the rows between,
/// and stops at the first `false`; it returns whether none was.
#[inline]
pub(crate) fn band(n: usize, mut f: impl FnMut(usize) -> bool) -> bool {
    let s = n + 3;
    let lines = [0, 1, n + 1, n + 2];
    for r in lines {
        for k in r * s..(r + 1) * s {
            if !f(k) {
                return false;
            }
        }
    }
    for r in 2..=n {
        for c in lines {
            if !f(r * s + c) {
                return false;
            }
        }
    }
    true
}

/// A patch corner kept as a full ring (the slate's corner array).
#[derive(Clone, Debug, Default)]
pub(crate) struct Corner {
    pub active: bool,
    pub ring: Ring,
    /// The ring's edge sharpness at the table's level, kept apart from `ring` because the limit
    /// evaluation of the corner refines `ring` in place, while the Chaikin rule at neighbouring
    /// points still needs it afterwards ([`far_info`]).
    pub sharp: Vec<f32>,
    /// The ring's whole-vertex values at the table's level (`Ring::whole`), kept with `sharp`.
    pub whole: Vec<f32>,
    /// Ring index of the edge along the patch side leaving this corner.
    pub ih: usize,
    pub valence: usize,
    pub boundary: bool,
}

impl Corner {
    /// Records the ring's edge sharpness in `sharp`; called whenever the ring is loaded or
    /// refined.
    pub(crate) fn keep_sharpness(&mut self) {
        self.sharp.clear();
        self.sharp
            .extend((0..self.ring.valence()).map(|r| self.ring.edge_sharpness(r)));
        self.whole.clear();
        self.whole.extend_from_slice(self.ring.whole());
    }
}

/// Table position and the two patch directions of corner `k` (grid size `n`): the side leaving
/// the corner (`d`) and the side arriving at it, reversed (`d2`, counter-clockwise from `d`).
#[inline]
pub(crate) fn corner_frame(k: usize, n: i32) -> ((i32, i32), usize, usize) {
    match k {
        0 => ((0, 0), 0, 1),
        1 => ((n, 0), 1, 2),
        2 => ((n, n), 2, 3),
        _ => ((0, n), 3, 0),
    }
}

/// Ring index of the corner's edge in table direction `dir` (None if the ring has no such edge).
#[inline]
pub(crate) fn ring_index_of_dir(c: &Corner, d: usize, d2: usize, dir: usize) -> Option<usize> {
    let m = c.valence;
    let off = if dir == d {
        0isize
    } else if dir == d2 {
        1
    } else if dir == (d + 2) % 4 {
        2
    } else {
        -1
    };
    let idx = c.ih as isize + off;
    if c.boundary {
        if idx < 0 || idx >= m as isize {
            None
        } else {
            Some(idx as usize)
        }
    } else {
        if off == 2 && m == 3 {
            // valence 3: the edge opposite d is the one before d (shared slot). Valence 2 needs
            // no exception: the opposite directions are the ring's two edges again (the other
            // face wraps around the corner), which the modular index gives.
            return Some((c.ih + m - 1) % m);
        }
        Some(((idx + m as isize) % m as isize) as usize)
    }
}

/// Semi-sharp (sum, count) at table vertex `(i, j)` excluding its edge in direction `excl`.
pub(crate) fn far_info(
    t: &Table,
    corners: &[Corner; 4],
    i: i32,
    j: i32,
    excl: usize,
) -> (f32, u32) {
    let n = t.grid_size as i32;
    for (k, c) in corners.iter().enumerate() {
        let ((ci, cj), d, d2) = corner_frame(k, n);
        if ci == i && cj == j && c.active {
            let m = c.valence;
            let excl_idx = ring_index_of_dir(c, d, d2, excl).unwrap_or(usize::MAX);
            return semi_sharp_excluding(&c.sharp[..m], excl_idx, &c.whole);
        }
    }
    if (0..=n).contains(&i) && (0..=n).contains(&j) {
        let mut sum = 0.0;
        let mut cnt = 0;
        for d in 0..4 {
            if d != excl && t.edge_exists(i, j, d) {
                let s = t.edge_sharp(i, j, d);
                if is_semi_sharp(s) {
                    sum += s;
                    cnt += 1;
                }
            }
        }
        return (sum, cnt);
    }
    // Outer ring: only the crossing edge's far half lies beyond the table.
    let (side, pos) = if j == -1 {
        (0, i)
    } else if i == n + 1 {
        (1, j)
    } else if j == n + 1 {
        (2, i)
    } else {
        (3, j)
    };
    if (0..=n).contains(&pos) {
        t.far_semi_sharp[side][pos as usize]
    } else {
        (0.0, 0)
    }
}
