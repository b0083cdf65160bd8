//! Render targets: the attachments of one size and sample count, and the host-visible buffer
//! their pixels are read back through.

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::context::Context;
use crate::error::{Result, VkError};
use crate::memory::{Buffer, Image};
use crate::pipeline::{COLOR_FORMAT, LINEAR_DEPTH_FORMAT, NORMAL_FORMAT};
use crate::samples;

/// Colour, auxiliary and depth attachments of one size (single-sample: what is read back),
/// the multisampled colour and depth attachments when drawing with several samples per pixel,
/// and a host-visible buffer that receives the read-back contents.
pub(crate) struct Target {
    pub extent: vk::Extent2D,
    /// Samples per pixel of the colour pass (1: no multisampled attachments).
    pub samples: u32,
    /// The colour image (resolved from [`Target::multisampled`] when there is one).
    pub color: Image,
    pub normal: Image,
    pub linear_depth: Image,
    /// Depth of the single-sample pass.
    pub depth: Image,
    /// Colour and depth with [`Target::samples`] samples per pixel.
    pub multisampled: Option<(Image, Image)>,
    pub readback: Buffer,
}

/// Byte sizes per pixel of the readback sections: colour, normal+scalar, linear depth.
pub(crate) const COLOR_BYTES: u64 = 4;
pub(crate) const NORMAL_BYTES: u64 = 16;
pub(crate) const LINEAR_DEPTH_BYTES: u64 = 4;

/// What to copy into the readback buffer at the end of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Readback {
    None,
    Color,
    All,
}

/// One attachment to make: format and samples, usage, aspect, name.
type Spec = (
    (vk::Format, vk::SampleCountFlags),
    vk::ImageUsageFlags,
    vk::ImageAspectFlags,
    &'static str,
);

/// Makes every image of `specs`, or none (those made are destroyed on a failure).
fn make_images(ctx: &mut Context, extent: vk::Extent2D, specs: &[Spec]) -> Result<Vec<Image>> {
    let mut made: Vec<Image> = Vec::new();
    for &(format, usage, aspect, name) in specs {
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
    Ok(made)
}

impl Target {
    /// Targets of `extent` drawn with `samples` per pixel (a count the device supports:
    /// [`samples::choose`]).
    pub fn new(ctx: &mut Context, extent: vk::Extent2D, samples: u32) -> Result<Self> {
        let max = ctx.limits.max_image_dimension2_d;
        if extent.width == 0 || extent.height == 0 || extent.width > max || extent.height > max {
            return Err(VkError::InvalidSize {
                width: extent.width,
                height: extent.height,
                max,
            });
        }
        let color_usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
        let color = vk::ImageAspectFlags::COLOR;
        let one = vk::SampleCountFlags::TYPE_1;
        let depth_usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
        let depth = vk::ImageAspectFlags::DEPTH;
        let mut specs: Vec<Spec> = vec![
            ((COLOR_FORMAT, one), color_usage, color, "colour target"),
            ((NORMAL_FORMAT, one), color_usage, color, "normal target"),
            (
                (LINEAR_DEPTH_FORMAT, one),
                color_usage,
                color,
                "linear depth target",
            ),
            ((ctx.depth_format, one), depth_usage, depth, "depth target"),
        ];
        if samples > 1 {
            let n = samples::flag(samples);
            let transient = vk::ImageUsageFlags::TRANSIENT_ATTACHMENT;
            specs.push((
                (COLOR_FORMAT, n),
                vk::ImageUsageFlags::COLOR_ATTACHMENT | transient,
                color,
                "multisampled colour target",
            ));
            specs.push((
                (ctx.depth_format, n),
                depth_usage | transient,
                depth,
                "multisampled depth target",
            ));
        }
        let made = make_images(ctx, extent, &specs)?;
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
        let (Some(color), Some(normal), Some(linear_depth), Some(depth)) =
            (it.next(), it.next(), it.next(), it.next())
        else {
            return Err(VkError::Vulkan {
                call: "create targets",
                result: vk::Result::ERROR_UNKNOWN,
            });
        };
        let multisampled = it.next().zip(it.next());
        Ok(Target {
            extent,
            samples: if multisampled.is_some() { samples } else { 1 },
            color,
            normal,
            linear_depth,
            depth,
            multisampled,
            readback,
        })
    }

    pub fn destroy(&mut self, ctx: &mut Context) {
        self.color.destroy(ctx);
        self.normal.destroy(ctx);
        self.linear_depth.destroy(ctx);
        self.depth.destroy(ctx);
        if let Some((mut color, mut depth)) = self.multisampled.take() {
            color.destroy(ctx);
            depth.destroy(ctx);
        }
        self.readback.destroy(ctx);
    }

    /// Whether this target has `extent` and `samples` per pixel.
    pub fn fits(&self, extent: vk::Extent2D, samples: u32) -> bool {
        self.extent == extent && self.samples == samples
    }

    pub fn pixels(&self) -> u64 {
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
