//! One-sided limit normals: where the limit surface has a crease or a corner at a vertex, each
//! face around it lies on one smooth side (*sector*) of it, with its own tangent plane.
//!
//! A sector is a maximal run of faces between two sharp edges of the limit ring (after the
//! refinement [`Ring::limit`](super::Ring::limit) does, every sharpness is 0 or infinite). An
//! interior crease has two sectors; the masks of the crease rule give each side's tangents (the
//! crease tangent and that side's cross tangent, see `LimitParts`). A corner's sectors are
//! bounded by crease curves that start at the corner along their first edges (the corner rule
//! keeps the vertex, the crease rule halves its edges): a sector's tangent plane is spanned by
//! its two bounding edges. Smooth points, darts, boundary creases and corners with one sector
//! have one normal.

use glam::DVec3;

use super::LimitParts;
use crate::crease::{Rule, is_sharp};

/// How the faces around a limit vertex split into sectors (a property of the configuration:
/// rule, boundary and which edges are sharp at the limit).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) enum Sides {
    /// One tangent plane.
    #[default]
    One,
    /// An interior crease between edges `c0 < c1`: faces `c0..c1` take the first side's
    /// tangents, the others the second's.
    Crease(usize, usize),
    /// A corner with two or more sectors, bounded by these sharp edges (ascending; for a
    /// boundary vertex its first and last edges are among them and no sector wraps around).
    Corner(Vec<usize>),
}

impl Sides {
    /// The sectors of a limit ring with `rule`, edge `sharp`ness and `num_faces` faces.
    pub(crate) fn new(rule: Rule, boundary: bool, sharp: &[f32], num_faces: usize) -> Sides {
        let n = sharp.len();
        match rule {
            Rule::Crease([c0, c1]) if !boundary && num_faces == n => Sides::Crease(c0, c1),
            Rule::Corner => {
                let edges: Vec<usize> = (0..n)
                    .filter(|&i| is_sharp(sharp[i]) || (boundary && (i == 0 || i + 1 == n)))
                    .collect();
                let sectors = if boundary {
                    edges.len().saturating_sub(1)
                } else {
                    edges.len()
                };
                if sectors >= 2 && (boundary || num_faces == n) {
                    Sides::Corner(edges)
                } else {
                    Sides::One
                }
            }
            _ => Sides::One,
        }
    }

    /// `true` when the faces do not all share one tangent plane.
    pub(crate) fn is_sided(&self) -> bool {
        *self != Sides::One
    }
}

/// The unit normal of every face of the limit ring `center`, `edges` (`num_faces` faces, face
/// `i` between edges `i` and `i + 1`), one-sided per [`Sides`], into `out` (cleared; left empty
/// for [`Sides::One`]). Each side is oriented like its own faces.
pub(crate) fn sided_normals(
    parts: &LimitParts,
    sides: &Sides,
    center: DVec3,
    edges: &[DVec3],
    num_faces: usize,
    out: &mut Vec<DVec3>,
) {
    out.clear();
    let n = edges.len();
    // Area vector of faces `a, a+1, ..` up to (not including) `b`, modulo `n`.
    let area = |a: usize, b: usize| {
        let mut s = DVec3::ZERO;
        let mut i = a;
        loop {
            s += (edges[i % n] - center).cross(edges[(i + 1) % n] - center);
            i += 1;
            if i % n == b % n {
                break s;
            }
        }
    };
    let scale = edges
        .iter()
        .map(|e| (*e - center).length_squared())
        .fold(0.0, f64::max);
    let orient = |v: DVec3, area: DVec3| {
        let len = v.length();
        if len > 1e-12 * scale.max(f64::MIN_POSITIVE) && len.is_finite() {
            let v = v / len;
            if v.dot(area) < 0.0 { -v } else { v }
        } else {
            area.normalize_or_zero()
        }
    };
    match sides {
        Sides::One => {}
        Sides::Crease(c0, c1) => {
            let (c0, c1) = (*c0, *c1);
            let first = orient(parts.t1.cross(parts.t2), area(c0, c1));
            let (u1, u2) = parts.other.unwrap_or((parts.t1, parts.t2));
            let second = orient(u1.cross(u2), area(c1, c0));
            out.extend((0..num_faces).map(|i| if (c0..c1).contains(&i) { first } else { second }));
        }
        Sides::Corner(sharp) => {
            out.resize(num_faces, DVec3::ZERO);
            let m = sharp.len();
            for k in 0..m {
                let (a, b) = (sharp[k], sharp[(k + 1) % m]);
                if k + 1 == m && (num_faces < n) {
                    break; // boundary: no sector wraps around
                }
                let nrm = orient((edges[a] - center).cross(edges[b % n] - center), area(a, b));
                let mut i = a;
                loop {
                    out[i % n] = nrm;
                    i += 1;
                    if i % n == b % n {
                        break;
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::Ring;
    use glam::DVec3;
    use subdiv_mesh::{Mesh, PolygonSoup, VertexId};

    use crate::Scheme;

    /// A tent: the planes z = |y| / 2 meeting at an infinitely sharp crease along y = 0, on a
    /// quad grid; each side is exactly planar in the limit, so each side's normal is its plane's.
    fn tent() -> Mesh {
        let mut p = Vec::new();
        for j in -3..=3 {
            for i in -3..=3 {
                p.push(glam::Vec3::new(i as f32, j as f32, (j as f32).abs() * 0.5));
            }
        }
        let mut faces = Vec::new();
        for j in 0..6u32 {
            for i in 0..6u32 {
                let a = j * 7 + i;
                faces.push(vec![a, a + 1, a + 8, a + 7]);
            }
        }
        let mut m = Mesh::from_soup(&PolygonSoup::from_faces(p, &faces)).unwrap();
        for a in 21..27u32 {
            let h = m.find_halfedge(VertexId(a), VertexId(a + 1)).unwrap();
            m.set_edge_sharpness(h.edge(), 10.0);
        }
        m
    }

    #[test]
    fn crease_sides_are_the_planes_of_a_tent() {
        let mesh = tent();
        let mut ring = Ring::new();
        let mut hs = Vec::new();
        let mut faces = Vec::new();
        // The middle of the crease, and a vertex off it (smooth: no sides).
        assert!(ring.load_with_halfedges(&mesh, VertexId(24), Scheme::CatmullClark, &mut hs));
        let (_, n) = ring.limit_sided(&mut faces);
        assert!((n - DVec3::Z).length() < 1e-12, "{n}");
        assert_eq!(faces.len(), 4);
        let up = DVec3::new(0.0, -0.5, 1.0).normalize();
        let down = DVec3::new(0.0, 0.5, 1.0).normalize();
        for (k, f) in faces.iter().enumerate() {
            let face = mesh.face(hs[k]);
            let y: f32 = mesh
                .face_vertices(face)
                .iter()
                .map(|&v| mesh.position(v).y)
                .sum();
            let want = if y > 0.0 { up } else { down };
            assert!((*f - want).length() < 1e-12, "face {k}: {f} want {want}");
        }
        assert!(ring.load(&mesh, VertexId(31), Scheme::CatmullClark));
        ring.limit_sided(&mut faces);
        assert!(faces.is_empty());
        // Loop on the same planes, triangulated: the same two sides.
        let soup = PolygonSoup::from_faces(
            (0..49).map(|v| mesh.position(VertexId(v))).collect(),
            &mesh
                .faces()
                .flat_map(|f| {
                    let v: Vec<u32> = mesh.face_vertices(f).iter().map(|v| v.0).collect();
                    [vec![v[0], v[1], v[2]], vec![v[0], v[2], v[3]]]
                })
                .collect::<Vec<_>>(),
        );
        let mut tri = Mesh::from_soup(&soup).unwrap();
        for a in 21..27u32 {
            let h = tri.find_halfedge(VertexId(a), VertexId(a + 1)).unwrap();
            tri.set_edge_sharpness(h.edge(), 10.0);
        }
        assert!(ring.load(&tri, VertexId(24), Scheme::Loop));
        ring.limit_sided(&mut faces);
        assert_eq!(faces.len(), 6);
        assert!(
            faces
                .iter()
                .all(|f| (*f - up).length() < 1e-12 || (*f - down).length() < 1e-12)
        );
        assert!(faces.iter().any(|f| (*f - up).length() < 1e-12));
    }

    #[test]
    fn corners_of_a_sharp_cube_have_one_side_per_face() {
        let cube = &subdiv_test_support::cube().obj();
        let mut mesh = Mesh::from_soup(&subdiv_mesh::parse_obj(cube).unwrap()).unwrap();
        for e in 0..mesh.num_edges() {
            mesh.set_edge_sharpness(subdiv_mesh::EdgeId(e as u32), 10.0);
        }
        let mut ring = Ring::new();
        let mut hs = Vec::new();
        let mut faces = Vec::new();
        assert!(ring.load_with_halfedges(&mesh, VertexId(7), Scheme::CatmullClark, &mut hs));
        ring.limit_sided(&mut faces);
        assert_eq!(faces.len(), 3);
        for (k, f) in faces.iter().enumerate() {
            let face = mesh.face(hs[k]);
            let c: glam::Vec3 = mesh
                .face_vertices(face)
                .iter()
                .map(|&v| mesh.position(v))
                .sum();
            let want = ((c / 4.0).as_dvec3() - DVec3::splat(0.5)) * 2.0;
            assert!((*f - want).length() < 1e-12, "face {k}: {f} want {want}");
        }
    }
}
