//! The viewer's winit application: window, input, camera, frame pacing,
//! title and screenshots. The GPU side lives in [`super::gpu`].

use std::collections::VecDeque;
use std::sync::Arc;
use std::time::{Duration, Instant};

use ash::vk;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, ModifiersState, NamedKey};
use winit::window::{Window, WindowId};

use super::gpu::{Drawn, Gpu};
use super::hud::{self, HudState};
use super::input::{Drag, drag, draws_continuously};
use super::playback::{PlaybackKey, Player};
use super::{Fault, FrameControl, FrameRequest, FrameSource, ViewerOptions, ViewerReport};
use crate::error::{Result, VkError};
use crate::image_io::write_png;
use crate::scene::{OrbitCamera, RenderOptions, Shading, View};

mod faults;
mod text;

use text::numbered;

/// See [`super::run`].
pub(super) fn run(source: &mut dyn FrameSource, options: ViewerOptions) -> Result<ViewerReport> {
    let mut builder = EventLoop::builder();
    #[cfg(all(unix, not(target_os = "macos"), not(target_os = "android")))]
    {
        use winit::platform::x11::EventLoopBuilderExtX11;
        builder.with_any_thread(true);
    }
    let event_loop = builder
        .build()
        .map_err(|e| VkError::Window(e.to_string()))?;
    event_loop.set_control_flow(ControlFlow::Wait);
    let mut faults = options.faults.clone();
    faults.sort_by_key(|(frame, _)| *frame);
    let mut app = App {
        gpu: None,
        window: None,
        source,
        camera: options.camera,
        home: options.camera,
        render: options.render,
        silhouettes: options.render.show_lines,
        target_fps: options.target_fps.max(1.0),
        control: options.control,
        hud: options.hud,
        frozen: None,
        player: options.playback.map(|p| Player::new(p, Instant::now())),
        left: false,
        middle: false,
        modifiers: ModifiersState::empty(),
        cursor: None,
        pending_pan: options.pan,
        dirty: true,
        last_frame: None,
        last_frame_time: Duration::ZERO,
        work_time: Duration::ZERO,
        fps: 0.0,
        last_title: None,
        screenshot_requested: false,
        report: ViewerReport::default(),
        error: None,
        options,
        faults: faults.into(),
        awaiting_size: None,
        zero_window_until: None,
        zero_extent: false,
        next_zero_check: None,
    };
    let run = event_loop.run_app(&mut app);
    // Vulkan objects go before the window they present to.
    let log = app.gpu.as_ref().map(|g| g.ctx.validation_log());
    app.report.validation_enabled = app.gpu.as_ref().is_some_and(|g| g.ctx.validation_enabled());
    if let Some(gpu) = app.gpu.as_mut() {
        app.report.swapchain_extents = std::mem::take(&mut gpu.extents);
        app.report.surface_recreations = gpu.surface_recreations;
    }
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
    /// The camera `Home`/`F` returns to: the initial one (given or fitted).
    home: Option<OrbitCamera>,
    render: RenderOptions,
    silhouettes: bool,
    target_fps: f32,
    control: FrameControl,
    hud: bool,
    frozen: Option<View>,
    /// Playback of an animated source ([`ViewerOptions::playback`]).
    player: Option<Player>,
    /// Mouse buttons held: left rotates (pans with shift), middle pans.
    left: bool,
    middle: bool,
    modifiers: ModifiersState,
    cursor: Option<(f64, f64)>,
    /// [`ViewerOptions::pan`], applied once the camera exists.
    pending_pan: Option<[f32; 2]>,
    /// Something changed since the last frame: draw one.
    dirty: bool,
    last_frame: Option<Instant>,
    last_frame_time: Duration,
    /// CPU time of the last frame (source + drawing), shown when not redrawing continuously.
    work_time: Duration,
    fps: f32,
    last_title: Option<Instant>,
    screenshot_requested: bool,
    report: ViewerReport,
    error: Option<VkError>,
    /// [`ViewerOptions::faults`] not injected yet, by frame.
    faults: VecDeque<(u64, Fault)>,
    /// A [`Fault::RequestSize`] waiting for the window to take that size (since then).
    awaiting_size: Option<(PhysicalSize<u32>, Instant)>,
    /// [`Fault::ZeroWindow`]: until then the window's size reads 0×0.
    zero_window_until: Option<Instant>,
    /// The last redraw found the window or its surface 0×0.
    zero_extent: bool,
    /// While [`App::zero_extent`]: when to look at the size again.
    next_zero_check: Option<Instant>,
}

/// How often a minimised (0×0) window is looked at again: no event need come when a
/// surface regains its size, and drawing back to back would spin on an empty window.
const ZERO_EXTENT_POLL: Duration = Duration::from_millis(50);

/// How long a [`Fault::RequestSize`] holds back the faults after it.
const REQUEST_SIZE_WAIT: Duration = Duration::from_secs(1);

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
        if matches!(key.as_ref(), Key::Named(NamedKey::Home)) {
            self.reset_view();
            return;
        }
        let playback = match key.as_ref() {
            Key::Named(NamedKey::Space) => Some(PlaybackKey::PlayPause),
            Key::Named(NamedKey::ArrowLeft) => Some(PlaybackKey::StepBack),
            Key::Named(NamedKey::ArrowRight) => Some(PlaybackKey::StepForward),
            _ => None,
        };
        if let Some(k) = playback {
            self.press(k);
            return;
        }
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
            "f" => self.reset_view(),
            "z" => {
                self.frozen = match self.frozen {
                    Some(_) => None,
                    None => self.current_view(),
                }
            }
            "i" => self.hud = !self.hud,
            "l" => self.render.legend = !self.render.legend,
            "+" | "=" => self.target_fps = (self.target_fps * 1.25).min(1000.0),
            "-" | "_" => self.target_fps = (self.target_fps / 1.25).max(1.0),
            "c" => self.control = self.control.next(),
            "p" => self.screenshot_requested = true,
            _ => {}
        }
    }

    /// A playback key (none without playback).
    fn press(&mut self, key: PlaybackKey) {
        if let Some(player) = self.player.as_mut() {
            player.press(key, Instant::now());
        }
    }

    /// Back to the initial camera (`Home`, `F`).
    fn reset_view(&mut self) {
        if self.home.is_some() {
            self.camera = self.home;
        }
    }

    /// A pan by (`dx`, `dy`) pixels: middle drag, shift + left drag, [`ViewerOptions::pan`].
    fn pan(&mut self, dx: f32, dy: f32) {
        let height = self
            .window
            .as_ref()
            .map_or(self.options.size[1], |w| w.inner_size().height) as f32;
        if let Some(camera) = self.camera.as_mut() {
            camera.pan(dx, dy, height);
        }
    }

    /// Whether frames are drawn back to back: frame-rate control needs frame times, and a
    /// scripted screenshot waits for its frame count. Otherwise only changes draw.
    fn continuous(&self) -> bool {
        draws_continuously(
            self.control.is_on(),
            self.options.screenshot_after,
            self.report.frames,
        ) || self.player.as_ref().is_some_and(Player::playing)
    }

    fn current_view(&self) -> Option<View> {
        let extent = self.gpu.as_ref()?.swapchain.as_ref()?.extent;
        let aspect = extent.width as f32 / extent.height.max(1) as f32;
        Some(self.camera?.view(aspect))
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        self.inject_faults();
        let Some(extent) = self.swapchain_extent()? else {
            self.report.skipped_frames += 1;
            return Ok(());
        };
        let aspect = extent.width as f32 / extent.height as f32;
        let now = Instant::now();
        self.update_fps(now);
        let mut request = self.request(extent, aspect)?;
        if let Some([dx, dy]) = self.pending_pan.take() {
            self.pan(dx, dy);
            request = self.request(extent, aspect)?;
        }
        let mut hud_state = self.hud_state();
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
        let size = [extent.width, extent.height];
        hud_state.triangles = triangles;
        hud_state.depth_cap = frame.depth_cap;
        hud_state.predicted_ms = frame.predicted_ms;
        let overlay = hud::overlay(&hud_state, &mesh, &options, size);
        // `swapchain_extent` returned an extent, so the GPU state exists.
        let Some(gpu) = self.gpu.as_mut() else {
            return Ok(());
        };
        let vertex_version = frame.vertex_version;
        let drawn = gpu.draw(
            &mesh,
            &request.view,
            &options,
            &overlay,
            (vertex_version, frame.dirty_vertices),
            shot,
        )?;
        let Drawn::Presented(image) = drawn else {
            // Out of date or surface lost: draw again at once, after the re-creation.
            self.report.skipped_frames += 1;
            self.dirty = true;
            return Ok(());
        };
        self.report.frames += 1;
        self.work_time = now.elapsed();

        if let Some(image) = image
            && self.save_screenshot(&image, at_limit)?
        {
            event_loop.exit();
            return Ok(());
        }
        if self
            .last_title
            .is_none_or(|t| now.duration_since(t) > Duration::from_millis(250))
        {
            self.last_title = Some(now);
            let title = self.title(triangles, &status);
            if let Some(window) = self.window.as_ref() {
                window.set_title(&title);
            }
        }
        Ok(())
    }

    /// What the HUD shows for this frame (the source's triangles and depth cap to be filled in).
    fn hud_state(&self) -> HudState {
        HudState {
            show: self.hud,
            fps: self.continuous().then_some(self.fps),
            work_ms: self.work_time.as_secs_f32() * 1e3,
            triangles: 0,
            depth_cap: None,
            control: self.control,
            target_fps: self.target_fps,
            measured_ms: (self.continuous() && !self.last_frame_time.is_zero())
                .then_some(self.last_frame_time.as_secs_f32() * 1e3),
            predicted_ms: None,
            shading: self.render.shading,
            wire: self.render.wire_overlay,
            silhouettes: self.silhouettes,
            frozen: self.frozen.is_some(),
        }
    }

    /// Measures the previous frame's time and smooths the frame rate (restarting after an
    /// idle pause, when no frames were drawn).
    fn update_fps(&mut self, now: Instant) {
        if let Some(last) = self.last_frame
            && now - last > Duration::from_millis(500)
        {
            self.fps = 0.0;
            self.last_frame = None;
        }
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
    }

    /// This frame's request to the source.
    ///
    /// The first frame is asked for with a provisional camera if none was
    /// given; the camera is then fitted to the geometry and used from then on.
    fn request(&mut self, extent: vk::Extent2D, aspect: f32) -> Result<FrameRequest> {
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
            control: self.control,
            last_frame_time: self.last_frame_time,
            frame_index: self.report.frames,
            time: self.player.as_ref().map(|p| p.time_at(Instant::now())),
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
            self.home = Some(fitted);
            request.view = fitted.view(aspect);
            request.cull_view = self.frozen.unwrap_or(request.view);
        }
        Ok(request)
    }

    /// Writes a screenshot; returns whether it was the one that ends the
    /// session ([`ViewerOptions::screenshot_after`]).
    fn save_screenshot(&mut self, image: &image::RgbaImage, at_limit: bool) -> Result<bool> {
        let path = if at_limit {
            self.options.screenshot_path.clone()
        } else {
            numbered(
                &self.options.screenshot_path,
                self.report.screenshots.len() + 1,
            )
        };
        write_png(&path, image)?;
        log::info!("screenshot: {}", path.display());
        self.report.screenshots.push(path);
        self.screenshot_requested = false;
        Ok(at_limit)
    }
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
        // Resizes, keys, drags and the wheel change what is shown; plain cursor moves do not.
        let changes = match &event {
            WindowEvent::Resized(_)
            | WindowEvent::KeyboardInput { .. }
            | WindowEvent::MouseWheel { .. } => true,
            WindowEvent::CursorMoved { .. } => self.left || self.middle,
            _ => false,
        };
        self.dirty |= changes;
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(_) => {
                if let Some(gpu) = self.gpu.as_mut() {
                    gpu.swapchain_dirty = true;
                }
                // Look at the new size at once, even if it is 0×0 again.
                self.zero_extent = false;
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
            WindowEvent::ModifiersChanged(m) => self.modifiers = m.state(),
            WindowEvent::MouseInput { state, button, .. } => {
                let pressed = state == ElementState::Pressed;
                match button {
                    MouseButton::Left => self.left = pressed,
                    MouseButton::Middle => self.middle = pressed,
                    _ => {}
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                if let Some((x, y)) = self.cursor {
                    let (dx, dy) = ((position.x - x) as f32, (position.y - y) as f32);
                    match drag(self.left, self.middle, self.modifiers.shift_key()) {
                        Some(Drag::Pan) => self.pan(dx, dy),
                        Some(Drag::Orbit) => {
                            if let Some(camera) = self.camera.as_mut() {
                                camera.rotate(dx * 0.01, dy * 0.01);
                            }
                        }
                        None => {}
                    }
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

    /// Draws again only when something changed or frames run back to back
    /// ([`App::continuous`]); otherwise the loop sleeps until the next event.
    /// While the window or its surface is 0×0 it only looks at the size again,
    /// every [`ZERO_EXTENT_POLL`].
    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        if self.zero_extent {
            // Nothing can be drawn: look again later instead of spinning.
            let now = Instant::now();
            let next = match self.next_zero_check {
                Some(t) if now < t => t,
                _ => {
                    if let Some(window) = self.window.as_ref() {
                        window.request_redraw();
                    }
                    now.checked_add(ZERO_EXTENT_POLL).unwrap_or(now)
                }
            };
            self.next_zero_check = Some(next);
            event_loop.set_control_flow(ControlFlow::WaitUntil(next));
            return;
        }
        let continuous = self.continuous();
        event_loop.set_control_flow(if continuous {
            ControlFlow::Poll
        } else {
            ControlFlow::Wait
        });
        if (continuous || self.dirty || self.screenshot_requested)
            && let Some(window) = self.window.as_ref()
        {
            self.dirty = false;
            window.request_redraw();
        }
    }
}
