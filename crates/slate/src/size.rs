//! What a uniform tessellation asks for, refused before anything is allocated: the slates'
//! depth limit, this machine's memory ([`Budget`]) and [`MAX_POINTS`].

use subdiv_mesh::Mesh;
use subdiv_rules::{Budget, Depth, MAX_DEPTH, Request, Scheme};

use crate::tessellate::{MAX_POINTS, SlateError};

/// `Ok` when the uniform `scheme` tessellation of `mesh` at `depth` (at least 1) fits the
/// slates, this machine's memory and [`MAX_POINTS`].
pub(crate) fn check_uniform_size(
    mesh: &Mesh,
    scheme: Scheme,
    depth: Depth,
) -> Result<(), SlateError> {
    if depth > MAX_DEPTH {
        return Err(SlateError::TooDeep {
            depth,
            max: MAX_DEPTH,
        });
    }
    Budget::machine().check(mesh, Request::Uniform { scheme, depth })?;
    // Points: a quad per face corner at level 1 (Catmull-Clark), a triangle per face (Loop),
    // each 4^(depth-1) or 4^depth quads or triangles, about one point per quad or two triangles.
    let estimate = match scheme {
        Scheme::CatmullClark | Scheme::Bilinear => {
            let corners: u64 = mesh.faces().map(|f| mesh.face_size(f) as u64).sum();
            corners.saturating_mul(1u64 << (2 * depth)) / 4
        }
        Scheme::Loop => (mesh.num_faces() as u64).saturating_mul(1u64 << (2 * depth)) / 2,
    };
    if estimate > MAX_POINTS {
        return Err(SlateError::TooLarge {
            depth,
            points: estimate,
        });
    }
    Ok(())
}
