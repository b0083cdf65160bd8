//! `subdiv bench quality`: image error of uniform and adaptive tessellations against the true
//! surface (a deeper uniform tessellation), rendered with the real renderer.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, bail};
use glam::Vec3;
use subdiv::BuiltinScene;
use subdiv::depth::DEFAULT_SHADING_ERROR_DEG;
use subdiv::mesh::Camera;
use subdiv::quality::{Config, QualityParams, QualityRun, orbit_cameras};
use subdiv::rules::Depth;
use subdiv::vk::Renderer;

use crate::camera_args::CameraArgs;
use crate::choices::{SceneName, value_name};

/// The camera of `subdiv bench framerate`'s first frame, in `--eye-relative` terms: the default
/// camera of `--scene helmet40` here.
const HELMET40_EYE_RELATIVE: Vec3 = Vec3::new(1.1, 0.55, 0.0);

#[derive(clap::Args, Debug)]
pub struct BenchQualityArgs {
    /// Input cage.
    #[arg(required_unless_present = "scene")]
    pub input: Option<PathBuf>,
    /// A built-in scene instead of an input file: helmet40 (paper Fig. 12). Its default camera
    /// is `subdiv bench framerate`'s first frame (--eye-relative 1.1,0.55,0).
    #[arg(long, conflicts_with = "input")]
    pub scene: Option<SceneName>,
    #[command(flatten)]
    pub camera: CameraArgs,
    /// Measure from N cameras evenly around the up axis (through the target), at the camera's
    /// distance and elevation; maxima and percentiles are over all frames.
    #[arg(long, default_value_t = 1)]
    pub orbit: usize,
    /// Deepest configuration: uniform depths 0..=N and the adaptive modes' max depth.
    #[arg(long, default_value_t = 5)]
    pub max_depth: Depth,
    /// Depth of the reference tessellation (default: max depth + 1); must be deeper than
    /// --max-depth.
    #[arg(long)]
    pub reference_depth: Option<Depth>,
    /// Timed renders per camera and configuration (the median is reported).
    #[arg(long, default_value_t = 3)]
    pub runs: usize,
    /// The pixel-error configurations' normal tolerance in degrees: the angle between the limit
    /// normal and the normal interpolated across the drawn triangles that 99 % of each patch
    /// stays within (180: silhouettes only).
    #[arg(long, value_name = "DEG", default_value_t = DEFAULT_SHADING_ERROR_DEG)]
    pub shading_error: f32,
    /// Give each extra fan of faces at a non-manifold vertex its own vertex (the surface opens
    /// there) instead of refining non-manifold cages as OpenSubdiv does.
    #[arg(long)]
    pub split_nonmanifold: bool,
}

impl BenchQualityArgs {
    /// Refuses flag values the run cannot use, naming the flags.
    fn params(&self) -> anyhow::Result<QualityParams> {
        if self.orbit == 0 {
            bail!("--orbit must be at least 1");
        }
        if self.runs == 0 {
            bail!("--runs must be at least 1");
        }
        if let Some(r) = self.reference_depth
            && r <= self.max_depth
        {
            bail!(
                "--reference-depth {r} is not deeper than --max-depth {}: the reference \
                 must be deeper than every configuration",
                self.max_depth
            );
        }
        let (w, h) = self.camera.size;
        let params = QualityParams {
            size: [w, h],
            max_depth: self.max_depth,
            reference_depth: self.reference_depth,
            timing_runs: self.runs,
            shading_error_deg: self.shading_error,
        };
        params.check()?;
        Ok(params)
    }

    /// The input's name for messages.
    fn label(&self) -> String {
        match (&self.scene, &self.input) {
            (Some(s), _) => format!("scene {}", value_name(s)),
            (None, Some(p)) => p.display().to_string(),
            (None, None) => String::from("(no input)"),
        }
    }

    /// The first camera: the camera flags, or for a built-in scene without them the
    /// frame-rate benchmark's camera.
    fn base_camera(&self, lo: Vec3, hi: Vec3) -> Camera {
        if self.scene.is_some() && !self.camera.has_camera() {
            let args = CameraArgs {
                eye_relative: Some(HELMET40_EYE_RELATIVE),
                ..self.camera.clone()
            };
            return args.camera(lo, hi);
        }
        self.camera.camera(lo, hi)
    }
}

pub fn run(a: &BenchQualityArgs) -> anyhow::Result<ExitCode> {
    let params = a.params()?;
    let cage = match (&a.scene, &a.input) {
        (Some(s), _) => BuiltinScene::from(*s).cage()?,
        (None, Some(p)) => {
            let cage = crate::load::load_cage(p, a.split_nonmanifold, None)?;
            // The configurations are Catmull-Clark (slates, adaptive); a stage naming another
            // scheme is refused rather than measured as a different surface.
            let scheme = crate::load::cage_scheme(p, &cage, None)?;
            if scheme != subdiv::rules::Scheme::CatmullClark {
                bail!(
                    "{}: the stage's subdivisionScheme is {}; bench quality measures \
                     Catmull-Clark tessellations",
                    p.display(),
                    crate::choices::value_name(&crate::choices::SchemeName::from(scheme))
                );
            }
            cage.mesh
        }
        (None, None) => bail!("give an input cage or --scene helmet40"),
    };
    let (lo, hi) = cage.bounds();
    let base = a.base_camera(lo, hi);
    let cameras = orbit_cameras(&base, a.orbit);
    let mut renderer = Renderer::new()?;
    let [w, h] = params.size;
    log::info!(
        "{}: {} faces, {w}x{h}, {} camera(s) from eye {:.4},{:.4},{:.4} (up {:.3},{:.3},{:.3}), \
         reference uniform depth {} on {}",
        a.label(),
        cage.num_faces(),
        cameras.len(),
        base.eye.x,
        base.eye.y,
        base.eye.z,
        base.up.x,
        base.up.y,
        base.up.z,
        params.reference_depth(),
        renderer.device_name()
    );
    let spinner = crate::progress::spinner("rendering the reference");
    let run = QualityRun::new(&mut renderer, &cage, &cameras, params);
    spinner.finish_and_clear();
    let run = run.with_context(|| a.label())?;
    log::info!("reference: {} triangles", run.reference_triangles());
    let configs = Config::all(run.params().max_depth).len() as u64;
    let bar = crate::progress::bar(configs, "configurations");
    let results = run.measure_all(&mut renderer, |q| {
        log::info!("done: {q}");
        bar.inc(1);
    });
    bar.finish_and_clear();
    let results = results.with_context(|| a.label())?;
    for q in &results {
        println!("{q}");
    }
    Ok(ExitCode::SUCCESS)
}
