//! What one frame produced: the vertex and index buffers handed to the renderer.

/// What one frame produced.
#[derive(Clone, Debug, Default)]
pub struct FrameGeometry {
    /// Vertex positions (all patch blocks, concatenated; shared points are referenced once).
    pub positions: Vec<[f32; 3]>,
    /// Unit limit normals.
    pub normals: Vec<[f32; 3]>,
    /// Triangle list, counter-clockwise.
    pub indices: Vec<u32>,
    /// Where the limit surface has a crease or a corner: (corner index in `indices`, the exact
    /// one-sided limit normal of that triangle's side), ascending and sparse. Each patch gives
    /// its own side's normal at the points of its border; `normals` keeps the averaged one.
    pub corner_normals: Vec<(u32, [f32; 3])>,
    /// Face-varying limit values (UVs) when the cage has them (`subdiv_slate::LevelUvs`).
    pub uvs: Vec<[f32; 2]>,
    /// The value in `uvs` of every triangle corner (parallel to `indices`; empty without UVs):
    /// the value on the corner's own patch's side of a seam, so a shared point carries one value
    /// per side and patches of different depths agree on it.
    pub uv_indices: Vec<u32>,
    /// Per vertex: the depth of the patch it belongs to (for depth colouring).
    pub vertex_depth: Vec<f32>,
    /// Depth of each unit (cage face) this frame; `u8::MAX` for units not drawn.
    pub unit_depth: Vec<u8>,
    /// Bumped whenever `positions`/`normals` changed since the previous frame.
    pub vertex_version: u64,
    /// Patches recomputed this frame.
    pub patches_recomputed: usize,
}

impl FrameGeometry {
    /// Replaces the vertex buffer by the blocks' points in order (`blocks` yields each block's
    /// positions and normals) and records where each block starts in `block_start` (one entry
    /// per block plus the total). Shared by the quad and the triangle assemblers.
    pub(crate) fn concatenate<'a>(
        &mut self,
        blocks: impl Iterator<Item = (&'a [[f32; 3]], &'a [[f32; 3]])> + Clone,
        block_start: &mut [u32],
    ) -> Result<(), subdiv_rules::OutOfMemory> {
        let mut acc = 0u32;
        let mut n = 0;
        for (i, (pos, _)) in blocks.clone().enumerate() {
            block_start[i] = acc;
            acc += pos.len() as u32;
            n = i + 1;
        }
        block_start[n] = acc;
        self.positions.clear();
        self.normals.clear();
        let total = acc as usize;
        subdiv_rules::budget::try_reserve(&mut self.positions, total, "frame positions")?;
        subdiv_rules::budget::try_reserve(&mut self.normals, total, "frame normals")?;
        for (pos, nrm) in blocks {
            self.positions.extend_from_slice(pos);
            self.normals.extend_from_slice(nrm);
        }
        Ok(())
    }

    /// Number of triangles.
    pub fn num_triangles(&self) -> usize {
        self.indices.len() / 3
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

    /// The referenced vertices only, renumbered (for writing files).
    pub fn compact(&self) -> (Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<u32>) {
        let mut map = vec![u32::MAX; self.positions.len()];
        let mut pos = Vec::new();
        let mut nrm = Vec::new();
        let mut idx = Vec::with_capacity(self.indices.len());
        for &i in &self.indices {
            let m = &mut map[i as usize];
            if *m == u32::MAX {
                *m = pos.len() as u32;
                pos.push(self.positions[i as usize]);
                nrm.push(self.normals[i as usize]);
            }
            idx.push(*m);
        }
        (pos, nrm, idx)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_per_depth_skips_undrawn_units() {
        let g = FrameGeometry {
            unit_depth: vec![2, u8::MAX, 0, 2, 2],
            ..Default::default()
        };
        assert_eq!(g.units_per_depth(), vec![1, 0, 3]);
        assert_eq!(
            FrameGeometry::default().units_per_depth(),
            Vec::<usize>::new()
        );
    }

    #[test]
    fn compact_keeps_referenced_vertices_in_first_use_order() {
        let p = |x: f32| [x, 0.0, 0.0];
        let g = FrameGeometry {
            positions: vec![p(0.0), p(1.0), p(2.0), p(3.0), p(4.0)],
            normals: vec![p(10.0), p(11.0), p(12.0), p(13.0), p(14.0)],
            indices: vec![3, 1, 4, 4, 1, 3],
            ..Default::default()
        };
        assert_eq!(g.num_triangles(), 2);
        let (pos, nrm, idx) = g.compact();
        assert_eq!(pos, vec![p(3.0), p(1.0), p(4.0)]);
        assert_eq!(nrm, vec![p(13.0), p(11.0), p(14.0)]);
        assert_eq!(idx, vec![0, 1, 2, 2, 1, 0]);
    }
}
