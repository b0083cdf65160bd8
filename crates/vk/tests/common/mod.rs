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
