//! `subdiv view`: the interactive Vulkan viewer on the limit surface.
//!
//! Keys (from `subdiv-vk`): left drag rotates, wheel zooms, `W` wireframe overlay, `D` depth
//! colours, `H` DoI heat map, `S` silhouettes, `F` freeze the culling camera, `+`/`-` target
//! frame rate, `C` frame-rate control, `P` screenshot, `Esc`/`Q` quit.

use std::path::PathBuf;
use std::process::ExitCode;

use glam::Vec3;
use subdiv::mesh::Camera;
use subdiv::vk::OrbitCamera;
use subdiv::vk::viewer::{self, FrameSource, ViewerOptions};
use subdiv::{AdaptiveSource, DoiSource, UniformSource, orbit_camera};

use crate::camera_args::CameraArgs;
use crate::choices::value_name;
use crate::surface_args::{StyleArgs, SurfaceArgs};

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
    let label = a.surface.label();
    let setup = a.surface.doi.setup(a.surface.load_cage()?, &label)?;
    let (lo, hi) = setup.bounds();
    let (camera, orbit) = start_camera(a, lo, hi);
    let title = format!(
        "subdiv view {label} ({} DoI, {} steps)",
        setup.kind.name(),
        a.surface.doi.steps
    );
    let mut source = DoiSource::new(setup);
    let options = ViewerOptions {
        title,
        size: [camera.width, camera.height],
        camera: Some(orbit),
        render,
        ..ViewerOptions::default()
    };
    show(a, &mut source, options, |s| s.note().to_string())
}

pub fn run(a: &ViewArgs) -> anyhow::Result<ExitCode> {
    a.surface.check_doi_options()?;
    if a.surface.doi.kind().is_some() {
        return run_doi(a);
    }
    if a.surface.is_adaptive(&a.camera)? {
        return run_adaptive(a);
    }
    let render = a.style.render_options()?;
    let scene = a.surface.uniform_scene()?;
    let (lo, hi) = scene.bounds();
    let (camera, orbit) = start_camera(a, lo, hi);
    let title = format!(
        "subdiv view {} ({}, depth {})",
        a.surface.label(),
        value_name(&a.surface.scheme),
        a.surface.uniform_depth()
    );
    let mut source = UniformSource::new(scene);
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
        a.surface.adaptive.max_depth()
    );
    let mut source = AdaptiveSource::new(a.surface.adaptive_node(cage)?);
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
