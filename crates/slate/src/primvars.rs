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

use std::collections::HashMap;

use glam::Vec2;
use subdiv_mesh::{FVarLinearInterpolation, FaceVarying, Mesh, Primvar, PrimvarInterpolation};
use subdiv_rules::{
    Depth, LimitChannel, LimitMesh, Scheme, SeamCurves, limit_surface, stand_in_base,
    vertex_channel,
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

/// The channel of a varying, uniform or face-varying primvar `p` of `mesh` (one value per
/// face corner of the surface): its values, two floats at a time, stand in for the cage's
/// texture coordinates under the face-varying option its kind takes (face-varying: the cage's;
/// varying and uniform: `All`, linear everywhere), and `pass(stand_in)` gives the surface's
/// face-varying values and the value of every corner for that cage (the uniform tessellations'
/// UVs, or an adaptive frame's, `subdiv-stitch`). Any other kind of primvar is read as a
/// uniform one.
pub fn face_varying_channel<E: From<subdiv_rules::RulesError>>(
    mesh: &Mesh,
    p: &Primvar,
    mut pass: impl FnMut(&Mesh) -> Result<(Vec<[f32; 2]>, Vec<u32>), E>,
) -> Result<LimitChannel, E> {
    let option = match p.interpolation {
        PrimvarInterpolation::FaceVarying => mesh.options().fvar,
        _ => FVarLinearInterpolation::All,
    };
    // The value of every corner: the corner's, the vertex's or the face's.
    let (offsets, verts) = mesh.face_lists();
    let corner_element: Vec<u32> = match p.interpolation {
        PrimvarInterpolation::FaceVarying => (0..verts.len() as u32).collect(),
        PrimvarInterpolation::Varying => verts.iter().map(|v| v.0).collect(),
        _ => (0..mesh.num_faces())
            .flat_map(|f| std::iter::repeat_n(f as u32, (offsets[f + 1] - offsets[f]) as usize))
            .collect(),
    };
    let indices: Vec<u32> = corner_element
        .iter()
        .map(|&e| p.indices[e as usize])
        .collect();
    let w = p.width;
    let mut stand_in = mesh.clone();
    stand_in.set_fvar_option(option);
    let mut passes: Vec<(Vec<[f32; 2]>, Vec<u32>)> = Vec::new();
    for chunk in 0..w.div_ceil(2) {
        let values = (0..p.num_values())
            .map(|i| {
                let c = |k: usize| p.values.get(i * w + 2 * chunk + k).copied();
                let second = if 2 * chunk + 1 < w { c(1) } else { None };
                Vec2::new(c(0).unwrap_or(0.0), second.unwrap_or(0.0))
            })
            .collect();
        let fv = FaceVarying {
            values,
            indices: indices.clone(),
            dependence: Vec::new(),
        };
        stand_in
            .set_uv(Some(fv))
            .map_err(subdiv_rules::RulesError::Internal)?;
        passes.push(pass(&stand_in)?);
    }
    // One value per distinct tuple of the passes' values at a corner.
    let corners = passes.first().map_or(0, |p| p.1.len());
    let mut ids: HashMap<Vec<u32>, u32> = HashMap::new();
    let (mut values, mut out_indices) = (Vec::new(), Vec::with_capacity(corners));
    let mut key = Vec::with_capacity(passes.len());
    for c in 0..corners {
        key.clear();
        key.extend(passes.iter().map(|(_, idx)| idx[c]));
        let next = ids.len() as u32;
        let id = *ids.entry(key.clone()).or_insert_with(|| {
            for (chunk, (uvs, idx)) in passes.iter().enumerate() {
                let t = uvs[idx[c] as usize];
                values.push(t[0]);
                if 2 * chunk + 1 < w {
                    values.push(t[1]);
                }
            }
            next
        });
        out_indices.push(id);
    }
    Ok(LimitChannel {
        name: p.name.clone(),
        width: w,
        values,
        indices: out_indices,
    })
}
