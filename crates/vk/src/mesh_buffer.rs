//! The mesh buffer each renderer (and each viewer frame in flight) draws from: vertices and
//! indices in one host-visible buffer that grows as needed, rewritten whole or in place.

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::context::Context;
use crate::error::{Result, VkError};
use crate::memory::Buffer;
use crate::scene::{self, RenderMesh};

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

    /// Writes the shared vertices `ranges` of `mesh` in place (as [`crate::scene::pack`] lays
    /// them out), if the buffer already holds at least `total` bytes; `false` when it does not
    /// (then some may be written, none is kept: the caller writes everything).
    pub fn upload_vertices(
        &mut self,
        mesh: &RenderMesh<'_>,
        ranges: &[std::ops::Range<u32>],
        total: u64,
    ) -> Result<bool> {
        let mut vertices = Vec::new();
        for r in ranges {
            let range = r.start as usize..(r.end as usize).min(mesh.positions.len());
            if range.is_empty() {
                continue;
            }
            scene::pack_vertices(mesh, range.clone(), &mut vertices);
            let at = range.start as u64 * scene::VERTEX_STRIDE;
            if self.upload_at(&vertices, at, total)?.is_none() {
                return Ok(false);
            }
        }
        Ok(true)
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
