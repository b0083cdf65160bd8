//! Limit surfaces of whole meshes: push-to-limit and the uniform depth-N tessellation.

use glam::Vec3;
use rayon::prelude::*;
use subdiv_mesh::{BoundaryInterpolation, Mesh, ObjData, VertexId};

use crate::refine::refine_uniform_levels;
use crate::ring::{Ring, limit_point_with};
use crate::{RulesError, Scheme};

/// A tessellated limit surface: one limit point and unit normal per vertex, and polygons.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LimitMesh {
    /// Limit positions.
    pub positions: Vec<[f32; 3]>,
    /// Unit limit normals (zero only where the surface is fully degenerate).
    pub normals: Vec<[f32; 3]>,
    /// Start of each face in `face_indices`, plus a final end offset.
    pub face_offsets: Vec<u32>,
    /// Vertex indices of all faces, counter-clockwise.
    pub face_indices: Vec<u32>,
}

impl LimitMesh {
    /// Number of faces.
    pub fn num_faces(&self) -> usize {
        self.face_offsets.len().saturating_sub(1)
    }
    /// The vertex indices of face `i`.
    pub fn face(&self, i: usize) -> &[u32] {
        &self.face_indices[self.face_offsets[i] as usize..self.face_offsets[i + 1] as usize]
    }
    /// Triangle list (each polygon as a fan from its first vertex).
    pub fn triangles(&self) -> Vec<u32> {
        let mut t = Vec::with_capacity(self.face_indices.len() * 3);
        for i in 0..self.num_faces() {
            let f = self.face(i);
            for k in 1..f.len() - 1 {
                t.extend_from_slice(&[f[0], f[k], f[k + 1]]);
            }
        }
        t
    }
    /// The distinct polygon edges (for wireframes; no triangulation diagonals).
    pub fn edges(&self) -> Vec<[u32; 2]> {
        let mut e: Vec<[u32; 2]> = Vec::with_capacity(self.face_indices.len());
        for i in 0..self.num_faces() {
            let f = self.face(i);
            for k in 0..f.len() {
                let (a, b) = (f[k], f[(k + 1) % f.len()]);
                e.push([a.min(b), a.max(b)]);
            }
        }
        e.sort_unstable();
        e.dedup();
        e
    }
    /// Axis-aligned bounds `(min, max)`.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| {
                let p = Vec3::from(*p);
                (lo.min(p), hi.max(p))
            },
        )
    }
    /// A view for [`subdiv_mesh::write_obj`].
    pub fn obj_data(&self) -> ObjData<'_> {
        ObjData {
            positions: &self.positions,
            normals: Some(&self.normals),
            face_offsets: &self.face_offsets,
            face_indices: &self.face_indices,
        }
    }
}

/// Push-to-limit: the exact limit point and normal of every vertex of `mesh`, and its visible
/// faces (holes left out), in parallel.
pub fn limit_surface(mesh: &Mesh, scheme: Scheme) -> LimitMesh {
    let n = mesh.num_vertices();
    let mut positions = vec![[0.0f32; 3]; n];
    let mut normals = vec![[0.0f32; 3]; n];
    const CHUNK: usize = 1024;
    positions
        .par_chunks_mut(CHUNK)
        .zip(normals.par_chunks_mut(CHUNK))
        .enumerate()
        .for_each_init(Ring::new, |ring, (c, (ps, ns))| {
            for k in 0..ps.len() {
                let v = VertexId((c * CHUNK + k) as u32);
                let (p, nrm) = limit_point_with(ring, mesh, v, scheme);
                ps[k] = p.to_array();
                ns[k] = nrm.to_array();
            }
        });
    let mut face_offsets = vec![0u32];
    let mut face_indices = Vec::with_capacity(mesh.face_lists().1.len());
    for f in mesh.faces() {
        if mesh.is_hole(f) {
            continue;
        }
        face_indices.extend(mesh.face_vertices(f).iter().map(|v| v.0));
        face_offsets.push(face_indices.len() as u32);
    }
    LimitMesh {
        positions,
        normals,
        face_offsets,
        face_indices,
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
/// assert_eq!(t.positions.len(), 4 + 6 + 24); // V - E + F = 2 at level 2
/// # Ok::<(), subdiv_mesh::MeshError>(())
/// ```
pub fn tessellate_uniform(
    mesh: &Mesh,
    scheme: Scheme,
    depth: u32,
) -> Result<LimitMesh, RulesError> {
    if scheme == Scheme::Loop {
        crate::refine::check_triangles(mesh)?;
    }
    let hidden;
    let base = if mesh.options().boundary == BoundaryInterpolation::None {
        let mut m = mesh.clone();
        let holes: Vec<bool> = m
            .faces()
            .map(|f| m.is_hole(f) || m.face_vertices(f).iter().any(|&v| m.is_boundary_vertex(v)))
            .collect();
        m.set_holes(holes);
        hidden = m;
        &hidden
    } else {
        mesh
    };
    let refined = refine_uniform_levels(base, scheme, depth)?;
    Ok(limit_surface(&refined, scheme))
}
