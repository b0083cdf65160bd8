//! Golden-image comparison for regression tests (`cargo xtask golden`).
//!
//! Comparison is exact by default: Debian 12's lavapipe renders byte-identical
//! frames. A [`Tolerance`] allows small differences on other Mesa versions.
//! On a mismatch the actual image and a difference image are written to the
//! output folder (by default `target/golden/`).

use std::path::{Path, PathBuf};

use image::{Rgba, RgbaImage};

use crate::error::Result;
use crate::image_io::{read_png, write_png};

/// Default folder for actual and difference images of failed comparisons.
pub const DEFAULT_OUTPUT_DIR: &str = "target/golden";

/// Allowed per-channel absolute error (0..255 units) when not comparing exactly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerance {
    /// Largest allowed mean absolute error over all channels of all pixels.
    pub mean: f64,
    /// Largest allowed 99th percentile of the per-pixel maximum channel error.
    pub p99: f64,
}

impl Default for Tolerance {
    fn default() -> Self {
        Tolerance {
            mean: 0.5,
            p99: 8.0,
        }
    }
}

/// Error statistics of a comparison, in 0..255 units.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Mean absolute error over all channels of all pixels.
    pub mean: f64,
    /// 99th percentile of the per-pixel maximum channel error.
    pub p99: f64,
    /// Largest channel error.
    pub max: u8,
    /// Pixels that differ at all.
    pub differing_pixels: u64,
}

/// Result of [`compare`].
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// Byte-identical.
    Identical,
    /// Different, but within the tolerance.
    WithinTolerance(Stats),
    /// Too different (or a different size); actual and difference images were written.
    Mismatch {
        /// Error statistics (zero when the sizes differ).
        stats: Stats,
        /// A human-readable reason.
        reason: String,
        /// Where the actual image was written.
        actual: PathBuf,
        /// Where the difference image was written (absent when sizes differ).
        diff: Option<PathBuf>,
    },
    /// No expected image exists; the actual image was written (bless it to accept).
    MissingExpected {
        /// Where the actual image was written.
        actual: PathBuf,
    },
}

impl Verdict {
    /// Whether the comparison passed.
    pub fn passed(&self) -> bool {
        matches!(self, Verdict::Identical | Verdict::WithinTolerance(_))
    }
}

/// Compares `actual` with the PNG at `expected_path`; writes failures to
/// [`DEFAULT_OUTPUT_DIR`] (relative to the current directory).
///
/// `tolerance = None` demands byte-identical pixels.
///
/// ```no_run
/// use subdiv_vk::golden::{self, Verdict};
/// # fn main() -> Result<(), subdiv_vk::VkError> {
/// let actual = image::RgbaImage::new(4, 4);
/// match golden::compare(&actual, "fixtures/golden/box.png", None)? {
///     Verdict::Identical | Verdict::WithinTolerance(_) => {}
///     other => eprintln!("golden mismatch: {other:?}"),
/// }
/// # Ok(())
/// # }
/// ```
pub fn compare(
    actual: &RgbaImage,
    expected_path: impl AsRef<Path>,
    tolerance: Option<Tolerance>,
) -> Result<Verdict> {
    compare_in(actual, expected_path, tolerance, DEFAULT_OUTPUT_DIR)
}

/// [`compare`] with an explicit output folder for actual and difference images.
pub fn compare_in(
    actual: &RgbaImage,
    expected_path: impl AsRef<Path>,
    tolerance: Option<Tolerance>,
    output_dir: impl AsRef<Path>,
) -> Result<Verdict> {
    let expected_path = expected_path.as_ref();
    let output_dir = output_dir.as_ref();
    let stem = expected_path.file_stem().map_or_else(
        || String::from("image"),
        |s| s.to_string_lossy().into_owned(),
    );
    let actual_path = output_dir.join(format!("{stem}.actual.png"));
    if !expected_path.exists() {
        write_png(&actual_path, actual)?;
        return Ok(Verdict::MissingExpected {
            actual: actual_path,
        });
    }
    let expected = read_png(expected_path)?;
    if expected.dimensions() != actual.dimensions() {
        write_png(&actual_path, actual)?;
        return Ok(Verdict::Mismatch {
            stats: Stats::default(),
            reason: format!(
                "size {}x{} differs from expected {}x{}",
                actual.width(),
                actual.height(),
                expected.width(),
                expected.height()
            ),
            actual: actual_path,
            diff: None,
        });
    }
    if expected.as_raw() == actual.as_raw() {
        return Ok(Verdict::Identical);
    }
    let stats = statistics(actual, &expected);
    if let Some(t) = tolerance
        && stats.mean <= t.mean
        && stats.p99 <= t.p99
    {
        return Ok(Verdict::WithinTolerance(stats));
    }
    write_png(&actual_path, actual)?;
    let diff_path = output_dir.join(format!("{stem}.diff.png"));
    write_png(&diff_path, &difference_image(actual, &expected))?;
    let reason = match tolerance {
        None => format!(
            "{} pixels differ (exact comparison; max error {}, mean {:.4})",
            stats.differing_pixels, stats.max, stats.mean
        ),
        Some(t) => format!(
            "mean error {:.4} (allowed {}), 99th percentile {:.1} (allowed {})",
            stats.mean, t.mean, stats.p99, t.p99
        ),
    };
    Ok(Verdict::Mismatch {
        stats,
        reason,
        actual: actual_path,
        diff: Some(diff_path),
    })
}

/// Overwrites the golden image at `expected_path` with `actual` ("bless").
pub fn bless(actual: &RgbaImage, expected_path: impl AsRef<Path>) -> Result<()> {
    write_png(expected_path, actual)
}

/// Error statistics of two images of equal size.
pub fn statistics(a: &RgbaImage, b: &RgbaImage) -> Stats {
    let mut sum = 0u64;
    let mut max = 0u8;
    let mut differing = 0u64;
    let mut histogram = [0u64; 256];
    for (pa, pb) in a.pixels().zip(b.pixels()) {
        let mut pixel_max = 0u8;
        for (ca, cb) in pa.0.iter().zip(pb.0.iter()) {
            let d = ca.abs_diff(*cb);
            sum += u64::from(d);
            pixel_max = pixel_max.max(d);
        }
        max = max.max(pixel_max);
        differing += u64::from(pixel_max > 0);
        histogram[pixel_max as usize] += 1;
    }
    let pixels = u64::from(a.width()) * u64::from(a.height());
    let channels = pixels * 4;
    // 99th percentile: smallest error e such that >= 99% of pixels have error <= e.
    let needed = (pixels * 99).div_ceil(100);
    let mut seen = 0u64;
    let mut p99 = 0.0;
    for (e, count) in histogram.iter().enumerate() {
        seen += count;
        if seen >= needed {
            p99 = e as f64;
            break;
        }
    }
    Stats {
        mean: if channels == 0 {
            0.0
        } else {
            sum as f64 / channels as f64
        },
        p99,
        max,
        differing_pixels: differing,
    }
}

/// Differing pixels in red (brighter = larger error, at least half intensity),
/// equal pixels as a faded grey copy of the expected image.
pub fn difference_image(actual: &RgbaImage, expected: &RgbaImage) -> RgbaImage {
    let mut out = RgbaImage::new(expected.width(), expected.height());
    for ((o, pa), pe) in out.pixels_mut().zip(actual.pixels()).zip(expected.pixels()) {
        let err =
            pa.0.iter()
                .zip(pe.0.iter())
                .map(|(a, e)| a.abs_diff(*e))
                .max()
                .unwrap_or(0);
        *o = if err > 0 {
            Rgba([128u8.saturating_add(err / 2).max(128), 0, 0, 255])
        } else {
            let grey = (u32::from(pe.0[0]) + u32::from(pe.0[1]) + u32::from(pe.0[2])) / 3;
            let faded = (200 + grey * 55 / 255) as u8;
            Rgba([faded, faded, faded, 255])
        };
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(value: u8) -> RgbaImage {
        RgbaImage::from_pixel(10, 10, Rgba([value, value, value, 255]))
    }

    #[test]
    fn identical_and_missing() {
        let dir = std::env::temp_dir().join(format!("subdiv-vk-golden-{}", std::process::id()));
        let expected = dir.join("expected.png");
        let out = dir.join("out");
        let a = image(10);
        let missing = compare_in(&a, &expected, None, &out).unwrap();
        assert!(matches!(missing, Verdict::MissingExpected { .. }));
        bless(&a, &expected).unwrap();
        assert_eq!(
            compare_in(&a, &expected, None, &out).unwrap(),
            Verdict::Identical
        );

        let mut b = a.clone();
        b.put_pixel(3, 4, Rgba([12, 10, 10, 255]));
        let verdict = compare_in(&b, &expected, None, &out).unwrap();
        let Verdict::Mismatch {
            stats,
            diff: Some(diff),
            actual,
            ..
        } = verdict
        else {
            panic!("expected a mismatch, got {verdict:?}");
        };
        assert_eq!(stats.differing_pixels, 1);
        assert_eq!(stats.max, 2);
        assert!(diff.exists() && actual.exists());
        // One pixel in a hundred: the 99th percentile is still zero.
        let within = compare_in(&b, &expected, Some(Tolerance::default()), &out).unwrap();
        assert!(matches!(within, Verdict::WithinTolerance(_)));
        let strict = Tolerance {
            mean: 0.0,
            p99: 0.0,
        };
        assert!(
            !compare_in(&b, &expected, Some(strict), &out)
                .unwrap()
                .passed()
        );

        let small = RgbaImage::new(3, 3);
        assert!(!compare_in(&small, &expected, None, &out).unwrap().passed());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
