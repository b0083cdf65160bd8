//! The library's front door: view-dependent adaptive tessellation, frame by frame.
//!
//! [`DynamicSubdivision`] is the paper's `DynamicSubdivisionCC` scene-graph node (Settgast et
//! al. 2004, Section 4): it owns the cage, its curvature depths (computed once), the per-patch
//! tessellation cache and the user parameters, and turns a camera (and the last frame time,
//! for frame-rate control) into the frame's geometry. The same node runs a Loop cage (its
//! triangles as patches, [`subdiv_stitch::TriAssembler`]) through the same depth assignment.

mod control;

pub use control::Control;

use control::{BudgetInputs, Controller, LastFrame, choose_budget, frame_work, pixels};
use subdiv_depth::{
    Assignment, BudgetController, DepthParams, FaceSpheres, FrameRateController, FrameTimeModel,
    FrameWork, PatchErrors, Seams, VertexData, assign, patch_errors, patch_errors_tri,
};
use subdiv_mesh::{Camera, Mesh};
use subdiv_rules::Scheme;
use subdiv_slate::Depth;
use subdiv_stitch::{
    AdaptiveFrame, Assembler, AssemblyError, FanMethod, TriAssembler, frame_primvars,
};

/// Frames the predictive control draws at the geometric depths while the frame-time model
/// learns the machine (the first frames' times, measured, fit it).
const WARMUP_FRAMES: u64 = 3;

/// [`DynamicSubdivision::flat_depth`] for `scheme`.
fn flat_depths(mesh: &Mesh, scheme: Scheme, p: &DepthParams) -> Option<Vec<Depth>> {
    (scheme == Scheme::Bilinear)
        .then(|| subdiv_depth::bilinear_face_depths(mesh, p.cone_aperture_deg, p.max_depth))
}

/// The patch assembly of the node's scheme.
#[derive(Debug)]
enum Stitcher {
    /// Catmull-Clark (or bilinear) units and quad fans (boxed: the patch set is large).
    Quads(Box<Assembler>),
    /// Loop triangles and triangle fans (boxed: with its cached UVs it is large too).
    Tris(Box<TriAssembler>),
}

impl Stitcher {
    fn new(mesh: &Mesh, scheme: Scheme, max_depth: Depth) -> Result<Stitcher, AssemblyError> {
        Ok(match scheme {
            Scheme::CatmullClark => Stitcher::Quads(Box::new(Assembler::new(mesh, max_depth)?)),
            Scheme::Loop => Stitcher::Tris(Box::new(TriAssembler::new(mesh, max_depth)?)),
            Scheme::Bilinear => Stitcher::Quads(Box::new(Assembler::bilinear(mesh, max_depth)?)),
        })
    }

    /// Unit `u`'s least depth (level-1 units need 1).
    fn min_depth(&self, u: usize) -> Depth {
        match self {
            Stitcher::Quads(a) => a.min_depth(u),
            Stitcher::Tris(_) => 0,
        }
    }

    /// Unit `u`'s cached block depth.
    fn cached_depth(&self, u: usize) -> Option<Depth> {
        match self {
            Stitcher::Quads(a) => a.cached_depth(u),
            Stitcher::Tris(a) => a.cached_depth(u),
        }
    }
}

/// View-dependent adaptive Catmull-Clark (or, with [`DynamicSubdivision::with_scheme`], Loop or
/// bilinear) tessellation with crack-free stitching.
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
    spheres: FaceSpheres,
    errors: Option<PatchErrors>,
    assembler: Stitcher,
    controller: Controller,
    /// A frame's time from its work, fitted from the times `update` is given (every mode).
    model: FrameTimeModel,
    /// The model was given ([`Self::set_frame_model`]), not learnt here: no warm-up frames.
    model_given: bool,
    last: LastFrame,
    fixed_depths: Option<Vec<Depth>>,
    assignment: Assignment,
    geometry: AdaptiveFrame,
    seams: Seams,
    /// Bilinear only, per face: the deepest level its patches' normals need
    /// ([`subdiv_depth::bilinear_face_depths`]). The curvature mode and the paper's controller
    /// draw no face deeper: past it a patch is flat to the cone, however large on screen or
    /// near the silhouette, and deeper levels draw the same picture.
    flat_depth: Option<Vec<Depth>>,
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
        let vertex = VertexData::compute(&mesh, scheme, params.cone_aperture_deg, params.max_depth);
        let spheres = FaceSpheres::new(&mesh, scheme);
        let seams = Seams::new(&mesh);
        let flat_depth = flat_depths(&mesh, scheme, &params);
        Ok(DynamicSubdivision {
            mesh,
            scheme,
            params,
            vertex,
            spheres,
            errors: None,
            assembler,
            controller: Controller::Off,
            model: FrameTimeModel::with_default_prior(),
            model_given: false,
            last: LastFrame::default(),
            fixed_depths: None,
            assignment: Assignment::default(),
            geometry: AdaptiveFrame::default(),
            seams,
            flat_depth,
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
            self.vertex =
                VertexData::compute(&self.mesh, self.scheme, p.cone_aperture_deg, p.max_depth);
            self.flat_depth = flat_depths(&self.mesh, self.scheme, &self.params);
        }
        if let Some(fps) = self.controller.target_fps() {
            self.controller = Controller::new(self.controller.mode(), fps, p.max_depth);
        }
        Ok(())
    }
    /// Moves the cage's vertices (animation, editing): curvature depths, bounding spheres and the
    /// patch cache are recomputed; the topology and tags stay, and so do the patches.
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
        self.vertex = VertexData::compute(
            &self.mesh,
            self.scheme,
            self.params.cone_aperture_deg,
            self.params.max_depth,
        );
        self.spheres.move_to(&self.mesh);
        self.flat_depth = flat_depths(&self.mesh, self.scheme, &self.params);
        self.seams = Seams::new(&self.mesh);
        self.errors = None;
        match &mut self.assembler {
            Stitcher::Quads(a) => a.move_to(&self.mesh),
            Stitcher::Tris(a) => a.invalidate(),
        }
        Ok(())
    }

    /// Turns frame-rate control on with the default (predictive, [`Control::Budget`])
    /// controller aiming at `target_fps`, or off with `None`.
    pub fn set_frame_rate_control(&mut self, target_fps: Option<f32>) {
        match target_fps {
            Some(fps) => self.set_control(Control::Budget, fps),
            None => self.set_control(Control::Off, 0.0),
        }
    }
    /// Chooses the frame-rate control and its target (ignored by [`Control::Off`]); a new
    /// controller starts, the frame-time model keeps what it has learnt.
    pub fn set_control(&mut self, control: Control, target_fps: f32) {
        self.controller = Controller::new(control, target_fps, self.params.max_depth);
    }
    /// The frame-rate control running.
    pub fn control(&self) -> Control {
        self.controller.mode()
    }
    /// The target frame rate, when control is on.
    pub fn target_fps(&self) -> Option<f32> {
        self.controller.target_fps()
    }
    /// Changes the target of the running controller without resetting it (turns the default
    /// control on if it was off).
    pub fn set_target_fps(&mut self, fps: f32) {
        match &mut self.controller {
            Controller::Budget(c) => c.set_target_fps(fps),
            Controller::Paper(c) => c.set_target_fps(fps),
            Controller::Off => self.set_frame_rate_control(Some(fps)),
        }
    }
    /// The paper's feedback controller, when it runs ([`Control::Paper`]).
    pub fn paper_controller(&self) -> Option<&FrameRateController> {
        match &self.controller {
            Controller::Paper(c) => Some(c),
            _ => None,
        }
    }
    /// The predictive controller, when it runs ([`Control::Budget`]).
    pub fn budget_controller(&self) -> Option<&BudgetController> {
        match &self.controller {
            Controller::Budget(c) => Some(c),
            _ => None,
        }
    }
    /// The frame-time model, fitted from the frame times given to [`Self::update`] in every
    /// mode.
    pub fn frame_model(&self) -> &FrameTimeModel {
        &self.model
    }
    /// Replaces the frame-time model (for example by one with known coefficients, to choose
    /// depths for a budget of triangles rather than of time). The predictive control trusts a
    /// given model from the next frame on, without the warm-up frames at the geometric depths
    /// that a model still learning the machine gets.
    pub fn set_frame_model(&mut self, model: FrameTimeModel) {
        self.model = model;
        self.model_given = true;
    }
    /// The last frame's work and the model's prediction of its time (seconds), made when it
    /// was tessellated (before its time was measured).
    pub fn last_frame(&self) -> Option<(FrameWork, f64)> {
        self.last.work.zip(self.last.predicted)
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
    /// Overrides the view-dependent depths with fixed per-face depths (uniform tessellation, or
    /// depths from a Degree-of-Interest function); `None` returns to view-dependent depths.
    /// The faces on one non-manifold edge are still drawn at the largest of their depths.
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
    pub fn geometry(&self) -> &AdaptiveFrame {
        &self.geometry
    }

    /// Computes the frame for `camera`; `last_frame_time` (seconds: how long the previous
    /// frame took, drawing included) fits the frame-time model and feeds the frame-rate
    /// controller when it is on. Only classification, depths, the patches whose depth rose above
    /// their cached depth, and the index buffer are recomputed; the frame's
    /// [`parts`](AdaptiveFrame::parts) say where the time went, and [`Self::last_frame`] what
    /// the model predicts for it.
    pub fn update(
        &mut self,
        camera: &Camera,
        last_frame_time: Option<f32>,
    ) -> Result<&AdaptiveFrame, AssemblyError> {
        let start = std::time::Instant::now();
        if let (Some(t), Some(w), false) = (last_frame_time, self.last.work, self.last.setup) {
            let t = f64::from(t);
            self.model.observe(&w, t);
            match &mut self.controller {
                Controller::Budget(c) => {
                    if let Some(p) = self.last.planned {
                        c.observe(t, p);
                    }
                }
                Controller::Paper(c) => c.update(t as f32),
                Controller::Off => {}
            }
        }
        let budget =
            matches!(self.controller, Controller::Budget(_)) && self.fixed_depths.is_none();
        self.last.setup = false;
        if self.params.pixel_error.is_some() || budget {
            let tolerance = self.params.shading_error_deg.to_radians();
            self.last.setup = !matches!(&self.errors, Some(e) if e.shading_tolerance == tolerance);
            self.patch_errors();
        }
        let errors = if budget { None } else { self.errors.as_ref() };
        let mut a = match &self.fixed_depths {
            Some(d) => {
                let mut a = assign(
                    &self.mesh,
                    &self.vertex,
                    self.spheres.spheres(),
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
                self.spheres.spheres(),
                errors,
                camera,
                &self.params,
            ),
        };
        for f in self.mesh.faces() {
            if self.mesh.is_hole(f) {
                a.active[f.idx()] = false;
            }
        }
        let curvature_mode = self.params.pixel_error.is_none() && !budget;
        let flat = self.flat_depth.as_deref();
        let cap = |a: &mut Assignment| {
            for (d, &most) in a.depth.iter_mut().zip(flat.unwrap_or_default()) {
                *d = (*d).min(most);
            }
        };
        if curvature_mode && self.fixed_depths.is_none() {
            cap(&mut a);
        }
        let px = pixels(&a, camera);
        self.last.planned = None;
        if self.fixed_depths.is_none() {
            match (&mut self.controller, self.errors.as_ref()) {
                (Controller::Paper(c), _) => {
                    c.apply(&mut a);
                    cap(&mut a);
                }
                // Until the model has seen a few frames of this machine, the geometric depths
                // (a sensible picture at a moderate cost) rather than a choice priced by the
                // prior alone; one of those frames a level shallower, so that the fit sees two
                // workloads and can tell the fixed cost from the per-triangle one.
                (Controller::Budget(_), _)
                    if !self.model_given && self.model.frames() < WARMUP_FRAMES =>
                {
                    let second_frame = self.model.frames() == 1;
                    if second_frame {
                        for (u, d) in a.depth.iter_mut().enumerate() {
                            *d = d.saturating_sub(1).max(self.assembler.min_depth(u));
                        }
                    }
                }
                (Controller::Budget(c), Some(errors)) => {
                    let n = a.depth.len();
                    let min_depth: Vec<Depth> =
                        (0..n).map(|u| self.assembler.min_depth(u)).collect();
                    let cached: Vec<Option<Depth>> =
                        (0..n).map(|u| self.assembler.cached_depth(u)).collect();
                    let inputs = BudgetInputs {
                        camera,
                        errors,
                        spheres: self.spheres.spheres(),
                        max_depth: self.params.max_depth,
                        pixels: px,
                    };
                    let planned =
                        choose_budget(c, &self.model, &inputs, &mut a, &min_depth, &cached);
                    self.last.planned = Some(planned);
                }
                _ => {}
            }
        }
        // The faces on the copies of one non-manifold edge (in different manifold pieces,
        // which stitching does not join) at one depth, so the copies get the same points.
        let assembler = &self.assembler;
        self.seams
            .raise(&mut a.depth, &a.active, |u| assembler.min_depth(u));
        let depths = start.elapsed().as_secs_f64();
        match &mut self.assembler {
            Stitcher::Quads(asm) => asm.frame(&self.mesh, &a.depth, &a.active, &mut self.geometry),
            Stitcher::Tris(asm) => asm.frame(&self.mesh, &a.depth, &a.active, &mut self.geometry),
        }?;
        self.geometry.set_depths_time(depths);
        let work = frame_work(&self.geometry, px);
        self.last.work = Some(work);
        self.last.predicted = Some(self.model.predict(&work));
        self.assignment = a;
        Ok(&self.geometry)
    }

    /// Adds the cage's primvars to the last frame's surface (one channel each, until the next
    /// [`update`](Self::update) writes a frame without them; [`subdiv_stitch::frame_primvars`]).
    /// Each three floats of a vertex primvar cost what recomputing the frame's blocks costs, and
    /// each two of a face-varying one a refinement of the cage's face-varying data to the
    /// frame's deepest level, so a frame loop that draws no primvar leaves this out.
    pub fn carry_primvars(&mut self) -> Result<(), AssemblyError> {
        let mesh = &self.mesh;
        let geometry = &mut self.geometry;
        match &self.assembler {
            Stitcher::Quads(a) => frame_primvars(
                mesh,
                |cage| a.stand_in_points(cage),
                |cage, frame| a.stand_in_corner_values(cage, frame),
                geometry,
            ),
            Stitcher::Tris(a) => frame_primvars(
                mesh,
                |cage| a.stand_in_points(cage),
                |cage, frame| a.stand_in_corner_values(cage, frame),
                geometry,
            ),
        }
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
    /// for the current tolerance, normal cone; see [`subdiv_depth::patch_errors`]), computed on first
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
            Stitcher::Quads(a) => patch_errors(mesh, a.patch_set(), max_depth, tolerance),
            Stitcher::Tris(a) => patch_errors_tri(mesh, a.layout(), max_depth, tolerance),
        })
    }
}
