//! `interpolateboundary none` cages with fully sharp boundary vertices: OpenSubdiv hides the
//! faces at a vertex only where one of its boundary edges is not tagged infinitely sharp
//! (`subdiv_mesh`'s `BoundaryNoneRule`), so some `none` cages get infinite crease tags on every
//! boundary edge, or on every boundary edge at a few boundary vertices.

use std::collections::HashMap;

use crate::fuzz::Rng;
use crate::osd_cage::OsdCage;

/// Percentage of `none` cages whose boundary is sharpened (their own random stream).
pub const SHARP_NONE_PERCENT: u64 = 40;

/// Tags infinitely sharp either every boundary edge (edges with one face) of `cage` or every
/// boundary edge at one to three boundary vertices (which then hide nothing, while their
/// neighbours along the boundary still do). Existing crease tags on those edges are raised.
pub(super) fn sharpen_boundary(rng: &mut Rng, cage: &mut OsdCage) {
    let mut uses: HashMap<(u32, u32), u32> = HashMap::new();
    for f in &cage.faces {
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            *uses.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let mut boundary: Vec<(u32, u32)> = uses
        .into_iter()
        .filter(|&(_, n)| n == 1)
        .map(|(e, _)| e)
        .collect();
    if boundary.is_empty() {
        return;
    }
    boundary.sort_unstable();
    let all = rng.chance(40);
    let chosen: Vec<u32> = (0..1 + rng.below(3))
        .map(|_| {
            let e = boundary[rng.below(boundary.len())];
            if rng.chance(50) { e.0 } else { e.1 }
        })
        .collect();
    for &(a, b) in &boundary {
        if !(all || chosen.contains(&a) || chosen.contains(&b)) {
            continue;
        }
        match cage
            .creases
            .iter_mut()
            .find(|c| (c.0.min(c.1), c.0.max(c.1)) == (a, b))
        {
            Some(c) => c.2 = 10.0,
            None => cage.creases.push((a, b, 10.0)),
        }
    }
}
