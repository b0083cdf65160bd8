//! Image quality of a tessellation against the true surface: what `subdiv bench quality`
//! measures (issue: adaptive depth must earn its keep).
//!
//! - `metrics.rs`: per-pixel silhouette distance and shading angle of one frame against its
//!   reference ([`compare_frames`], [`quantile`]);
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
