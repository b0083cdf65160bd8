//! Index-buffer emission: plain quads (two triangles each) and, next to a deeper neighbour,
//! triangle fans around the limit point of the quad's next-level face point.

use rayon::prelude::*;
use subdiv_slate::PatchRef;

use super::edges::Frame;
use super::grid::side_of_on;

/// How the quads next to a deeper neighbour are closed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FanMethod {
    /// Fans, plus the subdivided edge between two replaced quads of a patch (the paper's method).
    #[default]
    Subdivided,
    /// Fans only (the paper's "simple method", which shows buckles).
    Simple,
}

impl Frame<'_> {
    /// The frame's index buffer: each active, non-hole patch's triangles, emitted in parallel,
    /// then concatenated in patch order into `out` (cleared first).
    pub(super) fn emit_frame(&self, active: &[bool], method: FanMethod, out: &mut Vec<u32>) {
        let tris: Vec<Vec<u32>> = self
            .set
            .patches()
            .par_iter()
            .map(|p| {
                let mut v = Vec::new();
                if active[p.unit as usize]
                    && !self.mesh.is_hole(self.set.units()[p.unit as usize].face)
                {
                    self.emit_patch(p, method, &mut v);
                }
                v
            })
            .collect();
        out.clear();
        for t in tris {
            out.extend_from_slice(&t);
        }
    }

    /// The triangles of one patch.
    fn emit_patch(&self, p: &PatchRef, method: FanMethod, out: &mut Vec<u32>) {
        let pi = self.patch_index(p.unit as usize, p.sub as usize);
        let d = self.patch_depth(p);
        let n = 1u32 << d;
        let fans = self.fans(p);
        let replaced = |i: u32, j: u32| -> bool {
            (fans[0] && j == 0)
                || (fans[1] && i == n - 1)
                || (fans[2] && j == n - 1)
                || (fans[3] && i == 0)
        };
        let any = fans.iter().any(|&x| x);
        let id = |i: u32, j: u32| self.point_id(pi, p, i, j);
        let mut poly: Vec<u32> = Vec::with_capacity(16);
        for j in 0..n {
            for i in 0..n {
                if !(any && replaced(i, j)) {
                    let (a, b, c, e) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                    out.extend_from_slice(&[a, b, c, a, c, e]);
                    continue;
                }
                // Fan around the limit point of the quad's next-level face point.
                let centre = self.own(pi, 2 * i + 1, 2 * j + 1, d + 1);
                poly.clear();
                // The quad's four edges, counter-clockwise: bottom, right, top, left; each from
                // its start corner (inclusive) to its end corner (exclusive).
                let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
                for (ek, &(ci, cj)) in corners.iter().enumerate() {
                    poly.push(id(ci, cj));
                    let (ni, nj) = corners[(ek + 1) % 4];
                    // Is this edge on a fanned side of the patch?
                    let on_side = match ek {
                        0 if j == 0 => Some(0),
                        1 if i + 1 == n => Some(1),
                        2 if j + 1 == n => Some(2),
                        3 if i == 0 => Some(3),
                        _ => None,
                    };
                    if let Some(k) = on_side.filter(|&k| fans[k]) {
                        self.push_fine_points(p, pi, k, (ci, cj), (ni, nj), n, &mut poly);
                    } else if on_side.is_none() && method == FanMethod::Subdivided {
                        // Inner edge: subdivide it if the quad across is replaced too.
                        let (oi, oj) = match ek {
                            0 => (i, j.wrapping_sub(1)),
                            1 => (i + 1, j),
                            2 => (i, j + 1),
                            _ => (i.wrapping_sub(1), j),
                        };
                        if oi < n && oj < n && replaced(oi, oj) {
                            poly.push(self.own(pi, ci + ni, cj + nj, d + 1));
                        }
                    }
                }
                for k in 0..poly.len() {
                    out.extend_from_slice(&[centre, poly[k], poly[(k + 1) % poly.len()]]);
                }
            }
        }
    }

    /// The deeper neighbour's points strictly between two corners of a border quad on side `k`.
    #[allow(clippy::too_many_arguments)]
    fn push_fine_points(
        &self,
        p: &PatchRef,
        pi: usize,
        k: usize,
        a: (u32, u32),
        b: (u32, u32),
        n: u32,
        poly: &mut Vec<u32>,
    ) {
        let _ = pi;
        let u = p.unit as usize;
        let hs = &self.units[u].hs;
        let d = self.patch_depth(p);
        let (_, sa) = side_of_on(k, a.0, a.1, n);
        let (_, sb) = side_of_on(k, b.0, b.1, n);
        // Cage half-edge and the parameter range (at unit resolution) the side covers.
        let (h, ud, offset) = if p.level == 0 {
            (hs[k], d, 0)
        } else {
            let nsub = hs.len();
            let sub = p.sub as usize;
            match k {
                0 => (hs[sub], d + 1, 0),
                _ => (hs[(sub + nsub - 1) % nsub], d + 1, n),
            }
        };
        let r = self.edge_res[h.edge().idx()] as u32;
        let delta = r - ud;
        let (t0, t1) = ((offset + sa) << delta, (offset + sb) << delta);
        if t1 > t0 {
            for t in t0 + 1..t1 {
                poly.push(self.edge_point_id(h, t, r));
            }
        } else {
            for t in (t1 + 1..t0).rev() {
                poly.push(self.edge_point_id(h, t, r));
            }
        }
    }
}
