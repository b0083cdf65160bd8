//! The viewer's frame sources ([`FrameSource`]): a uniform scene, the per-frame adaptive
//! tessellation, and the DoI-driven adaptive Loop mesh, each with silhouettes for the viewer's
//! culling camera.

use glam::Vec3;
use subdiv_rules::Silhouettes;
use subdiv_vk::viewer::{FrameControl, FrameRequest, FrameSource, SourceFrame};
use subdiv_vk::{RenderMesh, Shading};

use subdiv_mesh::Mesh;
use subdiv_stitch::AssemblyError;

use crate::scene::render_mesh;
use crate::{Control, DoiSetup, DynamicSubdivision, Scene, camera_from_view, depth_histogram};

/// The error type of [`FrameSource::frame`].
type FrameError = Box<dyn std::error::Error + Send + Sync>;

/// `error: cause: cause ...` on one line, as the viewer shows a frame source's error.
fn chain(e: &dyn std::error::Error) -> String {
    let mut s = e.to_string();
    let mut source = e.source();
    while let Some(c) = source {
        s.push_str(": ");
        s.push_str(&c.to_string());
        source = c.source();
    }
    s
}

/// A uniform scene: fixed limit-surface vertices; silhouettes follow the culling camera (the
/// view camera unless it is frozen).
pub struct UniformSource {
    scene: Scene,
    /// Counts the scenes shown ([`UniformSource::set_scene`]): the vertex version.
    version: u64,
    lines: Vec<[f32; 3]>,
    faces: String,
    status: String,
    /// The tessellation's depth (the largest vertex depth).
    depth: Option<u32>,
}

impl UniformSource {
    /// The source showing `scene`.
    pub fn new(scene: Scene) -> UniformSource {
        let mut source = UniformSource {
            depth: None,
            faces: String::new(),
            status: String::new(),
            scene,
            version: 0,
            lines: Vec::new(),
        };
        source.describe();
        source
    }

    /// The scene shown.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// Shows `scene` from the next frame on (a moving cage's next frame): its vertices are
    /// uploaded again.
    pub fn set_scene(&mut self, scene: Scene) {
        self.scene = scene;
        self.version += 1;
        self.describe();
    }

    /// The face count and depth of the scene shown.
    fn describe(&mut self) {
        self.depth = self.scene.surface().scalar().and_then(|(_, s)| {
            s.iter()
                .copied()
                .filter(|d| d.is_finite())
                .reduce(f32::max)
                .map(|d| d.round().max(0.0) as u32)
        });
        self.faces = format!("{} faces", self.scene.faces());
    }
}

impl FrameSource for UniformSource {
    fn frame(&mut self, request: &FrameRequest) -> Result<SourceFrame<'_>, FrameError> {
        if request.silhouettes {
            self.scene.silhouettes().lines_into(
                self.scene.surface().positions(),
                request.cull_view.eye,
                &mut self.lines,
            );
        } else {
            self.lines.clear();
        }
        self.status.clone_from(&self.faces);
        if request.shading == Shading::Doi {
            self.status.push_str(" | no DoI values (uniform heat map)");
        }
        Ok(SourceFrame {
            mesh: RenderMesh {
                lines: Some(&self.lines),
                ..self.scene.render_mesh()
            },
            status: &self.status,
            // Positions, normals and depth scalars change with the scene only.
            vertex_version: Some(self.version),
            dirty_vertices: None,
            depth_cap: self.depth,
            predicted_ms: None,
        })
    }
}

/// The adaptive tessellation: each frame, depths follow the culling camera, frame-rate control
/// follows the viewer's switch and target with the real frame times, and the vertices stay on
/// the GPU while the tessellation's `vertex_version` is unchanged.
pub struct AdaptiveSource {
    node: DynamicSubdivision,
    /// The control and target the node was set up with.
    control: (FrameControl, f32),
    lines: Vec<[f32; 3]>,
    status: String,
}

impl AdaptiveSource {
    /// The source tessellating with `node` (frame-rate control as the viewer asks: its `C`
    /// cycles off, budget, paper).
    pub fn new(node: DynamicSubdivision) -> AdaptiveSource {
        AdaptiveSource {
            node,
            control: (FrameControl::Off, 0.0),
            lines: Vec::new(),
            status: String::new(),
        }
    }
}

impl AdaptiveSource {
    /// Moves the node's cage to `cage` (a moving cage's next frame): its positions when the
    /// topology is the same ([`DynamicSubdivision::set_positions`], the patches kept), else a
    /// node for the new cage with the same scheme and parameters.
    pub fn set_cage(&mut self, cage: Mesh) -> Result<(), AssemblyError> {
        if self.node.mesh().same_topology(&cage) {
            return self.node.set_positions(cage.positions());
        }
        let (scheme, params) = (self.node.scheme(), *self.node.params());
        self.node = DynamicSubdivision::with_scheme(cage, scheme, params)?;
        // The new node has no control yet: the next frame sets the viewer's.
        self.control = (FrameControl::Off, 0.0);
        Ok(())
    }
}

impl FrameSource for AdaptiveSource {
    fn frame(&mut self, request: &FrameRequest) -> Result<SourceFrame<'_>, FrameError> {
        let want = (request.control, request.target_fps);
        if want.0 != self.control.0 {
            let mode = match want.0 {
                FrameControl::Off => Control::Off,
                FrameControl::Budget => Control::Budget,
                FrameControl::Paper => Control::Paper,
            };
            self.node.set_control(mode, want.1);
        } else if want.1 != self.control.1 && want.0.is_on() {
            // A new target keeps the controller (and what it has learnt).
            self.node.set_target_fps(want.1);
        }
        self.control = want;
        let camera = camera_from_view(&request.cull_view, request.size);
        let t = request.last_frame_time.as_secs_f32();
        self.node.update(&camera, (t > 0.0).then_some(t))?;
        let g = self.node.geometry();
        self.lines.clear();
        if request.silhouettes {
            Silhouettes::new(g.surface()).lines_into(
                g.surface().positions(),
                request.cull_view.eye,
                &mut self.lines,
            );
        }
        let cap = self
            .node
            .paper_controller()
            .map_or(self.node.params().max_depth, |c| c.cap());
        self.status = format!(
            "patches per depth {} | maxsd {cap} | {} patches recomputed",
            depth_histogram(g),
            g.patches_recomputed()
        );
        Ok(SourceFrame {
            mesh: RenderMesh {
                lines: Some(&self.lines),
                ..render_mesh(g.surface())
            },
            status: &self.status,
            vertex_version: Some(g.vertex_version()),
            dirty_vertices: Some(g.dirty_vertices()),
            depth_cap: Some(u32::from(cap)),
            predicted_ms: self.node.last_frame().map(|(_, p)| (p * 1e3) as f32),
        })
    }
}

/// The DoI-driven adaptive Loop mesh, refined again whenever the culling camera moves
/// (view-dependent DoIs), with the DoI as the scalar.
pub struct DoiSource {
    setup: DoiSetup,
    scene: Option<Scene>,
    /// Culling camera (eye, forward) the scene was refined for.
    refined_for: Option<(Vec3, Vec3)>,
    version: u64,
    note: String,
    lines: Vec<[f32; 3]>,
    status: String,
}

impl DoiSource {
    /// The source refining with `setup` (the first frame refines).
    pub fn new(setup: DoiSetup) -> DoiSource {
        DoiSource {
            setup,
            scene: None,
            refined_for: None,
            version: 0,
            note: String::new(),
            lines: Vec::new(),
            status: String::new(),
        }
    }

    /// The [`DoiSetup::summary`] of the latest refinement (empty before the first frame).
    pub fn note(&self) -> &str {
        &self.note
    }
}

impl FrameSource for DoiSource {
    fn frame(&mut self, request: &FrameRequest) -> Result<SourceFrame<'_>, FrameError> {
        let key = (request.cull_view.eye, request.cull_view.forward());
        let stale = match self.refined_for {
            None => true,
            Some(k) => self.setup.is_view_dependent() && k != key,
        };
        if stale {
            let camera = camera_from_view(&request.cull_view, request.size);
            let scene = self.setup.scene(&camera).map_err(|e| chain(&e))?;
            self.note = self.setup.summary(scene.faces());
            self.scene = Some(scene);
            self.refined_for = Some(key);
            self.version += 1;
        }
        let scene = self.scene.as_ref().expect("refined above");
        if request.silhouettes {
            scene.silhouettes().lines_into(
                scene.surface().positions(),
                request.cull_view.eye,
                &mut self.lines,
            );
        } else {
            self.lines.clear();
        }
        self.status.clone_from(&self.note);
        if request.shading == Shading::Depth {
            self.status
                .push_str(" | colours show the DoI (no subdivision depths)");
        }
        Ok(SourceFrame {
            mesh: RenderMesh {
                lines: Some(&self.lines),
                ..scene.render_mesh()
            },
            status: &self.status,
            vertex_version: Some(self.version),
            dirty_vertices: None,
            // DoI refinement is driven by the DoI and its steps, not by a depth cap.
            depth_cap: None,
            predicted_ms: None,
        })
    }
}
