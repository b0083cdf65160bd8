//! The lanes at cage vertices: their stencils are probed from the vertex's ring refined as many
//! times as the tessellation's depth (`subdiv_rules::Ring::limit_tangents`), what the slates'
//! corners take, their rings refined once a step. Where OpenSubdiv's masks are not the limit (a
//! dart, a vertex of valence 2) that is the value at that level, as OpenSubdiv and the slates
//! give it, not the evaluator's limit; and the evaluator settles some corners numerically,
//! which the probes cannot follow. Where the ring's normal is not linear either (an interior
//! crease, whose normal averages its sides', a non-manifold copy) no table is made.

use glam::DVec3;
use subdiv_mesh::{Mesh, VertexId};
use subdiv_rules::{Ring, Scheme};

use crate::StencilError;
use crate::table::{BLOCK_FLOATS, LANES, RingLane, StencilTable, cage_size, close, probe_cage};

impl StencilTable {
    /// Replaces the weights of `lanes` by their vertices' ring limits at `level` (the ring
    /// refined `level` times, then its masks), probed like the evaluator's, and checks them on
    /// the `moved` cage against [`Ring::limit`] at that level: a lane that differs, or whose
    /// limit has no linear form, is an error.
    pub(crate) fn ring_lanes(
        &mut self,
        moved: &Mesh,
        scheme: Scheme,
        colours: &[u32],
        lanes: Vec<RingLane>,
        level: u32,
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
                let limit = load(&mut ring, &cage, lane.vertex, scheme, level)
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
            let (p, n) = if load(&mut ring, moved, lane.vertex, scheme, level) {
                ring.limit()
            } else {
                (DVec3::ZERO, DVec3::ZERO)
            };
            let sums = self.lane_sums(&g, lane.block, lane.lane, moved.positions());
            if !linear[k] || !close(sums, p, n, size) {
                return Err(StencilError::Support { point: lane.target });
            }
            self.ring_stencils += 1;
        }
        Ok(())
    }
}

/// Loads the ring of cage vertex `v` and refines it `level` times; `false` where the vertex has
/// no ring (isolated).
fn load(ring: &mut Ring, mesh: &Mesh, v: u32, scheme: Scheme, level: u32) -> bool {
    if !ring.load(mesh, VertexId(v), scheme) {
        return false;
    }
    for _ in 0..level {
        ring.refine();
    }
    true
}
