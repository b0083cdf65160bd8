//! DoIs for haptic rendering (Isenberg, Hartmann & König 2003, §4.2).
//!
//! - [`CloughTocher`]: the Clough-Tocher split-triangle interpolant (Clough & Tocher 1965; Farin,
//!   CAGD, 5th ed.): every triangle of the mesh is split at its centroid into three sub-triangles,
//!   each carrying a cubic Bézier patch with ten control points (Fig. 7), built from the vertex
//!   positions and normals. The patches interpolate the corners and are C¹ inside the macro
//!   triangle; across mesh edges they are only C⁰.
//! - [`HapticG1`]: the G¹ error of eqs. (4)–(6) between the patches on either side of each edge.
//! - [`HapticPoint`]: the binary haptic-interaction-point DoI (the triangle closest to the HIP
//!   and its one-neighbourhood).

use glam::Vec3;
use subdiv_mesh::{EdgeId, FaceId, Mesh, closest_point_on_triangle, vertex_normals};

use crate::DoiError;
use crate::framework::{Doi, DoiContext, Domain};

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

/// The barycentric combination of eq. (5): `x ≈ v1 q1 + v2 q2 + v3 q3` with `v1 + v2 + v3 = 1`,
/// solved in the least-squares sense (`x` projected onto the plane of the `q`s); `None` when the
/// `q`s are collinear.
#[inline]
pub fn barycentric_combination(x: Vec3, q1: Vec3, q2: Vec3, q3: Vec3) -> Option<[f32; 3]> {
    let (e1, e3, r) = (q1 - q2, q3 - q2, x - q2);
    let (a, b, c) = (e1.dot(e1), e1.dot(e3), e3.dot(e3));
    let det = a * c - b * b;
    if det <= 1e-10 * a * c || det <= f32::MIN_POSITIVE {
        return None;
    }
    let (r1, r3) = (e1.dot(r), e3.dot(r));
    let v1 = (c * r1 - b * r3) / det;
    let v3 = (a * r3 - b * r1) / det;
    Some([v1, 1.0 - v1 - v3, v3])
}

/// The G¹ error of eq. (6) across the edge shared by the macro triangles `ct_f` (where the edge
/// runs `a → b` from corner `ka` to `ka + 1`) and `ct_g` (where it runs `b → a` from corner
/// `kb`).
///
/// With `b` the sub-patch of `ct_f` on the edge and `b̂` the one of `ct_g`, eq. (5) writes each
/// first-row point `b̂_(1,j,k)`, `j + k = 2`, as a barycentric combination `v` of the sub-triangle
/// `b_(1,j,k), b_(0,j+1,k), b_(0,j,k+1)` of `b`'s net; for G¹ all three combinations agree. Eq. (6):
/// `Σ_i | |v_i¹| − |v_i²| | + | |v_i¹| − |v_i³| |` over the components `i`. Combinations that
/// cannot be formed (degenerate control nets) count as agreeing.
pub fn g1_error(ct_f: &CloughTocher, ka: usize, ct_g: &CloughTocher, kb: usize) -> f32 {
    let b = &ct_f.sub[ka];
    let bh = &ct_g.sub[kb];
    let mut v = [[0.0f32; 3]; 3];
    for (n, (j, k)) in [(2usize, 0usize), (1, 1), (0, 2)].into_iter().enumerate() {
        // In b: i on a, j on b, k on C. In b̂: i on b, j on a.
        let x = bh.at(k, j, 1);
        let q1 = b.at(j, k, 1);
        let q2 = b.at(j + 1, k, 0);
        let q3 = b.at(j, k + 1, 0);
        match barycentric_combination(x, q1, q2, q3) {
            Some(c) => v[n] = c,
            None => return 0.0,
        }
    }
    let [v1, v2, v3] = v;
    (0..3)
        .map(|i| (v1[i].abs() - v2[i].abs()).abs() + (v1[i].abs() - v3[i].abs()).abs())
        .sum()
}

/// The haptic DoI of eqs. (4)–(6): per edge, the G¹ error between the Clough-Tocher patches on
/// either side (0 on boundary edges). Static. Vertex normals are area-weighted face normals.
///
/// The paper gives no threshold for its Fig. 9; the default, 0.5, refines where the three
/// combinations of eq. (5) differ by more than about a sixth in each component.
///
/// ```
/// use subdiv_doi::{Doi, DoiContext, HapticG1};
/// use subdiv_mesh::{parse_obj, Mesh};
/// // Flat: the patches are the plane itself, so they join with no error.
/// let flat = Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4\nf 1 4 3\n")?)?;
/// let mut v = Vec::new();
/// HapticG1.evaluate(&flat, &DoiContext::default(), &mut v)?;
/// assert!(v.iter().all(|&e| e.abs() < 1e-5));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HapticG1;

impl Doi for HapticG1 {
    fn name(&self) -> &'static str {
        "haptic"
    }
    fn domain(&self) -> Domain {
        Domain::Edges
    }
    fn is_view_dependent(&self) -> bool {
        false
    }
    fn default_threshold(&self) -> f32 {
        0.5
    }
    fn evaluate(&self, mesh: &Mesh, _ctx: &DoiContext, out: &mut Vec<f32>) -> Result<(), DoiError> {
        mesh.check_triangles()?;
        let normals = vertex_normals(mesh);
        let ct = clough_tocher_patches(mesh, &normals);
        out.clear();
        out.extend(mesh.edges().map(|e| edge_g1_error(mesh, &ct, e)));
        Ok(())
    }
}

/// [`g1_error`] of edge `e` of a triangle mesh with per-face interpolants `ct`.
pub fn edge_g1_error(mesh: &Mesh, ct: &[CloughTocher], e: EdgeId) -> f32 {
    let h = e.halfedge(0);
    let (f, g) = (mesh.face(h), mesh.face(h.twin()));
    if !f.is_some() || !g.is_some() {
        return 0.0;
    }
    let corner = |face: FaceId, v| {
        mesh.face_vertices(face)
            .iter()
            .position(|&x| x == v)
            .unwrap_or(0)
    };
    let ka = corner(f, mesh.from(h));
    let kb = corner(g, mesh.to(h));
    g1_error(&ct[f.idx()], ka, &ct[g.idx()], kb)
}

/// The binary haptic-interaction-point DoI (§4.2): 1 for the triangle closest to the HIP
/// (`DoiContext::hip`) and every triangle sharing a vertex with it, 0 elsewhere. Changes with
/// the HIP, so it is re-evaluated per frame. Default threshold 0.5.
///
/// ```
/// use subdiv_doi::{Doi, DoiContext, HapticPoint};
/// use subdiv_mesh::{parse_obj, Mesh, glam::Vec3};
/// let strip = Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 2 0 0\nv 2 1 0\nv 3 0 0\nv 3 1 0\n\
///     f 1 2 4\nf 1 4 3\nf 2 5 6\nf 2 6 4\nf 5 7 8\nf 5 8 6\n")?)?;
/// let ctx = DoiContext { hip: Some(Vec3::new(0.1, 0.9, 0.2)), ..Default::default() };
/// let mut v = Vec::new();
/// HapticPoint.evaluate(&strip, &ctx, &mut v)?;
/// assert_eq!(v, vec![1.0, 1.0, 0.0, 1.0, 0.0, 0.0]); // faces sharing a vertex with face 1
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HapticPoint;

impl Doi for HapticPoint {
    fn name(&self) -> &'static str {
        "haptic-point"
    }
    fn domain(&self) -> Domain {
        Domain::Faces
    }
    fn is_view_dependent(&self) -> bool {
        true
    }
    fn default_threshold(&self) -> f32 {
        0.5
    }
    fn evaluate(&self, mesh: &Mesh, ctx: &DoiContext, out: &mut Vec<f32>) -> Result<(), DoiError> {
        let hip = ctx.hip.ok_or(DoiError::NeedsHip { doi: self.name() })?;
        if !hip.is_finite() {
            return Err(DoiError::NonFinite {
                what: "haptic interaction point",
                value: hip.x + hip.y + hip.z,
            });
        }
        out.clear();
        out.resize(mesh.num_faces(), 0.0);
        let Some(closest) = closest_face(mesh, hip) else {
            return Ok(());
        };
        let mut mark = vec![false; mesh.num_vertices()];
        for &v in mesh.face_vertices(closest) {
            mark[v.idx()] = true;
        }
        for f in mesh.faces() {
            if mesh.face_vertices(f).iter().any(|v| mark[v.idx()]) {
                out[f.idx()] = 1.0;
            }
        }
        Ok(())
    }
}

/// The face of a triangle mesh closest to `p` (ties: lowest index), `None` without faces.
pub fn closest_face(mesh: &Mesh, p: Vec3) -> Option<FaceId> {
    let mut best = (f32::INFINITY, None);
    for f in mesh.faces() {
        let v = mesh.face_vertices(f);
        let d = closest_point_on_triangle(
            p,
            mesh.position(v[0]),
            mesh.position(v[1]),
            mesh.position(v[2]),
        )
        .distance_squared(p);
        if d < best.0 {
            best = (d, Some(f));
        }
    }
    best.1
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

    #[test]
    fn g1_error_zero_when_flat_positive_on_a_fold() {
        use subdiv_mesh::PolygonSoup;
        let flat = Mesh::from_soup(&PolygonSoup::from_faces(
            vec![
                Vec3::ZERO,
                Vec3::X,
                Vec3::new(0.1, 1.2, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
            ],
            &[[0u32, 1, 3], [0, 3, 2]],
        ))
        .unwrap();
        let mut v = Vec::new();
        HapticG1
            .evaluate(&flat, &DoiContext::default(), &mut v)
            .unwrap();
        assert!(v.iter().all(|&e| e.abs() < 1e-5), "{v:?}");
        // A flat but tilted pair too.
        let tilted = Mesh::from_soup(&PolygonSoup::from_faces(
            vec![
                Vec3::ZERO,
                Vec3::new(1.0, 0.0, 0.5),
                Vec3::new(0.1, 1.2, 0.3),
                Vec3::new(1.0, 1.0, 0.75),
            ],
            &[[0u32, 1, 3], [0, 3, 2]],
        ))
        .unwrap();
        HapticG1
            .evaluate(&tilted, &DoiContext::default(), &mut v)
            .unwrap();
        assert!(v.iter().all(|&e| e.abs() < 1e-5), "{v:?}");
        // A bumpy grid: where the normals at an edge's two ends differ, the patches do not
        // join G1.
        let n = 4u32;
        let mut p = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let (x, y) = (i as f32, j as f32);
                p.push(Vec3::new(
                    x,
                    y,
                    0.3 * (1.7 * x).sin() * (1.1 * y + 0.4).cos(),
                ));
            }
        }
        let id = |i: u32, j: u32| j * (n + 1) + i;
        let mut f = Vec::new();
        for j in 0..n {
            for i in 0..n {
                f.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                f.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let m = Mesh::from_soup(&PolygonSoup::from_faces(p, &f)).unwrap();
        HapticG1
            .evaluate(&m, &DoiContext::default(), &mut v)
            .unwrap();
        let max = v.iter().fold(0.0f32, |a, &b| a.max(b));
        assert!(max > 0.05, "{v:?}");
        assert!(v.iter().all(|&e| e >= 0.0 && e.is_finite()));
        for e in m.edges().filter(|&e| m.is_boundary_edge(e)) {
            assert_eq!(v[e.idx()], 0.0);
        }
        // Eq. (5) on an exact combination.
        let q = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let c = barycentric_combination(q[0] * 0.2 + q[1] * 0.5 + q[2] * 0.3, q[0], q[1], q[2])
            .unwrap();
        assert!(
            (c[0] - 0.2).abs() < 1e-6 && (c[1] - 0.5).abs() < 1e-6 && (c[2] - 0.3).abs() < 1e-6
        );
        assert!(barycentric_combination(Vec3::Z, Vec3::ZERO, Vec3::X, Vec3::X * 2.0).is_none());
    }

    #[test]
    fn closest_points() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        assert!(
            (closest_point_on_triangle(Vec3::new(0.2, 0.2, 5.0), a, b, c)
                - Vec3::new(0.2, 0.2, 0.0))
            .length()
                < 1e-6
        );
        assert_eq!(
            closest_point_on_triangle(Vec3::new(-1.0, -1.0, 0.0), a, b, c),
            a
        );
        assert_eq!(
            closest_point_on_triangle(Vec3::new(2.0, -0.5, 0.0), a, b, c),
            b
        );
        assert!(
            (closest_point_on_triangle(Vec3::new(1.0, 1.0, 0.0), a, b, c)
                - Vec3::new(0.5, 0.5, 0.0))
            .length()
                < 1e-6
        );
        let e = HapticPoint
            .evaluate(
                &Mesh::from_soup(&subdiv_mesh::PolygonSoup::from_faces(
                    vec![a, b, c],
                    &[[0u32, 1, 2]],
                ))
                .unwrap(),
                &DoiContext::default(),
                &mut Vec::new(),
            )
            .unwrap_err();
        assert!(e.to_string().contains("needs a haptic interaction point"));
    }
}
