//! Image quality of a tessellation against the true surface: what `subdiv bench quality`
//! measures (issue: adaptive depth must earn its keep).

mod metrics;

pub use metrics::{FrameErrors, compare_frames, quantile, silhouette_distance};
