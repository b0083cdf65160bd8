//! Faces alike keep one copy of their weights: a face whose neighbourhood, points and
//! sharpness match another's (in the face's own frame: `support.rs` orders the neighbourhood,
//! `table.rs` the points) has the same weights but for the evaluator's rounding, and a frame
//! reads one copy for all of them from the cache instead of each from memory. On a cage of
//! mostly regular faces the table shrinks to a few kinds of face.
//!
//! Weights are alike when each pair differs by at most [`ALIKE`] (relative, at least 1 in
//! scale): far below what the weights are kept to in `f32` sums (the tests bound the frames
//! against fresh tessellations at `2e-6` of the cage's size).

use std::collections::HashMap;

use crate::table::{BLOCK_FLOATS, StencilTable};

/// Largest difference of two weights taken for the same one (relative, at least 1 in scale).
const ALIKE: f32 = 1e-6;

/// The grid the weights are hashed on (`2^-16`): alike weights fall on one point of it but
/// where they straddle a line of it (then they are kept apart, which only costs memory).
const HASH_GRID: f32 = 65536.0;

impl StencilTable {
    /// Stores each set of group weights once up to [`ALIKE`].
    pub(crate) fn share(&mut self) {
        let old = std::mem::take(&mut self.weights);
        let mut weights: Vec<f32> = Vec::new();
        let mut kept: HashMap<u64, Vec<usize>> = HashMap::new();
        for gi in 0..self.groups.len() {
            let g = self.groups[gi];
            let len = g.blocks as usize * g.len as usize * BLOCK_FLOATS;
            let w = &old[g.weights..][..len];
            let key = fnv(w);
            let same = |o: &usize| {
                let og = &self.groups[*o];
                og.len == g.len
                    && og.blocks == g.blocks
                    && weights[og.weights..][..len]
                        .iter()
                        .zip(w)
                        .all(|(a, b)| (a - b).abs() <= ALIKE * a.abs().max(1.0))
            };
            match kept.get(&key).and_then(|c| c.iter().copied().find(same)) {
                Some(o) => self.groups[gi].weights = self.groups[o].weights,
                None => {
                    self.groups[gi].weights = weights.len();
                    weights.extend_from_slice(w);
                    kept.entry(key).or_default().push(gi);
                }
            }
        }
        weights.shrink_to_fit();
        self.weights = weights;
    }
}

/// FNV-1a over `w` rounded to the hash grid.
fn fnv(w: &[f32]) -> u64 {
    w.iter().fold(0xcbf2_9ce4_8422_2325, |h, x| {
        let q = (x * HASH_GRID).round() as i64;
        (h ^ q as u64).wrapping_mul(0x0100_0000_01b3)
    })
}
