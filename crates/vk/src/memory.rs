//! Buffers and images backed by `gpu-allocator` memory.
//!
//! These types have no `Drop`: their owner calls `destroy` with the context
//! before the context itself goes away.

use ash::vk;
use gpu_allocator::MemoryLocation;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};

use crate::context::Context;
use crate::error::{Result, VkError, VkResultExt};

/// A buffer with its memory.
pub(crate) struct Buffer {
    pub raw: vk::Buffer,
    pub size: u64,
    allocation: Option<Allocation>,
}

impl Buffer {
    pub fn new(
        ctx: &mut Context,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
        name: &str,
    ) -> Result<Self> {
        let info = vk::BufferCreateInfo::default()
            .size(size.max(4))
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: `ctx.device` is live; `info` has a non-zero size and lives
        // through the call.
        let raw = unsafe { ctx.device.create_buffer(&info, None) }.call("vkCreateBuffer")?;
        // SAFETY: `raw` was just created by this device.
        let requirements = unsafe { ctx.device.get_buffer_memory_requirements(raw) };
        let allocation = match ctx.allocator().allocate(&AllocationCreateDesc {
            name,
            requirements,
            location,
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        }) {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: `raw` was created by this device just above and was never
                // bound or used by the GPU, so it can be destroyed at once.
                unsafe { ctx.device.destroy_buffer(raw, None) };
                return Err(e.into());
            }
        };
        // SAFETY: `allocation` was made from this device's allocator for
        // `requirements` of `raw`, which is not yet bound to any memory; the
        // memory handle (unsafe to obtain because it must not be freed by us)
        // is only used for this bind, and the allocator keeps owning it.
        let bound = unsafe {
            ctx.device
                .bind_buffer_memory(raw, allocation.memory(), allocation.offset())
        };
        let mut buffer = Buffer {
            raw,
            size: size.max(4),
            allocation: Some(allocation),
        };
        if let Err(result) = bound {
            buffer.destroy(ctx);
            return Err(VkError::Vulkan {
                call: "vkBindBufferMemory",
                result,
            });
        }
        Ok(buffer)
    }

    /// The mapped bytes of a host-visible buffer.
    pub fn mapped(&self) -> Result<&[u8]> {
        self.allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .ok_or(VkError::Vulkan {
                call: "map buffer memory",
                result: vk::Result::ERROR_MEMORY_MAP_FAILED,
            })
    }

    /// The mapped bytes of a host-visible buffer, writable.
    pub fn mapped_mut(&mut self) -> Result<&mut [u8]> {
        self.allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .ok_or(VkError::Vulkan {
                call: "map buffer memory",
                result: vk::Result::ERROR_MEMORY_MAP_FAILED,
            })
    }

    pub fn destroy(&mut self, ctx: &mut Context) {
        // SAFETY: the buffer was created by this device, and the owner calls this
        // only after the GPU finished with it (fence waited or device idle) or
        // when it was never used (`new` failing); the handle is nulled below so
        // it is destroyed once.
        unsafe { ctx.device.destroy_buffer(self.raw, None) };
        self.raw = vk::Buffer::null();
        if let Some(a) = self.allocation.take() {
            let _ = ctx.allocator().free(a);
        }
    }
}

/// A 2D image with one view, single- or multisampled.
pub(crate) struct Image {
    pub raw: vk::Image,
    pub view: vk::ImageView,
    allocation: Option<Allocation>,
}

impl Image {
    /// An image of `extent` and `format` with `samples` samples per pixel (a count the
    /// device supports for `usage`, see [`Context::sample_counts`]).
    pub fn new(
        ctx: &mut Context,
        extent: vk::Extent2D,
        (format, samples): (vk::Format, vk::SampleCountFlags),
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
        name: &str,
    ) -> Result<Self> {
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width: extent.width,
                height: extent.height,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(1)
            .samples(samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: `ctx.device` is live; `info` describes a 2D image with a
        // non-zero extent (checked by `Target::new`) and lives through the call.
        let raw = unsafe { ctx.device.create_image(&info, None) }.call("vkCreateImage")?;
        // SAFETY: `raw` was just created by this device.
        let requirements = unsafe { ctx.device.get_image_memory_requirements(raw) };
        let allocation = match ctx.allocator().allocate(&AllocationCreateDesc {
            name,
            requirements,
            location: MemoryLocation::GpuOnly,
            linear: false,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        }) {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: `raw` was created by this device just above and was never
                // bound or used by the GPU.
                unsafe { ctx.device.destroy_image(raw, None) };
                return Err(e.into());
            }
        };
        let mut image = Image {
            raw,
            view: vk::ImageView::null(),
            allocation: Some(allocation),
        };
        let memory = image.allocation.as_ref().map(|a| {
            // SAFETY: `Allocation::memory` is unsafe because the returned handle
            // must not be freed by us; it is only used to bind this image, and
            // the allocator keeps owning (and later frees) the memory.
            (unsafe { a.memory() }, a.offset())
        });
        if let Some((memory, offset)) = memory {
            // SAFETY: the memory was allocated for `requirements` of `raw`, which
            // is not yet bound to any memory.
            if let Err(result) = unsafe { ctx.device.bind_image_memory(raw, memory, offset) } {
                image.destroy(ctx);
                return Err(VkError::Vulkan {
                    call: "vkBindImageMemory",
                    result,
                });
            }
        }
        let view_info = vk::ImageViewCreateInfo::default()
            .image(raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(subresource_range(aspect));
        // SAFETY: `raw` was created by this device and is bound to memory;
        // `view_info` matches its format and lives through the call.
        match unsafe { ctx.device.create_image_view(&view_info, None) } {
            Ok(view) => image.view = view,
            Err(result) => {
                image.destroy(ctx);
                return Err(VkError::Vulkan {
                    call: "vkCreateImageView",
                    result,
                });
            }
        }
        Ok(image)
    }

    pub fn destroy(&mut self, ctx: &mut Context) {
        // SAFETY: the image and view were created by this device, and the owner
        // calls this only after the GPU finished with them (fence waited or
        // device idle) or when they were never used (`new` failing); the handles
        // are nulled below so they are destroyed once.
        unsafe {
            if self.view != vk::ImageView::null() {
                ctx.device.destroy_image_view(self.view, None);
            }
            ctx.device.destroy_image(self.raw, None);
        }
        self.view = vk::ImageView::null();
        self.raw = vk::Image::null();
        if let Some(a) = self.allocation.take() {
            let _ = ctx.allocator().free(a);
        }
    }
}

/// The whole of a single-level, single-layer image.
pub(crate) fn subresource_range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    }
}
