//! One depth per frame around each non-manifold edge of the cage.
//!
//! A non-manifold cage is refined as manifold pieces (`PolygonSoup::split_nonmanifold`, as
//! OpenSubdiv refines it): every piece has its own copy of a non-manifold edge, an infinitely
//! sharp edge whose vertices coincide with the other copies'. Depth assignment and the stitch
//! fans join depths only within one piece, so faces of different depths on the copies would
//! put 2^depth segments each on the one edge of the surface: T-junctions, a crack. An
//! infinitely sharp edge's limit curve depends only on its crease points (Settgast et al. 2004,
//! Section 3.3; the crease rules of DeRose et al. 1998), so copies drawn at the
//! same depth give the same points, to the bit since the tessellators write them from the
//! chain (`subdiv_rules::SeamCurves`); [`Seams::raise`] draws every face on the copies of one
//! edge at the largest of their depths, after assignment and before stitching.

use subdiv_mesh::{FaceId, Mesh};
use subdiv_rules::{Depth, SeamCurves};

/// The faces on each group of coincident, infinitely sharp cage edges (the copies of one
/// non-manifold edge); empty for a manifold cage.
#[derive(Debug, Default, Clone)]
pub struct Seams {
    groups: Vec<Vec<FaceId>>,
}

impl Seams {
    /// The faces on each of `mesh`'s seams (`subdiv_rules::SeamCurves::groups`: infinitely
    /// sharp edges grouped by their end points' bits, as the copies of a non-manifold edge
    /// coincide); keeps the groups with two or more faces.
    pub fn new(mesh: &Mesh) -> Seams {
        let mut groups: Vec<Vec<FaceId>> = SeamCurves::new(mesh)
            .groups()
            .iter()
            .map(|edges| {
                edges
                    .iter()
                    .flat_map(|e| [e.halfedge(0), e.halfedge(1)])
                    .map(|h| mesh.face(h))
                    .filter(|&f| f.is_some() && !mesh.is_hole(f))
                    .collect::<Vec<FaceId>>()
            })
            .filter(|faces| faces.len() > 1)
            .collect();
        groups.sort_unstable_by_key(|g| g[0].idx());
        Seams { groups }
    }

    /// Raises the drawn (`active`) faces of every group to the group's largest drawn depth,
    /// until no group changes (a face may lie on several non-manifold edges). A face's depth
    /// counts as at least `min_depth(face)` (the stitcher's smallest depth for it: 1 for a
    /// face tessellated through its level-1 quads), so that the stitcher's clamp leaves the
    /// group at one depth.
    pub fn raise(&self, depth: &mut [Depth], active: &[bool], min_depth: impl Fn(usize) -> Depth) {
        let mut changed = !self.groups.is_empty();
        while changed {
            changed = false;
            for g in &self.groups {
                let drawn = || g.iter().filter(|f| active[f.idx()]);
                let at = |f: &FaceId| depth[f.idx()].max(min_depth(f.idx()));
                let Some(most) = drawn().map(at).max() else {
                    continue;
                };
                for f in g {
                    if active[f.idx()] && depth[f.idx()] < most {
                        depth[f.idx()] = most;
                        changed = true;
                    }
                }
            }
        }
    }
}
