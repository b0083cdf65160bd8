//! The tessellated scene: a limit-surface tessellation packed for the renderer, with one scalar
//! per vertex (the subdivision depth, or a DoI value), normals split at creases, and what
//! silhouette extraction needs.

use glam::Vec3;
use subdiv_mesh::Mesh;
use subdiv_rules::{Depth, LimitMesh, RulesError, Scheme, tessellate_uniform};
use subdiv_slate::SlateError;
use subdiv_vk::OwnedMesh;

use crate::Silhouettes;

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

/// The uniform limit tessellation of `mesh` at `depth`: Catmull-Clark on the slate tessellator,
/// Loop on the whole-mesh refinement.
pub fn uniform_limit(mesh: &Mesh, scheme: Scheme, depth: Depth) -> Result<LimitMesh, SceneError> {
    Ok(match scheme {
        Scheme::CatmullClark => subdiv_slate::tessellate(mesh, depth)?,
        Scheme::Loop => tessellate_uniform(mesh, scheme, depth)?,
    })
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
        split_crease_normals(&limit, &mut mesh);
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
        self.mesh.positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(Vec3::from(*p)), hi.max(Vec3::from(*p))),
        )
    }
}

/// Corners whose limit normal is further than this from their face's normal (cosine) get the
/// face normal instead: 45°.
const CREASE_NORMAL_COS: f32 = std::f32::consts::FRAC_1_SQRT_2;

/// Triangulates `limit` into `mesh` (a fan per polygon) with split normals along creases.
///
/// A vertex on a sharp crease has one limit normal but two one-sided surface normals; shading
/// the faces on both sides with that one normal smears the crease. A face corner whose limit
/// normal deviates by more than 45° from the face's normal gets its own vertex with the face
/// normal (position and scalar copied; edges and silhouettes keep the shared vertices).
fn split_crease_normals(limit: &LimitMesh, mesh: &mut OwnedMesh) {
    let p = |i: u32| Vec3::from(limit.positions[i as usize]);
    let mut corner = Vec::new();
    for f in 0..limit.num_faces() {
        let vs = limit.face(f);
        // Newell's sum about the first corner: about the origin, the cross products of a small
        // face far from it cancel in f32 and leave noise for a normal.
        let o = p(vs[0]);
        let n: Vec3 = (1..vs.len().saturating_sub(1))
            .map(|k| (p(vs[k]) - o).cross(p(vs[k + 1]) - o))
            .sum();
        let n = n.normalize_or_zero();
        corner.clear();
        for &v in vs {
            let limit_normal = Vec3::from(limit.normals[v as usize]);
            if n == Vec3::ZERO || limit_normal.dot(n) >= CREASE_NORMAL_COS {
                corner.push(v);
            } else {
                corner.push(mesh.positions.len() as u32);
                mesh.positions.push(limit.positions[v as usize]);
                mesh.normals.push(n.to_array());
                if let Some(s) = mesh.scalars.as_mut() {
                    s.push(s[v as usize]);
                }
            }
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
    use crate::silhouettes::tests::cube;

    #[test]
    fn crease_corners_get_face_normals() {
        // The cube's corner normals are 54.7° off every face: all 24 corners are split.
        let limit = cube();
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
        }
        assert_eq!(m.scalars.as_ref().unwrap().len(), m.positions.len());
        assert_eq!(m.edges.as_ref().unwrap().len(), 12);
        // Normals within 45° of the face normal stay shared: a tilted-normal quad is not split.
        let quad = LimitMesh {
            positions: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
            ],
            normals: vec![
                [0.0, 0.6, 0.8],
                [0.0, 0.0, 1.0],
                [0.6, 0.0, 0.8],
                [0.0, 0.0, 1.0],
            ],
            face_offsets: vec![0, 4],
            face_indices: vec![0, 1, 2, 3],
        };
        let scene = Scene::from_limit(quad, vec![0.0; 4]);
        assert_eq!(scene.mesh.positions.len(), 4);
        assert_eq!(scene.mesh.triangles, [0, 1, 2, 0, 2, 3]);
    }

    #[test]
    fn small_faces_far_from_the_origin_keep_their_smooth_normals() {
        // Quads of 1e-4 around (1.73, -1.22, 0.31), like deep faces of catmark_pawn: about the
        // origin, the cross products cancel in f32 and the face normal was noise, so corners
        // were split with a wrong (often flipped) normal.
        for k in 0..50 {
            let t = k as f32 * 0.0137;
            let (x, y, z) = (1.7312345 + t, -1.2187654 - t, 0.3123456 + t);
            let s = 1e-4f32;
            let quad = LimitMesh {
                positions: vec![[x, y, z], [x + s, y, z], [x + s, y + s, z], [x, y + s, z]],
                normals: vec![[0.0, 0.0, 1.0]; 4],
                face_offsets: vec![0, 4],
                face_indices: vec![0, 1, 2, 3],
            };
            let scene = Scene::from_limit(quad, vec![6.0; 4]);
            assert_eq!(scene.mesh.positions.len(), 4, "corner split at offset {t}");
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
