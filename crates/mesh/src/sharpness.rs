//! Sharpness arithmetic: how creases and corners decay per level (OpenSubdiv 3.5 `Sdc::Crease`).
//!
//! Semi-sharp creases follow DeRose, Kass and Truong, "Subdivision Surfaces in Character
//! Animation", SIGGRAPH 1998: an edge of sharpness `s` is subdivided with the sharp (midpoint)
//! rule while `s >= 1`, its children get `s - 1`, and a fractional `0 < s < 1` blends the sharp
//! and smooth rules linearly. The Chaikin variant (OpenSubdiv's `CREASE_CHAIKIN`) smooths the
//! sharpness along a crease: each child gets `3/4` of its parent's sharpness plus `1/4` of the
//! average of the other semi-sharp edges at that end, minus one. The vertex rules and masks that
//! read these values live in `subdiv-rules` (`crease.rs`, which re-exports this module); the
//! arithmetic is here because [`crate::Mesh::set_whole_vertex_edges`] needs it too.

use crate::options::{CreaseMethod, SHARPNESS_INFINITE};

/// `true` for sharpness 0 (or less).
#[inline]
pub fn is_smooth(s: f32) -> bool {
    s <= 0.0
}
/// `true` for any positive sharpness.
#[inline]
pub fn is_sharp(s: f32) -> bool {
    s > 0.0
}
/// `true` for infinite sharpness (>= 10).
#[inline]
pub fn is_infinite(s: f32) -> bool {
    s >= SHARPNESS_INFINITE
}
/// `true` for finite positive sharpness.
#[inline]
pub fn is_semi_sharp(s: f32) -> bool {
    s > 0.0 && s < SHARPNESS_INFINITE
}

/// Sharpness one level down under the uniform rule (also the vertex-sharpness rule of both
/// methods): infinite stays infinite, anything `<= 1` becomes smooth.
#[inline]
pub fn decrement(s: f32) -> f32 {
    if is_infinite(s) {
        SHARPNESS_INFINITE
    } else if s > 1.0 {
        s - 1.0
    } else {
        0.0
    }
}

/// Sharpness of the child of an edge of sharpness `s` at one of its ends, where `others` is the
/// (sum, count) of the sharpness of the *other* semi-sharp edges at that end.
#[inline]
pub fn child_edge_sharpness(method: CreaseMethod, s: f32, others: (f32, u32)) -> f32 {
    if method == CreaseMethod::Uniform || !is_semi_sharp(s) || others.1 == 0 {
        return decrement(s);
    }
    let avg = others.0 / others.1 as f32;
    let c = 0.75 * s + 0.25 * avg - 1.0;
    if is_sharp(c) { c } else { 0.0 }
}

/// Child sharpness of every edge around a vertex, given the parent sharpness of those edges.
#[inline]
pub fn child_edge_sharpness_around(method: CreaseMethod, parent: &[f32], child: &mut [f32]) {
    debug_assert_eq!(parent.len(), child.len());
    let (sum, count) = semi_sharp_sum(parent);
    for (c, &p) in child.iter_mut().zip(parent) {
        let others = if is_semi_sharp(p) {
            (sum - p, count - 1)
        } else {
            (sum, count)
        };
        *c = child_edge_sharpness(method, p, others);
    }
}

/// Sum and count of the semi-sharp values in `s`.
#[inline]
pub fn semi_sharp_sum(s: &[f32]) -> (f32, u32) {
    s.iter()
        .filter(|&&x| is_semi_sharp(x))
        .fold((0.0, 0), |(a, n), &x| (a + x, n + 1))
}

/// The weight of the parent mask in a fractional sharpness transition: the average parent
/// sharpness of the vertex and the edges (parent `edges`, child `child_edges`) that become
/// smooth in this step, at most 1 (OpenSubdiv's `Sdc::Crease::ComputeFractionalWeightAtVertex`);
/// 0 when nothing becomes smooth.
#[inline]
pub fn fractional_weight(
    method: CreaseMethod,
    vertex_sharpness: f32,
    child_vertex_sharpness: f32,
    edges: &[f32],
    child_edges: &[f32],
) -> f32 {
    let mut sum = 0.0f32;
    let mut count = 0u32;
    if is_sharp(vertex_sharpness) && is_smooth(child_vertex_sharpness) {
        sum += vertex_sharpness;
        count += 1;
    }
    for (&p, &c) in edges.iter().zip(child_edges.iter()) {
        let transition = match method {
            CreaseMethod::Uniform => is_sharp(p) && p <= 1.0,
            CreaseMethod::Chaikin => is_sharp(p) && is_smooth(c),
        };
        if transition {
            sum += p;
            count += 1;
        }
    }
    if count == 0 {
        0.0
    } else {
        (sum / count as f32).min(1.0)
    }
}

/// The schedule of a *crease vertex* (exactly two infinitely sharp edges) that also carries a
/// vertex sharpness and semi-sharp edges, as one vertex sharpness: the vertex is a corner while
/// any of them is sharp, and at the level `k` where the last run out it blends into the crease
/// rule by the weight `w` of [`fractional_weight`] (OpenSubdiv's
/// `ComputeFractionalWeightAtVertex`: the average over the sharpness that runs out then). The
/// result `k + w` is the vertex sharpness that alone gives the same schedule, read by the seam
/// curves of `subdiv-rules` to compare the schedules of the copies of a non-manifold crease
/// vertex. `edges`: the sharpness of the vertex's edges (any order; values that are
/// not semi-sharp are ignored). 0 when nothing semi-sharp is there (a crease from the start).
/// For a vertex sharpness alone it returns that sharpness, bit for bit.
pub fn crease_vertex_schedule(method: CreaseMethod, vertex_sharpness: f32, edges: &[f32]) -> f32 {
    let mut parent: Vec<f32> = edges
        .iter()
        .copied()
        .filter(|&s| is_semi_sharp(s))
        .collect();
    // One summation order whatever the ring order, so copies holding the same values agree.
    parent.sort_unstable_by(f32::total_cmp);
    let mut child = vec![0.0f32; parent.len()];
    let mut vs = if is_semi_sharp(vertex_sharpness) {
        vertex_sharpness
    } else {
        0.0
    };
    // Every value below infinity decays by at least 1 per level (Chaikin's too: 3/4 of itself
    // plus 1/4 of an average of smaller or equal values, minus 1).
    for k in 0..=SHARPNESS_INFINITE as u32 {
        if !is_sharp(vs) && parent.iter().all(|&s| !is_sharp(s)) {
            return 0.0;
        }
        child_edge_sharpness_around(method, &parent, &mut child);
        let child_vs = decrement(vs);
        if !is_sharp(child_vs) && child.iter().all(|&s| !is_sharp(s)) {
            return k as f32 + fractional_weight(method, vs, child_vs, &parent, &child);
        }
        std::mem::swap(&mut parent, &mut child);
        vs = child_vs;
    }
    0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_vertex_sharpness_alone_is_its_own_schedule() {
        for s in [0.125f32, 0.5, 1.0, 1.5, 2.375, 7.75, 9.5] {
            for m in [CreaseMethod::Uniform, CreaseMethod::Chaikin] {
                assert_eq!(crease_vertex_schedule(m, s, &[]).to_bits(), s.to_bits());
                assert_eq!(crease_vertex_schedule(m, s, &[10.0, 0.0, 10.0]), s);
            }
        }
        assert_eq!(
            crease_vertex_schedule(CreaseMethod::Uniform, 0.0, &[10.0, 10.0]),
            0.0
        );
    }

    #[test]
    fn the_schedule_averages_what_runs_out_last() {
        let u = CreaseMethod::Uniform;
        // 1.3 and 1.5 both run out after level 1: corner for one level, then weight 0.4.
        let s = crease_vertex_schedule(u, 0.0, &[10.0, 1.3, 0.0, 1.5, 10.0]);
        assert!((s - 1.4).abs() < 1e-6, "{s}");
        // 0.5 runs out at level 0, while 1.5 keeps the corner: only 1.5 counts.
        assert_eq!(crease_vertex_schedule(u, 0.0, &[0.5, 1.5]), 1.5);
        // A vertex sharpness counts like an edge.
        let s = crease_vertex_schedule(u, 2.25, &[2.75]);
        assert!((s - 2.5).abs() < 1e-6, "{s}");
        // Chaikin: 2 next to 1 decays to 0.75 * 2 + 0.25 - 1 = 0.75, 1 to 0.75 + 0.5 - 1 =
        // 0.25; then both run out (weight 0.5, the average of 0.75 and 0.25).
        let s = crease_vertex_schedule(CreaseMethod::Chaikin, 0.0, &[2.0, 1.0]);
        assert_eq!(s, 1.5);
    }
}
