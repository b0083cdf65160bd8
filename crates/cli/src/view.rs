//! `subdiv view`: the interactive Vulkan viewer on the limit surface.
//!
//! Keys and mouse: `subdiv_vk::viewer::KEY_HELP`, printed at start and in `subdiv view --help`.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use subdiv::mesh::{Camera, Mesh, UsdReadOptions, UsdStageReader, is_usd_path};
use subdiv::vk::OrbitCamera;
use subdiv::vk::viewer::{self, FrameControl, FrameSource, Playback, ViewerOptions};
use subdiv::{
    AdaptiveSource, AnimatedSource, DoiSource, UniformSource, framing_box, orbit_camera,
    stage_playback,
};

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
    if a.style.primvar().is_some() {
        anyhow::bail!(
            "subdiv view: --shading {} is drawn by `subdiv render`; the viewer shows no \
             primvars",
            a.style.shading_name()
        );
    }
    if a.surface.doi.kind().is_some() {
        return run_doi(a);
    }
    if let Some((stage, playback)) = animated_stage(a)? {
        if a.surface.dicing.dicing()?.is_some() {
            anyhow::bail!(
                "subdiv view: --dicing-rate dices once, for one camera and one time; \
                 give --time T to view a frame of this animated stage diced"
            );
        }
        return run_animated(a, stage, playback);
    }
    let diced = a.surface.dicing_scene(&a.camera, None)?;
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

/// The input's stage and its playback when it is an animated USD stage: playing from the start
/// of its range, or paused at `--time` (and, for a scripted screenshot, paused at the start).
fn animated_stage(a: &ViewArgs) -> anyhow::Result<Option<(UsdStageReader, Playback)>> {
    let Some(input) = a.surface.input.as_ref().filter(|p| is_usd_path(p)) else {
        return Ok(None);
    };
    if a.surface.scene.is_some() {
        return Ok(None);
    }
    let opts = UsdReadOptions {
        prim: a.surface.prim.clone(),
        split_nonmanifold_vertices: a.surface.split_nonmanifold,
        time: None,
    };
    let stage = UsdStageReader::open(input, &opts)?;
    let playing = a.surface.time.is_none() && a.screenshot_after.is_none();
    let playback = stage_playback(&stage, a.surface.time, playing)
        .map_err(|e| anyhow::anyhow!("{}: {e}", input.display()))?;
    Ok(playback.map(|p| (stage, p)))
}

/// `subdiv view` on an animated stage: the cage read at each frame's time code, uniform or
/// adaptive, played at the stage's `timeCodesPerSecond`.
fn run_animated(
    a: &ViewArgs,
    stage: UsdStageReader,
    playback: Playback,
) -> anyhow::Result<ExitCode> {
    let render = a.style.render_options()?;
    if a.surface.cull_camera_eye_relative.is_some() {
        anyhow::bail!(
            "subdiv view: freeze the culling camera with Z instead of --cull-camera-eye-relative"
        );
    }
    let label = a.surface.label();
    let adaptive = a.surface.is_adaptive(&a.camera)?;
    // The cage at the first time code, as every command reads it (--time, else the start).
    let input = a
        .surface
        .input
        .as_deref()
        .context("an animated stage is an input")?;
    let first = crate::load::load_cage(
        input,
        a.surface.split_nonmanifold,
        a.surface.prim.as_deref(),
        Some(playback.time),
    )?;
    let scheme = crate::load::cage_scheme(input, &first, a.surface.scheme.map(Into::into))?;
    let cage = first.mesh;
    // Every view of a cage is framed on the cage (as `render` frames it).
    let (camera, orbit) = start_camera(a, &cage);
    let range = format!("time {}-{}", playback.start, playback.end);
    let (source, title, control) = if adaptive {
        let node = a.surface.adaptive_node(cage, scheme)?;
        let title = format!(
            "subdiv view {label} (adaptive, max depth {}, {range})",
            a.surface.adaptive.max_depth()
        );
        let source = AnimatedSource::adaptive(stage, node, playback.time);
        let control = if a.screenshot_after.is_none() {
            FrameControl::Budget
        } else {
            FrameControl::Off
        };
        (source, title, control)
    } else {
        let depth = a.surface.uniform_depth();
        let request = subdiv::rules::Request::Uniform { scheme, depth };
        a.surface.limit.check(&cage, request, &label)?;
        let source = AnimatedSource::uniform(stage, scheme, depth, playback.time)
            .map_err(|e| anyhow::anyhow!("{label}: {e}"))?;
        let title = format!(
            "subdiv view {label} ({}, depth {depth}, {range})",
            value_name(&crate::choices::SchemeName::from(scheme))
        );
        (source, title, FrameControl::Off)
    };
    let mut source = source;
    let options = ViewerOptions {
        title,
        size: [camera.width, camera.height],
        camera: Some(orbit),
        render,
        control,
        playback: Some(playback),
        ..ViewerOptions::default()
    };
    show(a, &mut source, options, |s| {
        format!("last time {}", s.time())
    })
}
