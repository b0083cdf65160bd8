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
