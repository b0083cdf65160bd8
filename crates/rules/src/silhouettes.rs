//! Silhouette extraction on a tessellation: the edges between faces that face the eye and faces
//! that face away, as line segments for the renderer (the silhouette edges of Isenberg et al.
//! 2003, eq. 2, on the drawn surface), and the contours (those plus the boundary edges) that
//! the image-quality measurement compares.

use glam::Vec3;

use crate::LimitMesh;

/// Silhouette extraction: an interior edge is a silhouette edge when one of its two faces faces
/// the eye and the other faces away. A face's normal is the mean of its vertices' limit normals
/// (the geometric normal where those cancel).
pub struct Silhouettes {
    /// Interior edges (vertex pairs) and their two faces.
    edges: Vec<([u32; 2], [u32; 2])>,
    /// Boundary edges (of one face).
    boundary: Vec<[u32; 2]>,
    face_normal: Vec<Vec3>,
    face_centre: Vec<Vec3>,
}

impl Silhouettes {
    /// Face adjacency and face normals of `limit`.
    pub fn new(limit: &LimitMesh) -> Silhouettes {
        let p = |i: u32| Vec3::from(limit.positions()[i as usize]);
        let mut keyed: Vec<([u32; 2], u32)> = Vec::with_capacity(limit.face_indices().len());
        let mut face_normal = Vec::with_capacity(limit.num_faces());
        let mut face_centre = Vec::with_capacity(limit.num_faces());
        for f in 0..limit.num_faces() {
            let vs = limit.face(f);
            let centre = vs.iter().map(|&v| p(v)).sum::<Vec3>() / vs.len() as f32;
            let mut n: Vec3 = vs
                .iter()
                .map(|&v| Vec3::from(limit.normals()[v as usize]))
                .sum();
            if n.length_squared() < 1e-12 {
                // Newell's normal of the polygon (relative to a corner).
                n = subdiv_mesh::newell_area(vs.iter().map(|&v| p(v)));
            }
            face_normal.push(n.normalize_or_zero());
            face_centre.push(centre);
            for k in 0..vs.len() {
                let (a, b) = (vs[k], vs[(k + 1) % vs.len()]);
                keyed.push(([a.min(b), a.max(b)], f as u32));
            }
        }
        keyed.sort_unstable();
        let mut edges = Vec::with_capacity(keyed.len() / 2);
        let mut boundary = Vec::new();
        let mut i = 0;
        while i < keyed.len() {
            let mut j = i + 1;
            while j < keyed.len() && keyed[j].0 == keyed[i].0 {
                j += 1;
            }
            if j - i == 2 {
                edges.push((keyed[i].0, [keyed[i].1, keyed[i + 1].1]));
            } else if j - i == 1 {
                boundary.push(keyed[i].0);
            }
            i = j;
        }
        Silhouettes {
            edges,
            boundary,
            face_normal,
            face_centre,
        }
    }

    /// The silhouette edges seen from `eye` as line segments (pairs of endpoints), into `out`.
    pub fn lines_into(&self, positions: &[[f32; 3]], eye: Vec3, out: &mut Vec<[f32; 3]>) {
        out.clear();
        let front =
            |f: u32| self.face_normal[f as usize].dot(eye - self.face_centre[f as usize]) > 0.0;
        for &([a, b], [f, g]) in &self.edges {
            if front(f) != front(g) {
                out.push(positions[a as usize]);
                out.push(positions[b as usize]);
            }
        }
    }

    /// Every contour of the surface seen from `eye`, hidden or not, as line segments: the
    /// silhouette edges ([`Silhouettes::lines_into`]) and the boundary edges, into `out`.
    pub fn contours_into(&self, positions: &[[f32; 3]], eye: Vec3, out: &mut Vec<[f32; 3]>) {
        self.lines_into(positions, eye, out);
        for &[a, b] in &self.boundary {
            out.push(positions[a as usize]);
            out.push(positions[b as usize]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube as six quads (CCW seen from outside) with outward face normals at the corners.
    fn cube() -> LimitMesh {
        let soup = subdiv_test_support::cube().map_positions(|p| p.map(|x| x * 2.0 - 1.0));
        let normals = soup
            .positions
            .iter()
            .map(|p| (Vec3::from(*p).normalize()).to_array())
            .collect();
        let offsets = (0..=6).map(|i| i * 4).collect();
        let indices = soup.faces.iter().flatten().copied().collect();
        LimitMesh::new(soup.positions, normals, offsets, indices).unwrap()
    }

    #[test]
    fn cube_silhouette_seen_along_an_axis_is_its_outline() {
        let limit = cube();
        let s = Silhouettes::new(&limit);
        assert_eq!(s.edges.len(), 12);
        let mut lines = Vec::new();
        // Looking down -z: the +z face faces the eye; in perspective the four side faces face
        // away, so the silhouette is the outline of the +z face.
        s.lines_into(limit.positions(), Vec3::new(0.0, 0.0, 100.0), &mut lines);
        assert_eq!(lines.len(), 8, "{lines:?}");
        assert!(lines.iter().all(|p| p[2] == 1.0));
        // Seen from a corner direction, three faces face the eye: six silhouette edges.
        s.lines_into(limit.positions(), Vec3::new(10.0, 11.0, 12.0), &mut lines);
        assert_eq!(lines.len(), 12);
        // Closed: the contours are the silhouette edges.
        s.contours_into(limit.positions(), Vec3::new(10.0, 11.0, 12.0), &mut lines);
        assert_eq!(lines.len(), 12);
        // Without the -z face the cube is open: its four edges are contours from anywhere.
        let open = LimitMesh::new(
            limit.positions().to_vec(),
            limit.normals().to_vec(),
            (0..=5).map(|f| 4 * f).collect(),
            limit.face_indices()[4..].to_vec(),
        )
        .unwrap();
        let s = Silhouettes::new(&open);
        assert_eq!((s.edges.len(), s.boundary.len()), (8, 4));
        s.contours_into(open.positions(), Vec3::new(0.0, 0.0, 100.0), &mut lines);
        assert_eq!(lines.len(), 8 + 8, "{lines:?}");
    }
}
