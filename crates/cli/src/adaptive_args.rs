//! Flags of the view-dependent depth assignment, shared by `tessellate`, `render` and `view`.

use anyhow::bail;
use subdiv::DynamicSubdivision;
use subdiv::depth::DepthParams;
use subdiv::rules::Depth;
use subdiv::stitch::{FanMethod, MAX_ADAPTIVE_DEPTH};

/// Flags of the view-dependent depth assignment.
#[derive(clap::Args, Debug, Clone)]
pub struct AdaptiveArgs {
    /// Deepest subdivision depth (the paper's `maxsd`).
    #[arg(long, default_value_t = 5)]
    pub max_depth: Depth,
    /// Normal-cone aperture in degrees for the curvature depth.
    #[arg(long, default_value_t = 10.0)]
    pub cone_aperture: f32,
    /// Vertex classifier epsilon (back / front / silhouette).
    #[arg(long, default_value_t = 0.1)]
    pub classifier: f32,
    /// Projected sub-patch radius bounds in pixels.
    #[arg(long, value_parser = parse_pair, default_value = "2,8")]
    pub projected_size: (f32, f32),
    /// Choose the least depth whose chord error is at most PX pixels on screen.
    #[arg(long)]
    pub pixel_error: Option<f32>,
    /// Leave out back faces instead of drawing them at depth 0.
    #[arg(long)]
    pub cull_back: bool,
    /// Close depth transitions with plain fans (the paper's "simple method").
    #[arg(long)]
    pub simple_fans: bool,
}

impl AdaptiveArgs {
    /// The depth parameters these flags describe.
    pub fn params(&self) -> anyhow::Result<DepthParams> {
        if self.max_depth > MAX_ADAPTIVE_DEPTH {
            bail!(
                "--max-depth {} is too deep (at most {MAX_ADAPTIVE_DEPTH})",
                self.max_depth
            );
        }
        if let Some(px) = self.pixel_error
            && !(px.is_finite() && px > 0.0)
        {
            bail!("--pixel-error must be a positive number of pixels");
        }
        Ok(DepthParams {
            max_depth: self.max_depth,
            cone_aperture_deg: self.cone_aperture,
            classifier_eps: self.classifier,
            projected_size: Some(self.projected_size),
            pixel_error: self.pixel_error,
            cull_back: self.cull_back,
        })
    }

    /// A ready node for `mesh`.
    pub fn node(&self, mesh: subdiv::mesh::Mesh) -> anyhow::Result<DynamicSubdivision> {
        let mut node = DynamicSubdivision::new(mesh, self.params()?)?;
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
