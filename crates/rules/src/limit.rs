//! Limit surfaces of whole meshes: push-to-limit and the uniform depth-N tessellation.

use glam::DVec3;
use rayon::prelude::*;
use subdiv_mesh::{Mesh, VertexId};

use crate::refine::refine_uniform_levels_f64;
use crate::ring::Ring;
use crate::{Depth, RulesError, Scheme};

mod bilinear;
mod channel;
mod mesh;
mod params;
mod split;
mod topology;
pub use bilinear::{bilinear_patches, inside_one_patch};
pub use channel::{LimitChannel, face_varying_channel, stand_in_base, vertex_channel};
pub use mesh::{KeyedWrite, LimitMesh, LimitMeshError, TriangleBuffers, VertexScalar};
pub use params::{VertexParams, subface_tiles_per_row};
pub use topology::TopologyKey;
use topology::TopologyStamp;

/// Push-to-limit: the exact limit point and normal of every vertex of `mesh`, and its visible
/// faces (holes left out), in parallel.
pub fn limit_surface(mesh: &Mesh, scheme: Scheme) -> LimitMesh {
    if scheme == Scheme::Bilinear {
        let pos: Vec<DVec3> = mesh.positions().iter().map(|p| p.as_dvec3()).collect();
        return bilinear::bilinear_limit(mesh, &pos, &bilinear_patches(mesh, 0));
    }
    limit_surface_from(mesh, scheme, |w| mesh.position(w).as_dvec3())
}

/// [`limit_surface`] with the vertex positions `pos(w)` instead of the mesh's.
fn limit_surface_from(
    mesh: &Mesh,
    scheme: Scheme,
    pos: impl Fn(VertexId) -> DVec3 + Sync,
) -> LimitMesh {
    let n = mesh.num_vertices();
    let mut positions = vec![[0.0f32; 3]; n];
    let mut normals = vec![[0.0f32; 3]; n];
    const CHUNK: usize = 1024;
    // One-sided normals per (vertex, face), for the vertices that have them.
    let sided: Vec<Vec<(u32, u32, [f32; 3])>> = positions
        .par_chunks_mut(CHUNK)
        .zip(normals.par_chunks_mut(CHUNK))
        .enumerate()
        .map_init(
            || (Ring::new(), Vec::new(), Vec::new()),
            |(ring, hs, faces), (c, (ps, ns))| {
                let mut sided = Vec::new();
                for k in 0..ps.len() {
                    let v = VertexId((c * CHUNK + k) as u32);
                    hs.clear();
                    hs.extend(mesh.outgoing(v));
                    if !ring.load_at(mesh, &pos, v, scheme) {
                        ps[k] = pos(v).as_vec3().to_array();
                        continue;
                    }
                    let (p, nrm) = ring.limit_sided(faces);
                    ps[k] = p.as_vec3().to_array();
                    ns[k] = nrm.as_vec3().to_array();
                    // Ring face `i` is the face of outgoing half-edge `i`.
                    for (&h, f) in hs.iter().zip(faces.iter()) {
                        sided.push((v.0, mesh.face(h).0, f.as_vec3().to_array()));
                    }
                }
                sided
            },
        )
        .collect();
    let mut sided: Vec<(u32, u32, [f32; 3])> = sided.into_iter().flatten().collect();
    sided.sort_unstable_by_key(|&(v, f, _)| (v, f));
    let mut face_offsets = vec![0u32];
    let mut face_indices = Vec::with_capacity(mesh.face_lists().1.len());
    let mut corner_normals = Vec::new();
    let mut uv_indices = Vec::new();
    let (offsets, _) = mesh.face_lists();
    // The exact limit; if the refinement it takes is refused (too large), OpenSubdiv's.
    let limit_uv = crate::limit_face_varying_exact(mesh, scheme)
        .unwrap_or_else(|_| crate::limit_face_varying(mesh, scheme));
    for f in mesh.faces() {
        if mesh.is_hole(f) {
            continue;
        }
        if let Some(fv) = &limit_uv {
            let r = offsets[f.idx()] as usize..offsets[f.idx() + 1] as usize;
            uv_indices.extend_from_slice(&fv.indices[r]);
        }
        for v in mesh.face_vertices(f) {
            if let Ok(k) = sided.binary_search_by_key(&(v.0, f.0), |&(v, f, _)| (v, f)) {
                corner_normals.push((face_indices.len() as u32, sided[k].2));
            }
            face_indices.push(v.0);
        }
        face_offsets.push(face_indices.len() as u32);
    }
    LimitMesh {
        positions,
        normals,
        face_offsets,
        face_indices,
        corner_normals,
        uvs: limit_uv
            .map(|fv| fv.values.iter().map(|t| t.to_array()).collect())
            .unwrap_or_default(),
        uv_indices,
        scalar: None,
        channels: Vec::new(),
        params: None,
        topology: TopologyStamp::default(),
        uniform_faces: 0,
    }
}

/// The uniform depth-`depth` tessellation of the limit surface: the faces of the level-`depth`
/// refinement, whose vertices are the exact limit points (and limit normals) of the level-`depth`
/// vertices. Vertex `i < cage vertices` is the limit of cage vertex `i`.
///
/// With boundary interpolation `None`, faces of the cage touching the boundary are left out (they
/// shape the surface but are not part of it), as in OpenSubdiv.
///
/// ```
/// use subdiv_mesh::{parse_obj, Mesh};
/// use subdiv_rules::{tessellate_uniform, Scheme};
/// let tet = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
/// let mesh = Mesh::from_soup(&parse_obj(tet)?)?;
/// let t = tessellate_uniform(&mesh, Scheme::Loop, 2).unwrap();
/// assert_eq!(t.num_faces(), 4 * 16);
/// assert_eq!(t.positions().len(), 4 + 6 + 24); // V - E + F = 2 at level 2
/// # Ok::<(), subdiv_mesh::MeshError>(())
/// ```
pub fn tessellate_uniform(
    mesh: &Mesh,
    scheme: Scheme,
    depth: Depth,
) -> Result<LimitMesh, RulesError> {
    if scheme == Scheme::Loop {
        mesh.check_triangles()?;
    }
    let (refined, pos) = refine_uniform_levels_f64(mesh, scheme, depth)?;
    if scheme == Scheme::Bilinear {
        let patches = bilinear_patches(mesh, depth);
        return Ok(bilinear::bilinear_limit(&refined, &pos, &patches));
    }
    Ok(limit_surface_from(&refined, scheme, |w| pos[w.idx()]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use subdiv_mesh::PolygonSoup;

    /// A regular (n+1)^2 quad grid with heights from `f`.
    fn quad_grid(n: i32, f: impl Fn(f32, f32) -> f32) -> Mesh {
        let g = subdiv_test_support::height_grid(n as u32, false, -(n / 2) as f32, f);
        let p = g.positions.into_iter().map(Vec3::from).collect();
        Mesh::from_soup(&PolygonSoup::from_faces(p, &g.faces)).unwrap()
    }

    /// A regular triangle lattice (unit spacing) with heights from `f`.
    fn tri_grid(n: i32, f: impl Fn(f32, f32) -> f32) -> Mesh {
        let mut p = Vec::new();
        let h = 3f32.sqrt() / 2.0;
        for j in 0..=n {
            for i in 0..=n {
                let x = (i - n / 2) as f32 + 0.5 * (j - n / 2) as f32;
                let y = (j - n / 2) as f32 * h;
                p.push(Vec3::new(x, y, f(x, y)));
            }
        }
        let w = (n + 1) as u32;
        let mut faces = Vec::new();
        for j in 0..n as u32 {
            for i in 0..n as u32 {
                let a = j * w + i;
                faces.push(vec![a, a + 1, a + w]);
                faces.push(vec![a + 1, a + w + 1, a + w]);
            }
        }
        Mesh::from_soup(&PolygonSoup::from_faces(p, &faces)).unwrap()
    }

    #[test]
    fn regular_quad_grid_is_bicubic_bspline() {
        // The uniform bicubic B-spline reproduces quadratics up to the offset of its knot mask
        // (1/6, 4/6, 1/6): z = x^2 + 2y^2 has limit z + 1/3 + 2/3 at every interior vertex, at
        // every level, and its normal is that of the paraboloid shifted by the same offset.
        let f = |x: f32, y: f32| x * x + 2.0 * y * y;
        let m = quad_grid(8, f);
        for depth in 0..=2u8 {
            let t = tessellate_uniform(&m, Scheme::CatmullClark, depth).unwrap();
            let scale = (1u32 << depth) as f32;
            let mut checked = 0;
            for p in t.positions() {
                let (x, y) = (p[0], p[1]);
                // Interior region only (two cage rings away from the boundary).
                if x.abs() <= 2.0 && y.abs() <= 2.0 {
                    let want = f(x, y) + 1.0;
                    assert!(
                        (p[2] - want).abs() < 1e-4,
                        "depth {depth}: z({x},{y}) = {} want {want}",
                        p[2]
                    );
                    checked += 1;
                }
            }
            assert!(checked as f32 >= (4.0 * scale + 1.0).powi(2));
        }
        // Limit normals are the surface normal (-2x, -4y, 1).
        let t = tessellate_uniform(&m, Scheme::CatmullClark, 1).unwrap();
        for (p, n) in t.positions().iter().zip(t.normals()) {
            if p[0].abs() <= 2.0 && p[1].abs() <= 2.0 {
                let want = Vec3::new(-2.0 * p[0], -4.0 * p[1], 1.0).normalize();
                assert!(Vec3::from(*n).dot(want) > 0.99999, "normal at {p:?}: {n:?}");
            }
        }
    }

    #[test]
    fn regular_triangle_grid_is_quartic_box_spline() {
        // The three-direction quartic box spline at a lattice point: 1/2 centre + 1/12 per
        // neighbour, so z = x^2 + y^2 has limit z + 1/2 on a unit lattice. Quadratics are
        // reproduced, so every point of the limit surface (level-1 vertices too) has that offset.
        let m = tri_grid(10, |x, y| x * x + y * y);
        for (depth, offset) in [(0u8, 0.5f32), (1, 0.5)] {
            let t = tessellate_uniform(&m, Scheme::Loop, depth).unwrap();
            let mut checked = 0;
            for p in t.positions().iter() {
                if p[0].abs() <= 1.5 && p[1].abs() <= 1.5 {
                    let want = p[0] * p[0] + p[1] * p[1] + offset;
                    assert!(
                        (p[2] - want).abs() < 1e-4,
                        "depth {depth}: z = {} want {want}",
                        p[2]
                    );
                    checked += 1;
                }
            }
            assert!(checked >= 9);
        }
    }

    #[test]
    fn sharp_crease_on_grid_is_a_bspline_curve() {
        // An infinitely sharp crease along y = 0 on z = x^2 + y^2: points on the crease follow
        // the cubic B-spline of the crease polygon (limit z = x^2 + 1/3), ignoring the y
        // curvature across it.
        let mut m = quad_grid(8, |x, y| x * x + y * y);
        let on_line: Vec<_> = m.vertices().filter(|&v| m.position(v).y == 0.0).collect();
        for &a in &on_line {
            for h in m.outgoing(a).collect::<Vec<_>>() {
                if m.position(m.to(h)).y == 0.0 {
                    m.set_edge_sharpness(h.edge(), 10.0);
                }
            }
        }
        let t = tessellate_uniform(&m, Scheme::CatmullClark, 2).unwrap();
        for p in t.positions() {
            if p[1] == 0.0 && p[0].abs() <= 2.0 {
                assert!((p[2] - (p[0] * p[0] + 1.0 / 3.0)).abs() < 1e-4, "{p:?}");
            }
        }
    }
}
