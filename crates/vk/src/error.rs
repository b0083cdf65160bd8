//! The crate's error type.

use std::path::PathBuf;

use ash::vk;

/// Everything that can go wrong while setting up Vulkan, rendering or writing images.
///
/// Each cause is printed once: variants that wrap another error (`Allocation`, `Io`, `Image`,
/// `Exr`) do not repeat it in their message but return it from [`std::error::Error::source`];
/// print the chain (e.g. `anyhow`'s `{:#}`) to see it.
#[derive(Debug, thiserror::Error)]
pub enum VkError {
    /// The Vulkan loader library (`libvulkan.so.1`) could not be opened.
    #[error(
        "cannot load the Vulkan loader ({detail}); install it with \
         `apt-get install libvulkan1 mesa-vulkan-drivers` (Debian package `mesa-vulkan-drivers` \
         provides the lavapipe software driver)"
    )]
    LoaderMissing {
        /// What the dynamic loader reported.
        detail: String,
    },
    /// The loader works but found no usable Vulkan driver (ICD).
    #[error(
        "no Vulkan driver found ({detail}); install the Debian package `mesa-vulkan-drivers` \
         (lavapipe, a CPU implementation) or a GPU driver, and check VK_DRIVER_FILES / VK_ICD_FILENAMES"
    )]
    NoDriver {
        /// What failed.
        detail: String,
    },
    /// Drivers exist, but none offers Vulkan 1.3 with dynamic rendering and synchronization2.
    #[error(
        "no Vulkan device supports Vulkan 1.3 with dynamic rendering and synchronization2 \
         (found: {found}); install a newer `mesa-vulkan-drivers`"
    )]
    NoSuitableDevice {
        /// The devices that were found, with their API versions.
        found: String,
    },
    /// Validation was required but the Khronos validation layer is not installed.
    #[error(
        "the Vulkan validation layer VK_LAYER_KHRONOS_validation is not installed; \
         install the Debian package `vulkan-validationlayers` or unset SUBDIV_VK_VALIDATION"
    )]
    ValidationLayerMissing,
    /// A Vulkan call failed.
    #[error("Vulkan call {call} failed: {result}")]
    Vulkan {
        /// The Vulkan function (or step) that failed.
        call: &'static str,
        /// The result code it returned.
        result: vk::Result,
    },
    /// GPU memory allocation failed.
    #[error("GPU memory allocation failed")]
    Allocation(#[from] gpu_allocator::AllocationError),
    /// The mesh handed to the renderer is inconsistent.
    #[error("invalid render mesh: {0}")]
    InvalidMesh(String),
    /// The requested image size is zero or larger than the device allows.
    #[error("invalid image size {width}x{height} (must be 1..={max} per side)")]
    InvalidSize {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
        /// The device limit.
        max: u32,
    },
    /// The device cannot draw with the sample count asked for.
    #[error(
        "{device} does not support {requested} samples per pixel (it supports {})",
        supported.iter().map(u32::to_string).collect::<Vec<_>>().join(", ")
    )]
    Samples {
        /// The samples per pixel asked for.
        requested: u32,
        /// The device.
        device: String,
        /// The counts it supports.
        supported: Vec<u32>,
    },
    /// Reading or writing a file failed.
    #[error("{path}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// PNG encoding or decoding failed.
    #[error("{path}")]
    Image {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: image::ImageError,
    },
    /// EXR encoding failed.
    #[error("{path}")]
    Exr {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: exr::error::Error,
    },
    /// The window system failed (viewer only).
    #[error("window system error: {0}")]
    Window(String),
    /// The window's Vulkan surface was lost (`VK_ERROR_SURFACE_LOST_KHR`) and creating it
    /// again did not help (viewer only).
    #[error(
        "the window's Vulkan surface was lost {times} times in a row and could not be \
         recreated; is the display still there?"
    )]
    SurfaceLost {
        /// Losses in a row, without a frame presented in between.
        times: u32,
    },
    /// The frame source of the viewer reported an error.
    #[error("frame source failed: {0}")]
    FrameSource(String),
}

/// Short for `Result<T, VkError>`.
pub type Result<T, E = VkError> = std::result::Result<T, E>;

/// Adds the name of the failing Vulkan call to a raw `vk::Result`.
pub(crate) trait VkResultExt<T> {
    fn call(self, call: &'static str) -> Result<T>;
}

impl<T> VkResultExt<T> for std::result::Result<T, vk::Result> {
    fn call(self, call: &'static str) -> Result<T> {
        self.map_err(|result| VkError::Vulkan { call, result })
    }
}

#[cfg(test)]
mod tests {
    use std::error::Error as _;

    /// Each cause is printed once: the message names the file, `source()` says what went wrong.
    #[test]
    fn io_cause_is_not_repeated() {
        let path = std::env::temp_dir().join("subdiv-vk-no-such-dir/missing.png");
        let e = crate::read_png(&path).unwrap_err();
        let cause = e.source().expect("the I/O or image error is the source");
        let (message, cause) = (e.to_string(), cause.to_string());
        assert!(message.ends_with("missing.png"), "{message}");
        assert!(!message.contains(&cause), "{message} repeats {cause}");
    }
}
