//! A cage's primvars on its uniform tessellations ([`tessellate_primvars`]): one
//! [`LimitChannel`] per primvar, in the numbering of the surface the same scheme and depth give.
//!
//! Every primvar goes through the tessellator that makes the surface, so that it meets the
//! surface's numbering, rules and exactness without a rule of its own:
//! - **vertex**: three floats at a time stand in for the cage's positions, in the layout made
//!   from the cage (its seams and numbering), so each output point gets their limit with the
//!   position's masks (sharpness included): OpenSubdiv's `Interpolate` then `Limit`;
//! - **face-varying**: two floats at a time stand in for the texture coordinates, under the
//!   cage's face-varying option: `InterpolateFaceVarying` then `LimitFaceVarying`;
//! - **varying**: as face-varying with one value per vertex and the option `All` (linear
//!   everywhere: face values centroids, edge values midpoints, vertex values kept),
//!   `InterpolateVarying`, whose values are their own limit;
//! - **uniform**: as face-varying with one value per face and `All`: constant on each face;
//! - **constant**: the one value at every point.

use subdiv_mesh::{Mesh, Primvar, PrimvarInterpolation};
use subdiv_rules::{
    Depth, LimitChannel, LimitMesh, Scheme, SeamCurves, face_varying_channel, limit_surface,
    stand_in_base, vertex_channel,
};

use crate::bilinear::tessellate_bilinear;
use crate::moving::UniformTessellator;
use crate::tessellate::{SlateError, tessellate};
use crate::tri::tessellate_tri;

/// Appends to `surface` (the uniform `scheme` tessellation of `mesh` at `depth`) one channel
/// per primvar of `mesh` (see the module notes); nothing for a cage without primvars.
pub fn tessellate_primvars(
    mesh: &Mesh,
    scheme: Scheme,
    depth: Depth,
    surface: &mut LimitMesh,
) -> Result<(), SlateError> {
    if mesh.primvars().is_empty() {
        return Ok(());
    }
    let mut vertex_pass: Option<VertexPass> = None;
    for p in mesh.primvars() {
        let channel = match p.interpolation {
            PrimvarInterpolation::Constant => LimitChannel {
                name: p.name.clone(),
                width: p.width,
                values: p.element(0).repeat(surface.num_vertices()),
                indices: Vec::new(),
            },
            PrimvarInterpolation::Vertex => {
                let pass = match &mut vertex_pass {
                    Some(pass) => pass,
                    None => vertex_pass.insert(VertexPass::new(mesh, scheme, depth)?),
                };
                pass.channel(p)?
            }
            PrimvarInterpolation::Varying
            | PrimvarInterpolation::Uniform
            | PrimvarInterpolation::FaceVarying => face_varying_channel(mesh, p, |stand_in| {
                let out = match scheme {
                    Scheme::CatmullClark => tessellate(stand_in, depth)?,
                    Scheme::Loop => tessellate_tri(stand_in, depth)?,
                    Scheme::Bilinear => tessellate_bilinear(stand_in, depth)?,
                };
                Ok::<_, SlateError>((out.uvs().to_vec(), out.uv_indices().to_vec()))
            })?,
        };
        surface.push_channel(channel)?;
    }
    Ok(())
}

/// Vertex primvars three floats at a time as the positions of the cage's layout.
struct VertexPass {
    /// The cage without face-varying data (its layout's seams and numbering).
    base: Mesh,
    moving: UniformTessellator,
    depth: Depth,
}

impl VertexPass {
    fn new(mesh: &Mesh, scheme: Scheme, depth: Depth) -> Result<VertexPass, SlateError> {
        let base = stand_in_base(mesh);
        let moving = UniformTessellator::new(&base, scheme, depth)?;
        Ok(VertexPass {
            base,
            moving,
            depth,
        })
    }

    /// The limit of `p` (one value per vertex) at every output point.
    fn channel(&mut self, p: &Primvar) -> Result<LimitChannel, SlateError> {
        let (base, depth) = (&self.base, self.depth);
        let moving = &mut self.moving;
        vertex_channel(base, p, |stand_in| {
            Ok(if depth == 0 {
                // The cage's own limit points; seams keyed by the cage's real positions.
                let mut out = limit_surface(stand_in, moving.scheme());
                SeamCurves::new(base).write_uniform(stand_in, 0, 0, out.positions_mut());
                out.positions().to_vec()
            } else {
                moving.update(stand_in)?.positions().to_vec()
            })
        })
    }
}
