//! `subdiv view`: the interactive Vulkan viewer on the limit surface.
//!
//! Keys (from `subdiv-vk`): left drag rotates, wheel zooms, `W` wireframe overlay, `D` depth
//! colours, `H` DoI heat map, `S` silhouettes, `F` freeze the culling camera, `+`/`-` target
//! frame rate, `C` frame-rate control, `P` screenshot, `Esc`/`Q` quit.

use std::path::PathBuf;
use std::process::ExitCode;

use glam::Vec3;
use subdiv_mesh::Camera;
use subdiv_rules::LimitMesh;
use subdiv::DynamicSubdivision;
use subdiv_vk::viewer::{self, FrameRequest, FrameSource, SourceFrame, ViewerOptions};
use subdiv_vk::{OrbitCamera, OwnedMesh, RenderMesh, Shading, View};

use crate::camera_args::CameraArgs;
use crate::render::{
    DEFAULT_DEPTH, DoiSetup, Scene, Silhouettes, StyleArgs, SurfaceArgs, depth_histogram,
    orbit_camera,
};

/// `subdiv view` arguments.
#[derive(clap::Args, Debug)]
pub struct ViewArgs {
    #[command(flatten)]
    pub surface: SurfaceArgs,
    #[command(flatten)]
    pub camera: CameraArgs,
    #[command(flatten)]
    pub style: StyleArgs,
    /// Render this many frames, save a screenshot to `-o`, and exit (for tests under Xvfb).
    #[arg(long, requires = "output", value_parser = clap::value_parser!(u32).range(1..))]
    pub screenshot_after: Option<u32>,
    /// Screenshot file: the `--screenshot-after` image, and the base name for `P` screenshots
    /// (`shot.png` -> `shot-0001.png`).
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
}

/// The viewer's frame source: fixed limit-surface vertices; silhouettes follow the culling
/// camera (the view camera unless it is frozen with `F`).
struct UniformSource {
    mesh: OwnedMesh,
    silhouettes: Silhouettes,
    lines: Vec<[f32; 3]>,
    faces: String,
    status: String,
}

impl FrameSource for UniformSource {
    fn frame(
        &mut self,
        request: &FrameRequest,
    ) -> Result<SourceFrame<'_>, Box<dyn std::error::Error + Send + Sync>> {
        if request.silhouettes {
            self.silhouettes.lines_into(
                &self.mesh.positions,
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
                ..self.mesh.as_render_mesh()
            },
            status: &self.status,
            // Positions, normals and depth scalars never change.
            vertex_version: Some(0),
        })
    }
}

/// The adaptive frame source: each frame, depths follow the culling camera (frozen with `F`),
/// frame-rate control follows the viewer's `C` and `+`/`-` with the real frame times, and the
/// vertices stay on the GPU while the tessellation's `vertex_version` is unchanged.
struct AdaptiveSource {
    node: DynamicSubdivision,
    /// The target frame rate the node's controller was set up with (`None`: control off).
    control: Option<f32>,
    lines: Vec<[f32; 3]>,
    status: String,
}

/// The `subdiv_mesh::Camera` of a renderer view at `size` pixels.
pub fn camera_from_view(view: &View, size: [u32; 2]) -> Camera {
    let inv = view.view.inverse();
    let up = inv.y_axis.truncate().normalize_or(Vec3::Y);
    let forward = view.forward();
    // Vulkan projection: |proj[1][1]| = 1 / tan(fov_y / 2).
    let fov = 2.0 * (1.0 / view.proj.y_axis.y.abs().max(1e-6)).atan();
    Camera::new(
        view.eye,
        view.eye + forward,
        up,
        fov.to_degrees(),
        size[0].max(1),
        size[1].max(1),
    )
}

impl FrameSource for AdaptiveSource {
    fn frame(
        &mut self,
        request: &FrameRequest,
    ) -> Result<SourceFrame<'_>, Box<dyn std::error::Error + Send + Sync>> {
        let want = request.frame_rate_control.then_some(request.target_fps);
        if want != self.control {
            // The node has no access to its controller's target: a new target restarts it.
            self.node.set_frame_rate_control(want);
            self.control = want;
        }
        let camera = camera_from_view(&request.cull_view, request.size);
        let t = request.last_frame_time.as_secs_f32();
        self.node.update(&camera, (t > 0.0).then_some(t))?;
        let g = self.node.geometry();
        self.lines.clear();
        if request.silhouettes {
            let limit = LimitMesh {
                positions: g.positions.clone(),
                normals: g.normals.clone(),
                face_offsets: (0..=g.indices.len() as u32 / 3).map(|i| i * 3).collect(),
                face_indices: g.indices.clone(),
            };
            Silhouettes::new(&limit).lines_into(
                &g.positions,
                request.cull_view.eye,
                &mut self.lines,
            );
        }
        let cap = self
            .node
            .controller()
            .map_or(self.node.params().max_depth, |c| c.cap());
        self.status = format!(
            "patches per depth {} | maxsd {cap} | {} patches recomputed",
            depth_histogram(g),
            g.patches_recomputed
        );
        Ok(SourceFrame {
            mesh: RenderMesh {
                positions: &g.positions,
                normals: &g.normals,
                triangles: &g.indices,
                edges: None,
                scalars: Some(&g.vertex_depth),
                lines: Some(&self.lines),
            },
            status: &self.status,
            vertex_version: Some(g.vertex_version),
        })
    }
}

/// The DoI frame source (`--doi`): the adaptive Loop mesh of the DoI, refined again whenever the
/// culling camera moves (view-dependent DoIs) and coloured by the DoI with `H`.
struct DoiSource {
    setup: DoiSetup,
    scene: Option<Scene>,
    /// Culling camera (eye, forward) the scene was refined for.
    refined_for: Option<(Vec3, Vec3)>,
    version: u64,
    note: String,
    lines: Vec<[f32; 3]>,
    status: String,
}

impl FrameSource for DoiSource {
    fn frame(
        &mut self,
        request: &FrameRequest,
    ) -> Result<SourceFrame<'_>, Box<dyn std::error::Error + Send + Sync>> {
        let key = (request.cull_view.eye, request.cull_view.forward());
        let stale = match self.refined_for {
            None => true,
            Some(k) => self.setup.is_view_dependent() && k != key,
        };
        if stale {
            let camera = camera_from_view(&request.cull_view, request.size);
            let (scene, note) = self.setup.scene(&camera).map_err(|e| format!("{e:#}"))?;
            self.scene = Some(scene);
            self.note = note;
            self.refined_for = Some(key);
            self.version += 1;
        }
        let scene = self.scene.as_ref().expect("refined above");
        if request.silhouettes {
            scene.silhouettes.lines_into(
                &scene.mesh.positions,
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
                ..scene.mesh.as_render_mesh()
            },
            status: &self.status,
            vertex_version: Some(self.version),
        })
    }
}

/// The initial camera for cage bounds `lo`, `hi` and the orbit camera the viewer starts from
/// (with a note when the orbit can only approximate it).
fn start_camera(a: &ViewArgs, lo: Vec3, hi: Vec3) -> (Camera, OrbitCamera) {
    let camera = a.camera.camera(lo, hi);
    let (orbit, exact) = orbit_camera(&camera, lo, hi);
    if !exact {
        eprintln!(
            "note: the viewer orbits about +Y; the camera's --up and vertical views are approximated"
        );
    }
    (camera, orbit)
}

/// Runs the viewer on `source` (screenshot flags from `a`), prints the screenshots written and
/// the closing line `viewed LABEL: N frames[ (NOTE)]`.
fn show<S: FrameSource>(
    a: &ViewArgs,
    source: &mut S,
    mut options: ViewerOptions,
    note: impl FnOnce(&S) -> String,
) -> anyhow::Result<ExitCode> {
    options.screenshot_after = a.screenshot_after;
    options.screenshot_path = a
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from("screenshot.png"));
    let report = viewer::run(source, options)?;
    for shot in &report.screenshots {
        println!("screenshot -> {}", shot.display());
    }
    let note = note(source);
    let note = if note.is_empty() {
        note
    } else {
        format!(" ({note})")
    };
    println!(
        "viewed {}: {} frames{note}",
        a.surface.label(),
        report.frames
    );
    Ok(ExitCode::SUCCESS)
}

/// `subdiv view --doi`.
fn run_doi(a: &ViewArgs) -> anyhow::Result<ExitCode> {
    let mut style = a.style.clone();
    style.doi_values = true;
    let render = style.render_options()?;
    let setup = DoiSetup::new(&a.surface)?;
    let (lo, hi) = setup.bounds();
    let (camera, orbit) = start_camera(a, lo, hi);
    let title = format!(
        "subdiv view {} ({} DoI, {} steps)",
        a.surface.label(),
        a.surface.doi.as_deref().unwrap_or_default(),
        a.surface.steps
    );
    let mut source = DoiSource {
        setup,
        scene: None,
        refined_for: None,
        version: 0,
        note: String::new(),
        lines: Vec::new(),
        status: String::new(),
    };
    let options = ViewerOptions {
        title,
        size: [camera.width, camera.height],
        camera: Some(orbit),
        render,
        ..ViewerOptions::default()
    };
    show(a, &mut source, options, |s| s.note.clone())
}

pub fn run(a: &ViewArgs) -> anyhow::Result<ExitCode> {
    a.surface.check_doi_options()?;
    if a.surface.doi.is_some() {
        return run_doi(a);
    }
    if a.surface.is_adaptive(&a.camera)? {
        return run_adaptive(a);
    }
    let render = a.style.render_options()?;
    let scene = Scene::load(&a.surface)?;
    let (lo, hi) = scene.bounds();
    let (camera, orbit) = start_camera(a, lo, hi);
    let title = format!(
        "subdiv view {} ({}, depth {})",
        a.surface.label(),
        a.surface.scheme,
        a.surface.depth.unwrap_or(DEFAULT_DEPTH)
    );
    let mut source = UniformSource {
        faces: format!("{} faces", scene.faces),
        status: String::new(),
        mesh: scene.mesh,
        silhouettes: scene.silhouettes,
        lines: Vec::new(),
    };
    let options = ViewerOptions {
        title,
        size: [camera.width, camera.height],
        camera: Some(orbit),
        render,
        ..ViewerOptions::default()
    };
    show(a, &mut source, options, |_| String::new())
}

/// `subdiv view` on the adaptive tessellation.
fn run_adaptive(a: &ViewArgs) -> anyhow::Result<ExitCode> {
    let render = a.style.render_options()?;
    if a.surface.cull_camera_eye_relative.is_some() {
        anyhow::bail!(
            "subdiv view: freeze the culling camera with F instead of --cull-camera-eye-relative"
        );
    }
    let cage = a.surface.load_cage()?;
    let (lo, hi) = cage.bounds();
    let (camera, orbit) = start_camera(a, lo, hi);
    let title = format!(
        "subdiv view {} (adaptive, max depth {})",
        a.surface.label(),
        a.surface.adaptive.max_depth
    );
    let mut source = AdaptiveSource {
        node: a.surface.adaptive_node(cage)?,
        control: None,
        lines: Vec::new(),
        status: String::new(),
    };
    let options = ViewerOptions {
        title,
        size: [camera.width, camera.height],
        camera: Some(orbit),
        render,
        // A scripted screenshot shows the view-dependent depths without frame-time feedback.
        frame_rate_control: a.screenshot_after.is_none(),
        ..ViewerOptions::default()
    };
    show(a, &mut source, options, |_| String::new())
}
