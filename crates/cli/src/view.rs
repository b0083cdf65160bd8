//! `subdiv view`: the interactive Vulkan viewer on the limit surface.
//!
//! Keys and mouse: `subdiv_vk::viewer::KEY_HELP`, printed at start and in `subdiv view --help`.

use std::path::PathBuf;
use std::process::ExitCode;

use subdiv::mesh::{Camera, Mesh};
use subdiv::vk::OrbitCamera;
use subdiv::vk::viewer::{self, FrameControl, FrameSource, ViewerOptions};
use subdiv::{AdaptiveSource, DoiSource, UniformSource, framing_box, orbit_camera};

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
    /// Start without the HUD and the colour legend (keys I and L turn them on); screenshots
    /// then equal `subdiv render`.
    #[arg(long)]
    pub no_hud: bool,
    /// Pan by DX,DY pixels (right, down) before the first frame, as a middle drag does.
    #[arg(long, value_name = "DX,DY", value_parser = parse_pan, allow_hyphen_values = true)]
    pub pan: Option<[f32; 2]>,
}

/// `--pan DX,DY`.
fn parse_pan(s: &str) -> Result<[f32; 2], String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|t| t.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("expected DX,DY in pixels: {e}"))?;
    match v[..] {
        [dx, dy] if dx.is_finite() && dy.is_finite() => Ok([dx, dy]),
        _ => Err(format!("expected two finite numbers DX,DY, got '{s}'")),
    }
}

/// The initial camera for `cage` (framed on it, as `subdiv render` frames it) and the orbit
/// camera the viewer starts from and Home/F return to (with a note when the orbit can only
/// approximate it).
fn start_camera(a: &ViewArgs, cage: &Mesh) -> (Camera, OrbitCamera) {
    let camera = a.camera.camera(cage);
    let (lo, hi) = framing_box(cage);
    let (orbit, exact) = orbit_camera(&camera, lo, hi);
    if !exact {
        log::warn!("the viewer orbits about the up axis (--up); a view along it is approximated");
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
    options.hud = !a.no_hud;
    options.render.legend |= !a.no_hud;
    options.pan = a.pan;
    log::info!("{}", viewer::KEY_HELP);
    options.screenshot_path = a
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from("screenshot.png"));
    let report = viewer::run(source, options)?;
    for shot in &report.screenshots {
        out!("screenshot -> {}", shot.display());
    }
    let note = note(source);
    let note = if note.is_empty() {
        note
    } else {
        format!(" ({note})")
    };
    out!(
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
    let setup = a.surface.doi_setup()?;
    let (camera, orbit) = start_camera(a, &setup.cage);
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
        // No frame-rate controller here: draw only when something changes.
        control: FrameControl::Off,
        ..ViewerOptions::default()
    };
    show(a, &mut source, options, |s| s.note().to_string())
}

pub fn run(a: &ViewArgs) -> anyhow::Result<ExitCode> {
    a.surface.check_doi_options()?;
    if a.surface.doi.kind().is_some() {
        return run_doi(a);
    }
    let diced = a.surface.dicing_scene(&a.camera)?;
    if diced.is_none() && a.surface.is_adaptive(&a.camera)? {
        return run_adaptive(a);
    }
    let render = a.style.render_options()?;
    // With --dicing-rate: diced once, for the starting camera.
    let (scene, what, cage) = match diced {
        Some(d) => (d.scene, d.note, d.cage),
        None => {
            let (scene, scheme, cage) = a.surface.uniform_scene()?;
            let what = format!(
                "{}, depth {}",
                value_name(&scheme),
                a.surface.uniform_depth()
            );
            (scene, what, cage)
        }
    };
    let (camera, orbit) = start_camera(a, &cage);
    let title = format!("subdiv view {} ({what})", a.surface.label());
    let mut source = UniformSource::new(scene);
    let options = ViewerOptions {
        title,
        size: [camera.width, camera.height],
        camera: Some(orbit),
        render,
        // A uniform tessellation has no frame-rate controller: draw only when something changes.
        control: FrameControl::Off,
        ..ViewerOptions::default()
    };
    show(a, &mut source, options, |_| String::new())
}

/// `subdiv view` on the adaptive tessellation.
fn run_adaptive(a: &ViewArgs) -> anyhow::Result<ExitCode> {
    let render = a.style.render_options()?;
    if a.surface.cull_camera_eye_relative.is_some() {
        anyhow::bail!(
            "subdiv view: freeze the culling camera with Z instead of --cull-camera-eye-relative"
        );
    }
    let (cage, scheme) = a.surface.load_cage_scheme()?;
    let (camera, orbit) = start_camera(a, &cage);
    let title = format!(
        "subdiv view {} (adaptive, max depth {})",
        a.surface.label(),
        a.surface.adaptive.max_depth()
    );
    let mut source = AdaptiveSource::new(a.surface.adaptive_node(cage, scheme)?);
    let options = ViewerOptions {
        title,
        size: [camera.width, camera.height],
        camera: Some(orbit),
        render,
        // A scripted screenshot shows the view-dependent depths without frame-time feedback.
        control: if a.screenshot_after.is_none() {
            FrameControl::Budget
        } else {
            FrameControl::Off
        },
        ..ViewerOptions::default()
    };
    show(a, &mut source, options, |_| String::new())
}
