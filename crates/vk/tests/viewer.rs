//! The windowed viewer under X11 (e.g. `xvfb-run -a -s "-screen 0 640x480x24"`).
//!
//! winit allows one event loop per process, so this file holds one test.
//! Without `DISPLAY` (or without a Vulkan driver) it prints a note and passes,
//! unless `SUBDIV_VK_REQUIRE_DISPLAY=1` is set.

mod common;
mod octahedron;

use octahedron::{POSITIONS, SCALARS, TRIANGLES};
use subdiv_vk::glam::Vec3;
use subdiv_vk::viewer::{FrameRequest, FrameSource, SourceFrame};
use subdiv_vk::{OrbitCamera, RenderMesh, RenderOptions, Shading};

static LINE: [[f32; 3]; 2] = [[-1.2, 0.0, 0.0], [1.2, 0.0, 0.0]];

/// An octahedron-ish test shape with per-vertex depth scalars and a line.
fn shape() -> RenderMesh<'static> {
    RenderMesh {
        positions: &POSITIONS,
        normals: &POSITIONS,
        triangles: &TRIANGLES,
        edges: None,
        scalars: Some(&SCALARS),
        colors: None,
        lines: Some(&LINE),
    }
}

/// Counts the frames it is asked for and checks the requests.
struct Counting {
    mesh: RenderMesh<'static>,
    frames: u64,
}

impl FrameSource for Counting {
    fn frame(
        &mut self,
        request: &FrameRequest,
    ) -> Result<SourceFrame<'_>, Box<dyn std::error::Error + Send + Sync>> {
        assert_eq!(request.frame_index, self.frames);
        assert_eq!(request.size, [160, 120]);
        assert_eq!(request.view, request.cull_view);
        assert_eq!(request.shading, Shading::Depth);
        self.frames += 1;
        // Same vertices every frame: from the third frame on, both per-frame
        // buffers keep them and only indices and lines are uploaded.
        Ok(SourceFrame {
            mesh: self.mesh,
            status: "test",
            vertex_version: Some(7),
            dirty_vertices: None,
            depth_cap: Some(5),
            predicted_ms: None,
        })
    }
}

#[test]
fn screenshot_after_n_frames_equals_headless_render() {
    let Some(mut headless) = common::display_and_renderer() else {
        return;
    };
    let camera = OrbitCamera::framing(Vec3::splat(-1.0), Vec3::splat(1.0));
    let render = RenderOptions {
        shading: Shading::Depth,
        wire_overlay: true,
        ..Default::default()
    };
    let mut source = Counting {
        mesh: shape(),
        frames: 0,
    };
    let (report, shot) = common::viewer_screenshot(&mut source, camera, render, 5, "viewer");
    assert_eq!(report.frames, 5);
    assert_eq!(source.frames, 5);
    assert_eq!(report.validation_enabled, headless.validation_enabled());
    let mesh = shape();
    let expected = headless
        .render(&mesh, &camera.view(160.0 / 120.0), [160, 120], &render)
        .unwrap();
    assert!(
        shot == expected,
        "viewer screenshot differs from the headless render"
    );
    let log = headless.validation_log();
    drop(headless);
    assert!(log.take().is_empty());
}
