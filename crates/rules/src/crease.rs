//! Sharpness: which vertex rule applies (the decay arithmetic is `subdiv_mesh::sharpness`,
//! re-exported here).
//!
//! Semi-sharp creases follow DeRose, Kass and Truong, "Subdivision Surfaces in Character
//! Animation", SIGGRAPH 1998: an edge of sharpness `s` is subdivided with the sharp (midpoint)
//! rule while `s >= 1`, its children get `s - 1`, and a fractional `0 < s < 1` blends the sharp
//! and smooth rules linearly. The Chaikin variant (OpenSubdiv's `CREASE_CHAIKIN`) smooths the
//! sharpness along a crease: each child gets `3/4` of its parent's sharpness plus `1/4` of the
//! average of the other semi-sharp edges at that end, minus one. Vertex rules (smooth, dart,
//! crease, corner) and their fractional transitions follow Hoppe et al. 1994 and the semantics
//! of OpenSubdiv 3.5 (`Sdc::Crease`), so that limit surfaces agree with it.

use subdiv_mesh::CreaseMethod;
#[cfg(test)]
use subdiv_mesh::SHARPNESS_INFINITE;

mod whole;
pub use whole::{child_whole_vertex_edges, far_semi_sharp, rule_with_whole, semi_sharp_excluding};

pub use subdiv_mesh::sharpness::{
    child_edge_sharpness, child_edge_sharpness_around, crease_vertex_schedule, decrement,
    fractional_weight, is_infinite, is_semi_sharp, is_sharp, is_smooth, semi_sharp_sum,
};

/// Weight of the sharp (midpoint) rule for the point inserted on an edge of sharpness `s` whose
/// two child edges get the sharpness `child`: 0 is the smooth rule; 1 the crease rule, when both
/// children are sharp (the edge point's own rule is then a crease); otherwise the transition
/// blend with weight `s` itself, as OpenSubdiv 3.5 `Sdc::Scheme::ComputeEdgeVertexMask` does
/// when the child rule is smooth or a dart. That weight is not clamped: under the Chaikin method
/// an edge of sharpness `s > 1` whose child decays to smooth at one end extrapolates past the
/// midpoint (weight `s`, smooth mask weight `1 - s < 0`), and so does OpenSubdiv.
#[inline]
pub fn edge_crease_weight(s: f32, child: [f32; 2]) -> f32 {
    if is_smooth(s) {
        0.0
    } else if is_sharp(child[0]) && is_sharp(child[1]) {
        1.0
    } else {
        s
    }
}

/// The rule that moves a vertex.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Rule {
    /// No sharp edge: the scheme's smooth rule.
    Smooth,
    /// One sharp edge: still the smooth rule.
    Dart,
    /// Two sharp edges, at positions `[i, j]` (`i < j`) in the vertex's edge ring.
    Crease([usize; 2]),
    /// Three or more sharp edges, or a sharp vertex: the vertex stays put.
    Corner,
}

impl Rule {
    /// The rule for a vertex with the given sharpness and incident edge sharpness (in ring order).
    pub fn determine(vertex_sharpness: f32, edge_sharpness: &[f32]) -> Rule {
        if is_sharp(vertex_sharpness) {
            return Rule::Corner;
        }
        let mut ends = [0usize; 2];
        let mut n = 0usize;
        for (i, &s) in edge_sharpness.iter().enumerate() {
            if is_sharp(s) {
                if n < 2 {
                    ends[n] = i;
                }
                n += 1;
            }
        }
        match n {
            0 => Rule::Smooth,
            1 => Rule::Dart,
            2 => Rule::Crease(ends),
            _ => Rule::Corner,
        }
    }

    /// `true` for [`Rule::Smooth`] and [`Rule::Dart`], which use the smooth mask.
    #[inline]
    pub fn is_smooth(self) -> bool {
        matches!(self, Rule::Smooth | Rule::Dart)
    }

    /// `true` if the two rules give different masks.
    #[inline]
    fn mask_differs(self, other: Rule) -> bool {
        match (self, other) {
            (a, b) if a.is_smooth() && b.is_smooth() => false,
            (Rule::Crease(a), Rule::Crease(b)) => a != b,
            (a, b) => a != b,
        }
    }
}

/// The rules that move one vertex in one refinement step: the parent rule, the child rule and the
/// weight of the parent mask when they differ (a fractional sharpness transition).
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct VertexRules {
    /// Rule of the vertex at this level.
    pub parent: Rule,
    /// Rule of its child at the next level.
    pub child: Rule,
    /// Weight of the parent mask; the child mask gets `1 - parent_weight`.
    pub parent_weight: f64,
}

impl VertexRules {
    /// Determines the rules for a vertex from its sharpness and the sharpness of its edges (ring
    /// order), and writes the child sharpness of those edges into `child_edges`. Inlined (the
    /// uniform one-pass case is small): the slate's general step calls it at every dirty point.
    #[inline]
    pub fn new(
        method: CreaseMethod,
        vertex_sharpness: f32,
        edge_sharpness: &[f32],
        child_edges: &mut [f32],
    ) -> VertexRules {
        if method == CreaseMethod::Uniform
            && !is_sharp(vertex_sharpness)
            && let Some(rules) = Self::uniform_lasting(edge_sharpness, child_edges)
        {
            return rules;
        }
        Self::general(method, vertex_sharpness, edge_sharpness, child_edges)
    }

    /// [`VertexRules::new`] in one pass over the edges for the common case of the uniform rule
    /// at a vertex without sharpness: the child sharpness is the decremented parent's, and where
    /// no sharp edge becomes smooth (or the parent rule is smooth) the child rule is the parent
    /// rule, without a fractional transition. `None` where a crease or corner loses an edge
    /// (then [`VertexRules::general`] decides; `child_edges` is rewritten there).
    #[inline]
    fn uniform_lasting(edge_sharpness: &[f32], child_edges: &mut [f32]) -> Option<VertexRules> {
        debug_assert_eq!(edge_sharpness.len(), child_edges.len());
        let mut ends = [0usize; 2];
        let mut n = 0usize;
        let mut lost = false;
        for (i, (&s, c)) in edge_sharpness
            .iter()
            .zip(child_edges.iter_mut())
            .enumerate()
        {
            *c = decrement(s);
            if is_sharp(s) {
                lost |= !is_sharp(*c);
                if n < 2 {
                    ends[n] = i;
                }
                n += 1;
            }
        }
        let parent = match n {
            0 => Rule::Smooth,
            1 => Rule::Dart,
            _ if lost => return None,
            2 => Rule::Crease(ends),
            _ => Rule::Corner,
        };
        Some(VertexRules {
            parent,
            child: parent,
            parent_weight: 1.0,
        })
    }

    /// [`VertexRules::new`] for any method and sharpness.
    fn general(
        method: CreaseMethod,
        vertex_sharpness: f32,
        edge_sharpness: &[f32],
        child_edges: &mut [f32],
    ) -> VertexRules {
        child_edge_sharpness_around(method, edge_sharpness, child_edges);
        let parent = Rule::determine(vertex_sharpness, edge_sharpness);
        if parent.is_smooth() {
            return VertexRules {
                parent,
                child: parent,
                parent_weight: 1.0,
            };
        }
        let child_vs = decrement(vertex_sharpness);
        let child = Rule::determine(child_vs, child_edges);
        if !parent.mask_differs(child) {
            return VertexRules {
                parent,
                child: parent,
                parent_weight: 1.0,
            };
        }
        let w = fractional_weight(
            method,
            vertex_sharpness,
            child_vs,
            edge_sharpness,
            child_edges,
        );
        VertexRules {
            parent,
            child,
            parent_weight: w as f64,
        }
    }

    /// `true` when no blend is needed.
    #[inline]
    pub fn is_simple(&self) -> bool {
        !self.parent.mask_differs(self.child)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The one-pass uniform case decides exactly as the general rules: rules, weight and child
    /// sharpness, over random vertices of valence 2 to 6 with every kind of sharpness.
    #[test]
    fn uniform_fast_path_matches_the_general_rules() {
        let choices = [0.0f32, 0.0, 0.0, 0.25, 0.5, 1.0, 1.5, 2.0, 3.0, 10.0, 12.0];
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = |k: usize| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 33) as usize % k
        };
        let mut fast_cases = 0;
        for _ in 0..4000 {
            let m = 2 + next(5);
            let vs = if next(4) == 0 {
                choices[next(choices.len())]
            } else {
                0.0
            };
            let es: Vec<f32> = (0..m).map(|_| choices[next(choices.len())]).collect();
            let (mut c0, mut c1) = (vec![-1.0; m], vec![-2.0; m]);
            let a = VertexRules::new(CreaseMethod::Uniform, vs, &es, &mut c0);
            let b = VertexRules::general(CreaseMethod::Uniform, vs, &es, &mut c1);
            assert_eq!(a, b, "vertex {vs} edges {es:?}");
            assert_eq!(c0, c1, "vertex {vs} edges {es:?}");
            fast_cases +=
                usize::from(vs == 0.0 && VertexRules::uniform_lasting(&es, &mut c1).is_some());
        }
        assert!(fast_cases > 1000, "{fast_cases}");
    }

    #[test]
    fn decrement_rules() {
        assert_eq!(decrement(0.0), 0.0);
        assert_eq!(decrement(0.5), 0.0);
        assert_eq!(decrement(1.0), 0.0);
        assert_eq!(decrement(2.5), 1.5);
        assert_eq!(decrement(10.0), 10.0);
        assert_eq!(decrement(25.0), 10.0);
    }

    #[test]
    fn chaikin_averages_along_crease() {
        // Edge 3 next to edge 1: 0.75*3 + 0.25*1 - 1 = 1.5; edge 1 next to 3: 0.75 + 0.75 - 1 = 0.5.
        let mut c = [0.0; 4];
        child_edge_sharpness_around(CreaseMethod::Chaikin, &[3.0, 0.0, 1.0, 0.0], &mut c);
        assert_eq!(c, [1.5, 0.0, 0.5, 0.0]);
        // A lone semi-sharp edge and infinite edges decay uniformly.
        child_edge_sharpness_around(CreaseMethod::Chaikin, &[3.0, 10.0, 0.0, 0.0], &mut c);
        assert_eq!(c, [2.0, 10.0, 0.0, 0.0]);
        child_edge_sharpness_around(CreaseMethod::Uniform, &[3.0, 0.0, 1.0, 0.0], &mut c);
        assert_eq!(c, [2.0, 0.0, 0.0, 0.0]);
    }

    #[test]
    fn rule_determination() {
        assert_eq!(Rule::determine(0.0, &[0.0; 4]), Rule::Smooth);
        assert_eq!(Rule::determine(0.0, &[0.0, 2.0, 0.0, 0.0]), Rule::Dart);
        assert_eq!(
            Rule::determine(0.0, &[0.0, 2.0, 0.0, 1.0]),
            Rule::Crease([1, 3])
        );
        assert_eq!(Rule::determine(0.0, &[1.0, 2.0, 0.0, 1.0]), Rule::Corner);
        assert_eq!(Rule::determine(0.5, &[0.0; 4]), Rule::Corner);
    }

    #[test]
    fn fractional_transitions() {
        let mut c = [0.0; 4];
        // A crease of sharpness 0.3 becomes smooth: 30 % crease mask, 70 % smooth mask.
        let r = VertexRules::new(CreaseMethod::Uniform, 0.0, &[0.3, 0.0, 0.3, 0.0], &mut c);
        assert_eq!(r.parent, Rule::Crease([0, 2]));
        assert_eq!(r.child, Rule::Smooth);
        assert!((r.parent_weight - 0.3).abs() < 1e-7);
        // Sharpness 2 stays a crease for this step: no blend.
        let r = VertexRules::new(CreaseMethod::Uniform, 0.0, &[2.0, 0.0, 2.0, 0.0], &mut c);
        assert!(r.is_simple());
        // Sharpness exactly 1: the child is smooth, weight 1 (full crease this step).
        let r = VertexRules::new(CreaseMethod::Uniform, 0.0, &[1.0, 0.0, 1.0, 0.0], &mut c);
        assert_eq!(r.child, Rule::Smooth);
        assert_eq!(r.parent_weight, 1.0);
        // A semi-sharp corner of 0.25 over a smooth vertex.
        let r = VertexRules::new(CreaseMethod::Uniform, 0.25, &[0.0; 4], &mut c);
        assert_eq!((r.parent, r.child), (Rule::Corner, Rule::Smooth));
        assert!((r.parent_weight - 0.25).abs() < 1e-7);
    }

    #[test]
    fn edge_weights() {
        assert_eq!(edge_crease_weight(0.0, [0.0; 2]), 0.0);
        assert_eq!(edge_crease_weight(0.4, [0.0; 2]), 0.4);
        // Uniform: sharpness 1 decays to 0 at both ends, a full crease this step.
        assert_eq!(edge_crease_weight(1.0, [0.0; 2]), 1.0);
        assert_eq!(edge_crease_weight(2.0, [1.0; 2]), 1.0);
        assert_eq!(edge_crease_weight(0.9, [0.1, 0.2]), 1.0);
        assert_eq!(edge_crease_weight(0.9, [0.1, 0.0]), 0.9);
        // Chaikin: sharpness 1.25 next to a crease of 0.25 decays to smooth at that end
        // (0.75 * 1.25 + 0.25 * 0.25 - 1 = 0): OpenSubdiv blends with the unclamped weight 1.25.
        let mut c = [0.0; 3];
        child_edge_sharpness_around(CreaseMethod::Chaikin, &[1.25, 0.25, 0.0], &mut c);
        assert_eq!(c, [0.0, 0.0, 0.0]);
        assert_eq!(edge_crease_weight(1.25, [c[0], 0.5]), 1.25);
        assert_eq!(
            edge_crease_weight(SHARPNESS_INFINITE, [SHARPNESS_INFINITE; 2]),
            1.0
        );
    }
}
