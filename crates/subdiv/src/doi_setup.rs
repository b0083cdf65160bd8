//! DoI set-up: from a DoI choice and its options (focus objects, skeleton, haptic interaction
//! point, threshold, steps, aggregation) to a ready [`Doi`] and a DoI-driven adaptive Loop
//! refinement of a cage for a camera (the meshes of Isenberg et al. 2003, Figs. 3, 4, 9, 10).

use glam::Vec3;
use subdiv_doi::{
    Aggregate, Curvature, Dihedral, Doi, DoiContext, DoiError, DoiKind, Focus, FocusSpec, Haptic,
    HapticPoint, Silhouette, ViewAngle, closest_surface_point, read_skeleton,
};
use subdiv_mesh::{Camera, Mesh, MeshError, PrimvarInterpolation, triangulate};
use subdiv_rules::{Depth, LimitChannel, LimitMesh, LimitMeshError, VertexScalar};

use crate::{Balance, RefineError, RefineOptions, Refined, Scene, refine_adaptive};

/// Why a DoI set-up was refused.
#[derive(Debug, thiserror::Error)]
pub enum DoiSetupError {
    /// Focus objects or a skeleton were given for a DoI other than [`DoiKind::Focus`].
    #[error("focus objects and a skeleton need the focus DoI")]
    FocusWithoutFocusDoi,
    /// A haptic interaction point was given for a DoI other than [`DoiKind::Haptic`].
    #[error("a haptic interaction point needs the haptic DoI")]
    HipWithoutHapticDoi,
    /// Splitting the cage into triangles failed.
    #[error("triangulating")]
    Triangulate(#[source] MeshError),
    /// The cage has a face that is no triangle and triangulation was not asked for.
    #[error("face {face} has {size} vertices; Loop subdivision needs triangles")]
    NotTriangles {
        /// The first such face.
        face: u32,
        /// Its number of vertices.
        size: usize,
    },
    /// The skeleton polyline could not be read.
    #[error(transparent)]
    Skeleton(DoiError),
    /// The focus objects do not name groups of the cage (or name none).
    #[error("focus objects")]
    Focus(#[source] DoiError),
    /// The threshold is NaN or infinite.
    #[error("the threshold must be a finite number")]
    Threshold,
    /// The DoI could not be evaluated.
    #[error(transparent)]
    Doi(#[from] DoiError),
    /// The refinement failed.
    #[error("refining")]
    Refine(#[source] RefineError),
    /// The refined surface broke an invariant of its output type.
    #[error(transparent)]
    Output(#[from] LimitMeshError),
    /// The scene could not show what was asked (a primvar the surface does not carry).
    #[error(transparent)]
    Scene(crate::SceneError),
}

/// A DoI choice and its options.
#[derive(Clone, Debug, PartialEq)]
pub struct DoiOptions {
    /// The Degree-of-Interest function.
    pub kind: DoiKind,
    /// Refine faces whose DoI exceeds this (`None`: the DoI's figure value from the paper).
    pub threshold: Option<f32>,
    /// Number of adaptive steps.
    pub steps: u32,
    /// How edge or vertex values become face values.
    pub aggregate: Aggregate,
    /// Split quads and n-gons into triangles first (Loop subdivision needs triangles).
    pub triangulate: bool,
    /// Focus objects for [`DoiKind::Focus`]: OBJ group or object names, `NAME` (interest 1) or
    /// `NAME=VALUE`.
    pub focus: Vec<String>,
    /// Skeleton polyline files for [`DoiKind::Focus`]: `FILE` (for every object without its
    /// own) or `NAME=FILE` (for focus object `NAME`).
    pub skeletons: Vec<String>,
    /// Haptic interaction point for [`DoiKind::Haptic`].
    pub hip: Option<Vec3>,
    /// Level balancing of the adaptive steps.
    pub balance: Balance,
}

impl DoiOptions {
    /// The options of `kind` with the defaults: the paper's threshold, 3 steps, the largest
    /// value around a face, no triangulation, no focus objects, skeleton or interaction point.
    pub fn new(kind: DoiKind) -> DoiOptions {
        DoiOptions {
            kind,
            threshold: None,
            steps: 3,
            aggregate: Aggregate::Max,
            triangulate: false,
            focus: Vec::new(),
            skeletons: Vec::new(),
            hip: None,
            balance: Balance::Vertex,
        }
    }
}

/// Refuses options that the chosen DoI (`kind`, `None` for no DoI at all) would ignore: focus
/// objects or skeletons without [`DoiKind::Focus`], a haptic interaction point without
/// [`DoiKind::Haptic`].
pub fn check_doi_options(
    kind: Option<DoiKind>,
    focus: &[String],
    skeletons: &[String],
    hip: Option<Vec3>,
) -> Result<(), DoiSetupError> {
    if kind != Some(DoiKind::Focus) && (!focus.is_empty() || !skeletons.is_empty()) {
        return Err(DoiSetupError::FocusWithoutFocusDoi);
    }
    if hip.is_some() && kind != Some(DoiKind::Haptic) {
        return Err(DoiSetupError::HipWithoutHapticDoi);
    }
    Ok(())
}

/// The DoI `kind` for `mesh`: focus objects and skeletons for [`DoiKind::Focus`] (the fade
/// radius is [`Focus::default_radius`]); with `hip`, [`DoiKind::Haptic`] is the interaction
/// point's neighbourhood.
pub fn make_doi(
    kind: DoiKind,
    mesh: &Mesh,
    focus: &[String],
    skeletons: &[String],
    hip: bool,
) -> Result<Box<dyn Doi>, DoiSetupError> {
    Ok(match kind {
        DoiKind::ViewAngle => Box::new(ViewAngle),
        DoiKind::Silhouette => Box::new(Silhouette),
        DoiKind::Dihedral => Box::new(Dihedral),
        DoiKind::Haptic if hip => Box::new(HapticPoint),
        DoiKind::Haptic => Box::new(Haptic::for_mesh(mesh, Haptic::DEFAULT_TOLERANCE)),
        DoiKind::Curvature => Box::new(Curvature),
        DoiKind::Focus => Box::new(make_focus(mesh, focus, skeletons)?),
    })
}

/// The focus DoI: `focus` as `NAME` or `NAME=VALUE`; `skeletons` as `NAME=FILE` when `NAME` is
/// one of the focus objects, otherwise `FILE` for every object without its own.
fn make_focus(mesh: &Mesh, focus: &[String], skeletons: &[String]) -> Result<Focus, DoiSetupError> {
    let mut specs = focus
        .iter()
        .map(|f| FocusSpec::parse(f))
        .collect::<Result<Vec<_>, _>>()
        .map_err(DoiSetupError::Focus)?;
    let mut shared = None;
    for s in skeletons {
        let read =
            |p: &str| read_skeleton(std::path::Path::new(p)).map_err(DoiSetupError::Skeleton);
        match s
            .split_once('=')
            .and_then(|(n, p)| Some((specs.iter().position(|x| x.name == n)?, p)))
        {
            Some((i, path)) => specs[i].skeleton = Some(read(path)?),
            None => shared = Some(read(s)?),
        }
    }
    Focus::new(mesh, &specs, shared, Focus::default_radius(mesh)).map_err(DoiSetupError::Focus)
}

/// Per-face Catmull-Clark depths driven by a DoI instead of the view: the DoI's face values
/// (largest value around each face) above `threshold` (`None`: the DoI's figure value) map
/// linearly onto depths `1..=max_depth`.
pub fn doi_face_depths(
    doi: &dyn Doi,
    mesh: &Mesh,
    camera: Camera,
    threshold: Option<f32>,
    max_depth: Depth,
) -> Result<Vec<u8>, DoiError> {
    let ctx = DoiContext::with_camera(camera);
    let (mut scratch, mut values) = (Vec::new(), Vec::new());
    subdiv_doi::face_values(doi, mesh, &ctx, Aggregate::Max, &mut scratch, &mut values)?;
    let t = threshold.unwrap_or(doi.default_threshold());
    Ok(subdiv_depth::depths_from_face_values(&values, t, max_depth))
}

/// A DoI-driven adaptive Loop refinement ready to run for a camera: the triangle cage (split
/// when asked to), the DoI and the refinement options.
pub struct DoiSetup {
    /// The triangle mesh refined.
    pub cage: Mesh,
    /// The Degree-of-Interest function.
    pub doi: Box<dyn Doi>,
    /// The DoI chosen.
    pub kind: DoiKind,
    /// Haptic interaction point, snapped to the closest point of the cage's surface.
    pub hip: Option<Vec3>,
    /// Threshold (the default filled in), steps and aggregation.
    pub opts: RefineOptions,
}

impl DoiSetup {
    /// Checks the options against each other and against `cage`, and builds the DoI.
    pub fn new(cage: Mesh, o: &DoiOptions) -> Result<DoiSetup, DoiSetupError> {
        check_doi_options(Some(o.kind), &o.focus, &o.skeletons, o.hip)?;
        let cage = if o.triangulate {
            triangulate(&cage).map_err(DoiSetupError::Triangulate)?
        } else if let Err(MeshError::NotTriangles { face, size }) = cage.check_triangles() {
            return Err(DoiSetupError::NotTriangles {
                face,
                size: size as usize,
            });
        } else {
            cage
        };
        let doi = make_doi(o.kind, &cage, &o.focus, &o.skeletons, o.hip.is_some())?;
        let threshold = o.threshold.unwrap_or(doi.default_threshold());
        if !threshold.is_finite() {
            return Err(DoiSetupError::Threshold);
        }
        // The haptic interaction point touches the surface: snap it to the closest cage point.
        let hip = o
            .hip
            .map(|p| closest_surface_point(&cage, p).map_or(p, |(_, q)| q));
        Ok(DoiSetup {
            cage,
            doi,
            kind: o.kind,
            hip,
            opts: RefineOptions {
                threshold,
                steps: o.steps,
                aggregate: o.aggregate,
                balance: o.balance,
            },
        })
    }

    /// Bounds of the cage.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.cage.bounds()
    }

    /// Whether the refinement depends on the camera.
    pub fn is_view_dependent(&self) -> bool {
        self.doi.is_view_dependent()
    }

    /// The evaluation context for `camera`.
    pub fn context(&self, camera: Camera) -> DoiContext {
        DoiContext {
            camera: Some(camera),
            hip: self.hip,
            ..Default::default()
        }
    }

    /// Refines the cage for `camera`.
    pub fn run(&self, camera: Camera) -> Result<Refined, RefineError> {
        refine_adaptive(
            &self.cage,
            self.doi.as_ref(),
            &self.context(camera),
            &self.opts,
        )
    }

    /// Refines for `camera`: the refined mesh as a scene (drawn as refined, not pushed to the
    /// limit, with vertex normals) with each vertex's largest DoI over its faces as the scalar.
    pub fn scene(&self, camera: &Camera) -> Result<Scene, DoiSetupError> {
        let r = self.run(*camera).map_err(DoiSetupError::Refine)?;
        let limit = self.refined_surface(&r, camera)?;
        Ok(Scene::from_limit(&limit))
    }

    /// [`DoiSetup::scene`] showing the refined primvar `name` ([`Scene::from_limit_showing`]).
    pub fn scene_showing(
        &self,
        camera: &Camera,
        name: &str,
    ) -> Result<(Scene, crate::PrimvarDisplay), DoiSetupError> {
        let r = self.run(*camera).map_err(DoiSetupError::Refine)?;
        let limit = self.refined_surface(&r, camera)?;
        Scene::from_limit_showing(limit, name).map_err(DoiSetupError::Scene)
    }

    /// A refinement of this set-up for `camera` as a surface to draw or write: the refined mesh
    /// (not pushed to the limit) with vertex normals, one-sided normals along sharp edges, its
    /// refined UVs when the cage has UVs, and each vertex's largest DoI over its faces as its
    /// scalar.
    pub fn refined_surface(
        &self,
        r: &Refined,
        camera: &Camera,
    ) -> Result<LimitMesh, DoiSetupError> {
        let m = &r.mesh.mesh;
        let ctx = self.context(*camera);
        let (mut scratch, mut values) = (Vec::new(), Vec::new());
        let (doi, agg) = (self.doi.as_ref(), self.opts.aggregate);
        subdiv_doi::face_values(doi, m, &ctx, agg, &mut scratch, &mut values)?;
        let mut scalar = vec![f32::NEG_INFINITY; m.num_vertices()];
        for f in m.faces() {
            let v = values[f.idx()];
            for x in m.face_vertices(f) {
                scalar[x.idx()] = scalar[x.idx()].max(if v.is_finite() { v } else { 0.0 });
            }
        }
        for s in &mut scalar {
            if !s.is_finite() {
                *s = 0.0;
            }
        }
        let normals = subdiv_mesh::vertex_normals(m);
        let (offsets, indices) = m.face_lists();
        // The refined values of the cage's UVs (not limit values: the mesh is not pushed to
        // the limit), one per face corner.
        let (uvs, uv_indices) = m.uv().map_or((Vec::new(), Vec::new()), |fv| {
            let uvs = fv.values.iter().map(|t| t.to_array()).collect();
            (uvs, fv.indices.clone())
        });
        let mut limit = LimitMesh::new(
            m.positions().iter().map(|p| p.to_array()).collect(),
            normals.iter().map(|n| n.to_array()).collect(),
            offsets.to_vec(),
            indices.iter().map(|v| v.0).collect(),
        )?;
        // Sharp edges shade as creases: each sector of a vertex its own normal.
        limit.set_corner_normals(subdiv_mesh::sector_corner_normals(m, &normals))?;
        limit.set_uvs(uvs, uv_indices)?;
        limit.set_scalar(VertexScalar::Doi, scalar)?;
        // The refined primvars (refined values, as the UVs): per vertex, or per face corner.
        let corner_face: Vec<usize> = (0..offsets.len() - 1)
            .flat_map(|f| std::iter::repeat_n(f, (offsets[f + 1] - offsets[f]) as usize))
            .collect();
        for p in m.primvars() {
            let indices: Vec<u32> = match p.interpolation {
                PrimvarInterpolation::Constant => vec![0; m.num_vertices()],
                PrimvarInterpolation::Vertex
                | PrimvarInterpolation::Varying
                | PrimvarInterpolation::FaceVarying => p.indices.clone(),
                PrimvarInterpolation::Uniform => {
                    corner_face.iter().map(|&f| p.indices[f]).collect()
                }
            };
            let per_vertex = matches!(
                p.interpolation,
                PrimvarInterpolation::Constant
                    | PrimvarInterpolation::Vertex
                    | PrimvarInterpolation::Varying
            );
            let channel = if per_vertex {
                let values = indices.iter().flat_map(|&i| {
                    let at = i as usize * p.width;
                    p.values[at..at + p.width].to_vec()
                });
                LimitChannel {
                    name: p.name.clone(),
                    width: p.width,
                    values: values.collect(),
                    indices: Vec::new(),
                }
            } else {
                LimitChannel {
                    name: p.name.clone(),
                    width: p.width,
                    values: p.values.clone(),
                    indices,
                }
            };
            limit.push_channel(channel)?;
        }
        Ok(limit)
    }

    /// One line about a refinement of this set-up to `triangles` triangles:
    /// `NAME DoI, threshold T, S steps: CAGE -> triangles triangles`.
    pub fn summary(&self, triangles: usize) -> String {
        format!(
            "{} DoI, threshold {}, {} steps: {} -> {} triangles",
            self.kind.name(),
            self.opts.threshold,
            self.opts.steps,
            self.cage.num_faces(),
            triangles
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::parse_obj;

    /// The unit cube in three groups: `bottom` (face 0), `top` (face 1) and `sides`.
    fn cube() -> Mesh {
        let obj = subdiv_test_support::grouped_cube_obj();
        Mesh::from_soup(&parse_obj(&obj).unwrap()).unwrap()
    }

    #[test]
    fn options_the_doi_would_ignore_are_refused() {
        let focus = vec![String::from("top")];
        let e = check_doi_options(Some(DoiKind::Dihedral), &focus, &[], None).unwrap_err();
        assert!(matches!(e, DoiSetupError::FocusWithoutFocusDoi));
        let hip = Some(Vec3::ZERO);
        let e = check_doi_options(None, &[], &[], hip).unwrap_err();
        assert!(matches!(e, DoiSetupError::HipWithoutHapticDoi));
        check_doi_options(Some(DoiKind::Haptic), &[], &[], hip).unwrap();
        check_doi_options(Some(DoiKind::Focus), &focus, &[], None).unwrap();
    }

    #[test]
    fn quads_need_triangulation_and_focus_names_groups() {
        let dihedral = DoiOptions::new(DoiKind::Dihedral);
        let e = DoiSetup::new(cube(), &dihedral).err().unwrap();
        assert!(
            matches!(e, DoiSetupError::NotTriangles { face: 0, size: 4 }),
            "{e}"
        );
        let mut focus = DoiOptions {
            triangulate: true,
            focus: vec!["lid".into()],
            ..DoiOptions::new(DoiKind::Focus)
        };
        let e = DoiSetup::new(cube(), &focus).err().unwrap();
        let cause = std::error::Error::source(&e).unwrap().to_string();
        assert!(cause.contains("available: bottom, top, sides"), "{cause}");
        focus.focus = vec!["top".into()];
        focus.threshold = Some(f32::NAN);
        let e = DoiSetup::new(cube(), &focus).err().unwrap();
        assert!(matches!(e, DoiSetupError::Threshold));
    }

    #[test]
    fn scene_carries_the_doi_per_vertex() {
        let o = DoiOptions {
            triangulate: true,
            steps: 2,
            ..DoiOptions::new(DoiKind::Dihedral)
        };
        let setup = DoiSetup::new(cube(), &o).unwrap();
        assert_eq!(setup.cage.num_faces(), 12);
        assert!(!setup.is_view_dependent());
        let (lo, hi) = setup.bounds();
        let camera = Camera::eye_relative(lo, hi, Vec3::new(0.8, 0.5, 2.2), 45.0, 64, 48);
        let scene = setup.scene(&camera).unwrap();
        assert!(scene.faces() > 12 && scene.faces() <= 12 * 16);
        let (kind, scalars) = scene.surface().scalar().unwrap();
        assert_eq!(kind, VertexScalar::Doi);
        assert!(scalars.iter().all(|s| s.is_finite()) && scalars.iter().any(|&s| s > 0.0));
        let line = setup.summary(scene.faces());
        assert!(
            line.starts_with("dihedral DoI, threshold 30, 2 steps: 12 -> "),
            "{line}"
        );
        let depths = doi_face_depths(setup.doi.as_ref(), &setup.cage, camera, None, 3).unwrap();
        assert_eq!(depths.len(), 12);
        assert!(depths.iter().all(|&d| d <= 3));
    }
}
