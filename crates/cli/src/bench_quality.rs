//! `subdiv bench quality`: image error of uniform and adaptive tessellations against the true
//! surface (a deeper uniform tessellation), rendered with the real renderer.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, bail};
use glam::Vec3;
use subdiv::BuiltinScene;
use subdiv::depth::{DEFAULT_MAX_DEPTH, DEFAULT_SHADING_ERROR_DEG};
use subdiv::mesh::{Camera, Mesh};
use subdiv::rules::{Depth, Request, Scheme};
use subdiv::vk::Renderer;
use subdiv_quality::{Config, CurvatureParams, QualityParams, QualityRun, orbit_cameras};

use crate::camera_args::CameraArgs;
use crate::choices::{SceneName, SchemeName, value_name};
use crate::limit_args::LimitArgs;

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
    /// Subdivision scheme of the reference and of every configuration [default: the USD
    /// subdivisionScheme, else catmull-clark].
    #[arg(long, value_enum)]
    pub scheme: Option<SchemeName>,
    #[command(flatten)]
    pub camera: CameraArgs,
    /// Measure from N cameras evenly around the up axis (through the target), at the camera's
    /// distance and elevation; maxima and percentiles are over all frames.
    #[arg(long, default_value_t = 1)]
    pub orbit: usize,
    /// Deepest configuration: uniform depths 0..=N and the adaptive modes' max depth.
    #[arg(long, default_value_t = DEFAULT_MAX_DEPTH)]
    pub max_depth: Depth,
    /// Depth of the reference tessellation (default: max depth + 1); must be deeper than
    /// --max-depth.
    #[arg(long)]
    pub reference_depth: Option<Depth>,
    /// Timed renders per camera and configuration (the median is reported).
    #[arg(long, default_value_t = 3)]
    pub runs: usize,
    /// The pixel-error configurations' normal tolerance in degrees: the angle between the limit
    /// normal and the normal interpolated across the drawn triangles that 99 % of the visible
    /// pixels off line pixels stay within (where the limit normal turns by more than DEG to a
    /// neighbouring pixel), or what uniform --max-depth reaches where that is worse (180:
    /// silhouettes only); also the turn that makes a line pixel in shading_deg_p99_off_lines.
    #[arg(long, value_name = "DEG", default_value_t = DEFAULT_SHADING_ERROR_DEG)]
    pub shading_error: f32,
    /// Give each extra fan of faces at a non-manifold vertex its own vertex (the surface opens
    /// there) instead of refining non-manifold cages as OpenSubdiv does.
    #[arg(long)]
    pub split_nonmanifold: bool,
    /// USD: the time code to read the stage at (time samples interpolated as USD does)
    /// [default: default values, else the earliest time samples].
    #[arg(
        long,
        value_name = "T",
        allow_hyphen_values = true,
        conflicts_with = "scene"
    )]
    pub time: Option<f64>,
    /// The dicing configurations' rates in pixels (comma-separated) [default: 2,1,0.5].
    #[arg(long, value_delimiter = ',', value_name = "PX")]
    pub dicing_rates: Vec<f32>,
    /// Which kinds of configuration to measure (comma-separated) [default: all four].
    #[arg(long, value_delimiter = ',')]
    pub configs: Vec<ConfigKind>,
    /// Also measure the predictive frame-rate control's choice for a budget of N triangles
    /// (comma-separated, one configuration `budget-<N>` each): the depths with the least
    /// estimated image error drawing at most N triangles before fans.
    #[arg(long, value_delimiter = ',', value_name = "N")]
    pub budget_triangles: Vec<u32>,
    /// Curvature mode: normal-cone apertures in degrees to measure (comma-separated; one
    /// configuration per combination with --classifier and --projected-size) [default: the
    /// `DepthParams` default].
    #[arg(long, value_delimiter = ',', value_name = "DEG")]
    pub cone_aperture: Vec<f32>,
    /// Curvature mode: vertex classifier epsilons to measure (comma-separated).
    #[arg(long, value_delimiter = ',', value_name = "EPS")]
    pub classifier: Vec<f32>,
    /// Curvature mode: projected sub-patch radius bounds in pixels, `MIN,MAX` or `off` (no
    /// adjustment); repeat the flag to measure several.
    #[arg(long, value_parser = parse_size_band, value_name = "MIN,MAX|off")]
    pub projected_size: Vec<SizeBand>,
    #[command(flatten)]
    pub limit: LimitArgs,
}

/// A kind of configuration of `subdiv bench quality`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConfigKind {
    /// `uniform-0` .. `uniform-<max depth>`.
    Uniform,
    /// The curvature mode (every combination of its parameter flags).
    Curvature,
    /// `pixel-error-2`, `pixel-error-1`, `pixel-error-0.5`.
    PixelError,
    /// `dicing-2`, `dicing-1`, `dicing-0.5` (or the rates of --dicing-rates).
    Dicing,
}

/// `--projected-size` of `bench quality`: a band, or none (`off`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SizeBand(Option<(f32, f32)>);

/// Parses `MIN,MAX` or `off`.
fn parse_size_band(s: &str) -> Result<SizeBand, String> {
    if s.trim() == "off" {
        return Ok(SizeBand(None));
    }
    crate::adaptive_args::parse_pair(s).map(|p| SizeBand(Some(p)))
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

    /// The configurations to measure, in the order of [`Config::all`]: the uniform depths,
    /// the curvature mode once per combination of its parameter flags, the pixel errors.
    fn configs(&self, max_depth: Depth) -> anyhow::Result<Vec<Config>> {
        for &a in &self.cone_aperture {
            if !(a > 0.0 && a < 180.0) {
                bail!("--cone-aperture {a}: need an angle in (0, 180) degrees");
            }
        }
        for &e in &self.classifier {
            if !(0.0..1.0).contains(&e) {
                bail!("--classifier {e}: need an epsilon in [0, 1)");
            }
        }
        let on = |k| self.configs.is_empty() || self.configs.contains(&k);
        let d = CurvatureParams::default();
        let or_default = |v: &[f32], x: f32| if v.is_empty() { vec![x] } else { v.to_vec() };
        let sizes = if self.projected_size.is_empty() {
            vec![d.projected_size]
        } else {
            self.projected_size.iter().map(|b| b.0).collect()
        };
        let mut out: Vec<Config> = Vec::new();
        if on(ConfigKind::Uniform) {
            out.extend((0..=max_depth).map(Config::Uniform));
        }
        if on(ConfigKind::Curvature) {
            for &cone_aperture_deg in &or_default(&self.cone_aperture, d.cone_aperture_deg) {
                for &classifier_eps in &or_default(&self.classifier, d.classifier_eps) {
                    for &projected_size in &sizes {
                        out.push(Config::Curvature(CurvatureParams {
                            cone_aperture_deg,
                            classifier_eps,
                            projected_size,
                        }));
                    }
                }
            }
        }
        if on(ConfigKind::PixelError) {
            out.extend(Config::pixel_errors());
        }
        for &n in &self.budget_triangles {
            if n == 0 {
                bail!("--budget-triangles {n}: need at least one triangle");
            }
            out.push(Config::Budget(n));
        }
        if on(ConfigKind::Dicing) {
            if self.dicing_rates.is_empty() {
                out.extend(Config::dicings());
            }
            for &px in &self.dicing_rates {
                if !(px.is_finite() && px > 0.0) {
                    bail!("--dicing-rates {px}: need a positive number of pixels");
                }
                out.push(Config::Dicing(px));
            }
        }
        Ok(out)
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
    fn base_camera(&self, cage: &Mesh) -> Camera {
        if self.scene.is_some() && !self.camera.has_camera() {
            let args = CameraArgs {
                eye_relative: Some(HELMET40_EYE_RELATIVE),
                ..self.camera.clone()
            };
            return args.camera(cage);
        }
        self.camera.camera(cage)
    }
}

pub fn run(a: &BenchQualityArgs) -> anyhow::Result<ExitCode> {
    let params = a.params()?;
    let configs = a.configs(params.max_depth)?;
    let requested = a.scheme.map(Scheme::from);
    let (cage, scheme) = match (&a.scene, &a.input) {
        (Some(s), _) => (
            BuiltinScene::from(*s).cage()?,
            requested.unwrap_or(Scheme::CatmullClark),
        ),
        (None, Some(p)) => {
            let cage = crate::load::load_cage(p, a.split_nonmanifold, None, a.time)?;
            // `--scheme`, else the stage's: the reference and every configuration use it.
            let scheme = crate::load::cage_scheme(p, &cage, requested)?;
            (cage.mesh, scheme)
        }
        (None, None) => bail!("give an input cage or --scene helmet40"),
    };
    // The reference is the largest tessellation; the adaptive configurations are bounded by
    // every face at the maximum depth.
    let depth = params.reference_depth();
    a.limit
        .check(&cage, Request::Uniform { scheme, depth }, &a.label())?;
    if configs.iter().any(|c| !matches!(c, Config::Uniform(_))) {
        let max_depth = params.max_depth;
        a.limit
            .check(&cage, Request::Adaptive { scheme, max_depth }, &a.label())?;
    }
    let base = a.base_camera(&cage);
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
    let run = QualityRun::with_scheme(&mut renderer, &cage, scheme, &cameras, params);
    spinner.finish_and_clear();
    let run = run.with_context(|| a.label())?;
    log::info!("reference: {} triangles", run.reference_triangles());
    let bar = crate::progress::bar(configs.len() as u64, "configurations");
    let results = run.measure_configs(&mut renderer, &configs, |q| {
        log::info!("done: {q}");
        bar.inc(1);
    });
    bar.finish_and_clear();
    let results = results.with_context(|| a.label())?;
    for q in &results {
        out!("{q}");
    }
    Ok(ExitCode::SUCCESS)
}
