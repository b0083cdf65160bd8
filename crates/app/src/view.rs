//! `subdiv view`: the interactive Vulkan viewer on the limit surface.
//!
//! Keys (from `subdiv-vk`): left drag rotates, wheel zooms, `W` wireframe overlay, `D` depth
//! colours, `H` DoI heat map, `S` silhouettes, `F` freeze the culling camera, `+`/`-` target
//! frame rate, `C` frame-rate control, `P` screenshot, `Esc`/`Q` quit.

use std::path::PathBuf;
use std::process::ExitCode;

use subdiv_vk::viewer::{self, FrameRequest, FrameSource, SourceFrame, ViewerOptions};
use subdiv_vk::{OwnedMesh, RenderMesh, Shading};

use crate::camera_args::CameraArgs;
use crate::render::{Scene, Silhouettes, StyleArgs, SurfaceArgs, orbit_camera};

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

pub fn run(a: &ViewArgs) -> anyhow::Result<ExitCode> {
    let render = a.style.render_options()?;
    let scene = Scene::load(&a.surface)?;
    let (lo, hi) = scene.bounds();
    let camera = a.camera.camera(lo, hi);
    let (orbit, exact) = orbit_camera(&camera, lo, hi);
    if !exact {
        eprintln!(
            "note: the viewer orbits about +Y; the camera's --up and vertical views are approximated"
        );
    }
    let title = format!(
        "subdiv view {} ({}, depth {})",
        a.surface.input.display(),
        a.surface.scheme,
        a.surface.depth
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
        screenshot_after: a.screenshot_after,
        screenshot_path: a
            .output
            .clone()
            .unwrap_or_else(|| PathBuf::from("screenshot.png")),
        ..ViewerOptions::default()
    };
    let report = viewer::run(&mut source, options)?;
    for shot in &report.screenshots {
        println!("screenshot -> {}", shot.display());
    }
    println!(
        "viewed {}: {} frames",
        a.surface.input.display(),
        report.frames
    );
    Ok(ExitCode::SUCCESS)
}
