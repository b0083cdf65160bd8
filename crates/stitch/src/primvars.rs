//! A cage's primvars on an adaptive frame ([`frame_primvars`]): one channel per primvar, in
//! the frame's numbering, as the uniform tessellations carry them (`subdiv_slate`'s
//! `tessellate_primvars`).
//!
//! - **vertex**: linear data refined with the positions' rules, so its values at the frame's
//!   points are what the frame's blocks give when the primvar's values, three floats at a time,
//!   stand in for the cage's positions ([`subdiv_rules::vertex_channel`]): the same patches at
//!   the same depths, written into the same slots;
//! - **face-varying, varying, uniform**: two floats at a time stand in for the cage's texture
//!   coordinates ([`subdiv_rules::face_varying_channel`]), and every frame corner takes its
//!   value as the frame's own UVs do (the same triangles emitted again with those values);
//! - **constant**: the one value at every point.

use std::convert::Infallible;

use subdiv_mesh::{Mesh, PrimvarInterpolation};
use subdiv_rules::{LimitChannel, face_varying_channel, stand_in_base, vertex_channel};

use crate::{AdaptiveFrame, AssemblyError};

/// Adds to `frame` (the last frame of an assembler of `mesh`) one channel per primvar of
/// `mesh`. `points(cage)` gives the frame's vertex buffer for a cage of `mesh`'s topology with
/// other positions ([`Assembler::stand_in_points`](crate::Assembler::stand_in_points),
/// [`TriAssembler::stand_in_points`](crate::TriAssembler::stand_in_points)); `corners(cage)`
/// the frame's face-varying values and corner values for a cage with other face-varying data
/// ([`Assembler::stand_in_corner_values`](crate::Assembler::stand_in_corner_values),
/// [`TriAssembler::stand_in_corner_values`](crate::TriAssembler::stand_in_corner_values)).
pub fn frame_primvars(
    mesh: &Mesh,
    points: impl Fn(&Mesh) -> Vec<[f32; 3]>,
    corners: impl Fn(&Mesh, &AdaptiveFrame) -> Result<(Vec<[f32; 2]>, Vec<u32>), AssemblyError>,
    frame: &mut AdaptiveFrame,
) -> Result<(), AssemblyError> {
    if mesh.primvars().is_empty() {
        return Ok(());
    }
    let base = stand_in_base(mesh);
    let n = frame.surface.num_vertices();
    let mut channels = Vec::with_capacity(mesh.primvars().len());
    for p in mesh.primvars() {
        channels.push(match p.interpolation {
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
            _ => face_varying_channel(mesh, p, |cage| corners(cage, frame))?,
        });
    }
    for c in channels {
        frame.surface.push_channel(c)?;
    }
    Ok(())
}
