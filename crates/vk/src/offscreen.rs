//! The headless renderer: draws a [`RenderMesh`] into offscreen targets and
//! reads the pixels back.

use ash::vk;
use image::RgbaImage;

use crate::context::{Context, ContextOptions, ValidationLog};
use crate::error::{Result, VkResultExt};
use crate::frame::{self, FrameInputs, Readback, Target};
use crate::mesh_buffer::MeshBuffer;
use crate::pipeline::Pipelines;
use crate::samples;
use crate::scene::{self, RenderMesh, RenderOptions, View};

/// Per-pixel data besides colour, read back from the auxiliary targets.
///
/// Pixels are row-major from the top-left corner. Background pixels have
/// `depth = +inf`, `coverage = 0`, zero normal and zero scalar.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AuxImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Linear view depth: distance from the eye along the viewing direction.
    pub depth: Vec<f32>,
    /// Unit world-space normal of the visible surface (as interpolated, not flipped).
    pub normals: Vec<[f32; 3]>,
    /// The interpolated per-vertex scalar ([`RenderMesh::scalars`]).
    pub scalars: Vec<f32>,
    /// 1 where a surface covers the pixel, else 0.
    pub coverage: Vec<f32>,
}

impl AuxImage {
    /// Index of pixel (`x`, `y`), `None` outside the image.
    pub fn index(&self, x: u32, y: u32) -> Option<usize> {
        (x < self.width && y < self.height).then(|| y as usize * self.width as usize + x as usize)
    }
}

/// A headless Vulkan renderer with its own instance and device.
///
/// ```no_run
/// use subdiv_vk::{OrbitCamera, RenderMesh, RenderOptions, Renderer, Shading};
///
/// # fn main() -> Result<(), subdiv_vk::VkError> {
/// let positions = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]];
/// let normals = [[0.0, 0.0, 1.0]; 3];
/// let mesh = RenderMesh {
///     positions: &positions,
///     normals: &normals,
///     triangles: &[0, 1, 2],
///     ..Default::default()
/// };
/// let (width, height) = (640, 480);
/// let view = OrbitCamera::framing_mesh(&mesh).view(width as f32 / height as f32);
/// let options = RenderOptions { shading: Shading::Smooth, wire_overlay: true, ..Default::default() };
///
/// let mut renderer = Renderer::new()?; // fails with a clear error if no Vulkan driver is installed
/// let (image, aux) = renderer.render_with_aux(&mesh, &view, [width, height], &options)?;
/// subdiv_vk::write_png("out.png", &image)?;
/// subdiv_vk::write_exr("out.exr", &aux)?;
/// # Ok(())
/// # }
/// ```
pub struct Renderer {
    // Field order matters only for `Drop` below, which tears down explicitly.
    ctx: Context,
    pipelines: Pipelines,
    pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    target: Option<Target>,
    mesh: MeshBuffer,
    /// The version and count of the vertices the mesh buffer holds, when a versioned render
    /// wrote them ([`Renderer::render_discard_versioned`]).
    held: Option<(u64, usize)>,
}

impl Renderer {
    /// A renderer with default options: system Vulkan loader, validation layer
    /// when `SUBDIV_VK_VALIDATION=1`.
    pub fn new() -> Result<Self> {
        Self::with_options(&ContextOptions::default())
    }

    /// A renderer with explicit loader / validation options.
    pub fn with_options(options: &ContextOptions) -> Result<Self> {
        let ctx = Context::new(options, &[], None)?;
        let pipelines = Pipelines::new(&ctx)?;
        let mut renderer = Renderer {
            ctx,
            pipelines,
            pool: vk::CommandPool::null(),
            cmd: vk::CommandBuffer::null(),
            fence: vk::Fence::null(),
            target: None,
            mesh: MeshBuffer::default(),
            held: None,
        };
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(renderer.ctx.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        let device = &renderer.ctx.device;
        // SAFETY: `device` is live and `pool_info` names its queue family; should
        // a later step fail, `Drop for Renderer` destroys the pool.
        renderer.pool =
            unsafe { device.create_command_pool(&pool_info, None) }.call("vkCreateCommandPool")?;
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(renderer.pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool was just created from `device` and is used by this
        // thread only; `alloc` lives through the call.
        let buffers =
            unsafe { device.allocate_command_buffers(&alloc) }.call("vkAllocateCommandBuffers")?;
        renderer.cmd = buffers.first().copied().unwrap_or_default();
        // SAFETY: `device` is live; the fence starts unsignalled, as `draw`
        // expects for its first submission. `Drop` destroys it.
        renderer.fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }
            .call("vkCreateFence")?;
        Ok(renderer)
    }

    /// Name of the Vulkan device in use.
    pub fn device_name(&self) -> &str {
        self.ctx.device_name()
    }

    /// Validation messages collected so far (always empty without the layer).
    /// Clone it before dropping the renderer to see messages from teardown too.
    pub fn validation_log(&self) -> ValidationLog {
        self.ctx.validation_log()
    }

    /// Whether the Khronos validation layer is active.
    pub fn validation_enabled(&self) -> bool {
        self.ctx.validation_enabled()
    }

    /// The samples per pixel the device can draw with (of [`crate::SAMPLE_COUNTS`]; 1 always).
    pub fn sample_counts(&self) -> Vec<u32> {
        samples::counts(self.ctx.sample_counts)
    }

    /// The samples per pixel a render with `options` uses here: [`RenderOptions::samples`] if
    /// the device supports it ([`VkError::Samples`](crate::VkError::Samples) otherwise), or
    /// without one [`DEFAULT_SAMPLES`](crate::DEFAULT_SAMPLES) where supported, else the most
    /// the device supports below it.
    pub fn samples(&self, options: &RenderOptions) -> Result<u32> {
        samples::choose(
            options.samples,
            self.ctx.sample_counts,
            self.ctx.device_name(),
        )
    }

    /// Renders `mesh` seen through `view` at `size` = `[width, height]` and
    /// returns the colour image.
    pub fn render(
        &mut self,
        mesh: &RenderMesh<'_>,
        view: &View,
        size: [u32; 2],
        options: &RenderOptions,
    ) -> Result<RgbaImage> {
        self.draw(mesh, view, size, options, Readback::Color)?;
        self.target()?.read_color()
    }

    /// Like [`Renderer::render`], also returning depth, normals and scalars per pixel.
    pub fn render_with_aux(
        &mut self,
        mesh: &RenderMesh<'_>,
        view: &View,
        size: [u32; 2],
        options: &RenderOptions,
    ) -> Result<(RgbaImage, AuxImage)> {
        self.draw(mesh, view, size, options, Readback::All)?;
        let target = self.target()?;
        Ok((target.read_color()?, target.read_aux()?))
    }

    /// Renders and waits for the GPU without reading pixels back (for
    /// frame-rate benchmarks: the time of this call is the frame time).
    pub fn render_discard(
        &mut self,
        mesh: &RenderMesh<'_>,
        view: &View,
        size: [u32; 2],
        options: &RenderOptions,
    ) -> Result<()> {
        self.draw(mesh, view, size, options, Readback::None)
    }

    /// [`Renderer::render_discard`] for a mesh whose vertices change a little from frame to
    /// frame (an adaptive frame): `version` identifies its vertex data, and `dirty` names the
    /// vertices that differ from version `version - 1`'s. When the renderer holds the previous
    /// (or this) version's vertices from the last call, it writes only the `dirty` ones and the
    /// indices (vertices appended since must be among the `dirty` ones, and the buffer must have
    /// room for them); otherwise everything. The caller guarantees that the vertices outside
    /// `dirty` equal those of version `version - 1`
    /// (`subdiv_stitch::AdaptiveFrame::dirty_vertices`).
    pub fn render_discard_versioned(
        &mut self,
        mesh: &RenderMesh<'_>,
        view: &View,
        size: [u32; 2],
        options: &RenderOptions,
        version: u64,
        dirty: &[std::ops::Range<u32>],
    ) -> Result<()> {
        self.draw_versioned(mesh, view, size, options, (version, dirty), Readback::None)
    }

    /// [`Renderer::render_discard_versioned`], returning the colour image.
    pub fn render_versioned(
        &mut self,
        mesh: &RenderMesh<'_>,
        view: &View,
        size: [u32; 2],
        options: &RenderOptions,
        version: u64,
        dirty: &[std::ops::Range<u32>],
    ) -> Result<RgbaImage> {
        self.draw_versioned(mesh, view, size, options, (version, dirty), Readback::Color)?;
        self.target()?.read_color()
    }

    fn draw_versioned(
        &mut self,
        mesh: &RenderMesh<'_>,
        view: &View,
        size: [u32; 2],
        options: &RenderOptions,
        (version, dirty): (u64, &[std::ops::Range<u32>]),
        readback: Readback,
    ) -> Result<()> {
        let n = mesh.positions.len();
        // Vertices appended since the held version (an adaptive frame's new blocks) must be
        // among the dirty ones; the others kept their index and bits.
        let keep = match self.held {
            Some((v, count)) => {
                (v == version || v + 1 == version)
                    && (count >= n || scene::covers(dirty, count as u32..n as u32))
            }
            None => false,
        };
        // Overlays and legends are not kept: they are drawn after the shared vertices.
        let keep = keep && !options.legend;
        self.held = None;
        let upload = if keep {
            Upload::Keep(dirty)
        } else {
            Upload::All
        };
        self.draw_with(mesh, view, size, options, readback, upload)?;
        self.held = Some((version, n));
        Ok(())
    }

    fn target(&self) -> Result<&Target> {
        self.target.as_ref().ok_or(crate::VkError::Vulkan {
            call: "render target",
            result: vk::Result::ERROR_UNKNOWN,
        })
    }

    fn draw(
        &mut self,
        mesh: &RenderMesh<'_>,
        view: &View,
        size: [u32; 2],
        options: &RenderOptions,
        readback: Readback,
    ) -> Result<()> {
        // Any unversioned draw overwrites the vertices a versioned one may rely on.
        self.held = None;
        self.draw_with(mesh, view, size, options, readback, Upload::All)
    }

    fn draw_with(
        &mut self,
        mesh: &RenderMesh<'_>,
        view: &View,
        size: [u32; 2],
        options: &RenderOptions,
        readback: Readback,
        upload: Upload<'_>,
    ) -> Result<()> {
        let overlay = if options.legend {
            crate::overlay::legend(options.shading, scene::scalar_range(mesh, options), size)
        } else {
            crate::overlay::Overlay::default()
        };
        let keep = matches!(upload, Upload::Keep(_));
        let (bytes, layout, offset) = scene::pack_from(mesh, options, &overlay, !keep)?;
        let extent = vk::Extent2D {
            width: size[0],
            height: size[1],
        };
        let samples = self.samples(options)?;
        self.pipelines.prepare(&self.ctx, samples)?;
        if self
            .target
            .as_ref()
            .is_none_or(|t| !t.fits(extent, samples))
        {
            if let Some(mut old) = self.target.take() {
                old.destroy(&mut self.ctx);
            }
            self.target = Some(Target::new(&mut self.ctx, extent, samples)?);
        }
        let kept = match upload {
            Upload::Keep(dirty) => {
                let ok = self.mesh.upload_vertices(mesh, dirty, layout.total)?;
                match self.mesh.upload_at(&bytes, offset, layout.total)? {
                    Some(b) if ok => Some(b),
                    _ => None,
                }
            }
            Upload::All => None,
        };
        let mesh_buffer = match kept {
            Some(b) => b,
            None if keep => {
                // The buffer could not take the frame in place: everything, packed afresh.
                let (all, _) = scene::pack(mesh, options, &overlay)?;
                self.mesh.upload(&mut self.ctx, &all)?
            }
            None => self.mesh.upload(&mut self.ctx, &bytes)?,
        };
        let target = self.target()?;
        let device = &self.ctx.device;
        let cmd = self.cmd;
        // SAFETY: every earlier submission of `cmd` was waited for on the fence
        // before `draw` returned (that wait fails only on device loss), so the
        // GPU no longer uses the command buffer, target or mesh buffer; `cmd`
        // comes from a pool created with RESET_COMMAND_BUFFER.
        unsafe {
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
                readback,
            },
        )?;
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
        let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmds)];
        // SAFETY: `cmd` was fully recorded by `frame::record` and ends here; the
        // fence is unsignalled (created so, and reset after every wait); the
        // queue is used from this thread only (`&mut self`), and all handles the
        // commands reference live until the wait below returns.
        unsafe {
            device.end_command_buffer(cmd).call("vkEndCommandBuffer")?;
            device
                .queue_submit2(self.ctx.queue, &submit, self.fence)
                .call("vkQueueSubmit2")?;
            let waited = device.wait_for_fences(&[self.fence], true, u64::MAX);
            // Reset even after a failed wait would leave the fence unusable; report the wait error.
            waited.call("vkWaitForFences")?;
            device.reset_fences(&[self.fence]).call("vkResetFences")?;
        }
        Ok(())
    }
}

/// What a draw uploads of the mesh.
enum Upload<'a> {
    /// Everything.
    All,
    /// The indices and the rest, and of the shared vertices only these ranges: the buffer holds
    /// the others already.
    Keep(&'a [std::ops::Range<u32>]),
}

impl Drop for Renderer {
    fn drop(&mut self) {
        // SAFETY: the device is live (`ctx` is dropped after this body); once it
        // is idle, nothing destroyed here is in use by the GPU. Everything was
        // made from this device and is destroyed once (taken, or null-checked),
        // before `ctx` destroys the device itself.
        unsafe {
            let _ = self.ctx.device.device_wait_idle();
            if let Some(mut t) = self.target.take() {
                t.destroy(&mut self.ctx);
            }
            self.mesh.destroy(&mut self.ctx);
            self.pipelines.destroy(&self.ctx);
            if self.fence != vk::Fence::null() {
                self.ctx.device.destroy_fence(self.fence, None);
            }
            if self.pool != vk::CommandPool::null() {
                self.ctx.device.destroy_command_pool(self.pool, None);
            }
        }
    }
}
