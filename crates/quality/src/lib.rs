//! `subdiv-quality`: image quality of a tessellation against the true surface, rendered — what
//! `subdiv bench quality` measures, and the bound tests of the pixel-error mode.
//!
//! A run renders a reference per camera (a uniform tessellation deeper than every
//! configuration, supersampled) and then each configuration (uniform depths, the curvature mode
//! of Settgast et al. 2004, the pixel-error mode) through the `subdiv` front door, and compares
//! the images pixel by pixel: the silhouette distance to the reference's supersampled mask
//! boundary and projected contours, and the shading angle between the interpolated normals
//! (also off the reference's line pixels, where no depth resolves the normal at pixel scale).
//!
//! **Invariants.** Nothing here changes a cage or a frame the caller passed in; a run's
//! parameters are checked before anything is rendered ([`QualityParams::check`]); the metrics
//! are pure functions of the images.
//!
//! - `metrics.rs`: per-pixel silhouette distance and shading angle of one frame
//!   against its reference ([`compare_frames`], [`quantile`]);
//! - `lines.rs`: the line pixels of a reference, where no depth resolves the normal at pixel
//!   scale ([`line_pixels`]);
//! - `config.rs`: the configurations, parameters, errors and result line of a run;
//! - `run.rs`: a whole run — reference renders per camera, then every configuration
//!   ([`QualityRun`], [`measure`], [`Config`]);
//! - `orbit.rs`: cameras evenly around the model ([`orbit_cameras`]).

mod config;
mod lines;
mod metrics;
mod orbit;
mod run;
#[cfg(test)]
mod tests;

pub use config::{Config, ConfigQuality, CurvatureParams, QualityError, QualityParams};
pub use lines::line_pixels;
pub use metrics::{
    FrameErrors, SUPERSAMPLE, area_coverage, compare_frames, compare_with_distance, quantile,
    sample_silhouette_distance, silhouette_distance,
};
pub use orbit::orbit_cameras;
pub use run::{QualityRun, measure};
