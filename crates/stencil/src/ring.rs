//! The lanes at cage vertices where the evaluator's limit is not linear in the probes: their
//! stencils are probed from the vertex's ring instead (`subdiv_rules::Ring::limit_tangents`,
//! what the slates' corners take). Where even that is not linear (an interior crease, whose
//! normal averages its sides', a non-manifold copy) no table is made.

use subdiv_mesh::{Mesh, VertexId};
use subdiv_rules::{Ring, Scheme};

use crate::StencilError;
use crate::table::{BLOCK_FLOATS, LANES, RingLane, StencilTable, cage_size, close, probe_cage};

impl StencilTable {
    /// Replaces the weights of `lanes` by their vertices' ring limits, probed like the
    /// evaluator's, and checks them on the `moved` cage against [`Ring::limit`]: a lane that
    /// differs, or whose limit has no linear form, is an error.
    pub(crate) fn ring_lanes(
        &mut self,
        moved: &Mesh,
        scheme: Scheme,
        colours: &[u32],
        lanes: Vec<RingLane>,
    ) -> Result<(), StencilError> {
        if lanes.is_empty() {
            return Ok(());
        }
        let mut linear = vec![true; lanes.len()];
        let mut ring = Ring::new();
        let mut cage = moved.clone();
        let num_colours = colours.iter().map(|&c| c + 1).max().unwrap_or(0);
        for probe in 0..num_colours.div_ceil(3) {
            probe_cage(&mut cage, colours, probe);
            for (k, lane) in lanes.iter().enumerate() {
                let limit = ring
                    .load(&cage, VertexId(lane.vertex), scheme)
                    .then(|| ring.limit_tangents())
                    .flatten();
                let Some((pos, t1, t2)) = limit else {
                    linear[k] = false;
                    continue;
                };
                let g = self.groups[lane.group];
                let support = &self.support[g.support as usize..][..g.len as usize];
                for (j, &v) in support.iter().enumerate() {
                    let c = colours[v as usize];
                    if c / 3 != probe {
                        continue;
                    }
                    let i = (c % 3) as usize;
                    let at =
                        g.weights + (lane.block * g.len as usize + j) * BLOCK_FLOATS + lane.lane;
                    self.weights[at] = pos[i] as f32;
                    self.weights[at + LANES] = t1[i] as f32;
                    self.weights[at + 2 * LANES] = t2[i] as f32;
                }
            }
        }
        let size = cage_size(moved);
        for (k, lane) in lanes.iter().enumerate() {
            let g = self.groups[lane.group];
            let (p, n) =
                subdiv_rules::limit_point_with(&mut ring, moved, VertexId(lane.vertex), scheme);
            let sums = self.lane_sums(&g, lane.block, lane.lane, moved.positions());
            if !linear[k] || !close(sums, p.as_dvec3(), n.as_dvec3(), size) {
                return Err(StencilError::Support { point: lane.target });
            }
            self.ring_stencils += 1;
        }
        Ok(())
    }
}
