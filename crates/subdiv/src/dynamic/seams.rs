//! One depth per frame around each non-manifold edge of the cage.
//!
//! A non-manifold cage is refined as manifold pieces (`PolygonSoup::split_nonmanifold`, as
//! OpenSubdiv refines it): every piece has its own copy of a non-manifold edge, an infinitely
//! sharp edge whose vertices coincide with the other copies'. Depth assignment and the stitch
//! fans join depths only within one piece, so faces of different depths on the copies would
//! put 2^depth segments each on the one edge of the surface: T-junctions, a crack (issue 13
//! item 6). An infinitely sharp edge's limit curve depends only on its crease points (Settgast
//! et al. 2004, Section 3.3; the crease rules of DeRose et al. 1998), so copies drawn at the
//! same depth give the same points; [`Seams::raise`] draws every face on the copies of one
//! edge at the largest of their depths, after assignment and before stitching.

use std::collections::HashMap;

use subdiv_mesh::{FaceId, Mesh, SHARPNESS_INFINITE};
use subdiv_slate::Depth;

/// The faces on each group of coincident, infinitely sharp cage edges (the copies of one
/// non-manifold edge); empty for a manifold cage.
#[derive(Debug, Default, Clone)]
pub(crate) struct Seams {
    groups: Vec<Vec<FaceId>>,
}

impl Seams {
    /// Groups `mesh`'s infinitely sharp edges by their end points' bits (copies of a
    /// non-manifold edge coincide); keeps the groups of two or more edges.
    pub(crate) fn new(mesh: &Mesh) -> Seams {
        let key = |v| mesh.position(v).to_array().map(f32::to_bits);
        let mut by_ends: HashMap<([u32; 3], [u32; 3]), Vec<FaceId>> = HashMap::new();
        let mut edges: HashMap<([u32; 3], [u32; 3]), u32> = HashMap::new();
        for e in mesh.edges() {
            if mesh.edge_sharpness(e) < SHARPNESS_INFINITE {
                continue;
            }
            let h = e.halfedge(0);
            let (a, b) = (key(mesh.from(h)), key(mesh.to(h)));
            let ends = (a.min(b), a.max(b));
            *edges.entry(ends).or_default() += 1;
            let faces = by_ends.entry(ends).or_default();
            for side in 0..2 {
                let f = mesh.face(e.halfedge(side));
                if f.is_some() && !mesh.is_hole(f) {
                    faces.push(f);
                }
            }
        }
        let mut groups: Vec<Vec<FaceId>> = by_ends
            .into_iter()
            .filter(|(ends, faces)| edges[ends] > 1 && faces.len() > 1)
            .map(|(_, faces)| faces)
            .collect();
        groups.sort_unstable_by_key(|g| g[0].idx());
        Seams { groups }
    }

    /// Raises the drawn (`active`) faces of every group to the group's largest drawn depth,
    /// until no group changes (a face may lie on several non-manifold edges).
    pub(crate) fn raise(&self, depth: &mut [Depth], active: &[bool]) {
        let mut changed = !self.groups.is_empty();
        while changed {
            changed = false;
            for g in &self.groups {
                let drawn = || g.iter().filter(|f| active[f.idx()]);
                let Some(most) = drawn().map(|f| depth[f.idx()]).max() else {
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
