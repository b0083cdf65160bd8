//! Multisampling: which sample count a render uses ([`RenderOptions::samples`]).
//!
//! [`RenderOptions::samples`]: crate::RenderOptions::samples

use ash::vk;

use crate::error::{Result, VkError};

/// Samples per pixel when none is asked for, on a device that supports it; elsewhere the
/// most it supports below this.
pub const DEFAULT_SAMPLES: u32 = 4;

/// The sample counts a render may ask for: 1, 2, 4 and 8 per pixel.
pub const SAMPLE_COUNTS: [u32; 4] = [1, 2, 4, 8];

/// The Vulkan flag of `n` samples (`n` one of [`SAMPLE_COUNTS`]).
pub(crate) fn flag(n: u32) -> vk::SampleCountFlags {
    match n {
        2 => vk::SampleCountFlags::TYPE_2,
        4 => vk::SampleCountFlags::TYPE_4,
        8 => vk::SampleCountFlags::TYPE_8,
        _ => vk::SampleCountFlags::TYPE_1,
    }
}

/// The counts of [`SAMPLE_COUNTS`] in `supported` (1 always: every device has it).
pub(crate) fn counts(supported: vk::SampleCountFlags) -> Vec<u32> {
    SAMPLE_COUNTS
        .into_iter()
        .filter(|&n| n == 1 || supported.contains(flag(n)))
        .collect()
}

/// The sample count a render uses on `device` with `supported` counts: `requested` if the
/// device has it (an error naming the counts it has otherwise), or without a request
/// [`DEFAULT_SAMPLES`] where supported, else the largest supported count below it.
pub(crate) fn choose(
    requested: Option<u32>,
    supported: vk::SampleCountFlags,
    device: &str,
) -> Result<u32> {
    let have = counts(supported);
    match requested {
        Some(n) if have.contains(&n) => Ok(n),
        Some(n) => Err(VkError::Samples {
            requested: n,
            device: device.to_string(),
            supported: have,
        }),
        None => Ok(have
            .into_iter()
            .filter(|&n| n <= DEFAULT_SAMPLES)
            .max()
            .unwrap_or(1)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_is_four_where_supported_else_the_most_below() {
        let lavapipe = vk::SampleCountFlags::TYPE_1 | vk::SampleCountFlags::TYPE_4;
        assert_eq!(counts(lavapipe), [1, 4]);
        assert_eq!(choose(None, lavapipe, "llvmpipe").unwrap(), 4);
        assert_eq!(choose(Some(1), lavapipe, "llvmpipe").unwrap(), 1);
        let e = choose(Some(8), lavapipe, "llvmpipe")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "llvmpipe does not support 8 samples per pixel (it supports 1, 4)"
        );
        assert!(choose(Some(3), lavapipe, "llvmpipe").is_err());
        let two = vk::SampleCountFlags::TYPE_1 | vk::SampleCountFlags::TYPE_2;
        assert_eq!(choose(None, two, "gpu").unwrap(), 2);
        let all = two | vk::SampleCountFlags::TYPE_4 | vk::SampleCountFlags::TYPE_8;
        assert_eq!(choose(None, all, "gpu").unwrap(), 4);
        assert_eq!(choose(Some(8), all, "gpu").unwrap(), 8);
        // A device reporting nothing still draws one sample per pixel.
        assert_eq!(
            choose(None, vk::SampleCountFlags::empty(), "odd").unwrap(),
            1
        );
    }
}
