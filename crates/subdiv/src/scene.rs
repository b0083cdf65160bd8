//! The uniform limit tessellation, and the drawing helper [`Scene`]: a tessellation in the
//! form the renderer draws (one normal per vertex, split at one-sided normals), with its scalar
//! (the subdivision depth, or a DoI value), polygon edges and what silhouette extraction needs.

use glam::Vec3;
use subdiv_mesh::Mesh;
use subdiv_rules::{
    Depth, LimitMesh, LimitMeshError, RulesError, Scheme, Silhouettes, VertexScalar,
};
use subdiv_slate::SlateError;
use subdiv_vk::RenderMesh;

/// Why a uniform tessellation could not be made or drawn.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The Catmull-Clark slate tessellator refused the cage.
    #[error(transparent)]
    Slate(#[from] SlateError),
    /// The Loop refinement refused the cage.
    #[error(transparent)]
    Rules(#[from] RulesError),
    /// The tessellation broke an invariant of its output type.
    #[error(transparent)]
    Output(#[from] LimitMeshError),
    /// The tessellation has no faces (e.g. every face of the cage is a hole).
    #[error("the limit surface has no faces to draw")]
    Empty,
    /// The primvar asked to be shown is not on the surface.
    #[error("no primvar '{name}' on the surface (it carries: {carried})")]
    NoPrimvar {
        /// The name asked for.
        name: String,
        /// The names it carries, comma-separated (`none` without any).
        carried: String,
    },
}

/// The uniform limit tessellation of `mesh` at `depth` on the slate tessellators: quad slates
/// for Catmull-Clark, triangular slates for Loop, bilinear patches for bilinear. A cage with face-varying data (UVs) gets its
/// face-varying limit values at every corner (`LimitMesh::uvs`). A depth whose output is beyond
/// this machine's memory is refused before anything is allocated
/// ([`SlateError::OutputTooLarge`], with the size asked for).
pub fn uniform_limit(mesh: &Mesh, scheme: Scheme, depth: Depth) -> Result<LimitMesh, SceneError> {
    let t0 = std::time::Instant::now();
    let limit = match scheme {
        Scheme::CatmullClark => subdiv_slate::tessellate(mesh, depth)?,
        // A cage Loop refuses (not triangles, a doubled triangle) is a rules error, as before.
        Scheme::Loop => subdiv_slate::tessellate_tri(mesh, depth).map_err(|e| match e {
            SlateError::Rules(r) => SceneError::Rules(r),
            e => SceneError::Slate(e),
        })?,
        Scheme::Bilinear => subdiv_slate::tessellate_bilinear(mesh, depth)?,
    };
    let mut limit = limit;
    // The cage's primvars on the surface (the same scheme and depth).
    subdiv_slate::tessellate_primvars(mesh, scheme, depth, &mut limit)?;
    log::debug!(
        "uniform {scheme:?} depth {depth}: {} faces -> {} limit points, {} faces in {:.1} ms",
        mesh.num_faces(),
        limit.num_vertices(),
        limit.num_faces(),
        t0.elapsed().as_secs_f64() * 1e3
    );
    Ok(limit)
}

/// What the renderer draws of a tessellated surface: its split form
/// ([`LimitMesh::split_sided`]: triangles, one normal per vertex, the surface's scalar) with
/// every corner's normal on its triangle's side ([`LimitMesh::normals_facing_faces`]), the
/// polygon edges for wireframes, what silhouette extraction needs, and the lines drawn on top.
pub struct Scene {
    /// The split surface; vertex `i` of the tessellation keeps index `i` (but where it is split
    /// by a primvar's values per face corner: [`Scene::show_primvar`]).
    pub(crate) surface: LimitMesh,
    /// Polygon edges, as indices of `surface`.
    pub(crate) edges: Vec<[u32; 2]>,
    pub(crate) silhouettes: Silhouettes,
    /// The positions `silhouettes` indexes, where they are not `surface`'s.
    pub(crate) silhouette_positions: Option<Vec<[f32; 3]>>,
    pub(crate) faces: usize,
    pub(crate) lines: Option<Vec<[f32; 3]>>,
    /// The primvar shown, one value per vertex of `surface`.
    pub(crate) shown: Option<crate::scene_primvar::Shown>,
}

impl Scene {
    /// The uniform tessellation of `cage` at `depth` as a scene; every vertex's scalar is
    /// `depth`. A tessellation without faces is [`SceneError::Empty`].
    pub fn uniform(cage: &Mesh, scheme: Scheme, depth: Depth) -> Result<Scene, SceneError> {
        Scene::from_uniform(uniform_limit(cage, scheme, depth)?, depth)
    }

    /// The scene of a uniform tessellation `limit` at `depth` (every vertex's scalar is
    /// `depth`); a tessellation without faces is [`SceneError::Empty`].
    pub fn from_uniform(mut limit: LimitMesh, depth: Depth) -> Result<Scene, SceneError> {
        if limit.num_faces() == 0 {
            return Err(SceneError::Empty);
        }
        // Uniform tessellation: every vertex sits at the same subdivision depth. The adaptive
        // tessellator sets per-vertex depths of its patches instead.
        let depths = vec![depth as f32; limit.num_vertices()];
        limit.set_scalar(VertexScalar::Depth, depths)?;
        Ok(Scene::from_limit(&limit))
    }

    /// A scene of a tessellation, with its scalar (the subdivision depth that
    /// [`Shading::Depth`](subdiv_vk::Shading::Depth) colours, or a DoI value) when it has one.
    pub fn from_limit(limit: &LimitMesh) -> Scene {
        Scene {
            surface: limit.split_sided(false).normals_facing_faces(),
            edges: limit.edges(),
            silhouettes: Silhouettes::new(limit),
            silhouette_positions: None,
            faces: limit.num_faces(),
            lines: None,
            shown: None,
        }
    }

    /// The split surface drawn ([`LimitMesh::split_sided`] without UVs, normals facing their
    /// faces).
    pub fn surface(&self) -> &LimitMesh {
        &self.surface
    }

    /// Faces per edge, face normals and centres, for silhouettes.
    pub fn silhouettes(&self) -> &Silhouettes {
        &self.silhouettes
    }

    /// Polygons of the tessellation.
    pub fn faces(&self) -> usize {
        self.faces
    }

    /// The line segments drawn on top (pairs of endpoints), if any.
    pub fn lines(&self) -> Option<&[[f32; 3]]> {
        self.lines.as_deref()
    }

    /// Sets the line segments drawn on top (e.g. [`Scene::silhouette_lines`]).
    pub fn set_lines(&mut self, lines: Option<Vec<[f32; 3]>>) {
        self.lines = lines;
    }

    /// The buffers the renderer uploads: triangles, normals, scalars, polygon edges, lines.
    pub fn render_mesh(&self) -> RenderMesh<'_> {
        let mesh = RenderMesh {
            edges: Some(&self.edges),
            lines: self.lines.as_deref(),
            ..render_mesh(&self.surface)
        };
        match &self.shown {
            Some(shown) => shown.apply(mesh),
            None => mesh,
        }
    }

    /// The silhouette edges seen from `eye` as line segments (pairs of endpoints).
    pub fn silhouette_lines(&self, eye: Vec3) -> Vec<[f32; 3]> {
        let mut lines = Vec::new();
        let positions = self
            .silhouette_positions
            .as_deref()
            .unwrap_or(self.surface.positions());
        self.silhouettes.lines_into(positions, eye, &mut lines);
        lines
    }

    /// Axis-aligned bounds of the tessellation.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.surface.bounds()
    }
}

/// The triangle buffers of a triangle-list surface (no one-sided corner normals drawn: the
/// [`LimitMesh::split_sided`] form shows them), its scalar as the render scalars.
pub(crate) fn render_mesh(s: &LimitMesh) -> RenderMesh<'_> {
    RenderMesh {
        positions: s.positions(),
        normals: s.normals(),
        triangles: s.face_indices(),
        edges: None,
        scalars: s.scalar().map(|(_, v)| v),
        colors: None,
        lines: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cage of a cube with every edge infinitely sharp: its limit surface is the cube.
    fn sharp_cube(scheme: Scheme) -> Mesh {
        let cube = subdiv_test_support::cube();
        let text = if scheme == Scheme::Loop {
            cube.triangulated().obj()
        } else {
            cube.obj()
        };
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
                let scene = Scene::uniform(&cage, scheme, depth).unwrap();
                let m = scene.surface();
                for t in m.face_indices().chunks(3) {
                    let p: Vec<Vec3> = t
                        .iter()
                        .map(|&i| Vec3::from(m.positions()[i as usize]))
                        .collect();
                    let flat = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
                    for &i in t {
                        let n = Vec3::from(m.normals()[i as usize]);
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
        let cube = subdiv_mesh::parse_obj(&subdiv_test_support::cube().obj()).unwrap();
        let cage = Mesh::from_soup(&cube).unwrap();
        let scene = Scene::uniform(&cage, Scheme::CatmullClark, 2).unwrap();
        assert_eq!(scene.faces(), 6 * 16);
        let (kind, depths) = scene.surface().scalar().unwrap();
        assert!(kind == VertexScalar::Depth && depths.iter().all(|&s| s == 2.0));
        let (lo, hi) = scene.bounds();
        assert!(lo.cmpge(Vec3::ZERO).all() && hi.cmple(Vec3::ONE).all());
        let e = Scene::uniform(&cage, Scheme::Loop, 1).err().unwrap();
        assert!(matches!(e, SceneError::Rules(_)), "{e}");
    }
}
