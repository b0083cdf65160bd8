//! `subdiv bench framerate`: the paper's frame-rate experiment (Fig. 7) on the Fig. 12 scene,
//! rendered headless: fixed depths, or adaptive with frame-rate control at a target.

use std::process::ExitCode;
use std::time::Instant;

use anyhow::bail;
use glam::Vec3;
use subdiv::depth::DepthParams;
use subdiv::mesh::Camera;
use subdiv::rules::Depth;
use subdiv::vk::{RenderMesh, RenderOptions, Renderer};
use subdiv::{BuiltinScene, DynamicSubdivision, view_for};

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
    for f in [a.target_fps, a.switch_fps].into_iter().flatten() {
        if !(f.is_finite() && f > 0.0) {
            bail!("frame rates must be positive");
        }
    }
    Ok(())
}

pub fn run(a: &BenchFramerateArgs) -> anyhow::Result<ExitCode> {
    check(a)?;
    let mesh = BuiltinScene::from(a.scene).cage()?;
    let nf = mesh.num_faces();
    let (lo, hi) = mesh.bounds();
    let centre = (lo + hi) * 0.5;
    let radius = (hi - lo).length() * 0.5;
    let mut node = DynamicSubdivision::new(
        mesh,
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
    let mut renderer = if a.no_render {
        None
    } else {
        Some(Renderer::new()?)
    };
    let (w, h) = a.size;
    println!(
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
        // The camera orbits the scene centre about the y axis, looking at it from above.
        let ang = (i as f32 * a.orbit_step).to_radians();
        let eye = centre
            + Vec3::new(
                ang.cos() * 1.1 * radius,
                0.55 * radius,
                ang.sin() * 1.1 * radius,
            );
        let camera = Camera::new(eye, centre, Vec3::Y, 45.0, w, h);
        if a.no_cache {
            node.clear_cache();
        }
        let g = node.update(&camera, last)?;
        let mesh = RenderMesh {
            positions: &g.positions,
            normals: &g.normals,
            triangles: &g.indices,
            ..Default::default()
        };
        if let Some(r) = renderer.as_mut() {
            let view = view_for(&camera, lo, hi);
            r.render_discard(&mesh, &view, [w, h], &RenderOptions::default())?;
        }
        let dt = t0.elapsed().as_secs_f32();
        last = Some(dt);
        let tris = g.num_triangles();
        let per: Vec<String> = g.units_per_depth().iter().map(|n| n.to_string()).collect();
        let cap = node
            .controller()
            .map(|c| c.cap())
            .unwrap_or(a.depth.unwrap_or(a.max_depth));
        crate::progress::suspend(|| {
            println!(
                "frame={i} fps={:.3} triangles={tris} maxsd={cap} patches={}",
                1.0 / dt,
                per.join(",")
            );
        });
        bar.inc(1);
    }
    bar.finish_and_clear();
    Ok(ExitCode::SUCCESS)
}
