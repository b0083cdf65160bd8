//! The interactive viewer: a winit window with a Vulkan swapchain.
//!
//! Each frame the viewer asks a [`FrameSource`] for geometry given the current
//! camera, renders it with exactly the same code as the headless [`crate::Renderer`]
//! into an offscreen image, and blits that image to the swapchain. Screenshots
//! read the offscreen image back, so they equal a headless render of the same view.
//!
//! Controls: see [`KEY_HELP`]. A HUD (frame rate, triangles, depth cap, frame-rate control
//! and its target, measured and predicted frame time, mode) and, for the depth and DoI
//! shadings, a colour legend are
//! drawn over the frame with Vulkan ([`crate::overlay`]); the title shows the
//! same plus the source's status text. Frames are drawn back to back only while
//! frame-rate control is on (it needs frame times) or a scripted screenshot
//! waits for its frame; otherwise the viewer draws when something changes.

mod app;
mod gpu;
mod hud;
mod input;
mod playback;
mod slot;
mod swapchain;
mod versions;

use std::path::PathBuf;
use std::time::Duration;

use crate::context::ContextOptions;
use crate::error::Result;
use crate::scene::{OrbitCamera, RenderMesh, RenderOptions, Shading, View};

pub use playback::{Playback, PlaybackKey};

/// The viewer's keys and mouse, as printed by `subdiv view` at start and in its `--help`.
pub const KEY_HELP: &str = "\
Viewer controls:
  left drag                      orbit about the model's up axis (--up)
  middle drag, shift + left drag pan
  wheel                          zoom
  Home, F                        frame the model again (reset the view)
  W  wireframe overlay           D  depth colours       H  DoI heat map
  S  silhouette lines            Z  freeze the culling camera (its frustum is drawn)
  C  frame-rate control: off, budget (predictive), paper     +, -  target frame rate
  I  HUD on/off                  L  colour legend on/off
  P  screenshot                  Esc, Q  quit
  Space  play/pause an animated cage   Left, Right  one time code back, on";

/// The frame-rate control the viewer asks its source for; `C` cycles them in this order.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FrameControl {
    /// No control: the source's own depths.
    #[default]
    Off,
    /// Predictive control: the least image error within the predicted frame time.
    Budget,
    /// The paper's feedback controller.
    Paper,
}

impl FrameControl {
    /// The next mode in the cycle of `C`.
    pub fn next(self) -> FrameControl {
        match self {
            FrameControl::Off => FrameControl::Budget,
            FrameControl::Budget => FrameControl::Paper,
            FrameControl::Paper => FrameControl::Off,
        }
    }

    /// Whether a target frame rate is aimed at.
    pub fn is_on(self) -> bool {
        self != FrameControl::Off
    }

    /// The mode's name (`off`, `budget`, `paper`).
    pub fn name(self) -> &'static str {
        match self {
            FrameControl::Off => "off",
            FrameControl::Budget => "budget",
            FrameControl::Paper => "paper",
        }
    }
}

/// What the viewer asks its [`FrameSource`] for, once per frame.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameRequest {
    /// The camera the frame is rendered with.
    pub view: View,
    /// The camera to cull and choose levels of detail with: equal to `view`
    /// unless the culling camera is frozen (`Z`).
    pub cull_view: View,
    /// Image size in pixels.
    pub size: [u32; 2],
    /// Current shading mode: fill [`RenderMesh::scalars`] with subdivision depths
    /// for [`Shading::Depth`] and degrees of interest for [`Shading::Doi`].
    pub shading: Shading,
    /// Whether silhouette lines ([`RenderMesh::lines`]) are shown.
    pub silhouettes: bool,
    /// Target frame rate set with `+`/`-`.
    pub target_fps: f32,
    /// The frame-rate control (`C`); while it is on, frames are drawn back to back.
    pub control: FrameControl,
    /// Wall time of the previous frame (zero for the first).
    pub last_frame_time: Duration,
    /// Frame counter, from 0.
    pub frame_index: u64,
    /// The time code to show, with [`ViewerOptions::playback`] (`None` without).
    pub time: Option<f64>,
}

/// Geometry for one frame, borrowed from the source.
#[derive(Clone, Copy, Debug, Default)]
pub struct SourceFrame<'a> {
    /// What to draw.
    pub mesh: RenderMesh<'a>,
    /// Extra text for the window title, e.g. patches per depth.
    pub status: &'a str,
    /// Identifies the vertex data (positions, normals, scalars). When it equals
    /// the previous frame's, the viewer keeps the vertices already in its
    /// per-frame device buffers and uploads only indices and lines (e.g. limit
    /// points stay while subdivision depths do not rise). `None`: always upload.
    pub vertex_version: Option<u64>,
    /// With a `vertex_version`: the vertices that differ from version `vertex_version - 1`'s
    /// (appended ones included), every other vertex keeping its index and bits, so that the
    /// viewer writes only these (`subdiv_stitch::AdaptiveFrame::dirty_vertices`). `None`: not
    /// known, and a new version is written in full.
    pub dirty_vertices: Option<&'a [std::ops::Range<u32>]>,
    /// The subdivision depth cap of this frame (the HUD's "depth cap"): the frame-rate
    /// controller's cap or the maximum depth; `None` where no cap applies.
    pub depth_cap: Option<u32>,
    /// The source's prediction of this frame's time in milliseconds (the HUD shows it beside
    /// the measured time); `None` where it predicts nothing.
    pub predicted_ms: Option<f32>,
}

/// Produces the geometry of each frame (e.g. the adaptive tessellator).
pub trait FrameSource {
    /// Geometry for the camera in `request`.
    fn frame(
        &mut self,
        request: &FrameRequest,
    ) -> std::result::Result<SourceFrame<'_>, Box<dyn std::error::Error + Send + Sync>>;
}

/// The same buffers every frame.
impl FrameSource for RenderMesh<'_> {
    fn frame(
        &mut self,
        _request: &FrameRequest,
    ) -> std::result::Result<SourceFrame<'_>, Box<dyn std::error::Error + Send + Sync>> {
        // The buffers cannot change while the viewer borrows them: one vertex version.
        Ok(SourceFrame {
            mesh: *self,
            status: "",
            vertex_version: Some(0),
            dirty_vertices: None,
            depth_cap: None,
            predicted_ms: None,
        })
    }
}

/// Viewer settings.
#[derive(Clone, Debug)]
pub struct ViewerOptions {
    /// Window title prefix.
    pub title: String,
    /// Initial window size in pixels.
    pub size: [u32; 2],
    /// Initial camera; `None`: frame the first frame's geometry.
    pub camera: Option<OrbitCamera>,
    /// Initial render options (shading, overlay, colours); `legend` starts the
    /// colour legend on (`L`).
    pub render: RenderOptions,
    /// Whether the HUD starts on (`I`). Screenshots include it: turn it (and the
    /// legend) off for screenshots that must equal headless renders.
    pub hud: bool,
    /// Pan by this many pixels (right, down) before the first frame, exactly as a
    /// middle drag does (scripted views and tests).
    pub pan: Option<[f32; 2]>,
    /// Initial target frame rate.
    pub target_fps: f32,
    /// The frame-rate control the viewer starts with.
    pub control: FrameControl,
    /// Render this many frames, save a screenshot to `screenshot_path`, exit.
    pub screenshot_after: Option<u32>,
    /// An animated source's time range: frames ask for a time code
    /// ([`FrameRequest::time`]), played at its rate while playing (frames back to back),
    /// space pauses and plays, the arrow keys step one time code.
    pub playback: Option<Playback>,
    /// Where screenshots go: this path for `screenshot_after`; for `P`, the
    /// same name with a counter (`shot.png` → `shot-0001.png`).
    pub screenshot_path: PathBuf,
    /// Vulkan loader and validation options.
    pub context: ContextOptions,
    /// Test hook: faults injected before frame `n` is drawn (sorted by `n`), so that tests
    /// under Xvfb run the real recovery code. Empty outside tests.
    #[doc(hidden)]
    pub faults: Vec<(u64, Fault)>,
}

/// A fault [`ViewerOptions::faults`] injects: a window-system request made for real, or
/// a result the viewer's next Vulkan call is made to report. Test hook, not a stable API.
#[doc(hidden)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fault {
    /// Ask the window system for this inner size (`request_inner_size`). Later faults wait
    /// until the window has that size, or a second.
    RequestSize([u32; 2]),
    /// Ask the window system to minimise the window (`set_minimized(true)`).
    Minimize,
    /// For this long the window reports an inner size of 0×0, as a minimised window does
    /// on Windows.
    ZeroWindow(Duration),
    /// For this long the surface reports a current extent of 0×0, and the swapchain is
    /// marked for re-creation as a resize marks it: a window minimised under a compositor.
    ZeroSurface(Duration),
    /// The next `vkAcquireNextImageKHR` reports this (out of date and surface lost
    /// without acquiring an image, suboptimal with one).
    Acquire(SwapchainFault),
    /// The next `vkQueuePresentKHR` presents, then reports this.
    Present(SwapchainFault),
    /// A playback key pressed (space, an arrow key), as the keyboard would.
    Press(PlaybackKey),
}

/// A result [`Fault::Acquire`] and [`Fault::Present`] inject. Test hook.
#[doc(hidden)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SwapchainFault {
    /// `VK_ERROR_OUT_OF_DATE_KHR`.
    OutOfDate,
    /// `VK_SUBOPTIMAL_KHR`.
    Suboptimal,
    /// `VK_ERROR_SURFACE_LOST_KHR`.
    SurfaceLost,
}

impl Default for ViewerOptions {
    fn default() -> Self {
        ViewerOptions {
            title: String::from("subdiv"),
            size: [960, 720],
            camera: None,
            render: RenderOptions::default(),
            hud: true,
            pan: None,
            target_fps: 30.0,
            control: FrameControl::Budget,
            screenshot_after: None,
            playback: None,
            screenshot_path: PathBuf::from("screenshot.png"),
            context: ContextOptions::default(),
            faults: Vec::new(),
        }
    }
}

/// What happened during a viewer session.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ViewerReport {
    /// Frames rendered.
    pub frames: u64,
    /// Screenshots written.
    pub screenshots: Vec<PathBuf>,
    /// The camera when the viewer closed.
    pub camera: Option<OrbitCamera>,
    /// Whether the Khronos validation layer was active.
    pub validation_enabled: bool,
    /// Validation-layer messages (empty unless the layer was enabled).
    pub validation_messages: Vec<String>,
    /// Redraws that drew nothing: the window or its surface was 0×0 (minimised), or the
    /// swapchain was out of date or the surface lost when an image was acquired.
    pub skipped_frames: u64,
    /// The extent of each swapchain created, in order: one per (re)creation after a
    /// resize, an out-of-date or suboptimal swapchain, or a lost surface.
    pub swapchain_extents: Vec<[u32; 2]>,
    /// Times the window's surface was lost and created again.
    pub surface_recreations: u64,
}

/// Opens a window and runs the viewer until it is closed (or the screenshot
/// requested by [`ViewerOptions::screenshot_after`] is written).
///
/// winit allows one event loop per process, so call this at most once.
///
/// ```no_run
/// use subdiv_vk::RenderMesh;
/// use subdiv_vk::viewer::{self, ViewerOptions};
///
/// # fn main() -> Result<(), subdiv_vk::VkError> {
/// let mut mesh = RenderMesh {
///     positions: &[[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]],
///     normals: &[[0.0, 0.0, 1.0]; 3],
///     triangles: &[0, 1, 2],
///     ..Default::default()
/// };
/// let report = viewer::run(&mut mesh, ViewerOptions::default())?;
/// println!("{} frames", report.frames);
/// # Ok(())
/// # }
/// ```
pub fn run(source: &mut dyn FrameSource, options: ViewerOptions) -> Result<ViewerReport> {
    app::run(source, options)
}
