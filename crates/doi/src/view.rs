//! View-dependent DoIs for silhouette generation (Isenberg, Hartmann & König 2003, §4.1), and
//! the silhouette polyline used to compare meshes (Fig. 5).

use glam::{Vec2, Vec3};
use subdiv_mesh::{Camera, EdgeId, Mesh, face_normals};

use crate::framework::{Doi, DoiContext, Domain};
use crate::{DoiError, DoiKind};

/// The view-angle DoI, eq. (1): `DoI_f = n · v` for face normal `n` and the unit view ray `v`
/// from the eye to the face centroid.
///
/// The value reported is `acos(|n · v|)` in degrees, the angle between the face normal and the
/// view ray folded to `[0°, 90°]`: 90° for faces seen edge-on, 0° for faces seen head-on. The
/// paper's Fig. 3(a) refines "faces with an angle of less than 20 degrees to the viewing
/// direction", i.e. within 20° of edge-on: the default threshold is 70°.
///
/// ```
/// use subdiv_doi::{Doi, DoiContext, ViewAngle};
/// use subdiv_mesh::{parse_obj, Camera, Mesh, glam::Vec3};
/// // A triangle in the plane x = 0 seen from +z: edge-on.
/// let m = Mesh::from_soup(&parse_obj("v 0 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n")?)?;
/// let cam = Camera::new(Vec3::new(0.0, 0.3, 100.0), Vec3::new(0.0, 0.3, 0.3), Vec3::Y, 45.0, 100, 100);
/// let mut v = Vec::new();
/// ViewAngle.evaluate(&m, &DoiContext::with_camera(cam), &mut v)?;
/// assert!((v[0] - 90.0).abs() < 0.01);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ViewAngle;

impl Doi for ViewAngle {
    fn name(&self) -> &'static str {
        DoiKind::ViewAngle.name()
    }
    fn domain(&self) -> Domain {
        Domain::Faces
    }
    fn is_view_dependent(&self) -> bool {
        true
    }
    fn default_threshold(&self) -> f32 {
        70.0
    }
    fn evaluate(&self, mesh: &Mesh, ctx: &DoiContext, out: &mut Vec<f32>) -> Result<(), DoiError> {
        let cam = ctx.camera_for(self.name())?;
        out.clear();
        out.reserve(mesh.num_faces());
        for f in mesh.faces() {
            let n = mesh.face_normal(f);
            let v = cam.ray_to(mesh.face_centroid(f));
            out.push(view_angle_deg(n, v));
        }
        Ok(())
    }
}

/// `acos(|n · v|)` in degrees (eq. (1) folded so front and back faces agree).
#[inline]
pub fn view_angle_deg(n: Vec3, v: Vec3) -> f32 {
    n.dot(v).abs().min(1.0).acos().to_degrees()
}

/// The binary silhouette-edge DoI, eq. (2): 1 on edges where a front-facing and a back-facing
/// triangle meet (`n1·v ≥ 0 ∧ n2·v < 0` or `n1·v ≤ 0 ∧ n2·v > 0`, with `v` the unit ray from the
/// eye to the edge midpoint), 0 elsewhere and on boundary edges. Any threshold in (0, 1) works;
/// the default is 0.5 (Fig. 3(b)).
///
/// ```
/// use subdiv_doi::{Doi, DoiContext, Silhouette};
/// use subdiv_mesh::{parse_obj, Camera, Mesh, glam::Vec3};
/// // A roof ridge along x seen from the side: one face toward the eye, one away.
/// let m = Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 1\nv 0 1 1\nv 0 2 0\nv 1 2 0\nf 1 2 3\nf 1 3 4\nf 4 3 6\nf 4 6 5\n")?)?;
/// let cam = Camera::new(Vec3::new(0.5, -5.0, 1.0), Vec3::new(0.5, 1.0, 1.0), Vec3::Z, 45.0, 100, 100);
/// let mut v = Vec::new();
/// Silhouette.evaluate(&m, &DoiContext::with_camera(cam), &mut v)?;
/// assert_eq!(v.iter().filter(|&&x| x == 1.0).count(), 1); // the ridge 3-4
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Silhouette;

impl Doi for Silhouette {
    fn name(&self) -> &'static str {
        DoiKind::Silhouette.name()
    }
    fn domain(&self) -> Domain {
        Domain::Edges
    }
    fn is_view_dependent(&self) -> bool {
        true
    }
    fn default_threshold(&self) -> f32 {
        0.5
    }
    fn evaluate(&self, mesh: &Mesh, ctx: &DoiContext, out: &mut Vec<f32>) -> Result<(), DoiError> {
        let cam = ctx.camera_for(self.name())?;
        let mut normals = Vec::new();
        face_normals(mesh, &mut normals);
        out.clear();
        out.extend(mesh.edges().map(|e| {
            if is_silhouette(mesh, &normals, cam, e) {
                1.0
            } else {
                0.0
            }
        }));
        Ok(())
    }
}

/// Eq. (2) for edge `e` with precomputed face normals.
#[inline]
pub fn is_silhouette(mesh: &Mesh, normals: &[Vec3], cam: &Camera, e: EdgeId) -> bool {
    let (f1, f2) = (mesh.face(e.halfedge(0)), mesh.face(e.halfedge(1)));
    if !f1.is_some() || !f2.is_some() {
        return false;
    }
    let [a, b] = mesh.edge_vertices(e);
    let v = cam.ray_to((mesh.position(a) + mesh.position(b)) * 0.5);
    let d1 = normals[f1.idx()].dot(v);
    let d2 = normals[f2.idx()].dot(v);
    (d1 >= 0.0 && d2 < 0.0) || (d1 <= 0.0 && d2 > 0.0)
}

/// The silhouette edges of `mesh` (eq. (2)) projected to pixels: one segment per edge, edges
/// behind the eye skipped.
pub fn silhouette_segments(mesh: &Mesh, cam: &Camera) -> Vec<[Vec2; 2]> {
    let mut normals = Vec::new();
    face_normals(mesh, &mut normals);
    let mut out = Vec::new();
    for e in mesh.edges() {
        if !is_silhouette(mesh, &normals, cam, e) {
            continue;
        }
        let [a, b] = mesh.edge_vertices(e);
        if let (Some(p), Some(q)) = (cam.project(mesh.position(a)), cam.project(mesh.position(b))) {
            out.push([p, q]);
        }
    }
    out
}

/// Distance from `p` to segment `s`.
#[inline]
pub fn point_segment_distance(p: Vec2, s: [Vec2; 2]) -> f32 {
    let d = s[1] - s[0];
    let l2 = d.length_squared();
    let t = if l2 > 0.0 {
        ((p - s[0]).dot(d) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(s[0] + d * t)
}

/// Distances between two silhouettes (segment sets in pixels): every segment of `a` is sampled
/// at its ends and every `step` pixels, and each sample's distance to the nearest segment of `b`
/// is taken. Returns `(max, mean)` over the samples (the directed Hausdorff distance and the
/// mean deviation); `(inf, inf)` when `b` is empty and `a` is not.
pub fn silhouette_distance(a: &[[Vec2; 2]], b: &[[Vec2; 2]], step: f32) -> (f32, f32) {
    if a.is_empty() {
        return (0.0, 0.0);
    }
    if b.is_empty() {
        return (f32::INFINITY, f32::INFINITY);
    }
    // A uniform grid over b's segments keeps this near linear.
    let cell = 8.0f32;
    let (mut lo, mut hi) = (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY));
    for s in b {
        lo = lo.min(s[0].min(s[1]));
        hi = hi.max(s[0].max(s[1]));
    }
    let nx = (((hi.x - lo.x) / cell) as usize + 1).min(4096);
    let ny = (((hi.y - lo.y) / cell) as usize + 1).min(4096);
    let cell_of = |p: Vec2| -> (usize, usize) {
        let c = ((p - lo) / cell).max(Vec2::ZERO);
        ((c.x as usize).min(nx - 1), (c.y as usize).min(ny - 1))
    };
    let mut grid: Vec<Vec<u32>> = vec![Vec::new(); nx * ny];
    for (i, s) in b.iter().enumerate() {
        let (x0, y0) = cell_of(s[0].min(s[1]));
        let (x1, y1) = cell_of(s[0].max(s[1]));
        for y in y0..=y1 {
            for x in x0..=x1 {
                grid[y * nx + x].push(i as u32);
            }
        }
    }
    let nearest = |p: Vec2| -> f32 {
        let (cx, cy) = cell_of(p);
        let mut best = f32::INFINITY;
        let mut r = 0usize;
        loop {
            let (x0, x1) = (cx.saturating_sub(r), (cx + r).min(nx - 1));
            let (y0, y1) = (cy.saturating_sub(r), (cy + r).min(ny - 1));
            for y in y0..=y1 {
                for x in x0..=x1 {
                    if r > 0 && x != x0 && x != x1 && y != y0 && y != y1 {
                        continue;
                    }
                    for &i in &grid[y * nx + x] {
                        best = best.min(point_segment_distance(p, b[i as usize]));
                    }
                }
            }
            // Everything within r cells is searched: done once the best is closer than that.
            let covered = r as f32 * cell;
            if best <= covered || (x0 == 0 && y0 == 0 && x1 == nx - 1 && y1 == ny - 1) {
                return best;
            }
            r += 1;
        }
    };
    let (mut max, mut sum, mut n) = (0.0f32, 0.0f64, 0u64);
    for s in a {
        let len = s[0].distance(s[1]);
        let k = ((len / step.max(1e-3)).ceil() as u32).max(1);
        for i in 0..=k {
            let d = nearest(s[0].lerp(s[1], i as f32 / k as f32));
            max = max.max(d);
            sum += d as f64;
            n += 1;
        }
    }
    (max, (sum / n as f64) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::PolygonSoup;
    use subdiv_rules::{Scheme, refine_uniform};

    /// An icosahedron refined `levels` times with its vertices pushed onto the unit sphere.
    pub(crate) fn sphere(levels: u32) -> Mesh {
        let t = (1.0 + 5f32.sqrt()) / 2.0;
        let p: Vec<Vec3> = [
            [-1.0, t, 0.0],
            [1.0, t, 0.0],
            [-1.0, -t, 0.0],
            [1.0, -t, 0.0],
            [0.0, -1.0, t],
            [0.0, 1.0, t],
            [0.0, -1.0, -t],
            [0.0, 1.0, -t],
            [t, 0.0, -1.0],
            [t, 0.0, 1.0],
            [-t, 0.0, -1.0],
            [-t, 0.0, 1.0],
        ]
        .iter()
        .map(|a| Vec3::from_array(*a).normalize())
        .collect();
        let f: [[u32; 3]; 20] = [
            [0, 11, 5],
            [0, 5, 1],
            [0, 1, 7],
            [0, 7, 10],
            [0, 10, 11],
            [1, 5, 9],
            [5, 11, 4],
            [11, 10, 2],
            [10, 7, 6],
            [7, 1, 8],
            [3, 9, 4],
            [3, 4, 2],
            [3, 2, 6],
            [3, 6, 8],
            [3, 8, 9],
            [4, 9, 5],
            [2, 4, 11],
            [6, 2, 10],
            [8, 6, 7],
            [9, 8, 1],
        ];
        let mut m = Mesh::from_soup(&PolygonSoup::from_faces(p, &f)).unwrap();
        for _ in 0..levels {
            m = refine_uniform(&m, Scheme::Loop).unwrap();
            for q in m.positions_mut() {
                *q = q.normalize();
            }
        }
        m
    }

    #[test]
    fn sphere_silhouette_lies_on_the_equator_seen_from_z() {
        let m = sphere(2);
        let cam = Camera::new(
            Vec3::new(0.0, 0.0, 1000.0),
            Vec3::ZERO,
            Vec3::Y,
            1.0,
            800,
            800,
        );
        let mut v = Vec::new();
        Silhouette
            .evaluate(&m, &DoiContext::with_camera(cam), &mut v)
            .unwrap();
        let sil: Vec<EdgeId> = m.edges().filter(|e| v[e.idx()] == 1.0).collect();
        assert!(
            sil.len() >= 20,
            "a closed loop around the sphere: {}",
            sil.len()
        );
        for e in &sil {
            let [a, b] = m.edge_vertices(*e);
            let z = (m.position(a).z + m.position(b).z) * 0.5;
            assert!(z.abs() < 0.2, "silhouette edge {e} at z = {z}");
        }
        // Every silhouette vertex has exactly two silhouette edges: a closed curve.
        let mut deg = vec![0u32; m.num_vertices()];
        for e in &sil {
            for x in m.edge_vertices(*e) {
                deg[x.idx()] += 1;
            }
        }
        assert!(deg.iter().all(|&d| d == 0 || d == 2), "{deg:?}");
        // And the values are binary.
        assert!(v.iter().all(|&x| x == 0.0 || x == 1.0));
    }

    #[test]
    fn view_angle_values() {
        let m = sphere(1);
        let cam = Camera::new(
            Vec3::new(0.0, 0.0, 1000.0),
            Vec3::ZERO,
            Vec3::Y,
            1.0,
            800,
            800,
        );
        let mut v = Vec::new();
        ViewAngle
            .evaluate(&m, &DoiContext::with_camera(cam), &mut v)
            .unwrap();
        for f in m.faces() {
            let c = m.face_centroid(f);
            // The face normal is close to the radial direction, so the angle is close to
            // 90° - latitude above the view plane.
            let want = c.normalize().z.abs().acos().to_degrees();
            assert!(
                (v[f.idx()] - want).abs() < 12.0,
                "face {f}: {} vs {want}",
                v[f.idx()]
            );
        }
        assert_eq!(view_angle_deg(Vec3::Z, -Vec3::Z), 0.0);
        assert!((view_angle_deg(Vec3::X, -Vec3::Z) - 90.0).abs() < 1e-5);
        // Without a camera: a clear error.
        let e = ViewAngle
            .evaluate(&m, &DoiContext::default(), &mut v)
            .unwrap_err();
        assert!(
            e.to_string()
                .contains("view-angle DoI is view-dependent and needs a camera")
        );
    }

    #[test]
    fn silhouette_distance_of_shifted_lines() {
        let a = vec![[Vec2::new(0.0, 0.0), Vec2::new(100.0, 0.0)]];
        let b = vec![
            [Vec2::new(0.0, 3.0), Vec2::new(50.0, 3.0)],
            [Vec2::new(50.0, 3.0), Vec2::new(100.0, 4.0)],
        ];
        let (max, mean) = silhouette_distance(&a, &b, 1.0);
        assert!((max - 4.0).abs() < 1e-3, "{max}");
        assert!(mean > 3.0 && mean < 4.0);
        assert_eq!(silhouette_distance(&[], &b, 1.0), (0.0, 0.0));
        assert!(silhouette_distance(&a, &[], 1.0).0.is_infinite());
        // Far from every segment: the grid search widens until it finds one.
        let far = vec![[Vec2::new(0.0, 500.0), Vec2::new(1.0, 500.0)]];
        assert!((silhouette_distance(&far, &b, 1.0).0 - 497.0).abs() < 1e-2);
    }
}
