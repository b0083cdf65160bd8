//! The viewer's fault paths under X11 (`xvfb-run -a`): window resizes to 1×1 and 0×0 and
//! minimising, asked of the X server for real; a 0×0 window or surface, out-of-date and
//! suboptimal swapchains and a lost surface, injected into the viewer's next Vulkan call
//! ([`ViewerOptions::faults`]), so that its own recovery code runs.
//!
//! winit allows one event loop per process, so each test runs its viewer in a child process:
//! this test binary again, filtered to that one test. Without `DISPLAY` (or without a Vulkan
//! driver) the tests print a note and pass, unless `SUBDIV_VK_REQUIRE_DISPLAY=1` is set.

mod octahedron;

use octahedron::{POSITIONS, SCALARS, TRIANGLES};
use std::process::Command;
use std::time::{Duration, Instant};

use subdiv_vk::glam::Vec3;
use subdiv_vk::image::RgbaImage;
use subdiv_vk::viewer::{
    self, Fault, FrameRequest, FrameSource, SourceFrame, SwapchainFault, ViewerOptions,
    ViewerReport,
};
use subdiv_vk::{
    ContextOptions, OrbitCamera, RenderMesh, RenderOptions, Renderer, Shading, Validation, VkError,
};

/// Set in the child process that runs one test's viewer.
const CHILD_ENV: &str = "SUBDIV_VK_VIEWER_FAULTS_CHILD";

/// The window size every test starts with.
const SIZE: [u32; 2] = [160, 120];

fn required() -> bool {
    std::env::var("SUBDIV_VK_REQUIRE_DISPLAY").as_deref() == Ok("1")
}

/// Runs `body` in a child process (this binary, filtered to `name`), or, in that child,
/// runs it here.
fn in_own_process(name: &str, body: impl FnOnce()) {
    if std::env::var_os(CHILD_ENV).is_some() {
        body();
        return;
    }
    if std::env::var_os("DISPLAY").is_none() && !required() {
        eprintln!("skipping: no DISPLAY (run under xvfb-run)");
        return;
    }
    let exe = std::env::current_exe().unwrap();
    let out = Command::new(exe)
        .args([name, "--exact", "--nocapture", "--test-threads=1"])
        .env(CHILD_ENV, "1")
        .output()
        .unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(
        out.status.success(),
        "{name} failed in its own process:\n{stdout}\n{stderr}"
    );
    assert!(
        stdout.contains("1 passed"),
        "{name} did not run in its own process:\n{stdout}\n{stderr}"
    );
    eprint!("{stderr}");
}

/// An octahedron.
fn shape() -> RenderMesh<'static> {
    RenderMesh {
        positions: &POSITIONS,
        normals: &POSITIONS,
        triangles: &TRIANGLES,
        scalars: Some(&SCALARS),
        ..Default::default()
    }
}

/// Serves [`shape`] and records the image size of every request.
struct Recording {
    mesh: RenderMesh<'static>,
    sizes: Vec<[u32; 2]>,
}

impl FrameSource for Recording {
    fn frame(
        &mut self,
        request: &FrameRequest,
    ) -> Result<SourceFrame<'_>, Box<dyn std::error::Error + Send + Sync>> {
        assert!(
            request.size[0] > 0 && request.size[1] > 0,
            "{:?}",
            request.size
        );
        self.sizes.push(request.size);
        Ok(SourceFrame {
            mesh: self.mesh,
            status: "",
            vertex_version: Some(1),
            dirty_vertices: None,
            depth_cap: None,
            predicted_ms: None,
        })
    }
}

fn camera() -> OrbitCamera {
    OrbitCamera::framing(Vec3::splat(-1.0), Vec3::splat(1.0))
}

fn render_options() -> RenderOptions {
    RenderOptions {
        shading: Shading::Depth,
        wire_overlay: true,
        ..Default::default()
    }
}

/// What one viewer session did.
struct Session {
    report: ViewerReport,
    /// Image sizes the source was asked for.
    sizes: Vec<[u32; 2]>,
    screenshot: RgbaImage,
    elapsed: Duration,
}

/// Runs the viewer at [`SIZE`] with `faults` until `frames` frames are drawn (then a
/// screenshot); `hud` also draws the HUD and legend. `None` when there is no Vulkan driver
/// and none is required. Asserts the run succeeded without validation messages.
fn session(name: &str, faults: Vec<(u64, Fault)>, frames: u32, hud: bool) -> Option<Session> {
    match try_session(name, faults, frames, hud) {
        Err(e @ (VkError::LoaderMissing { .. } | VkError::NoDriver { .. })) if !required() => {
            eprintln!("skipping: {e}");
            None
        }
        Err(e) => panic!("viewer failed: {e}"),
        Ok(s) => Some(s),
    }
}

fn try_session(
    name: &str,
    faults: Vec<(u64, Fault)>,
    frames: u32,
    hud: bool,
) -> Result<Session, VkError> {
    let dir = std::env::temp_dir().join(format!("subdiv-vk-faults-{}", std::process::id()));
    let path = dir.join(format!("{name}.png"));
    let mut source = Recording {
        mesh: shape(),
        sizes: Vec::new(),
    };
    let mut render = render_options();
    render.legend = hud;
    let start = Instant::now();
    let report = viewer::run(
        &mut source,
        ViewerOptions {
            size: SIZE,
            camera: Some(camera()),
            render,
            screenshot_after: Some(frames),
            screenshot_path: path.clone(),
            hud,
            context: ContextOptions {
                validation: Validation::IfAvailable,
                ..Default::default()
            },
            faults,
            ..Default::default()
        },
    )?;
    let elapsed = start.elapsed();
    assert!(
        report.validation_messages.is_empty(),
        "{:#?}",
        report.validation_messages
    );
    if std::env::var("SUBDIV_VK_VALIDATION").as_deref() == Ok("1") {
        assert!(report.validation_enabled, "validation was asked for");
    }
    assert_eq!(report.frames, u64::from(frames));
    assert_eq!(report.screenshots, vec![path.clone()]);
    let screenshot = subdiv_vk::read_png(&path).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    Ok(Session {
        report,
        sizes: source.sizes,
        screenshot,
        elapsed,
    })
}

/// The headless render of the viewer's view at [`SIZE`] (no HUD).
fn headless() -> RgbaImage {
    let mut renderer = Renderer::with_options(&ContextOptions {
        validation: Validation::IfAvailable,
        ..Default::default()
    })
    .unwrap();
    let [w, h] = SIZE;
    let image = renderer
        .render(
            &shape(),
            &camera().view(w as f32 / h as f32),
            SIZE,
            &render_options(),
        )
        .unwrap();
    let log = renderer.validation_log();
    drop(renderer);
    assert!(log.take().is_empty());
    image
}

fn assert_equals_headless(s: &Session) {
    assert!(
        s.screenshot == headless(),
        "viewer screenshot differs from the headless render"
    );
}

/// A resize to 1×1 and back: the swapchain is recreated at each size, frames keep coming
/// at 1×1 (HUD and legend included), and the last are full size again. Two recoveries ask
/// for each re-creation, and either alone suffices: the window's resize event, and the
/// real `VK_SUBOPTIMAL_KHR` that lavapipe's X11 acquire returns once the window's size
/// differs from the swapchain's.
#[test]
fn resize_to_one_pixel_and_back() {
    in_own_process("resize_to_one_pixel_and_back", || {
        let faults = vec![
            (2, Fault::RequestSize([1, 1])),
            (4, Fault::RequestSize(SIZE)),
        ];
        let Some(s) = session("one-pixel", faults, 7, true) else {
            return;
        };
        let extents = &s.report.swapchain_extents;
        let tiny = extents.iter().position(|e| *e == [1, 1]);
        assert!(tiny.is_some(), "no 1x1 swapchain: {extents:?}");
        assert_eq!(extents.first(), Some(&SIZE), "{extents:?}");
        assert_eq!(extents.last(), Some(&SIZE), "{extents:?}");
        assert!(s.sizes.contains(&[1, 1]), "no 1x1 frame: {:?}", s.sizes);
        assert_eq!(s.sizes.last(), Some(&SIZE), "{:?}", s.sizes);
        assert_eq!(s.screenshot.dimensions(), (SIZE[0], SIZE[1]));
    });
}

/// Under Xvfb without a window manager, a request for 0×0 is refused by the X server (a
/// window cannot be 0×0 in X11) and `set_minimized(true)` asks a window manager that is not
/// there: neither changes the window. The viewer keeps drawing at its size and never
/// asks its source for a 0×0 frame.
#[test]
fn zero_size_request_and_minimise_leave_the_x11_window_as_it_is() {
    in_own_process(
        "zero_size_request_and_minimise_leave_the_x11_window_as_it_is",
        || {
            let faults = vec![(2, Fault::RequestSize([0, 0])), (3, Fault::Minimize)];
            let Some(s) = session("zero-request", faults, 8, false) else {
                return;
            };
            assert!(s.sizes.iter().all(|z| *z == SIZE), "{:?}", s.sizes);
            assert_eq!(s.report.swapchain_extents, vec![SIZE]);
            assert_eq!(s.report.skipped_frames, 0);
            assert_equals_headless(&s);
        },
    );
}

/// A window that reads 0×0 (minimised, as on Windows) for 300 ms: frames are skipped,
/// looked at again every 50 ms rather than back to back, and drawn again afterwards.
#[test]
fn zero_size_window_skips_frames_without_spinning() {
    in_own_process("zero_size_window_skips_frames_without_spinning", || {
        let faults = vec![(2, Fault::ZeroWindow(Duration::from_millis(300)))];
        let Some(s) = session("zero-window", faults, 5, false) else {
            return;
        };
        let skipped = s.report.skipped_frames;
        assert!((1..=30).contains(&skipped), "{skipped} frames skipped");
        assert!(s.elapsed >= Duration::from_millis(300));
        assert_eq!(s.report.swapchain_extents, vec![SIZE]);
        assert_equals_headless(&s);
    });
}

/// A surface whose current extent reads 0×0 for 300 ms after a resize (a window minimised
/// under a compositor): frames are skipped without spinning, the old swapchain is kept,
/// and a new one is made when the surface has its size again.
#[test]
fn zero_size_surface_skips_frames_then_recreates_the_swapchain() {
    in_own_process(
        "zero_size_surface_skips_frames_then_recreates_the_swapchain",
        || {
            let faults = vec![(2, Fault::ZeroSurface(Duration::from_millis(300)))];
            let Some(s) = session("zero-surface", faults, 5, false) else {
                return;
            };
            let skipped = s.report.skipped_frames;
            assert!((1..=30).contains(&skipped), "{skipped} frames skipped");
            assert!(s.elapsed >= Duration::from_millis(300));
            assert_eq!(s.report.swapchain_extents, vec![SIZE, SIZE]);
            assert_equals_headless(&s);
        },
    );
}

/// `vkAcquireNextImageKHR` out of date (the frame is skipped, drawn again at once) and
/// suboptimal (the frame is drawn): each recreates the swapchain before the next frame.
#[test]
fn acquire_out_of_date_or_suboptimal_recreates_the_swapchain() {
    in_own_process(
        "acquire_out_of_date_or_suboptimal_recreates_the_swapchain",
        || {
            let faults = vec![
                (1, Fault::Acquire(SwapchainFault::OutOfDate)),
                (3, Fault::Acquire(SwapchainFault::Suboptimal)),
            ];
            let Some(s) = session("acquire", faults, 6, false) else {
                return;
            };
            assert_eq!(s.report.skipped_frames, 1);
            assert_eq!(s.report.swapchain_extents, vec![SIZE; 3]);
            assert_eq!(s.report.surface_recreations, 0);
            assert_equals_headless(&s);
        },
    );
}

/// `vkQueuePresentKHR` out of date or suboptimal: the frame was drawn, and the swapchain
/// is recreated before the next.
#[test]
fn present_out_of_date_or_suboptimal_recreates_the_swapchain() {
    in_own_process(
        "present_out_of_date_or_suboptimal_recreates_the_swapchain",
        || {
            let faults = vec![
                (1, Fault::Present(SwapchainFault::OutOfDate)),
                (3, Fault::Present(SwapchainFault::Suboptimal)),
            ];
            let Some(s) = session("present", faults, 6, false) else {
                return;
            };
            assert_eq!(s.report.skipped_frames, 0);
            assert_eq!(s.report.swapchain_extents, vec![SIZE; 3]);
            assert_equals_headless(&s);
        },
    );
}

/// `VK_ERROR_SURFACE_LOST_KHR` from acquire and from present: each time the surface and
/// its swapchain are created again and the viewer goes on.
#[test]
fn lost_surface_is_recreated() {
    in_own_process("lost_surface_is_recreated", || {
        let faults = vec![
            (2, Fault::Acquire(SwapchainFault::SurfaceLost)),
            (4, Fault::Present(SwapchainFault::SurfaceLost)),
        ];
        let Some(s) = session("surface-lost", faults, 7, false) else {
            return;
        };
        assert_eq!(s.report.surface_recreations, 2);
        assert_eq!(s.report.skipped_frames, 1);
        assert_eq!(s.report.swapchain_extents, vec![SIZE; 3]);
        assert_equals_headless(&s);
    });
}

/// A surface lost again each time it is recreated ends the viewer with
/// [`VkError::SurfaceLost`] after three tries: an error, not a panic or a hang.
#[test]
fn surface_lost_for_good_is_an_error() {
    in_own_process("surface_lost_for_good_is_an_error", || {
        let faults = vec![(1, Fault::Acquire(SwapchainFault::SurfaceLost)); 4];
        match try_session("lost-for-good", faults, 5, false) {
            Err(VkError::SurfaceLost { times }) => assert_eq!(times, 4),
            Err(e @ (VkError::LoaderMissing { .. } | VkError::NoDriver { .. })) if !required() => {
                eprintln!("skipping: {e}");
            }
            Err(e) => panic!("expected a lost surface, got: {e}"),
            Ok(s) => panic!("expected a lost surface, got {:?}", s.report),
        }
    });
}
