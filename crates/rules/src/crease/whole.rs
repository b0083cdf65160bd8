//! The vertex rules at a copy of a non-manifold crease vertex whose semi-sharp edges lie in
//! several copies ([`Mesh::whole_vertex_edges`]).
//!
//! OpenSubdiv 3.5 decides a vertex's rule (`Sdc::Crease::DetermineVertexVertexRule`), its
//! fractional weight (`ComputeFractionalWeightAtVertex`) and the Chaikin decay of its edges
//! (`SubdivideEdgeSharpnessesAroundVertex`) over all the vertex's edges. A copy sees only its
//! own ring; so wherever a vertex carries the whole vertex's semi-sharp values, the rules read
//! its ring with its own semi-sharp edges taken out and the whole vertex's values put in, and
//! each own semi-sharp edge takes the child sharpness of its value among them. Every copy
//! then decides from the same values in the same order and gets the same rules and weights to
//! the bit; the crease rule reads the far ends of the two infinitely sharp edges, which every
//! copy holds.

use subdiv_mesh::{CreaseMethod, HalfedgeId, Mesh};

use super::{Rule, VertexRules, child_edge_sharpness_around, is_semi_sharp, semi_sharp_sum};

/// The most edges plus whole-vertex values kept on the stack; larger rings allocate.
const STACK: usize = 32;

impl VertexRules {
    /// [`VertexRules::new`] at a vertex with the whole vertex's semi-sharp values `whole`
    /// (sorted, as [`Mesh::whole_vertex_edges`] keeps them): the rules of the whole vertex,
    /// the child sharpness of the ring's own edges in `child_edges`, and the whole vertex's
    /// child values (the sharp ones, sorted) in `child_whole`.
    pub fn with_whole(
        method: CreaseMethod,
        vertex_sharpness: f32,
        edge_sharpness: &[f32],
        whole: &[f32],
        child_edges: &mut [f32],
        child_whole: &mut Vec<f32>,
    ) -> VertexRules {
        let n = edge_sharpness.len();
        let m = n + whole.len();
        let (mut ext_s, mut cext_s) = ([0.0f32; STACK], [0.0f32; STACK]);
        let (mut ext_h, mut cext_h) = (Vec::new(), Vec::new());
        let (ext, cext): (&mut [f32], &mut [f32]) = if m <= STACK {
            (&mut ext_s[..m], &mut cext_s[..m])
        } else {
            ext_h.resize(m, 0.0);
            cext_h.resize(m, 0.0);
            (&mut ext_h, &mut cext_h)
        };
        for (e, &s) in ext.iter_mut().zip(edge_sharpness) {
            *e = if is_semi_sharp(s) { 0.0 } else { s };
        }
        ext[n..].copy_from_slice(whole);
        let mut rules = VertexRules::new(method, vertex_sharpness, ext, cext);
        // The crease's two edges are the ring's own infinitely sharp ones, but at a crease copy
        // that lacks them (`Mesh::crease_copy_of`), whose point is the other copy's: there a
        // crease through a whole-vertex value is no rule of this ring.
        let own = |r: Rule| match r {
            Rule::Crease([_, j]) if j >= n => Rule::Corner,
            r => r,
        };
        (rules.parent, rules.child) = (own(rules.parent), own(rules.child));
        for (i, (c, &s)) in child_edges.iter_mut().zip(edge_sharpness).enumerate() {
            *c = if is_semi_sharp(s) {
                // Its value is among the whole vertex's (equal values decay alike).
                match whole.iter().position(|w| w.to_bits() == s.to_bits()) {
                    Some(j) => cext[n + j],
                    None => {
                        debug_assert!(false, "edge sharpness {s} not among {whole:?}");
                        cext[i]
                    }
                }
            } else {
                cext[i]
            };
        }
        child_whole.clear();
        child_whole.extend(cext[n..].iter().copied().filter(|&s| is_semi_sharp(s)));
        child_whole.sort_unstable_by(f32::total_cmp);
        rules
    }
}

/// The whole vertex's values one level down ([`VertexRules::with_whole`]'s `child_whole`, the
/// same bits: the ring's own edges do not enter the decay of the whole vertex's values).
pub fn child_whole_vertex_edges(method: CreaseMethod, whole: &[f32]) -> Vec<f32> {
    let mut child = vec![0.0f32; whole.len()];
    child_edge_sharpness_around(method, whole, &mut child);
    child.retain(|&s| is_semi_sharp(s));
    child.sort_unstable_by(f32::total_cmp);
    child
}

/// [`Rule::determine`] at a vertex with the whole vertex's values `whole` (`None`: the ring
/// alone).
pub fn rule_with_whole(
    vertex_sharpness: f32,
    edge_sharpness: &[f32],
    whole: Option<&[f32]>,
) -> Rule {
    match whole {
        None => Rule::determine(vertex_sharpness, edge_sharpness),
        Some(whole) => {
            let mut ext: Vec<f32> = edge_sharpness
                .iter()
                .map(|&s| if is_semi_sharp(s) { 0.0 } else { s })
                .collect();
            ext.extend_from_slice(whole);
            Rule::determine(vertex_sharpness, &ext)
        }
    }
}

/// The (sum, count) of the semi-sharp edges at the end of `h` other than `h`'s own: what the
/// Chaikin rule averages there (the far end of a ring's edge). At a vertex with
/// [`Mesh::whole_vertex_edges`], the whole vertex's values, summed as
/// [`child_edge_sharpness_around`] sums them.
pub fn far_semi_sharp(mesh: &Mesh, h: HalfedgeId) -> (f32, u32) {
    let w = mesh.to(h);
    let own = mesh.edge_sharpness(h.edge());
    if let Some(whole) = mesh.whole_vertex_edges(w) {
        let (sum, count) = semi_sharp_sum(whole);
        return if is_semi_sharp(own) {
            (sum - own, count - 1)
        } else {
            (sum, count)
        };
    }
    let mut sum = 0.0f32;
    let mut n = 0u32;
    for g in mesh.outgoing(w) {
        let s = mesh.edge_sharpness(g.edge());
        if g.edge() != h.edge() && is_semi_sharp(s) {
            sum += s;
            n += 1;
        }
    }
    (sum, n)
}

/// [`far_semi_sharp`] from a vertex's ring: the (sum, count) of the semi-sharp values in
/// `sharp` but `sharp[skip]` (`skip` out of range: all of them), or of the whole vertex's
/// values `whole` less the value of `sharp[skip]` where `whole` is not empty.
pub fn semi_sharp_excluding(sharp: &[f32], skip: usize, whole: &[f32]) -> (f32, u32) {
    if !whole.is_empty() {
        let (sum, count) = semi_sharp_sum(whole);
        return match sharp.get(skip) {
            Some(&s) if is_semi_sharp(s) => (sum - s, count - 1),
            _ => (sum, count),
        };
    }
    let mut sum = 0.0f32;
    let mut n = 0u32;
    for (r, &s) in sharp.iter().enumerate() {
        if r != skip && is_semi_sharp(s) {
            sum += s;
            n += 1;
        }
    }
    (sum, n)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three copies of a crease vertex (infinitely sharp edges first and last), 1.9, 1.1 and 1.1
    /// in one copy each: every copy gets the whole vertex's rules, weight and decay.
    #[test]
    fn every_copy_gets_the_whole_vertex_rules() {
        let whole = [1.1f32, 1.1, 1.9];
        let one = |own: f32| {
            let ring = [10.0, own, 0.0, 10.0];
            let (mut c, mut cw) = ([0.0; 4], Vec::new());
            let r =
                VertexRules::with_whole(CreaseMethod::Uniform, 0.0, &ring, &whole, &mut c, &mut cw);
            (r, c, cw)
        };
        let (r0, c0, w0) = one(1.9);
        assert_eq!(r0.parent, Rule::Corner);
        assert!((c0[1] - 0.9).abs() < 1e-6 && c0[0] == 10.0 && c0[3] == 10.0);
        let (r1, c1, w1) = one(1.1);
        assert_eq!(r0, r1);
        assert!((c1[1] - 0.1).abs() < 1e-6);
        assert_eq!(w0, w1);
        assert_eq!(w0, child_whole_vertex_edges(CreaseMethod::Uniform, &whole));
        // One level down all three run out together: corner to crease by their average.
        let ring = [10.0, c0[1], 0.0, 10.0];
        let (mut c, mut cw) = ([0.0; 4], Vec::new());
        let r = VertexRules::with_whole(CreaseMethod::Uniform, 0.0, &ring, &w0, &mut c, &mut cw);
        assert_eq!((r.parent, r.child), (Rule::Corner, Rule::Crease([0, 3])));
        assert!(
            (r.parent_weight - (0.9 + 0.1 + 0.1) / 3.0).abs() < 1e-6,
            "{r:?}"
        );
        assert!(cw.is_empty());
    }

    /// Chaikin: an own edge decays by the average of the whole vertex's other values.
    #[test]
    fn chaikin_decays_by_the_whole_vertex() {
        let whole = [1.5f32, 2.0];
        let ring = [10.0, 2.0, 10.0];
        let (mut c, mut cw) = ([0.0; 3], Vec::new());
        VertexRules::with_whole(CreaseMethod::Chaikin, 0.0, &ring, &whole, &mut c, &mut cw);
        assert_eq!(c[1], 0.75 * 2.0 + 0.25 * 1.5 - 1.0);
        assert_eq!(cw, vec![0.625, 0.875]);
        assert_eq!(
            rule_with_whole(0.0, &[10.0, 0.5, 10.0], Some(&[0.5, 0.5])),
            Rule::Corner
        );
        assert_eq!(
            rule_with_whole(0.0, &[10.0, 0.0, 10.0], None),
            Rule::Crease([0, 2])
        );
    }
}
