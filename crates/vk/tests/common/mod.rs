//! What the headless rendering tests share: a renderer (skipped without a driver unless
//! `SUBDIV_VK_REQUIRE_DRIVER=1`), the validation check at teardown, and a square to draw.
#![allow(dead_code)] // each test crate uses its own subset

use subdiv_vk::glam::Vec3;
use subdiv_vk::{ContextOptions, RenderMesh, Renderer, Validation, View, VkError};

/// A renderer with validation when available; `None` (test skipped) without a driver.
pub fn renderer() -> Option<Renderer> {
    let options = ContextOptions {
        validation: Validation::IfAvailable,
        ..Default::default()
    };
    match Renderer::with_options(&options) {
        Ok(r) => {
            let layer = "/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json";
            if std::path::Path::new(layer).exists() {
                assert!(
                    r.validation_enabled(),
                    "validation layer installed but not enabled"
                );
            }
            Some(r)
        }
        Err(e @ (VkError::LoaderMissing { .. } | VkError::NoDriver { .. }))
            if std::env::var("SUBDIV_VK_REQUIRE_DRIVER").as_deref() != Ok("1") =>
        {
            eprintln!("skipping: {e}");
            None
        }
        Err(e) => panic!("cannot create renderer: {e}"),
    }
}

/// For a window test: a headless renderer to compare with, `None` (test skipped) without
/// `DISPLAY` or a driver, unless `SUBDIV_VK_REQUIRE_DISPLAY=1` is set.
pub fn display_and_renderer() -> Option<Renderer> {
    let require = std::env::var("SUBDIV_VK_REQUIRE_DISPLAY").as_deref() == Ok("1");
    if std::env::var_os("DISPLAY").is_none() && !require {
        eprintln!("skipping: no DISPLAY (run under xvfb-run)");
        return None;
    }
    let context = ContextOptions {
        validation: Validation::IfAvailable,
        ..Default::default()
    };
    match Renderer::with_options(&context) {
        Ok(r) => Some(r),
        Err(e) => {
            assert!(!require, "no Vulkan driver: {e}");
            eprintln!("skipping: no Vulkan driver");
            None
        }
    }
}

/// Runs the viewer on `source` at 160×120 with `camera` and `render`, no HUD, validation when
/// available, for `frames` frames, and returns its report and the screenshot taken after the
/// last one (`name`: a word for the temporary directory).
pub fn viewer_screenshot(
    source: &mut dyn subdiv_vk::viewer::FrameSource,
    camera: subdiv_vk::OrbitCamera,
    render: subdiv_vk::RenderOptions,
    frames: u32,
    name: &str,
) -> (subdiv_vk::viewer::ViewerReport, subdiv_vk::image::RgbaImage) {
    let dir = std::env::temp_dir().join(format!("subdiv-vk-{name}-{}", std::process::id()));
    let path = dir.join("shot.png");
    let report = subdiv_vk::viewer::run(
        source,
        subdiv_vk::viewer::ViewerOptions {
            size: [160, 120],
            camera: Some(camera),
            render,
            screenshot_after: Some(frames),
            screenshot_path: path.clone(),
            // No HUD: the screenshot can equal a headless render.
            hud: false,
            context: ContextOptions {
                validation: Validation::IfAvailable,
                ..Default::default()
            },
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(report.screenshots, vec![path.clone()]);
    assert!(
        report.validation_messages.is_empty(),
        "{:#?}",
        report.validation_messages
    );
    let shot = subdiv_vk::read_png(&path).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    (report, shot)
}

/// Drops the renderer and fails on any validation message, teardown included.
pub fn finish(renderer: Renderer) {
    let log = renderer.validation_log();
    drop(renderer);
    let messages = log.take();
    assert!(
        messages.is_empty(),
        "validation messages:\n{}",
        messages.join("\n")
    );
}

/// A 2x2 square in the z = 0 plane, as two triangles, with its 4 outline edges.
pub struct Square {
    pub positions: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    pub triangles: Vec<u32>,
    pub edges: Vec<[u32; 2]>,
    pub scalars: Vec<f32>,
}

pub fn square(scalar: f32) -> Square {
    Square {
        positions: vec![
            [-1.0, -1.0, 0.0],
            [1.0, -1.0, 0.0],
            [1.0, 1.0, 0.0],
            [-1.0, 1.0, 0.0],
        ],
        normals: vec![[0.0, 0.0, 1.0]; 4],
        triangles: vec![0, 1, 2, 0, 2, 3],
        edges: vec![[0, 1], [1, 2], [2, 3], [3, 0]],
        scalars: vec![scalar; 4],
    }
}

impl Square {
    pub fn mesh(&self) -> RenderMesh<'_> {
        RenderMesh {
            positions: &self.positions,
            normals: &self.normals,
            triangles: &self.triangles,
            edges: Some(&self.edges),
            scalars: Some(&self.scalars),
            colors: None,
            lines: None,
        }
    }
}

/// Looking straight at the square from z = 4; it fills the middle of the image.
pub fn front_view(aspect: f32) -> View {
    View::look_at(
        Vec3::new(0.0, 0.0, 4.0),
        Vec3::ZERO,
        Vec3::Y,
        0.6,
        aspect,
        0.1,
        100.0,
    )
}

pub const SIZE: [u32; 2] = [64, 48];
pub const WHITE: [u8; 4] = [255, 255, 255, 255];

pub fn px(image: &subdiv_vk::image::RgbaImage, x: u32, y: u32) -> [u8; 4] {
    image.get_pixel(x, y).0
}

pub fn tilted_square() -> Square {
    let mut sq = square(0.0);
    let (s, c) = 30f32.to_radians().sin_cos();
    for p in &mut sq.positions {
        *p = [c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]];
    }
    sq
}
