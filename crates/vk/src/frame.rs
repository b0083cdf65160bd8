//! The command recording of one frame, shared by the headless renderer and the viewer (so
//! both produce identical pixels), and the mesh upload buffer.

use ash::vk;

use crate::error::Result;
use crate::memory::subresource_range;
use crate::pipeline::{PipelineSet, Pipelines};
use crate::scene::{self, Layout, RenderOptions, View};
pub(crate) use crate::target::{COLOR_BYTES, NORMAL_BYTES, Readback, Target};

fn image_barrier(
    image: vk::Image,
    aspect: vk::ImageAspectFlags,
    (src_stage, src_access, old): Use,
    (dst_stage, dst_access, new): Use,
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

/// Stage, access and layout of an image on one side of a barrier.
type Use = (vk::PipelineStageFlags2, vk::AccessFlags2, vk::ImageLayout);

const UNUSED: Use = (
    vk::PipelineStageFlags2::ALL_COMMANDS,
    vk::AccessFlags2::NONE,
    vk::ImageLayout::UNDEFINED,
);
const COLOR_WRITE: Use = (
    vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
    vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
    vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
);
const DEPTH_TESTS: vk::PipelineStageFlags2 = vk::PipelineStageFlags2::from_raw(
    vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS.as_raw()
        | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS.as_raw(),
);
const DEPTH_WRITE: Use = (
    DEPTH_TESTS,
    vk::AccessFlags2::from_raw(
        vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ.as_raw()
            | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw(),
    ),
    vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
);

/// Records one frame. Afterwards the colour image is in `TRANSFER_SRC_OPTIMAL`
/// layout and the requested readback copies are recorded and made host-visible.
///
/// With one sample per pixel, one pass draws colour and the auxiliary targets. With several,
/// a multisampled pass draws colour (resolved into the target's colour image), and only when
/// the auxiliary images are read back a second, single-sample pass draws them: depth, normals
/// and scalars stay point-sampled at pixel centres whatever the sample count.
///
/// `cmd` must be in the recording state; every handle in `f` must belong to
/// `device` and stay alive until the submission completes (the callers wait
/// on a fence before reusing or destroying any of them). Fails only when the
/// multisampled pipelines were not prepared.
pub(crate) fn record(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    f: &FrameInputs<'_>,
) -> Result<()> {
    let t = f.target;
    let single = &f.pipelines.single;
    match &t.multisampled {
        None => {
            let aux = [
                (t.normal.view, Load::Clear),
                (t.linear_depth.view, Load::Clear),
            ];
            barriers(device, cmd, &single_pass_barriers(t, UNUSED));
            begin_rendering(
                device,
                cmd,
                f,
                (t.color.view, None, Load::Clear),
                &aux,
                t.depth.view,
            );
            draw_triangles(device, cmd, f, triangle_pipeline(single, f.options));
            draw_lines(device, cmd, f, single);
            draw_overlay(device, cmd, f, single);
            // SAFETY: `cmd` is recording inside the rendering begun above.
            unsafe { device.cmd_end_rendering(cmd) };
        }
        Some((ms_color, ms_depth)) => {
            let set = f.pipelines.multisampled(t.samples)?;
            let color = vk::ImageAspectFlags::COLOR;
            barriers(
                device,
                cmd,
                &[
                    image_barrier(ms_color.raw, color, UNUSED, COLOR_WRITE),
                    image_barrier(t.color.raw, color, UNUSED, COLOR_WRITE),
                    image_barrier(
                        ms_depth.raw,
                        vk::ImageAspectFlags::DEPTH,
                        UNUSED,
                        DEPTH_WRITE,
                    ),
                ],
            );
            let resolve = Some(t.color.view);
            begin_rendering(
                device,
                cmd,
                f,
                (ms_color.view, resolve, Load::Clear),
                &[],
                ms_depth.view,
            );
            draw_triangles(device, cmd, f, triangle_pipeline(set, f.options));
            draw_lines(device, cmd, f, set);
            draw_overlay(device, cmd, f, set);
            // SAFETY: `cmd` is recording inside the rendering begun above.
            unsafe { device.cmd_end_rendering(cmd) };
            if f.readback == Readback::All {
                // The resolved colour is kept (loaded, never written: the pipeline's colour
                // mask is empty); the auxiliary targets get the triangles at one sample.
                let resolved = (
                    vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                    vk::AccessFlags2::COLOR_ATTACHMENT_READ
                        | vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
                    vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                );
                barriers(
                    device,
                    cmd,
                    &single_pass_barriers(t, COLOR_WRITE).map(|b| {
                        if b.image == t.color.raw {
                            b.dst_access_mask(resolved.1)
                        } else {
                            b
                        }
                    }),
                );
                let aux = [
                    (t.normal.view, Load::Clear),
                    (t.linear_depth.view, Load::Clear),
                ];
                begin_rendering(
                    device,
                    cmd,
                    f,
                    (t.color.view, None, Load::Keep),
                    &aux,
                    t.depth.view,
                );
                draw_triangles(device, cmd, f, single.fill_depth_only);
                // SAFETY: `cmd` is recording inside the rendering begun above.
                unsafe { device.cmd_end_rendering(cmd) };
            }
        }
    }
    to_transfer_source(device, cmd, f);
    if f.readback != Readback::None {
        copy_to_readback(device, cmd, f);
    }
    Ok(())
}

/// The barriers into the single-sample pass: colour from `color_before`, the auxiliary and
/// depth targets from unused.
fn single_pass_barriers(t: &Target, color_before: Use) -> [vk::ImageMemoryBarrier2<'static>; 4] {
    let color = vk::ImageAspectFlags::COLOR;
    [
        image_barrier(t.color.raw, color, color_before, COLOR_WRITE),
        image_barrier(t.normal.raw, color, UNUSED, COLOR_WRITE),
        image_barrier(t.linear_depth.raw, color, UNUSED, COLOR_WRITE),
        image_barrier(
            t.depth.raw,
            vk::ImageAspectFlags::DEPTH,
            UNUSED,
            DEPTH_WRITE,
        ),
    ]
}

fn barriers(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    barriers: &[vk::ImageMemoryBarrier2<'_>],
) {
    // SAFETY: `cmd` is recording outside a rendering (see `record`); the images belong to
    // `device` and outlive the submission, and each barrier's old layout is the one the
    // image is in at this point of the frame (or UNDEFINED, discarding its contents).
    unsafe {
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(barriers),
        );
    }
}

/// What a colour attachment starts a pass with.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Load {
    /// Cleared (to the background, or zero for the auxiliary targets).
    Clear,
    /// What an earlier pass left.
    Keep,
}

/// Begins rendering to the colour attachment `(view, resolve target, load)`, the auxiliary
/// attachments `aux` and the depth attachment `depth` (cleared), with viewport and scissor
/// covering the target. The attachments are in their attachment layouts.
fn begin_rendering(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    f: &FrameInputs<'_>,
    (color, resolve, load): (vk::ImageView, Option<vk::ImageView>, Load),
    aux: &[(vk::ImageView, Load)],
    depth: vk::ImageView,
) {
    let t = f.target;
    let attachment = |view, load: Load, clear: [f32; 4]| {
        let info = vk::RenderingAttachmentInfo::default()
            .image_view(view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .store_op(vk::AttachmentStoreOp::STORE);
        match load {
            Load::Clear => info
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .clear_value(vk::ClearValue {
                    color: vk::ClearColorValue { float32: clear },
                }),
            Load::Keep => info.load_op(vk::AttachmentLoadOp::LOAD),
        }
    };
    let mut first = attachment(color, load, f.options.background);
    if let Some(resolve) = resolve {
        // The multisampled image itself is not needed after the resolve.
        first = first
            .store_op(vk::AttachmentStoreOp::DONT_CARE)
            .resolve_mode(vk::ResolveModeFlags::AVERAGE)
            .resolve_image_view(resolve)
            .resolve_image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL);
    }
    let colors: Vec<_> = std::iter::once(first)
        .chain(
            aux.iter()
                .map(|&(view, load)| attachment(view, load, [0.0; 4])),
        )
        .collect();
    let depth = vk::RenderingAttachmentInfo::default()
        .image_view(depth)
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
    // SAFETY: `cmd` is recording outside a rendering (see `record`); the views belong to
    // `device`, outlive the submission and are in the layouts the attachment infos name.
    unsafe {
        device.cmd_begin_rendering(cmd, &rendering);
        device.cmd_set_viewport(cmd, 0, &[viewport]);
        device.cmd_set_scissor(cmd, 0, &[area]);
    }
}

/// The triangle pipeline of `set` for `options`: shaded, or without colour for
/// [`scene::Shading::Wire`] (depth and auxiliary targets only).
fn triangle_pipeline(set: &PipelineSet, options: &RenderOptions) -> vk::Pipeline {
    if options.shading == scene::Shading::Wire {
        set.fill_depth_only
    } else {
        set.fill
    }
}

/// Draws the triangles with `pipeline`.
fn draw_triangles(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    f: &FrameInputs<'_>,
    pipeline: vk::Pipeline,
) {
    let l = f.layout;
    let p = f.pipelines;
    let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
    if l.tri_count == 0 {
        return;
    }
    let push = scene::mesh_push_constants(f.view, f.options, l);
    // SAFETY: `cmd` is recording inside the render pass; pipeline, layout and
    // mesh buffer belong to `device` and outlive the submission; the offsets
    // and counts come from the layout the buffer was packed with.
    unsafe {
        device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
        device.cmd_push_constants(cmd, p.layout, stages, 0, &push);
        device.cmd_bind_vertex_buffers(
            cmd,
            0,
            &[f.mesh_buffer, f.mesh_buffer],
            &[l.tri_vertices, l.tri_colors],
        );
        if l.tri_indexed {
            device.cmd_bind_index_buffer(cmd, f.mesh_buffer, l.tri_indices, vk::IndexType::UINT32);
            device.cmd_draw_indexed(cmd, l.tri_count * 3, 1, 0, 0, 0);
        } else {
            device.cmd_draw(cmd, l.tri_count * 3, 1, 0, 0);
        }
    }
}

/// Draws the wireframe edges and the extra lines with the line pipeline of `set`.
fn draw_lines(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    f: &FrameInputs<'_>,
    set: &PipelineSet,
) {
    let l = f.layout;
    let p = f.pipelines;
    let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
    // SAFETY: as in `draw_triangles`; depth test and line width are dynamic
    // state of the line pipeline (line width only when `dynamic_line_width`).
    unsafe {
        if l.edge_count > 0 || l.line_count > 0 {
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, set.line);
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

/// Draws the overlay rectangles (HUD, legend) over everything, blended, with `set`.
fn draw_overlay(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    f: &FrameInputs<'_>,
    set: &PipelineSet,
) {
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
        device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, set.overlay);
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
    let to_transfer = (
        vk::PipelineStageFlags2::ALL_TRANSFER,
        vk::AccessFlags2::TRANSFER_READ,
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
    );
    let mut list = vec![image_barrier(
        t.color.raw,
        color_aspect,
        COLOR_WRITE,
        to_transfer,
    )];
    if f.readback == Readback::All {
        list.push(image_barrier(
            t.normal.raw,
            color_aspect,
            COLOR_WRITE,
            to_transfer,
        ));
        list.push(image_barrier(
            t.linear_depth.raw,
            color_aspect,
            COLOR_WRITE,
            to_transfer,
        ));
    }
    barriers(device, cmd, &list);
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
