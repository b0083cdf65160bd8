//! What a quality run compares and reports: the configurations ([`Config`]), the run's
//! parameters ([`QualityParams`]), its errors ([`QualityError`]) and the result line of one
//! configuration ([`ConfigQuality`]).

use std::fmt;

use subdiv::depth::{DEFAULT_MAX_DEPTH, DEFAULT_SHADING_ERROR_DEG, DepthParams};
use subdiv::rules::{Depth, MAX_DEPTH};
use subdiv::stitch::{AssemblyError, MAX_ADAPTIVE_DEPTH};
use subdiv::vk::VkError;

use subdiv::SceneError;

/// One tessellation configuration of the comparison.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Config {
    /// Uniform slate tessellation at this depth (`uniform-<d>`).
    Uniform(Depth),
    /// [`DynamicSubdivision`] in the paper's mode for the run's max depth: curvature,
    /// classification and projected size with these parameters (`curvature` for the
    /// [`DepthParams`] defaults, else `curvature-cone<A>-eps<E>-size<MIN>-<MAX>`).
    Curvature(CurvatureParams),
    /// [`DynamicSubdivision`] with `pixel_error = Some(px)` (`pixel-error-<px>`).
    PixelError(f32),
    /// [`DynamicSubdivision`] under the predictive frame-rate control with a frame time of one
    /// unit per triangle and a budget of this many triangles (`budget-<n>`): the depths with
    /// the least estimated image error that draw at most `n` triangles (before fans), as the
    /// controller chooses them for a machine whose frames cost their triangles. Deterministic:
    /// what the controller buys with a budget, apart from any machine's timing.
    Budget(u32),
    /// Dicing by pixels at this dicing rate (`dicing-<px>`): every cage edge's rate from its
    /// limit curve's length on screen, the surface evaluated exactly
    /// ([`subdiv::eval::dice`], Cycles' off-screen scale).
    Dicing(f32),
}

impl Config {
    /// The configuration's name as `subdiv bench quality` prints it: `uniform-3`, `curvature`,
    /// `pixel-error-0.5`.
    pub fn name(&self) -> String {
        match self {
            Config::Uniform(d) => format!("uniform-{d}"),
            Config::Curvature(c) => c.name(),
            Config::PixelError(px) => format!("pixel-error-{px}"),
            Config::Budget(n) => format!("budget-{n}"),
            Config::Dicing(px) => format!("dicing-{px}"),
        }
    }

    /// The configurations of `subdiv bench quality`: `uniform-0` .. `uniform-<max_depth>`,
    /// `curvature`, `pixel-error-2`, `pixel-error-1`, `pixel-error-0.5`, `dicing-2`,
    /// `dicing-1`, `dicing-0.5`.
    pub fn all(max_depth: Depth) -> Vec<Config> {
        (0..=max_depth)
            .map(Config::Uniform)
            .chain([Config::Curvature(CurvatureParams::default())])
            .chain(Config::pixel_errors())
            .chain(Config::dicings())
            .collect()
    }

    /// The dicing configurations of [`Config::all`]: 2, 1 and 0.5 px.
    pub fn dicings() -> [Config; 3] {
        [
            Config::Dicing(2.0),
            Config::Dicing(1.0),
            Config::Dicing(0.5),
        ]
    }

    /// The pixel-error configurations of [`Config::all`]: 2, 1 and 0.5 px.
    pub fn pixel_errors() -> [Config; 3] {
        [
            Config::PixelError(2.0),
            Config::PixelError(1.0),
            Config::PixelError(0.5),
        ]
    }
}

/// The paper's user parameters of the curvature mode (Settgast et al. 2004, Section 3.1):
/// `NormalConeAperture`, `VertexClassifier` and `ProjectedSizeMin/Max`, as in [`DepthParams`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvatureParams {
    /// [`DepthParams::cone_aperture_deg`].
    pub cone_aperture_deg: f32,
    /// [`DepthParams::classifier_eps`].
    pub classifier_eps: f32,
    /// [`DepthParams::projected_size`].
    pub projected_size: Option<(f32, f32)>,
}

impl Default for CurvatureParams {
    /// The [`DepthParams`] defaults.
    fn default() -> Self {
        let d = DepthParams::default();
        CurvatureParams {
            cone_aperture_deg: d.cone_aperture_deg,
            classifier_eps: d.classifier_eps,
            projected_size: d.projected_size,
        }
    }
}

impl CurvatureParams {
    /// `curvature` for the defaults, else `curvature-cone<A>-eps<E>-size<MIN>-<MAX>`
    /// (`-sizeoff` without the projected-size adjustment).
    pub fn name(&self) -> String {
        if *self == CurvatureParams::default() {
            return "curvature".to_string();
        }
        let size = match self.projected_size {
            Some((lo, hi)) => format!("size{lo}-{hi}"),
            None => "sizeoff".to_string(),
        };
        format!(
            "curvature-cone{}-eps{}-{size}",
            self.cone_aperture_deg, self.classifier_eps
        )
    }

    /// `p` with these parameters.
    pub fn apply(&self, p: DepthParams) -> DepthParams {
        DepthParams {
            cone_aperture_deg: self.cone_aperture_deg,
            classifier_eps: self.classifier_eps,
            projected_size: self.projected_size,
            ..p
        }
    }
}

/// Size, depths and timing repetitions of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QualityParams {
    /// Image size in pixels; every camera is used at this size.
    pub size: [u32; 2],
    /// Deepest depth of the configurations (uniform depths `0..=max_depth`, the adaptive
    /// modes' `maxsd`).
    pub max_depth: Depth,
    /// Depth of the reference tessellation; `None`: `max_depth + 1`.
    pub reference_depth: Option<Depth>,
    /// Timed `render_discard` calls per camera and configuration (the median is reported).
    pub timing_runs: usize,
    /// The pixel-error configurations' normal tolerance
    /// ([`DepthParams::shading_error_deg`]).
    pub shading_error_deg: f32,
}

impl Default for QualityParams {
    fn default() -> Self {
        QualityParams {
            size: [800, 600],
            max_depth: DEFAULT_MAX_DEPTH,
            reference_depth: None,
            timing_runs: 3,
            shading_error_deg: DEFAULT_SHADING_ERROR_DEG,
        }
    }
}

impl QualityParams {
    /// The reference depth: the given one, else `max_depth + 1`.
    pub fn reference_depth(&self) -> Depth {
        self.reference_depth
            .unwrap_or(self.max_depth.saturating_add(1))
    }

    /// Refuses parameters a run cannot use.
    pub fn check(&self) -> Result<(), QualityError> {
        let [w, h] = self.size;
        if w == 0 || h == 0 {
            return Err(QualityError::EmptyImage {
                width: w,
                height: h,
            });
        }
        if self.max_depth > MAX_ADAPTIVE_DEPTH {
            return Err(QualityError::MaxDepthTooDeep {
                max_depth: self.max_depth,
            });
        }
        let reference = self.reference_depth();
        if reference <= self.max_depth {
            return Err(QualityError::ReferenceNotDeeper {
                reference,
                max_depth: self.max_depth,
            });
        }
        if reference > MAX_DEPTH {
            return Err(QualityError::ReferenceTooDeep { reference });
        }
        if self.timing_runs == 0 {
            return Err(QualityError::NoTimingRuns);
        }
        if !(self.shading_error_deg > 0.0 && self.shading_error_deg <= 180.0) {
            return Err(QualityError::ShadingError {
                degrees: self.shading_error_deg,
            });
        }
        Ok(())
    }
}

/// Why a quality run could not be made.
#[derive(Debug, thiserror::Error)]
pub enum QualityError {
    /// The reference is not deeper than every configuration.
    #[error(
        "reference depth {reference} is not deeper than the deepest configuration \
         (max depth {max_depth}); use a reference depth of at least {}",
        *max_depth as u16 + 1
    )]
    ReferenceNotDeeper {
        /// The reference depth asked for.
        reference: Depth,
        /// The configurations' max depth.
        max_depth: Depth,
    },
    /// The reference depth exceeds what the tessellator supports.
    #[error("reference depth {reference} is too deep (at most {MAX_DEPTH})")]
    ReferenceTooDeep {
        /// The reference depth asked for.
        reference: Depth,
    },
    /// The max depth exceeds what the adaptive tessellation supports.
    #[error(
        "max depth {max_depth} is too deep for the adaptive tessellation (at most {MAX_ADAPTIVE_DEPTH})"
    )]
    MaxDepthTooDeep {
        /// The max depth asked for.
        max_depth: Depth,
    },
    /// An image without pixels.
    #[error("image size {width}x{height} has no pixels")]
    EmptyImage {
        /// Width asked for.
        width: u32,
        /// Height asked for.
        height: u32,
    },
    /// A dicing configuration failed (the evaluation refused the cage).
    #[error("{config}: {what}")]
    Dicing {
        /// The configuration.
        config: String,
        /// What failed.
        what: String,
    },
    /// A normal tolerance outside `(0, 180]` degrees.
    #[error("shading error {degrees}° is not an angle in (0, 180] degrees")]
    ShadingError {
        /// The tolerance asked for.
        degrees: f32,
    },
    /// No timed renders asked for.
    #[error("at least one timed render per camera is needed")]
    NoTimingRuns,
    /// No cameras given.
    #[error("no cameras to measure from")]
    NoCameras,
    /// The reference surface is not in view of a camera.
    #[error("camera {camera}: the reference surface covers no pixel (is the model in view?)")]
    EmptyReference {
        /// Index of the camera.
        camera: usize,
    },
    /// A configuration produced nothing to draw.
    #[error("{config}, camera {camera}: the tessellation has no triangles")]
    EmptyFrame {
        /// The configuration's name.
        config: String,
        /// Index of the camera.
        camera: usize,
    },
    /// The uniform tessellation of the reference or of a configuration failed.
    #[error("{config}: uniform tessellation")]
    Scene {
        /// `reference` or the configuration's name.
        config: String,
        /// What the tessellator said.
        #[source]
        source: SceneError,
    },
    /// The adaptive tessellation failed.
    #[error("{config}: adaptive tessellation")]
    Adaptive {
        /// The configuration's name.
        config: String,
        /// What the adaptive node said.
        #[source]
        source: AssemblyError,
    },
    /// The renderer failed.
    #[error("{config}, camera {camera}: rendering")]
    Render {
        /// `reference` or the configuration's name.
        config: String,
        /// Index of the camera.
        camera: usize,
        /// What the renderer said.
        #[source]
        source: VkError,
    },
}

/// The result of one configuration over all cameras.
#[derive(Clone, Debug, PartialEq)]
pub struct ConfigQuality {
    /// The configuration.
    pub config: Config,
    /// Triangles drawn (the most over the cameras).
    pub triangles: usize,
    /// Largest silhouette error over all cameras, in pixels (0 when no pixel disagrees).
    pub silhouette_px_max: f32,
    /// 99th percentile of the silhouette error over the disagreeing pixels of all cameras.
    pub silhouette_px_p99: f32,
    /// 99th percentile of the shading angle over the pixels covered by both, all cameras, in
    /// degrees.
    pub shading_deg_p99: f32,
    /// The same over the pixels off the reference's line pixels (where the true normal turns
    /// by more than the run's shading tolerance to a neighbouring pixel: crease lines, folds).
    /// What `--shading-error` bounds.
    pub shading_deg_p99_off_lines: f32,
    /// Median time to produce the geometry, in milliseconds.
    pub update_ms: f64,
    /// Median `render_discard` time, in milliseconds.
    pub render_ms: f64,
}

impl fmt::Display for ConfigQuality {
    /// `config=<name> triangles=<n> silhouette_px_max=<f> silhouette_px_p99=<f>
    /// shading_deg_p99=<f> update_ms=<f> render_ms=<f> shading_deg_p99_off_lines=<f>`
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "config={} triangles={} silhouette_px_max={:.3} silhouette_px_p99={:.3} \
             shading_deg_p99={:.3} update_ms={:.3} render_ms={:.3} shading_deg_p99_off_lines={:.3}",
            self.config.name(),
            self.triangles,
            self.silhouette_px_max,
            self.silhouette_px_p99,
            self.shading_deg_p99,
            self.update_ms,
            self.render_ms,
            self.shading_deg_p99_off_lines
        )
    }
}
