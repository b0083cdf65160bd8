//! The flags `render` and `view` share: which surface to tessellate ([`SurfaceArgs`]) and how to
//! draw it ([`StyleArgs`]).

use std::path::PathBuf;

use anyhow::{Context, bail};
use glam::Vec3;
use subdiv::mesh::{Camera, Mesh};
use subdiv::rules::{Depth, Request, Scheme};
use subdiv::vk::{RenderOptions, Shading};
use subdiv::{BuiltinScene, DynamicSubdivision, PrimvarDisplay, Scene, uniform_limit};

use crate::adaptive_args::AdaptiveArgs;
use crate::camera_args::{CameraArgs, parse_vec3};
use crate::choices::{SceneName, SchemeName, ShadingChoice, parse_shading, value_name};
use crate::dicing_args::DicingArgs;
use crate::doi_args::DoiArgs;
use crate::limit_args::LimitArgs;

/// Which surface to tessellate.
#[derive(clap::Args, Debug, Clone)]
#[command(mut_arg("doi", |a| a.help(
    "Render the DoI-driven adaptive Loop mesh of `subdiv refine` (Isenberg et al. 2003) for this \
     Degree-of-Interest function, seen from the camera (`--shading doi` colours it by the DoI)"
)))]
pub struct SurfaceArgs {
    /// Input cage: OBJ with optional OpenSubdiv tags, or USD (.usda, .usdc, .usdz; every Mesh
    /// prim merged unless --prim names one).
    #[arg(required_unless_present = "scene")]
    pub input: Option<PathBuf>,
    /// The USD mesh prim to read (e.g. /World/Body).
    #[arg(long, value_name = "PATH", conflicts_with = "scene")]
    pub prim: Option<String>,
    /// USD: the time code to read the stage at (time samples interpolated as USD does)
    /// [default: default values, else the earliest time samples]; `view` opens an animated
    /// stage paused at this time (space plays).
    #[arg(
        long,
        value_name = "T",
        allow_hyphen_values = true,
        conflicts_with = "scene"
    )]
    pub time: Option<f64>,
    /// A built-in scene instead of an input file: helmet40 (paper Fig. 12: 40 instances of
    /// catmark_helmet on an 8x5 grid).
    #[arg(long, conflicts_with = "input")]
    pub scene: Option<SceneName>,
    /// Subdivision scheme [default: the USD subdivisionScheme, else catmull-clark].
    #[arg(long, value_enum)]
    pub scheme: Option<SchemeName>,
    /// Uniform subdivision depth. Without it, a camera (--eye or --eye-relative) makes the
    /// tessellation adaptive (Catmull-Clark or Loop); otherwise the default is depth 3.
    #[arg(long)]
    pub depth: Option<subdiv::rules::Depth>,
    /// Give each extra fan of faces at a non-manifold vertex its own vertex (the surface opens
    /// there) instead of refining non-manifold cages as OpenSubdiv does.
    #[arg(long)]
    pub split_nonmanifold: bool,
    #[command(flatten)]
    pub adaptive: AdaptiveArgs,
    #[command(flatten)]
    pub dicing: DicingArgs,
    /// Choose the adaptive depths (and back-face culling) with a second camera at bbox centre +
    /// (X,Y,Z) * bbox radius, while the image is seen from the first (paper Fig. 8); its frustum
    /// is drawn as lines.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub cull_camera_eye_relative: Option<Vec3>,
    /// Fixed per-face depths instead of view-dependent ones: a comma list (one per cage face)
    /// or a file of such numbers (for figures of depth transitions).
    #[arg(long, hide = true)]
    pub face_depths: Option<String>,
    #[command(flatten)]
    pub doi: DoiArgs,
    #[command(flatten)]
    pub limit: LimitArgs,
}

/// Uniform depth when neither `--depth` nor an adaptive camera is given.
pub const DEFAULT_DEPTH: subdiv::rules::Depth = 3;

impl SurfaceArgs {
    /// The DoI set-up of `--doi` for the cage, refused beyond `--max-triangles` or this
    /// machine's memory (every face refined at every step).
    pub fn doi_setup(&self) -> anyhow::Result<subdiv::DoiSetup> {
        let label = self.label();
        // The DoI-driven mesh is Loop's red-green refinement (Isenberg et al. 2003): another
        // scheme asked for by name, or declared by a USD stage, would silently be drawn as Loop.
        let (cage, declared) = self.load_cage_declared()?;
        if let Some(s) = declared.filter(|&s| s != Scheme::Loop) {
            let name = SchemeName::from(s);
            let how = if self.scheme.is_some() {
                format!("--scheme {}", value_name(&name))
            } else {
                format!("the stage's subdivisionScheme ({})", value_name(&name))
            };
            bail!(
                "{label}: --doi draws the DoI-driven adaptive Loop mesh (Isenberg et al. 2003): \
                 {how} cannot go with it (pass --scheme loop, or a camera and no --doi for the \
                 {} adaptive tessellation)",
                value_name(&name)
            );
        }
        let setup = self.doi.setup(cage, &label)?;
        let steps = self.doi.steps;
        self.limit
            .check(&setup.cage, Request::Refine { steps }, &label)?;
        Ok(setup)
    }

    /// Refuses DoI options without the DoI that uses them (as `subdiv refine` does).
    pub fn check_doi_options(&self) -> anyhow::Result<()> {
        self.doi.check()
    }

    /// The input's name for messages.
    pub fn label(&self) -> String {
        match (&self.scene, &self.input) {
            (Some(s), _) => format!("scene {}", value_name(s)),
            (None, Some(p)) => p.display().to_string(),
            (None, None) => String::from("(no input)"),
        }
    }

    /// Reads the cage (or builds the built-in scene) and the scheme named for it: `--scheme`,
    /// else a USD stage's `subdivisionScheme` (`None` where neither names one).
    pub fn load_cage_declared(&self) -> anyhow::Result<(Mesh, Option<Scheme>)> {
        match (&self.scene, &self.input) {
            (Some(s), _) => Ok((BuiltinScene::from(*s).cage()?, self.scheme.map(Into::into))),
            (None, Some(p)) => {
                let cage = crate::load::load_cage(
                    p,
                    self.split_nonmanifold,
                    self.prim.as_deref(),
                    self.time,
                )?;
                let declared = match (self.scheme, cage.scheme) {
                    (None, None) => None,
                    (requested, _) => Some(crate::load::cage_scheme(
                        p,
                        &cage,
                        requested.map(Into::into),
                    )?),
                };
                Ok((cage.mesh, declared))
            }
            (None, None) => bail!("give an input cage or --scene helmet40"),
        }
    }

    /// Reads the cage (or builds the built-in scene) and the scheme to subdivide it with:
    /// `--scheme`, else a USD stage's `subdivisionScheme`, else Catmull-Clark.
    pub fn load_cage_scheme(&self) -> anyhow::Result<(Mesh, Scheme)> {
        let (cage, declared) = self.load_cage_declared()?;
        Ok((cage, declared.unwrap_or(Scheme::CatmullClark)))
    }

    /// The uniform depth (`--depth`, else [`DEFAULT_DEPTH`]).
    pub fn uniform_depth(&self) -> subdiv::rules::Depth {
        self.depth.unwrap_or(DEFAULT_DEPTH)
    }

    /// Loads the cage and tessellates it uniformly; returns the scene, its scheme and the cage
    /// (what its views are framed on: [`subdiv::framing_box`]).
    pub fn uniform_scene(&self) -> anyhow::Result<(Scene, SchemeName, Mesh)> {
        let (scene, _, scheme, cage) = self.uniform_scene_showing(None)?;
        Ok((scene, scheme, cage))
    }

    /// [`SurfaceArgs::uniform_scene`], showing the cage's primvar `primvar` when given (and how
    /// it is shown).
    pub fn uniform_scene_showing(
        &self,
        primvar: Option<&str>,
    ) -> anyhow::Result<(Scene, Option<PrimvarDisplay>, SchemeName, Mesh)> {
        let (cage, scheme) = self.load_cage_scheme()?;
        let depth = self.uniform_depth();
        self.limit
            .check(&cage, Request::Uniform { scheme, depth }, &self.label())?;
        let spinner = crate::progress::spinner(format!("tessellating at depth {depth}"));
        let scene = match primvar {
            None => Scene::uniform(&cage, scheme, depth).map(|s| (s, None)),
            Some(name) => uniform_limit(&cage, scheme, depth)
                .and_then(|limit| Scene::show_primvar(limit, depth, name))
                .map(|(s, d)| (s, Some(d))),
        };
        spinner.finish_and_clear();
        let (scene, display) = scene.map_err(|e| anyhow::anyhow!("{}: {e}", self.label()))?;
        Ok((scene, display, scheme.into(), cage))
    }

    /// With `--dicing-rate`: the cage diced for the camera of `camera_args` (tessellated once,
    /// for that camera); `None` without it. Flags that choose another tessellation are refused
    /// next to it.
    /// With `primvar`, the scene shows that primvar of the cage ([`Scene::from_limit_showing`]).
    pub fn dicing_scene(
        &self,
        camera_args: &CameraArgs,
        primvar: Option<&str>,
    ) -> anyhow::Result<Option<Diced>> {
        let Some(d) = self.dicing.dicing()? else {
            return Ok(None);
        };
        let mut given = self.adaptive.given();
        for (on, flag) in [
            (self.depth.is_some(), "--depth"),
            (self.doi.kind().is_some(), "--doi"),
            (self.face_depths.is_some(), "--face-depths"),
            (
                self.cull_camera_eye_relative.is_some(),
                "--cull-camera-eye-relative",
            ),
        ] {
            if on {
                given.push(flag);
            }
        }
        if !given.is_empty() {
            bail!(
                "--dicing-rate chooses the tessellation itself: {} cannot go with it",
                given.join(", ")
            );
        }
        let (cage, scheme) = self.load_cage_scheme()?;
        let camera = camera_args.camera(&cage);
        let label = self.label();
        let eval = subdiv::eval::Evaluator::new(&cage, scheme)
            .map_err(|e| anyhow::anyhow!("{label}: {e}"))?;
        let mut t =
            subdiv::eval::dice(&eval, &camera, &d).map_err(|e| anyhow::anyhow!("{label}: {e}"))?;
        if primvar.is_some() {
            crate::load::dice_primvars(&cage, scheme, &mut t, &label)?;
        }
        let note = format!(
            "{}, dicing rate {} px",
            value_name(&SchemeName::from(scheme)),
            d.rate_px
        );
        let (scene, display) = match primvar {
            None => (Scene::from_limit(&t.surface), None),
            Some(name) => Scene::from_limit_showing(t.surface, name)
                .map(|(s, d)| (s, Some(d)))
                .map_err(|e| anyhow::anyhow!("{label}: {e}"))?,
        };
        Ok(Some(Diced {
            scene,
            display,
            cage,
            note,
        }))
    }

    /// Whether these flags ask for the adaptive tessellation ([`AdaptiveArgs::wants_adaptive`]:
    /// no `--depth`, and a camera or an adaptive flag; the default camera when no camera flag is
    /// given). Adaptive flags that cannot apply are refused.
    pub fn is_adaptive(&self, camera: &CameraArgs) -> anyhow::Result<bool> {
        let mut extra = Vec::new();
        if self.cull_camera_eye_relative.is_some() {
            extra.push("--cull-camera-eye-relative");
        }
        if self.face_depths.is_some() {
            extra.push("--face-depths");
        }
        self.adaptive
            .wants_adaptive(self.depth.is_some(), camera.has_camera(), &extra)
    }

    /// The adaptive node for the `scheme` surface of `mesh` with the adaptive flags (fan
    /// method, fixed face depths).
    pub fn adaptive_node(&self, mesh: Mesh, scheme: Scheme) -> anyhow::Result<DynamicSubdivision> {
        let faces = mesh.num_faces();
        let max_depth = self.adaptive.max_depth();
        self.limit.check(
            &mesh,
            Request::Adaptive { scheme, max_depth },
            &self.label(),
        )?;
        let mut node = self
            .adaptive
            .node(mesh, scheme)
            .with_context(|| self.label())?;
        if let Some(spec) = &self.face_depths {
            let depths = parse_face_depths(spec, self.adaptive.max_depth())?;
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

    /// The culling camera of `--cull-camera-eye-relative` (else `camera`) for `cage`.
    pub fn cull_camera(&self, camera_args: &CameraArgs, camera: &Camera, cage: &Mesh) -> Camera {
        match self.cull_camera_eye_relative {
            Some(rel) => CameraArgs {
                eye: None,
                target: None,
                eye_relative: Some(rel),
                ..camera_args.clone()
            }
            .camera(cage),
            None => *camera,
        }
    }
}

/// A diced surface ready to draw ([`SurfaceArgs::dicing_scene`]).
pub struct Diced {
    /// The surface.
    pub scene: Scene,
    /// How the primvar asked for is shown, if one was.
    pub display: Option<PrimvarDisplay>,
    /// The cage it was diced from (the camera flags frame it).
    pub cage: Mesh,
    /// Scheme and dicing rate, for the report.
    pub note: String,
}

/// Parses `--face-depths`: a comma/whitespace list of depths, or a file holding one.
fn parse_face_depths(spec: &str, max_depth: Depth) -> anyhow::Result<Vec<Depth>> {
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

/// How to draw it.
#[derive(clap::Args, Debug, Clone)]
pub struct StyleArgs {
    /// Surface shading: smooth (limit normals), flat (face normals), wire (hidden-line
    /// wireframe), depth (subdivision depth colours), doi (degree-of-interest heat map), or
    /// primvar:NAME (`render`: the cage's primvar NAME
    /// as colours, its first three floats as red, green and blue, or one float as the heat
    /// map; `subdiv info` lists a cage's primvars).
    #[arg(long, value_name = "SHADING", value_parser = parse_shading, default_value = "smooth")]
    pub shading: ShadingChoice,
    /// Draw the tessellation's edges over the shaded surface.
    #[arg(long)]
    pub wire_overlay: bool,
    /// Draw the silhouette edges (between front- and back-facing faces) as lines.
    #[arg(long)]
    pub silhouettes: bool,
    /// Draw the colour legend of the depth or DoI shading (levels and their colours, or the
    /// heat map with its range) in the top-right corner. The viewer shows it unless --no-hud.
    #[arg(long)]
    pub legend: bool,
    /// Samples per pixel (multisampling: anti-aliased silhouettes, creases and lines) [default:
    /// 4 where the device supports it, else the most it supports below 4]. Depth, normals and
    /// the scalar of `--exr` are point-sampled at pixel centres whatever this is.
    #[arg(long, value_name = "N", value_parser = parse_samples)]
    pub samples: Option<u32>,
    /// Set when DoI values are available (`--doi`); not a flag.
    #[arg(skip)]
    pub doi_values: bool,
}

/// `--samples 1|2|4|8`.
pub fn parse_samples(s: &str) -> Result<u32, String> {
    s.trim()
        .parse::<u32>()
        .ok()
        .filter(|n| subdiv::vk::SAMPLE_COUNTS.contains(n))
        .ok_or_else(|| format!("'{s}' is not a sample count: give 1, 2, 4 or 8"))
}

impl StyleArgs {
    /// The renderer options these flags describe.
    /// The primvar `--shading primvar:NAME` names.
    pub fn primvar(&self) -> Option<&str> {
        match &self.shading {
            ShadingChoice::Primvar(name) => Some(name),
            ShadingChoice::Mode(_) => None,
        }
    }

    /// The name of the shading, as `--shading` takes it.
    pub fn shading_name(&self) -> String {
        match &self.shading {
            ShadingChoice::Primvar(name) => format!("primvar:{name}"),
            ShadingChoice::Mode(m) => value_name(m),
        }
    }

    /// The renderer options these flags describe; with `--shading primvar:NAME` the shading
    /// is [`Shading::Color`] (the caller shows a one-float primvar as [`Shading::Doi`]).
    pub fn render_options(&self) -> anyhow::Result<RenderOptions> {
        let shading = match &self.shading {
            ShadingChoice::Mode(m) => Shading::from(*m),
            ShadingChoice::Primvar(_) => Shading::Color,
        };
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
            legend: self.legend,
            samples: self.samples,
            ..RenderOptions::default()
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::choices::ShadingName;

    #[test]
    fn doi_shading_is_refused_without_doi_values() {
        let mut style = StyleArgs {
            shading: ShadingChoice::Mode(ShadingName::Doi),
            wire_overlay: false,
            silhouettes: false,
            legend: false,
            samples: None,
            doi_values: false,
        };
        let e = style.render_options().unwrap_err().to_string();
        assert!(e.contains("--shading doi needs --doi"), "{e}");
        style.doi_values = true;
        assert_eq!(style.render_options().unwrap().shading, Shading::Doi);
        let style = StyleArgs {
            shading: ShadingChoice::Mode(ShadingName::Depth),
            wire_overlay: true,
            silhouettes: true,
            legend: true,
            samples: Some(8),
            doi_values: false,
        };
        let o = style.render_options().unwrap();
        assert_eq!(o.shading, Shading::Depth);
        assert!(o.wire_overlay && o.show_lines && o.legend);
        assert_eq!(o.samples, Some(8));
        assert_eq!(parse_samples("4"), Ok(4));
        for bad in ["0", "3", "16", "four"] {
            assert!(
                parse_samples(bad).unwrap_err().contains("1, 2, 4 or 8"),
                "{bad}"
            );
        }
    }
}
