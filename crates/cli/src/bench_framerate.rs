//! `subdiv bench framerate`: the paper's frame-rate experiment (Figs. 5-7) on the Fig. 12 scene,
//! rendered headless: fixed depths, or adaptive with frame-rate control at a target. Each frame
//! prints its rate, triangles, cap, patches and quads per depth and the controller's share (0
//! without control); with `--error-every K` every K-th
//! frame also its image error against the true surface (`subdiv_quality`, untimed).

use std::process::ExitCode;
use std::time::Instant;

use anyhow::bail;
use glam::Vec3;
use subdiv::depth::DepthParams;
use subdiv::mesh::{Camera, Mesh};
use subdiv::rules::{Depth, Request, Scheme};
use subdiv::vk::{RenderMesh, RenderOptions, Renderer};
use subdiv::{BuiltinScene, DynamicSubdivision, Scene, framing_box, view_for};
use subdiv_quality::{QualityParams, QualityRun, quantile};

use crate::camera_args::parse_size;
use crate::choices::{SceneName, value_name};

#[derive(clap::Args, Debug)]
pub struct BenchFramerateArgs {
    /// The scene (the paper's Fig. 12: 40 instances of catmark_helmet).
    #[arg(long, value_enum, default_value = "helmet40")]
    pub scene: SceneName,
    /// Adaptive tessellation with frame-rate control aiming at this frame rate.
    #[arg(long)]
    pub target_fps: Option<f32>,
    /// Change the target to this frame rate half-way through (the paper switches from 14-15 to
    /// 39-40 fps).
    #[arg(long)]
    pub switch_fps: Option<f32>,
    /// Fixed uniform depth for every patch (no adaptivity, no control).
    #[arg(long)]
    pub depth: Option<Depth>,
    /// Number of frames.
    #[arg(long, default_value_t = 150)]
    pub frames: usize,
    /// Deepest depth for the adaptive mode (the paper uses 0-4).
    #[arg(long, default_value_t = 4)]
    pub max_depth: Depth,
    /// Viewport size.
    #[arg(long, value_parser = parse_size, default_value = "640x480")]
    pub size: (u32, u32),
    /// Degrees the camera moves around the scene per frame.
    #[arg(long, default_value_t = 2.0)]
    pub orbit_step: f32,
    /// Tessellate only (no Vulkan): frame times are the tessellation's.
    #[arg(long)]
    pub no_render: bool,
    /// Drop the per-patch cache before every frame (everything is re-tessellated).
    #[arg(long)]
    pub no_cache: bool,
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
    /// Samples per pixel of the frames drawn (as `render --samples`) [default: 4 where the
    /// device supports it].
    #[arg(long, value_name = "N", value_parser = crate::surface_args::parse_samples)]
    pub samples: Option<u32>,
    #[command(flatten)]
    pub limit: crate::limit_args::LimitArgs,
}

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
    Ok(Some(QualityRun::new(renderer, cage, &cameras, params)?))
}

/// Refuses flag values the experiment cannot run with.
fn check(a: &BenchFramerateArgs) -> anyhow::Result<()> {
    if a.frames == 0 {
        bail!("--frames must be at least 1");
    }
    if a.max_depth > 6 {
        bail!(
            "--max-depth {} is too deep for this scene (at most 6)",
            a.max_depth
        );
    }
    if let Some(d) = a.depth
        && d > a.max_depth
    {
        bail!("--depth {d} exceeds --max-depth {}", a.max_depth);
    }
    if a.error_every == Some(0) {
        bail!("--error-every must be at least 1");
    }
    if a.error_size.0 == 0 || a.error_size.1 == 0 {
        bail!("--error-size must have pixels");
    }
    for f in [a.target_fps, a.switch_fps].into_iter().flatten() {
        if !(f.is_finite() && f > 0.0) {
            bail!("frame rates must be positive");
        }
    }
    Ok(())
}

pub fn run(a: &BenchFramerateArgs) -> anyhow::Result<ExitCode> {
    check(a)?;
    let cage = BuiltinScene::from(a.scene).cage()?;
    let label = format!("scene {}", value_name(&a.scene));
    let scheme = Scheme::CatmullClark;
    let max_depth = a.max_depth;
    a.limit
        .check(&cage, Request::Adaptive { scheme, max_depth }, &label)?;
    if a.error_every.is_some() {
        let depth = a.reference_depth.unwrap_or(max_depth.saturating_add(1));
        a.limit
            .check(&cage, Request::Uniform { scheme, depth }, &label)?;
    }
    let nf = cage.num_faces();
    let (lo, hi) = framing_box(&cage);
    let mut node = DynamicSubdivision::new(
        cage.clone(),
        DepthParams {
            max_depth: a.max_depth,
            ..Default::default()
        },
    )?;
    let mode = match (a.depth, a.target_fps) {
        (Some(d), _) => {
            node.set_face_depths(Some(vec![d; nf]))?;
            format!("uniform depth {d}")
        }
        (None, Some(t)) => {
            node.set_frame_rate_control(Some(t));
            format!("adaptive, target {t} fps")
        }
        (None, None) => "adaptive, no frame-rate control".to_string(),
    };
    let mut renderer = if a.no_render && a.error_every.is_none() {
        None
    } else {
        Some(Renderer::new()?)
    };
    let errors = match renderer.as_mut() {
        Some(r) => error_run(a, &cage, r)?,
        None => None,
    };
    let (w, h) = a.size;
    out!(
        "scene={} faces={nf} size={w}x{h} mode={mode}",
        value_name(&a.scene)
    );
    let mut last: Option<f32> = None;
    let bar = crate::progress::bar(a.frames as u64, "frames");
    for i in 0..a.frames {
        if let (Some(s), true) = (a.switch_fps, i == a.frames / 2) {
            node.set_target_fps(s);
        }
        let t0 = Instant::now();
        let camera = frame_camera(a, i, lo, hi);
        if a.no_cache {
            node.clear_cache();
        }
        let g = node.update(&camera, last)?;
        let mesh = RenderMesh {
            positions: g.surface().positions(),
            normals: g.surface().normals(),
            triangles: g.surface().face_indices(),
            ..Default::default()
        };
        if let (Some(r), false) = (renderer.as_mut(), a.no_render) {
            let view = view_for(&camera, lo, hi);
            let options = RenderOptions {
                samples: a.samples,
                ..RenderOptions::default()
            };
            r.render_discard(&mesh, &view, [w, h], &options)?;
        }
        let dt = t0.elapsed().as_secs_f32();
        last = Some(dt);
        let tris = g.num_triangles();
        let per: Vec<String> = g.units_per_depth().iter().map(|n| n.to_string()).collect();
        let mut line = format!(
            "frame={i} fps={:.3} triangles={tris} maxsd={} patches={} quads={} share={:.3}",
            1.0 / dt,
            node.controller()
                .map(|c| c.cap())
                .unwrap_or(a.depth.unwrap_or(a.max_depth)),
            per.join(","),
            node.quads_per_depth()
                .iter()
                .map(|n| n.to_string())
                .collect::<Vec<_>>()
                .join(","),
            node.controller().map_or(0.0, |c| c.share())
        );
        if let (Some(run), Some(r), Some(k)) = (&errors, renderer.as_mut(), a.error_every)
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
    Ok(ExitCode::SUCCESS)
}
