//! Uniform tessellation of a moving cage, frame after frame: [`UniformTessellator`] keeps the
//! layout (patches, owners, output numbering, face-varying values) and the output's faces while
//! the cage's topology stays, and rewrites only the limit points and normals of each frame.
//!
//! This is what OpenSubdiv's stencil tables are for: the work that depends on topology alone is
//! done once, the work that depends on positions every frame. Here the per-frame work is the
//! whole slate pipeline (gather, steps, limits) of every patch, which reads the positions; what
//! is kept is the layout and, through the output's topology key, the index buffer
//! ([`LimitMesh::topology_written`] is false on a frame that kept it).

use subdiv_mesh::Mesh;
use subdiv_rules::{Depth, LimitMesh, Scheme, VertexParams};

use crate::bilinear::{BilinearLayout, tessellate_bilinear, tessellate_bilinear_into};
use crate::layout::PatchLayout;
use crate::primvars::tessellate_primvars;
use crate::size::check_uniform_size;
use crate::tessellate::{SlateError, tessellate, tessellate_layout_into};
use crate::tri::{TriLayout, tessellate_tri, tessellate_tri_layout_into};

/// The layout of one scheme.
#[derive(Debug)]
enum Layout {
    /// Catmull-Clark: the quad slates (boxed: a layout is large).
    Quads(Box<PatchLayout>),
    /// Loop: the triangular slates.
    Tris(Box<TriLayout>),
    /// Bilinear: its patches.
    Bilinear(Box<BilinearLayout>),
    /// Depth 0: the cage's own limit points, made afresh each frame.
    Cage,
}

/// The uniform limit tessellation of a cage that moves between calls (an animated character):
/// [`UniformTessellator::update`] with the cage of a frame rewrites points and normals into
/// the same output, and lays the cage out again only when its topology (faces, sharpness,
/// holes, options, face-varying data: [`Mesh::same_topology`]) changed.
///
/// ```
/// use subdiv_mesh::{parse_obj, Mesh};
/// use subdiv_rules::Scheme;
/// use subdiv_slate::UniformTessellator;
/// let cube = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
///             f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
/// let mut mesh = Mesh::from_soup(&parse_obj(cube)?)?;
/// let mut t = UniformTessellator::new(&mesh, Scheme::CatmullClark, 3).unwrap();
/// assert!(t.surface().topology_written());
/// mesh.positions_mut()[7].z += 0.5; // the next frame
/// let surface = t.update(&mesh).unwrap();
/// assert!(!surface.topology_written()); // the index buffer stays
/// assert_eq!(t.layouts_built(), 1);
/// # Ok::<(), subdiv_mesh::MeshError>(())
/// ```
#[derive(Debug)]
pub struct UniformTessellator {
    scheme: Scheme,
    depth: Depth,
    layout: Layout,
    /// The cage the layout was made for (its positions are those of the last frame).
    cage: Mesh,
    out: LimitMesh,
    built: u64,
}

impl UniformTessellator {
    /// Lays out the `scheme` surface of `mesh` at `depth` and tessellates its first frame
    /// (errors as [`tessellate`] and [`tessellate_tri`] give them).
    pub fn new(
        mesh: &Mesh,
        scheme: Scheme,
        depth: Depth,
    ) -> Result<UniformTessellator, SlateError> {
        let mut t = UniformTessellator {
            scheme,
            depth,
            layout: Layout::Cage,
            cage: mesh.clone(),
            out: LimitMesh::default(),
            built: 0,
        };
        t.lay_out(mesh)?;
        t.tessellate(mesh)?;
        Ok(t)
    }

    /// The surface of `mesh`, a later frame of the cage: only points and normals (and the
    /// one-sided normals) are rewritten while the topology stays; a cage of another topology
    /// is laid out again first. On an error the last surface is kept.
    pub fn update(&mut self, mesh: &Mesh) -> Result<&LimitMesh, SlateError> {
        if !self.cage.same_topology(mesh) {
            self.lay_out(mesh)?;
            self.cage = mesh.clone();
        } else {
            self.cage.positions_mut().copy_from_slice(mesh.positions());
        }
        self.tessellate(mesh)?;
        Ok(&self.out)
    }

    /// The last frame's surface.
    pub fn surface(&self) -> &LimitMesh {
        &self.out
    }

    /// The last frame's surface, for a caller that rewrites its points for a frame of the same
    /// topology itself (`subdiv-stencil`); its faces are the layout's.
    pub fn surface_mut(&mut self) -> &mut LimitMesh {
        &mut self.out
    }

    /// Whether `mesh` has the topology the layout was made for ([`Mesh::same_topology`]).
    pub fn same_topology(&self, mesh: &Mesh) -> bool {
        self.cage.same_topology(mesh)
    }

    /// The scheme.
    pub fn scheme(&self) -> Scheme {
        self.scheme
    }

    /// The depth.
    pub fn depth(&self) -> Depth {
        self.depth
    }

    /// The parameter point of every point of [`UniformTessellator::surface`] (index: vertex):
    /// the cage face and the `(u, v)` in its domain (`subdiv_eval::Domain`), from the kept
    /// layout ([`PatchLayout::point_params`], [`TriLayout::point_params`]). `None` for the
    /// bilinear scheme and depth 0 (no slate layout), and where the layout gives none (holes,
    /// seams, isolated vertices).
    pub fn point_params(&self) -> Option<VertexParams> {
        match &self.layout {
            Layout::Quads(l) => l.point_params(&self.cage),
            Layout::Tris(l) => l.point_params(&self.cage),
            Layout::Bilinear(_) | Layout::Cage => None,
        }
    }

    /// How many layouts were made: one, plus one per change of topology.
    pub fn layouts_built(&self) -> u64 {
        self.built
    }

    /// Checks `mesh` and makes its layout (refused before allocating, as a first tessellation).
    fn lay_out(&mut self, mesh: &Mesh) -> Result<(), SlateError> {
        subdiv_rules::check_coordinates(mesh)?;
        // (A Loop layout checks the cage is triangles; depth 0 checks as it tessellates.)
        self.layout = match (self.scheme, self.depth) {
            (_, 0) => Layout::Cage,
            (Scheme::CatmullClark, d) => {
                check_uniform_size(mesh, self.scheme, d)?;
                Layout::Quads(Box::new(PatchLayout::new(mesh, d)?))
            }
            (Scheme::Loop, d) => {
                check_uniform_size(mesh, self.scheme, d)?;
                Layout::Tris(Box::new(TriLayout::new(mesh, d)?))
            }
            (Scheme::Bilinear, d) => Layout::Bilinear(Box::new(BilinearLayout::new(mesh, d)?)),
        };
        self.built += 1;
        Ok(())
    }

    fn tessellate(&mut self, mesh: &Mesh) -> Result<(), SlateError> {
        // The level-1 points of n-gons and their neighbours follow the cage.
        if let Layout::Quads(l) = &mut self.layout {
            l.move_to(mesh);
        }
        match &self.layout {
            Layout::Quads(l) => tessellate_layout_into(mesh, l, &mut self.out),
            Layout::Tris(l) => tessellate_tri_layout_into(mesh, l, &mut self.out),
            Layout::Bilinear(l) => tessellate_bilinear_into(mesh, l, &mut self.out),
            Layout::Cage => {
                self.out = match self.scheme {
                    Scheme::CatmullClark => tessellate(mesh, 0)?,
                    Scheme::Loop => tessellate_tri(mesh, 0)?,
                    Scheme::Bilinear => tessellate_bilinear(mesh, 0)?,
                };
                Ok(())
            }
        }?;
        // The cage's primvars follow the surface (none: nothing to do).
        tessellate_primvars(mesh, self.scheme, self.depth, &mut self.out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use subdiv_mesh::PolygonSoup;

    fn cube(triangles: bool) -> Mesh {
        let mut s = subdiv_test_support::cube();
        if triangles {
            s = s.triangulated();
        }
        let p = s.positions.into_iter().map(Vec3::from).collect();
        Mesh::from_soup(&PolygonSoup::from_faces(p, &s.faces)).unwrap()
    }

    /// Every frame equals a fresh tessellation of that frame's cage, bit for bit; the faces are
    /// written on the first frame and after a change of topology only.
    #[test]
    fn each_frame_is_a_fresh_tessellation_and_the_faces_stay() {
        // Catmull-Clark on triangles: every unit through its local level-1 quads.
        let cases = [
            (Scheme::CatmullClark, false),
            (Scheme::CatmullClark, true),
            (Scheme::Loop, true),
            (Scheme::Bilinear, true),
        ];
        for (scheme, tris) in cases {
            for depth in [0, 1, 3] {
                let mut mesh = cube(tris);
                let fresh = |m: &Mesh| match scheme {
                    Scheme::CatmullClark => tessellate(m, depth).unwrap(),
                    Scheme::Loop => tessellate_tri(m, depth).unwrap(),
                    Scheme::Bilinear => tessellate_bilinear(m, depth).unwrap(),
                };
                let mut t = UniformTessellator::new(&mesh, scheme, depth).unwrap();
                assert_eq!(*t.surface(), fresh(&mesh));
                for frame in 1..4 {
                    for (i, p) in mesh.positions_mut().iter_mut().enumerate() {
                        let a = frame as f32 * 0.3 + i as f32;
                        *p += Vec3::new(a.sin(), a.cos(), 0.5 * a.sin()) * 0.1;
                    }
                    let s = t.update(&mesh).unwrap();
                    assert_eq!(*s, fresh(&mesh), "{scheme:?} depth {depth} frame {frame}");
                    if depth > 0 {
                        assert!(!s.topology_written(), "{scheme:?} depth {depth}");
                    }
                }
                assert_eq!(t.layouts_built(), 1);
                // Another topology: laid out again, faces written.
                let mut sharp = mesh.clone();
                sharp.set_edge_sharpness(subdiv_mesh::EdgeId(0), 2.0);
                let s = t.update(&sharp).unwrap();
                assert!(s.topology_written());
                assert_eq!(*s, fresh(&sharp));
                assert_eq!(t.layouts_built(), 2);
            }
        }
    }

    #[test]
    fn a_cage_the_scheme_refuses_is_an_error_and_the_last_surface_stays() {
        let mesh = cube(false);
        assert!(UniformTessellator::new(&mesh, Scheme::Loop, 2).is_err());
        let mut t = UniformTessellator::new(&mesh, Scheme::CatmullClark, 2).unwrap();
        let before = t.surface().clone();
        let mut bad = mesh.clone();
        bad.positions_mut()[0].x = f32::INFINITY;
        assert!(t.update(&bad).is_err());
        assert_eq!(*t.surface(), before);
    }
}
