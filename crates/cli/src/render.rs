//! `subdiv render`: a headless Vulkan render of the limit surface to PNG (and EXR).
//!
//! Also the pieces `subdiv view` shares: surface and style flags, the tessellated scene with its
//! per-vertex scalars, silhouette extraction, and the camera conversion.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, bail};
use glam::Vec3;
use subdiv_mesh::{Camera, Mesh, parse_obj};
use subdiv_rules::{LimitMesh, Scheme};
use subdiv::DynamicSubdivision;
use subdiv_stitch::FrameGeometry;
use subdiv_vk::{OrbitCamera, OwnedMesh, RenderOptions, Renderer, Shading, View};

use crate::camera_args::{CameraArgs, parse_vec3};
use crate::tessellate::AdaptiveArgs;

/// Which surface to tessellate: the flags `render` and `view` share.
#[derive(clap::Args, Debug, Clone)]
pub struct SurfaceArgs {
    /// Input cage (OBJ with optional OpenSubdiv tags).
    #[arg(required_unless_present = "scene")]
    pub input: Option<PathBuf>,
    /// A built-in scene instead of an input file: helmet40 (paper Fig. 12: 40 instances of
    /// catmark_helmet on an 8x5 grid).
    #[arg(long, value_parser = ["helmet40"], conflicts_with = "input")]
    pub scene: Option<String>,
    /// Subdivision scheme.
    #[arg(long, default_value = "catmull-clark", value_parser = ["catmull-clark", "loop"])]
    pub scheme: String,
    /// Uniform subdivision depth. Without it, a camera (--eye or --eye-relative) makes the
    /// Catmull-Clark tessellation adaptive; otherwise the default is depth 3.
    #[arg(long)]
    pub depth: Option<u32>,
    /// Give each extra fan of faces at a non-manifold vertex its own vertex instead of refusing.
    #[arg(long)]
    pub split_nonmanifold: bool,
    #[command(flatten)]
    pub adaptive: AdaptiveArgs,
    /// Choose the adaptive depths (and back-face culling) with a second camera at bbox centre +
    /// (X,Y,Z) * bbox radius, while the image is seen from the first (paper Fig. 8); its frustum
    /// is drawn as lines.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub cull_camera_eye_relative: Option<Vec3>,
    /// Fixed per-face depths instead of view-dependent ones: a comma list (one per cage face)
    /// or a file of such numbers (for figures of depth transitions).
    #[arg(long, hide = true)]
    pub face_depths: Option<String>,
    /// Render the DoI-driven adaptive Loop mesh of `subdiv refine` (Isenberg et al. 2003) for
    /// this Degree-of-Interest function, seen from the camera (`--shading doi` colours it by the
    /// DoI).
    #[arg(long, value_parser = ["view-angle", "silhouette", "dihedral", "haptic", "focus"])]
    pub doi: Option<String>,
    /// DoI threshold (default: the paper's figure value).
    #[arg(long, allow_hyphen_values = true)]
    pub threshold: Option<f32>,
    /// Adaptive Loop steps for --doi.
    #[arg(long, default_value_t = 3)]
    pub steps: u32,
    /// Split quads and n-gons into triangles first (for --doi on a Catmull-Clark cage).
    #[arg(long)]
    pub triangulate: bool,
    /// Focus objects (OBJ group names) for --doi focus; repeatable.
    #[arg(long = "focus", value_name = "NAME")]
    pub focus: Vec<String>,
    /// Skeleton polyline for --doi focus (points as `v X Y Z` or `X Y Z` lines).
    #[arg(long)]
    pub skeleton: Option<PathBuf>,
    /// Haptic interaction point for --doi haptic: refine the triangle closest to it and its
    /// one-neighbourhood instead of using the Clough-Tocher G1 error.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub hip: Option<Vec3>,
    /// How edge or vertex DoI values become face values (--doi).
    #[arg(long, default_value = "max", value_parser = ["max", "avg", "min"])]
    pub aggregate: String,
}

/// Uniform depth when neither `--depth` nor an adaptive camera is given.
pub const DEFAULT_DEPTH: u32 = 3;

/// Cage file of the built-in `helmet40` scene's model.
const HELMET_OBJ: &str = include_str!("../../../fixtures/reference/shapes/catmark_helmet.obj");

/// The test scene of the paper's Fig. 12: 40 instances of `catmark_helmet` (58 faces each) on an
/// 8 x 5 grid in the XZ plane, 1.25 model widths apart.
pub fn helmet40() -> anyhow::Result<Mesh> {
    let soup = parse_obj(HELMET_OBJ).context("embedded catmark_helmet")?;
    let (lo, hi) = soup.positions.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let ext = hi - lo;
    let step = 1.25 * ext.x.max(ext.z);
    let offsets: Vec<Vec3> = (0..5)
        .flat_map(|row| {
            (0..8).map(move |col| {
                Vec3::new((col as f32 - 3.5) * step, 0.0, (row as f32 - 2.0) * step)
            })
        })
        .collect();
    Mesh::from_soup(&soup.instanced(&offsets)).context("helmet40 scene")
}

impl SurfaceArgs {
    /// Refuses DoI options without the DoI that uses them (as `subdiv refine` does).
    pub fn check_doi_options(&self) -> anyhow::Result<()> {
        crate::refine::check_doi_options(
            self.doi.as_deref(),
            &self.focus,
            self.skeleton.as_deref(),
            self.hip,
        )?;
        if self.doi.is_none() && self.aggregate != "max" {
            bail!("--aggregate needs --doi NAME");
        }
        Ok(())
    }

    /// The input's name for messages.
    pub fn label(&self) -> String {
        match (&self.scene, &self.input) {
            (Some(s), _) => format!("scene {s}"),
            (None, Some(p)) => p.display().to_string(),
            (None, None) => String::from("(no input)"),
        }
    }

    /// Reads the cage (or builds the built-in scene).
    pub fn load_cage(&self) -> anyhow::Result<Mesh> {
        match (&self.scene, &self.input) {
            (Some(_), _) => helmet40(),
            (None, Some(p)) => crate::load::load_mesh(p, self.split_nonmanifold),
            (None, None) => bail!("give an input cage or --scene helmet40"),
        }
    }

    /// Whether these flags ask for the adaptive tessellation: Catmull-Clark, no `--depth`, and a
    /// camera. Adaptive-only flags without it are refused.
    pub fn is_adaptive(&self, camera: &CameraArgs) -> anyhow::Result<bool> {
        let adaptive =
            self.depth.is_none() && camera.has_camera() && self.scheme == "catmull-clark";
        if !adaptive && (self.cull_camera_eye_relative.is_some() || self.face_depths.is_some()) {
            bail!(
                "--cull-camera-eye-relative and --face-depths need the adaptive tessellation: \
                 --scheme catmull-clark, a camera (--eye or --eye-relative) and no --depth"
            );
        }
        Ok(adaptive)
    }

    /// The adaptive node for `mesh` with the adaptive flags (fan method, fixed face depths).
    pub fn adaptive_node(&self, mesh: Mesh) -> anyhow::Result<DynamicSubdivision> {
        let faces = mesh.num_faces();
        let mut node = self.adaptive.node(mesh).with_context(|| self.label())?;
        if let Some(spec) = &self.face_depths {
            let depths = parse_face_depths(spec, self.adaptive.max_depth)?;
            if depths.len() != faces {
                bail!(
                    "--face-depths has {} depths, the cage has {faces} faces",
                    depths.len()
                );
            }
            node.set_face_depths(Some(depths))?;
        }
        Ok(node)
    }

    /// The culling camera of `--cull-camera-eye-relative` (else `camera`).
    pub fn cull_camera(
        &self,
        camera_args: &CameraArgs,
        camera: &Camera,
        lo: Vec3,
        hi: Vec3,
    ) -> Camera {
        match self.cull_camera_eye_relative {
            Some(rel) => CameraArgs {
                eye: None,
                target: None,
                eye_relative: Some(rel),
                ..camera_args.clone()
            }
            .camera(lo, hi),
            None => *camera,
        }
    }
}

/// Parses `--face-depths`: a comma/whitespace list of depths, or a file holding one.
fn parse_face_depths(spec: &str, max_depth: u8) -> anyhow::Result<Vec<u8>> {
    let text = if spec
        .chars()
        .all(|c| c.is_ascii_digit() || c == ',' || c.is_whitespace())
    {
        spec.to_string()
    } else {
        std::fs::read_to_string(spec)
            .with_context(|| format!("--face-depths: cannot read '{spec}'"))?
    };
    let mut out = Vec::new();
    for t in text
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
    {
        let d: u8 = t
            .parse()
            .ok()
            .filter(|&d| d <= max_depth)
            .with_context(|| {
                format!("--face-depths: '{t}' is not a depth between 0 and --max-depth {max_depth}")
            })?;
        out.push(d);
    }
    if out.is_empty() {
        bail!("--face-depths: no depths given");
    }
    Ok(out)
}

/// The triangles of an adaptive frame as a [`LimitMesh`] (referenced vertices only) and the
/// per-vertex depths of their patches.
pub fn frame_limit(g: &FrameGeometry) -> (LimitMesh, Vec<f32>) {
    let mut map = vec![u32::MAX; g.positions.len()];
    let mut limit = LimitMesh {
        positions: Vec::new(),
        normals: Vec::new(),
        face_offsets: (0..=g.indices.len() as u32 / 3).map(|i| i * 3).collect(),
        face_indices: Vec::with_capacity(g.indices.len()),
    };
    let mut depths = Vec::new();
    for &i in &g.indices {
        let m = &mut map[i as usize];
        if *m == u32::MAX {
            *m = limit.positions.len() as u32;
            limit.positions.push(g.positions[i as usize]);
            limit.normals.push(g.normals[i as usize]);
            depths.push(g.vertex_depth[i as usize]);
        }
        limit.face_indices.push(*m);
    }
    (limit, depths)
}

/// `0:a 1:b ...` patches (cage faces) per depth, with the culled count.
pub fn depth_histogram(g: &FrameGeometry) -> String {
    let per: Vec<String> = g
        .units_per_depth()
        .iter()
        .enumerate()
        .map(|(d, n)| format!("{d}:{n}"))
        .collect();
    let culled = g.unit_depth.iter().filter(|&&d| d == u8::MAX).count();
    let mut s = per.join(" ");
    if culled > 0 {
        s.push_str(&format!(" culled:{culled}"));
    }
    s
}

/// How to draw it: the flags `render` and `view` share.
#[derive(clap::Args, Debug, Clone)]
pub struct StyleArgs {
    /// Surface shading: smooth (limit normals), flat (face normals), wire (hidden-line
    /// wireframe), depth (subdivision depth colours), doi (degree-of-interest heat map).
    #[arg(long, default_value = "smooth", value_parser = ["smooth", "flat", "wire", "depth", "doi"])]
    pub shading: String,
    /// Draw the tessellation's edges over the shaded surface.
    #[arg(long)]
    pub wire_overlay: bool,
    /// Draw the silhouette edges (between front- and back-facing faces) as lines.
    #[arg(long)]
    pub silhouettes: bool,
    /// Set when DoI values are available (`--doi`); not a flag.
    #[arg(skip)]
    pub doi_values: bool,
}

impl StyleArgs {
    /// The renderer options these flags describe.
    pub fn render_options(&self) -> anyhow::Result<RenderOptions> {
        let shading = Shading::from_name(&self.shading)
            .with_context(|| format!("unknown shading '{}'", self.shading))?;
        if shading == Shading::Doi && !self.doi_values {
            bail!("--shading doi needs --doi NAME (degree-of-interest values to colour by)");
        }
        Ok(RenderOptions {
            shading,
            wire_overlay: self.wire_overlay,
            show_lines: self.silhouettes,
            // Depth-tested like the wireframe (surfaces are drawn with a depth bias), so
            // silhouettes behind the surface stay hidden.
            lines_on_top: false,
            ..RenderOptions::default()
        })
    }
}

/// `subdiv render` arguments.
#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    #[command(flatten)]
    pub surface: SurfaceArgs,
    #[command(flatten)]
    pub camera: CameraArgs,
    #[command(flatten)]
    pub style: StyleArgs,
    /// Output PNG.
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
    /// Also write linear depth, normals and the per-vertex scalar (subdivision depth) as EXR.
    #[arg(long)]
    pub exr: Option<PathBuf>,
}

/// A tessellated surface ready to draw: the render mesh (with per-vertex scalars) and what
/// silhouette extraction needs.
pub struct Scene {
    /// Positions, limit normals, triangles, polygon edges and scalars (no lines).
    pub mesh: OwnedMesh,
    /// Faces per edge, face normals and centres, for silhouettes.
    pub silhouettes: Silhouettes,
    /// Polygons of the tessellation.
    pub faces: usize,
}

impl Scene {
    /// Loads, tessellates uniformly and packs the surface `args` names.
    pub fn load(args: &SurfaceArgs) -> anyhow::Result<Scene> {
        let scheme: Scheme = args.scheme.parse().map_err(anyhow::Error::msg)?;
        let cage = args.load_cage()?;
        let depth = args.depth.unwrap_or(DEFAULT_DEPTH);
        let limit = crate::tessellate::uniform(&cage, scheme, depth)
            .map_err(|e| anyhow::anyhow!("{}: {e}", args.label()))?;
        if limit.num_faces() == 0 {
            bail!("{}: the limit surface has no faces to draw", args.label());
        }
        // Uniform tessellation: every vertex sits at the same subdivision depth. The adaptive
        // tessellator will hand per-vertex depths of its patches to `from_limit` instead.
        let depths = vec![depth as f32; limit.positions.len()];
        Ok(Scene::from_limit(limit, depths))
    }

    /// A scene from a tessellation and one subdivision depth per vertex (the scalar that
    /// `--shading depth` colours).
    pub fn from_limit(limit: LimitMesh, vertex_depths: Vec<f32>) -> Scene {
        let silhouettes = Silhouettes::new(&limit);
        let faces = limit.num_faces();
        let mut mesh = OwnedMesh {
            triangles: Vec::new(),
            edges: Some(limit.edges()),
            scalars: Some(vertex_depths),
            lines: None,
            positions: limit.positions.clone(),
            normals: limit.normals.clone(),
        };
        split_crease_normals(&limit, &mut mesh);
        Scene {
            mesh,
            silhouettes,
            faces,
        }
    }

    /// Axis-aligned bounds of the tessellation.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.mesh.positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(Vec3::from(*p)), hi.max(Vec3::from(*p))),
        )
    }
}

/// Corners whose limit normal is further than this from their face's normal (cosine) get the
/// face normal instead: 45°.
const CREASE_NORMAL_COS: f32 = std::f32::consts::FRAC_1_SQRT_2;

/// Triangulates `limit` into `mesh` (a fan per polygon) with split normals along creases.
///
/// A vertex on a sharp crease has one limit normal but two one-sided surface normals; shading
/// the faces on both sides with that one normal smears the crease. A face corner whose limit
/// normal deviates by more than 45° from the face's normal gets its own vertex with the face
/// normal (position and scalar copied; edges and silhouettes keep the shared vertices).
fn split_crease_normals(limit: &LimitMesh, mesh: &mut OwnedMesh) {
    let p = |i: u32| Vec3::from(limit.positions[i as usize]);
    let mut corner = Vec::new();
    for f in 0..limit.num_faces() {
        let vs = limit.face(f);
        let n: Vec3 = (0..vs.len())
            .map(|k| p(vs[k]).cross(p(vs[(k + 1) % vs.len()])))
            .sum();
        let n = n.normalize_or_zero();
        corner.clear();
        for &v in vs {
            let limit_normal = Vec3::from(limit.normals[v as usize]);
            if n == Vec3::ZERO || limit_normal.dot(n) >= CREASE_NORMAL_COS {
                corner.push(v);
            } else {
                corner.push(mesh.positions.len() as u32);
                mesh.positions.push(limit.positions[v as usize]);
                mesh.normals.push(n.to_array());
                if let Some(s) = mesh.scalars.as_mut() {
                    s.push(s[v as usize]);
                }
            }
        }
        for k in 1..corner.len() - 1 {
            mesh.triangles
                .extend_from_slice(&[corner[0], corner[k], corner[k + 1]]);
        }
    }
}

/// Silhouette extraction: an interior edge is a silhouette edge when one of its two faces faces
/// the eye and the other faces away. A face's normal is the mean of its vertices' limit normals
/// (the geometric normal where those cancel).
pub struct Silhouettes {
    /// Interior edges (vertex pairs) and their two faces.
    edges: Vec<([u32; 2], [u32; 2])>,
    face_normal: Vec<Vec3>,
    face_centre: Vec<Vec3>,
}

impl Silhouettes {
    /// Face adjacency and face normals of `limit`.
    pub fn new(limit: &LimitMesh) -> Silhouettes {
        let p = |i: u32| Vec3::from(limit.positions[i as usize]);
        let mut keyed: Vec<([u32; 2], u32)> = Vec::with_capacity(limit.face_indices.len());
        let mut face_normal = Vec::with_capacity(limit.num_faces());
        let mut face_centre = Vec::with_capacity(limit.num_faces());
        for f in 0..limit.num_faces() {
            let vs = limit.face(f);
            let centre = vs.iter().map(|&v| p(v)).sum::<Vec3>() / vs.len() as f32;
            let mut n: Vec3 = vs
                .iter()
                .map(|&v| Vec3::from(limit.normals[v as usize]))
                .sum();
            if n.length_squared() < 1e-12 {
                // Newell's normal of the polygon.
                n = (0..vs.len())
                    .map(|k| p(vs[k]).cross(p(vs[(k + 1) % vs.len()])))
                    .sum();
            }
            face_normal.push(n.normalize_or_zero());
            face_centre.push(centre);
            for k in 0..vs.len() {
                let (a, b) = (vs[k], vs[(k + 1) % vs.len()]);
                keyed.push(([a.min(b), a.max(b)], f as u32));
            }
        }
        keyed.sort_unstable();
        let mut edges = Vec::with_capacity(keyed.len() / 2);
        let mut i = 0;
        while i < keyed.len() {
            let mut j = i + 1;
            while j < keyed.len() && keyed[j].0 == keyed[i].0 {
                j += 1;
            }
            if j - i == 2 {
                edges.push((keyed[i].0, [keyed[i].1, keyed[i + 1].1]));
            }
            i = j;
        }
        Silhouettes {
            edges,
            face_normal,
            face_centre,
        }
    }

    /// The silhouette edges seen from `eye` as line segments (pairs of endpoints), into `out`.
    pub fn lines_into(&self, positions: &[[f32; 3]], eye: Vec3, out: &mut Vec<[f32; 3]>) {
        out.clear();
        let front =
            |f: u32| self.face_normal[f as usize].dot(eye - self.face_centre[f as usize]) > 0.0;
        for &([a, b], [f, g]) in &self.edges {
            if front(f) != front(g) {
                out.push(positions[a as usize]);
                out.push(positions[b as usize]);
            }
        }
    }
}

/// Half the diagonal of the box `lo..hi` as seen from `target`: the largest distance from
/// `target` to a corner.
fn radius_about(lo: Vec3, hi: Vec3, target: Vec3) -> f32 {
    (0..8)
        .map(|i| {
            let c = Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            );
            (c - target).length()
        })
        .fold(0.0, f32::max)
        .max(1e-6)
}

/// The viewer's orbit camera for `camera` (it orbits about +Y), and whether it reproduces the
/// camera exactly (an up vector along +Y and a view direction that is not vertical). Near and far
/// planes enclose the box `lo..hi`.
pub fn orbit_camera(camera: &Camera, lo: Vec3, hi: Vec3) -> (OrbitCamera, bool) {
    let offset = camera.eye - camera.target;
    let distance = offset.length().max(1e-6);
    let dir = offset / distance;
    let limit = 89f32.to_radians();
    let pitch = dir.y.clamp(-1.0, 1.0).asin();
    let orbit = OrbitCamera {
        target: camera.target,
        distance,
        yaw: dir.x.atan2(dir.z),
        pitch: pitch.clamp(-limit, limit),
        fov_y: camera.fov_y_deg.to_radians(),
        radius: radius_about(lo, hi, camera.target),
    };
    let up = camera.up.normalize_or_zero();
    let exact = up.cross(Vec3::Y).length() < 1e-6 && up.y > 0.0 && pitch.abs() <= limit;
    (orbit, exact)
}

/// The renderer's view for `camera` with near and far planes around the box `lo..hi`. Cameras the
/// viewer can orbit go through [`OrbitCamera`], so `subdiv view` shows exactly what `subdiv
/// render` draws.
pub fn view_for(camera: &Camera, lo: Vec3, hi: Vec3) -> View {
    let (orbit, exact) = orbit_camera(camera, lo, hi);
    if exact {
        return orbit.view(camera.aspect());
    }
    let distance = orbit.distance;
    let near = (distance - 2.0 * orbit.radius)
        .max(distance * 1e-3)
        .max(1e-6);
    let far = (distance + 2.0 * orbit.radius).max(near * 2.0);
    View {
        view: camera.view_matrix(),
        proj: View::perspective(camera.fov_y_deg.to_radians(), camera.aspect(), near, far),
        eye: camera.eye,
    }
}

pub fn run(a: &RenderArgs) -> anyhow::Result<ExitCode> {
    a.surface.check_doi_options()?;
    if a.surface.doi.is_some() {
        return run_doi(a);
    }
    if a.surface.is_adaptive(&a.camera)? {
        return run_adaptive(a);
    }
    let options = a.style.render_options()?;
    let t0 = Instant::now();
    let mut scene = Scene::load(&a.surface)?;
    let tessellate_ms = t0.elapsed().as_secs_f64() * 1e3;
    let (lo, hi) = scene.bounds();
    let camera = a.camera.camera(lo, hi);
    let view = view_for(&camera, lo, hi);
    if a.style.silhouettes {
        let mut lines = Vec::new();
        scene
            .silhouettes
            .lines_into(&scene.mesh.positions, view.eye, &mut lines);
        scene.mesh.lines = Some(lines);
    }
    let note = format!(
        "{}, depth {}",
        a.surface.scheme,
        a.surface.depth.unwrap_or(DEFAULT_DEPTH)
    );
    draw_and_report(
        a,
        &scene,
        &view,
        [camera.width, camera.height],
        &options,
        &note,
        tessellate_ms,
    )
}

/// A DoI-driven adaptive Loop refinement ready to run for a camera (the meshes of Isenberg et
/// al., Figs. 3, 4, 9, 10): the cage (triangulated with `--triangulate`), the DoI and the
/// refinement options of the surface flags. Shared by `render --doi` and `view --doi`.
pub struct DoiSetup {
    refinement: crate::refine::DoiRefinement,
    name: String,
}

impl DoiSetup {
    /// Loads the cage and builds the DoI the surface flags name (`--doi` must be given).
    pub fn new(surface: &SurfaceArgs) -> anyhow::Result<DoiSetup> {
        surface.check_doi_options()?;
        let name = surface.doi.clone().context("--doi NAME is needed")?;
        let refinement = crate::refine::DoiRefinement::new(
            surface.load_cage()?,
            &surface.label(),
            &crate::refine::DoiFlags {
                doi: &name,
                threshold: surface.threshold,
                steps: surface.steps,
                aggregate: &surface.aggregate,
                triangulate: surface.triangulate,
                focus: &surface.focus,
                skeleton: surface.skeleton.as_deref(),
                hip: surface.hip,
            },
        )?;
        Ok(DoiSetup { refinement, name })
    }

    /// Bounds of the cage.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.refinement.cage.bounds()
    }

    /// Whether the refinement depends on the camera.
    pub fn is_view_dependent(&self) -> bool {
        self.refinement.doi.is_view_dependent()
    }

    /// Refines for `camera`: the refined mesh (drawn as refined, not pushed to the limit) with
    /// each vertex's largest DoI over its faces as the scalar, and a one-line summary.
    pub fn scene(&self, camera: &Camera) -> anyhow::Result<(Scene, String)> {
        let r = self.refinement.run(*camera).context("refining")?;
        let m = &r.mesh.mesh;
        let (doi, opts) = (self.refinement.doi.as_ref(), &self.refinement.opts);
        let ctx = self.refinement.context(*camera);
        let (mut scratch, mut values) = (Vec::new(), Vec::new());
        subdiv_doi::face_values(doi, m, &ctx, opts.aggregate, &mut scratch, &mut values)?;
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
        let limit = LimitMesh {
            positions: m.positions().iter().map(|p| p.to_array()).collect(),
            normals: normals.iter().map(|n| n.to_array()).collect(),
            face_offsets: offsets.to_vec(),
            face_indices: indices.iter().map(|v| v.0).collect(),
        };
        let note = format!(
            "{} DoI, threshold {}, {} steps: {} -> {} triangles",
            self.name,
            opts.threshold,
            opts.steps,
            self.refinement.cage.num_faces(),
            m.num_faces()
        );
        Ok((Scene::from_limit(limit, scalar), note))
    }
}

/// `subdiv render --doi`: the DoI-driven adaptive Loop mesh with the DoI as the scalar.
fn run_doi(a: &RenderArgs) -> anyhow::Result<ExitCode> {
    let mut style = a.style.clone();
    style.doi_values = true;
    let options = style.render_options()?;
    let t0 = Instant::now();
    let setup = DoiSetup::new(&a.surface)?;
    let (lo, hi) = setup.bounds();
    let camera = a.camera.camera(lo, hi);
    let (mut scene, note) = setup.scene(&camera).with_context(|| a.surface.label())?;
    let tessellate_ms = t0.elapsed().as_secs_f64() * 1e3;
    let view = view_for(&camera, lo, hi);
    if a.style.silhouettes {
        let mut lines = Vec::new();
        scene
            .silhouettes
            .lines_into(&scene.mesh.positions, view.eye, &mut lines);
        scene.mesh.lines = Some(lines);
    }
    draw_and_report(
        a,
        &scene,
        &view,
        [camera.width, camera.height],
        &options,
        &note,
        tessellate_ms,
    )
}

/// `subdiv render` of the adaptive tessellation: depths (and culling) from the camera, or from
/// the `--cull-camera-eye-relative` camera while the image is seen from the first.
fn run_adaptive(a: &RenderArgs) -> anyhow::Result<ExitCode> {
    let mut options = a.style.render_options()?;
    let t0 = Instant::now();
    let cage = a.surface.load_cage()?;
    let (lo, hi) = cage.bounds();
    let camera = a.camera.camera(lo, hi);
    let cull = a.surface.cull_camera(&a.camera, &camera, lo, hi);
    let mut node = a.surface.adaptive_node(cage)?;
    let g = node.update(&cull, None)?;
    if g.num_triangles() == 0 {
        bail!("{}: nothing to draw (every face culled)", a.surface.label());
    }
    let histogram = depth_histogram(g);
    let (limit, depths) = frame_limit(g);
    let mut scene = Scene::from_limit(limit, depths);
    let tessellate_ms = t0.elapsed().as_secs_f64() * 1e3;
    let view = view_for(&camera, lo, hi);
    let mut lines = Vec::new();
    if a.style.silhouettes {
        scene
            .silhouettes
            .lines_into(&scene.mesh.positions, cull.eye, &mut lines);
    }
    if a.surface.cull_camera_eye_relative.is_some() {
        lines.extend(view_for(&cull, lo, hi).frustum_lines());
        options.show_lines = true;
    }
    if !lines.is_empty() {
        scene.mesh.lines = Some(lines);
    }
    let note = format!(
        "adaptive, max depth {}, patches per depth {histogram}",
        a.surface.adaptive.max_depth
    );
    draw_and_report(
        a,
        &scene,
        &view,
        [camera.width, camera.height],
        &options,
        &note,
        tessellate_ms,
    )
}

/// Renders `scene`, writes the PNG (and EXR) and prints the summary line.
fn draw_and_report(
    a: &RenderArgs,
    scene: &Scene,
    view: &View,
    size: [u32; 2],
    options: &RenderOptions,
    note: &str,
    tessellate_ms: f64,
) -> anyhow::Result<ExitCode> {
    let t1 = Instant::now();
    let mut renderer = Renderer::new()?;
    let mesh = scene.mesh.as_render_mesh();
    let image = if let Some(exr) = &a.exr {
        let (image, aux) = renderer.render_with_aux(&mesh, view, size, options)?;
        subdiv_vk::write_exr(exr, &aux)?;
        image
    } else {
        renderer.render(&mesh, view, size, options)?
    };
    subdiv_vk::write_png(&a.output, &image)?;
    let render_ms = t1.elapsed().as_secs_f64() * 1e3;
    let line_note = match (&scene.mesh.lines, a.style.silhouettes) {
        (Some(l), true) => format!(", {} line segments", l.len() / 2),
        _ => String::new(),
    };
    println!(
        "rendered {}: {} faces, {} triangles{} ({}, {} shading) at {}x{} on {}: \
         tessellated in {:.1} ms, rendered in {:.1} ms -> {}{}",
        a.surface.label(),
        scene.faces,
        mesh.triangle_count(),
        line_note,
        note,
        options.shading.name(),
        size[0],
        size[1],
        renderer.device_name(),
        tessellate_ms,
        render_ms,
        a.output.display(),
        a.exr
            .as_ref()
            .map(|p| format!(" and {}", p.display()))
            .unwrap_or_default(),
    );
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube as six quads (CCW seen from outside) with outward face normals at the corners.
    fn cube() -> LimitMesh {
        let positions: Vec<[f32; 3]> = (0..8)
            .map(|i| {
                [
                    (i & 1) as f32 * 2.0 - 1.0,
                    ((i >> 1) & 1) as f32 * 2.0 - 1.0,
                    ((i >> 2) & 1) as f32 * 2.0 - 1.0,
                ]
            })
            .collect();
        let normals = positions
            .iter()
            .map(|p| (Vec3::from(*p).normalize()).to_array())
            .collect();
        let faces: [[u32; 4]; 6] = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        LimitMesh {
            positions,
            normals,
            face_offsets: (0..=6).map(|i| i * 4).collect(),
            face_indices: faces.iter().flatten().copied().collect(),
        }
    }

    #[test]
    fn cube_silhouette_seen_along_an_axis_is_its_outline() {
        let limit = cube();
        let s = Silhouettes::new(&limit);
        assert_eq!(s.edges.len(), 12);
        let mut lines = Vec::new();
        // Looking down -z: the +z face faces the eye; in perspective the four side faces face
        // away, so the silhouette is the outline of the +z face.
        s.lines_into(&limit.positions, Vec3::new(0.0, 0.0, 100.0), &mut lines);
        assert_eq!(lines.len(), 8, "{lines:?}");
        assert!(lines.iter().all(|p| p[2] == 1.0));
        // Seen from a corner direction, three faces face the eye: six silhouette edges.
        s.lines_into(&limit.positions, Vec3::new(10.0, 11.0, 12.0), &mut lines);
        assert_eq!(lines.len(), 12);
    }

    #[test]
    fn crease_corners_get_face_normals() {
        // The cube's corner normals are 54.7° off every face: all 24 corners are split.
        let limit = cube();
        let scene = Scene::from_limit(limit.clone(), vec![1.0; 8]);
        let m = &scene.mesh;
        assert_eq!(m.positions.len(), 8 + 24);
        assert_eq!(m.triangles.len(), 6 * 2 * 3);
        assert!(m.triangles.iter().all(|&i| i >= 8));
        for t in m.triangles.chunks(3) {
            let n: Vec<Vec3> = t
                .iter()
                .map(|&i| Vec3::from(m.normals[i as usize]))
                .collect();
            assert!(
                n[0] == n[1] && n[1] == n[2] && n[0].abs().max_element() == 1.0,
                "{n:?}"
            );
        }
        assert_eq!(m.scalars.as_ref().unwrap().len(), m.positions.len());
        assert_eq!(m.edges.as_ref().unwrap().len(), 12);
        // Normals within 45° of the face normal stay shared: a tilted-normal quad is not split.
        let quad = LimitMesh {
            positions: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
            ],
            normals: vec![
                [0.0, 0.6, 0.8],
                [0.0, 0.0, 1.0],
                [0.6, 0.0, 0.8],
                [0.0, 0.0, 1.0],
            ],
            face_offsets: vec![0, 4],
            face_indices: vec![0, 1, 2, 3],
        };
        let scene = Scene::from_limit(quad, vec![0.0; 4]);
        assert_eq!(scene.mesh.positions.len(), 4);
        assert_eq!(scene.mesh.triangles, [0, 1, 2, 0, 2, 3]);
    }

    #[test]
    fn default_camera_goes_through_the_orbit_camera() {
        let (lo, hi) = (Vec3::splat(-1.0), Vec3::splat(1.0));
        let cam = Camera::eye_relative(lo, hi, Vec3::new(0.8, 0.5, 2.2), 45.0, 320, 240);
        let (orbit, exact) = orbit_camera(&cam, lo, hi);
        assert!(exact);
        assert!((orbit.eye() - cam.eye).length() < 1e-5);
        let view = view_for(&cam, lo, hi);
        assert_eq!(view, orbit.view(320.0 / 240.0));
        // The same view as the camera's own matrix, and the box lies between near and far.
        let m = cam.view_matrix();
        for (a, b) in view.view.to_cols_array().iter().zip(m.to_cols_array()) {
            assert!((a - b).abs() < 1e-5);
        }
        for corner in [lo, hi, Vec3::new(-1.0, 1.0, -1.0)] {
            let ndc = view.view_proj().project_point3(corner);
            assert!(ndc.z > 0.0 && ndc.z < 1.0, "{ndc}");
        }
        // Looking straight down with +Z up is not an orbit view; the camera's matrix is used.
        let top = Camera::eye_relative(lo, hi, Vec3::new(0.0, 3.0, 0.0), 45.0, 320, 240);
        assert!(!orbit_camera(&top, lo, hi).1);
        assert_eq!(view_for(&top, lo, hi).view, top.view_matrix());
    }

    #[test]
    fn doi_shading_is_refused_without_doi_values() {
        let mut style = StyleArgs {
            shading: "doi".into(),
            wire_overlay: false,
            silhouettes: false,
            doi_values: false,
        };
        let e = style.render_options().unwrap_err().to_string();
        assert!(e.contains("--shading doi needs --doi"), "{e}");
        style.doi_values = true;
        assert_eq!(style.render_options().unwrap().shading, Shading::Doi);
        let style = StyleArgs {
            shading: "depth".into(),
            wire_overlay: true,
            silhouettes: true,
            doi_values: false,
        };
        let o = style.render_options().unwrap();
        assert_eq!(o.shading, Shading::Depth);
        assert!(o.wire_overlay && o.show_lines);
    }
}
