//! A cage's primvars on an adaptive frame ([`frame_primvars`]): one channel per vertex or
//! constant primvar, in the frame's numbering.
//!
//! A vertex primvar is linear data refined with the positions' rules, so its values at the
//! frame's points are what the frame's blocks give when the primvar's values, three floats at
//! a time, stand in for the cage's positions ([`subdiv_slate::vertex_channel`], as the uniform
//! tessellations carry it): the same patches at the same depths, written into the same slots.
//! Varying, uniform and face-varying primvars need the face-varying values of every frame
//! corner (as the UVs have them) and are not carried yet: their names are returned.

use std::convert::Infallible;

use subdiv_mesh::{Mesh, PrimvarInterpolation};
use subdiv_rules::{LimitChannel, LimitMeshError};
use subdiv_slate::{stand_in_base, vertex_channel};

use crate::AdaptiveFrame;

/// Adds to `frame` (the last frame of an assembler of `mesh`) one channel per vertex and
/// constant primvar of `mesh`; `points(cage)` gives the frame's vertex buffer for a cage of
/// `mesh`'s topology with other positions
/// ([`Assembler::stand_in_points`](crate::Assembler::stand_in_points),
/// [`TriAssembler::stand_in_points`](crate::TriAssembler::stand_in_points)). Returns the names
/// of the primvars not carried (varying, uniform, face-varying).
pub fn frame_primvars(
    mesh: &Mesh,
    points: impl Fn(&Mesh) -> Vec<[f32; 3]>,
    frame: &mut AdaptiveFrame,
) -> Result<Vec<String>, LimitMeshError> {
    let mut left = Vec::new();
    if mesh.primvars().is_empty() {
        return Ok(left);
    }
    let base = stand_in_base(mesh);
    let n = frame.surface.num_vertices();
    for p in mesh.primvars() {
        let channel = match p.interpolation {
            PrimvarInterpolation::Constant => LimitChannel {
                name: p.name.clone(),
                width: p.width,
                values: p.element(0).repeat(n),
                indices: Vec::new(),
            },
            PrimvarInterpolation::Vertex => {
                let Ok(c) = vertex_channel(&base, p, |cage| Ok::<_, Infallible>(points(cage)));
                c
            }
            _ => {
                left.push(p.name.clone());
                continue;
            }
        };
        frame.surface.push_channel(channel)?;
    }
    Ok(left)
}
