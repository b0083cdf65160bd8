//! One subdivision step ([`Worker::step`]): the table of slate `i` into the table of slate
//! `1 - i` with the rules of `subdiv-rules`, and the corner arrays refined in place.
//!
//! Every table is first refined by the smooth regular rules in their separable form (rows split,
//! then split rows combined, [`step_regular`]; the row loop in `rows`, its AVX2 kernels in
//! `wide::split`); a table with creases or boundaries then redoes,
//! with the general face, edge and vertex rules, only its *dirty* points: the ends of sharp edges
//! and the neighbours of missing points ([`step_general`]). Those lie on the *band* (rows and
//! columns `-1, 0, n, n + 1`, see [`band`](crate::table::band)), so the general work grows with
//! the patch's side, not its area.

use glam::{DVec3, Vec3A};
use subdiv_mesh::CreaseMethod;
use subdiv_rules::catmark;
use subdiv_rules::crease::{self, VertexRules, edge_crease_weight, is_semi_sharp};

use crate::table::{Corner, DI, DJ, Table, band, corner_frame, far_info, ring_index_of_dir};
use crate::worker::Worker;

pub(crate) mod rows;

impl Worker {
    /// One subdivision step: slate `cur` to slate `1 - cur`, corner arrays refined in place.
    pub(crate) fn step(&mut self) {
        let (a, b) = self.t.split_at_mut(1);
        let (src, dst) = if self.cur == 0 {
            (&a[0], &mut b[0])
        } else {
            (&b[0], &mut a[0])
        };
        let n = src.grid_size as i32;
        dst.reset(
            src.grid_size * 2,
            self.regular,
            self.method == CreaseMethod::Chaikin,
        );
        for c in self.corners.iter_mut() {
            if c.active {
                c.ring.refine();
                c.keep_sharpness();
            }
        }
        if self.regular {
            step_regular(src, dst, &mut self.split);
        } else {
            let scratch = Scratch {
                dirty: &mut self.dirty,
                dirty_list: &mut self.dirty_list,
                sharp_edges: &mut self.sharp_edges,
                split: &mut self.split,
            };
            step_general(src, dst, &self.corners, self.method, scratch);
        }
        // Corner arrays fill the table where it cannot be computed.
        for (k, c) in self.corners.iter().enumerate() {
            if !c.active {
                continue;
            }
            let ((ci, cj), d, d2) = corner_frame(k, 2 * n);
            write_corner(dst, c, ci, cj, d, d2, self.origin);
        }
        self.cur = 1 - self.cur;
        if !self.regular && self.method != CreaseMethod::Chaikin {
            self.regular = self.table_is_regular();
        }
    }

    /// `true` if the current table would have made [`Worker::gather`] choose the regular rules:
    /// no sharp edge, no missing point but the diagonal spots of corner arrays, no boundary or
    /// sharp vertex at a corner array (Uniform creases; Chaikin keeps the general rules).
    ///
    /// A patch whose sharp edges all run along its outer ring has none left after one step (their
    /// children lie beyond the table), and from then on the general step computes exactly what the
    /// regular one does: no point is dirty but the neighbours of the corner arrays' diagonal spots,
    /// whose general edge points `write_corner` replaces. So such a patch switches to the regular
    /// rules for its remaining steps and its limits, with bit-identical results.
    fn table_is_regular(&self) -> bool {
        if self.corners.iter().any(|c| {
            c.active && (c.boundary || c.ring.vertex_sharpness() > 0.0 || c.ring.has_master())
        }) {
            return false;
        }
        let t = &self.t[self.cur];
        let (n, s) = (t.grid_size, t.stride);
        // Sharp edges and missing points can only be on the band; the diagonal spots are the
        // corners of the storage square.
        band(n, |k| {
            let spot = k == 0 || k == s - 1 || k == s * (s - 1) || k == s * s - 1;
            t.horizontal_sharpness[k] == 0.0
                && t.vertical_sharpness[k] == 0.0
                && (t.exists[k] || spot)
        })
    }
}

/// Copies a refined corner array into the table around its corner `(ci, cj)`.
fn write_corner(t: &mut Table, c: &Corner, ci: i32, cj: i32, d: usize, d2: usize, origin: DVec3) {
    let r = &c.ring;
    let m = c.valence;
    let put = |t: &mut Table, i: i32, j: i32, p: Option<DVec3>| {
        let k = t.at(i, j);
        match p {
            Some(p) => {
                t.positions[k] = Vec3A::from((p - origin).as_vec3());
                t.exists[k] = true;
            }
            None => {
                t.positions[k] = Vec3A::from((r.center() - origin).as_vec3());
                t.exists[k] = false;
            }
        }
    };
    put(t, ci, cj, Some(r.center()));
    let back = (d + 2) % 4; // -d
    let down = (d2 + 2) % 4; // -d2
    let e_back = ring_index_of_dir(c, d, d2, back);
    let e_down = ring_index_of_dir(c, d, d2, down);
    put(t, ci + DI[back], cj + DJ[back], e_back.map(|x| r.edge(x)));
    put(t, ci + DI[down], cj + DJ[down], e_down.map(|x| r.edge(x)));
    // The diagonal behind the corner exists only for an interior valence-4 vertex.
    let diag = if !c.boundary && m == 4 {
        Some(r.diag((c.ih + 2) % 4))
    } else {
        None
    };
    put(t, ci + DI[back] + DI[down], cj + DJ[back] + DJ[down], diag);
    // Child sharpness of the corner's edges.
    for dir in [d, d2, back, down] {
        let (ni, nj) = (ci + DI[dir], cj + DJ[dir]);
        if !t.inside(ni, nj) {
            continue;
        }
        let s = ring_index_of_dir(c, d, d2, dir)
            .map(|x| r.edge_sharpness(x))
            .unwrap_or(0.0);
        t.set_edge_sharp(ci, cj, dir, s);
    }
}

/// Smooth regular step: no sharpness, no boundary. The face, edge and vertex rules of a regular
/// grid in their separable form (`catmark::split_row` and friends): each source row is split
/// along its length, and neighbouring split rows combine into the rows of `dst`. Split rows live
/// in a three-row rolling buffer `split`. Active corners get a (meaningless) vertex point too:
/// `write_corner` replaces it.
fn step_regular(src: &Table, dst: &mut Table, split: &mut Vec<Vec3A>) {
    let ss = src.stride;
    let ds = dst.stride;
    debug_assert_eq!(ds, 2 * ss - 3);
    if split.len() < 3 * ds {
        split.resize(3 * ds, Vec3A::ZERO);
    }
    let (src, dst_p) = (&src.positions, &mut dst.positions);
    if !crate::wide::split_rows(src, ss, dst_p, ds, split) {
        rows::regular_rows(&rows::Scalar, src, ss, dst_p, ds, split);
    }
    dst.exists[..ds * ds].fill(true);
}

/// The worker's scratch a general step uses (borrowed field by field beside the tables).
struct Scratch<'a> {
    dirty: &'a mut Vec<bool>,
    dirty_list: &'a mut Vec<u32>,
    sharp_edges: &'a mut Vec<(u32, u8)>,
    split: &'a mut Vec<Vec3A>,
}

/// What the general rules of one step read: the source table, the refined corner arrays and the
/// crease rule.
#[derive(Clone, Copy)]
struct General<'a> {
    src: &'a Table,
    corners: &'a [Corner; 4],
    method: CreaseMethod,
    /// Every point of `src` exists (no boundary, no corner array's diagonal spot left empty):
    /// then an edge or face exists exactly when it lies inside the table.
    all_exist: bool,
}

impl General<'_> {
    /// [`Table::face_exists`] of the source table.
    #[inline]
    fn face_exists(&self, i: i32, j: i32) -> bool {
        if self.all_exist {
            self.src.inside(i, j) && self.src.inside(i + 1, j + 1)
        } else {
            self.src.face_exists(i, j)
        }
    }

    /// [`Table::edge_exists`] of the source table.
    #[inline]
    fn edge_exists(&self, i: i32, j: i32, d: usize) -> bool {
        if self.all_exist {
            self.src.inside(i + DI[d], j + DJ[d])
        } else {
            self.src.edge_exists(i, j, d)
        }
    }
}

/// General step: creases, boundaries, fractional sharpness, Chaikin.
fn step_general(
    src: &Table,
    dst: &mut Table,
    corners: &[Corner; 4],
    method: CreaseMethod,
    sc: Scratch<'_>,
) {
    let n = src.grid_size as i32;
    // The smooth regular rules everywhere first; then the general rules where they differ.
    step_regular(src, dst, sc.split);
    let missing = src.mark_dirty(sc.dirty, sc.dirty_list, sc.sharp_edges);
    let g = General {
        src,
        corners,
        method,
        all_exist: !missing,
    };
    if missing {
        // Missing points lie on the outer ring, so only faces touching it can be missing.
        for j in -1..=n {
            let all = j == -1 || j == n;
            for i in -1..=n {
                if (all || i == -1 || i == n) && !src.face_exists(i, j) {
                    let k = dst.at(2 * i + 1, 2 * j + 1);
                    dst.exists[k] = false;
                }
            }
        }
    }
    // Child sharpness at active corners comes from their (already refined) corner arrays.
    for (k, c) in corners.iter().enumerate() {
        if c.active {
            let ((ci, cj), d, d2) = corner_frame(k, n);
            for dir in 0..4 {
                if let Some(x) = ring_index_of_dir(c, d, d2, dir) {
                    dst.set_edge_sharp(2 * ci, 2 * cj, dir, c.ring.edge_sharpness(x));
                }
            }
        }
    }
    // Vertex points and the child sharpness of their edges, at the patch's dirty points.
    let is_corner = |i: i32, j: i32| -> Option<usize> {
        (0..4).find(|&k| {
            let ((ci, cj), _, _) = corner_frame(k, n);
            ci == i && cj == j && corners[k].active
        })
    };
    let ss = src.stride;
    for &kk in sc.dirty_list.iter() {
        let kk = kk as usize;
        let (i, j) = ((kk % ss) as i32 - 1, (kk / ss) as i32 - 1);
        if !((0..=n).contains(&i) && (0..=n).contains(&j) && src.exists[kk]) {
            continue;
        }
        if (i == 0 || i == n) && (j == 0 || j == n) && is_corner(i, j).is_some() {
            continue;
        }
        if g.all_exist {
            plain_vertex_point(method, src, dst, kk);
        } else {
            general_vertex_point(g, dst, i, j);
        }
    }
    if missing {
        general_edges_near_missing(g, dst, sc.dirty, sc.dirty_list);
    } else {
        // Every point exists: a smooth edge of rows or columns 0..=n lies between two faces, and
        // the regular pass computed its point alike; only the sharp edges need the general rule.
        for &(k, dir) in sc.sharp_edges.iter() {
            let (k, dir) = (k as usize, dir as usize);
            let (i, j) = ((k % ss) as i32 - 1, (k / ss) as i32 - 1);
            let row = if dir == 0 { j } else { i };
            if (0..=n).contains(&row) && src.inside(i + DI[dir], j + DJ[dir]) {
                if method == CreaseMethod::Chaikin {
                    general_edge_point(g, dst, sc.dirty, i, j, dir);
                } else {
                    sharp_edge_point(src, dst, k, dir);
                }
            }
        }
    }
    // The outer ends of crossing edges exist as edge points; new outer-ring vertices beyond
    // (odd positions) are face points (already marked).
}

/// The general edge points of a table with missing points: every edge with a dirty end, once,
/// from its dirty end with the lower index. Horizontal edges of rows 0..=n and vertical edges of
/// columns 0..=n (the outer ring's own edges have no children in the next table).
fn general_edges_near_missing(g: General<'_>, dst: &mut Table, dirty: &[bool], list: &[u32]) {
    let (src, n) = (g.src, g.src.grid_size as i32);
    let ss = src.stride;
    for &kk in list.iter() {
        let kk = kk as usize;
        let (i, j) = ((kk % ss) as i32 - 1, (kk / ss) as i32 - 1);
        for d in 0..4 {
            let (qi, qj) = (i + DI[d], j + DJ[d]);
            if !src.inside(qi, qj) {
                continue;
            }
            let qk = src.at(qi, qj);
            if dirty[qk] && qk < kk {
                continue;
            }
            let (ei, ej, dir) = if d < 2 { (i, j, d) } else { (qi, qj, d - 2) };
            let row = if dir == 0 { ej } else { ei };
            if (0..=n).contains(&row) {
                general_edge_point(g, dst, dirty, ei, ej, dir);
            }
        }
    }
}

/// [`general_edge_point`] of a sharp edge of rows or columns `0..=n` in a table where every point
/// exists, under a rule without far-end information (not Chaikin): both ends are dirty, the edge
/// and the faces beside it exist, and the child sharpness beyond the outer ring is the parent's
/// decremented (`child_edge_sharpness` without semi-sharp neighbours). `k` is the storage index
/// of the edge's lower end, `dir` 0 horizontal, 1 vertical. The same operations on the same
/// values as the general path, without its existence tests and index arithmetic.
#[inline]
fn sharp_edge_point(src: &Table, dst: &mut Table, k: usize, dir: usize) {
    let (n, ss, ds) = (src.grid_size, src.stride, dst.stride);
    let (x, y) = (k % ss, k / ss);
    let b = if dir == 0 { k + 1 } else { k + ss };
    let (s, kd) = if dir == 0 {
        (src.horizontal_sharpness[k], y * 2 * ds - ds + 2 * x)
    } else {
        (src.vertical_sharpness[k], 2 * x + 2 * y * ds - 1)
    };
    // `kd`: storage index in `dst` of the edge point, level coordinates `(i + bi, j + bj)` with
    // storage `(2 x - 1, 2 y - 1) + (DI, DJ)` for `(x, y)` the lower end's storage position.
    debug_assert_eq!(kd, {
        let (i, j) = (x as i32 - 1, y as i32 - 1);
        dst.at(2 * i + DI[dir], 2 * j + DJ[dir])
    });
    let inner = |x: usize, y: usize| (1..=n + 1).contains(&x) && (1..=n + 1).contains(&y);
    let child = |x: usize, y: usize, toward: usize| -> f32 {
        if inner(x, y) {
            dst.edge_sharp(2 * x as i32 - 2, 2 * y as i32 - 2, toward)
        } else {
            crease::decrement(s)
        }
    };
    let (bx, by) = if dir == 0 { (x + 1, y) } else { (x, y + 1) };
    let c0 = child(x, y, dir);
    let c1 = child(bx, by, dir + 2);
    let w = edge_crease_weight(s, [c0, c1]);
    let (a, bp) = (src.positions[k], src.positions[b]);
    let e = if w == 1.0 {
        catmark::edge_point(a, bp, &[], w)
    } else {
        // The face points beside the edge (both exist: every point does, and the edge lies in
        // rows or columns 0..=n): below/left of it first, as the general path reads them.
        let f0 = if dir == 0 { kd - ds } else { kd - 1 };
        let f1 = if dir == 0 { kd + ds } else { kd + 1 };
        catmark::edge_point(a, bp, &[dst.positions[f0], dst.positions[f1]], w)
    };
    dst.positions[kd] = e;
    dst.exists[kd] = true;
}

/// [`general_vertex_point`] at a patch point (storage index `k`) of a table where every point
/// exists: its four edges and four faces exist (its neighbours lie inside the table), so they are
/// read by storage index in the general path's order (edges E, N, W, S; faces NE, NW, SW, SE).
#[inline]
fn plain_vertex_point(method: CreaseMethod, src: &Table, dst: &mut Table, k: usize) {
    let (ss, ds) = (src.stride, dst.stride);
    let (hs, vs, p) = (
        &src.horizontal_sharpness,
        &src.vertical_sharpness,
        &src.positions,
    );
    let e_sh = [hs[k], vs[k], hs[k - 1], vs[k - ss]];
    let e_pts = [p[k + 1], p[k + ss], p[k - 1], p[k - ss]];
    let mut c_sh = [0.0f32; 4];
    let rules = VertexRules::new(method, 0.0, &e_sh, &mut c_sh);
    // Storage index in `dst` of the vertex point: level coordinates `(2 i, 2 j)`.
    let kd = (2 * (k / ss) - 1) * ds + 2 * (k % ss) - 1;
    let v = p[k];
    let q = if rules.parent.is_smooth() || rules.child.is_smooth() {
        let d = &dst.positions;
        let f_pts = [
            d[kd + ds + 1],
            d[kd + ds - 1],
            d[kd - ds - 1],
            d[kd - ds + 1],
        ];
        catmark::vertex_point(v, &e_pts, &f_pts, &rules)
    } else {
        catmark::vertex_point(v, &e_pts, &[], &rules)
    };
    dst.positions[kd] = q;
    dst.exists[kd] = true;
    dst.horizontal_sharpness[kd] = c_sh[0];
    dst.vertical_sharpness[kd] = c_sh[1];
    dst.horizontal_sharpness[kd - 1] = c_sh[2];
    dst.vertical_sharpness[kd - ds] = c_sh[3];
}

/// Vertex point of patch point `(i, j)` by the general rules, and the child sharpness of its
/// edges.
#[inline]
fn general_vertex_point(g: General<'_>, dst: &mut Table, i: i32, j: i32) {
    let src = g.src;
    // At most four edges and faces: on the stack.
    let mut dirs = [0usize; 4];
    let mut e_pts = [Vec3A::ZERO; 4];
    let mut e_sh = [0.0f32; 4];
    let mut f_pts = [Vec3A::ZERO; 4];
    let (mut ne, mut nf) = (0, 0);
    for d in 0..4 {
        if g.edge_exists(i, j, d) {
            dirs[ne] = d;
            e_pts[ne] = src.positions[src.at(i + DI[d], j + DJ[d])];
            e_sh[ne] = src.edge_sharp(i, j, d);
            ne += 1;
        }
    }
    let mut c_sh = [0.0f32; 4];
    let rules = VertexRules::new(g.method, 0.0, &e_sh[..ne], &mut c_sh[..ne]);
    // Only the smooth rule reads the face points (crease and corner rules do not).
    if rules.parent.is_smooth() || rules.child.is_smooth() {
        for d in 0..4 {
            let d2 = (d + 1) % 4;
            let (fi, fj) = (i + (DI[d] + DI[d2] - 1) / 2, j + (DJ[d] + DJ[d2] - 1) / 2);
            if g.face_exists(fi, fj) {
                f_pts[nf] = dst.positions[dst.at(2 * fi + 1, 2 * fj + 1)];
                nf += 1;
            }
        }
    }
    let v = src.positions[src.at(i, j)];
    let k = dst.at(2 * i, 2 * j);
    dst.positions[k] = catmark::vertex_point(v, &e_pts[..ne], &f_pts[..nf], &rules);
    dst.exists[k] = true;
    for (&d, &c) in dirs[..ne].iter().zip(&c_sh[..ne]) {
        dst.set_edge_sharp(2 * i, 2 * j, d, c);
    }
}

/// Edge point of the horizontal edge `(i,j)-(i+1,j)` (`dir` 0) or the vertical one
/// `(i,j)-(i,j+1)` (`dir` 1), if it has a dirty end and the general rules differ there.
#[inline]
fn general_edge_point(g: General<'_>, dst: &mut Table, dirty: &[bool], i: i32, j: i32, dir: usize) {
    let (src, n, method) = (g.src, g.src.grid_size as i32, g.method);
    let (bi, bj) = (i + DI[dir], j + DJ[dir]);
    // A missing end marks both ends dirty, so clean edges exist.
    if !(dirty[src.at(i, j)] || dirty[src.at(bi, bj)]) {
        return;
    }
    if !g.edge_exists(i, j, dir) {
        let k = dst.at(i + bi, j + bj);
        dst.exists[k] = false;
        return;
    }
    let s = src.edge_sharp(i, j, dir);
    // Faces on either side of the edge.
    let sides: [(i32, i32); 2] = if dir == 0 {
        [(i, j - 1), (i, j)]
    } else {
        [(i - 1, j), (i, j)]
    };
    if s == 0.0 && g.face_exists(sides[0].0, sides[0].1) && g.face_exists(sides[1].0, sides[1].1) {
        // A smooth edge between two faces: the regular pass computed it alike.
        return;
    }
    // Child sharpness at each end: from the vertex rules (inner ends) or the far info.
    let child_at = |vi: i32, vj: i32, toward: usize| -> f32 {
        if (0..=n).contains(&vi) && (0..=n).contains(&vj) {
            dst.edge_sharp(2 * vi, 2 * vj, toward)
        } else {
            // Far-end information only matters to the Chaikin rule.
            let far = if method == CreaseMethod::Chaikin {
                far_info(src, g.corners, vi, vj, (toward + 2) % 4)
            } else {
                (0.0, 0)
            };
            crease::child_edge_sharpness(method, s, far)
        }
    };
    let c0 = child_at(i, j, dir);
    let c1 = child_at(bi, bj, (dir + 2) % 4);
    let w = edge_crease_weight(s, [c0, c1]);
    let mut faces = [Vec3A::ZERO; 2];
    let mut nf = 0;
    // The crease rule (weight 1) is the midpoint: the faces are not read.
    for (fi, fj) in sides {
        if w != 1.0 && g.face_exists(fi, fj) {
            faces[nf] = dst.positions[dst.at(2 * fi + 1, 2 * fj + 1)];
            nf += 1;
        }
    }
    let e = catmark::edge_point(
        src.positions[src.at(i, j)],
        src.positions[src.at(bi, bj)],
        &faces[..nf],
        w,
    );
    let k = dst.at(i + bi, j + bj);
    dst.positions[k] = e;
    dst.exists[k] = true;
    if method == CreaseMethod::Chaikin {
        crossing_far(g, dst, s, i, j, dir);
    }
}

/// New far information (Chaikin rule) for an edge `(i,j)`-(direction `dir`) of sharpness `s`
/// that crosses out of the table: the child crossing edge's semi-sharpness at its outer end.
#[inline]
fn crossing_far(g: General<'_>, dst: &mut Table, s: f32, i: i32, j: i32, dir: usize) {
    let (src, n, method) = (g.src, g.src.grid_size as i32, g.method);
    let (bi, bj) = (i + DI[dir], j + DJ[dir]);
    let outer = |vi: i32, vj: i32| !((0..=n).contains(&vi) && (0..=n).contains(&vj));
    if !(outer(i, j) || outer(bi, bj)) {
        return;
    }
    let (oi, oj, toward) = if outer(i, j) {
        (i, j, dir)
    } else {
        (bi, bj, (dir + 2) % 4)
    };
    let cf = crease::child_edge_sharpness(method, s, far_info(src, g.corners, oi, oj, toward));
    let info = if is_semi_sharp(cf) { (cf, 1) } else { (0.0, 0) };
    let (side, pos) = if oj == -1 {
        (0, 2 * i)
    } else if oi == n + 1 {
        (1, 2 * j)
    } else if oj == n + 1 {
        (2, 2 * i)
    } else {
        (3, 2 * j)
    };
    if (0..=2 * n).contains(&pos) {
        dst.far_semi_sharp[side][pos as usize] = info;
    }
}
