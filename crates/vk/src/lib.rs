//! `subdiv-vk`: the Vulkan renderer of subdiv.
//!
//! Its job: draw plain triangle meshes ([`RenderMesh`]) with several shading
//! modes, wireframe and extra lines, headless or in a window, and read the
//! pixels back. Raw [`ash`] on Vulkan 1.3 (dynamic rendering, synchronization2),
//! memory from `gpu-allocator`, GLSL shaders compiled to SPIR-V by naga at
//! build time.
//!
//! - [`Renderer`]: headless offscreen rendering with readback to PNG ([`write_png`])
//!   and depth / normals / scalar to EXR ([`write_exr`]);
//! - [`viewer`]: an interactive window (winit + swapchain) fed by a [`viewer::FrameSource`];
//! - [`golden`]: golden-image comparison for regression tests;
//! - [`overlay`]: screen-space rectangles and text from an embedded 5×7 bitmap font (the
//!   viewer's HUD, the colour legends of renders and the viewer).
//!
//! # Invariants
//!
//! - **Knows no other workspace crate.** Input is plain buffers: positions,
//!   normals, `u32` indices, optional edges, scalars and line segments in a
//!   [`RenderMesh`], plus a [`View`] and [`RenderOptions`]. Whoever produces
//!   geometry (the tessellator, a test) converts to these; nothing here
//!   depends on subdivision types.
//! - **The loader is opened at run time.** The Vulkan library is loaded with
//!   `dlopen` when a [`Renderer`] or viewer is created, never linked, so the
//!   crate builds and its users run without a driver: every entry point then
//!   returns [`VkError::LoaderMissing`] or [`VkError::NoDriver`] naming the
//!   Debian package to install. Set `SUBDIV_VK_VALIDATION=1` to enable the
//!   Khronos validation layer.
//! - **Nothing global.** Each [`Renderer`] and viewer owns its own instance,
//!   device and allocator, so any number of them can run in parallel threads. The one
//!   process-wide setting, [`keep_freed_heap`] (the C heap a CPU driver draws from), is
//!   the program's to call.
//! - **One frame recipe.** The headless renderer and the viewer record frames
//!   with the same code into the same offscreen targets; a viewer screenshot
//!   equals a headless render of the same camera, size and options (legend
//!   included) when the viewer's HUD is off. Overlays (HUD, legend) are drawn
//!   last, into the colour target only: depth, normals and scalars read back
//!   for EXR never contain them.
//! - **Never prints.** Messages go through the `log` crate (validation messages
//!   as warnings); the program decides what reaches the terminal.
//! - **Owned teardown.** Every Vulkan object is destroyed by its owner once
//!   the GPU is done with it (a fence waited on, or the device idle), and
//!   before the device; each `unsafe` block states why it is sound in a
//!   `// SAFETY:` comment.
//!
//! See [`Renderer`] for an example.

mod context;
mod error;
mod frame;
mod heap;
mod image_io;
mod memory;
mod mesh_buffer;
mod offscreen;
pub mod overlay;
mod pipeline;
mod samples;
mod scene;
mod shaders;
mod target;

pub mod golden;
pub mod viewer;

pub use context::{
    ContextOptions, DEVICE_ENV, REQUIRE_VALIDATION_ENV, VALIDATION_ENV, Validation, ValidationLog,
};
pub use error::{Result, VkError};
pub use heap::keep_freed_heap;
pub use image_io::{EXR_CHANNELS, ExrChannel, read_exr, read_png, write_exr, write_png};
pub use offscreen::{AuxImage, Renderer};
pub use samples::{DEFAULT_SAMPLES, SAMPLE_COUNTS};
pub use scene::{OrbitCamera, RenderMesh, RenderOptions, Shading, View};

pub use glam;
pub use image;
