//! What one frame produced: the surface (a [`LimitMesh`] triangle list) and the frame's
//! bookkeeping.

use std::ops::Range;

use subdiv_rules::LimitMesh;

/// What one adaptive frame produced: the surface, and per unit (cage face) its depth.
///
/// The surface is a triangle list (counter-clockwise) over the vertices of all patch blocks,
/// each in its slot of the vertex buffer (shared points referenced once; points of blocks no
/// triangle uses, and slots left behind by blocks that grew, stay until the buffer is laid out
/// afresh). Where
/// the limit surface has a crease or a corner, each patch gives its own side's one-sided normal
/// at the points of its border; the vertex normals keep the averaged one. Its face-varying
/// values (UVs, `subdiv_slate::LevelUvs`) are those on each corner's own patch's side of a seam,
/// so that patches of different depths agree on them. Its scalar is the depth
/// ([`VertexScalar::Depth`](subdiv_rules::VertexScalar)) of the patch each vertex belongs to.
#[derive(Clone, Debug, Default)]
pub struct AdaptiveFrame {
    pub(crate) surface: LimitMesh,
    pub(crate) unit_depth: Vec<u8>,
    pub(crate) vertex_version: u64,
    pub(crate) patches_recomputed: usize,
    pub(crate) points_recomputed: usize,
    pub(crate) parts: UpdateParts,
    pub(crate) dirty: Vec<Range<u32>>,
}

/// A frame's depths, drawn flags and a stand-in's face-varying values
/// ([`AdaptiveFrame::stand_in_uvs`]).
pub(crate) type StandInUvs = (Vec<subdiv_slate::Depth>, Vec<bool>, subdiv_slate::LevelUvs);

/// Where one frame's update spent its time, in seconds of wall clock.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct UpdateParts {
    /// Choosing the depths (classification, projected size or pixel error, frame-rate control):
    /// set by whoever assigns them (`subdiv::DynamicSubdivision`), 0 from an assembler alone.
    pub depths: f64,
    /// Tessellating the patches whose cached block was too coarse.
    pub tessellate: f64,
    /// Edge resolutions and owners, fans and the index buffer.
    pub stitch: f64,
    /// The vertex buffer and per-vertex data (blocks concatenated when any changed, vertex
    /// depths, face-varying values) and the surface's checks: what an upload reads.
    pub buffers: f64,
}

impl UpdateParts {
    /// The whole update.
    pub fn total(&self) -> f64 {
        self.depths + self.tessellate + self.stitch + self.buffers
    }
}

/// Seconds since `t`, and `t` moved to now.
#[inline]
pub(crate) fn lap(t: &mut std::time::Instant) -> f64 {
    let now = std::time::Instant::now();
    let s = (now - *t).as_secs_f64();
    *t = now;
    s
}

impl AdaptiveFrame {
    /// The frame's surface (see [`AdaptiveFrame`]).
    #[inline]
    pub fn surface(&self) -> &LimitMesh {
        &self.surface
    }

    /// Per vertex: the depth of the patch it belongs to (the surface's scalar).
    #[inline]
    pub fn vertex_depth(&self) -> &[f32] {
        self.surface.scalar().map_or(&[], |(_, v)| v)
    }

    /// Depth of each unit (cage face) this frame; `u8::MAX` for units not drawn.
    #[inline]
    pub fn unit_depth(&self) -> &[u8] {
        &self.unit_depth
    }

    /// Bumped whenever the surface's positions or normals changed since the previous frame.
    #[inline]
    pub fn vertex_version(&self) -> u64 {
        self.vertex_version
    }

    /// The vertex ranges this frame rewrote (empty when the vertex buffer is the previous
    /// frame's): every other vertex kept its index and its bits, so a renderer that keeps the
    /// previous buffer uploads only these. The blocks of the recomputed patches, or the whole
    /// buffer when it was laid out afresh.
    #[inline]
    pub fn dirty_vertices(&self) -> &[Range<u32>] {
        &self.dirty
    }

    /// Patches recomputed this frame.
    #[inline]
    pub fn patches_recomputed(&self) -> usize {
        self.patches_recomputed
    }

    /// Limit points computed this frame (the grids of the recomputed patches).
    #[inline]
    pub fn points_recomputed(&self) -> usize {
        self.points_recomputed
    }

    /// Where this frame's update spent its time.
    #[inline]
    pub fn parts(&self) -> UpdateParts {
        self.parts
    }

    /// Sets the time spent choosing this frame's depths (the caller that assigned them).
    #[inline]
    pub fn set_depths_time(&mut self, seconds: f64) {
        self.parts.depths = seconds;
    }

    /// Number of triangles.
    #[inline]
    pub fn num_triangles(&self) -> usize {
        self.surface.num_faces()
    }

    /// Records the frame's vertex version, recomputed patches and unit depths (`depth[u]`
    /// where `active[u]`, `u8::MAX` elsewhere). Shared by the quad and the triangle assemblers.
    pub(crate) fn set_bookkeeping(
        &mut self,
        version: u64,
        recomputed: (usize, usize),
        depth: &[u8],
        active: &[bool],
    ) {
        self.vertex_version = version;
        (self.patches_recomputed, self.points_recomputed) = recomputed;
        self.unit_depth.clear();
        let drawn = depth.iter().zip(active);
        self.unit_depth
            .extend(drawn.map(|(&d, &a)| if a { d } else { u8::MAX }));
    }

    /// The depth and whether it is drawn of every unit (0 for units not drawn), as the frame
    /// was made with.
    pub(crate) fn drawn(&self) -> (Vec<subdiv_slate::Depth>, Vec<bool>) {
        let on = |d: u8| d != u8::MAX;
        let depth = self
            .unit_depth
            .iter()
            .map(|&d| if on(d) { d } else { 0 })
            .collect();
        (depth, self.unit_depth.iter().map(|&d| on(d)).collect())
    }

    /// For face-varying values of `stand_in` (this frame's cage with other face-varying data)
    /// at this frame's corners: the depths and drawn flags the frame was made with, and the
    /// values of `stand_in` under `scheme` down to the deepest drawn depth plus `below` (the
    /// levels the frame's corners lie on); `None` when nothing is drawn or `stand_in` has no
    /// face-varying data.
    pub(crate) fn stand_in_uvs(
        &self,
        stand_in: &subdiv_mesh::Mesh,
        scheme: subdiv_rules::Scheme,
        below: subdiv_slate::Depth,
    ) -> Result<Option<StandInUvs>, crate::AssemblyError> {
        let deepest = self
            .unit_depth
            .iter()
            .copied()
            .filter(|&d| d != u8::MAX)
            .max();
        let Some(d) = deepest else {
            return Ok(None);
        };
        let Some(uvs) = subdiv_slate::LevelUvs::new(stand_in, scheme, d + below)? else {
            return Ok(None);
        };
        let (depth, active) = self.drawn();
        Ok(Some((depth, active, uvs)))
    }

    /// Number of units drawn at each depth (index = depth).
    pub fn units_per_depth(&self) -> Vec<usize> {
        let mut v = Vec::new();
        for &d in &self.unit_depth {
            if d != u8::MAX {
                if v.len() <= d as usize {
                    v.resize(d as usize + 1, 0);
                }
                v[d as usize] += 1;
            }
        }
        v
    }

    /// The referenced vertices only, renumbered in order of first use
    /// ([`LimitMesh::referenced_only`]): positions, normals and the triangle list.
    pub fn compact(&self) -> (Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<u32>) {
        let s = self.surface.referenced_only();
        (
            s.positions().to_vec(),
            s.normals().to_vec(),
            s.face_indices().to_vec(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_per_depth_skips_undrawn_units() {
        let g = AdaptiveFrame {
            unit_depth: vec![2, u8::MAX, 0, 2, 2],
            ..Default::default()
        };
        assert_eq!(g.units_per_depth(), vec![1, 0, 3]);
        assert_eq!(
            AdaptiveFrame::default().units_per_depth(),
            Vec::<usize>::new()
        );
    }
}
