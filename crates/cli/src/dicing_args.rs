//! The dicing flags (`--dicing-rate PX`, `--offscreen-dicing-scale S`), shared by
//! `tessellate`, `render`, `view` and `bench quality`'s dicing configurations.

use anyhow::bail;
use subdiv::eval::{DEFAULT_OFFSCREEN_DICING_SCALE, Dicing, MAX_RATE};

/// Dicing by pixels: every cage edge's tessellation rate from the length of its limit curve
/// on screen (Blender Cycles' definition), the surface evaluated exactly at those rates.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct DicingArgs {
    /// Tessellate at any rate, each cage edge cut into pieces of about PX pixels on screen
    /// (the length of its limit curve seen by the camera over PX, rounded up; Cycles'
    /// "dicing rate"; more where the curve bends on screen, so that its pieces stay within
    /// PX/32 of it); the points are exact limit points, watertight to the bit, and each
    /// vertex carries its (face, u, v) (glTF _FACE and _PATCH_UV, PLY face u v).
    #[arg(long, value_name = "PX")]
    pub dicing_rate: Option<f32>,
    /// With --dicing-rate: outside the view frustum (and behind the camera) the dicing rate is S
    /// times coarser [default: 4, as Cycles].
    #[arg(long, value_name = "S", requires = "dicing_rate")]
    pub offscreen_dicing_scale: Option<f32>,
    /// With --dicing-rate: the largest rate of a cage edge [default: 256].
    #[arg(long, value_name = "N", requires = "dicing_rate")]
    pub max_dicing_rate: Option<u32>,
}

impl DicingArgs {
    /// The dicing asked for, checked; `None` without `--dicing-rate`.
    pub fn dicing(&self) -> anyhow::Result<Option<Dicing>> {
        let Some(rate_px) = self.dicing_rate else {
            return Ok(None);
        };
        if !(rate_px.is_finite() && rate_px > 0.0) {
            bail!("--dicing-rate must be a positive number of pixels, found {rate_px}");
        }
        let offscreen_scale = self
            .offscreen_dicing_scale
            .unwrap_or(DEFAULT_OFFSCREEN_DICING_SCALE);
        if !(offscreen_scale.is_finite() && offscreen_scale >= 1.0) {
            bail!("--offscreen-dicing-scale must be at least 1, found {offscreen_scale}");
        }
        let max_rate = self.max_dicing_rate.unwrap_or(256);
        if !(1..=MAX_RATE).contains(&max_rate) {
            bail!("--max-dicing-rate must be 1..={MAX_RATE}, found {max_rate}");
        }
        Ok(Some(Dicing {
            offscreen_scale,
            max_rate,
            ..Dicing::new(rate_px)
        }))
    }
}
