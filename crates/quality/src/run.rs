//! A quality run: the reference render of the true surface (a deep uniform tessellation) per
//! camera, then every tessellation configuration rendered from the same cameras and compared
//! with it ([`compare_frames`]), with its triangle count and timings.

use std::time::Instant;

use subdiv::depth::{DepthParams, FrameTimeModel};
use subdiv::mesh::{Camera, Mesh};
use subdiv::rules::{Scheme, VertexScalar};
use subdiv::vk::{RenderMesh, RenderOptions, Renderer, View, VkError};

use super::config::{Config, ConfigQuality, QualityError, QualityParams};
use super::lines::line_pixels;
use super::metrics::{
    FrameErrors, SUPERSAMPLE, area_coverage, compare_with_distance, quantile,
    sample_silhouette_distance,
};
use subdiv::{Control, DynamicSubdivision, Scene, framing_box, uniform_limit, view_for};

/// The reference render of one camera.
struct ReferenceFrame {
    camera: Camera,
    view: View,
    coverage: Vec<bool>,
    normals: Vec<[f32; 3]>,
    /// Per pixel: distance to the reference's silhouette (supersampled mask and contours).
    distance: Vec<f32>,
    /// Per pixel: a line pixel at the run's shading tolerance ([`line_pixels`]).
    lines: Vec<bool>,
}

/// What the cameras of one configuration add up to.
#[derive(Default)]
struct Tally {
    triangles: usize,
    silhouette_max: f32,
    silhouette: Vec<f32>,
    shading: Vec<f32>,
    shading_off_lines: Vec<f32>,
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
            shading_deg_p99_off_lines: quantile(&self.shading_off_lines, 0.99),
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

/// What every render of a quality run uses: smooth shading, no lines, one sample per pixel.
/// The run measures coverage with its own supersampling ([`SUPERSAMPLE`]² point samples per
/// pixel, from the point-sampled auxiliary images), whatever sample count `subdiv render` uses;
/// one sample also keeps the timed renders free of resolve work.
fn render_options() -> RenderOptions {
    RenderOptions {
        show_lines: false,
        samples: Some(1),
        ..RenderOptions::default()
    }
}

/// Image error of tessellations of `cage` against its true surface, seen from a list of cameras
/// (what `subdiv bench quality` prints).
///
/// The reference is the uniform Catmull-Clark (or, with [`QualityRun::with_scheme`], Loop)
/// slate tessellation at
/// [`QualityParams::reference_depth`] with smooth limit normals, packed as a [`Scene`] exactly as
/// `subdiv render` draws it (normals split at creases) and rendered once per camera; every
/// configuration goes through the same [`Scene`] path and the same view ([`view_for`] with the
/// cage's [`framing_box`]). (`no_run`: rendering needs a Vulkan driver.)
///
/// ```no_run
/// use subdiv_quality::{Config, QualityParams, QualityRun, orbit_cameras};
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
    scheme: Scheme,
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
        QualityRun::with_scheme(renderer, cage, Scheme::CatmullClark, cameras, params)
    }

    /// [`QualityRun::new`] for the `scheme` surface of `cage`: the reference, the uniform
    /// configurations and the adaptive ones ([`DynamicSubdivision::with_scheme`]) all of it.
    pub fn with_scheme(
        renderer: &mut Renderer,
        cage: &'a Mesh,
        scheme: Scheme,
        cameras: &[Camera],
        params: QualityParams,
    ) -> Result<QualityRun<'a>, QualityError> {
        params.check()?;
        if cameras.is_empty() {
            return Err(QualityError::NoCameras);
        }
        let depth = params.reference_depth();
        let scene = Scene::uniform(cage, scheme, depth).map_err(|source| QualityError::Scene {
            config: format!("reference (uniform depth {depth})"),
            source,
        })?;
        let mesh = scene.render_mesh();
        let (lo, hi) = framing_box(cage);
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
            let lines = line_pixels(
                &coverage,
                &normals,
                w as usize,
                h as usize,
                params.shading_error_deg,
            );
            frames.push(ReferenceFrame {
                camera,
                view,
                coverage,
                normals,
                distance,
                lines,
            });
        }
        Ok(QualityRun {
            cage,
            scheme,
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
                    let limit = uniform_limit(self.cage, self.scheme, depth).map_err(scene_err)?;
                    tally.update_ms.push(elapsed_ms(t));
                    let scene = match &scene {
                        Some(s) => s,
                        None => {
                            let mut limit = limit;
                            let depths = vec![depth as f32; limit.num_vertices()];
                            limit
                                .set_scalar(VertexScalar::Depth, depths)
                                .map_err(|e| scene_err(e.into()))?;
                            scene.insert(Scene::from_limit(&limit))
                        }
                    };
                    self.compare(renderer, scene, i, &name, &mut tally)?;
                }
            }
            Config::Dicing(px) => {
                let eval_err = |e: subdiv::eval::EvalError| QualityError::Dicing {
                    config: name.clone(),
                    what: e.to_string(),
                };
                let eval =
                    subdiv::eval::Evaluator::new(self.cage, self.scheme).map_err(eval_err)?;
                let dicing = subdiv::eval::Dicing::new(px);
                for (i, f) in self.frames.iter().enumerate() {
                    let t = Instant::now();
                    let d = subdiv::eval::dice(&eval, &f.camera, &dicing).map_err(eval_err)?;
                    tally.update_ms.push(elapsed_ms(t));
                    self.compare(
                        renderer,
                        &Scene::from_limit(&d.surface),
                        i,
                        &name,
                        &mut tally,
                    )?;
                }
            }
            Config::Curvature(_) | Config::PixelError(_) | Config::Budget(_) => {
                let adaptive_err = |source| QualityError::Adaptive {
                    config: name.clone(),
                    source,
                };
                let mut params = DepthParams {
                    max_depth: self.params.max_depth,
                    shading_error_deg: self.params.shading_error_deg,
                    ..DepthParams::default()
                };
                match config {
                    Config::PixelError(px) => params.pixel_error = Some(px),
                    Config::Curvature(c) => params = c.apply(params),
                    Config::Uniform(_) | Config::Budget(_) | Config::Dicing(_) => {}
                }
                let mut node =
                    DynamicSubdivision::with_scheme(self.cage.clone(), self.scheme, params)
                        .map_err(adaptive_err)?;
                if let Config::Budget(n) = config {
                    // One second per 10^5 triangles, nothing else: a budget of n triangles is
                    // a frame time of n * 1e-5 seconds.
                    node.set_frame_model(FrameTimeModel::new([0.0, 1.0, 0.0, 0.0, 0.0]));
                    node.set_control(Control::Budget, (1e5 / f64::from(n.max(1))) as f32);
                }
                if params.pixel_error.is_some() || matches!(config, Config::Budget(_)) {
                    node.patch_errors();
                }
                for (i, f) in self.frames.iter().enumerate() {
                    let t = Instant::now();
                    let g = node.update(&f.camera, None).map_err(adaptive_err)?;
                    tally.update_ms.push(elapsed_ms(t));
                    let scene = Scene::from_limit(&g.surface().referenced_only());
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
        progress: impl FnMut(&ConfigQuality),
    ) -> Result<Vec<ConfigQuality>, QualityError> {
        self.measure_configs(renderer, &Config::all(self.params.max_depth), progress)
    }

    /// Measures `configs` in order, calling `progress` after each (a sweep of the curvature
    /// mode's parameters, or a subset of [`Config::all`]).
    pub fn measure_configs(
        &self,
        renderer: &mut Renderer,
        configs: &[Config],
        mut progress: impl FnMut(&ConfigQuality),
    ) -> Result<Vec<ConfigQuality>, QualityError> {
        let mut out = Vec::new();
        for &config in configs {
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
        let mesh = scene.render_mesh();
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
            &f.lines,
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
        let mesh = scene.render_mesh();
        tally.triangles = tally.triangles.max(mesh.triangle_count());
        tally.silhouette_max = e
            .silhouette_px
            .iter()
            .copied()
            .fold(tally.silhouette_max, f32::max);
        tally.silhouette.extend(e.silhouette_px);
        tally.shading.extend(e.shading_deg);
        tally.shading_off_lines.extend(e.shading_deg_off_lines);
        let options = render_options();
        let render_err = |source| QualityError::Render {
            config: name.to_string(),
            camera: i,
            source,
        };
        let view = &self.frames[i].view;
        // One untimed render first: the comparison above rendered at the supersampled size, so
        // this one re-creates the render target at the run's size and grows the mesh buffer;
        // neither belongs to the cost of drawing the mesh.
        renderer
            .render_discard(&mesh, view, self.params.size, &options)
            .map_err(render_err)?;
        for _ in 0..self.params.timing_runs {
            let t = Instant::now();
            renderer
                .render_discard(&mesh, view, self.params.size, &options)
                .map_err(render_err)?;
            tally.render_ms.push(elapsed_ms(t));
        }
        Ok(())
    }
}

/// Every contour of `scene` seen by `camera` ([`subdiv::rules::Silhouettes::contours_into`]: silhouette
/// and boundary edges, hidden or not), projected to pixels; segments reaching behind the eye are
/// left out.
fn projected_contours(scene: &Scene, camera: &Camera) -> Vec<[[f32; 2]; 2]> {
    let mut lines = Vec::new();
    scene
        .silhouettes()
        .contours_into(scene.surface().positions(), camera.eye, &mut lines);
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
