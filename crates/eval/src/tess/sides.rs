//! A unit's sides: the points along a cage edge between two steps of its rate, and where each
//! point's normal is to be taken on this side of a crease.

use subdiv_mesh::{FaceId, HalfedgeId, VertexId};
use subdiv_rules::Scheme;

use super::Builder;
use crate::{Domain, Query};

/// One unit's sides: point indices from each corner to the next, with the parameter of each
/// point in the unit's face where its normal is to be taken on this side.
pub(super) struct Side {
    pub(super) points: Vec<u32>,
    pub(super) sided: Vec<Option<Query>>,
}

/// How far into its face (in the face's parameter) the one-sided normal of a point on a
/// semi-sharp crease is taken: just beyond the crease's band, `2 · 2^-s` for sharpness `s`
/// (the crease rule holds for `s` levels, then smooth rules round it off over about one
/// level's cells), at most half the spacing `1 / rate` of the points next to it, unless the
/// tessellation resolves the band (two steps or more across it: 0, the exact normals). The
/// exact limit normal on a semi-sharp crease is the smooth one, yet the surface turns within
/// the band: a band the tessellation does not resolve would be drawn as a wide blend of
/// normals across each triangle, where the surface shows a crease, and one resolved by a single
/// step puts points inside it where neither side's normal is right. Infinitely sharp creases
/// (0 here) get their one-sided normal from the face itself.
fn semi_sharp_offset(sharpness: f32, rate: u32) -> f64 {
    if !(sharpness > 0.0 && sharpness < subdiv_mesh::SHARPNESS_INFINITE) {
        return 0.0;
    }
    let band = 2.0 * (-f64::from(sharpness)).exp2();
    let spacing = 1.0 / f64::from(rate.max(1));
    if band < 2.0 * spacing {
        band.min(0.5 * spacing)
    } else {
        0.0
    }
}

impl Builder<'_> {
    /// Whether a point's normal may differ between the faces around it (at every vertex of a
    /// bilinear cage: its patches meet with a crease at every edge).
    pub(super) fn sharp_vertex(&self, v: VertexId) -> bool {
        let m = self.mesh;
        self.scheme == Scheme::Bilinear
            || m.vertex_sharpness(v) > 0.0
            || m.whole_vertex_edges(v).is_some()
            || m.crease_ends(v).is_some()
            || m.outgoing(v).any(|h| m.edge_sharpness(h.edge()) > 0.0)
    }

    /// [`semi_sharp_offset`] at cage vertex `v` for points `1 / rate` apart: that of the widest
    /// band among its semi-sharp edges and its own semi-sharp sharpness (0 where there is none).
    fn vertex_offset(&self, v: VertexId, rate: u32) -> f64 {
        let m = self.mesh;
        let semi = |s: f32| s > 0.0 && s < subdiv_mesh::SHARPNESS_INFINITE;
        let least = m
            .outgoing(v)
            .map(|h| m.edge_sharpness(h.edge()))
            .chain(std::iter::once(m.vertex_sharpness(v)))
            .filter(|&s| semi(s))
            .fold(f32::INFINITY, f32::min);
        if least.is_finite() {
            semi_sharp_offset(least, rate)
        } else {
            0.0
        }
    }

    /// The side along half-edge `k` of face `f` from step `a` to step `b` of its rate.
    pub(super) fn edge_side(
        &self,
        f: FaceId,
        h: HalfedgeId,
        k: usize,
        domain: &Domain,
        (a, b): (u32, u32),
    ) -> Side {
        let r = self.rate[h.edge().idx()];
        let points: Vec<u32> = (a..=b).map(|m| self.edge_point(h, m)).collect();
        // Bilinear patches meet with a crease at every edge: every edge point is one-sided.
        let bilinear = self.scheme == Scheme::Bilinear;
        let sharpness = self.mesh.edge_sharpness(h.edge());
        let sharp_edge = bilinear || sharpness > 0.0;
        let inward = if bilinear {
            0.0
        } else {
            semi_sharp_offset(sharpness, r)
        };
        let ends = [self.mesh.from(h), self.mesh.to(h)];
        // At a cage vertex on a semi-sharp crease: beyond the band of each of the face's two
        // sides there, along the diagonal into the face.
        let corner_inward = if bilinear {
            [0.0; 2]
        } else {
            ends.map(|v| self.vertex_offset(v, r) * std::f64::consts::SQRT_2)
        };
        let sided = (a..=b)
            .map(|m| {
                let (corner, offset) = if m == 0 {
                    (Some(ends[0]), corner_inward[0])
                } else if m == r {
                    (Some(ends[1]), corner_inward[1])
                } else {
                    (None, inward)
                };
                let sharp = sharp_edge || corner.is_some_and(|v| self.sharp_vertex(v));
                sharp.then(|| {
                    let [u, v] = domain.edge_point(k, f64::from(m) / f64::from(r));
                    match domain {
                        // On a semi-sharp crease whose band the steps do not resolve: the
                        // normal just beyond the band, towards the face's centre (from a
                        // corner, at most half way there).
                        Domain::Quad | Domain::Triangle if offset > 0.0 => {
                            let [cu, cv] = domain.centre();
                            let (du, dv) = (cu - u, cv - v);
                            let len = du.hypot(dv).max(1e-12);
                            let t = if corner.is_some() {
                                offset.min(0.5 * len)
                            } else {
                                offset
                            };
                            Query::new(f.0, u + t * du / len, v + t * dv / len)
                        }
                        _ => Query::new(f.0, u, v),
                    }
                })
            })
            .collect();
        Side { points, sided }
    }
}
