//! Geometric helpers shared by every crate: polygon normals that stay accurate on tiny faces,
//! vertex normals, point bounds, closest points, the triangle check and triangulation.
//!
//! One home per helper: the rules, the DoIs, the stitching and the renderer's silhouettes all
//! call these instead of writing their own.

use std::ops::{AddAssign, Sub};

use glam::{DVec3, Vec3};

use crate::{Mesh, MeshError, PolygonSoup, Primvar, PrimvarInterpolation, VertexId};

/// A 3-vector type the polygon helpers work on (`Vec3` and `DVec3`).
pub trait Vector3: Copy + Default + Sub<Output = Self> + AddAssign {
    /// The cross product.
    fn cross3(self, other: Self) -> Self;
}

impl Vector3 for Vec3 {
    #[inline]
    fn cross3(self, other: Vec3) -> Vec3 {
        self.cross(other)
    }
}

impl Vector3 for DVec3 {
    #[inline]
    fn cross3(self, other: DVec3) -> DVec3 {
        self.cross(other)
    }
}

/// Twice the vector area of a polygon (Newell's method), summed relative to its first corner.
///
/// Newell's sum `Σ p_k × p_(k+1)` is translation invariant in exact arithmetic, but in floating
/// point its terms grow with the distance from the origin while their sum shrinks with the
/// polygon: a face of size `h` at distance `d` loses about `log2(d / h)` bits. Taking every
/// corner relative to the first, `Σ (p_k − p_0) × (p_(k+1) − p_0)`, keeps the terms of the
/// order of `h²`, so the normal of a tiny face deep in a tessellation is as accurate as that of a
/// big one. Zero for fewer than three corners or a degenerate polygon.
///
/// ```
/// use subdiv_mesh::{glam::Vec3, newell_area};
/// let far = Vec3::splat(1.0e4);
/// let h = 1.0e-3;
/// let quad = [far, far + Vec3::X * h, far + Vec3::new(h, h, 0.0), far + Vec3::Y * h];
/// let n = newell_area(quad).normalize();
/// assert!((n - Vec3::Z).length() < 1e-6);
/// ```
#[inline]
pub fn newell_area<T: Vector3>(corners: impl IntoIterator<Item = T>) -> T {
    let mut it = corners.into_iter();
    let mut sum = T::default();
    let Some(first) = it.next() else {
        return sum;
    };
    let Some(second) = it.next() else {
        return sum;
    };
    let mut prev = second - first;
    for p in it {
        let cur = p - first;
        sum += prev.cross3(cur);
        prev = cur;
    }
    sum
}

/// The unit normal of a polygon from [`newell_area`]; zero for a degenerate polygon.
#[inline]
pub fn newell_normal(corners: impl IntoIterator<Item = Vec3>) -> Vec3 {
    newell_area(corners).normalize_or_zero()
}

/// Axis-aligned bounds `(min, max)` of `points`, per component the `min`/`max` of every
/// point in order (`(+inf, -inf)` for none): the one home of point bounds, so the cage, the
/// tessellations and the scenes agree to the bit.
///
/// ```
/// use subdiv_mesh::{glam::Vec3, point_bounds};
/// let (lo, hi) = point_bounds([Vec3::new(1.0, -2.0, 0.5), Vec3::new(-1.0, 3.0, 0.0)]);
/// assert_eq!((lo, hi), (Vec3::new(-1.0, -2.0, 0.0), Vec3::new(1.0, 3.0, 0.5)));
/// ```
#[inline]
pub fn point_bounds(points: impl IntoIterator<Item = Vec3>) -> (Vec3, Vec3) {
    points.into_iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    )
}

/// All face normals of `mesh` into `out` (one per face, [`Mesh::face_normal`]).
pub fn face_normals(mesh: &Mesh, out: &mut Vec<Vec3>) {
    out.clear();
    out.extend(mesh.faces().map(|f| mesh.face_normal(f)));
}

/// Area-weighted vertex normals of a mesh (unit length; zero for isolated vertices): each face
/// adds its [`newell_area`] to its corners.
pub fn vertex_normals(mesh: &Mesh) -> Vec<Vec3> {
    let mut n = vec![Vec3::ZERO; mesh.num_vertices()];
    let pos = mesh.positions();
    for f in mesh.faces() {
        let v = mesh.face_vertices(f);
        let s = newell_area(v.iter().map(|x| pos[x.idx()]));
        for &x in v {
            n[x.idx()] += s;
        }
    }
    for x in &mut n {
        *x = x.normalize_or_zero();
    }
    n
}

/// Frame `frame` of `frames` of a swaying cage, for benchmarks of moving cages where no
/// animation is authored: every point moves along the bounding box's next axis after its
/// longest by a twentieth of the box's diagonal times `sin(2 pi (frame / frames + h))`, `h` its
/// height along the longest axis (0 to 1 over the box): a wave travelling up the cage. Frame 0
/// is not the rest pose; the same frame gives the same points (`xtask/osd/bench_animate.cpp`
/// sways OpenSubdiv's cage the same way).
pub fn sway(rest: &[Vec3], frame: usize, frames: usize, out: &mut Vec<Vec3>) {
    let (lo, hi) = point_bounds(rest.iter().copied());
    let ext = (hi - lo).to_array();
    let a = (0..3).fold(0, |m, i| if ext[i] > ext[m] { i } else { m });
    let b = (a + 1) % 3;
    let amplitude = 0.05 * (hi - lo).length();
    let phase = frame as f32 / frames.max(1) as f32;
    let height = ext[a].max(f32::MIN_POSITIVE);
    out.clear();
    out.extend(rest.iter().map(|&p| {
        let h = (p[a] - lo[a]) / height;
        let mut q = p;
        q[b] += amplitude * (std::f32::consts::TAU * (phase + h)).sin();
        q
    }));
}

/// The point of triangle `a b c` closest to `p` (Ericson, Real-Time Collision Detection, 5.1.5).
#[inline]
pub fn closest_point_on_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

impl Mesh {
    /// Refuses a mesh with a face that is not a triangle (Loop subdivision, red-green closure
    /// and the triangle DoIs need triangles): [`MeshError::NotTriangles`] names the first one.
    pub fn check_triangles(&self) -> Result<(), MeshError> {
        match self.faces().find(|&f| self.face_size(f) != 3) {
            Some(f) => Err(MeshError::NotTriangles {
                face: f.0,
                size: self.face_size(f) as u32,
            }),
            None => Ok(()),
        }
    }
}

/// Splits every face of `mesh` into triangles: quads along their shorter diagonal, larger
/// polygons as a fan from their first vertex. Triangles stay as they are. Groups, holes, edge
/// and vertex sharpness, the scheme options and the UVs (each triangle corner keeps its face
/// corner's value) and the primvars (each triangle its face's uniform value and its corners'
/// face-varying ones) carry over; the new diagonals are smooth.
///
/// ```
/// use subdiv_mesh::{parse_obj, triangulate, Mesh};
/// let m = Mesh::from_soup(&parse_obj("v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nv 1 2 0\nf 1 2 3 4\nf 4 3 5\n")?)?;
/// let t = triangulate(&m)?;
/// assert_eq!(t.num_faces(), 3);
/// assert!(t.faces().all(|f| t.face_size(f) == 3));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn triangulate(mesh: &Mesh) -> Result<Mesh, MeshError> {
    let mut soup = PolygonSoup {
        positions: mesh.positions().to_vec(),
        options: mesh.options(),
        groups: mesh.groups().to_vec(),
        ..Default::default()
    };
    let mut holes = Vec::new();
    let (offsets, _) = mesh.face_lists();
    if let Some(fv) = mesh.uv() {
        soup.uvs = fv.values.clone();
    }
    // Primvars: per vertex and constant ones as they are; per face and per corner ones follow
    // their faces and corners (filled below).
    soup.primvars = mesh
        .primvars()
        .iter()
        .map(|p| match p.interpolation {
            PrimvarInterpolation::Uniform | PrimvarInterpolation::FaceVarying => Primvar {
                indices: Vec::new(),
                ..p.clone()
            },
            _ => p.clone(),
        })
        .collect();
    for f in mesh.faces() {
        let v: Vec<i64> = mesh.face_vertices(f).iter().map(|x| x.0 as i64).collect();
        // Triangles as corners of the face.
        let tris: Vec<[usize; 3]> = match v.len() {
            3 => vec![[0, 1, 2]],
            4 => {
                let p = |i: usize| mesh.position(VertexId(v[i] as u32));
                if p(0).distance_squared(p(2)) <= p(1).distance_squared(p(3)) {
                    vec![[0, 1, 2], [0, 2, 3]]
                } else {
                    vec![[0, 1, 3], [1, 2, 3]]
                }
            }
            n => (1..n - 1).map(|k| [0, k, k + 1]).collect(),
        };
        for t in tris {
            soup.push_face(t.map(|k| v[k]));
            let c = offsets[f.idx()] as usize;
            if let Some(fv) = mesh.uv() {
                soup.uv_indices
                    .extend(t.map(|k| i64::from(fv.indices[c + k])));
            }
            for (q, p) in soup.primvars.iter_mut().zip(mesh.primvars()) {
                match p.interpolation {
                    PrimvarInterpolation::Uniform => q.indices.push(p.indices[f.idx()]),
                    PrimvarInterpolation::FaceVarying => {
                        q.indices.extend(t.map(|k| p.indices[c + k]));
                    }
                    _ => {}
                }
            }
            soup.face_groups.push(mesh.face_group(f));
            holes.push(mesh.is_hole(f));
        }
    }
    let mut out = Mesh::from_soup(&soup)?;
    out.set_holes(holes);
    for e in mesh.edges() {
        let s = mesh.edge_sharpness(e);
        if s > 0.0 && !mesh.is_boundary_edge(e) {
            let [a, b] = mesh.edge_vertices(e);
            if let Some(h) = out.find_halfedge(a, b) {
                out.set_edge_sharpness(h.edge(), s);
            }
        }
    }
    for v in mesh.vertices() {
        let s = mesh.vertex_sharpness(v);
        if s > out.vertex_sharpness(v) {
            out.set_vertex_sharpness(v, s);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{FaceId, parse_obj};

    #[test]
    fn newell_relative_to_a_corner_survives_distance_from_the_origin() {
        // A square of side 2^-8 about 2^11 away from the origin (corners exact in f32):
        // absolute-coordinate Newell loses the area to cancellation; the corner-relative sum
        // keeps it exactly.
        let o = Vec3::new(1024.0, -2048.0, 512.0);
        let h = 1.0 / 256.0;
        let quad = [
            o,
            o + Vec3::X * h,
            o + Vec3::new(h, h, 0.0),
            o + Vec3::Y * h,
        ];
        let n = newell_normal(quad);
        assert!((n - Vec3::Z).length() < 1e-3, "{n}");
        let absolute: Vec3 = (0..4).map(|k| quad[k].cross(quad[(k + 1) % 4])).sum();
        assert!(
            (absolute.normalize_or_zero() - Vec3::Z).length() > 1e-2,
            "the test must exercise cancellation: {absolute}"
        );
        let area = newell_area(quad).length() / 2.0;
        assert_eq!(area, h * h);
        // Same in f64, and degenerate inputs give zero.
        let d = newell_area([DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0)]);
        assert_eq!(d, DVec3::new(0.0, 0.0, 1.0));
        assert_eq!(newell_area([Vec3::ONE, Vec3::ONE * 2.0]), Vec3::ZERO);
        assert_eq!(
            newell_normal([Vec3::ZERO, Vec3::X, Vec3::X * 2.0]),
            Vec3::ZERO
        );
    }

    #[test]
    fn check_triangles_names_the_first_other_face() {
        let m = Mesh::from_soup(
            &parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nf 1 2 4\nf 2 5 3 4\n")
                .unwrap(),
        )
        .unwrap();
        let e = m.check_triangles().unwrap_err();
        assert_eq!(e, MeshError::NotTriangles { face: 1, size: 4 });
        assert!(e.to_string().contains("face 1 has 4 vertices"), "{e}");
        assert!(triangulate(&m).unwrap().check_triangles().is_ok());
    }

    #[test]
    fn vertex_normals_and_closest_points() {
        let m =
            Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap()).unwrap();
        assert!(
            vertex_normals(&m)
                .iter()
                .all(|n| (*n - Vec3::Z).length() < 1e-6)
        );
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        let q = closest_point_on_triangle(Vec3::new(0.25, 0.25, 3.0), a, b, c);
        assert!((q - Vec3::new(0.25, 0.25, 0.0)).length() < 1e-6, "{q}");
        assert_eq!(
            closest_point_on_triangle(Vec3::new(-1.0, -1.0, 0.0), a, b, c),
            a
        );
        let q = closest_point_on_triangle(Vec3::new(1.0, 1.0, 0.0), a, b, c);
        assert!((q - Vec3::new(0.5, 0.5, 0.0)).length() < 1e-6);
    }

    #[test]
    fn triangulate_keeps_creases_groups_and_area() {
        let m = Mesh::from_soup(
            &parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\ng a\nf 1 2 3 4\ng b\nf 2 5 6 3\nt crease 2/1/0 1 2 2.5\n")
                .unwrap(),
        )
        .unwrap();
        let t = triangulate(&m).unwrap();
        assert_eq!(t.num_faces(), 4);
        assert_eq!(t.groups(), &["a".to_string(), "b".to_string()]);
        assert_eq!(t.face_groups(), &[0, 0, 1, 1]);
        let e = t.find_halfedge(VertexId(1), VertexId(2)).unwrap().edge();
        assert_eq!(t.edge_sharpness(e), 2.5);
        let area: f32 = t
            .faces()
            .map(|f| {
                let v = t.face_vertices(f);
                newell_area(v.iter().map(|&x| t.position(x))).length() / 2.0
            })
            .sum();
        assert!((area - 2.0).abs() < 1e-6);
        // A hexagon becomes a fan of four.
        let hex = Mesh::from_soup(
            &parse_obj(
                "v 2 0 0\nv 1 2 0\nv -1 2 0\nv -2 0 0\nv -1 -2 0\nv 1 -2 0\nf 1 2 3 4 5 6\n",
            )
            .unwrap(),
        )
        .unwrap();
        assert_eq!(triangulate(&hex).unwrap().num_faces(), 4);
    }

    #[test]
    fn triangulate_keeps_each_corner_uv() {
        // Two quads with a UV seam between them (the shared edge's corners differ).
        let m = Mesh::from_soup(
            &parse_obj(
                "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n\
                 vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 5 0\nvt 6 0\nvt 6 1\nvt 5 1\n\
                 f 1/1 2/2 3/3 4/4\nf 2/5 5/6 6/7 3/8\n",
            )
            .unwrap(),
        )
        .unwrap();
        let t = triangulate(&m).unwrap();
        let fv = t.uv().expect("UVs carried");
        assert_eq!(fv.values, m.uv().unwrap().values);
        let (offsets, _) = t.face_lists();
        // Every triangle corner has the value of the quad corner at the same vertex.
        let (mo, _) = m.face_lists();
        for f in t.faces() {
            let quad = FaceId(f.0 / 2);
            let qv = m.face_vertices(quad);
            for (k, v) in t.face_vertices(f).iter().enumerate() {
                let q = qv.iter().position(|x| x == v).unwrap();
                let want = m.uv().unwrap().indices[mo[quad.idx()] as usize + q];
                assert_eq!(fv.indices[offsets[f.idx()] as usize + k], want);
            }
        }
    }
}
