//! The viewer's swapchain: (re)creation, destruction, and the blit of a
//! rendered frame into a swapchain image.

use ash::vk;
use winit::dpi::PhysicalSize;

use super::gpu::{Gpu, unless_lost};
use crate::error::{Result, VkError, VkResultExt};

pub(super) struct Swapchain {
    pub(super) raw: vk::SwapchainKHR,
    pub(super) images: Vec<vk::Image>,
    pub(super) extent: vk::Extent2D,
    /// One per swapchain image: signalled by rendering, waited by presentation.
    pub(super) rendered: Vec<vk::Semaphore>,
}

impl Gpu {
    /// (Re)creates the swapchain when needed; returns its extent. `None`: no
    /// frame can be drawn now, because the surface is 0×0 (a minimised window;
    /// the swapchain stays marked for re-creation) or was lost
    /// ([`Gpu::surface_lost`] set).
    pub(super) fn ensure_swapchain(
        &mut self,
        size: PhysicalSize<u32>,
    ) -> Result<Option<vk::Extent2D>> {
        if !self.swapchain_dirty
            && let Some(s) = &self.swapchain
        {
            return Ok(Some(s.extent));
        }
        let (surface_loader, surface) = self.surface()?;
        // SAFETY: the physical device and the surface were both created from
        // this context's instance, which outlives the call.
        let caps = unsafe {
            surface_loader.get_physical_device_surface_capabilities(self.ctx.physical, surface)
        };
        // SAFETY: as above.
        let modes = unsafe {
            surface_loader.get_physical_device_surface_present_modes(self.ctx.physical, surface)
        };
        let caps = unless_lost(caps, "vkGetPhysicalDeviceSurfaceCapabilitiesKHR")?;
        let modes = unless_lost(modes, "vkGetPhysicalDeviceSurfacePresentModesKHR")?;
        let (Some(mut caps), Some(modes)) = (caps, modes) else {
            self.surface_lost = true;
            return Ok(None);
        };
        if self.injected.zero_surface() {
            caps.current_extent = vk::Extent2D::default();
        }
        let extent = swap_extent(&caps, size);
        if extent.width == 0 || extent.height == 0 {
            // A swapchain cannot be 0×0: keep the old one until the window has a size again.
            return Ok(None);
        }
        let mode = present_mode(&modes);
        let mut count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            count = count.min(caps.max_image_count);
        }
        let old = self.swapchain.take();
        // SAFETY: the device is live. Waiting for it to be idle ensures no
        // submission still uses the old swapchain's per-image semaphores, which
        // are destroyed below.
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
        // SAFETY: `surface` belongs to this context and the queue family was
        // chosen to present to it; `old_swapchain` is the previous swapchain,
        // still alive, which this call retires; `info` lives through the call.
        let created = unsafe { self.loader.create_swapchain(&info, None) };
        if let Some(old) = old {
            self.destroy_swapchain(old);
        }
        let Some(raw) = unless_lost(created, "vkCreateSwapchainKHR")? else {
            self.surface_lost = true;
            return Ok(None);
        };
        let swapchain = self.swapchain_parts(raw, extent)?;
        self.swapchain = Some(swapchain);
        self.swapchain_dirty = false;
        self.extents.push([extent.width, extent.height]);
        Ok(Some(extent))
    }

    /// Wraps a new swapchain with its images and one semaphore per image;
    /// destroys it again if that fails.
    fn swapchain_parts(&self, raw: vk::SwapchainKHR, extent: vk::Extent2D) -> Result<Swapchain> {
        let mut swapchain = Swapchain {
            raw,
            images: Vec::new(),
            extent,
            rendered: Vec::new(),
        };
        // SAFETY: `raw` was just created by this loader and is alive.
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
            // SAFETY: the device is live and the create info lives through the call.
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
        Ok(swapchain)
    }

    pub(super) fn destroy_swapchain(&self, swapchain: Swapchain) {
        // SAFETY: every caller has waited for the device to be idle (or the
        // swapchain was never used), so no submission or presentation still uses
        // these semaphores or the swapchain; they were created by this device and
        // loader, and `swapchain` is consumed, so each is destroyed once.
        unsafe {
            for s in swapchain.rendered {
                self.ctx.device.destroy_semaphore(s, None);
            }
            self.loader.destroy_swapchain(swapchain.raw, None);
        }
    }
}

/// The surface's fixed extent, else the window size clamped to what it allows.
fn swap_extent(caps: &vk::SurfaceCapabilitiesKHR, size: PhysicalSize<u32>) -> vk::Extent2D {
    if caps.current_extent.width != u32::MAX {
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
    }
}

/// Unthrottled presentation keeps measured frame times meaningful.
fn present_mode(modes: &[vk::PresentModeKHR]) -> vk::PresentModeKHR {
    [vk::PresentModeKHR::MAILBOX, vk::PresentModeKHR::IMMEDIATE]
        .into_iter()
        .find(|m| modes.contains(m))
        .unwrap_or(vk::PresentModeKHR::FIFO)
}

/// Records the copy of the rendered colour image (`TRANSFER_SRC_OPTIMAL`, as
/// [`crate::frame::record`] leaves it) into `swap_image`, which ends in
/// `PRESENT_SRC_KHR`.
pub(super) fn record_blit(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    color: vk::Image,
    swap_image: vk::Image,
    extent: vk::Extent2D,
) {
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
        .src_image(color)
        .src_image_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL)
        .dst_image(swap_image)
        .dst_image_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
        .regions(&regions)
        .filter(vk::Filter::NEAREST);
    // SAFETY: `cmd` is in the recording state; `color` and `swap_image` belong
    // to this device (the latter acquired for this frame), and the barriers put
    // each in the layout the blit and the presentation expect; the structures
    // live through the calls.
    unsafe {
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&to_dst),
        );
        device.cmd_blit_image2(cmd, &blit);
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&to_present),
        );
    }
}
