//! Points on the copies of one non-manifold edge, bit-identical in every copy.
//!
//! A non-manifold cage is refined as manifold pieces (`subdiv_mesh::PolygonSoup::split_nonmanifold`,
//! as OpenSubdiv refines it): every piece holds its own copy of a non-manifold edge, an
//! infinitely sharp edge whose end points coincide with the other copies'. A *seam* is such a
//! group of coincident, infinitely sharp edges. Each copy is tessellated by its own piece's
//! patches, which gather it in their own orientation, hold positions relative to their own
//! origin and may be evaluated at different depths (cached blocks): the copies' limit points
//! agree only to rounding, and welding the pieces leaves cracks.
//!
//! The limit curve of an infinitely sharp edge depends on the crease points along it only:
//! sharp edges are split at their midpoints and a crease vertex moves by `(1, 6, 1) / 8` of its
//! two sharp neighbours, a corner stays (DeRose, Kass & Truong 1998, Section 3; the same rules
//! in Catmull-Clark and Loop, OpenSubdiv's `Sdc::Crease`). That is cubic B-spline subdivision
//! of the *crease chain*, whose limit is the uniform cubic B-spline of the chain's points, with
//! a corner end reflected (`2 P_1 - P_2`, which keeps the corner and the midpoints). So
//! [`SeamCurves`] evaluates every point of a seam copy from the cage points of its chain alone,
//! in `f64`, in one canonical orientation (by the bits of the points, the same in every copy)
//! and at the dyadic parameter of the point: every copy, every piece, every depth and every
//! orientation gives the same bits. A chain vertex must be a corner (infinite vertex
//! sharpness, or three or more infinitely sharp edges) or a crease (exactly two infinitely
//! sharp edges). A crease vertex may carry a semi-sharp vertex sharpness or semi-sharp edges:
//! it is a corner while they last, then blends into the crease rule by the average of what
//! runs out last (OpenSubdiv's fractional weight, `Sdc::Crease::ComputeFractionalWeightAtVertex`),
//! taken as the one vertex sharpness with that schedule (`crease::crease_vertex_schedule`, the
//! same bits in every copy of a non-manifold crease vertex, whichever holds the edges),
//! which still reads the chain's points only; the segment is refined in 1D until the
//! sharpness has run out, then evaluated as a B-spline. A seam where a copy's chain does not
//! qualify, or where the copies' chains differ, is left to the tessellators (they agree with
//! the limit to rounding only there).

use std::collections::HashMap;

use glam::DVec3;
use subdiv_mesh::{EdgeId, HalfedgeId, Mesh, VertexId};

use crate::Depth;
use crate::crease::{crease_vertex_schedule, decrement, is_infinite};

/// What lies beyond a chain vertex along its crease chain: nothing (a corner) or the far end of
/// its other infinitely sharp edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ChainEnd {
    Corner,
    Crease(VertexId),
}

/// A chain vertex: what lies beyond it on each side and its vertex sharpness (a crease's
/// semi-sharp schedule; 0 for a corner, which needs none).
type Ends = (ChainEnd, ChainEnd, f32);

/// One seam copy: its end vertices (from and to of the edge's even half-edge), what lies
/// beyond each along the chain, and their vertex sharpness (see [`Ends`]).
#[derive(Clone, Copy, Debug)]
struct Curve {
    a: VertexId,
    b: VertexId,
    beyond_a: ChainEnd,
    beyond_b: ChainEnd,
    sharp: [f32; 2],
}

/// The seams of a mesh (groups of coincident, infinitely sharp edges: the copies of one
/// non-manifold edge) and the exact, copy-independent points on them (see the module notes).
/// Holds topology only; positions are read from the mesh at evaluation, so it stays valid while
/// the cage's points move, as long as coincident copies move together.
#[derive(Clone, Debug, Default)]
pub struct SeamCurves {
    /// Per mesh edge: its index in `curves`, or `u32::MAX` (empty: no seams).
    edge_curve: Vec<u32>,
    curves: Vec<Curve>,
    /// Per mesh vertex on a seam: its chain ends (empty: no seams).
    vertex_ends: HashMap<VertexId, Ends>,
    /// The copies of each seam (two or more edges each), whether evaluated here or not.
    groups: Vec<Vec<EdgeId>>,
}

/// Bits of a point, the key copies are matched and ordered by (`-0.0` as `0.0`).
#[inline]
fn key(p: glam::Vec3) -> [u32; 3] {
    p.to_array().map(|x| if x == 0.0 { 0 } else { x.to_bits() })
}

/// A seam's crease chain in one orientation: the edge's ends `p1`, `p2` and the crease points
/// beyond them (`None` at a corner end), in `f64`.
#[derive(Clone, Copy, Debug)]
struct Chain {
    beyond1: Option<DVec3>,
    p1: DVec3,
    p2: DVec3,
    beyond2: Option<DVec3>,
}

impl Chain {
    /// The same chain read from `p2` to `p1`.
    fn reversed(self) -> Chain {
        Chain {
            beyond1: self.beyond2,
            p1: self.p2,
            p2: self.p1,
            beyond2: self.beyond1,
        }
    }

    /// The points' bits (`f32`, signed zeros as one), ends first: the order the canonical
    /// orientation is chosen by.
    fn keys(&self) -> [Option<[u32; 3]>; 4] {
        [Some(self.p1), Some(self.p2), self.beyond1, self.beyond2]
            .map(|x| x.map(|y| key(y.as_vec3())))
    }
}

/// The chain ends of vertex `v` if its rule reads the chain only at every level (see the
/// module notes): a corner, or a crease with the far ends of its two infinitely sharp edges and
/// its vertex sharpness.
fn chain_ends(mesh: &Mesh, v: VertexId) -> Option<Ends> {
    let vs = mesh.vertex_sharpness(v);
    if let Some(ends) = mesh.crease_ends(v) {
        // A copy lacking the crease's edges moves by the crease rule over them.
        let values = mesh.whole_vertex_edges(v).unwrap_or(&[]);
        let schedule = crease_vertex_schedule(mesh.options().crease, vs, values);
        let [a, b] = ends.map(|h| ChainEnd::Crease(mesh.to(h)));
        return Some((a, b, schedule));
    }
    let mut sharp = [VertexId::NONE; 2];
    let mut count = 0usize;
    let mut ring = Vec::new();
    for h in mesh.outgoing(v) {
        let s = mesh.edge_sharpness(h.edge());
        if is_infinite(s) {
            if count < 2 {
                sharp[count] = mesh.to(h);
            }
            count += 1;
        }
        ring.push(s);
    }
    if is_infinite(vs) || count >= 3 {
        Some((ChainEnd::Corner, ChainEnd::Corner, 0.0))
    } else if count == 2 {
        let ends = (ChainEnd::Crease(sharp[0]), ChainEnd::Crease(sharp[1]));
        // Semi-sharp edges keep it a corner for a while too: one vertex sharpness with the
        // same schedule, the same bits in every copy that has it.
        // At a copy given the whole vertex's values, those (its own among them).
        let values = mesh.whole_vertex_edges(v).unwrap_or(&ring);
        let schedule = crease_vertex_schedule(mesh.options().crease, vs, values);
        Some((ends.0, ends.1, schedule))
    } else {
        None
    }
}

/// What lies beyond `v` on the chain through the seam edge from `v` to `other`: the crease end
/// that is not `other` (nor a copy of it, where the ends are a crease copy's other copy's).
fn beyond(mesh: &Mesh, ends: Ends, other: VertexId) -> ChainEnd {
    match ends {
        (ChainEnd::Crease(x), ChainEnd::Crease(y), _) => {
            if x == other || key(mesh.position(x)) == key(mesh.position(other)) {
                ChainEnd::Crease(y)
            } else {
                ChainEnd::Crease(x)
            }
        }
        _ => ChainEnd::Corner,
    }
}

impl SeamCurves {
    /// Finds the seams of `mesh`. Cheap and empty for a cage without coincident infinitely
    /// sharp edges.
    pub fn new(mesh: &Mesh) -> SeamCurves {
        let mut by_ends: HashMap<([u32; 3], [u32; 3]), Vec<EdgeId>> = HashMap::new();
        for e in mesh.edges() {
            if !is_infinite(mesh.edge_sharpness(e)) {
                continue;
            }
            let [a, b] = mesh.edge_vertices(e);
            let (ka, kb) = (key(mesh.position(a)), key(mesh.position(b)));
            by_ends.entry((ka.min(kb), ka.max(kb))).or_default().push(e);
        }
        let mut groups: Vec<Vec<EdgeId>> = by_ends.into_values().filter(|g| g.len() > 1).collect();
        if groups.is_empty() {
            return SeamCurves::default();
        }
        groups.sort_unstable_by_key(|g| g[0]);
        let mut s = SeamCurves {
            edge_curve: vec![u32::MAX; mesh.num_edges()],
            groups,
            ..SeamCurves::default()
        };
        for g in 0..s.groups.len() {
            s.add_group(mesh, g);
        }
        s
    }

    /// Evaluates the copies of group `g` here when every copy's chain qualifies and all are the
    /// same chain (the same points in canonical order).
    fn add_group(&mut self, mesh: &Mesh, g: usize) {
        let mut curves = Vec::with_capacity(self.groups[g].len());
        let mut ends = Vec::with_capacity(2 * self.groups[g].len());
        type Bits = ([Option<[u32; 3]>; 4], [u32; 2]);
        let mut canon: Option<Bits> = None;
        for &e in &self.groups[g] {
            let [a, b] = mesh.edge_vertices(e);
            let (Some(ea), Some(eb)) = (chain_ends(mesh, a), chain_ends(mesh, b)) else {
                return;
            };
            let c = Curve {
                a,
                b,
                beyond_a: beyond(mesh, ea, b),
                beyond_b: beyond(mesh, eb, a),
                sharp: [ea.2, eb.2],
            };
            let (chain, sharp, _) = Self::canonical(mesh, &c);
            let bits = (chain.keys(), sharp.map(f32::to_bits));
            if canon.is_some_and(|k| k != bits) {
                return;
            }
            canon = Some(bits);
            curves.push((e, c));
            ends.push((a, ea));
            ends.push((b, eb));
        }
        for (e, c) in curves {
            self.edge_curve[e.idx()] = self.curves.len() as u32;
            self.curves.push(c);
        }
        self.vertex_ends.extend(ends);
    }

    /// `true` when the mesh has no seam evaluated here.
    pub fn is_empty(&self) -> bool {
        self.curves.is_empty()
    }

    /// The copies of every seam (coincident infinitely sharp edges, two or more per group), in
    /// order of their first edge.
    pub fn groups(&self) -> &[Vec<EdgeId>] {
        &self.groups
    }

    /// The curve's control points `[P0, P1, P2, P3]` (`None`: a corner end, reflected) and
    /// the vertex sharpness of `P1` and `P2`, in canonical order, and whether that order runs
    /// against the edge's even half-edge.
    fn canonical(mesh: &Mesh, c: &Curve) -> (Chain, [f32; 2], bool) {
        let p = |v: VertexId| mesh.position(v).as_dvec3();
        let end = |e: ChainEnd| match e {
            ChainEnd::Corner => None,
            ChainEnd::Crease(v) => Some(p(v)),
        };
        let fwd = Chain {
            beyond1: end(c.beyond_a),
            p1: p(c.a),
            p2: p(c.b),
            beyond2: end(c.beyond_b),
        };
        let rev = fwd.reversed();
        let k = |q: &Chain, s: [f32; 2]| (q.keys(), s.map(f32::to_bits));
        let [s1, s2] = c.sharp;
        if k(&rev, [s2, s1]) < k(&fwd, [s1, s2]) {
            (rev, [s2, s1], true)
        } else {
            (fwd, [s1, s2], false)
        }
    }

    /// The limit point of seam vertex `v`, the same bits in every copy: the vertex itself at a
    /// corner; at a crease refined with its neighbours while its vertex sharpness lasts, then
    /// `(P_- + 4 P + P_+) / 6`; `None` off the seams.
    pub fn vertex_point(&self, mesh: &Mesh, v: VertexId) -> Option<glam::Vec3> {
        let &(x, y, mut s) = self.vertex_ends.get(&v)?;
        let (ChainEnd::Crease(x), ChainEnd::Crease(y)) = (x, y) else {
            return Some(mesh.position(v));
        };
        let (x, y) = (mesh.position(x), mesh.position(y));
        let (x, y) = if key(y) < key(x) { (y, x) } else { (x, y) };
        let (mut x, mut c, mut y) = (x.as_dvec3(), mesh.position(v).as_dvec3(), y.as_dvec3());
        while s > 0.0 {
            (x, c, y) = (
                (x + c) * 0.5,
                vertex_step(Some(x), c, Some(y), s),
                (c + y) * 0.5,
            );
            s = decrement(s);
        }
        Some(((x + c * 4.0 + y) / 6.0).as_vec3())
    }

    /// The limit point at parameter `num / 2^log2` (`0..=2^log2`) along half-edge `h` of the
    /// mesh, from `from(h)`, when `h`'s edge is on a seam evaluated here (`None` otherwise):
    /// the same bits in every copy, from either side, at any depth.
    pub fn point(&self, mesh: &Mesh, h: HalfedgeId, num: u32, log2: Depth) -> Option<glam::Vec3> {
        let &ci = self.edge_curve.get(h.edge().idx())?;
        if ci == u32::MAX {
            return None;
        }
        let den = 1u64 << log2;
        let num = u64::from(num);
        if num == 0 || num == den {
            let v = if num == 0 { mesh.from(h) } else { mesh.to(h) };
            return self.vertex_point(mesh, v);
        }
        let (mut q, mut s, reversed) = Self::canonical(mesh, &self.curves[ci as usize]);
        // Parameter from P1 towards P2 (dyadic: exact in f64).
        let along = (h == h.edge().halfedge(0)) != reversed;
        let mut t = num as f64 / den as f64;
        if !along {
            t = 1.0 - t;
        }
        // A symmetric chain reads the same both ways: take the half nearer P1.
        if (q.beyond1, q.p1, s[0]) == (q.beyond2, q.p2, s[1]) {
            t = t.min(1.0 - t);
        }
        // Refine the half holding `t` while a vertex sharpness lasts at either end.
        while s[0] > 0.0 || s[1] > 0.0 {
            let (p1, p2) = (q.p1, q.p2);
            let v1 = vertex_step(q.beyond1, p1, Some(p2), s[0]);
            let v2 = vertex_step(Some(p1), p2, q.beyond2, s[1]);
            let m = (p1 + p2) * 0.5;
            if t <= 0.5 {
                q = Chain {
                    beyond1: q.beyond1.map(|p0| (p0 + p1) * 0.5),
                    p1: v1,
                    p2: m,
                    beyond2: Some(v2),
                };
                s = [decrement(s[0]), 0.0];
                t *= 2.0;
            } else {
                q = Chain {
                    beyond1: Some(v1),
                    p1: m,
                    p2: v2,
                    beyond2: q.beyond2.map(|p3| (p2 + p3) * 0.5),
                };
                s = [0.0, decrement(s[1])];
                t = 2.0 * t - 1.0;
            }
        }
        let (p1, p2) = (q.p1, q.p2);
        let p0 = q.beyond1.unwrap_or(p1 * 2.0 - p2);
        let p3 = q.beyond2.unwrap_or(p2 * 2.0 - p1);
        Some(bspline(p0, p1, p2, p3, t).as_vec3())
    }

    /// Overwrites the seam points of a uniform tessellation at `depth` numbered as both slate
    /// layouts number theirs: cage vertex `v` at id `v`, and the `2^depth - 1` inner points of
    /// cage edge `e` from id `edge_base + e (2^depth - 1)` on, along its even half-edge (none
    /// at depth 0). Every other point is left as it is.
    pub fn write_uniform(
        &self,
        mesh: &Mesh,
        depth: Depth,
        edge_base: u32,
        positions: &mut [[f32; 3]],
    ) {
        if self.is_empty() {
            return;
        }
        for &v in self.vertex_ends.keys() {
            if let Some(p) = self.vertex_point(mesh, v) {
                positions[v.idx()] = p.to_array();
            }
        }
        let m = 1u32 << depth;
        for (e, &c) in self.edge_curve.iter().enumerate() {
            if c == u32::MAX {
                continue;
            }
            let h = EdgeId(e as u32).halfedge(0);
            let first = (edge_base + e as u32 * (m - 1)) as usize;
            for s in 1..m {
                if let Some(p) = self.point(mesh, h, s, depth) {
                    positions[first + s as usize - 1] = p.to_array();
                }
            }
        }
    }
}

/// One refinement step of chain vertex `c` between `x` and `y` (`None`: `c` is a corner) with
/// vertex sharpness `s`: a corner stays; a crease takes `(x + 6 c + y) / 8`; a semi-sharp
/// crease vertex stays while its child sharpness is positive and otherwise blends the two by
/// its parent sharpness (OpenSubdiv's fractional weight: the only sharpness at the vertex that
/// runs out is its own).
#[inline]
fn vertex_step(x: Option<DVec3>, c: DVec3, y: Option<DVec3>, s: f32) -> DVec3 {
    let (Some(x), Some(y)) = (x, y) else {
        return c;
    };
    let crease = (x + c * 6.0 + y) / 8.0;
    if s <= 0.0 {
        crease
    } else if decrement(s) > 0.0 {
        c
    } else {
        let w = f64::from(s.min(1.0));
        c * w + crease * (1.0 - w)
    }
}

/// The uniform cubic B-spline segment of control points `p0..p3` at `t` in `[0, 1]` (from the
/// limit of `(p0 + 4 p1 + p2) / 6` at 0 to that of `(p1 + 4 p2 + p3) / 6` at 1).
#[inline]
fn bspline(p0: DVec3, p1: DVec3, p2: DVec3, p3: DVec3, t: f64) -> DVec3 {
    let s = 1.0 - t;
    let (t2, t3) = (t * t, t * t * t);
    let b0 = s * s * s / 6.0;
    let b1 = (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0;
    let b2 = (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0;
    let b3 = t3 / 6.0;
    p0 * b0 + p1 * b1 + p2 * b2 + p3 * b3
}

#[cfg(test)]
mod tests;
