//! The viewer's GPU state: Vulkan context, pipelines and the frames in flight,
//! and the drawing of one frame into the swapchain.

use std::collections::VecDeque;
use std::ops::Range;
use std::time::Instant;

use ash::{khr, vk};
use raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::window::Window;

use super::SwapchainFault;
use super::slot::{Slot, begin_commands, create_slot};
use super::swapchain::{Swapchain, record_blit};
use super::versions::{History, Write};
use crate::context::{Context, ContextOptions};
use crate::error::{Result, VkError, VkResultExt};
use crate::frame::{self, FrameInputs, Readback, Target};
use crate::overlay::Overlay;
use crate::pipeline::Pipelines;
use crate::samples;
use crate::scene::{self, Layout, RenderMesh, RenderOptions, View};

/// Frames in flight: the CPU builds frame n+1 while the GPU draws frame n.
const FRAMES_IN_FLIGHT: usize = 2;

/// Surface losses in a row (no frame presented in between) that are recovered from by
/// creating the surface again; one more ends the viewer with [`VkError::SurfaceLost`].
const SURFACE_RETRIES: u32 = 3;

pub(super) struct Gpu {
    pub(super) ctx: Context,
    pipelines: Pipelines,
    pub(super) loader: khr::swapchain::Device,
    pool: vk::CommandPool,
    slots: Vec<Slot>,
    next: usize,
    pub(super) swapchain: Option<Swapchain>,
    pub(super) swapchain_dirty: bool,
    pub(super) format: vk::SurfaceFormatKHR,
    /// The surface reported `VK_ERROR_SURFACE_LOST_KHR`: create it again before the next frame.
    pub(super) surface_lost: bool,
    /// Surface losses since the last frame presented.
    losses: u32,
    /// Times the surface was created again.
    pub(super) surface_recreations: u64,
    /// The extent of each swapchain created, in order.
    pub(super) extents: Vec<[u32; 2]>,
    /// Faults injected by tests ([`super::Fault`]).
    pub(super) injected: Injected,
    /// The dirty vertex ranges of the source's last versions.
    history: History,
}

/// Results the next swapchain calls are made to report ([`super::Fault`]).
#[derive(Default)]
pub(super) struct Injected {
    pub(super) acquire: VecDeque<SwapchainFault>,
    pub(super) present: VecDeque<SwapchainFault>,
    /// Until then the surface's current extent reads 0×0.
    pub(super) zero_surface_until: Option<Instant>,
}

impl Injected {
    pub(super) fn zero_surface(&self) -> bool {
        self.zero_surface_until.is_some_and(|t| Instant::now() < t)
    }
}

/// What [`Gpu::draw`] did.
pub(super) enum Drawn {
    /// Nothing: the swapchain was out of date or the surface lost (marked for
    /// re-creation before the next frame).
    Skipped,
    /// The frame was rendered and presented; with the screenshot, if one was asked for.
    Presented(Option<image::RgbaImage>),
}

/// One frame's mesh, packed on the CPU before waiting for the slot.
struct Packed<'a> {
    mesh: &'a RenderMesh<'a>,
    options: &'a RenderOptions,
    overlay: &'a Overlay,
    /// The packed bytes; without the vertices unless everything is written.
    bytes: Vec<u8>,
    layout: Layout,
    /// Where `bytes` belong in the buffer.
    offset: u64,
    /// Which vertices the slot writes.
    write: Write,
    vertex_version: Option<u64>,
}

impl Gpu {
    pub(super) fn new(window: &Window, options: &ContextOptions) -> Result<Self> {
        let display = window
            .display_handle()
            .map_err(|e| VkError::Window(e.to_string()))?
            .as_raw();
        let extensions = ash_window::enumerate_required_extensions(display)
            .call("enumerate surface extensions")?;
        let factory =
            |entry: &ash::Entry, instance: &ash::Instance| create_surface(entry, instance, window);
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
            history: History::default(),
            swapchain: None,
            swapchain_dirty: true,
            format: vk::SurfaceFormatKHR::default(),
            surface_lost: false,
            losses: 0,
            surface_recreations: 0,
            extents: Vec::new(),
            injected: Injected::default(),
        };
        let (surface_loader, surface) = gpu.surface()?;
        // SAFETY: the physical device and the surface were both created from
        // this context's instance, which outlives the call.
        let formats = unsafe {
            surface_loader.get_physical_device_surface_formats(gpu.ctx.physical, surface)
        }
        .call("vkGetPhysicalDeviceSurfaceFormatsKHR")?;
        gpu.format = pick_format(&formats)?;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(gpu.ctx.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: the device is live and `pool_info` names its queue family;
        // should a later step fail, `Drop for Gpu` destroys the pool.
        gpu.pool = unsafe { gpu.ctx.device.create_command_pool(&pool_info, None) }
            .call("vkCreateCommandPool")?;
        for _ in 0..FRAMES_IN_FLIGHT {
            let slot = create_slot(&gpu.ctx.device, gpu.pool)?;
            gpu.slots.push(slot);
        }
        Ok(gpu)
    }

    pub(super) fn surface(&self) -> Result<(&khr::surface::Instance, vk::SurfaceKHR)> {
        self.ctx
            .surface
            .as_ref()
            .map(|(l, s)| (l, *s))
            .ok_or(VkError::Window("no surface".into()))
    }

    /// Creates the surface again after `VK_ERROR_SURFACE_LOST_KHR`, and marks the swapchain
    /// for re-creation; returns whether it worked (`false`: lost again, retry next frame).
    /// Fails with [`VkError::SurfaceLost`] after [`SURFACE_RETRIES`] losses in a row.
    pub(super) fn recreate_surface(&mut self, window: &Window) -> Result<bool> {
        self.losses += 1;
        if self.losses > SURFACE_RETRIES {
            return Err(VkError::SurfaceLost { times: self.losses });
        }
        log::warn!("the window's Vulkan surface was lost; creating it again");
        // SAFETY: the device is live. Once it is idle, no submission uses the
        // swapchain's semaphores and no presentation waits on them.
        unsafe { self.ctx.device.device_wait_idle() }.call("vkDeviceWaitIdle")?;
        // A swapchain goes before its surface.
        if let Some(s) = self.swapchain.take() {
            self.destroy_swapchain(s);
        }
        self.swapchain_dirty = true;
        if let Some((loader, old)) = self.ctx.surface.take() {
            // SAFETY: the surface was created from this instance, its swapchain is
            // destroyed above, and it is taken out of the context: destroyed once.
            unsafe { loader.destroy_surface(old, None) };
            let raw = create_surface(&self.ctx.entry, &self.ctx.instance, window)?;
            self.ctx.surface = Some((loader, raw));
        }
        let (loader, surface) = self.surface()?;
        let (physical, family) = (self.ctx.physical, self.ctx.queue_family);
        // SAFETY: the physical device and the new surface come from this
        // context's instance, and `family` is one of the device's queue families.
        let support =
            unsafe { loader.get_physical_device_surface_support(physical, family, surface) };
        let Some(support) = unless_lost(support, "vkGetPhysicalDeviceSurfaceSupportKHR")? else {
            return Ok(false);
        };
        if !support {
            return Err(VkError::Window(
                "the viewer's queue cannot present to the recreated surface".into(),
            ));
        }
        // SAFETY: as above.
        let formats = unsafe { loader.get_physical_device_surface_formats(physical, surface) };
        let Some(formats) = unless_lost(formats, "vkGetPhysicalDeviceSurfaceFormatsKHR")? else {
            return Ok(false);
        };
        self.format = pick_format(&formats)?;
        self.surface_lost = false;
        self.surface_recreations += 1;
        Ok(true)
    }

    /// Draws and presents one frame with `overlay` on top; with `screenshot`, waits for it and
    /// returns the image.
    pub(super) fn draw(
        &mut self,
        mesh: &RenderMesh<'_>,
        view: &View,
        options: &RenderOptions,
        overlay: &Overlay,
        (vertex_version, dirty): (Option<u64>, Option<&[Range<u32>]>),
        screenshot: bool,
    ) -> Result<Drawn> {
        let Some(extent) = self.swapchain.as_ref().map(|s| s.extent) else {
            return Ok(Drawn::Skipped);
        };
        let index = self.next;
        // CPU work first (overlaps the GPU's previous frame): pack the mesh,
        // without the vertices if this slot's buffer already holds them.
        let samples = samples::choose(
            options.samples,
            self.ctx.sample_counts,
            self.ctx.device_name(),
        )?;
        self.pipelines.prepare(&self.ctx, samples)?;
        // Only the vertices that changed since the slot's version, when that is known.
        self.history.record(vertex_version, dirty);
        let n = mesh.positions.len();
        let write = self
            .history
            .write(self.slots[index].vertices, vertex_version, n);
        let (bytes, layout, offset) =
            scene::pack_from(mesh, options, overlay, write == Write::All)?;
        let packed = Packed {
            mesh,
            options,
            overlay,
            bytes,
            layout,
            offset,
            write,
            vertex_version,
        };
        self.next = (self.next + 1) % FRAMES_IN_FLIGHT;
        let (fence, acquired, cmd) = {
            let slot = &self.slots[index];
            (slot.fence, slot.acquired, slot.cmd)
        };
        // SAFETY: `fence` was created by this device for this slot; it is either
        // still signalled from creation or pending on the slot's last submission.
        unsafe { self.ctx.device.wait_for_fences(&[fence], true, u64::MAX) }
            .call("vkWaitForFences")?;

        // Acquire before touching the fence, so an out-of-date swapchain leaves it signalled.
        let Some(image_index) = self.acquire(acquired)? else {
            return Ok(Drawn::Skipped);
        };
        let mesh_buffer = self.prepare_slot(index, (extent, samples), &packed)?;
        let slot = &self.slots[index];
        let (Some(target), Some(swapchain)) = (slot.target.as_ref(), self.swapchain.as_ref())
        else {
            return Ok(Drawn::Skipped);
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
        begin_commands(device, fence, cmd)?;
        frame::record(
            device,
            cmd,
            &FrameInputs {
                pipelines: &self.pipelines,
                target,
                mesh_buffer,
                layout: &packed.layout,
                view,
                options,
                readback: if screenshot {
                    Readback::Color
                } else {
                    Readback::None
                },
            },
        )?;
        record_blit(device, cmd, target.color.raw, swap_image, extent);
        let presented =
            self.submit_and_present(cmd, fence, (acquired, rendered), swapchain.raw, image_index)?;
        // An injected fault replaces a success only: the image was presented, as it is
        // when a real out-of-date or lost-surface presentation is rejected.
        let presented = match (presented, self.injected.present.pop_front()) {
            (Ok(_), Some(SwapchainFault::OutOfDate)) => Err(vk::Result::ERROR_OUT_OF_DATE_KHR),
            (Ok(_), Some(SwapchainFault::Suboptimal)) => Ok(true),
            (Ok(_), Some(SwapchainFault::SurfaceLost)) => Err(vk::Result::ERROR_SURFACE_LOST_KHR),
            (presented, _) => presented,
        };
        // The frame was rendered either way (the screenshot below is valid); a rejected
        // presentation only means the next frame needs a new swapchain or surface.
        match presented {
            Ok(suboptimal) => {
                self.swapchain_dirty |= suboptimal;
                self.losses = 0;
            }
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => self.swapchain_dirty = true,
            Err(vk::Result::ERROR_SURFACE_LOST_KHR) => self.surface_lost = true,
            Err(result) => {
                return Err(VkError::Vulkan {
                    call: "vkQueuePresentKHR",
                    result,
                });
            }
        }
        if !screenshot {
            return Ok(Drawn::Presented(None));
        }
        // SAFETY: `fence` belongs to this device and was just submitted with this frame.
        unsafe { device.wait_for_fences(&[fence], true, u64::MAX) }.call("vkWaitForFences")?;
        target
            .read_color()
            .map(|image| Drawn::Presented(Some(image)))
    }

    /// Acquires the next swapchain image, signalling `acquired`; `None` (and
    /// the swapchain or the surface marked for re-creation) when it is out of
    /// date or the surface is lost.
    fn acquire(&mut self, acquired: vk::Semaphore) -> Result<Option<u32>> {
        let swapchain_raw = self
            .swapchain
            .as_ref()
            .map_or(vk::SwapchainKHR::null(), |s| s.raw);
        // An injected error acquires nothing (`acquired` stays unsignalled, as
        // after a real error); an injected suboptimal result acquires an image.
        let acquire = match self.injected.acquire.pop_front() {
            Some(SwapchainFault::OutOfDate) => Err(vk::Result::ERROR_OUT_OF_DATE_KHR),
            Some(SwapchainFault::SurfaceLost) => Err(vk::Result::ERROR_SURFACE_LOST_KHR),
            injected => {
                // SAFETY: `swapchain_raw` is this loader's current swapchain (`draw`
                // read its extent); `acquired` has no pending operation: its last wait
                // was in this slot's previous submission, which completed when the
                // slot's fence signalled (waited on by `draw` just before). An error
                // between this acquire and the submit would leave it signalled, but
                // every error from `draw` ends the viewer.
                unsafe {
                    self.loader.acquire_next_image(
                        swapchain_raw,
                        u64::MAX,
                        acquired,
                        vk::Fence::null(),
                    )
                }
                .map(|(i, suboptimal)| (i, suboptimal || injected.is_some()))
            }
        };
        match acquire {
            Ok((i, suboptimal)) => {
                self.swapchain_dirty |= suboptimal;
                Ok(Some(i))
            }
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => {
                self.swapchain_dirty = true;
                Ok(None)
            }
            Err(vk::Result::ERROR_SURFACE_LOST_KHR) => {
                self.surface_lost = true;
                Ok(None)
            }
            Err(result) => Err(VkError::Vulkan {
                call: "vkAcquireNextImageKHR",
                result,
            }),
        }
    }

    /// Submits `cmd` (waiting on `acquired`, signalling `rendered` and
    /// `fence`) and presents image `image_index`; returns the present result.
    fn submit_and_present(
        &self,
        cmd: vk::CommandBuffer,
        fence: vk::Fence,
        (acquired, rendered): (vk::Semaphore, vk::Semaphore),
        swapchain: vk::SwapchainKHR,
        image_index: u32,
    ) -> Result<std::result::Result<bool, vk::Result>> {
        let device = &self.ctx.device;
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
        let swapchains = [swapchain];
        let indices = [image_index];
        let wait_present = [rendered];
        let present = vk::PresentInfoKHR::default()
            .wait_semaphores(&wait_present)
            .swapchains(&swapchains)
            .image_indices(&indices);
        // SAFETY: `cmd` is fully recorded and ends here; `fence` was reset by
        // `begin_commands` and is unsignalled; `acquired` is signalled by the
        // acquire of this frame and waited on by this submission; `rendered`
        // belongs to the acquired image and is signalled here and waited on by
        // its presentation; the queue is used from this thread only.
        unsafe {
            device.end_command_buffer(cmd).call("vkEndCommandBuffer")?;
            device
                .queue_submit2(self.ctx.queue, &submit, fence)
                .call("vkQueueSubmit2")?;
            Ok(self.loader.queue_present(self.ctx.queue, &present))
        }
    }

    /// Gives slot `index` a target of `extent` and `samples` per pixel and uploads the frame's mesh
    /// (only the part after the vertices when the slot still holds them);
    /// returns the mesh buffer. The slot's fence has been waited on.
    fn prepare_slot(
        &mut self,
        index: usize,
        (extent, samples): (vk::Extent2D, u32),
        packed: &Packed<'_>,
    ) -> Result<vk::Buffer> {
        let slot = &mut self.slots[index];
        if slot
            .target
            .as_ref()
            .is_none_or(|t| !t.fits(extent, samples))
        {
            if let Some(mut old) = slot.target.take() {
                old.destroy(&mut self.ctx);
            }
            slot.target = Some(Target::new(&mut self.ctx, extent, samples)?);
        }
        slot.vertices = None;
        let total = packed.layout.total;
        let kept = match &packed.write {
            Write::Ranges(dirty) => {
                let ok = slot.mesh.upload_vertices(packed.mesh, dirty, total)?;
                match slot.mesh.upload_at(&packed.bytes, packed.offset, total)? {
                    Some(buffer) if ok => Some(buffer),
                    _ => None,
                }
            }
            Write::All => None,
        };
        let reuse = packed.write != Write::All;
        let mesh_buffer = match kept {
            Some(buffer) => buffer,
            None if reuse => {
                let (all, _) = scene::pack(packed.mesh, packed.options, packed.overlay)?;
                slot.mesh.upload(&mut self.ctx, &all)?
            }
            None => slot.mesh.upload(&mut self.ctx, &packed.bytes)?,
        };
        slot.vertices = packed
            .vertex_version
            .map(|v| (v, packed.mesh.positions.len()));
        Ok(mesh_buffer)
    }
}

/// Creates a Vulkan surface for `window`.
fn create_surface(
    entry: &ash::Entry,
    instance: &ash::Instance,
    window: &Window,
) -> Result<vk::SurfaceKHR> {
    let display = window
        .display_handle()
        .map_err(|e| VkError::Window(e.to_string()))?
        .as_raw();
    let handle = window
        .window_handle()
        .map_err(|e| VkError::Window(e.to_string()))?
        .as_raw();
    // SAFETY: `display` and `handle` are the live raw handles of `window`; the
    // instance was created with the extensions ash-window lists for this
    // display; the window outlives the surface, because the viewer drops the
    // GPU state (whose context destroys the surface) first.
    unsafe { ash_window::create_surface(entry, instance, display, handle, None) }
        .call("vkCreate*SurfaceKHR")
}

/// The swapchain format: UNORM keeps the shader's values, so the window equals
/// headless renders; else the surface's first.
fn pick_format(formats: &[vk::SurfaceFormatKHR]) -> Result<vk::SurfaceFormatKHR> {
    [vk::Format::B8G8R8A8_UNORM, vk::Format::R8G8B8A8_UNORM]
        .iter()
        .find_map(|f| formats.iter().find(|s| s.format == *f).copied())
        .or_else(|| formats.first().copied())
        .ok_or(VkError::Window("the surface offers no formats".into()))
}

/// `Ok(None)` for `VK_ERROR_SURFACE_LOST_KHR`, which the viewer recovers from by
/// creating the surface again; other errors name `call`.
pub(super) fn unless_lost<T>(
    result: std::result::Result<T, vk::Result>,
    call: &'static str,
) -> Result<Option<T>> {
    match result {
        Ok(v) => Ok(Some(v)),
        Err(vk::Result::ERROR_SURFACE_LOST_KHR) => Ok(None),
        Err(result) => Err(VkError::Vulkan { call, result }),
    }
}

impl Drop for Gpu {
    fn drop(&mut self) {
        // SAFETY: the device is live (the context is dropped after this body);
        // waiting for it to be idle makes every object destroyed below unused.
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
            // SAFETY: the device is idle (waited above); the fence and semaphore
            // were created by this device for this slot and are destroyed once,
            // as the slots were taken out of `self`.
            unsafe {
                self.ctx.device.destroy_fence(slot.fence, None);
                self.ctx.device.destroy_semaphore(slot.acquired, None);
            }
        }
        self.pipelines.destroy(&self.ctx);
        if self.pool != vk::CommandPool::null() {
            // SAFETY: the device is idle; the pool was created by this device, and
            // destroying it frees the slots' command buffers, none of them pending.
            unsafe { self.ctx.device.destroy_command_pool(self.pool, None) };
        }
    }
}
