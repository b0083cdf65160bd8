//! `subdiv-vk`: the Vulkan renderer of subdiv.
//!
//! Raw [`ash`] on Vulkan 1.3 (dynamic rendering, synchronization2), memory
//! from `gpu-allocator`, GLSL shaders compiled to SPIR-V by naga at build time.
//! It draws plain triangle meshes ([`RenderMesh`]) with several shading modes,
//! wireframe and extra lines:
//!
//! - [`Renderer`]: headless offscreen rendering with readback to PNG ([`write_png`])
//!   and depth / normals / scalar to EXR ([`write_exr`]);
//! - [`viewer`]: an interactive window (winit + swapchain) fed by a [`viewer::FrameSource`];
//! - [`golden`]: golden-image comparison for regression tests.
//!
//! The Vulkan library is loaded at run time; without a driver every entry point
//! returns [`VkError::LoaderMissing`] or [`VkError::NoDriver`], naming the Debian
//! package to install. Set `SUBDIV_VK_VALIDATION=1` to enable the Khronos
//! validation layer.
//!
//! See [`Renderer`] for an example.

#![warn(missing_docs)]

mod context;
mod error;
mod frame;
mod image_io;
mod memory;
mod offscreen;
mod pipeline;
mod scene;
mod shaders;

pub mod golden;
pub mod viewer;

pub use context::{ContextOptions, DEVICE_ENV, VALIDATION_ENV, Validation, ValidationLog};
pub use error::{Result, VkError};
pub use image_io::{EXR_CHANNELS, ExrChannel, read_exr, read_png, write_exr, write_png};
pub use offscreen::{AuxImage, Renderer};
pub use scene::{OrbitCamera, OwnedMesh, RenderMesh, RenderOptions, Shading, View};

pub use glam;
pub use image;
