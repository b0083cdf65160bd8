//! Flags of the view-dependent depth assignment, shared by `tessellate`, `render` and `view`.

use anyhow::bail;
use subdiv::DynamicSubdivision;
use subdiv::depth::{DEFAULT_MAX_DEPTH, DEFAULT_SHADING_ERROR_DEG, DepthParams};
use subdiv::rules::{Depth, Scheme};
use subdiv::stitch::{FanMethod, MAX_ADAPTIVE_DEPTH};

/// Flags of the view-dependent depth assignment. Every flag is optional so that the commands can
/// tell which were given: any of them asks for the adaptive tessellation in `tessellate`,
/// `render` and `view` alike (with the default camera when no camera flag is given), and is
/// refused next to `--depth`.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct AdaptiveArgs {
    /// Deepest subdivision depth (the paper's `maxsd`) [default: 5].
    #[arg(long)]
    pub max_depth: Option<Depth>,
    /// Normal-cone aperture in degrees for the curvature depth [default: 10].
    #[arg(long)]
    pub cone_aperture: Option<f32>,
    /// Vertex classifier epsilon (back / front / silhouette) [default: 0.1].
    #[arg(long)]
    pub classifier: Option<f32>,
    /// Projected sub-patch radius bounds in pixels [default: 0.9,4].
    #[arg(long, value_parser = parse_pair)]
    pub projected_size: Option<(f32, f32)>,
    /// Choose the least depth whose chord error is at most PX pixels on screen.
    #[arg(long)]
    pub pixel_error: Option<f32>,
    /// With --pixel-error: also keep the normals interpolated across the drawn triangles within
    /// DEG degrees of the limit normals on 99 % of the visible pixels off line pixels (where the
    /// limit normal turns by more than DEG to a neighbouring pixel: crease lines, folds), or
    /// within what uniform --max-depth reaches where that is worse (180: silhouettes only)
    /// [default: 10].
    #[arg(long, value_name = "DEG", requires = "pixel_error")]
    pub shading_error: Option<f32>,
    /// Leave out back faces instead of drawing them at depth 0.
    #[arg(long)]
    pub cull_back: bool,
    /// Close depth transitions with plain fans (the paper's "simple method"; Catmull-Clark:
    /// Loop's triangle fans have one form).
    #[arg(long)]
    pub simple_fans: bool,
}

impl AdaptiveArgs {
    /// The deepest depth (`--max-depth` or its default).
    pub fn max_depth(&self) -> Depth {
        self.max_depth.unwrap_or(DEFAULT_MAX_DEPTH)
    }

    /// The adaptive flags given on the command line, by name.
    pub fn given(&self) -> Vec<&'static str> {
        [
            (self.max_depth.is_some(), "--max-depth"),
            (self.cone_aperture.is_some(), "--cone-aperture"),
            (self.classifier.is_some(), "--classifier"),
            (self.projected_size.is_some(), "--projected-size"),
            (self.pixel_error.is_some(), "--pixel-error"),
            (self.shading_error.is_some(), "--shading-error"),
            (self.cull_back, "--cull-back"),
            (self.simple_fans, "--simple-fans"),
        ]
        .into_iter()
        .filter_map(|(on, name)| on.then_some(name))
        .collect()
    }

    /// The one rule of `tessellate`, `render` and `view`: adaptive when there is no `--depth`
    /// and a camera flag or an adaptive flag was given (`extra` lists adaptive flags a command
    /// adds, e.g. `--cull-camera-eye-relative`); adaptive flags next to `--depth` are refused,
    /// never ignored. Either scheme: Loop cages are tessellated adaptively on their triangles.
    pub fn wants_adaptive(
        &self,
        depth_given: bool,
        camera_given: bool,
        extra: &[&'static str],
    ) -> anyhow::Result<bool> {
        let mut given = self.given();
        given.extend_from_slice(extra);
        if !given.is_empty() {
            let flags = given.join(", ");
            if depth_given {
                bail!(
                    "{flags} choose adaptive depths, which --depth N replaces by a uniform one; \
                     drop one or the other"
                );
            }
        }
        Ok(!depth_given && (camera_given || !given.is_empty()))
    }

    /// The depth parameters these flags describe.
    pub fn params(&self) -> anyhow::Result<DepthParams> {
        let max_depth = self.max_depth();
        if max_depth > MAX_ADAPTIVE_DEPTH {
            bail!("--max-depth {max_depth} is too deep (at most {MAX_ADAPTIVE_DEPTH})");
        }
        if let Some(px) = self.pixel_error
            && !(px.is_finite() && px > 0.0)
        {
            bail!("--pixel-error must be a positive number of pixels");
        }
        let shading_error_deg = self.shading_error.unwrap_or(DEFAULT_SHADING_ERROR_DEG);
        if !(shading_error_deg > 0.0 && shading_error_deg <= 180.0) {
            bail!("--shading-error must be an angle in (0, 180] degrees");
        }
        // The paper's parameters default to `DepthParams::default()`, their one home.
        let d = DepthParams::default();
        Ok(DepthParams {
            max_depth,
            cone_aperture_deg: self.cone_aperture.unwrap_or(d.cone_aperture_deg),
            classifier_eps: self.classifier.unwrap_or(d.classifier_eps),
            projected_size: self.projected_size.or(d.projected_size),
            pixel_error: self.pixel_error,
            shading_error_deg,
            cull_back: self.cull_back,
        })
    }

    /// A ready node for the `scheme` surface of `mesh`.
    pub fn node(
        &self,
        mesh: subdiv::mesh::Mesh,
        scheme: Scheme,
    ) -> anyhow::Result<DynamicSubdivision> {
        if self.simple_fans && scheme == Scheme::Loop {
            bail!(
                "--simple-fans chooses between the Catmull-Clark fan forms; Loop's triangle fans \
                 have one"
            );
        }
        let mut node = DynamicSubdivision::with_scheme(mesh, scheme, self.params()?)?;
        if self.simple_fans {
            node.set_fan_method(FanMethod::Simple);
        }
        Ok(node)
    }
}

/// Parses `A,B`.
pub fn parse_pair(s: &str) -> Result<(f32, f32), String> {
    let (a, b) = s
        .split_once(',')
        .ok_or_else(|| format!("'{s}' is not MIN,MAX"))?;
    let a: f32 = a
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not MIN,MAX"))?;
    let b: f32 = b
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not MIN,MAX"))?;
    if !(a.is_finite() && b.is_finite() && a > 0.0 && b >= a) {
        return Err(format!("'{s}': need 0 < MIN <= MAX"));
    }
    Ok((a, b))
}
