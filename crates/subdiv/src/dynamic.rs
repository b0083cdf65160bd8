//! The library's front door: view-dependent adaptive tessellation, frame by frame.
//!
//! [`DynamicSubdivision`] is the paper's `DynamicSubdivisionCC` scene-graph node (Settgast et
//! al. 2004, Section 4): it owns the cage, its curvature depths (computed once), the per-patch
//! tessellation cache and the user parameters, and turns a camera (and the last frame time,
//! for frame-rate control) into the frame's geometry. The same node runs a Loop cage (its
//! triangles as patches, [`subdiv_stitch::TriAssembler`]) through the same depth assignment.

use subdiv_depth::{
    Assignment, DepthParams, FrameRateController, PatchErrors, Sphere, VertexData, assign,
    face_spheres_scheme,
};
use subdiv_mesh::{Camera, Mesh};
use subdiv_rules::Scheme;
use subdiv_slate::Depth;
use subdiv_stitch::{Assembler, AssemblyError, FanMethod, FrameGeometry, TriAssembler};

use crate::{patch_errors, patch_errors_loop};

/// The patch assembly of the node's scheme.
#[derive(Debug)]
enum Stitcher {
    /// Catmull-Clark units and quad fans (boxed: the Catmull-Clark patch set is large).
    Quads(Box<Assembler>),
    /// Loop triangles and triangle fans (boxed: with its cached UVs it is large too).
    Tris(Box<TriAssembler>),
}

impl Stitcher {
    fn new(mesh: &Mesh, scheme: Scheme, max_depth: Depth) -> Result<Stitcher, AssemblyError> {
        Ok(match scheme {
            Scheme::CatmullClark => Stitcher::Quads(Box::new(Assembler::new(mesh, max_depth)?)),
            Scheme::Loop => Stitcher::Tris(Box::new(TriAssembler::new(mesh, max_depth)?)),
        })
    }
}

/// View-dependent adaptive Catmull-Clark (or, with [`DynamicSubdivision::with_scheme`], Loop)
/// tessellation with crack-free stitching.
///
/// ```
/// use subdiv_mesh::{read_obj, Camera, glam::Vec3};
/// use subdiv_depth::DepthParams;
/// use subdiv::DynamicSubdivision;
/// # let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/reference/shapes/catmark_pawn.obj");
/// let mesh = read_obj(path).unwrap();
/// let mut node = DynamicSubdivision::new(mesh, DepthParams::default()).unwrap();
/// let (lo, hi) = node.mesh().bounds();
/// let camera = Camera::eye_relative(lo, hi, Vec3::new(0.0, 0.3, 2.5), 45.0, 800, 600);
/// let frame = node.update(&camera, None).unwrap();
/// println!("{} triangles", frame.num_triangles());
/// assert!(frame.num_triangles() > 0);
/// ```
#[derive(Debug)]
pub struct DynamicSubdivision {
    mesh: Mesh,
    scheme: Scheme,
    params: DepthParams,
    vertex: VertexData,
    spheres: Vec<Sphere>,
    errors: Option<PatchErrors>,
    assembler: Stitcher,
    controller: Option<FrameRateController>,
    fixed_depths: Option<Vec<Depth>>,
    assignment: Assignment,
    geometry: FrameGeometry,
}

impl DynamicSubdivision {
    /// Sets up the node for the Catmull-Clark surface of `mesh`: curvature depths, bounding
    /// spheres and patches.
    pub fn new(mesh: Mesh, params: DepthParams) -> Result<DynamicSubdivision, AssemblyError> {
        DynamicSubdivision::with_scheme(mesh, Scheme::CatmullClark, params)
    }

    /// Sets up the node for the `scheme` surface of `mesh` (a Loop cage must be triangles:
    /// [`AssemblyError::Rules`] otherwise).
    pub fn with_scheme(
        mesh: Mesh,
        scheme: Scheme,
        params: DepthParams,
    ) -> Result<DynamicSubdivision, AssemblyError> {
        let assembler = Stitcher::new(&mesh, scheme, params.max_depth)?;
        let vertex =
            VertexData::compute_scheme(&mesh, scheme, params.cone_aperture_deg, params.max_depth);
        let spheres = face_spheres_scheme(&mesh, scheme);
        Ok(DynamicSubdivision {
            mesh,
            scheme,
            params,
            vertex,
            spheres,
            errors: None,
            assembler,
            controller: None,
            fixed_depths: None,
            assignment: Assignment::default(),
            geometry: FrameGeometry::default(),
        })
    }

    /// The cage.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }
    /// The subdivision scheme.
    pub fn scheme(&self) -> Scheme {
        self.scheme
    }
    /// The user parameters.
    pub fn params(&self) -> &DepthParams {
        &self.params
    }
    /// Changes the parameters (curvature depths are recomputed when the aperture or the maximum
    /// depth changes).
    pub fn set_params(&mut self, p: DepthParams) -> Result<(), AssemblyError> {
        let recompute = p.cone_aperture_deg != self.params.cone_aperture_deg
            || p.max_depth != self.params.max_depth;
        if p.max_depth != self.params.max_depth {
            self.assembler = Stitcher::new(&self.mesh, self.scheme, p.max_depth)?;
            self.errors = None;
        }
        self.params = p;
        if recompute {
            self.vertex = VertexData::compute_scheme(
                &self.mesh,
                self.scheme,
                p.cone_aperture_deg,
                p.max_depth,
            );
            self.spheres = face_spheres_scheme(&self.mesh, self.scheme);
        }
        if let Some(c) = &mut self.controller {
            let fps = c.target_fps();
            *c = FrameRateController::new(fps, p.max_depth);
        }
        Ok(())
    }
    /// Moves the cage's vertices (animation, editing): curvature depths, bounding spheres and the
    /// patch cache are recomputed; the topology and tags stay.
    pub fn set_positions(&mut self, positions: &[glam::Vec3]) -> Result<(), AssemblyError> {
        if positions.len() != self.mesh.num_vertices() {
            return Err(AssemblyError::Length {
                what: "positions",
                got: positions.len(),
                want: self.mesh.num_vertices(),
            });
        }
        if let Some(v) = positions.iter().position(|p| !p.is_finite()) {
            return Err(AssemblyError::NonFinite { vertex: v as u32 });
        }
        self.mesh.positions_mut().copy_from_slice(positions);
        self.vertex = VertexData::compute_scheme(
            &self.mesh,
            self.scheme,
            self.params.cone_aperture_deg,
            self.params.max_depth,
        );
        self.spheres = face_spheres_scheme(&self.mesh, self.scheme);
        self.errors = None;
        self.assembler = Stitcher::new(&self.mesh, self.scheme, self.params.max_depth)?;
        Ok(())
    }

    /// Turns frame-rate control on (with a target) or off.
    pub fn set_frame_rate_control(&mut self, target_fps: Option<f32>) {
        self.controller = target_fps.map(|f| FrameRateController::new(f, self.params.max_depth));
    }
    /// Changes the target of the running frame-rate controller without resetting it (turns the
    /// control on if it was off).
    pub fn set_target_fps(&mut self, fps: f32) {
        match &mut self.controller {
            Some(c) => c.set_target_fps(fps),
            None => self.set_frame_rate_control(Some(fps)),
        }
    }
    /// Drops the cached patch tessellations (the next frame recomputes every patch; for
    /// measuring what the cache saves).
    pub fn clear_cache(&mut self) {
        match &mut self.assembler {
            Stitcher::Quads(a) => a.invalidate(),
            Stitcher::Tris(a) => a.invalidate(),
        }
    }
    /// Number of triangles of the uniform tessellation at `depth` (visible faces).
    pub fn uniform_triangles_at(&self, depth: Depth) -> usize {
        let d = depth as u32;
        self.mesh
            .faces()
            .filter(|&f| !self.mesh.is_hole(f))
            .map(|f| {
                let n = self.mesh.face_size(f);
                if self.scheme == Scheme::Loop {
                    1usize << (2 * d)
                } else if n == 4 {
                    2usize << (2 * d)
                } else {
                    n * (2usize << (2 * d.saturating_sub(1)))
                }
            })
            .sum()
    }
    /// The frame-rate controller, when on.
    pub fn controller(&self) -> Option<&FrameRateController> {
        self.controller.as_ref()
    }
    /// Overrides the view-dependent depths with fixed per-face depths (uniform tessellation, or
    /// depths from a Degree-of-Interest function); `None` returns to view-dependent depths.
    pub fn set_face_depths(&mut self, depths: Option<Vec<Depth>>) -> Result<(), AssemblyError> {
        if let Some(d) = &depths
            && d.len() != self.mesh.num_faces()
        {
            return Err(AssemblyError::Length {
                what: "face depths",
                got: d.len(),
                want: self.mesh.num_faces(),
            });
        }
        self.fixed_depths = depths;
        Ok(())
    }
    /// Chooses how quads next to deeper neighbours are closed (Catmull-Clark; a Loop node's
    /// triangle fans have one form and ignore it).
    pub fn set_fan_method(&mut self, m: FanMethod) {
        if let Stitcher::Quads(a) = &mut self.assembler {
            a.set_method(m);
        }
    }
    /// Limit points, normals and curvature depths of the cage vertices.
    pub fn vertex_data(&self) -> &VertexData {
        &self.vertex
    }
    /// The last frame's per-face depths and classes.
    pub fn assignment(&self) -> &Assignment {
        &self.assignment
    }
    /// The last frame's geometry.
    pub fn geometry(&self) -> &FrameGeometry {
        &self.geometry
    }

    /// Computes the frame for `camera`; `last_frame_time` (seconds) feeds the frame-rate
    /// controller when it is on. Only classification, depths, the patches whose depth rose above
    /// their cached depth, and the index buffer are recomputed.
    pub fn update(
        &mut self,
        camera: &Camera,
        last_frame_time: Option<f32>,
    ) -> Result<&FrameGeometry, AssemblyError> {
        if self.params.pixel_error.is_some() {
            self.patch_errors();
        }
        let mut a = match &self.fixed_depths {
            Some(d) => {
                let mut a = assign(
                    &self.mesh,
                    &self.vertex,
                    &self.spheres,
                    None,
                    camera,
                    &self.params,
                );
                a.depth.clone_from(d);
                a
            }
            None => assign(
                &self.mesh,
                &self.vertex,
                &self.spheres,
                self.errors.as_ref(),
                camera,
                &self.params,
            ),
        };
        if let Some(c) = &mut self.controller {
            if let Some(t) = last_frame_time {
                c.update(t);
            }
            c.apply(&mut a);
        }
        for f in self.mesh.faces() {
            if self.mesh.is_hole(f) {
                a.active[f.idx()] = false;
            }
        }
        match &mut self.assembler {
            Stitcher::Quads(asm) => asm.frame(&self.mesh, &a.depth, &a.active, &mut self.geometry),
            Stitcher::Tris(asm) => asm.frame(&self.mesh, &a.depth, &a.active, &mut self.geometry),
        }?;
        self.assignment = a;
        Ok(&self.geometry)
    }

    /// The last frame's quads per depth before gap prevention (Settgast et al. Fig. 6; see
    /// [`subdiv_stitch::Assembler::quads_per_depth`]); for Loop the lattice triangles per depth
    /// ([`TriAssembler::triangles_per_depth`]).
    pub fn quads_per_depth(&self) -> Vec<u64> {
        match &self.assembler {
            Stitcher::Quads(a) => a.quads_per_depth(&self.geometry),
            Stitcher::Tris(a) => a.triangles_per_depth(&self.geometry),
        }
    }

    /// Number of triangles of the uniform tessellation at the maximum depth (for comparison).
    pub fn uniform_triangles(&self) -> usize {
        self.uniform_triangles_at(self.params.max_depth)
    }

    /// What the pixel-error mode knows of each face (chord error per depth, shading outliers
    /// for the current tolerance, normal cone; see [`crate::patch_errors`]), computed on first
    /// use and again when the shading tolerance changes.
    pub fn patch_errors(&mut self) -> &PatchErrors {
        let tolerance = self.params.shading_error_deg.to_radians();
        if self
            .errors
            .as_ref()
            .is_some_and(|e| e.shading_tolerance != tolerance)
        {
            self.errors = None;
        }
        let (mesh, max_depth) = (&self.mesh, self.params.max_depth);
        self.errors.get_or_insert_with(|| match &self.assembler {
            Stitcher::Quads(a) => patch_errors(mesh, a, max_depth, tolerance),
            Stitcher::Tris(a) => patch_errors_loop(mesh, a, max_depth, tolerance),
        })
    }
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use glam::Vec3;

    use subdiv_depth::Class;
    use subdiv_mesh::parse_obj;

    use super::*;

    /// The unit cube: face 0 is `z = 0`, face 1 is `z = 1`, faces 2..=5 the sides.
    fn cube() -> Mesh {
        let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
                   f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
        Mesh::from_soup(&parse_obj(obj).unwrap()).unwrap()
    }

    /// A closed triangular prism (two triangles, three quads).
    fn prism() -> Mesh {
        let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\n\
                   f 1 3 2\nf 4 5 6\nf 1 2 5 4\nf 1 4 6 3\nf 2 3 6 5\n";
        Mesh::from_soup(&parse_obj(obj).unwrap()).unwrap()
    }

    fn params(max_depth: Depth) -> DepthParams {
        DepthParams {
            max_depth,
            projected_size: None,
            ..DepthParams::default()
        }
    }

    /// A camera on the `+z` axis at distance `dist` from the cube's centre, looking at it.
    fn camera_on_z(dist: f32) -> Camera {
        let c = Vec3::splat(0.5);
        Camera::new(c + Vec3::Z * dist, c, Vec3::Y, 45.0, 800, 600)
    }

    /// After welding bitwise equal positions, every edge of a closed surface has exactly two
    /// triangles, in opposite directions.
    fn assert_closed(g: &FrameGeometry) {
        let mut weld: HashMap<[u32; 3], u32> = HashMap::new();
        let id: Vec<u32> = g
            .positions
            .iter()
            .map(|p| {
                let n = weld.len() as u32;
                *weld.entry(p.map(f32::to_bits)).or_insert(n)
            })
            .collect();
        let mut dir: HashMap<(u32, u32), u32> = HashMap::new();
        for t in g.indices.chunks(3) {
            let t = [id[t[0] as usize], id[t[1] as usize], id[t[2] as usize]];
            assert!(
                t[0] != t[1] && t[1] != t[2] && t[0] != t[2],
                "degenerate {t:?}"
            );
            for k in 0..3 {
                *dir.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        for (&(a, b), &c) in &dir {
            assert_eq!(c, 1, "edge {a}->{b} used {c} times");
            assert!(dir.contains_key(&(b, a)), "open edge {a}->{b}");
        }
    }

    #[test]
    fn back_faces_stay_at_depth_zero_front_faces_go_deeper() {
        let mut node = DynamicSubdivision::new(cube(), params(3)).unwrap();
        let g = node.update(&camera_on_z(20.0), None).unwrap().clone();
        let a = node.assignment();
        assert_eq!(a.class[0], Class::Back);
        assert_eq!(a.class[1], Class::Front);
        assert_eq!(a.depth[0], 0);
        assert!(a.depth[1] > 0, "front face depth {}", a.depth[1]);
        for f in 2..6 {
            assert_eq!(a.class[f], Class::Silhouette, "side face {f}");
            assert!(a.depth[f] > 0);
        }
        assert_eq!(g.unit_depth, a.depth);
        assert!(g.num_triangles() < node.uniform_triangles_at(3));
        assert_closed(&g);
        // From the other side the roles swap.
        node.update(&camera_on_z(-20.0), None).unwrap();
        let a = node.assignment();
        assert_eq!((a.class[0], a.class[1]), (Class::Front, Class::Back));
        assert_eq!(a.depth[1], 0);
        assert!(a.depth[0] > 0);
    }

    #[test]
    fn culled_back_faces_are_not_drawn() {
        let p = DepthParams {
            cull_back: true,
            ..params(3)
        };
        let mut node = DynamicSubdivision::new(cube(), p).unwrap();
        let g = node.update(&camera_on_z(20.0), None).unwrap();
        assert_eq!(g.unit_depth[0], u8::MAX);
        assert!(!node.assignment().active[0]);
        assert!(node.assignment().active[1..].iter().all(|&x| x));
    }

    #[test]
    fn fixed_face_depths_are_checked_and_used() {
        let mut node = DynamicSubdivision::new(cube(), params(3)).unwrap();
        let err = node.set_face_depths(Some(vec![1; 5])).unwrap_err();
        assert!(matches!(
            err,
            AssemblyError::Length {
                got: 5,
                want: 6,
                ..
            }
        ));
        let depths = vec![0u8, 3, 1, 2, 1, 2];
        node.set_face_depths(Some(depths.clone())).unwrap();
        // The camera sees face 0 from behind, but the fixed depths win.
        let g = node.update(&camera_on_z(20.0), None).unwrap().clone();
        assert_eq!(g.unit_depth, depths);
        assert_eq!(node.assignment().depth, depths);
        assert_closed(&g);
        // Back to view-dependent depths.
        node.set_face_depths(None).unwrap();
        node.update(&camera_on_z(-20.0), None).unwrap();
        assert_eq!(node.assignment().depth[1], 0);
    }

    #[test]
    fn positions_are_checked_and_name_the_bad_vertex() {
        let mut node = DynamicSubdivision::new(cube(), params(2)).unwrap();
        let mut pos = node.mesh().positions().to_vec();
        pos[3].y = f32::NAN;
        let err = node.set_positions(&pos).unwrap_err();
        assert!(matches!(err, AssemblyError::NonFinite { vertex: 3 }));
        assert!(err.to_string().contains("vertex 3"), "{err}");
        pos[3].y = f32::INFINITY;
        assert!(matches!(
            node.set_positions(&pos),
            Err(AssemblyError::NonFinite { vertex: 3 })
        ));
        assert!(matches!(
            node.set_positions(&pos[..7]),
            Err(AssemblyError::Length {
                got: 7,
                want: 8,
                ..
            })
        ));
        // The cage is unchanged by the refused calls; good positions move it.
        assert_eq!(node.mesh().position(subdiv_mesh::VertexId(3)).y, 1.0);
        let doubled: Vec<Vec3> = cube().positions().iter().map(|p| *p * 2.0).collect();
        node.set_positions(&doubled).unwrap();
        assert_eq!(node.mesh().bounds().1, Vec3::splat(2.0));
        let g = node.update(&camera_on_z(20.0), None).unwrap();
        assert_closed(g);
    }

    #[test]
    fn uniform_triangle_count_matches_a_uniform_frame() {
        // Depth 0 is left out for the prism: its quads touch triangles, so they are level-1
        // units whose depth is clamped to 1 in the frame, while `uniform_triangles_at(0)`
        // counts them as 2 triangles each.
        for (mesh, depths) in [(cube(), 0..=3u8), (prism(), 1..=3)] {
            let nf = mesh.num_faces();
            let mut node = DynamicSubdivision::new(mesh, params(3)).unwrap();
            for d in depths {
                node.set_face_depths(Some(vec![d; nf])).unwrap();
                let g = node.update(&camera_on_z(20.0), None).unwrap();
                assert_eq!(g.num_triangles(), node.uniform_triangles_at(d), "depth {d}");
            }
            assert_eq!(node.uniform_triangles(), node.uniform_triangles_at(3));
        }
    }

    #[test]
    fn frame_rate_control_toggles() {
        let mut node = DynamicSubdivision::new(cube(), params(3)).unwrap();
        assert!(node.controller().is_none());
        node.set_frame_rate_control(Some(30.0));
        let fps = node.controller().map(|c| c.target_fps()).unwrap();
        assert!((fps - 30.0).abs() < 1e-3, "{fps}");
        node.update(&camera_on_z(20.0), Some(0.1)).unwrap();
        assert!(node.controller().is_some());
        node.set_frame_rate_control(None);
        assert!(node.controller().is_none());
        node.set_target_fps(60.0);
        let fps = node.controller().map(|c| c.target_fps()).unwrap();
        assert!((fps - 60.0).abs() < 1e-3, "{fps}");
    }

    /// The Loop icosahedron.
    fn icosahedron() -> Mesh {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../fixtures/reference/shapes/loop_icosahedron.obj"
        );
        Mesh::from_soup(&parse_obj(&std::fs::read_to_string(path).unwrap()).unwrap()).unwrap()
    }

    #[test]
    fn loop_node_runs_every_adaptive_mode_watertight() {
        let mesh = icosahedron();
        let nf = mesh.num_faces();
        let (lo, hi) = mesh.bounds();
        let camera = Camera::eye_relative(lo, hi, Vec3::new(0.3, 0.2, 2.5), 45.0, 800, 600);
        let mut node = DynamicSubdivision::with_scheme(mesh, Scheme::Loop, params(4)).unwrap();
        assert_eq!(node.scheme(), Scheme::Loop);
        // Curvature and classification: back faces at depth 0, front ones deeper.
        let g = node.update(&camera, None).unwrap().clone();
        assert_closed(&g);
        let a = node.assignment().clone();
        assert!(a.class.contains(&Class::Back) && a.class.contains(&Class::Front));
        for f in 0..nf {
            if a.class[f] == Class::Back {
                assert_eq!(a.depth[f], 0);
            }
        }
        assert!(a.depth.iter().any(|&d| d > 0));
        let lattice: u64 = node.quads_per_depth().iter().sum();
        assert!(g.num_triangles() as u64 >= lattice);
        assert!(g.num_triangles() < node.uniform_triangles());
        // Pixel error, projected size, frame-rate control, fixed (DoI) depths, culling.
        node.set_params(DepthParams {
            pixel_error: Some(0.5),
            ..params(4)
        })
        .unwrap();
        assert_closed(&node.update(&camera, None).unwrap().clone());
        assert_eq!(node.patch_errors().faces.len(), nf);
        node.set_params(DepthParams {
            projected_size: Some((2.0, 8.0)),
            ..params(4)
        })
        .unwrap();
        node.set_frame_rate_control(Some(60.0));
        for _ in 0..5 {
            assert_closed(&node.update(&camera, Some(0.5)).unwrap().clone());
        }
        node.set_frame_rate_control(None);
        let depths: Vec<Depth> = (0..nf).map(|f| (f % 5) as Depth).collect();
        node.set_face_depths(Some(depths.clone())).unwrap();
        let g = node.update(&camera, None).unwrap().clone();
        assert_eq!(g.unit_depth, depths);
        assert_closed(&g);
        node.set_face_depths(Some(vec![2; nf])).unwrap();
        let g = node.update(&camera, None).unwrap();
        assert_eq!(g.num_triangles(), node.uniform_triangles_at(2));
    }

    #[test]
    fn loop_node_refuses_quads() {
        let err = DynamicSubdivision::with_scheme(cube(), Scheme::Loop, params(3)).unwrap_err();
        assert!(matches!(err, AssemblyError::Rules(_)), "{err}");
    }

    #[test]
    fn pixel_error_mode_is_watertight() {
        let p = DepthParams {
            pixel_error: Some(0.5),
            ..params(3)
        };
        let mut node = DynamicSubdivision::new(cube(), p).unwrap();
        let g = node.update(&camera_on_z(3.0), None).unwrap().clone();
        assert!(g.num_triangles() > 0);
        assert_closed(&g);
        assert_eq!(node.assignment().depth[0], 0, "back face");
        // Deviations shrink with depth on every face.
        let errors = node.patch_errors().clone();
        assert_eq!(errors.faces.len(), 6);
        assert!(errors.closed);
        for f in &errors.faces {
            let d = &f.deviation;
            assert_eq!(d.len(), 4);
            assert!(d.windows(2).all(|w| w[1] <= w[0]), "{d:?}");
        }
    }
}
