//! `subdiv bench framerate`: the paper's frame-rate experiment (Figs. 5-7) on the Fig. 12 scene or
//! any cage (`--instances N` copies laid out as Fig. 12 lays out its helmets), rendered headless:
//! fixed depths, or adaptive with frame-rate control at a target (`--control budget`, the
//! predictive default, or `paper`). Each frame prints its rate, triangles, cap, patches and quads
//! per depth, the paper controller's share (0 otherwise), its measured and predicted time and
//! the update's parts; with `--error-every K` every K-th frame also its image error against the
//! true surface (`subdiv_quality`, untimed, on a renderer of its own). `--calibrate` first
//! measures how steadily the machine holds a rate (uniform depth 2).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::bail;
use glam::Vec3;
use subdiv::depth::DepthParams;
use subdiv::mesh::{Camera, Mesh};
use subdiv::rules::{Depth, Request, Scheme};
use subdiv::vk::{RenderMesh, RenderOptions, Renderer};
use subdiv::{
    BuiltinScene, Control, DynamicSubdivision, Scene, framing_box, instance_grid, view_for,
};
use subdiv_quality::{QualityParams, QualityRun, quantile};

use crate::camera_args::parse_size;
use crate::choices::{ControlName, SceneName, SchemeName};

#[derive(clap::Args, Debug)]
pub struct BenchFramerateArgs {
    /// Input cage [default: --scene helmet40].
    pub input: Option<PathBuf>,
    /// A built-in scene instead of an input file (the paper's Fig. 12: 40 instances of
    /// catmark_helmet).
    #[arg(long, value_enum, conflicts_with = "input")]
    pub scene: Option<SceneName>,
    /// Lay out N copies of the cage (with --scene helmet40: of its helmet) as Fig. 12 lays out
    /// its helmets: rows of 8, 1.25 model widths apart.
    #[arg(long, value_name = "N")]
    pub instances: Option<usize>,
    /// Subdivision scheme [default: the USD subdivisionScheme, else catmull-clark].
    #[arg(long, value_enum)]
    pub scheme: Option<SchemeName>,
    /// Adaptive tessellation with frame-rate control aiming at this frame rate.
    #[arg(long)]
    pub target_fps: Option<f32>,
    /// How the target is met: budget (predictive: the depths that minimise the estimated image
    /// error within the frame time a model fitted to the machine predicts) or paper (Settgast et
    /// al.'s feedback steps on the depth cap and a share of the patches) [default: budget].
    #[arg(long, value_enum, requires = "target_fps")]
    pub control: Option<ControlName>,
    /// Change the target to this frame rate half-way through (the paper switches from 14-15 to
    /// 39-40 fps).
    #[arg(long, requires = "target_fps")]
    pub switch_fps: Option<f32>,
    /// Fixed uniform depth for every patch (no adaptivity, no control).
    #[arg(long, conflicts_with = "target_fps")]
    pub depth: Option<Depth>,
    /// Number of frames.
    #[arg(long, default_value_t = 150)]
    pub frames: usize,
    /// Deepest depth for the adaptive mode (the paper uses 0-4).
    #[arg(long, default_value_t = 4)]
    pub max_depth: Depth,
    /// Normal-cone aperture in degrees for the curvature depth [default: 10].
    #[arg(long, conflicts_with = "depth")]
    pub cone_aperture: Option<f32>,
    /// Vertex classifier epsilon (back / front / silhouette) [default: 0.1].
    #[arg(long, conflicts_with = "depth")]
    pub classifier: Option<f32>,
    /// Projected sub-patch radius bounds in pixels [default: 0.9,4].
    #[arg(long, value_parser = crate::adaptive_args::parse_pair, conflicts_with = "depth")]
    pub projected_size: Option<(f32, f32)>,
    /// Viewport size.
    #[arg(long, value_parser = parse_size, default_value = "640x480")]
    pub size: (u32, u32),
    /// Degrees the camera moves around the scene per frame (0: a still camera).
    #[arg(long, default_value_t = 2.0)]
    pub orbit_step: f32,
    /// Tessellate only (no Vulkan): frame times are the tessellation's.
    #[arg(long)]
    pub no_render: bool,
    /// Drop the per-patch cache before every frame (everything is re-tessellated).
    #[arg(long)]
    pub no_cache: bool,
    /// First render 30 frames at uniform depth 2 and print how steadily this machine holds a
    /// rate: `calibrate frames=30 median_fps=<f> ceiling_within10=<share of frames within ±10 %
    /// of their median>`.
    #[arg(long)]
    pub calibrate: bool,
    /// Every K-th frame (0, K, 2K, ...), also measure the frame's image error against the true
    /// surface (uniform depth --reference-depth, rendered from the same camera at --error-size)
    /// and print `silhouette_px_max= silhouette_px_p99= shading_deg_p99=` (see `bench quality`).
    /// Not part of the frame time.
    #[arg(long, value_name = "K")]
    pub error_every: Option<usize>,
    /// Image size of the error measurement.
    #[arg(long, value_parser = parse_size, default_value = "320x240")]
    pub error_size: (u32, u32),
    /// Depth of the reference surface for --error-every (default: --max-depth + 1).
    #[arg(long)]
    pub reference_depth: Option<Depth>,
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
    /// Samples per pixel of the frames drawn (as `render --samples`) [default: 4 where the
    /// device supports it].
    #[arg(long, value_name = "N", value_parser = crate::surface_args::parse_samples)]
    pub samples: Option<u32>,
    #[command(flatten)]
    pub limit: crate::limit_args::LimitArgs,
}

/// Frames of `--calibrate`.
const CALIBRATION_FRAMES: usize = 30;

/// The camera of frame `i`: it orbits the scene centre about the y axis, looking at it from
/// above, `orbit_step` degrees per frame.
fn frame_camera(a: &BenchFramerateArgs, i: usize, lo: Vec3, hi: Vec3) -> Camera {
    let centre = (lo + hi) * 0.5;
    let radius = (hi - lo).length() * 0.5;
    let ang = (i as f32 * a.orbit_step).to_radians();
    let eye = centre
        + Vec3::new(
            ang.cos() * 1.1 * radius,
            0.55 * radius,
            ang.sin() * 1.1 * radius,
        );
    Camera::new(eye, centre, Vec3::Y, 45.0, a.size.0, a.size.1)
}

/// The reference renders for `--error-every`: one per measured frame.
fn error_run<'a>(
    a: &BenchFramerateArgs,
    cage: &'a Mesh,
    scheme: Scheme,
    renderer: &mut Renderer,
) -> anyhow::Result<Option<QualityRun<'a>>> {
    let Some(k) = a.error_every else {
        return Ok(None);
    };
    let (lo, hi) = framing_box(cage);
    let cameras: Vec<Camera> = (0..a.frames)
        .step_by(k)
        .map(|i| frame_camera(a, i, lo, hi))
        .collect();
    let params = QualityParams {
        size: [a.error_size.0, a.error_size.1],
        max_depth: a.max_depth,
        reference_depth: a.reference_depth,
        timing_runs: 1,
        ..QualityParams::default()
    };
    Ok(Some(QualityRun::with_scheme(
        renderer, cage, scheme, &cameras, params,
    )?))
}

/// Refuses flag values the experiment cannot run with.
fn check(a: &BenchFramerateArgs) -> anyhow::Result<()> {
    if a.frames == 0 {
        bail!("--frames must be at least 1");
    }
    if a.max_depth > 6 {
        bail!(
            "--max-depth {} is too deep for this benchmark (at most 6)",
            a.max_depth
        );
    }
    if let Some(d) = a.depth
        && d > a.max_depth
    {
        bail!("--depth {d} exceeds --max-depth {}", a.max_depth);
    }
    if let Some(c) = a.cone_aperture
        && !(c > 0.0 && c < 180.0)
    {
        bail!("--cone-aperture {c}: need an angle in (0, 180) degrees");
    }
    if let Some(e) = a.classifier
        && !(0.0..1.0).contains(&e)
    {
        bail!("--classifier {e}: need an epsilon in [0, 1)");
    }
    if a.error_every == Some(0) {
        bail!("--error-every must be at least 1");
    }
    if a.instances == Some(0) {
        bail!("--instances must be at least 1");
    }
    if a.error_size.0 == 0 || a.error_size.1 == 0 {
        bail!("--error-size must have pixels");
    }
    if a.calibrate && a.no_render {
        bail!("--calibrate measures rendered frames; drop --no-render");
    }
    for f in [a.target_fps, a.switch_fps].into_iter().flatten() {
        if !(f.is_finite() && f > 0.0) {
            bail!("frame rates must be positive");
        }
    }
    if !a.orbit_step.is_finite() {
        bail!("--orbit-step must be a number of degrees");
    }
    Ok(())
}

/// The benchmark's cage, its name and scheme.
fn cage(a: &BenchFramerateArgs) -> anyhow::Result<(Mesh, String, Scheme)> {
    let (mesh, name, scheme) = match &a.input {
        Some(path) => {
            let c = crate::load::load_cage(path, a.split_nonmanifold, None, a.time)?;
            let scheme = crate::load::cage_scheme(path, &c, a.scheme.map(Into::into))?;
            (c.mesh, path.display().to_string(), scheme)
        }
        None => {
            let scene = BuiltinScene::from(a.scene.unwrap_or(SceneName::Helmet40));
            let name = scene.name().to_string();
            let scheme = a.scheme.map_or(Scheme::CatmullClark, Into::into);
            match a.instances {
                // The scene's own model, copied as asked.
                Some(_) => (subdiv::helmet()?, name, scheme),
                None => (scene.cage()?, name, scheme),
            }
        }
    };
    match a.instances {
        Some(n) => {
            let copies = instance_grid(&mesh, n).map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
            Ok((copies, format!("{name} x{n}"), scheme))
        }
        None => Ok((mesh, name, scheme)),
    }
}

/// Share of `fps` within ±10 % of `around`.
fn within10(fps: &[f64], around: f64) -> f64 {
    let ok = fps
        .iter()
        .filter(|&&f| (f / around - 1.0).abs() <= 0.1)
        .count();
    ok as f64 / fps.len().max(1) as f64
}

/// The median of `v` (0 for none).
fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    s.get(s.len() / 2).copied().unwrap_or(0.0)
}

/// Renders `mesh` for frame `camera` unless `--no-render`.
fn draw(
    renderer: &mut Option<Renderer>,
    a: &BenchFramerateArgs,
    g: &subdiv::stitch::AdaptiveFrame,
    camera: &Camera,
    (lo, hi): (Vec3, Vec3),
) -> anyhow::Result<()> {
    if let (Some(r), false) = (renderer.as_mut(), a.no_render) {
        let mesh = RenderMesh {
            positions: g.surface().positions(),
            normals: g.surface().normals(),
            triangles: g.surface().face_indices(),
            ..Default::default()
        };
        let view = view_for(camera, lo, hi);
        let options = RenderOptions {
            samples: a.samples,
            ..RenderOptions::default()
        };
        // The vertex buffer is kept between frames: only what a frame rewrote is uploaded.
        let size = [a.size.0, a.size.1];
        let (version, dirty) = (g.vertex_version(), g.dirty_vertices());
        r.render_discard_versioned(&mesh, &view, size, &options, version, dirty)?;
    }
    Ok(())
}

/// `--calibrate`: uniform depth 2 rendered for [`CALIBRATION_FRAMES`] frames on the orbit.
fn calibrate(
    a: &BenchFramerateArgs,
    node: &mut DynamicSubdivision,
    renderer: &mut Option<Renderer>,
    bounds: (Vec3, Vec3),
) -> anyhow::Result<()> {
    let nf = node.mesh().num_faces();
    node.set_face_depths(Some(vec![2.min(a.max_depth); nf]))?;
    let mut fps = Vec::new();
    let mut last = None;
    for i in 0..CALIBRATION_FRAMES {
        let t0 = Instant::now();
        let camera = frame_camera(a, i, bounds.0, bounds.1);
        let g = node.update(&camera, last)?;
        draw(renderer, a, g, &camera, bounds)?;
        let dt = t0.elapsed().as_secs_f32();
        last = Some(dt);
        fps.push(1.0 / f64::from(dt));
    }
    node.set_face_depths(None)?;
    let m = median(&fps);
    out!(
        "calibrate frames={CALIBRATION_FRAMES} median_fps={m:.3} ceiling_within10={:.3}",
        within10(&fps, m)
    );
    Ok(())
}

pub fn run(a: &BenchFramerateArgs) -> anyhow::Result<ExitCode> {
    check(a)?;
    let (cage, name, scheme) = cage(a)?;
    let max_depth = a.max_depth;
    a.limit
        .check(&cage, Request::Adaptive { scheme, max_depth }, &name)?;
    if a.error_every.is_some() {
        let depth = a.reference_depth.unwrap_or(max_depth.saturating_add(1));
        a.limit
            .check(&cage, Request::Uniform { scheme, depth }, &name)?;
    }
    let nf = cage.num_faces();
    let bounds = framing_box(&cage);
    let d = DepthParams::default();
    let params = DepthParams {
        max_depth: a.max_depth,
        cone_aperture_deg: a.cone_aperture.unwrap_or(d.cone_aperture_deg),
        classifier_eps: a.classifier.unwrap_or(d.classifier_eps),
        projected_size: a.projected_size.or(d.projected_size),
        ..d
    };
    let mut node = DynamicSubdivision::with_scheme(cage.clone(), scheme, params)?;
    let control = a.control.map_or(Control::Budget, Into::into);
    let mut renderer = if a.no_render {
        None
    } else {
        Some(Renderer::new()?)
    };
    // The image errors are rendered on a renderer of their own. On the frames' renderer each
    // measurement would replace the vertex buffer the frames keep, so the frame after it would
    // upload the whole mesh again: a time the controller would then answer, and one no viewer
    // pays.
    let mut error_renderer = match a.error_every {
        Some(_) => Some(Renderer::new()?),
        None => None,
    };
    if a.calibrate {
        calibrate(a, &mut node, &mut renderer, bounds)?;
    }
    let mode = match (a.depth, a.target_fps) {
        (Some(d), _) => {
            node.set_face_depths(Some(vec![d; nf]))?;
            format!("uniform depth {d}")
        }
        (None, Some(t)) => {
            node.set_control(control, t);
            format!("adaptive, {} control, target {t} fps", control.name())
        }
        (None, None) => "adaptive, no frame-rate control".to_string(),
    };
    let errors = match error_renderer.as_mut() {
        Some(r) => error_run(a, &cage, scheme, r)?,
        None => None,
    };
    let (w, h) = a.size;
    out!("scene={name} faces={nf} size={w}x{h} mode={mode}");
    let mut last: Option<f32> = None;
    let mut fps_all = Vec::with_capacity(a.frames);
    let switch_at = a.switch_fps.map(|_| a.frames / 2);
    let bar = crate::progress::bar(a.frames as u64, "frames");
    for i in 0..a.frames {
        if let (Some(s), Some(k)) = (a.switch_fps, switch_at)
            && i == k
        {
            node.set_target_fps(s);
        }
        let t0 = Instant::now();
        let camera = frame_camera(a, i, bounds.0, bounds.1);
        if a.no_cache {
            node.clear_cache();
        }
        let g = node.update(&camera, last)?;
        let update = t0.elapsed().as_secs_f64();
        draw(&mut renderer, a, g, &camera, bounds)?;
        let dt = t0.elapsed().as_secs_f32();
        last = Some(dt);
        fps_all.push(1.0 / f64::from(dt));
        let line = frame_line(a, &node, i, f64::from(dt), update);
        let mut line = line;
        if let (Some(run), Some(r), Some(k)) = (&errors, error_renderer.as_mut(), a.error_every)
            && i % k == 0
        {
            let scene = Scene::from_limit(&node.geometry().surface().referenced_only());
            let e = run.frame_errors(r, &scene, i / k, &format!("frame {i}"))?;
            let max = e.silhouette_px.iter().copied().fold(0.0f32, f32::max);
            line.push_str(&format!(
                " silhouette_px_max={max:.3} silhouette_px_p99={:.3} shading_deg_p99={:.3}",
                quantile(&e.silhouette_px, 0.99),
                quantile(&e.shading_deg, 0.99)
            ));
        }
        crate::progress::suspend(|| out!("{line}"));
        bar.inc(1);
    }
    bar.finish_and_clear();
    out!("{}", summary(a, &fps_all, switch_at));
    Ok(ExitCode::SUCCESS)
}

/// One frame's line: `frame= fps= triangles= maxsd= patches= quads= share=`, then the
/// measured and predicted milliseconds and the update's parts.
fn frame_line(
    a: &BenchFramerateArgs,
    node: &DynamicSubdivision,
    i: usize,
    dt: f64,
    update: f64,
) -> String {
    let g = node.geometry();
    let join = |v: Vec<String>| v.join(",");
    let per = join(g.units_per_depth().iter().map(|n| n.to_string()).collect());
    let quads = join(
        node.quads_per_depth()
            .iter()
            .map(|n| n.to_string())
            .collect(),
    );
    let cap = node
        .paper_controller()
        .map_or(a.depth.unwrap_or(a.max_depth), |c| c.cap());
    let share = node.paper_controller().map_or(0.0, |c| c.share());
    let predicted = node.last_frame().map_or(0.0, |(_, p)| p);
    let p = g.parts();
    format!(
        "frame={i} fps={:.3} triangles={} maxsd={cap} patches={per} quads={quads} \
         share={share:.3} ms={:.3} predicted_ms={:.3} update_ms={:.3} depths_ms={:.3} \
         tessellate_ms={:.3} fans_ms={:.3} upload_prep_ms={:.3} points={}",
        1.0 / dt,
        g.num_triangles(),
        dt * 1e3,
        predicted * 1e3,
        update * 1e3,
        p.depths * 1e3,
        p.tessellate * 1e3,
        p.stitch * 1e3,
        p.buffers * 1e3,
        g.points_recomputed(),
    )
}

/// The run's last line: `summary frames= median_fps= within10=`, the share of frames within
/// ±10 % of the target (without a target: of the median rate); with `--switch-fps` also the
/// frames after the switch until the first within ±10 % of the new target and the share from
/// there on (`switch_frame= settle_frames= within10_after=`).
fn summary(a: &BenchFramerateArgs, fps: &[f64], switch_at: Option<usize>) -> String {
    let m = median(fps);
    let mut s = match (a.target_fps, switch_at) {
        (Some(t), Some(k)) => format!(
            "summary frames={} median_fps={m:.3} within10={:.3}",
            fps.len(),
            within10(&fps[..k], f64::from(t))
        ),
        (Some(t), None) => format!(
            "summary frames={} median_fps={m:.3} within10={:.3}",
            fps.len(),
            within10(fps, f64::from(t))
        ),
        (None, _) => format!(
            "summary frames={} median_fps={m:.3} within10={:.3}",
            fps.len(),
            within10(fps, m)
        ),
    };
    if let (Some(t2), Some(k)) = (a.switch_fps, switch_at) {
        let after = &fps[k..];
        let t2 = f64::from(t2);
        let settle = after.iter().position(|&f| (f / t2 - 1.0).abs() <= 0.1);
        match settle {
            Some(n) => s.push_str(&format!(
                " switch_frame={k} settle_frames={n} within10_after={:.3}",
                within10(&after[n..], t2)
            )),
            None => s.push_str(&format!(
                " switch_frame={k} settle_frames=none within10_after=0"
            )),
        }
    }
    s
}
