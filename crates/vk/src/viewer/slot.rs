//! One frame in flight of the viewer: its command buffer, fence, acquire semaphore, offscreen
//! target and mesh buffer, and their creation and reset.

use ash::vk;

use crate::error::{Result, VkError, VkResultExt};
use crate::frame::Target;
use crate::mesh_buffer::MeshBuffer;

/// A frame in flight.
pub(super) struct Slot {
    pub(super) cmd: vk::CommandBuffer,
    pub(super) fence: vk::Fence,
    pub(super) acquired: vk::Semaphore,
    pub(super) target: Option<Target>,
    /// Vertex + index buffer of this slot: indices rebuilt per frame,
    /// double-buffered across slots so the CPU never overwrites what the GPU
    /// still reads.
    pub(super) mesh: MeshBuffer,
    /// [`super::SourceFrame::vertex_version`] and count of the vertices in `mesh`.
    pub(super) vertices: Option<(u64, usize)>,
}

/// Resets the slot's fence and command buffer and begins recording.
pub(super) fn begin_commands(
    device: &ash::Device,
    fence: vk::Fence,
    cmd: vk::CommandBuffer,
) -> Result<()> {
    // SAFETY: the slot's previous submission completed (`draw` waited on its
    // fence), so the fence may be reset and the GPU no longer reads its command
    // buffer, target or mesh buffer; `cmd` comes from a pool created with
    // RESET_COMMAND_BUFFER.
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
    Ok(())
}

/// A command buffer, a signalled fence and a semaphore for one frame in flight.
pub(super) fn create_slot(device: &ash::Device, pool: vk::CommandPool) -> Result<Slot> {
    let alloc = vk::CommandBufferAllocateInfo::default()
        .command_pool(pool)
        .level(vk::CommandBufferLevel::PRIMARY)
        .command_buffer_count(1);
    // SAFETY: `pool` was created from `device` and is used by this thread only;
    // the create infos live through the calls. If the semaphore fails, the fence
    // made just before is destroyed here (never used); the command buffer is
    // freed with the pool by `Drop for Gpu`.
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
        let acquired = match device.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) {
            Ok(s) => s,
            Err(result) => {
                device.destroy_fence(fence, None);
                return Err(VkError::Vulkan {
                    call: "vkCreateSemaphore",
                    result,
                });
            }
        };
        Ok(Slot {
            cmd: cmd.first().copied().unwrap_or_default(),
            fence,
            acquired,
            target: None,
            mesh: MeshBuffer::default(),
            vertices: None,
        })
    }
}
