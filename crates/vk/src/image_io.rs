//! PNG and EXR files.

use std::path::Path;

use exr::prelude::{
    AnyChannel, AnyChannels, Encoding, FlatSamples, Image, Layer, LayerAttributes, ReadChannels,
    ReadLayers, SmallVec, WritableImage,
};
use image::RgbaImage;

use crate::error::{Result, VkError};
use crate::offscreen::AuxImage;

/// Channel names written by [`write_exr`].
pub const EXR_CHANNELS: [&str; 6] = ["Z", "N.X", "N.Y", "N.Z", "S", "A"];

fn io_error(path: &Path, source: std::io::Error) -> VkError {
    VkError::Io {
        path: path.to_path_buf(),
        source,
    }
}

fn create_parent(path: &Path) -> Result<()> {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => {
            std::fs::create_dir_all(dir).map_err(|e| io_error(dir, e))
        }
        _ => Ok(()),
    }
}

/// Writes an RGBA image as PNG (creating the parent folder).
pub fn write_png(path: impl AsRef<Path>, image: &RgbaImage) -> Result<()> {
    let path = path.as_ref();
    create_parent(path)?;
    image
        .save_with_format(path, image::ImageFormat::Png)
        .map_err(|source| VkError::Image {
            path: path.to_path_buf(),
            source,
        })
}

/// Reads a PNG (any colour type) as RGBA.
pub fn read_png(path: impl AsRef<Path>) -> Result<RgbaImage> {
    let path = path.as_ref();
    let reader = image::ImageReader::open(path).map_err(|e| io_error(path, e))?;
    let mut reader = reader;
    reader.set_format(image::ImageFormat::Png);
    reader
        .decode()
        .map(|img| img.into_rgba8())
        .map_err(|source| VkError::Image {
            path: path.to_path_buf(),
            source,
        })
}

/// Writes the auxiliary images as a single-layer float EXR with channels
/// `Z` (linear view depth, +inf on background), `N.X`, `N.Y`, `N.Z` (unit
/// world-space normal), `S` (the per-vertex scalar, e.g. subdivision depth)
/// and `A` (coverage).
pub fn write_exr(path: impl AsRef<Path>, aux: &AuxImage) -> Result<()> {
    let path = path.as_ref();
    let pixels = aux.width as usize * aux.height as usize;
    let lengths = [
        aux.depth.len(),
        aux.normals.len(),
        aux.scalars.len(),
        aux.coverage.len(),
    ];
    if pixels == 0 || lengths.iter().any(|&n| n != pixels) {
        return Err(VkError::InvalidMesh(format!(
            "auxiliary image {}x{} has inconsistent channel lengths {lengths:?}",
            aux.width, aux.height
        )));
    }
    create_parent(path)?;
    let component = |k: usize| aux.normals.iter().map(|n| n[k]).collect::<Vec<f32>>();
    let channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = SmallVec::from_vec(vec![
        AnyChannel::new("Z", FlatSamples::F32(aux.depth.clone())),
        AnyChannel::new("N.X", FlatSamples::F32(component(0))),
        AnyChannel::new("N.Y", FlatSamples::F32(component(1))),
        AnyChannel::new("N.Z", FlatSamples::F32(component(2))),
        AnyChannel::new("S", FlatSamples::F32(aux.scalars.clone())),
        AnyChannel::new("A", FlatSamples::F32(aux.coverage.clone())),
    ]);
    let layer = Layer::new(
        (aux.width as usize, aux.height as usize),
        LayerAttributes::named("subdiv"),
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(channels),
    );
    Image::from_layer(layer)
        .write()
        .to_file(path)
        .map_err(|source| VkError::Exr {
            path: path.to_path_buf(),
            source,
        })
}

/// One EXR channel read back as f32 samples (row-major from the top-left).
#[derive(Clone, Debug, PartialEq)]
pub struct ExrChannel {
    /// Channel name, e.g. `Z`.
    pub name: String,
    /// Samples.
    pub samples: Vec<f32>,
}

/// Reads all channels of the first layer of an EXR file: (width, height, channels).
pub fn read_exr(path: impl AsRef<Path>) -> Result<(u32, u32, Vec<ExrChannel>)> {
    let path = path.as_ref();
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|source| VkError::Exr {
            path: path.to_path_buf(),
            source,
        })?;
    let layer = image.layer_data;
    let size = layer.size;
    let channels = layer
        .channel_data
        .list
        .iter()
        .map(|c| ExrChannel {
            name: c.name.to_string(),
            samples: c.sample_data.values_as_f32().collect(),
        })
        .collect();
    Ok((size.0 as u32, size.1 as u32, channels))
}
