//! `subdiv render`: a headless Vulkan render of the limit surface to PNG (and EXR).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, bail};
use subdiv::mesh::Camera;
use subdiv::mesh::glam::Vec3;
use subdiv::vk::{RenderOptions, Renderer, View};
use subdiv::{Scene, depth_histogram, view_for};

use crate::camera_args::CameraArgs;
use crate::choices::value_name;
use crate::surface_args::{StyleArgs, SurfaceArgs};

/// `subdiv render` arguments.
#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    #[command(flatten)]
    pub surface: SurfaceArgs,
    #[command(flatten)]
    pub camera: CameraArgs,
    #[command(flatten)]
    pub style: StyleArgs,
    /// Output PNG.
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
    /// Also write linear depth, normals and the per-vertex scalar (subdivision depth) as EXR.
    #[arg(long)]
    pub exr: Option<PathBuf>,
}

/// What is drawn: the scene, the view and size, the renderer options, the summary's note and
/// the tessellation time.
struct Drawing<'a> {
    scene: &'a Scene,
    view: &'a View,
    size: [u32; 2],
    options: &'a RenderOptions,
    note: &'a str,
    tessellate_ms: f64,
}

pub fn run(a: &RenderArgs) -> anyhow::Result<ExitCode> {
    a.surface.check_doi_options()?;
    if a.surface.doi.kind().is_some() {
        return run_doi(a);
    }
    let t0 = Instant::now();
    if let Some(mut d) = a.surface.dicing_scene(&a.camera)? {
        let options = a.style.render_options()?;
        let ms = t0.elapsed().as_secs_f64() * 1e3;
        return draw_seen_from(a, &mut d.scene, &d.camera, d.bounds, &options, &d.note, ms);
    }
    if a.surface.is_adaptive(&a.camera)? {
        return run_adaptive(a);
    }
    let options = a.style.render_options()?;
    let t0 = Instant::now();
    let (mut scene, scheme) = a.surface.uniform_scene()?;
    let tessellate_ms = t0.elapsed().as_secs_f64() * 1e3;
    let (lo, hi) = scene.bounds();
    let camera = a.camera.camera(lo, hi);
    let note = format!(
        "{}, depth {}",
        value_name(&scheme),
        a.surface.uniform_depth()
    );
    draw_seen_from(
        a,
        &mut scene,
        &camera,
        (lo, hi),
        &options,
        &note,
        tessellate_ms,
    )
}

/// Draws `scene` seen from `camera` (with its silhouettes when asked) and reports it: what the
/// uniform and the DoI renders share.
fn draw_seen_from(
    a: &RenderArgs,
    scene: &mut Scene,
    camera: &Camera,
    (lo, hi): (Vec3, Vec3),
    options: &RenderOptions,
    note: &str,
    tessellate_ms: f64,
) -> anyhow::Result<ExitCode> {
    let view = view_for(camera, lo, hi);
    if a.style.silhouettes {
        scene.set_lines(Some(scene.silhouette_lines(view.eye)));
    }
    draw_and_report(
        a,
        &Drawing {
            scene,
            view: &view,
            size: [camera.width, camera.height],
            options,
            note,
            tessellate_ms,
        },
    )
}

/// `subdiv render --doi`: the DoI-driven adaptive Loop mesh with the DoI as the scalar.
fn run_doi(a: &RenderArgs) -> anyhow::Result<ExitCode> {
    let mut style = a.style.clone();
    style.doi_values = true;
    let options = style.render_options()?;
    let t0 = Instant::now();
    let label = a.surface.label();
    let setup = a.surface.doi_setup()?;
    let (lo, hi) = setup.bounds();
    let camera = a.camera.camera(lo, hi);
    let spinner = crate::progress::spinner(format!("refining ({} steps)", a.surface.doi.steps));
    let scene = setup.scene(&camera);
    spinner.finish_and_clear();
    let mut scene = scene.with_context(|| label.clone())?;
    let note = setup.summary(scene.faces());
    let tessellate_ms = t0.elapsed().as_secs_f64() * 1e3;
    draw_seen_from(
        a,
        &mut scene,
        &camera,
        (lo, hi),
        &options,
        &note,
        tessellate_ms,
    )
}

/// `subdiv render` of the adaptive tessellation: depths (and culling) from the camera, or from
/// the `--cull-camera-eye-relative` camera while the image is seen from the first.
fn run_adaptive(a: &RenderArgs) -> anyhow::Result<ExitCode> {
    let mut options = a.style.render_options()?;
    let t0 = Instant::now();
    let (cage, scheme) = a.surface.load_cage_scheme()?;
    let (lo, hi) = cage.bounds();
    let camera = a.camera.camera(lo, hi);
    let cull = a.surface.cull_camera(&a.camera, &camera, lo, hi);
    let mut node = a.surface.adaptive_node(cage, scheme)?;
    let spinner = crate::progress::spinner("adaptive tessellation");
    let g = node.update(&cull, None);
    spinner.finish_and_clear();
    let g = g?;
    if g.num_triangles() == 0 {
        bail!("{}: nothing to draw (every face culled)", a.surface.label());
    }
    let histogram = depth_histogram(g);
    let mut scene = Scene::from_limit(&g.surface().referenced_only());
    let tessellate_ms = t0.elapsed().as_secs_f64() * 1e3;
    let view = view_for(&camera, lo, hi);
    let mut lines = Vec::new();
    if a.style.silhouettes {
        lines = scene.silhouette_lines(cull.eye);
    }
    if a.surface.cull_camera_eye_relative.is_some() {
        lines.extend(view_for(&cull, lo, hi).frustum_lines());
        options.show_lines = true;
    }
    if !lines.is_empty() {
        scene.set_lines(Some(lines));
    }
    let note = format!(
        "adaptive, max depth {}, patches per depth {histogram}",
        a.surface.adaptive.max_depth()
    );
    draw_and_report(
        a,
        &Drawing {
            scene: &scene,
            view: &view,
            size: [camera.width, camera.height],
            options: &options,
            note: &note,
            tessellate_ms,
        },
    )
}

/// Renders the drawing, writes the PNG (and EXR) and prints the summary line.
fn draw_and_report(a: &RenderArgs, d: &Drawing<'_>) -> anyhow::Result<ExitCode> {
    let t1 = Instant::now();
    let mut renderer = Renderer::new()?;
    let mesh = d.scene.render_mesh();
    let image = if let Some(exr) = &a.exr {
        let (image, aux) = renderer.render_with_aux(&mesh, d.view, d.size, d.options)?;
        subdiv::vk::write_exr(exr, &aux)?;
        image
    } else {
        renderer.render(&mesh, d.view, d.size, d.options)?
    };
    subdiv::vk::write_png(&a.output, &image)?;
    let render_ms = t1.elapsed().as_secs_f64() * 1e3;
    let line_note = match (d.scene.lines(), a.style.silhouettes) {
        (Some(l), true) => format!(", {} line segments", l.len() / 2),
        _ => String::new(),
    };
    out!(
        "rendered {}: {} faces, {} triangles{} ({}, {} shading) at {}x{} on {}: \
         tessellated in {:.1} ms, rendered in {:.1} ms -> {}{}",
        a.surface.label(),
        d.scene.faces(),
        mesh.triangle_count(),
        line_note,
        d.note,
        d.options.shading.name(),
        d.size[0],
        d.size[1],
        renderer.device_name(),
        d.tessellate_ms,
        render_ms,
        a.output.display(),
        a.exr
            .as_ref()
            .map(|p| format!(" and {}", p.display()))
            .unwrap_or_default(),
    );
    Ok(ExitCode::SUCCESS)
}
