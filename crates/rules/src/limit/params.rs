//! [`VertexParams`]: where each vertex of a [`LimitMesh`] lies on the limit surface, for
//! ptex-style textures and displacement (the exact tessellations write them).

use super::{LimitMesh, LimitMeshError};

/// Tiles per row of the parameter domain of a Catmull-Clark face of `corners` corners (not
/// four): OpenSubdiv's `Bfr` lays an n-gon's sub-faces out as unit tiles in rows of this many
/// (`subdiv_eval::Domain::SubFaces`), tile `k` at `(k % dim, k / dim)`.
pub fn subface_tiles_per_row(corners: u32) -> u32 {
    if corners < 10 {
        2 + u32::from(corners > 4)
    } else {
        1 + ((corners - 1) as f32).sqrt() as u32
    }
}

/// Where each vertex of a surface is on the limit surface: the cage face and the `(u, v)` in
/// that face's parameter domain (OpenSubdiv's `Bfr` parameterisation, `subdiv_eval::Domain`),
/// for ptex-style textures and displacement.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VertexParams {
    /// The cage face of each vertex.
    pub face: Vec<u32>,
    /// The `(u, v)` of each vertex in its face.
    pub uv: Vec<[f32; 2]>,
}

impl VertexParams {
    /// An empty set with room for `n` vertices.
    pub fn with_capacity(n: usize) -> VertexParams {
        VertexParams {
            face: Vec::with_capacity(n),
            uv: Vec::with_capacity(n),
        }
    }

    /// Appends vertex `i` of `src`.
    #[inline]
    pub(super) fn push_from(&mut self, src: &VertexParams, i: usize) {
        self.face.push(src.face[i]);
        self.uv.push(src.uv[i]);
    }
}

impl LimitMesh {
    /// Each vertex's parameter point, when set.
    #[inline]
    pub fn params(&self) -> Option<&VertexParams> {
        self.params.as_ref()
    }

    /// Sets each vertex's parameter point (checked: one per position).
    pub fn set_params(&mut self, params: VertexParams) -> Result<(), LimitMeshError> {
        let n = self.positions.len();
        if params.face.len() != n || params.uv.len() != n {
            return Err(LimitMeshError(format!(
                "{} parameter faces and {} (u, v) for {n} positions",
                params.face.len(),
                params.uv.len()
            )));
        }
        self.params = Some(params);
        Ok(())
    }
}
