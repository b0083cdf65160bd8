//! The interactive viewer: a winit window with a Vulkan swapchain.
//!
//! Each frame the viewer asks a [`FrameSource`] for geometry given the current
//! camera, renders it with exactly the same code as the headless [`crate::Renderer`]
//! into an offscreen image, and blits that image to the swapchain. Screenshots
//! read the offscreen image back, so they equal a headless render of the same view.
//!
//! Controls: left drag rotates, wheel zooms; `W` wireframe overlay, `D` depth
//! colours, `H` DoI heat map, `S` silhouette lines, `F` freeze the culling camera
//! (its frustum is drawn), `+`/`-` target frame rate, `C` frame-rate control on/off,
//! `P` screenshot, `Esc`/`Q` quit. The title shows fps, triangles and the
//! source's status text.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use ash::{khr, vk};
use raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

use crate::context::{Context, ContextOptions};
use crate::error::{Result, VkError, VkResultExt};
use crate::frame::{self, FrameInputs, MeshBuffer, Readback, Target};
use crate::image_io::write_png;
use crate::pipeline::Pipelines;
use crate::scene::{self, OrbitCamera, OwnedMesh, RenderMesh, RenderOptions, Shading, View};

/// What the viewer asks its [`FrameSource`] for, once per frame.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameRequest {
    /// The camera the frame is rendered with.
    pub view: View,
    /// The camera to cull and choose levels of detail with: equal to `view`
    /// unless the culling camera is frozen (`F`).
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
    /// Whether frame-rate control is on (`C`).
    pub frame_rate_control: bool,
    /// Wall time of the previous frame (zero for the first).
    pub last_frame_time: Duration,
    /// Frame counter, from 0.
    pub frame_index: u64,
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
}

/// Produces the geometry of each frame (e.g. the adaptive tessellator).
pub trait FrameSource {
    /// Geometry for the camera in `request`.
    fn frame(
        &mut self,
        request: &FrameRequest,
    ) -> std::result::Result<SourceFrame<'_>, Box<dyn std::error::Error + Send + Sync>>;
}

impl FrameSource for OwnedMesh {
    fn frame(
        &mut self,
        _request: &FrameRequest,
    ) -> std::result::Result<SourceFrame<'_>, Box<dyn std::error::Error + Send + Sync>> {
        // The mesh cannot change while the viewer borrows it: one vertex version.
        Ok(SourceFrame {
            mesh: self.as_render_mesh(),
            status: "",
            vertex_version: Some(0),
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
    /// Initial render options (shading, overlay, colours).
    pub render: RenderOptions,
    /// Initial target frame rate.
    pub target_fps: f32,
    /// Whether frame-rate control starts on.
    pub frame_rate_control: bool,
    /// Render this many frames, save a screenshot to `screenshot_path`, exit.
    pub screenshot_after: Option<u32>,
    /// Where screenshots go: this path for `screenshot_after`; for `P`, the
    /// same name with a counter (`shot.png` → `shot-0001.png`).
    pub screenshot_path: PathBuf,
    /// Vulkan loader and validation options.
    pub context: ContextOptions,
}

impl Default for ViewerOptions {
    fn default() -> Self {
        ViewerOptions {
            title: String::from("subdiv"),
            size: [960, 720],
            camera: None,
            render: RenderOptions::default(),
            target_fps: 30.0,
            frame_rate_control: true,
            screenshot_after: None,
            screenshot_path: PathBuf::from("screenshot.png"),
            context: ContextOptions::default(),
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
}

/// Opens a window and runs the viewer until it is closed (or the screenshot
/// requested by [`ViewerOptions::screenshot_after`] is written).
///
/// winit allows one event loop per process, so call this at most once.
///
/// ```no_run
/// use subdiv_vk::OwnedMesh;
/// use subdiv_vk::viewer::{self, ViewerOptions};
///
/// # fn main() -> Result<(), subdiv_vk::VkError> {
/// let mut mesh = OwnedMesh {
///     positions: vec![[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]],
///     normals: vec![[0.0, 0.0, 1.0]; 3],
///     triangles: vec![0, 1, 2],
///     ..Default::default()
/// };
/// let report = viewer::run(&mut mesh, ViewerOptions::default())?;
/// println!("{} frames", report.frames);
/// # Ok(())
/// # }
/// ```
pub fn run(source: &mut dyn FrameSource, options: ViewerOptions) -> Result<ViewerReport> {
    let mut builder = EventLoop::builder();
    #[cfg(all(unix, not(target_os = "macos"), not(target_os = "android")))]
    {
        use winit::platform::x11::EventLoopBuilderExtX11;
        builder.with_any_thread(true);
    }
    let event_loop = builder
        .build()
        .map_err(|e| VkError::Window(e.to_string()))?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App {
        gpu: None,
        window: None,
        source,
        camera: options.camera,
        render: options.render,
        silhouettes: options.render.show_lines,
        target_fps: options.target_fps.max(1.0),
        frame_rate_control: options.frame_rate_control,
        frozen: None,
        dragging: false,
        cursor: None,
        last_frame: None,
        last_frame_time: Duration::ZERO,
        fps: 0.0,
        last_title: None,
        screenshot_requested: false,
        report: ViewerReport::default(),
        error: None,
        options,
    };
    let run = event_loop.run_app(&mut app);
    // Vulkan objects go before the window they present to.
    let log = app.gpu.as_ref().map(|g| g.ctx.validation_log());
    app.report.validation_enabled = app.gpu.as_ref().is_some_and(|g| g.ctx.validation_enabled());
    app.gpu = None;
    app.report.validation_messages = log.map(|l| l.take()).unwrap_or_default();
    app.window = None;
    if let Some(e) = app.error.take() {
        return Err(e);
    }
    run.map_err(|e| VkError::Window(e.to_string()))?;
    app.report.camera = app.camera;
    Ok(app.report)
}

struct App<'s> {
    // Declared before `window`: dropped first.
    gpu: Option<Gpu>,
    window: Option<Arc<Window>>,
    source: &'s mut dyn FrameSource,
    options: ViewerOptions,
    camera: Option<OrbitCamera>,
    render: RenderOptions,
    silhouettes: bool,
    target_fps: f32,
    frame_rate_control: bool,
    frozen: Option<View>,
    dragging: bool,
    cursor: Option<(f64, f64)>,
    last_frame: Option<Instant>,
    last_frame_time: Duration,
    fps: f32,
    last_title: Option<Instant>,
    screenshot_requested: bool,
    report: ViewerReport,
    error: Option<VkError>,
}

impl App<'_> {
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: VkError) {
        if self.error.is_none() {
            self.error = Some(error);
        }
        event_loop.exit();
    }

    fn init(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let [w, h] = self.options.size;
        let attributes = Window::default_attributes()
            .with_title(self.options.title.clone())
            .with_inner_size(PhysicalSize::new(w.max(1), h.max(1)));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .map_err(|e| VkError::Window(e.to_string()))?,
        );
        let gpu = Gpu::new(&window, &self.options.context)?;
        self.window = Some(window);
        self.gpu = Some(gpu);
        Ok(())
    }

    fn key(&mut self, key: &Key) {
        let Key::Character(c) = key.as_ref() else {
            return;
        };
        let toggle = |current: Shading, mode: Shading| {
            if current == mode {
                Shading::Smooth
            } else {
                mode
            }
        };
        match c.to_ascii_lowercase().as_str() {
            "w" => self.render.wire_overlay = !self.render.wire_overlay,
            "d" => self.render.shading = toggle(self.render.shading, Shading::Depth),
            "h" => self.render.shading = toggle(self.render.shading, Shading::Doi),
            "s" => self.silhouettes = !self.silhouettes,
            "f" => {
                self.frozen = match self.frozen {
                    Some(_) => None,
                    None => self.current_view(),
                }
            }
            "+" | "=" => self.target_fps = (self.target_fps * 1.25).min(1000.0),
            "-" | "_" => self.target_fps = (self.target_fps / 1.25).max(1.0),
            "c" => self.frame_rate_control = !self.frame_rate_control,
            "p" => self.screenshot_requested = true,
            _ => {}
        }
    }

    fn current_view(&self) -> Option<View> {
        let extent = self.gpu.as_ref()?.swapchain.as_ref()?.extent;
        let aspect = extent.width as f32 / extent.height.max(1) as f32;
        Some(self.camera?.view(aspect))
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let Some(gpu) = self.gpu.as_mut() else {
            return Ok(());
        };
        let Some(window) = self.window.as_ref() else {
            return Ok(());
        };
        let size = window.inner_size();
        if size.width == 0 || size.height == 0 {
            return Ok(()); // minimised
        }
        let extent = gpu.ensure_swapchain(size)?;
        let aspect = extent.width as f32 / extent.height as f32;
        let now = Instant::now();
        if let Some(last) = self.last_frame {
            self.last_frame_time = now - last;
            let instant = 1.0 / self.last_frame_time.as_secs_f32().max(1e-6);
            self.fps = if self.fps == 0.0 {
                instant
            } else {
                0.9 * self.fps + 0.1 * instant
            };
        }
        self.last_frame = Some(now);

        // The first frame is asked for with a provisional camera if none was
        // given; the camera is then fitted to the geometry and used from then on.
        let provisional = self.camera.is_none();
        let camera = self.camera.unwrap_or_else(|| {
            OrbitCamera::framing(glam::Vec3::splat(-1.0), glam::Vec3::splat(1.0))
        });
        let view = camera.view(aspect);
        let mut request = FrameRequest {
            view,
            cull_view: self.frozen.unwrap_or(view),
            size: [extent.width, extent.height],
            shading: self.render.shading,
            silhouettes: self.silhouettes,
            target_fps: self.target_fps,
            frame_rate_control: self.frame_rate_control,
            last_frame_time: self.last_frame_time,
            frame_index: self.report.frames,
        };
        if provisional {
            let fitted = {
                let frame = self
                    .source
                    .frame(&request)
                    .map_err(|e| VkError::FrameSource(e.to_string()))?;
                OrbitCamera::framing_mesh(&frame.mesh)
            };
            self.camera = Some(fitted);
            request.view = fitted.view(aspect);
            request.cull_view = self.frozen.unwrap_or(request.view);
        }
        let frame = self
            .source
            .frame(&request)
            .map_err(|e| VkError::FrameSource(e.to_string()))?;

        let mut options = self.render;
        options.show_lines = self.silhouettes || self.frozen.is_some();
        // Silhouettes off but a frozen frustum to show: drop the source's lines.
        let mut extra_lines: Vec<[f32; 3]> = Vec::new();
        let mut mesh = frame.mesh;
        if let Some(frozen) = self.frozen {
            if self.silhouettes {
                extra_lines.extend_from_slice(mesh.lines.unwrap_or_default());
            }
            extra_lines.extend(frozen.frustum_lines());
            mesh.lines = Some(&extra_lines);
        }
        let at_limit = self
            .options
            .screenshot_after
            .is_some_and(|n| self.report.frames + 1 >= u64::from(n));
        let shot = self.screenshot_requested || at_limit;
        let triangles = mesh.triangle_count();
        let status = frame.status.to_string();
        let image = gpu.draw(&mesh, &request.view, &options, frame.vertex_version, shot)?;
        self.report.frames += 1;

        if let Some(image) = image {
            let path = if at_limit {
                self.options.screenshot_path.clone()
            } else {
                numbered(
                    &self.options.screenshot_path,
                    self.report.screenshots.len() + 1,
                )
            };
            write_png(&path, &image)?;
            eprintln!("screenshot: {}", path.display());
            self.report.screenshots.push(path);
            self.screenshot_requested = false;
            if at_limit {
                event_loop.exit();
                return Ok(());
            }
        }
        if self
            .last_title
            .is_none_or(|t| now.duration_since(t) > Duration::from_millis(250))
        {
            self.last_title = Some(now);
            let mut title = format!(
                "{} | {:.1} fps | {} triangles | {}",
                self.options.title,
                self.fps,
                triangles,
                self.render.shading.name()
            );
            if self.render.wire_overlay {
                title.push_str(" +wire");
            }
            if self.silhouettes {
                title.push_str(" +silhouettes");
            }
            if self.frozen.is_some() {
                title.push_str(" | culling camera frozen");
            }
            if self.frame_rate_control {
                title.push_str(&format!(" | target {:.0} fps", self.target_fps));
            } else {
                title.push_str(" | fps control off");
            }
            if !status.is_empty() {
                title.push_str(" | ");
                title.push_str(&status);
            }
            window.set_title(&title);
        }
        Ok(())
    }
}

/// `dir/name.png` → `dir/name-0003.png`.
fn numbered(path: &std::path::Path, n: usize) -> PathBuf {
    let stem = path
        .file_stem()
        .map_or_else(|| "screenshot".into(), |s| s.to_string_lossy().into_owned());
    let ext = path
        .extension()
        .map_or_else(|| "png".into(), |s| s.to_string_lossy().into_owned());
    path.with_file_name(format!("{stem}-{n:04}.{ext}"))
}

impl ApplicationHandler for App<'_> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_none()
            && let Err(e) = self.init(event_loop)
        {
            self.fail(event_loop, e);
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(_) => {
                if let Some(gpu) = self.gpu.as_mut() {
                    gpu.swapchain_dirty = true;
                }
            }
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.redraw(event_loop) {
                    self.fail(event_loop, e);
                }
            }
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                if matches!(event.logical_key.as_ref(), Key::Named(NamedKey::Escape))
                    || matches!(event.logical_key.as_ref(), Key::Character(c) if c.eq_ignore_ascii_case("q"))
                {
                    event_loop.exit();
                } else {
                    self.key(&event.logical_key);
                }
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => {
                self.dragging = state == ElementState::Pressed;
            }
            WindowEvent::CursorMoved { position, .. } => {
                if self.dragging
                    && let (Some((x, y)), Some(camera)) = (self.cursor, self.camera.as_mut())
                {
                    camera.rotate(
                        ((position.x - x) * 0.01) as f32,
                        ((position.y - y) * 0.01) as f32,
                    );
                }
                self.cursor = Some((position.x, position.y));
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                if let Some(camera) = self.camera.as_mut() {
                    camera.zoom(0.9f32.powf(steps));
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(window) = self.window.as_ref() {
            window.request_redraw();
        }
    }
}

/// Frames in flight: the CPU builds frame n+1 while the GPU draws frame n.
const FRAMES_IN_FLIGHT: usize = 2;

struct Slot {
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    acquired: vk::Semaphore,
    target: Option<Target>,
    /// Vertex + index buffer of this slot: indices rebuilt per frame,
    /// double-buffered across slots so the CPU never overwrites what the GPU
    /// still reads.
    mesh: MeshBuffer,
    /// [`SourceFrame::vertex_version`] of the vertices in `mesh`.
    vertex_version: Option<u64>,
}

struct Swapchain {
    raw: vk::SwapchainKHR,
    images: Vec<vk::Image>,
    extent: vk::Extent2D,
    /// One per swapchain image: signalled by rendering, waited by presentation.
    rendered: Vec<vk::Semaphore>,
}

struct Gpu {
    ctx: Context,
    pipelines: Pipelines,
    loader: khr::swapchain::Device,
    pool: vk::CommandPool,
    slots: Vec<Slot>,
    next: usize,
    swapchain: Option<Swapchain>,
    swapchain_dirty: bool,
    format: vk::SurfaceFormatKHR,
}

impl Gpu {
    fn new(window: &Window, options: &ContextOptions) -> Result<Self> {
        let display = window
            .display_handle()
            .map_err(|e| VkError::Window(e.to_string()))?
            .as_raw();
        let handle = window
            .window_handle()
            .map_err(|e| VkError::Window(e.to_string()))?
            .as_raw();
        let extensions = ash_window::enumerate_required_extensions(display)
            .call("enumerate surface extensions")?;
        let factory = |entry: &ash::Entry, instance: &ash::Instance| {
            // SAFETY: the window outlives the context (the viewer drops the GPU state first).
            unsafe { ash_window::create_surface(entry, instance, display, handle, None) }
                .call("vkCreate*SurfaceKHR")
        };
        let ctx = Context::new(options, extensions, Some(&factory))?;
        let pipelines = Pipelines::new(&ctx)?;
        let loader = khr::swapchain::Device::new(&ctx.instance, &ctx.device);
        let mut gpu = Gpu {
            ctx,
            pipelines,
            loader,
            pool: vk::CommandPool::null(),
            slots: Vec::new(),
            next: 0,
            swapchain: None,
            swapchain_dirty: true,
            format: vk::SurfaceFormatKHR::default(),
        };
        let (surface_loader, surface) = gpu.surface()?;
        // SAFETY: valid handles.
        let formats = unsafe {
            surface_loader.get_physical_device_surface_formats(gpu.ctx.physical, surface)
        }
        .call("vkGetPhysicalDeviceSurfaceFormatsKHR")?;
        // UNORM formats keep the shader's values, so the window equals headless renders.
        gpu.format = [vk::Format::B8G8R8A8_UNORM, vk::Format::R8G8B8A8_UNORM]
            .iter()
            .find_map(|f| formats.iter().find(|s| s.format == *f).copied())
            .or_else(|| formats.first().copied())
            .ok_or(VkError::Window("the surface offers no formats".into()))?;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(gpu.ctx.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        let device = &gpu.ctx.device;
        // SAFETY: valid device; `Drop` cleans up on any later error.
        gpu.pool =
            unsafe { device.create_command_pool(&pool_info, None) }.call("vkCreateCommandPool")?;
        for _ in 0..FRAMES_IN_FLIGHT {
            let alloc = vk::CommandBufferAllocateInfo::default()
                .command_pool(gpu.pool)
                .level(vk::CommandBufferLevel::PRIMARY)
                .command_buffer_count(1);
            // SAFETY: as above.
            unsafe {
                let cmd = device
                    .allocate_command_buffers(&alloc)
                    .call("vkAllocateCommandBuffers")?;
                let fence = device
                    .create_fence(
                        &vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED),
                        None,
                    )
                    .call("vkCreateFence")?;
                let acquired =
                    match device.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) {
                        Ok(s) => s,
                        Err(result) => {
                            device.destroy_fence(fence, None);
                            return Err(VkError::Vulkan {
                                call: "vkCreateSemaphore",
                                result,
                            });
                        }
                    };
                gpu.slots.push(Slot {
                    cmd: cmd.first().copied().unwrap_or_default(),
                    fence,
                    acquired,
                    target: None,
                    mesh: MeshBuffer::default(),
                    vertex_version: None,
                });
            }
        }
        Ok(gpu)
    }

    fn surface(&self) -> Result<(&khr::surface::Instance, vk::SurfaceKHR)> {
        self.ctx
            .surface
            .as_ref()
            .map(|(l, s)| (l, *s))
            .ok_or(VkError::Window("no surface".into()))
    }

    /// (Re)creates the swapchain when needed; returns its extent.
    fn ensure_swapchain(&mut self, size: PhysicalSize<u32>) -> Result<vk::Extent2D> {
        if !self.swapchain_dirty
            && let Some(s) = &self.swapchain
        {
            return Ok(s.extent);
        }
        let (surface_loader, surface) = self.surface()?;
        // SAFETY: valid handles.
        let caps = unsafe {
            surface_loader.get_physical_device_surface_capabilities(self.ctx.physical, surface)
        }
        .call("vkGetPhysicalDeviceSurfaceCapabilitiesKHR")?;
        // SAFETY: valid handles.
        let modes = unsafe {
            surface_loader.get_physical_device_surface_present_modes(self.ctx.physical, surface)
        }
        .call("vkGetPhysicalDeviceSurfacePresentModesKHR")?;
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: size
                    .width
                    .clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: size
                    .height
                    .clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        };
        if extent.width == 0 || extent.height == 0 {
            return Err(VkError::Window("the window has zero size".into()));
        }
        // Unthrottled presentation keeps measured frame times meaningful.
        let mode = [vk::PresentModeKHR::MAILBOX, vk::PresentModeKHR::IMMEDIATE]
            .into_iter()
            .find(|m| modes.contains(m))
            .unwrap_or(vk::PresentModeKHR::FIFO);
        let mut count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            count = count.min(caps.max_image_count);
        }
        let old = self.swapchain.take();
        // SAFETY: wait before destroying per-image semaphores of the old swapchain.
        unsafe { self.ctx.device.device_wait_idle() }.call("vkDeviceWaitIdle")?;
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface)
            .min_image_count(count)
            .image_format(self.format.format)
            .image_color_space(self.format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(vk::ImageUsageFlags::TRANSFER_DST)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(vk::CompositeAlphaFlagsKHR::OPAQUE)
            .present_mode(mode)
            .clipped(true)
            .old_swapchain(old.as_ref().map_or(vk::SwapchainKHR::null(), |s| s.raw));
        // SAFETY: valid handles; the old swapchain is retired by this call.
        let created = unsafe { self.loader.create_swapchain(&info, None) };
        if let Some(old) = old {
            self.destroy_swapchain(old);
        }
        let raw = created.call("vkCreateSwapchainKHR")?;
        let mut swapchain = Swapchain {
            raw,
            images: Vec::new(),
            extent,
            rendered: Vec::new(),
        };
        // SAFETY: swapchain just created.
        let images = unsafe { self.loader.get_swapchain_images(raw) };
        match images {
            Ok(images) => swapchain.images = images,
            Err(result) => {
                self.destroy_swapchain(swapchain);
                return Err(VkError::Vulkan {
                    call: "vkGetSwapchainImagesKHR",
                    result,
                });
            }
        }
        for _ in 0..swapchain.images.len() {
            // SAFETY: valid device.
            match unsafe {
                self.ctx
                    .device
                    .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
            } {
                Ok(s) => swapchain.rendered.push(s),
                Err(result) => {
                    self.destroy_swapchain(swapchain);
                    return Err(VkError::Vulkan {
                        call: "vkCreateSemaphore",
                        result,
                    });
                }
            }
        }
        self.swapchain = Some(swapchain);
        self.swapchain_dirty = false;
        Ok(extent)
    }

    fn destroy_swapchain(&self, swapchain: Swapchain) {
        // SAFETY: the device is idle (callers wait) and nothing else uses these.
        unsafe {
            for s in swapchain.rendered {
                self.ctx.device.destroy_semaphore(s, None);
            }
            self.loader.destroy_swapchain(swapchain.raw, None);
        }
    }

    /// Draws and presents one frame; with `screenshot`, waits for it and returns the image.
    fn draw(
        &mut self,
        mesh: &RenderMesh<'_>,
        view: &View,
        options: &RenderOptions,
        vertex_version: Option<u64>,
        screenshot: bool,
    ) -> Result<Option<image::RgbaImage>> {
        let Some(extent) = self.swapchain.as_ref().map(|s| s.extent) else {
            return Ok(None);
        };
        let index = self.next;
        // CPU work first (overlaps the GPU's previous frame): pack the mesh,
        // without the vertices if this slot's buffer already holds them.
        let reuse = vertex_version.is_some() && self.slots[index].vertex_version == vertex_version;
        let (bytes, layout, offset) = scene::pack_from(mesh, options, !reuse)?;
        self.next = (self.next + 1) % FRAMES_IN_FLIGHT;
        let (fence, acquired, cmd) = {
            let slot = &self.slots[index];
            (slot.fence, slot.acquired, slot.cmd)
        };
        // SAFETY: the fence belongs to this device.
        unsafe { self.ctx.device.wait_for_fences(&[fence], true, u64::MAX) }
            .call("vkWaitForFences")?;

        // Acquire before touching the fence, so an out-of-date swapchain leaves it signalled.
        let swapchain_raw = self
            .swapchain
            .as_ref()
            .map_or(vk::SwapchainKHR::null(), |s| s.raw);
        // SAFETY: valid swapchain and unsignalled semaphore (its last wait completed with the fence).
        let acquire = unsafe {
            self.loader
                .acquire_next_image(swapchain_raw, u64::MAX, acquired, vk::Fence::null())
        };
        let image_index = match acquire {
            Ok((i, suboptimal)) => {
                self.swapchain_dirty |= suboptimal;
                i
            }
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => {
                self.swapchain_dirty = true;
                return Ok(None);
            }
            Err(result) => {
                return Err(VkError::Vulkan {
                    call: "vkAcquireNextImageKHR",
                    result,
                });
            }
        };

        let slot = &mut self.slots[index];
        if slot.target.as_ref().is_none_or(|t| t.extent != extent) {
            if let Some(mut old) = slot.target.take() {
                old.destroy(&mut self.ctx);
            }
            slot.target = Some(Target::new(&mut self.ctx, extent)?);
        }
        slot.vertex_version = None;
        let kept = if reuse {
            slot.mesh.upload_at(&bytes, offset, layout.total)?
        } else {
            None
        };
        let mesh_buffer = match kept {
            Some(buffer) => buffer,
            None if reuse => {
                let (all, _) = scene::pack(mesh, options)?;
                slot.mesh.upload(&mut self.ctx, &all)?
            }
            None => slot.mesh.upload(&mut self.ctx, &bytes)?,
        };
        slot.vertex_version = vertex_version;
        let (Some(target), Some(swapchain)) = (slot.target.as_ref(), self.swapchain.as_ref())
        else {
            return Ok(None);
        };
        let swap_image = swapchain
            .images
            .get(image_index as usize)
            .copied()
            .unwrap_or_default();
        let rendered = swapchain
            .rendered
            .get(image_index as usize)
            .copied()
            .unwrap_or_default();
        let device = &self.ctx.device;
        // SAFETY: the slot's previous submission completed (fence waited), so its
        // command buffer, target and mesh buffer are free.
        unsafe {
            device.reset_fences(&[fence]).call("vkResetFences")?;
            device
                .reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty())
                .call("vkResetCommandBuffer")?;
            device
                .begin_command_buffer(
                    cmd,
                    &vk::CommandBufferBeginInfo::default()
                        .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
                )
                .call("vkBeginCommandBuffer")?;
        }
        frame::record(
            device,
            cmd,
            &FrameInputs {
                pipelines: &self.pipelines,
                target,
                mesh_buffer,
                layout: &layout,
                view,
                options,
                readback: if screenshot {
                    Readback::Color
                } else {
                    Readback::None
                },
            },
        );
        let range = crate::memory::subresource_range(vk::ImageAspectFlags::COLOR);
        let to_dst = [vk::ImageMemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::ALL_TRANSFER)
            .src_access_mask(vk::AccessFlags2::NONE)
            .dst_stage_mask(vk::PipelineStageFlags2::ALL_TRANSFER)
            .dst_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .old_layout(vk::ImageLayout::UNDEFINED)
            .new_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
            .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .image(swap_image)
            .subresource_range(range)];
        let to_present = [vk::ImageMemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::ALL_TRANSFER)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::NONE)
            .dst_access_mask(vk::AccessFlags2::NONE)
            .old_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
            .new_layout(vk::ImageLayout::PRESENT_SRC_KHR)
            .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .image(swap_image)
            .subresource_range(range)];
        let layers = vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        };
        let corner = vk::Offset3D {
            x: i32::try_from(extent.width).unwrap_or(i32::MAX),
            y: i32::try_from(extent.height).unwrap_or(i32::MAX),
            z: 1,
        };
        let regions = [vk::ImageBlit2::default()
            .src_subresource(layers)
            .src_offsets([vk::Offset3D::default(), corner])
            .dst_subresource(layers)
            .dst_offsets([vk::Offset3D::default(), corner])];
        let blit = vk::BlitImageInfo2::default()
            .src_image(target.color.raw)
            .src_image_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL)
            .dst_image(swap_image)
            .dst_image_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
            .regions(&regions)
            .filter(vk::Filter::NEAREST);
        let waits = [vk::SemaphoreSubmitInfo::default()
            .semaphore(acquired)
            .stage_mask(vk::PipelineStageFlags2::ALL_TRANSFER)];
        let signals = [vk::SemaphoreSubmitInfo::default()
            .semaphore(rendered)
            .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)];
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
        let submit = [vk::SubmitInfo2::default()
            .wait_semaphore_infos(&waits)
            .command_buffer_infos(&cmds)
            .signal_semaphore_infos(&signals)];
        let swapchains = [swapchain.raw];
        let indices = [image_index];
        let wait_present = [rendered];
        let present = vk::PresentInfoKHR::default()
            .wait_semaphores(&wait_present)
            .swapchains(&swapchains)
            .image_indices(&indices);
        // SAFETY: recorded with valid handles; semaphores/fence as documented above.
        let presented = unsafe {
            device.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().image_memory_barriers(&to_dst),
            );
            device.cmd_blit_image2(cmd, &blit);
            device.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().image_memory_barriers(&to_present),
            );
            device.end_command_buffer(cmd).call("vkEndCommandBuffer")?;
            device
                .queue_submit2(self.ctx.queue, &submit, fence)
                .call("vkQueueSubmit2")?;
            self.loader.queue_present(self.ctx.queue, &present)
        };
        match presented {
            Ok(suboptimal) => self.swapchain_dirty |= suboptimal,
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => self.swapchain_dirty = true,
            Err(result) => {
                return Err(VkError::Vulkan {
                    call: "vkQueuePresentKHR",
                    result,
                });
            }
        }
        if !screenshot {
            return Ok(None);
        }
        // SAFETY: fence of the submission above.
        unsafe { device.wait_for_fences(&[fence], true, u64::MAX) }.call("vkWaitForFences")?;
        target.read_color().map(Some)
    }
}

impl Drop for Gpu {
    fn drop(&mut self) {
        // SAFETY: wait for the GPU, then destroy in reverse order of creation;
        // the context (dropped after this body) destroys the device last.
        unsafe {
            let _ = self.ctx.device.device_wait_idle();
        }
        if let Some(s) = self.swapchain.take() {
            self.destroy_swapchain(s);
        }
        let mut slots = std::mem::take(&mut self.slots);
        for slot in &mut slots {
            if let Some(mut t) = slot.target.take() {
                t.destroy(&mut self.ctx);
            }
            slot.mesh.destroy(&mut self.ctx);
            // SAFETY: idle device.
            unsafe {
                self.ctx.device.destroy_fence(slot.fence, None);
                self.ctx.device.destroy_semaphore(slot.acquired, None);
            }
        }
        self.pipelines.destroy(&self.ctx);
        if self.pool != vk::CommandPool::null() {
            // SAFETY: idle device; frees the command buffers too.
            unsafe { self.ctx.device.destroy_command_pool(self.pool, None) };
        }
    }
}
