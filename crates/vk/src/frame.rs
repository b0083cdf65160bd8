//! Render targets and the command recording of one frame, shared by the
//! headless renderer and the viewer (so both produce identical pixels).

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::context::Context;
use crate::error::{Result, VkError};
use crate::memory::{Buffer, Image, subresource_range};
use crate::pipeline::{COLOR_FORMAT, LINEAR_DEPTH_FORMAT, NORMAL_FORMAT, Pipelines};
use crate::scene::{self, Layout, RenderOptions, View};

/// Colour, auxiliary and depth attachments of one size, plus a host-visible
/// buffer that receives their contents.
pub(crate) struct Target {
    pub extent: vk::Extent2D,
    pub color: Image,
    normal: Image,
    linear_depth: Image,
    depth: Image,
    pub readback: Buffer,
}

/// Byte sizes per pixel of the readback sections: colour, normal+scalar, linear depth.
const COLOR_BYTES: u64 = 4;
const NORMAL_BYTES: u64 = 16;
const LINEAR_DEPTH_BYTES: u64 = 4;

/// What to copy into the readback buffer at the end of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Readback {
    None,
    Color,
    All,
}

impl Target {
    pub fn new(ctx: &mut Context, extent: vk::Extent2D) -> Result<Self> {
        let max = ctx.limits.max_image_dimension2_d;
        if extent.width == 0 || extent.height == 0 || extent.width > max || extent.height > max {
            return Err(VkError::InvalidSize {
                width: extent.width,
                height: extent.height,
                max,
            });
        }
        let color_usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
        let color_aspect = vk::ImageAspectFlags::COLOR;
        let mut made: Vec<Image> = Vec::new();
        let specs = [
            (COLOR_FORMAT, color_usage, color_aspect, "colour target"),
            (NORMAL_FORMAT, color_usage, color_aspect, "normal target"),
            (
                LINEAR_DEPTH_FORMAT,
                color_usage,
                color_aspect,
                "linear depth target",
            ),
            (
                ctx.depth_format,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
                vk::ImageAspectFlags::DEPTH,
                "depth target",
            ),
        ];
        for (format, usage, aspect, name) in specs {
            match Image::new(ctx, extent, format, usage, aspect, name) {
                Ok(image) => made.push(image),
                Err(e) => {
                    for mut image in made {
                        image.destroy(ctx);
                    }
                    return Err(e);
                }
            }
        }
        let pixels = u64::from(extent.width) * u64::from(extent.height);
        let readback = match Buffer::new(
            ctx,
            pixels * (COLOR_BYTES + NORMAL_BYTES + LINEAR_DEPTH_BYTES),
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
            "readback",
        ) {
            Ok(b) => b,
            Err(e) => {
                for mut image in made {
                    image.destroy(ctx);
                }
                return Err(e);
            }
        };
        let mut it = made.into_iter();
        match (it.next(), it.next(), it.next(), it.next()) {
            (Some(color), Some(normal), Some(linear_depth), Some(depth)) => Ok(Target {
                extent,
                color,
                normal,
                linear_depth,
                depth,
                readback,
            }),
            _ => Err(VkError::Vulkan {
                call: "create targets",
                result: vk::Result::ERROR_UNKNOWN,
            }),
        }
    }

    pub fn destroy(&mut self, ctx: &mut Context) {
        self.color.destroy(ctx);
        self.normal.destroy(ctx);
        self.linear_depth.destroy(ctx);
        self.depth.destroy(ctx);
        self.readback.destroy(ctx);
    }

    fn pixels(&self) -> u64 {
        u64::from(self.extent.width) * u64::from(self.extent.height)
    }

    /// The colour image read back (valid after a frame with [`Readback::Color`] or `All` completed).
    pub fn read_color(&self) -> Result<image::RgbaImage> {
        let n = (self.pixels() * COLOR_BYTES) as usize;
        let bytes = self
            .readback
            .mapped()?
            .get(..n)
            .map(<[u8]>::to_vec)
            .unwrap_or_default();
        image::RgbaImage::from_raw(self.extent.width, self.extent.height, bytes).ok_or(
            VkError::Vulkan {
                call: "read back colour",
                result: vk::Result::ERROR_UNKNOWN,
            },
        )
    }

    /// The auxiliary images read back (valid after a frame with [`Readback::All`] completed).
    pub fn read_aux(&self) -> Result<crate::AuxImage> {
        let pixels = self.pixels() as usize;
        let mapped = self.readback.mapped()?;
        let normal_start = pixels * COLOR_BYTES as usize;
        let depth_start = normal_start + pixels * NORMAL_BYTES as usize;
        let f = |bytes: &[u8]| f32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]);
        let normal_bytes = mapped.get(normal_start..depth_start).unwrap_or_default();
        let depth_bytes = mapped
            .get(depth_start..depth_start + pixels * LINEAR_DEPTH_BYTES as usize)
            .unwrap_or_default();
        let mut aux = crate::AuxImage {
            width: self.extent.width,
            height: self.extent.height,
            depth: Vec::with_capacity(pixels),
            normals: Vec::with_capacity(pixels),
            scalars: Vec::with_capacity(pixels),
            coverage: Vec::with_capacity(pixels),
        };
        for (n, d) in normal_bytes
            .chunks_exact(16)
            .zip(depth_bytes.chunks_exact(4))
        {
            let depth = f(d);
            let covered = depth > 0.0;
            aux.coverage.push(if covered { 1.0 } else { 0.0 });
            aux.depth.push(if covered { depth } else { f32::INFINITY });
            aux.normals.push([f(&n[0..4]), f(&n[4..8]), f(&n[8..12])]);
            aux.scalars.push(f(&n[12..16]));
        }
        Ok(aux)
    }
}

fn image_barrier(
    image: vk::Image,
    aspect: vk::ImageAspectFlags,
    (src_stage, src_access, old): (vk::PipelineStageFlags2, vk::AccessFlags2, vk::ImageLayout),
    (dst_stage, dst_access, new): (vk::PipelineStageFlags2, vk::AccessFlags2, vk::ImageLayout),
) -> vk::ImageMemoryBarrier2<'static> {
    vk::ImageMemoryBarrier2::default()
        .src_stage_mask(src_stage)
        .src_access_mask(src_access)
        .dst_stage_mask(dst_stage)
        .dst_access_mask(dst_access)
        .old_layout(old)
        .new_layout(new)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .image(image)
        .subresource_range(subresource_range(aspect))
}

/// Everything `record` needs besides the device and command buffer.
pub(crate) struct FrameInputs<'a> {
    pub pipelines: &'a Pipelines,
    pub target: &'a Target,
    /// Buffer holding the packed mesh (see [`scene::pack`]).
    pub mesh_buffer: vk::Buffer,
    pub layout: &'a Layout,
    pub view: &'a View,
    pub options: &'a RenderOptions,
    pub readback: Readback,
}

/// Records one frame. Afterwards the colour image is in `TRANSFER_SRC_OPTIMAL`
/// layout and the requested readback copies are recorded and made host-visible.
///
/// `cmd` must be in the recording state; every handle in `f` must belong to
/// `device` and stay alive until the submission completes (the callers wait
/// on a fence before reusing or destroying any of them).
pub(crate) fn record(device: &ash::Device, cmd: vk::CommandBuffer, f: &FrameInputs<'_>) {
    begin_rendering(device, cmd, f);
    draw_triangles(device, cmd, f);
    draw_lines(device, cmd, f);
    draw_overlay(device, cmd, f);
    // SAFETY: `cmd` is recording inside the render pass begun by `begin_rendering`.
    unsafe { device.cmd_end_rendering(cmd) };
    to_transfer_source(device, cmd, f);
    if f.readback != Readback::None {
        copy_to_readback(device, cmd, f);
    }
}

/// Moves the attachments into their attachment layouts and begins rendering
/// to them (cleared), with viewport and scissor covering the target.
fn begin_rendering(device: &ash::Device, cmd: vk::CommandBuffer, f: &FrameInputs<'_>) {
    let t = f.target;
    let color_aspect = vk::ImageAspectFlags::COLOR;
    let attach_stage = vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT;
    let tests = vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
        | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS;
    let before = (
        vk::PipelineStageFlags2::ALL_TRANSFER | attach_stage,
        vk::AccessFlags2::NONE,
        vk::ImageLayout::UNDEFINED,
    );
    let to_attachment = (
        attach_stage,
        vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
        vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
    );
    let barriers = [
        image_barrier(t.color.raw, color_aspect, before, to_attachment),
        image_barrier(t.normal.raw, color_aspect, before, to_attachment),
        image_barrier(t.linear_depth.raw, color_aspect, before, to_attachment),
        image_barrier(
            t.depth.raw,
            vk::ImageAspectFlags::DEPTH,
            (tests, vk::AccessFlags2::NONE, vk::ImageLayout::UNDEFINED),
            (
                tests,
                vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ
                    | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
            ),
        ),
    ];
    let color_attachment = |view, clear: [f32; 4]| {
        vk::RenderingAttachmentInfo::default()
            .image_view(view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue {
                color: vk::ClearColorValue { float32: clear },
            })
    };
    let colors = [
        color_attachment(t.color.view, f.options.background),
        color_attachment(t.normal.view, [0.0; 4]),
        color_attachment(t.linear_depth.view, [0.0; 4]),
    ];
    let depth = vk::RenderingAttachmentInfo::default()
        .image_view(t.depth.view)
        .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::DONT_CARE)
        .clear_value(vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue {
                depth: 1.0,
                stencil: 0,
            },
        });
    let area = vk::Rect2D {
        offset: vk::Offset2D::default(),
        extent: t.extent,
    };
    let rendering = vk::RenderingInfo::default()
        .render_area(area)
        .layer_count(1)
        .color_attachments(&colors)
        .depth_attachment(&depth);
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: t.extent.width as f32,
        height: t.extent.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    // SAFETY: `cmd` is recording (see `record`); the target's images and views
    // belong to `device` and outlive the submission; the barriers move them
    // into the layouts the attachment infos name.
    unsafe {
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&barriers),
        );
        device.cmd_begin_rendering(cmd, &rendering);
        device.cmd_set_viewport(cmd, 0, &[viewport]);
        device.cmd_set_scissor(cmd, 0, &[area]);
    }
}

/// Draws the triangles (shaded, or depth and auxiliary targets only for
/// [`scene::Shading::Wire`]).
fn draw_triangles(device: &ash::Device, cmd: vk::CommandBuffer, f: &FrameInputs<'_>) {
    let l = f.layout;
    let p = f.pipelines;
    let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
    if l.tri_count == 0 {
        return;
    }
    let pipeline = if f.options.shading == scene::Shading::Wire {
        p.fill_depth_only
    } else {
        p.fill
    };
    let push = scene::mesh_push_constants(f.view, f.options, l);
    // SAFETY: `cmd` is recording inside the render pass; pipeline, layout and
    // mesh buffer belong to `device` and outlive the submission; the offsets
    // and counts come from the layout the buffer was packed with.
    unsafe {
        device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
        device.cmd_push_constants(cmd, p.layout, stages, 0, &push);
        device.cmd_bind_vertex_buffers(cmd, 0, &[f.mesh_buffer], &[l.tri_vertices]);
        if l.tri_indexed {
            device.cmd_bind_index_buffer(cmd, f.mesh_buffer, l.tri_indices, vk::IndexType::UINT32);
            device.cmd_draw_indexed(cmd, l.tri_count * 3, 1, 0, 0, 0);
        } else {
            device.cmd_draw(cmd, l.tri_count * 3, 1, 0, 0);
        }
    }
}

/// Draws the wireframe edges and the extra lines with the line pipeline.
fn draw_lines(device: &ash::Device, cmd: vk::CommandBuffer, f: &FrameInputs<'_>) {
    let l = f.layout;
    let p = f.pipelines;
    let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
    // SAFETY: as in `draw_triangles`; depth test and line width are dynamic
    // state of the line pipeline (line width only when `dynamic_line_width`).
    unsafe {
        if l.edge_count > 0 || l.line_count > 0 {
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, p.line);
        }
        if l.edge_count > 0 {
            let push = scene::line_push_constants(f.view, f.options.wire_color);
            device.cmd_push_constants(cmd, p.layout, stages, 0, &push);
            device.cmd_set_depth_test_enable(cmd, true);
            if p.dynamic_line_width {
                device.cmd_set_line_width(cmd, p.line_width(f.options.wire_width));
            }
            device.cmd_bind_vertex_buffers(cmd, 0, &[f.mesh_buffer], &[l.vertices]);
            device.cmd_bind_index_buffer(cmd, f.mesh_buffer, l.edge_indices, vk::IndexType::UINT32);
            device.cmd_draw_indexed(cmd, l.edge_count * 2, 1, 0, 0, 0);
        }
        if l.line_count > 0 {
            let push = scene::line_push_constants(f.view, f.options.line_color);
            device.cmd_push_constants(cmd, p.layout, stages, 0, &push);
            device.cmd_set_depth_test_enable(cmd, !f.options.lines_on_top);
            if p.dynamic_line_width {
                device.cmd_set_line_width(cmd, p.line_width(f.options.line_width));
            }
            device.cmd_bind_vertex_buffers(cmd, 0, &[f.mesh_buffer], &[l.line_vertices]);
            device.cmd_draw(cmd, l.line_count * 2, 1, 0, 0);
        }
    }
}

/// Draws the overlay rectangles (HUD, legend) over everything, blended.
fn draw_overlay(device: &ash::Device, cmd: vk::CommandBuffer, f: &FrameInputs<'_>) {
    let l = f.layout;
    if l.overlay_vertex_count == 0 {
        return;
    }
    let p = f.pipelines;
    let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
    let size = [f.target.extent.width, f.target.extent.height];
    let push = scene::overlay_push_constants(size);
    // SAFETY: as in `draw_triangles`; the overlay section of the mesh buffer holds
    // `overlay_vertex_count` packed vertices at `overlay_vertices`.
    unsafe {
        device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, p.overlay);
        device.cmd_push_constants(cmd, p.layout, stages, 0, &push);
        device.cmd_bind_vertex_buffers(cmd, 0, &[f.mesh_buffer], &[l.overlay_vertices]);
        device.cmd_draw(cmd, l.overlay_vertex_count, 1, 0, 0);
    }
}

/// After rendering: the colour image (and with [`Readback::All`] the
/// auxiliary images) into `TRANSFER_SRC_OPTIMAL`.
fn to_transfer_source(device: &ash::Device, cmd: vk::CommandBuffer, f: &FrameInputs<'_>) {
    let t = f.target;
    let color_aspect = vk::ImageAspectFlags::COLOR;
    let from_attachment = (
        vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
        vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
        vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
    );
    let to_transfer = (
        vk::PipelineStageFlags2::ALL_TRANSFER,
        vk::AccessFlags2::TRANSFER_READ,
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
    );
    let mut barriers = vec![image_barrier(
        t.color.raw,
        color_aspect,
        from_attachment,
        to_transfer,
    )];
    if f.readback == Readback::All {
        barriers.push(image_barrier(
            t.normal.raw,
            color_aspect,
            from_attachment,
            to_transfer,
        ));
        barriers.push(image_barrier(
            t.linear_depth.raw,
            color_aspect,
            from_attachment,
            to_transfer,
        ));
    }
    // SAFETY: `cmd` is recording outside a render pass; the images belong to
    // `device` and were left in COLOR_ATTACHMENT_OPTIMAL by the rendering.
    unsafe {
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&barriers),
        );
    }
}

/// Copies the requested images into the readback buffer and makes the
/// copies visible to the host.
fn copy_to_readback(device: &ash::Device, cmd: vk::CommandBuffer, f: &FrameInputs<'_>) {
    let t = f.target;
    let pixels = u64::from(t.extent.width) * u64::from(t.extent.height);
    let copy = |offset: u64| vk::BufferImageCopy {
        buffer_offset: offset,
        buffer_row_length: 0,
        buffer_image_height: 0,
        image_subresource: vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        },
        image_offset: vk::Offset3D::default(),
        image_extent: vk::Extent3D {
            width: t.extent.width,
            height: t.extent.height,
            depth: 1,
        },
    };
    let src = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
    let to_host = [vk::BufferMemoryBarrier2::default()
        .src_stage_mask(vk::PipelineStageFlags2::ALL_TRANSFER)
        .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
        .dst_stage_mask(vk::PipelineStageFlags2::HOST)
        .dst_access_mask(vk::AccessFlags2::HOST_READ)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .buffer(t.readback.raw)
        .offset(0)
        .size(vk::WHOLE_SIZE)];
    // SAFETY: `cmd` is recording outside a render pass; the copied images are
    // in TRANSFER_SRC_OPTIMAL (`to_transfer_source`); the readback buffer
    // belongs to `device` and holds all three sections for this extent
    // (`Target::new` sized it), so every copy stays in bounds.
    unsafe {
        device.cmd_copy_image_to_buffer(cmd, t.color.raw, src, t.readback.raw, &[copy(0)]);
        if f.readback == Readback::All {
            let normal_at = pixels * COLOR_BYTES;
            let depth_at = normal_at + pixels * NORMAL_BYTES;
            device.cmd_copy_image_to_buffer(
                cmd,
                t.normal.raw,
                src,
                t.readback.raw,
                &[copy(normal_at)],
            );
            device.cmd_copy_image_to_buffer(
                cmd,
                t.linear_depth.raw,
                src,
                t.readback.raw,
                &[copy(depth_at)],
            );
        }
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().buffer_memory_barriers(&to_host),
        );
    }
}

/// A host-visible vertex + index buffer that grows as needed.
#[derive(Default)]
pub(crate) struct MeshBuffer {
    buffer: Option<Buffer>,
}

impl MeshBuffer {
    /// Copies `bytes` in (growing the buffer if needed) and returns the buffer.
    /// The caller guarantees the GPU is done with the previous contents.
    pub fn upload(&mut self, ctx: &mut Context, bytes: &[u8]) -> Result<vk::Buffer> {
        let needed = (bytes.len() as u64).max(256);
        if self.buffer.as_ref().is_none_or(|b| b.size < needed) {
            if let Some(mut old) = self.buffer.take() {
                old.destroy(ctx);
            }
            self.buffer = Some(Buffer::new(
                ctx,
                needed.next_power_of_two(),
                vk::BufferUsageFlags::VERTEX_BUFFER | vk::BufferUsageFlags::INDEX_BUFFER,
                MemoryLocation::CpuToGpu,
                "mesh",
            )?);
        }
        let buffer = self.buffer.as_mut().ok_or(VkError::Vulkan {
            call: "create mesh buffer",
            result: vk::Result::ERROR_UNKNOWN,
        })?;
        let mapped = buffer.mapped_mut()?;
        if let Some(dst) = mapped.get_mut(..bytes.len()) {
            dst.copy_from_slice(bytes);
        }
        Ok(buffer.raw)
    }

    /// Copies `bytes` to `offset`, keeping what lies before it, if the buffer
    /// already holds at least `total` bytes; `None` (nothing written) otherwise.
    pub fn upload_at(
        &mut self,
        bytes: &[u8],
        offset: u64,
        total: u64,
    ) -> Result<Option<vk::Buffer>> {
        let Some(buffer) = self.buffer.as_mut().filter(|b| b.size >= total) else {
            return Ok(None);
        };
        let start = usize::try_from(offset).unwrap_or(usize::MAX);
        let mapped = buffer.mapped_mut()?;
        match start
            .checked_add(bytes.len())
            .and_then(|end| mapped.get_mut(start..end))
        {
            Some(dst) => {
                dst.copy_from_slice(bytes);
                Ok(Some(buffer.raw))
            }
            None => Ok(None),
        }
    }

    pub fn destroy(&mut self, ctx: &mut Context) {
        if let Some(mut b) = self.buffer.take() {
            b.destroy(ctx);
        }
    }
}
