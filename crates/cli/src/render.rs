//! `subdiv render`: a headless Vulkan render of the limit surface to PNG (and EXR).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, bail};
use subdiv::mesh::{Camera, Mesh};
use subdiv::vk::{RenderOptions, Renderer, Shading, View};
use subdiv::{PrimvarDisplay, Scene, depth_histogram, framing_box, view_for};

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

/// What is drawn: the scene, the camera and its view, the renderer options, the summary's note
/// and the tessellation time.
struct Drawing<'a> {
    scene: &'a Scene,
    camera: &'a Camera,
    view: &'a View,
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
    if let Some(mut d) = a.surface.dicing_scene(&a.camera, a.style.primvar())? {
        let mut options = a.style.render_options()?;
        if d.display == Some(PrimvarDisplay::Heat) {
            options.shading = Shading::Doi;
        }
        let ms = t0.elapsed().as_secs_f64() * 1e3;
        return draw_seen_from(a, &mut d.scene, &d.cage, &options, &d.note, ms);
    }
    if a.surface.is_adaptive(&a.camera)? {
        return run_adaptive(a);
    }
    let mut options = a.style.render_options()?;
    let t0 = Instant::now();
    let (mut scene, display, scheme, cage) = a.surface.uniform_scene_showing(a.style.primvar())?;
    if display == Some(PrimvarDisplay::Heat) {
        options.shading = Shading::Doi;
    }
    let tessellate_ms = t0.elapsed().as_secs_f64() * 1e3;
    let note = format!(
        "{}, depth {}",
        value_name(&scheme),
        a.surface.uniform_depth()
    );
    draw_seen_from(a, &mut scene, &cage, &options, &note, tessellate_ms)
}

/// Draws `scene`, made from `cage`, seen from the camera flags (framed on the cage, with its
/// silhouettes when asked) and reports it: what the uniform and the DoI renders share.
fn draw_seen_from(
    a: &RenderArgs,
    scene: &mut Scene,
    cage: &Mesh,
    options: &RenderOptions,
    note: &str,
    tessellate_ms: f64,
) -> anyhow::Result<ExitCode> {
    let camera = a.camera.camera(cage);
    let (lo, hi) = framing_box(cage);
    let view = view_for(&camera, lo, hi);
    if a.style.silhouettes {
        scene.set_lines(Some(scene.silhouette_lines(view.eye)));
    }
    draw_and_report(
        a,
        &Drawing {
            scene,
            camera: &camera,
            view: &view,
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
    let mut options = style.render_options()?;
    let t0 = Instant::now();
    let label = a.surface.label();
    let setup = a.surface.doi_setup()?;
    let camera = a.camera.camera(&setup.cage);
    let spinner = crate::progress::spinner(format!("refining ({} steps)", a.surface.doi.steps));
    let scene = match a.style.primvar() {
        None => setup.scene(&camera),
        Some(name) => setup.scene_showing(&camera, name).map(|(scene, display)| {
            if display == PrimvarDisplay::Heat {
                options.shading = Shading::Doi;
            }
            scene
        }),
    };
    spinner.finish_and_clear();
    let mut scene = scene.with_context(|| label.clone())?;
    let note = setup.summary(scene.faces());
    let tessellate_ms = t0.elapsed().as_secs_f64() * 1e3;
    draw_seen_from(a, &mut scene, &setup.cage, &options, &note, tessellate_ms)
}

/// `subdiv render` of the adaptive tessellation: depths (and culling) from the camera, or from
/// the `--cull-camera-eye-relative` camera while the image is seen from the first.
fn run_adaptive(a: &RenderArgs) -> anyhow::Result<ExitCode> {
    let mut options = a.style.render_options()?;
    let t0 = Instant::now();
    let (cage, scheme) = a.surface.load_cage_scheme()?;
    let (lo, hi) = framing_box(&cage);
    let camera = a.camera.camera(&cage);
    let cull = a.surface.cull_camera(&a.camera, &camera, &cage);
    let mut node = a.surface.adaptive_node(cage, scheme)?;
    let spinner = crate::progress::spinner("adaptive tessellation");
    let g = node.update(&cull, None).map(|_| ());
    spinner.finish_and_clear();
    g?;
    if a.style.primvar().is_some() {
        node.carry_primvars()?;
    }
    let g = node.geometry();
    if g.num_triangles() == 0 {
        bail!("{}: nothing to draw (every face culled)", a.surface.label());
    }
    let histogram = depth_histogram(g);
    let surface = g.surface().referenced_only();
    let mut scene = match a.style.primvar() {
        None => Scene::from_limit(&surface),
        Some(name) => {
            let (scene, display) = Scene::from_limit_showing(surface, name)
                .map_err(|e| anyhow::anyhow!("{}: {e}", a.surface.label()))?;
            if display == PrimvarDisplay::Heat {
                options.shading = Shading::Doi;
            }
            scene
        }
    };
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
            camera: &camera,
            view: &view,
            options: &options,
            note: &note,
            tessellate_ms,
        },
    )
}

/// Renders the drawing, writes the PNG (and EXR) and prints the camera line and the summary
/// line.
fn draw_and_report(a: &RenderArgs, d: &Drawing<'_>) -> anyhow::Result<ExitCode> {
    let t1 = Instant::now();
    let mut renderer = Renderer::new()?;
    let samples = renderer.samples(d.options)?;
    let mesh = d.scene.render_mesh();
    let size = [d.camera.width, d.camera.height];
    let image = if let Some(exr) = &a.exr {
        let (image, aux) = renderer.render_with_aux(&mesh, d.view, size, d.options)?;
        subdiv::vk::write_exr(exr, &aux)?;
        image
    } else {
        renderer.render(&mesh, d.view, size, d.options)?
    };
    subdiv::vk::write_png(&a.output, &image)?;
    let render_ms = t1.elapsed().as_secs_f64() * 1e3;
    let line_note = match (d.scene.lines(), a.style.silhouettes) {
        (Some(l), true) => format!(", {} line segments", l.len() / 2),
        _ => String::new(),
    };
    out!("{}", camera_line(d.camera));
    out!(
        "rendered {}: {} faces, {} triangles{} ({}, {} shading, {samples} samples per pixel) at \
         {}x{} on {}: tessellated in {:.1} ms, rendered in {:.1} ms -> {}{}",
        a.surface.label(),
        d.scene.faces(),
        mesh.triangle_count(),
        line_note,
        d.note,
        a.style.shading_name(),
        size[0],
        size[1],
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

/// `camera: --eye X,Y,Z --target X,Y,Z --up X,Y,Z --fov DEG --size WxH`: the camera a render
/// used, as the flags that give it again (each number the shortest text that reads back to the
/// same `f32`), so a view can be reproduced here or in another tool.
pub fn camera_line(c: &Camera) -> String {
    let v = |v: subdiv::mesh::glam::Vec3| format!("{},{},{}", v.x, v.y, v.z);
    format!(
        "camera: --eye {} --target {} --up {} --fov {} --size {}x{}",
        v(c.eye),
        v(c.target),
        v(c.up),
        c.fov_y_deg,
        c.width,
        c.height
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera_args::{parse_size, parse_vec3};

    #[test]
    fn the_camera_line_reads_back_to_the_same_camera() {
        let c = Camera::new(
            subdiv::mesh::glam::Vec3::new(0.1, -2.0 / 3.0, 1e-7),
            subdiv::mesh::glam::Vec3::new(1.0, 2.5, -3.25),
            subdiv::mesh::glam::Vec3::Z,
            37.5,
            640,
            480,
        );
        let line = camera_line(&c);
        assert!(line.starts_with("camera: --eye 0.1,-0.6666667,0.0000001 --target 1,2.5,-3.25 --up 0,0,1 --fov 37.5 --size 640x480"), "{line}");
        let words: Vec<&str> = line.split(' ').collect();
        let at = |flag: &str| words[words.iter().position(|w| *w == flag).unwrap() + 1];
        assert_eq!(parse_vec3(at("--eye")).unwrap(), c.eye);
        assert_eq!(parse_vec3(at("--target")).unwrap(), c.target);
        assert_eq!(parse_vec3(at("--up")).unwrap(), c.up);
        assert_eq!(at("--fov").parse::<f32>().unwrap(), c.fov_y_deg);
        assert_eq!(parse_size(at("--size")).unwrap(), (640, 480));
    }
}
