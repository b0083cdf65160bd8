//! The Clough-Tocher split-triangle interpolant (Clough & Tocher 1965; Farin, CAGD, 5th ed.),
//! used by the haptic DoIs (Isenberg, Hartmann & König 2003, §4.2, Fig. 7): every triangle of the
//! mesh is split at its centroid into three sub-triangles, each carrying a cubic Bézier patch with
//! ten control points, built from the vertex positions and normals. The patches interpolate the
//! corners and are C¹ inside the macro triangle; across mesh edges they are only C⁰.

use glam::Vec3;
use subdiv_mesh::Mesh;

/// Index of control point `b_ijk` (`i + j + k = 3`) in [`CubicTriangle::b`].
#[inline]
pub const fn bezier_index(i: usize, j: usize, _k: usize) -> usize {
    let r = 3 - i;
    r * (r + 1) / 2 + (r - j)
}

/// A cubic Bézier triangle: ten control points `b_ijk`, `i + j + k = 3`, over barycentric
/// coordinates `(u, v, w)` of its three corners.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CubicTriangle {
    /// Control points, in the order of [`bezier_index`].
    pub b: [Vec3; 10],
}

impl CubicTriangle {
    /// Control point `b_ijk`.
    #[inline]
    pub fn at(&self, i: usize, j: usize, k: usize) -> Vec3 {
        self.b[bezier_index(i, j, k)]
    }

    /// The point at barycentric `(u, v, w)`.
    #[inline]
    pub fn eval(&self, u: f32, v: f32, w: f32) -> Vec3 {
        let mut p = Vec3::ZERO;
        for i in 0..=3usize {
            for j in 0..=(3 - i) {
                let k = 3 - i - j;
                let c = 6.0 / (fact(i) * fact(j) * fact(k));
                p +=
                    self.at(i, j, k) * (c * u.powi(i as i32) * v.powi(j as i32) * w.powi(k as i32));
            }
        }
        p
    }

    /// The derivative at `(u, v, w)` along the barycentric direction `d` (components summing
    /// to 0).
    #[inline]
    pub fn derivative(&self, d: [f32; 3], u: f32, v: f32, w: f32) -> Vec3 {
        let mut p = Vec3::ZERO;
        for i in 0..=2usize {
            for j in 0..=(2 - i) {
                let k = 2 - i - j;
                let c = 2.0 / (fact(i) * fact(j) * fact(k));
                let q = self.at(i + 1, j, k) * d[0]
                    + self.at(i, j + 1, k) * d[1]
                    + self.at(i, j, k + 1) * d[2];
                p += q * (c * u.powi(i as i32) * v.powi(j as i32) * w.powi(k as i32));
            }
        }
        p * 3.0
    }
}

#[inline]
fn fact(n: usize) -> f32 {
    [1.0, 1.0, 2.0, 6.0][n]
}

/// The Clough-Tocher interpolant of one triangle: sub-patch `k` has corners `P_k`, `P_{k+1}` and
/// the split point `C` (barycentric `u` on `P_k`, `v` on `P_{k+1}`, `w` on `C`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CloughTocher {
    /// The three cubic sub-patches.
    pub sub: [CubicTriangle; 3],
}

impl CloughTocher {
    /// Builds the interpolant of triangle `p` (counter-clockwise) with unit vertex normals `n`.
    ///
    /// Boundary control points: `T_ij = P_i + ((P_j − P_i) projected into the tangent plane at
    /// P_i) / 3`. Interior points: `I_i = (P_i + T_ij + T_ik) / 3` (C¹ at the vertices); the point
    /// beside each edge is chosen so that the derivative toward `C` across the edge midpoint
    /// varies linearly along the edge (the "reduced" Clough-Tocher choice, which reproduces
    /// planes); `S_i = (I_i + F_ij + F_ki) / 3` and `C = (S_0 + S_1 + S_2) / 3` make the three
    /// patches C¹ across the split lines, the split point being the centroid.
    ///
    /// ```
    /// use subdiv_doi::CloughTocher;
    /// use subdiv_mesh::glam::Vec3;
    /// let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
    /// let ct = CloughTocher::new(p, [Vec3::Z; 3]);
    /// assert!((ct.eval([0.0, 1.0, 0.0]) - Vec3::X).length() < 1e-6);
    /// // Flat data: the patch is the triangle itself.
    /// assert!((ct.eval([0.2, 0.3, 0.5]) - Vec3::new(0.3, 0.5, 0.0)).length() < 1e-6);
    /// ```
    pub fn new(p: [Vec3; 3], n: [Vec3; 3]) -> CloughTocher {
        let t = |i: usize, j: usize| -> Vec3 {
            let d = p[j] - p[i];
            p[i] + (d - n[i] * d.dot(n[i])) / 3.0
        };
        // t_fwd[i] = T_{i,i+1}, t_back[i] = T_{i,i-1}.
        let t_fwd = [t(0, 1), t(1, 2), t(2, 0)];
        let t_back = [t(0, 2), t(1, 0), t(2, 1)];
        let ii: [Vec3; 3] = std::array::from_fn(|i| (p[i] + t_fwd[i] + t_back[i]) / 3.0);
        // f[k]: beside edge k = (k, k+1).
        let f: [Vec3; 3] = std::array::from_fn(|k| {
            let kn = (k + 1) % 3;
            let (tij, tji) = (t_fwd[k], t_back[kn]);
            let c20 = ii[k] - 0.5 * p[k] - 0.5 * tij;
            let c02 = ii[kn] - 0.5 * tji - 0.5 * p[kn];
            0.5 * (tij + tji) + 0.5 * (c20 + c02)
        });
        let s: [Vec3; 3] = std::array::from_fn(|i| (ii[i] + f[i] + f[(i + 2) % 3]) / 3.0);
        let c = (s[0] + s[1] + s[2]) / 3.0;
        let sub = std::array::from_fn(|k| {
            let kn = (k + 1) % 3;
            let mut b = [Vec3::ZERO; 10];
            b[bezier_index(3, 0, 0)] = p[k];
            b[bezier_index(0, 3, 0)] = p[kn];
            b[bezier_index(0, 0, 3)] = c;
            b[bezier_index(2, 1, 0)] = t_fwd[k];
            b[bezier_index(1, 2, 0)] = t_back[kn];
            b[bezier_index(2, 0, 1)] = ii[k];
            b[bezier_index(0, 2, 1)] = ii[kn];
            b[bezier_index(1, 1, 1)] = f[k];
            b[bezier_index(1, 0, 2)] = s[k];
            b[bezier_index(0, 1, 2)] = s[kn];
            CubicTriangle { b }
        });
        CloughTocher { sub }
    }

    /// The sub-patch containing macro barycentric `l` and its coordinates there.
    #[inline]
    pub fn locate(l: [f32; 3]) -> (usize, [f32; 3]) {
        // Sub-triangle k is where l[k+2] is the smallest coordinate.
        let k = if l[2] <= l[0] && l[2] <= l[1] {
            0
        } else if l[0] <= l[1] {
            1
        } else {
            2
        };
        let (a, b, c) = (l[k], l[(k + 1) % 3], l[(k + 2) % 3]);
        (k, [a - c, b - c, 3.0 * c])
    }

    /// Maps a macro barycentric direction `d` to the coordinates of sub-patch `k`.
    #[inline]
    pub fn sub_direction(k: usize, d: [f32; 3]) -> [f32; 3] {
        let (a, b, c) = (d[k], d[(k + 1) % 3], d[(k + 2) % 3]);
        [a - c, b - c, 3.0 * c]
    }

    /// The surface point at macro barycentric `l` (coordinates of the triangle's corners).
    pub fn eval(&self, l: [f32; 3]) -> Vec3 {
        let (k, [u, v, w]) = Self::locate(l);
        self.sub[k].eval(u, v, w)
    }
}

/// The Clough-Tocher interpolant of every face of a triangle mesh, with `normals` per vertex.
pub fn clough_tocher_patches(mesh: &Mesh, normals: &[Vec3]) -> Vec<CloughTocher> {
    mesh.faces()
        .map(|f| {
            let v = mesh.face_vertices(f);
            let p = [0, 1, 2].map(|k| mesh.position(v[k]));
            let n = [0, 1, 2].map(|k| normals[v[k].idx()]);
            CloughTocher::new(p, n)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_ct() -> CloughTocher {
        let p = [
            Vec3::new(0.0, 0.0, 0.1),
            Vec3::new(1.0, 0.1, 0.0),
            Vec3::new(0.2, 0.9, 0.3),
        ];
        let n = [
            Vec3::new(0.1, -0.2, 1.0),
            Vec3::new(0.4, 0.1, 1.0),
            Vec3::new(-0.2, 0.3, 1.0),
        ]
        .map(|x| x.normalize());
        CloughTocher::new(p, n)
    }

    #[test]
    fn bezier_indices_are_a_bijection() {
        let mut seen = [false; 10];
        for i in 0..=3 {
            for j in 0..=3 - i {
                let x = bezier_index(i, j, 3 - i - j);
                assert!(!seen[x]);
                seen[x] = true;
            }
        }
        assert!(seen.iter().all(|&s| s));
    }

    #[test]
    fn interpolates_corners_and_tangent_planes() {
        let p = [
            Vec3::new(0.0, 0.0, 0.1),
            Vec3::new(1.0, 0.1, 0.0),
            Vec3::new(0.2, 0.9, 0.3),
        ];
        let n = [
            Vec3::new(0.1, -0.2, 1.0),
            Vec3::new(0.4, 0.1, 1.0),
            Vec3::new(-0.2, 0.3, 1.0),
        ]
        .map(|x| x.normalize());
        let ct = CloughTocher::new(p, n);
        for k in 0..3 {
            let mut l = [0.0; 3];
            l[k] = 1.0;
            assert!((ct.eval(l) - p[k]).length() < 1e-6, "corner {k}");
            // Both derivatives at the corner lie in the tangent plane given by the normal.
            let (s, [u, v, w]) = CloughTocher::locate(l);
            for d in [[1.0, -1.0, 0.0], [1.0, 0.0, -1.0]] {
                let dd = ct.sub[s].derivative(CloughTocher::sub_direction(s, d), u, v, w);
                assert!(
                    dd.dot(n[k]).abs() < 1e-5 * dd.length().max(1.0),
                    "corner {k}: {dd}"
                );
            }
        }
    }

    #[test]
    fn c1_across_the_split_lines() {
        let ct = sample_ct();
        let c = [1.0 / 3.0; 3];
        let dirs = [[1.0f32, -1.0, 0.0], [0.0, 1.0, -1.0], [-1.0, 0.0, 1.0]];
        for k in 0..3 {
            // Points on the split line from corner k to the centre, shared by sub-patches k and
            // k - 1 (= k + 2).
            let km = (k + 2) % 3;
            for s in [0.1f32, 0.35, 0.6, 0.9] {
                let mut l = [0.0f32; 3];
                for i in 0..3 {
                    l[i] = (1.0 - s) * if i == k { 1.0 } else { 0.0 } + s * c[i];
                }
                let coords = |sub: usize| {
                    let (a, b, cc) = (l[sub], l[(sub + 1) % 3], l[(sub + 2) % 3]);
                    [a - cc, b - cc, 3.0 * cc]
                };
                let (ua, ub) = (coords(k), coords(km));
                let pa = ct.sub[k].eval(ua[0], ua[1], ua[2]);
                let pb = ct.sub[km].eval(ub[0], ub[1], ub[2]);
                assert!((pa - pb).length() < 1e-6, "C0 on split line {k} at {s}");
                for d in dirs {
                    let da = ct.sub[k].derivative(
                        CloughTocher::sub_direction(k, d),
                        ua[0],
                        ua[1],
                        ua[2],
                    );
                    let db = ct.sub[km].derivative(
                        CloughTocher::sub_direction(km, d),
                        ub[0],
                        ub[1],
                        ub[2],
                    );
                    assert!(
                        (da - db).length() < 1e-5,
                        "C1 on split line {k} at {s}, dir {d:?}: {da} vs {db}"
                    );
                }
            }
        }
        // A non-C1 net is detected by the same check: move one interior point.
        let mut bad = ct;
        bad.sub[0].b[bezier_index(1, 1, 1)] += Vec3::Z * 0.1;
        let l = [0.5f32, 0.25, 0.25];
        let ua = [l[0] - l[2], l[1] - l[2], 3.0 * l[2]];
        let ub = [l[2] - l[1], l[0] - l[1], 3.0 * l[1]];
        let d = [0.0f32, 1.0, -1.0];
        let da = bad.sub[0].derivative(CloughTocher::sub_direction(0, d), ua[0], ua[1], ua[2]);
        let db = bad.sub[2].derivative(CloughTocher::sub_direction(2, d), ub[0], ub[1], ub[2]);
        assert!((da - db).length() > 1e-3);
    }
}
