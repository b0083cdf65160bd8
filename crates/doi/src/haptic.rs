//! DoIs for haptic rendering (Isenberg, Hartmann & König 2003, §4.2).
//!
//! The surface is interpolated by Clough-Tocher patches ([`CloughTocher`], Fig. 7). The paper
//! asks two things of them: (1) the patches of neighbouring triangles join at least G¹, tested by
//! eq. (5) and scored by eq. (6); (2) "the patch for a triangle is entirely on one side of the
//! triangle". Triangles failing either are subdivided.
//!
//! - [`HapticG1`]: per edge, the G¹ error of eqs. (4)–(6), with eq. (5) solved exactly and its
//!   out-of-plane residual counted ([`g1_error`]).
//! - [`Haptic`]: the DoI of §4.2, per face, both criteria against a tolerance derived from the
//!   mesh's mean edge length ([`plane_crossing`] for the second).
//! - [`HapticPoint`]: the binary haptic-interaction-point DoI (the triangle closest to the HIP,
//!   snapped to the surface, and its one-neighbourhood).

use glam::Vec3;
use subdiv_mesh::{EdgeId, FaceId, Mesh, closest_point_on_triangle, vertex_normals};

use crate::clough_tocher::{CloughTocher, clough_tocher_patches};
use crate::framework::{Aggregate, Doi, DoiContext, Domain};
use crate::{DoiError, DoiKind};

/// The solution of eq. (5) for one first-row control point: `x = v1 q1 + v2 q2 + v3 q3 + r`
/// with `v1 + v2 + v3 = 1` and `r` perpendicular to the plane of the `q`s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Combination {
    /// The barycentric coordinates `v` (exact when `x` lies in the plane of the `q`s).
    pub v: [f32; 3],
    /// `|r|` divided by the longest edge of the sub-triangle `q1 q2 q3`: 0 exactly when `x` is
    /// a barycentric combination of the `q`s, as eq. (5) requires.
    pub off_plane: f32,
}

/// Eq. (5): writes `x` as a barycentric combination of `q1, q2, q3`. The in-plane part is solved
/// exactly (the unique `v` whose combination is the foot of `x` on the plane); where `x` is off
/// the plane no combination exists, and the distance, relative to the sub-triangle's longest
/// edge, is returned with it. `None` when the `q`s are (nearly) collinear: a degenerate net.
///
/// ```
/// use subdiv_doi::barycentric_combination;
/// use subdiv_mesh::glam::Vec3;
/// let c = barycentric_combination(Vec3::new(0.5, 0.3, 0.0), Vec3::ZERO, Vec3::X, Vec3::Y).unwrap();
/// assert!((c.v[0] - 0.2).abs() < 1e-6 && (c.v[1] - 0.5).abs() < 1e-6 && c.off_plane == 0.0);
/// let c = barycentric_combination(Vec3::new(0.5, 0.3, 0.1), Vec3::ZERO, Vec3::X, Vec3::Y).unwrap();
/// assert!((c.off_plane - 0.1 / 2f32.sqrt()).abs() < 1e-6); // not coplanar: no combination
/// ```
#[inline]
pub fn barycentric_combination(x: Vec3, q1: Vec3, q2: Vec3, q3: Vec3) -> Option<Combination> {
    let (e1, e3, r) = (q1 - q2, q3 - q2, x - q2);
    let (a, b, c) = (e1.dot(e1), e1.dot(e3), e3.dot(e3));
    let det = a * c - b * b;
    if det <= 1e-10 * a * c || det <= f32::MIN_POSITIVE {
        return None;
    }
    let (r1, r3) = (e1.dot(r), e3.dot(r));
    let v1 = (c * r1 - b * r3) / det;
    let v3 = (a * r3 - b * r1) / det;
    let n = e1.cross(e3).normalize();
    let longest = a.max(c).max((q1 - q3).length_squared()).sqrt();
    Some(Combination {
        v: [v1, 1.0 - v1 - v3, v3],
        off_plane: r.dot(n).abs() / longest,
    })
}

/// The G¹ error given to an edge whose control net is degenerate (a sub-triangle of eq. (5)
/// with collinear points): G¹ cannot be verified there, so the edge counts as failing any
/// sensible tolerance (the error of agreeing nets is 0, of visibly kinked ones about 0.1 to 2).
pub const DEGENERATE_G1_ERROR: f32 = 100.0;

/// The G¹ error across the edge shared by the macro triangles `ct_f` (where the edge runs
/// `a → b` from corner `ka` to `ka + 1`) and `ct_g` (where it runs `b → a` from corner `kb`).
///
/// With `b` the sub-patch of `ct_f` on the edge and `b̂` the one of `ct_g`, eq. (5) writes each
/// first-row point `b̂_(1,j,k)`, `j + k = 2`, as a barycentric combination `v` of the sub-triangle
/// `b_(1,j,k), b_(0,j+1,k), b_(0,j,k+1)` of `b`'s net; for G¹ each point lies in the plane of its
/// sub-triangle and all three combinations agree. The error is eq. (6),
/// `Σ_i | |v_i¹| − |v_i²| | + | |v_i¹| − |v_i³| |`, plus the three out-of-plane residuals
/// ([`Combination::off_plane`]), so a net that is not coplanar never counts as agreeing. A
/// degenerate net gives [`DEGENERATE_G1_ERROR`].
pub fn g1_error(ct_f: &CloughTocher, ka: usize, ct_g: &CloughTocher, kb: usize) -> f32 {
    let b = &ct_f.sub[ka];
    let bh = &ct_g.sub[kb];
    let mut v = [[0.0f32; 3]; 3];
    let mut off = 0.0f32;
    for (n, (j, k)) in [(2usize, 0usize), (1, 1), (0, 2)].into_iter().enumerate() {
        // In b: i on a, j on b, k on C. In b̂: i on b, j on a.
        let x = bh.at(k, j, 1);
        let q1 = b.at(j, k, 1);
        let q2 = b.at(j + 1, k, 0);
        let q3 = b.at(j, k + 1, 0);
        match barycentric_combination(x, q1, q2, q3) {
            Some(c) => {
                v[n] = c.v;
                off += c.off_plane;
            }
            None => return DEGENERATE_G1_ERROR,
        }
    }
    let [v1, v2, v3] = v;
    let eq6: f32 = (0..3)
        .map(|i| (v1[i].abs() - v2[i].abs()).abs() + (v1[i].abs() - v3[i].abs()).abs())
        .sum();
    (eq6 + off).min(DEGENERATE_G1_ERROR)
}

/// How far the Clough-Tocher patch `ct` of triangle `p` crosses the triangle's plane: with `d`
/// the signed distances of its control points from the plane, `min(max d, max −d)` (a length).
/// 0 means the whole patch lies on one side (the patch is in the convex hull of its control
/// points), as the paper's second criterion asks; a positive value is the smaller of the two
/// excursions, so a patch only touching the plane from the other side scores little. A
/// zero-area triangle has no plane and scores 0.
///
/// ```
/// use subdiv_doi::{plane_crossing, CloughTocher};
/// use subdiv_mesh::glam::Vec3;
/// let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
/// // Normals tilted like a dome: the patch bulges to one side only.
/// let dome = [Vec3::new(-1.0, -1.0, 3.0), Vec3::new(1.0, 0.0, 3.0), Vec3::new(0.0, 1.0, 3.0)].map(|n| n.normalize());
/// assert_eq!(plane_crossing(&CloughTocher::new(p, dome), p), 0.0);
/// ```
pub fn plane_crossing(ct: &CloughTocher, p: [Vec3; 3]) -> f32 {
    let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
    let (mut hi, mut lo) = (0.0f32, 0.0f32);
    for sub in &ct.sub {
        for b in sub.b {
            let d = (b - p[0]).dot(n);
            hi = hi.max(d);
            lo = lo.min(d);
        }
    }
    hi.min(-lo)
}

/// The mean edge length of a mesh (0 without edges).
pub fn mean_edge_length(mesh: &Mesh) -> f32 {
    let n = mesh.num_edges();
    if n == 0 {
        return 0.0;
    }
    let sum: f64 = mesh
        .edges()
        .map(|e| {
            let [a, b] = mesh.edge_vertices(e);
            mesh.position(a).distance(mesh.position(b)) as f64
        })
        .sum();
    (sum / n as f64) as f32
}

/// The G¹ error of eqs. (4)–(6) per edge ([`g1_error`]; 0 on boundary edges). Static. Vertex
/// normals are area-weighted face normals. One term of [`Haptic`]; on its own, threshold 0.6
/// (the G¹ part of [`Haptic`] at the default tolerance).
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
        "haptic-g1"
    }
    fn domain(&self) -> Domain {
        Domain::Edges
    }
    fn is_view_dependent(&self) -> bool {
        false
    }
    fn default_threshold(&self) -> f32 {
        Haptic::G1_PER_TOLERANCE * Haptic::DEFAULT_TOLERANCE
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

/// The haptic DoI of §4.2: per face, both of the paper's criteria, each divided by its
/// tolerance, combined by the larger ("the DoI has to incorporate two aspects": a triangle is
/// subdivided when either fails). Threshold 1.
///
/// The tolerance is a length, `tolerance` (relative) times the cage's mean edge length `L`:
/// - one side: [`plane_crossing`] of the face's patch divided by `tolerance · L`;
/// - G¹: the [`g1_error`]s of the face's edges, combined with the aggregation (eq. (6) gives
///   a value per edge; the largest by default, as for every edge DoI, or their mean or
///   smallest: [`Doi::evaluate_faces`]), divided by `12 · tolerance`. Why 12: the
///   error is in units of the control net's spacing `s ≈ L/3`; moving one first-row point by `δ`
///   changes its combination by about `δ/s` in two components, each entering eq. (6) twice, so
///   an error `e` is a misplacement of about `e·s/4 = e·L/12`, and a misplacement of
///   `tolerance · L` is an error of `12 · tolerance`.
///
/// Static (the cage's `L` is fixed when the DoI is made, so refinement converges).
///
/// ```
/// use subdiv_doi::{Doi, DoiContext, Haptic};
/// use subdiv_mesh::{parse_obj, Mesh};
/// let flat = Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4\nf 1 4 3\n")?)?;
/// let h = Haptic::for_mesh(&flat, Haptic::DEFAULT_TOLERANCE);
/// let mut v = Vec::new();
/// h.evaluate(&flat, &DoiContext::default(), &mut v)?;
/// assert!(v.iter().all(|&x| x < 1e-3)); // flat: nothing to refine
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Haptic {
    /// The tolerance in units of the mean edge length.
    pub tolerance: f32,
    /// The tolerance as a length.
    pub length: f32,
}

impl Haptic {
    /// Default tolerance: 5 % of the mean edge length.
    pub const DEFAULT_TOLERANCE: f32 = 0.05;
    /// G¹ error per unit of relative tolerance (see the type's documentation).
    pub const G1_PER_TOLERANCE: f32 = 12.0;

    /// The DoI for `mesh` with `tolerance` in units of its mean edge length.
    pub fn for_mesh(mesh: &Mesh, tolerance: f32) -> Haptic {
        Haptic {
            tolerance,
            length: (tolerance * mean_edge_length(mesh)).max(f32::MIN_POSITIVE),
        }
    }

    /// The two terms of face `f` (G¹ and one-side, each divided by its tolerance); the G¹
    /// errors of its three edges (eq. (6) is a value per edge) are combined with `agg`.
    pub fn terms(&self, mesh: &Mesh, ct: &[CloughTocher], f: FaceId, agg: Aggregate) -> [f32; 2] {
        let h0 = mesh.face_halfedge(f);
        let g1 =
            agg.of([h0, mesh.next(h0), mesh.prev(h0)].map(|h| edge_g1_error(mesh, ct, h.edge())));
        let v = mesh.face_vertices(f);
        let p = [0, 1, 2].map(|k| mesh.position(v[k]));
        let side = plane_crossing(&ct[f.idx()], p);
        [
            g1 / (Self::G1_PER_TOLERANCE * self.tolerance),
            side / self.length,
        ]
    }
}

impl Doi for Haptic {
    fn name(&self) -> &'static str {
        DoiKind::Haptic.name()
    }
    fn domain(&self) -> Domain {
        Domain::Faces
    }
    fn is_view_dependent(&self) -> bool {
        false
    }
    fn default_threshold(&self) -> f32 {
        1.0
    }
    /// The face values with the G¹ errors of each face's edges combined by their maximum (the
    /// paper's default aggregation; [`Doi::evaluate_faces`] takes any).
    fn evaluate(&self, mesh: &Mesh, ctx: &DoiContext, out: &mut Vec<f32>) -> Result<(), DoiError> {
        self.evaluate_faces(mesh, ctx, Aggregate::Max, &mut Vec::new(), out)
    }
    /// The G¹ error is a value per edge (eq. (6), "an error value for each line"), the one-side
    /// criterion one per face: the edges' G¹ errors are combined around each face with `agg`
    /// (as for every edge DoI), then the larger of the two terms is the face's value.
    fn evaluate_faces(
        &self,
        mesh: &Mesh,
        _ctx: &DoiContext,
        agg: Aggregate,
        _scratch: &mut Vec<f32>,
        out: &mut Vec<f32>,
    ) -> Result<(), DoiError> {
        mesh.check_triangles()?;
        let normals = vertex_normals(mesh);
        let ct = clough_tocher_patches(mesh, &normals);
        out.clear();
        out.extend(mesh.faces().map(|f| {
            let [a, b] = self.terms(mesh, &ct, f, agg);
            a.max(b)
        }));
        Ok(())
    }
}

/// The binary haptic-interaction-point DoI (§4.2): 1 for the triangle closest to the HIP
/// (`DoiContext::hip`, snapped to the closest surface point) and every triangle sharing a vertex
/// with it, 0 elsewhere. Changes with the HIP, so it is re-evaluated per frame. Threshold 0.5.
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
        let Some((closest, _)) = closest_surface_point(mesh, hip) else {
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

/// The face of a triangle mesh closest to `p` and the closest point on it (the surface contact
/// point; ties: lowest face index), `None` without faces.
pub fn closest_surface_point(mesh: &Mesh, p: Vec3) -> Option<(FaceId, Vec3)> {
    let mut best = (f32::INFINITY, None);
    for f in mesh.faces() {
        let v = mesh.face_vertices(f);
        let q = closest_point_on_triangle(
            p,
            mesh.position(v[0]),
            mesh.position(v[1]),
            mesh.position(v[2]),
        );
        let d = q.distance_squared(p);
        if d < best.0 {
            best = (d, Some((f, q)));
        }
    }
    best.1
}

/// The face of a triangle mesh closest to `p` (ties: lowest index), `None` without faces.
pub fn closest_face(mesh: &Mesh, p: Vec3) -> Option<FaceId> {
    closest_surface_point(mesh, p).map(|(f, _)| f)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clough_tocher::{CubicTriangle, bezier_index};

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
        let g = subdiv_test_support::height_grid(4, true, 0.0, |x, y| {
            0.3 * (1.7 * x).sin() * (1.1 * y + 0.4).cos()
        });
        let p = g.positions.into_iter().map(Vec3::from).collect();
        let m = Mesh::from_soup(&PolygonSoup::from_faces(p, &g.faces)).unwrap();
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
        assert!((c.v[0] - 0.2).abs() < 1e-6 && (c.v[1] - 0.5).abs() < 1e-6);
        assert!((c.v[2] - 0.3).abs() < 1e-6 && c.off_plane == 0.0);
        assert!(barycentric_combination(Vec3::Z, Vec3::ZERO, Vec3::X, Vec3::X * 2.0).is_none());
    }

    /// Two hand-built cubic nets sharing the edge from a = (0,0,0) to b = (3,0,0): `b` with its
    /// first row at y = 1 and z = 0, `b̂` with its first row given by `row(k)` for the point at
    /// b-weight `k` (so `b̂(k, j, 1)` faces `b(j, k, 1)`).
    fn nets(row: impl Fn(usize) -> Vec3) -> (CloughTocher, CloughTocher) {
        let mut b = CubicTriangle {
            b: [Vec3::ZERO; 10],
        };
        let mut bh = b;
        for j in 0..=3usize {
            let k = 3 - j; // j on a, k on b: boundary point at x = k
            b.b[bezier_index(j, k, 0)] = Vec3::new(k as f32, 0.0, 0.0);
            bh.b[bezier_index(k, j, 0)] = Vec3::new(k as f32, 0.0, 0.0);
        }
        for (j, k) in [(2usize, 0usize), (1, 1), (0, 2)] {
            b.b[bezier_index(j, k, 1)] = Vec3::new(k as f32 + 0.5, 1.0, 0.0);
            bh.b[bezier_index(k, j, 1)] = row(k);
        }
        let wrap = |t: CubicTriangle| CloughTocher { sub: [t; 3] };
        (wrap(b), wrap(bh))
    }

    #[test]
    fn g1_on_hand_built_nets() {
        // Coplanar and G1 (the same combination v = (-2, 1.5, 1.5) for all three points, not
        // C1): no error.
        let (f, g) = nets(|k| Vec3::new(k as f32 + 0.5, -2.0, 0.0));
        assert!(g1_error(&f, 0, &g, 0) < 1e-5);
        // The same combinations in the plane, but lifted off it: eq. (6) alone is 0 (the
        // least-squares reading called this G1); the out-of-plane residual makes it an error.
        let (f, g) = nets(|k| Vec3::new(k as f32 + 0.5, -2.0, 0.3));
        let e = g1_error(&f, 0, &g, 0);
        assert!((e - 3.0 * 0.3 / 1.25f32.sqrt()).abs() < 1e-4, "{e}");
        // Coplanar but the combinations differ: eq. (6).
        let (f, g) = nets(|k| Vec3::new(k as f32 + 0.5 + 0.2 * k as f32, -1.0, 0.0));
        assert!(g1_error(&f, 0, &g, 0) > 0.1);
        // A degenerate net (first-row point on the boundary line): not 0 but the defined error.
        let (mut f, g) = nets(|k| Vec3::new(k as f32 + 0.5, -1.0, 0.0));
        f.sub[0].b[bezier_index(1, 1, 1)] = Vec3::new(1.5, 0.0, 0.0);
        assert_eq!(g1_error(&f, 0, &g, 0), DEGENERATE_G1_ERROR);
    }

    #[test]
    fn patches_crossing_their_plane() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let flat = CloughTocher::new(p, [Vec3::Z; 3]);
        assert_eq!(plane_crossing(&flat, p), 0.0);
        // Normals twisted like a saddle: the patch goes below the plane near edge 0-1 and above
        // it near edge 1-2.
        let n = [
            Vec3::new(0.5, 0.0, 1.0),
            Vec3::new(0.5, 0.0, 1.0),
            Vec3::new(-0.5, 0.0, 1.0),
        ]
        .map(|x| x.normalize());
        let twisted = CloughTocher::new(p, n);
        let c = plane_crossing(&twisted, p);
        assert!(c > 0.05, "{c}");
        // In a mesh: the one-side term of the Haptic DoI is that crossing over the tolerance.
        let m = Mesh::from_soup(&subdiv_mesh::PolygonSoup::from_faces(
            p.to_vec(),
            &[[0u32, 1, 2]],
        ))
        .unwrap();
        let h = Haptic::for_mesh(&m, 0.05);
        assert!((h.length - 0.05 * (2.0 + 2f32.sqrt()) / 3.0).abs() < 1e-6);
        assert_eq!(
            h.terms(&m, &[twisted], subdiv_mesh::FaceId(0), Aggregate::Max)[1],
            c / h.length
        );
        assert_eq!(
            h.terms(&m, &[flat], subdiv_mesh::FaceId(0), Aggregate::Avg),
            [0.0, 0.0]
        );
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
