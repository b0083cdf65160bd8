//! A primvar drawn on a [`Scene`] (`subdiv render --shading primvar:NAME`): a channel of the
//! tessellation, one value per drawn vertex, as colours or as the scalar's heat map.
//!
//! # Invariants
//! - The values drawn are the channel's own, vertex for vertex: a channel with one value per
//!   vertex keeps the scene's numbering; one with a value per face corner (face-varying,
//!   uniform) splits the surface by its values, so seams keep both sides' values, and the
//!   wireframe and silhouettes stay those of the unsplit surface (the same positions, bit for
//!   bit).

use std::collections::HashMap;

use subdiv_rules::{Depth, LimitChannel, LimitMesh, Silhouettes, VertexScalar};
use subdiv_vk::RenderMesh;

use crate::scene::{Scene, SceneError};

/// The name the texture coordinates (a surface's UVs) are shown by.
const UV_NAME: &str = "st";

/// How [`Scene::show_primvar`] draws a primvar.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrimvarDisplay {
    /// One float a value: the heat map of [`Shading::Doi`](subdiv_vk::Shading::Doi), over the
    /// channel's range.
    Heat,
    /// Two floats or more: the first three as red, green and blue (blue 0 for two floats), with
    /// [`Shading::Color`](subdiv_vk::Shading::Color).
    Colors,
}

/// The values a scene draws in place of its scalar or as its colours.
pub(crate) enum Shown {
    Heat(Vec<f32>),
    Colors(Vec<[f32; 3]>),
}

impl Shown {
    /// `mesh` drawing these values.
    pub(crate) fn apply<'a>(&'a self, mesh: RenderMesh<'a>) -> RenderMesh<'a> {
        match self {
            Shown::Heat(v) => RenderMesh {
                scalars: Some(v),
                ..mesh
            },
            Shown::Colors(c) => RenderMesh {
                colors: Some(c),
                ..mesh
            },
        }
    }

    /// The per-vertex `channel` as drawn.
    fn of(channel: &LimitChannel) -> (Shown, PrimvarDisplay) {
        let w = channel.width;
        let n = channel.values.len() / w.max(1);
        if w == 1 {
            return (Shown::Heat(channel.values.clone()), PrimvarDisplay::Heat);
        }
        let colors = (0..n)
            .map(|i| {
                let v = channel.value(i);
                [v[0], v[1], v.get(2).copied().unwrap_or(0.0)]
            })
            .collect();
        (Shown::Colors(colors), PrimvarDisplay::Colors)
    }
}

impl Scene {
    /// The scene of the uniform tessellation `limit` at `depth` (every vertex's scalar `depth`,
    /// as [`Scene::from_uniform`]) showing its primvar `name` (a channel of `limit`, as
    /// [`uniform_limit`](crate::uniform_limit) carries them); how it is shown is returned beside
    /// it; `st` names the surface's texture coordinates (its UVs) unless a channel has that
    /// name. A name the surface does not carry is [`SceneError::NoPrimvar`], naming those it
    /// carries.
    pub fn show_primvar(
        mut limit: LimitMesh,
        depth: Depth,
        name: &str,
    ) -> Result<(Scene, PrimvarDisplay), SceneError> {
        limit.set_scalar(
            VertexScalar::Depth,
            vec![depth as f32; limit.num_vertices()],
        )?;
        Scene::from_limit_showing(limit, name)
    }

    /// The scene of a tessellation `limit` (any: uniform, an adaptive frame's surface; its
    /// scalar kept) showing its primvar `name`, as [`Scene::show_primvar`] shows it.
    pub fn from_limit_showing(
        mut limit: LimitMesh,
        name: &str,
    ) -> Result<(Scene, PrimvarDisplay), SceneError> {
        // The texture coordinates are the surface's UVs (`st`, as `subdiv info` lists them).
        if name == UV_NAME && limit.channel(name).is_none() && !limit.uv_indices().is_empty() {
            let uvs = LimitChannel {
                name: UV_NAME.to_string(),
                width: 2,
                values: limit.uvs().concat(),
                indices: limit.uv_indices().to_vec(),
            };
            limit.push_channel(uvs)?;
        }
        let Some(channel) = limit.channels().iter().find(|c| c.name == name) else {
            let mut names: Vec<&str> = limit.channels().iter().map(|c| c.name.as_str()).collect();
            if !limit.uv_indices().is_empty() {
                names.insert(0, UV_NAME);
            }
            return Err(SceneError::NoPrimvar {
                name: name.to_string(),
                carried: if names.is_empty() {
                    "none".to_string()
                } else {
                    names.join(", ")
                },
            });
        };
        if limit.num_faces() == 0 {
            return Err(SceneError::Empty);
        }
        let mut scene = if channel.per_vertex() {
            Scene::from_limit(&limit)
        } else {
            split_by_corner_values(&limit)
        };
        let channel = scene
            .surface
            .channels()
            .iter()
            .find(|c| c.name == name && c.per_vertex())
            .ok_or_else(|| SceneError::NoPrimvar {
                name: name.to_string(),
                carried: "none drawable per vertex".to_string(),
            })?;
        let (shown, display) = Shown::of(channel);
        scene.shown = Some(shown);
        Ok((scene, display))
    }
}

/// The scene of `limit` split by its per-corner values ([`LimitMesh::split_sided`] with
/// them); its wireframe and silhouettes are `limit`'s, mapped onto the split vertices at the
/// same positions.
fn split_by_corner_values(limit: &LimitMesh) -> Scene {
    let surface = limit.split_sided(true).normals_facing_faces();
    let key = |p: &[f32; 3]| p.map(f32::to_bits);
    let mut at: HashMap<[u32; 3], u32> = HashMap::with_capacity(surface.num_vertices());
    for (i, p) in surface.positions().iter().enumerate() {
        at.entry(key(p)).or_insert(i as u32);
    }
    let positions = limit.positions();
    // Every vertex of a polygon edge is referenced by a face, so it has a copy.
    let edges = limit
        .edges()
        .into_iter()
        .filter_map(|[a, b]| {
            let a = *at.get(&key(&positions[a as usize]))?;
            let b = *at.get(&key(&positions[b as usize]))?;
            Some([a, b])
        })
        .collect();
    Scene {
        edges,
        silhouettes: Silhouettes::new(limit),
        silhouette_positions: Some(positions.to_vec()),
        faces: limit.num_faces(),
        lines: None,
        shown: None,
        surface,
    }
}

#[cfg(test)]
mod tests {
    use subdiv_mesh::{Mesh, parse_obj, read_obj};
    use subdiv_rules::Scheme;

    use subdiv_test_support::colours_from_positions;

    use super::*;
    use crate::uniform_limit;

    /// The sharp-edged pawn with vertex colours (`fixtures/scenes/pawn_colors.obj`).
    fn pawn_colors() -> Mesh {
        read_obj(subdiv_test_support::fixture("scenes/pawn_colors.obj")).unwrap()
    }

    /// A vertex primvar equal to the positions is drawn as the positions, bit for bit, on
    /// every drawn vertex (copies included): the colours are the channel's own values.
    #[test]
    fn a_vertex_primvar_is_drawn_with_the_positions_masks() {
        let path = subdiv_test_support::fixture("scenes/pawn_colors.obj");
        let text = colours_from_positions(&std::fs::read_to_string(path).unwrap());
        let cage = Mesh::from_soup(&parse_obj(&text).unwrap()).unwrap();
        assert_eq!(cage.primvars().len(), 1);
        for depth in [1, 3] {
            let limit = uniform_limit(&cage, Scheme::CatmullClark, depth).unwrap();
            let (scene, display) = Scene::show_primvar(limit, depth, "displayColor").unwrap();
            assert_eq!(display, PrimvarDisplay::Colors);
            let mesh = scene.render_mesh();
            let colors = mesh.colors.unwrap();
            assert_eq!(colors.len(), mesh.positions.len());
            assert!(colors.iter().zip(mesh.positions).all(|(c, p)| c == p));
            // The depth scalar stays for the other shadings.
            assert!(mesh.scalars.unwrap().iter().all(|&s| s == depth as f32));
        }
    }

    /// Texture coordinates split the surface at their seams: both sides keep their values,
    /// while the wireframe and the silhouettes are the unsplit surface's.
    #[test]
    fn face_varying_values_split_the_surface_but_not_its_outline() {
        let cage = read_obj(subdiv_test_support::fixture("meshes/fvar/cube_uv.obj")).unwrap();
        let depth = 2;
        let limit = uniform_limit(&cage, Scheme::CatmullClark, depth).unwrap();
        let plain = Scene::from_uniform(limit.clone(), depth).unwrap();
        let (scene, display) = Scene::show_primvar(limit.clone(), depth, "st").unwrap();
        assert_eq!(display, PrimvarDisplay::Colors);
        let mesh = scene.render_mesh();
        assert!(
            mesh.positions.len() > plain.render_mesh().positions.len(),
            "split at seams"
        );
        // Every drawn corner has the UV of its face corner in the tessellation.
        let (uvs, uv_index) = (limit.uvs(), limit.uv_indices());
        let mut seen = std::collections::HashSet::new();
        for (k, &v) in mesh.triangles.iter().enumerate() {
            let c = mesh.colors.unwrap()[v as usize];
            assert_eq!(c[2], 0.0);
            seen.insert([c[0].to_bits(), c[1].to_bits()]);
            assert!(
                uvs.iter().any(|uv| uv[0] == c[0] && uv[1] == c[1]),
                "corner {k}: {c:?}"
            );
        }
        assert_eq!(seen.len(), {
            let mut used: Vec<u32> = uv_index.to_vec();
            used.sort_unstable();
            used.dedup();
            used.len()
        });
        // The same edges (as segments) and silhouettes as without the primvar.
        let segments = |m: &RenderMesh<'_>| {
            let mut s: Vec<[[u32; 3]; 2]> = m
                .edges
                .unwrap()
                .iter()
                .map(|e| {
                    let mut e = e.map(|v| m.positions[v as usize].map(f32::to_bits));
                    e.sort_unstable();
                    e
                })
                .collect();
            s.sort_unstable();
            s
        };
        assert_eq!(segments(&mesh), segments(&plain.render_mesh()));
        let eye = glam::Vec3::new(3.0, 2.0, 4.0);
        assert_eq!(scene.silhouette_lines(eye), plain.silhouette_lines(eye));
    }

    #[test]
    fn a_missing_primvar_names_those_carried() {
        let limit = uniform_limit(&pawn_colors(), Scheme::CatmullClark, 1).unwrap();
        let e = Scene::show_primvar(limit, 1, "st1").err().unwrap();
        assert_eq!(
            e.to_string(),
            "no primvar 'st1' on the surface (it carries: displayColor)"
        );
    }
}
