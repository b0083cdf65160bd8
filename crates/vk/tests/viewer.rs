//! The windowed viewer under X11 (e.g. `xvfb-run -a -s "-screen 0 640x480x24"`).
//!
//! winit allows one event loop per process, so this file holds one test.
//! Without `DISPLAY` (or without a Vulkan driver) it prints a note and passes,
//! unless `SUBDIV_VK_REQUIRE_DISPLAY=1` is set.

mod octahedron;

use octahedron::{POSITIONS, SCALARS, TRIANGLES};
use subdiv_vk::glam::Vec3;
use subdiv_vk::viewer::{self, FrameRequest, FrameSource, SourceFrame, ViewerOptions};
use subdiv_vk::{
    ContextOptions, OrbitCamera, RenderMesh, RenderOptions, Renderer, Shading, Validation,
};

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
    let require = std::env::var("SUBDIV_VK_REQUIRE_DISPLAY").as_deref() == Ok("1");
    if std::env::var_os("DISPLAY").is_none() && !require {
        eprintln!("skipping: no DISPLAY (run under xvfb-run)");
        return;
    }
    let context = ContextOptions {
        validation: Validation::IfAvailable,
        ..Default::default()
    };
    let Ok(mut headless) = Renderer::with_options(&context) else {
        assert!(!require, "no Vulkan driver");
        eprintln!("skipping: no Vulkan driver");
        return;
    };
    let camera = OrbitCamera::framing(Vec3::splat(-1.0), Vec3::splat(1.0));
    let render = RenderOptions {
        shading: Shading::Depth,
        wire_overlay: true,
        ..Default::default()
    };
    let dir = std::env::temp_dir().join(format!("subdiv-vk-viewer-{}", std::process::id()));
    let path = dir.join("shot.png");
    let mut source = Counting {
        mesh: shape(),
        frames: 0,
    };
    let report = viewer::run(
        &mut source,
        ViewerOptions {
            size: [160, 120],
            camera: Some(camera),
            render,
            screenshot_after: Some(5),
            screenshot_path: path.clone(),
            // No HUD: the screenshot must equal the headless render.
            hud: false,
            context,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(report.frames, 5);
    assert_eq!(source.frames, 5);
    assert_eq!(report.screenshots, vec![path.clone()]);
    assert_eq!(report.validation_enabled, headless.validation_enabled());
    assert!(
        report.validation_messages.is_empty(),
        "{:#?}",
        report.validation_messages
    );

    let shot = subdiv_vk::read_png(&path).unwrap();
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
    let _ = std::fs::remove_dir_all(&dir);
}
