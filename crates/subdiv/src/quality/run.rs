//! A quality run: the reference render of the true surface (a deep uniform tessellation) per
//! camera, then every tessellation configuration rendered from the same cameras and compared
//! with it ([`compare_frames`]), with its triangle count and timings.

use std::fmt;
use std::time::Instant;

use subdiv_depth::{DEFAULT_SHADING_ERROR_DEG, DepthParams};
use subdiv_mesh::{Camera, Mesh};
use subdiv_rules::{Depth, MAX_DEPTH, Scheme};
use subdiv_stitch::{AssemblyError, MAX_ADAPTIVE_DEPTH};
use subdiv_vk::{RenderMesh, RenderOptions, Renderer, View, VkError};

use super::metrics::{
    FrameErrors, SUPERSAMPLE, area_coverage, compare_with_distance, quantile,
    sample_silhouette_distance,
};
use crate::{DynamicSubdivision, Scene, SceneError, frame_limit, uniform_limit, view_for};

/// One tessellation configuration of the comparison.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Config {
    /// Uniform slate tessellation at this depth (`uniform-<d>`).
    Uniform(Depth),
    /// [`DynamicSubdivision`] with the [`DepthParams`] defaults for the run's max depth:
    /// curvature, classification and projected size (`curvature`).
    Curvature,
    /// [`DynamicSubdivision`] with `pixel_error = Some(px)` (`pixel-error-<px>`).
    PixelError(f32),
}

impl Config {
    /// The configuration's name as `subdiv bench quality` prints it: `uniform-3`, `curvature`,
    /// `pixel-error-0.5`.
    pub fn name(&self) -> String {
        match self {
            Config::Uniform(d) => format!("uniform-{d}"),
            Config::Curvature => "curvature".to_string(),
            Config::PixelError(px) => format!("pixel-error-{px}"),
        }
    }

    /// The configurations of `subdiv bench quality`: `uniform-0` .. `uniform-<max_depth>`,
    /// `curvature`, `pixel-error-2`, `pixel-error-1`, `pixel-error-0.5`.
    pub fn all(max_depth: Depth) -> Vec<Config> {
        (0..=max_depth)
            .map(Config::Uniform)
            .chain([
                Config::Curvature,
                Config::PixelError(2.0),
                Config::PixelError(1.0),
                Config::PixelError(0.5),
            ])
            .collect()
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
            max_depth: 5,
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
    /// Median time to produce the geometry, in milliseconds.
    pub update_ms: f64,
    /// Median `render_discard` time, in milliseconds.
    pub render_ms: f64,
}

impl fmt::Display for ConfigQuality {
    /// `config=<name> triangles=<n> silhouette_px_max=<f> silhouette_px_p99=<f>
    /// shading_deg_p99=<f> update_ms=<f> render_ms=<f>`
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "config={} triangles={} silhouette_px_max={:.3} silhouette_px_p99={:.3} \
             shading_deg_p99={:.3} update_ms={:.3} render_ms={:.3}",
            self.config.name(),
            self.triangles,
            self.silhouette_px_max,
            self.silhouette_px_p99,
            self.shading_deg_p99,
            self.update_ms,
            self.render_ms
        )
    }
}

/// The reference render of one camera.
struct ReferenceFrame {
    camera: Camera,
    view: View,
    coverage: Vec<bool>,
    normals: Vec<[f32; 3]>,
    /// Per pixel: distance to the reference's silhouette (supersampled mask and contours).
    distance: Vec<f32>,
}

/// What the cameras of one configuration add up to.
#[derive(Default)]
struct Tally {
    triangles: usize,
    silhouette_max: f32,
    silhouette: Vec<f32>,
    shading: Vec<f32>,
    update_ms: Vec<f64>,
    render_ms: Vec<f64>,
}

impl Tally {
    fn finish(self, config: Config) -> ConfigQuality {
        ConfigQuality {
            config,
            triangles: self.triangles,
            silhouette_px_max: self.silhouette_max,
            silhouette_px_p99: quantile(&self.silhouette, 0.99),
            shading_deg_p99: quantile(&self.shading, 0.99),
            update_ms: median(self.update_ms),
            render_ms: median(self.render_ms),
        }
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn elapsed_ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// What every render of a quality run uses: smooth shading, no lines.
fn render_options() -> RenderOptions {
    RenderOptions {
        show_lines: false,
        ..RenderOptions::default()
    }
}

/// Image error of tessellations of `cage` against its true surface, seen from a list of cameras
/// (what `subdiv bench quality` prints).
///
/// The reference is the uniform Catmull-Clark slate tessellation at
/// [`QualityParams::reference_depth`] with smooth limit normals, packed as a [`Scene`] exactly as
/// `subdiv render` draws it (normals split at creases) and rendered once per camera; every
/// configuration goes through the same [`Scene`] path and the same view ([`view_for`] with the
/// cage's bounds). (`no_run`: rendering needs a Vulkan driver.)
///
/// ```no_run
/// use subdiv::quality::{Config, QualityParams, QualityRun, orbit_cameras};
/// use subdiv::mesh::{Camera, read_obj, glam::Vec3};
/// use subdiv::vk::Renderer;
/// let cage = read_obj("fixtures/reference/shapes/catmark_pawn.obj")?;
/// let (lo, hi) = cage.bounds();
/// let base = Camera::eye_relative(lo, hi, Vec3::new(0.0, 0.3, 2.2), 45.0, 800, 600);
/// let mut renderer = Renderer::new()?;
/// let params = QualityParams::default(); // 800x600, max depth 5, reference depth 6
/// let run = QualityRun::new(&mut renderer, &cage, &orbit_cameras(&base, 8), params)?;
/// for config in Config::all(params.max_depth) {
///     println!("{}", run.measure(&mut renderer, config)?);
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct QualityRun<'a> {
    cage: &'a Mesh,
    params: QualityParams,
    frames: Vec<ReferenceFrame>,
    reference_triangles: usize,
}

impl<'a> QualityRun<'a> {
    /// Tessellates the reference and renders it from every camera (at `params.size`).
    pub fn new(
        renderer: &mut Renderer,
        cage: &'a Mesh,
        cameras: &[Camera],
        params: QualityParams,
    ) -> Result<QualityRun<'a>, QualityError> {
        params.check()?;
        if cameras.is_empty() {
            return Err(QualityError::NoCameras);
        }
        let depth = params.reference_depth();
        let scene = Scene::uniform(cage, Scheme::CatmullClark, depth).map_err(|source| {
            QualityError::Scene {
                config: format!("reference (uniform depth {depth})"),
                source,
            }
        })?;
        let mesh = scene.mesh.as_render_mesh();
        let (lo, hi) = cage.bounds();
        let [w, h] = params.size;
        let mut frames = Vec::with_capacity(cameras.len());
        for (i, c) in cameras.iter().enumerate() {
            let camera = Camera {
                width: w,
                height: h,
                ..*c
            };
            let view = view_for(&camera, lo, hi);
            let (coverage, normals, samples) = render_masks(renderer, &mesh, &view, params.size)
                .map_err(|source| QualityError::Render {
                    config: "reference".to_string(),
                    camera: i,
                    source,
                })?;
            let contours = projected_contours(&scene, &camera);
            let distance =
                sample_silhouette_distance(&samples, params.size, SUPERSAMPLE, &contours);
            if !coverage.contains(&true) {
                return Err(QualityError::EmptyReference { camera: i });
            }
            frames.push(ReferenceFrame {
                camera,
                view,
                coverage,
                normals,
                distance,
            });
        }
        Ok(QualityRun {
            cage,
            params,
            frames,
            reference_triangles: mesh.triangle_count(),
        })
    }

    /// Triangles of the reference tessellation.
    pub fn reference_triangles(&self) -> usize {
        self.reference_triangles
    }

    /// The run's parameters.
    pub fn params(&self) -> &QualityParams {
        &self.params
    }

    /// The cameras, at the run's size.
    pub fn cameras(&self) -> impl Iterator<Item = &Camera> {
        self.frames.iter().map(|f| &f.camera)
    }

    /// Measures one configuration over every camera. Uniform depths are tessellated once per
    /// camera (each tessellation timed); an adaptive configuration's node is made once and
    /// updated per camera in order (the pixel-error mode's chord deviations, a one-time set-up,
    /// are computed before the first timed update; the first update fills the patch cache).
    pub fn measure(
        &self,
        renderer: &mut Renderer,
        config: Config,
    ) -> Result<ConfigQuality, QualityError> {
        let name = config.name();
        let mut tally = Tally::default();
        match config {
            Config::Uniform(depth) => {
                let scene_err = |source| QualityError::Scene {
                    config: name.clone(),
                    source,
                };
                let mut scene = None;
                for i in 0..self.frames.len() {
                    let t = Instant::now();
                    let limit =
                        uniform_limit(self.cage, Scheme::CatmullClark, depth).map_err(scene_err)?;
                    tally.update_ms.push(elapsed_ms(t));
                    let scene = match &scene {
                        Some(s) => s,
                        None => {
                            let depths = vec![depth as f32; limit.positions.len()];
                            scene.insert(Scene::from_limit(limit, depths))
                        }
                    };
                    self.compare(renderer, scene, i, &name, &mut tally)?;
                }
            }
            Config::Curvature | Config::PixelError(_) => {
                let adaptive_err = |source| QualityError::Adaptive {
                    config: name.clone(),
                    source,
                };
                let params = DepthParams {
                    max_depth: self.params.max_depth,
                    pixel_error: match config {
                        Config::PixelError(px) => Some(px),
                        _ => None,
                    },
                    shading_error_deg: self.params.shading_error_deg,
                    ..DepthParams::default()
                };
                let mut node =
                    DynamicSubdivision::new(self.cage.clone(), params).map_err(adaptive_err)?;
                if params.pixel_error.is_some() {
                    node.patch_errors();
                }
                for (i, f) in self.frames.iter().enumerate() {
                    let t = Instant::now();
                    let g = node.update(&f.camera, None).map_err(adaptive_err)?;
                    tally.update_ms.push(elapsed_ms(t));
                    let (limit, depths) = frame_limit(g);
                    let scene = Scene::from_limit(limit, depths);
                    self.compare(renderer, &scene, i, &name, &mut tally)?;
                }
            }
        }
        Ok(tally.finish(config))
    }

    /// Measures every configuration of [`Config::all`] for the run's max depth, calling
    /// `progress` after each.
    pub fn measure_all(
        &self,
        renderer: &mut Renderer,
        mut progress: impl FnMut(&ConfigQuality),
    ) -> Result<Vec<ConfigQuality>, QualityError> {
        let mut out = Vec::new();
        for config in Config::all(self.params.max_depth) {
            let q = self.measure(renderer, config)?;
            progress(&q);
            out.push(q);
        }
        Ok(out)
    }

    /// Renders `scene` from camera `i` (at the run's size) and compares it with that camera's
    /// reference render, untimed: what [`Self::measure`] does per camera, for callers that make
    /// their own geometry (e.g. the frames of `subdiv bench framerate`).
    pub fn frame_errors(
        &self,
        renderer: &mut Renderer,
        scene: &Scene,
        i: usize,
        name: &str,
    ) -> Result<FrameErrors, QualityError> {
        let f = self.frames.get(i).ok_or(QualityError::NoCameras)?;
        let mesh = scene.mesh.as_render_mesh();
        if mesh.triangle_count() == 0 {
            return Err(QualityError::EmptyFrame {
                config: name.to_string(),
                camera: i,
            });
        }
        let (coverage, normals, _) = render_masks(renderer, &mesh, &f.view, self.params.size)
            .map_err(|source| QualityError::Render {
                config: name.to_string(),
                camera: i,
                source,
            })?;
        Ok(compare_with_distance(
            &coverage,
            &normals,
            &f.coverage,
            &f.normals,
            &f.distance,
        ))
    }

    /// Renders `scene` from camera `i`, compares it with the reference and times the render.
    fn compare(
        &self,
        renderer: &mut Renderer,
        scene: &Scene,
        i: usize,
        name: &str,
        tally: &mut Tally,
    ) -> Result<(), QualityError> {
        let e = self.frame_errors(renderer, scene, i, name)?;
        let mesh = scene.mesh.as_render_mesh();
        tally.triangles = tally.triangles.max(mesh.triangle_count());
        tally.silhouette_max = e
            .silhouette_px
            .iter()
            .copied()
            .fold(tally.silhouette_max, f32::max);
        tally.silhouette.extend(e.silhouette_px);
        tally.shading.extend(e.shading_deg);
        let options = render_options();
        for _ in 0..self.params.timing_runs {
            let t = Instant::now();
            renderer
                .render_discard(&mesh, &self.frames[i].view, self.params.size, &options)
                .map_err(|source| QualityError::Render {
                    config: name.to_string(),
                    camera: i,
                    source,
                })?;
            tally.render_ms.push(elapsed_ms(t));
        }
        Ok(())
    }
}

/// Every contour of `scene` seen by `camera` ([`crate::Silhouettes::contours_into`]: silhouette
/// and boundary edges, hidden or not), projected to pixels; segments reaching behind the eye are
/// left out.
fn projected_contours(scene: &Scene, camera: &Camera) -> Vec<[[f32; 2]; 2]> {
    let mut lines = Vec::new();
    scene
        .silhouettes
        .contours_into(&scene.mesh.positions, camera.eye, &mut lines);
    lines
        .chunks_exact(2)
        .filter_map(|ab| {
            let a = camera.project(glam::Vec3::from(ab[0]))?;
            let b = camera.project(glam::Vec3::from(ab[1]))?;
            Some([a.to_array(), b.to_array()])
        })
        .collect()
}

/// The area-coverage mask and mean normals of a render (see [`area_coverage`]), and its
/// [`SUPERSAMPLE`]d coverage.
type Masks = (Vec<bool>, Vec<[f32; 3]>, Vec<f32>);

/// Renders `mesh` and returns its coverage mask, per-pixel normals and sample coverage.
fn render_masks(
    renderer: &mut Renderer,
    mesh: &RenderMesh<'_>,
    view: &View,
    size: [u32; 2],
) -> Result<Masks, VkError> {
    let s = SUPERSAMPLE;
    let big = [size[0] * s, size[1] * s];
    let (_, aux) = renderer.render_with_aux(mesh, view, big, &render_options())?;
    let (mask, normals) = area_coverage(&aux.coverage, &aux.normals, size, s);
    Ok((mask, normals, aux.coverage))
}

/// Measures every configuration of [`Config::all`]: [`QualityRun::new`] then
/// [`QualityRun::measure_all`].
pub fn measure(
    renderer: &mut Renderer,
    cage: &Mesh,
    cameras: &[Camera],
    params: QualityParams,
) -> Result<Vec<ConfigQuality>, QualityError> {
    QualityRun::new(renderer, cage, cameras, params)?.measure_all(renderer, |_| {})
}
