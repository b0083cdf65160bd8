//! Curvature depth per cage vertex with the cone of normals (Shirman and Abi-Ezzi 1993), as in
//! Settgast et al. 2004, Section 3.1: the smallest depth `l` at which the normals of all faces
//! around the vertex at level `l` lie within the cone of aperture `alpha` around its limit
//! normal. Computed once per mesh by refining each vertex's ring locally.

use glam::{DVec3, Vec3};
use rayon::prelude::*;
use subdiv_mesh::{Mesh, VertexId};
use subdiv_rules::{Depth, Ring, Scheme};
use subdiv_slate::bilinear_patch_corners;

/// Limit point, limit normal and curvature depth of every cage vertex.
#[derive(Clone, Debug, Default)]
pub struct VertexData {
    /// Limit positions.
    pub limit: Vec<Vec3>,
    /// Unit limit normals (zero for isolated vertices).
    pub normal: Vec<Vec3>,
    /// Curvature depth (`0..=max_depth`).
    pub depth: Vec<Depth>,
}

impl VertexData {
    /// Computes limit points, normals and curvature depths of all cage vertices of the limit surface of
    /// `scheme` (its rings refined with its rules) for cone aperture `aperture_deg` (the paper's `NormalConeAperture`), capped at `max_depth`.
    ///
    /// ```
    /// use subdiv_mesh::{parse_obj, Mesh};
    /// use subdiv_depth::VertexData;
    /// use subdiv_rules::Scheme;
    /// let cube = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
    ///             f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    /// let mesh = Mesh::from_soup(&parse_obj(cube)?)?;
    /// let v = VertexData::compute(&mesh, Scheme::CatmullClark, 20.0, 5);
    /// // A cube's corners are strongly curved: they need a few levels for a 20 degree cone.
    /// assert!(v.depth.iter().all(|&d| d >= 2));
    /// # Ok::<(), subdiv_mesh::MeshError>(())
    /// ```
    pub fn compute(mesh: &Mesh, scheme: Scheme, aperture_deg: f32, max_depth: Depth) -> VertexData {
        if scheme == Scheme::Bilinear {
            return bilinear_vertex_data(mesh, aperture_deg, max_depth);
        }
        let cos_a = (aperture_deg.to_radians() as f64).cos();
        let per: Vec<(Vec3, Vec3, Depth)> = (0..mesh.num_vertices() as u32)
            .into_par_iter()
            .map_init(Ring::new, |ring, v| {
                let v = VertexId(v);
                if !ring.load(mesh, v, scheme) {
                    return (mesh.position(v), Vec3::ZERO, 0);
                }
                let mut probe = ring.clone();
                let (p, ln) = probe.limit();
                (
                    p.as_vec3(),
                    ln.as_vec3(),
                    cone_depth(ring, ln, cos_a, max_depth),
                )
            })
            .collect();
        VertexData {
            limit: per.iter().map(|x| x.0).collect(),
            normal: per.iter().map(|x| x.1).collect(),
            depth: per.iter().map(|x| x.2).collect(),
        }
    }
}

/// [`VertexData`] of the bilinear surface, whose limit points are the cage's own and whose
/// patches meet with a crease at every edge, so no cone around a vertex ever narrows: a vertex's
/// normal is the mean of its patches' unit normals there, and its depth the deepest its faces
/// need ([`bilinear_face_depths`]).
fn bilinear_vertex_data(mesh: &Mesh, aperture_deg: f32, max_depth: Depth) -> VertexData {
    let mut normal = vec![Vec3::ZERO; mesh.num_vertices()];
    let mut depth: Vec<Depth> = vec![0; mesh.num_vertices()];
    for f in mesh.faces().filter(|&f| !mesh.is_hole(f)) {
        let (d, corners) = bilinear_face(mesh, f, aperture_deg, max_depth);
        for (v, n) in mesh.face_vertices(f).iter().zip(corners) {
            normal[v.idx()] += n;
            depth[v.idx()] = depth[v.idx()].max(d);
        }
    }
    VertexData {
        limit: mesh.positions().to_vec(),
        normal: normal.into_iter().map(Vec3::normalize_or_zero).collect(),
        depth,
    }
}

/// Per cage face of the bilinear surface, the depth at which the normals across each of its
/// sub-patches fit the cone of aperture `aperture_deg` (at most `max_depth`; holes 0). A
/// bilinear patch's normal varies about linearly over it, so a patch whose corner normals
/// spread by `s` needs `ceil(log2(s / alpha))` levels; beyond that its sub-patches are flat to
/// the cone and a deeper level draws the same picture.
pub fn bilinear_face_depths(mesh: &Mesh, aperture_deg: f32, max_depth: Depth) -> Vec<Depth> {
    mesh.faces()
        .map(|f| match mesh.is_hole(f) {
            true => 0,
            false => bilinear_face(mesh, f, aperture_deg, max_depth).0,
        })
        .collect()
}

/// Face `f`'s depth ([`bilinear_face_depths`]) and its patches' unit normals at its corners.
fn bilinear_face(
    mesh: &Mesh,
    f: subdiv_mesh::FaceId,
    aperture_deg: f32,
    max_depth: Depth,
) -> (Depth, Vec<Vec3>) {
    let alpha = aperture_deg.to_radians().max(f32::MIN_POSITIVE);
    let m = mesh.face_size(f);
    // The face's bilinear patches: the quad, or an n-gon's level-1 quads (patch k's corner 0
    // at the face's vertex k).
    let patches: Vec<[Vec3; 4]> = if m == 4 {
        vec![bilinear_patch_corners(mesh, f, None)]
    } else {
        (0..m)
            .map(|k| bilinear_patch_corners(mesh, f, Some(k)))
            .collect()
    };
    let mut spread = 0.0f32;
    let mut corners = Vec::with_capacity(m);
    for q in &patches {
        let corner = |c: usize| (q[(c + 1) % 4] - q[c]).cross(q[(c + 3) % 4] - q[c]);
        let n: [Vec3; 4] = [0, 1, 2, 3].map(|c| corner(c).normalize_or_zero());
        for a in 0..4 {
            for b in a + 1..4 {
                if n[a] != Vec3::ZERO && n[b] != Vec3::ZERO {
                    spread = spread.max(n[a].dot(n[b]).clamp(-1.0, 1.0).acos());
                }
            }
        }
        // A quad's corners are all the face's; an n-gon's patch has one.
        corners.extend_from_slice(&n[..if m == 4 { 4 } else { 1 }]);
    }
    let d = if spread > alpha {
        ((spread / alpha).log2().ceil() as Depth).min(max_depth)
    } else {
        0
    };
    (d, corners)
}

/// The smallest level at which all face normals around the ring's centre are within the cone.
fn cone_depth(ring: &mut Ring, ln: DVec3, cos_a: f64, max_depth: Depth) -> Depth {
    if ln == DVec3::ZERO {
        return 0;
    }
    for l in 0..=max_depth {
        let inside = (0..ring.face_count()).all(|i| {
            let n = ring.face_normal(i);
            n == DVec3::ZERO || n.dot(ln) >= cos_a
        });
        if inside {
            return l;
        }
        ring.refine();
    }
    max_depth
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::PolygonSoup;

    /// An `n x n` grid of quads centred on the origin, at height `f(x, y)`.
    fn grid(n: i32, f: impl Fn(f32, f32) -> f32) -> Mesh {
        let g = subdiv_test_support::height_grid(n as u32, false, -(n / 2) as f32, f);
        let p = g.positions.into_iter().map(Vec3::from).collect();
        Mesh::from_soup(&PolygonSoup::from_faces(p, &g.faces)).unwrap()
    }

    /// A cage vertex of valence 2 takes OpenSubdiv's corner limit masks through `Ring::limit`:
    /// its limit is the vertex itself, its normal `(e0 - v) x (e1 - v)`; the two faces of the
    /// pillow's corner are back to back, so no cone holds them and it gets the most depth.
    #[test]
    fn valence2_vertex_uses_the_corner_masks() {
        let text = std::fs::read_to_string(subdiv_test_support::fixture(
            "reference/shapes/catmark_pillow_valence2.obj",
        ))
        .unwrap();
        let mesh = Mesh::from_soup(&subdiv_mesh::parse_obj(&text).unwrap()).unwrap();
        let v = VertexId(0);
        assert_eq!(mesh.valence(v), 2);
        let data = VertexData::compute(&mesh, Scheme::CatmullClark, 20.0, 5);
        assert_eq!(data.limit[0], mesh.position(v));
        let p = mesh.position(v);
        let e: Vec<Vec3> = mesh
            .outgoing(v)
            .map(|h| mesh.position(mesh.to(h)))
            .collect();
        let want = (e[0] - p).cross(e[1] - p).normalize();
        assert!(
            (data.normal[0] - want).length() < 1e-6,
            "{:?}",
            data.normal[0]
        );
        assert_eq!(data.depth[0], 5);
    }

    #[test]
    fn loop_rings_give_loop_limits_and_cone_depths() {
        // The Loop icosahedron: all vertices alike (valence 5), limit points on a sphere
        // inside the cage, the same curvature depth everywhere, deeper for a narrower cone.
        let text = std::fs::read_to_string(subdiv_test_support::fixture(
            "reference/shapes/loop_icosahedron.obj",
        ))
        .unwrap();
        let mesh = Mesh::from_soup(&subdiv_mesh::parse_obj(&text).unwrap()).unwrap();
        let lim = subdiv_rules::tessellate_uniform(&mesh, Scheme::Loop, 0).unwrap();
        let v = VertexData::compute(&mesh, Scheme::Loop, 10.0, 6);
        for (k, p) in v.limit.iter().enumerate() {
            let want = Vec3::from(lim.positions()[k]);
            assert!((*p - want).length() < 1e-5, "{p} vs {want}");
            assert!(p.length() < mesh.position(VertexId(k as u32)).length());
        }
        assert!(
            v.depth.iter().all(|&d| d == v.depth[0] && d > 0),
            "{:?}",
            v.depth
        );
        let narrow = VertexData::compute(&mesh, Scheme::Loop, 2.0, 6);
        assert!(narrow.depth[0] > v.depth[0]);
        // Catmull-Clark rules on the same cage give other limit points.
        let cc = VertexData::compute(&mesh, Scheme::CatmullClark, 10.0, 6);
        assert!((cc.limit[0] - v.limit[0]).length() > 1e-3);
    }

    #[test]
    fn curved_needs_more_depth_than_flat() {
        let flat = VertexData::compute(&grid(6, |_, _| 0.0), Scheme::CatmullClark, 5.0, 6);
        let bump = VertexData::compute(
            &grid(6, |x, y| 0.4 * (x * x + y * y)),
            Scheme::CatmullClark,
            5.0,
            6,
        );
        let centre = 3 * 7 + 3;
        assert_eq!(flat.depth[centre], 0);
        assert!(bump.depth[centre] == 0 || bump.depth.iter().max() > flat.depth.iter().max());
        // Away from the centre the paraboloid is steep: more depth than the plane.
        let edge_ring = 3 * 7 + 5;
        assert!(
            bump.depth[edge_ring] > flat.depth[edge_ring],
            "{:?}",
            bump.depth
        );
        // A wider cone never needs more depth.
        let wide = VertexData::compute(
            &grid(6, |x, y| 0.4 * (x * x + y * y)),
            Scheme::CatmullClark,
            30.0,
            6,
        );
        assert!(wide.depth.iter().zip(&bump.depth).all(|(w, n)| w <= n));
    }

    /// Bilinear: a cage of planar quads needs no depth however it bends at its edges (its
    /// patches are flat); a twisted quad needs `ceil(log2(spread / aperture))` levels, its
    /// spread the largest angle between its corner normals.
    #[test]
    fn bilinear_depth_follows_the_twist_of_each_patch() {
        let folded = grid(4, |x, _| (x * 0.9).round().abs());
        let v = VertexData::compute(&folded, Scheme::Bilinear, 5.0, 6);
        assert!(v.depth.iter().all(|&d| d == 0), "{:?}", v.depth);
        assert_eq!(v.limit, folded.positions());
        // One quad twisted by lifting a corner: its corner normals spread by `s`.
        let h = 0.5f32;
        let soup = PolygonSoup::from_faces(
            vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, h), Vec3::Y],
            &[vec![0, 1, 2, 3]],
        );
        let quad = Mesh::from_soup(&soup).unwrap();
        // Corner normals: (0,0,1) at 0, (-h,0,1) at 1 and (0,-h,1) at 3 (normalised), so the
        // largest angle lies between corners 1 and 3.
        let (n1, n3) = (
            Vec3::new(-h, 0.0, 1.0).normalize(),
            Vec3::new(0.0, -h, 1.0).normalize(),
        );
        let s = n1.dot(n3).acos();
        for aperture in [2.0f32, 5.0, 10.0, 40.0] {
            let v = VertexData::compute(&quad, Scheme::Bilinear, aperture, 6);
            let want = (s / aperture.to_radians()).log2().ceil().max(0.0) as Depth;
            assert!(
                v.depth.iter().all(|&d| d == want),
                "{aperture}: {:?} {want}",
                v.depth
            );
            assert!(
                v.normal
                    .iter()
                    .all(|n| n.z > 0.8 && (n.length() - 1.0).abs() < 1e-6)
            );
        }
    }
}
