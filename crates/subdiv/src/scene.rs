//! The tessellated scene: a limit-surface tessellation packed for the renderer, with one scalar
//! per vertex (the subdivision depth, or a DoI value), one-sided normals at creases, and what
//! silhouette extraction needs.

use std::collections::HashMap;

use glam::Vec3;
use subdiv_mesh::Mesh;
use subdiv_rules::{Depth, LimitMesh, RulesError, Scheme, Silhouettes};
use subdiv_slate::SlateError;
use subdiv_vk::OwnedMesh;

/// Why a uniform tessellation could not be made or drawn.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The Catmull-Clark slate tessellator refused the cage.
    #[error(transparent)]
    Slate(#[from] SlateError),
    /// The Loop refinement refused the cage.
    #[error(transparent)]
    Rules(#[from] RulesError),
    /// The tessellation has no faces (e.g. every face of the cage is a hole).
    #[error("the limit surface has no faces to draw")]
    Empty,
}

/// The uniform limit tessellation of `mesh` at `depth` on the slate tessellators: quad slates
/// for Catmull-Clark, triangular slates for Loop. A cage with face-varying data (UVs) gets its
/// face-varying limit values at every corner (`LimitMesh::uvs`). A depth whose output is beyond
/// this machine's memory is refused before anything is allocated
/// ([`SlateError::OutputTooLarge`], with the size asked for).
pub fn uniform_limit(mesh: &Mesh, scheme: Scheme, depth: Depth) -> Result<LimitMesh, SceneError> {
    let t0 = std::time::Instant::now();
    let limit = match scheme {
        Scheme::CatmullClark => subdiv_slate::tessellate(mesh, depth)?,
        // A cage Loop refuses (not triangles, a doubled triangle) is a rules error, as before.
        Scheme::Loop => subdiv_slate::tessellate_loop(mesh, depth).map_err(|e| match e {
            SlateError::Rules(r) => SceneError::Rules(r),
            e => SceneError::Slate(e),
        })?,
    };
    log::debug!(
        "uniform {scheme:?} depth {depth}: {} faces -> {} limit points, {} faces in {:.1} ms",
        mesh.num_faces(),
        limit.positions.len(),
        limit.num_faces(),
        t0.elapsed().as_secs_f64() * 1e3
    );
    Ok(limit)
}

/// A tessellated surface ready to draw: the render mesh (with per-vertex scalars) and what
/// silhouette extraction needs.
pub struct Scene {
    /// Positions, limit normals, triangles, polygon edges and scalars (no lines).
    pub mesh: OwnedMesh,
    /// Faces per edge, face normals and centres, for silhouettes.
    pub silhouettes: Silhouettes,
    /// Polygons of the tessellation.
    pub faces: usize,
}

impl Scene {
    /// The uniform tessellation of `cage` at `depth` as a scene; every vertex's scalar is
    /// `depth`. A tessellation without faces is [`SceneError::Empty`].
    pub fn uniform(cage: &Mesh, scheme: Scheme, depth: Depth) -> Result<Scene, SceneError> {
        let limit = uniform_limit(cage, scheme, depth)?;
        if limit.num_faces() == 0 {
            return Err(SceneError::Empty);
        }
        // Uniform tessellation: every vertex sits at the same subdivision depth. The adaptive
        // tessellator hands per-vertex depths of its patches to `from_limit` instead.
        let depths = vec![depth as f32; limit.positions.len()];
        Ok(Scene::from_limit(limit, depths))
    }

    /// A scene from a tessellation and one scalar per vertex (the subdivision depth that
    /// [`Shading::Depth`](subdiv_vk::Shading::Depth) colours, or a DoI value).
    pub fn from_limit(limit: LimitMesh, vertex_depths: Vec<f32>) -> Scene {
        let silhouettes = Silhouettes::new(&limit);
        let faces = limit.num_faces();
        let mut mesh = OwnedMesh {
            triangles: Vec::new(),
            edges: Some(limit.edges()),
            scalars: Some(vertex_depths),
            lines: None,
            positions: limit.positions.clone(),
            normals: limit.normals.clone(),
        };
        split_sided_vertices(&limit, &mut mesh);
        Scene {
            mesh,
            silhouettes,
            faces,
        }
    }

    /// The silhouette edges seen from `eye` as line segments (pairs of endpoints).
    pub fn silhouette_lines(&self, eye: Vec3) -> Vec<[f32; 3]> {
        let mut lines = Vec::new();
        self.silhouettes
            .lines_into(&self.mesh.positions, eye, &mut lines);
        lines
    }

    /// Axis-aligned bounds of the tessellation.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        subdiv_mesh::point_bounds(self.mesh.positions.iter().map(|p| Vec3::from(*p)))
    }
}

/// Triangulates `limit` into `mesh` (a fan per polygon) with the one-sided normals of the
/// tessellation at creases and corners.
///
/// A point on a crease has one normal per side; a face corner with a one-sided normal gets a
/// vertex of its own per distinct normal (position copied bit for bit, so the surface stays
/// watertight, and scalar copied; edges and silhouettes keep the shared vertices).
pub(crate) fn split_sided_vertices(limit: &LimitMesh, mesh: &mut OwnedMesh) {
    let mut copies: HashMap<(u32, [u32; 3]), u32> = HashMap::new();
    let mut sided = limit.corner_normals.iter().peekable();
    let mut corner = Vec::new();
    for f in 0..limit.num_faces() {
        corner.clear();
        for c in limit.face_offsets[f]..limit.face_offsets[f + 1] {
            let v = limit.face_indices[c as usize];
            let Some(&(_, n)) = sided.next_if(|&&(k, _)| k == c) else {
                corner.push(v);
                continue;
            };
            let id = *copies.entry((v, n.map(f32::to_bits))).or_insert_with(|| {
                mesh.positions.push(limit.positions[v as usize]);
                mesh.normals.push(n);
                if let Some(s) = mesh.scalars.as_mut() {
                    s.push(s[v as usize]);
                }
                mesh.positions.len() as u32 - 1
            });
            corner.push(id);
        }
        for k in 1..corner.len() - 1 {
            mesh.triangles
                .extend_from_slice(&[corner[0], corner[k], corner[k + 1]]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corners_with_one_sided_normals_get_their_own_vertices() {
        // The cube with the normal of its face at every corner: all 24 corners are split, and
        // corners sharing a vertex and a normal share the copy.
        let cc = Scheme::CatmullClark;
        let mut limit = subdiv_rules::tessellate_uniform(&sharp_cube(cc), cc, 0).unwrap();
        let p = |i: u32| Vec3::from(limit.positions[i as usize]);
        limit.corner_normals = (0..limit.face_indices.len() as u32)
            .map(|c| {
                let f = &limit.face_indices[(c / 4 * 4) as usize..][..4];
                let n = (p(f[1]) - p(f[0])).cross(p(f[2]) - p(f[1])).normalize();
                (c, n.to_array())
            })
            .collect();
        let scene = Scene::from_limit(limit.clone(), vec![1.0; 8]);
        let m = &scene.mesh;
        assert_eq!(m.positions.len(), 8 + 24);
        assert_eq!(m.triangles.len(), 6 * 2 * 3);
        assert!(m.triangles.iter().all(|&i| i >= 8));
        for t in m.triangles.chunks(3) {
            let n: Vec<Vec3> = t
                .iter()
                .map(|&i| Vec3::from(m.normals[i as usize]))
                .collect();
            assert!(
                n[0] == n[1] && n[1] == n[2] && n[0].abs().max_element() == 1.0,
                "{n:?}"
            );
            // Copies keep the position's bits.
            for &i in t {
                assert!(limit.positions.contains(&m.positions[i as usize]));
            }
        }
        assert_eq!(m.scalars.as_ref().unwrap().len(), m.positions.len());
        assert_eq!(m.edges.as_ref().unwrap().len(), 12);
        // Without one-sided normals nothing is split, however far the normals lean.
        limit.corner_normals.clear();
        let scene = Scene::from_limit(limit, vec![0.0; 8]);
        assert_eq!(scene.mesh.positions.len(), 8);
    }

    /// The cage of a cube with every edge infinitely sharp: its limit surface is the cube.
    fn sharp_cube(scheme: Scheme) -> Mesh {
        let quads = "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
        let tris = "f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6\nf 1 6 5\nf 3 7 8\nf 3 8 4\n\
                    f 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 8 6\n";
        let faces = if scheme == Scheme::Loop { tris } else { quads };
        let text = format!(
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n{faces}"
        );
        let mut cage = Mesh::from_soup(&subdiv_mesh::parse_obj(&text).unwrap()).unwrap();
        for e in 0..cage.num_edges() as u32 {
            let e = subdiv_mesh::EdgeId(e);
            let [a, b] = cage.edge_vertices(e);
            // Cube edges only (not the triangles' diagonals).
            let d = cage.position(a) - cage.position(b);
            if d.abs().max_element() == d.length() {
                cage.set_edge_sharpness(e, 10.0);
            }
        }
        cage
    }

    #[test]
    fn a_sharp_cube_is_shaded_flat_at_every_depth() {
        for (scheme, depths) in [(Scheme::CatmullClark, 0..=3), (Scheme::Loop, 0..=2)] {
            let cage = sharp_cube(scheme);
            for depth in depths {
                let m = Scene::uniform(&cage, scheme, depth).unwrap().mesh;
                for t in m.triangles.chunks(3) {
                    let p: Vec<Vec3> = t
                        .iter()
                        .map(|&i| Vec3::from(m.positions[i as usize]))
                        .collect();
                    let flat = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
                    for &i in t {
                        let n = Vec3::from(m.normals[i as usize]);
                        assert!(
                            n.dot(flat) > 1.0 - 1e-6,
                            "{scheme:?} depth {depth}: normal {n} on face {flat}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn uniform_scenes_carry_the_depth_and_refuse_empty_surfaces() {
        let cube = subdiv_mesh::parse_obj(
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
             f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n",
        )
        .unwrap();
        let cage = Mesh::from_soup(&cube).unwrap();
        let scene = Scene::uniform(&cage, Scheme::CatmullClark, 2).unwrap();
        assert_eq!(scene.faces, 6 * 16);
        assert!(
            scene
                .mesh
                .scalars
                .as_ref()
                .unwrap()
                .iter()
                .all(|&s| s == 2.0)
        );
        let (lo, hi) = scene.bounds();
        assert!(lo.cmpge(Vec3::ZERO).all() && hi.cmple(Vec3::ONE).all());
        let e = Scene::uniform(&cage, Scheme::Loop, 1).err().unwrap();
        assert!(matches!(e, SceneError::Rules(_)), "{e}");
    }
}
