//! A curve skeleton computed from an object's triangles: its level-set diagram.
//!
//! After F. Lazarus and A. Verroust, "Level Set Diagrams of Polyhedral Objects", ACM Symposium
//! on Solid Modeling and Applications 1999: the vertices are sorted by their geodesic distance
//! from a source vertex, cut into bands of equal width, and every connected piece of a band
//! becomes a node at its centroid; pieces of neighbouring bands that share a mesh edge are
//! joined. A tube gives its axis, a ring (a bracelet) its core circle, a branching object its
//! branches, where the principal axis ([`crate::principal_axis_skeleton`]) gives one straight
//! segment, through the hole of a ring.
//!
//! Choices made here. The source is the end of a double sweep (the vertex farthest from the
//! vertex farthest from an arbitrary one), an extremity of the object; distances are
//! Dijkstra's along edges. The band width is the larger of the
//! object's extent over [`BANDS`] and its longest edge (a band narrower than an edge would
//! break a ring of vertices into pieces). At the ends the diagram reaches the surface (the
//! first band is a cap around the source); a medial curve stops about one radius inside, so
//! every end branch is cut back to the first node whose distance from the tip is at least its
//! own radius (the mean distance of its band piece from its centroid): a capsule keeps the
//! segment between its caps' centres; where the two ends meet (a compact object) the skeleton
//! is the centroid of the object's vertices. An end branch whose tip
//! lies within 1.5 radii of the node it leaves from is a spur (on a ring, the cap around the
//! source) and is removed.
//!
//! Accuracy (the tests): on a capsule of radius 1 the skeleton stays within 0.2 of the axis
//! (mean 0.04); on a ring of tube radius 1 within 0.55 of the core circle (mean under 0.25: the
//! band pieces where the sweep's level sets split and merge are C-shaped, their centroids
//! half a radius off); on a bent tube within 0.4 of its arc. Always inside the object, which
//! is what a focus distance needs.

use glam::Vec3;
use subdiv_mesh::UnionFind;

/// An end branch whose tip is closer than this many radii to its branch node is removed.
const SPUR: f32 = 1.5;

/// Bands of the level-set diagram over the object's geodesic extent (fewer when the edges are
/// long: a band is at least one edge wide).
pub const BANDS: usize = 24;

/// The curve skeleton of the triangles `tris` (indices into `positions`) as segments: the
/// level-set diagram of each connected piece (see the module documentation), end branches cut
/// back by the local radius. A piece that shrinks to a point gives a zero-length segment.
/// Empty without triangles.
///
/// ```
/// use subdiv_doi::curve_skeleton;
/// use subdiv_mesh::glam::Vec3;
/// // An octahedron: a compact object, whose skeleton is its centre.
/// let p = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
/// let t = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]];
/// let s = curve_skeleton(&p, &t);
/// assert!(s.iter().flatten().all(|q| q.length() < 1e-6));
/// ```
pub fn curve_skeleton(positions: &[Vec3], tris: &[[u32; 3]]) -> Vec<[Vec3; 2]> {
    let g = Graph::new(positions, tris);
    let mut out = Vec::new();
    let mut piece = vec![u32::MAX; g.n];
    for start in 0..g.n {
        if piece[start] != u32::MAX || g.adj_start[start] == g.adj_start[start + 1] {
            continue;
        }
        let label = start as u32;
        let d0 = g.dijkstra(start, label, &mut piece);
        let far = far_vertex(&d0, &piece, label);
        let d = g.dijkstra(far, label, &mut piece);
        let diagram = g.level_sets(&d, &piece, start as u32);
        out.extend(diagram.trimmed());
    }
    out
}

/// The vertices and edges of a triangle set (compact adjacency).
struct Graph<'a> {
    pos: &'a [Vec3],
    n: usize,
    adj_start: Vec<u32>,
    adj: Vec<u32>,
    longest: f32,
}

impl<'a> Graph<'a> {
    fn new(pos: &'a [Vec3], tris: &[[u32; 3]]) -> Graph<'a> {
        let n = pos.len();
        let mut pairs: Vec<(u32, u32)> = Vec::with_capacity(tris.len() * 6);
        for t in tris {
            if t.iter().any(|&v| v as usize >= n) {
                continue;
            }
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if a != b {
                    pairs.push((a, b));
                    pairs.push((b, a));
                }
            }
        }
        pairs.sort_unstable();
        pairs.dedup();
        let mut adj_start = vec![0u32; n + 1];
        for &(a, _) in &pairs {
            adj_start[a as usize + 1] += 1;
        }
        for i in 0..n {
            adj_start[i + 1] += adj_start[i];
        }
        let longest = pairs
            .iter()
            .map(|&(a, b)| pos[a as usize].distance(pos[b as usize]))
            .fold(0.0f32, f32::max);
        Graph {
            pos,
            n,
            adj_start,
            adj: pairs.into_iter().map(|(_, b)| b).collect(),
            longest,
        }
    }

    #[inline]
    fn neighbours(&self, v: usize) -> &[u32] {
        &self.adj[self.adj_start[v] as usize..self.adj_start[v + 1] as usize]
    }

    /// Edge-path distances from `src` over its connected piece, whose vertices get the `piece`
    /// label `label` (infinite elsewhere).
    fn dijkstra(&self, src: usize, label: u32, piece: &mut [u32]) -> Vec<f32> {
        use std::cmp::Reverse;
        use std::collections::BinaryHeap;
        let mut d = vec![f32::INFINITY; self.n];
        let mut heap = BinaryHeap::new();
        d[src] = 0.0;
        heap.push(Reverse((0u32, src as u32)));
        while let Some(Reverse((bits, v))) = heap.pop() {
            let (v, dv) = (v as usize, f32::from_bits(bits));
            if dv > d[v] {
                continue;
            }
            piece[v] = label;
            for &w in self.neighbours(v) {
                let nd = dv + self.pos[v].distance(self.pos[w as usize]);
                if nd < d[w as usize] {
                    d[w as usize] = nd;
                    // Non-negative floats order like their bits.
                    heap.push(Reverse((nd.to_bits(), w)));
                }
            }
        }
        d
    }

    /// The level-set diagram of the piece `label` for distances `d` from its source.
    fn level_sets(&self, d: &[f32], piece: &[u32], label: u32) -> Diagram {
        let verts: Vec<usize> = (0..self.n).filter(|&v| piece[v] == label).collect();
        let extent = verts.iter().map(|&v| d[v]).fold(0.0f32, f32::max);
        let width = (extent / BANDS as f32)
            .max(self.longest)
            .max(f32::MIN_POSITIVE);
        let band = |v: usize| (d[v] / width) as u32;
        // Pieces of bands: union-find over edges inside a band.
        let mut parent = UnionFind::new(self.n);
        for &v in &verts {
            for &w in self.neighbours(v) {
                if band(v) == band(w as usize) {
                    parent.union(v, w as usize);
                }
            }
        }
        let mut node_of = vec![u32::MAX; self.n];
        let mut nodes: Vec<(Vec3, u32)> = Vec::new();
        for &v in &verts {
            let r = parent.find(v);
            if node_of[r] == u32::MAX {
                node_of[r] = nodes.len() as u32;
                nodes.push((Vec3::ZERO, 0));
            }
            node_of[v] = node_of[r];
            let k = node_of[v] as usize;
            nodes[k].0 += self.pos[v];
            nodes[k].1 += 1;
        }
        let centre: Vec<Vec3> = nodes.iter().map(|&(s, c)| s / c as f32).collect();
        let mut radius = vec![0.0f32; nodes.len()];
        for &v in &verts {
            let k = node_of[v] as usize;
            radius[k] += self.pos[v].distance(centre[k]) / nodes[k].1 as f32;
        }
        let mut links: Vec<(u32, u32)> = Vec::new();
        for &v in &verts {
            for &w in self.neighbours(v) {
                let (a, b) = (node_of[v], node_of[w as usize]);
                if a < b {
                    links.push((a, b));
                }
            }
        }
        links.sort_unstable();
        links.dedup();
        Diagram {
            centre,
            radius,
            count: nodes.iter().map(|&(_, c)| c).collect(),
            links,
        }
    }
}

/// The vertex of piece `label` farthest by `d` (the double sweep's second source).
fn far_vertex(d: &[f32], piece: &[u32], label: u32) -> usize {
    let mut best = (0.0f32, label as usize);
    for (v, &x) in d.iter().enumerate() {
        if piece[v] == label && x.is_finite() && x > best.0 {
            best = (x, v);
        }
    }
    best.1
}

/// A level-set diagram: nodes (band pieces) at their centroids with their radii and vertex
/// counts, and links.
struct Diagram {
    centre: Vec<Vec3>,
    radius: Vec<f32>,
    count: Vec<u32>,
    links: Vec<(u32, u32)>,
}

impl Diagram {
    /// The segments after cutting every end branch back to the first node at least its own
    /// radius from the tip.
    fn trimmed(&self) -> Vec<[Vec3; 2]> {
        let n = self.centre.len();
        let mut nb: Vec<Vec<u32>> = vec![Vec::new(); n];
        for &(a, b) in &self.links {
            nb[a as usize].push(b);
            nb[b as usize].push(a);
        }
        let mut alive = vec![true; n];
        let mut points = Vec::new();
        let leaves: Vec<usize> = (0..n).filter(|&v| nb[v].len() == 1).collect();
        for &tip in &leaves {
            if !alive[tip] {
                continue;
            }
            // Walk inwards along the branch while nodes have two links.
            let (mut prev, mut cur) = (tip, nb[tip][0] as usize);
            let mut path = vec![tip];
            loop {
                if self.centre[cur].distance(self.centre[tip]) >= self.radius[cur]
                    || nb[cur].len() != 2
                    || !alive[cur]
                {
                    break;
                }
                path.push(cur);
                let next = if nb[cur][0] as usize == prev {
                    nb[cur][1]
                } else {
                    nb[cur][0]
                } as usize;
                (prev, cur) = (cur, next);
                if nb[cur].len() == 1 {
                    // A whole piece of the diagram is one chain shorter than its radii: a
                    // compact object, whose skeleton is its centre.
                    path.push(cur);
                    points.push(self.mean(&path));
                    break;
                }
            }
            // A branch whose tip lies within 1.5 radii of the node it leaves from is a spur of
            // the diagram (the cap around the source, or the last band), not a limb: it goes.
            if nb[cur].len() == 2 && alive[cur] {
                let (mut p2, mut c2, mut ext) = (prev, cur, Vec::new());
                while nb[c2].len() == 2 && alive[c2] && ext.len() < n {
                    ext.push(c2);
                    let next = if nb[c2][0] as usize == p2 {
                        nb[c2][1]
                    } else {
                        nb[c2][0]
                    };
                    (p2, c2) = (c2, next as usize);
                }
                let d = self.centre[c2].distance(self.centre[tip]);
                if nb[c2].len() >= 3 && d < SPUR * self.radius[c2] {
                    path.extend(ext);
                }
            }
            for v in path {
                alive[v] = false;
            }
        }
        let mut out: Vec<[Vec3; 2]> = self
            .links
            .iter()
            .filter(|&&(a, b)| alive[a as usize] && alive[b as usize])
            .map(|&(a, b)| [self.centre[a as usize], self.centre[b as usize]])
            .collect();
        out.extend(points.iter().map(|&p| [p; 2]));
        if out.is_empty() && n > 0 {
            // Everything was cut (the two ends met): a compact object, its centre.
            out.push([self.mean(&(0..n).collect::<Vec<_>>()); 2]);
        }
        out
    }

    /// The centroid of the vertices of the band pieces `nodes`.
    fn mean(&self, nodes: &[usize]) -> Vec3 {
        let (sum, count) = nodes.iter().fold((Vec3::ZERO, 0u32), |(s, c), &k| {
            (s + self.centre[k] * self.count[k] as f32, c + self.count[k])
        });
        sum / count.max(1) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::principal_axis_skeleton;
    use std::f32::consts::{PI, TAU};

    /// A tube of radius `r` around the arc of radius `big` in the xy plane from angle 0 to
    /// `sweep` (`nu` rings of `nv` vertices); closed into a torus when `sweep` is a full turn.
    fn tube(big: f32, r: f32, sweep: f32, nu: u32, nv: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let closed = (sweep - TAU).abs() < 1e-6;
        let rings = if closed { nu } else { nu + 1 };
        let mut p = Vec::new();
        for i in 0..rings {
            let u = sweep * i as f32 / nu as f32;
            let (c, s) = (u.cos(), u.sin());
            for j in 0..nv {
                let v = TAU * j as f32 / nv as f32;
                let rho = big + r * v.cos();
                p.push(Vec3::new(rho * c, rho * s, r * v.sin()));
            }
        }
        let id = |i: u32, j: u32| (i % rings) * nv + j % nv;
        let mut t = Vec::new();
        for i in 0..nu {
            for j in 0..nv {
                t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        (p, t)
    }

    /// Distance from `q` to the circle of radius `big` around the z axis in the xy plane.
    fn to_circle(q: Vec3, big: f32) -> f32 {
        Vec3::new(q.truncate().length() - big, 0.0, q.z).length()
    }

    #[test]
    fn a_ring_gives_its_core_circle() {
        // A bracelet: the principal axis collapses into the hole, 4 units from the material.
        let (p, t) = tube(4.0, 1.0, TAU, 48, 12);
        let s = curve_skeleton(&p, &t);
        assert!(s.len() >= 20, "{}", s.len());
        let worst = s
            .iter()
            .flatten()
            .map(|&q| to_circle(q, 4.0))
            .fold(0.0, f32::max);
        let mean =
            s.iter().flatten().map(|&q| to_circle(q, 4.0)).sum::<f32>() / (2 * s.len()) as f32;
        // Inside the tube and nearer its core than its surface everywhere (the junction pieces
        // beside the sweep's two ends are C-shaped, their centroids half a radius off), close
        // to the core on average.
        assert!(worst < 0.55 && mean < 0.25, "{worst} {mean}");
        // The whole circle is covered: no gap of more than 45 degrees between skeleton points.
        let mut ang: Vec<f32> = s.iter().flatten().map(|q| q.y.atan2(q.x)).collect();
        ang.sort_by(f32::total_cmp);
        let gap = ang
            .windows(2)
            .map(|w| w[1] - w[0])
            .chain([ang[0] + TAU - ang[ang.len() - 1]])
            .fold(0.0, f32::max);
        assert!(gap < PI / 4.0, "{gap}");
        // The principal axis crosses the hole: its middle is the ring's centre, 4 from the core.
        let axis = principal_axis_skeleton(&p).unwrap();
        let mid = (axis[0] + axis[axis.len() - 1]) * 0.5;
        assert!(to_circle(mid, 4.0) > 3.9, "{axis:?}");
    }

    #[test]
    fn a_bent_tube_gives_its_bent_axis() {
        // Half a ring, open at both ends: the skeleton follows the arc; the principal-axis
        // segment is a chord, far from the arc in the middle.
        let (p, t) = tube(5.0, 0.8, PI, 40, 10);
        let s = curve_skeleton(&p, &t);
        let worst = s
            .iter()
            .flatten()
            .map(|&q| to_circle(q, 5.0))
            .fold(0.0, f32::max);
        let mean =
            s.iter().flatten().map(|&q| to_circle(q, 5.0)).sum::<f32>() / (2 * s.len()) as f32;
        assert!(worst < 0.4 && mean < 0.15, "{worst} {mean}");
        let (lo, hi) = s
            .iter()
            .flatten()
            .map(|q| q.y.atan2(q.x))
            .fold((f32::MAX, f32::MIN), |(a, b), x| (a.min(x), b.max(x)));
        assert!(lo < 0.4 && hi > PI - 0.4, "{lo} {hi}");
        let axis = principal_axis_skeleton(&p).unwrap();
        let mid = (axis[0] + axis[axis.len() - 1]) * 0.5;
        assert!(to_circle(mid, 5.0) > 1.5, "{mid}");
    }

    #[test]
    fn a_capsule_gives_its_axis_and_a_ball_its_centre() {
        // A closed cylinder along x, radius 1, from 0 to 10, with flat caps.
        let (n, nv) = (20u32, 12u32);
        let mut p = Vec::new();
        for i in 0..=n {
            for j in 0..nv {
                let v = TAU * j as f32 / nv as f32;
                p.push(Vec3::new(10.0 * i as f32 / n as f32, v.cos(), v.sin()));
            }
        }
        let (c0, c1) = (p.len() as u32, p.len() as u32 + 1);
        p.extend([Vec3::ZERO, Vec3::new(10.0, 0.0, 0.0)]);
        let id = |i: u32, j: u32| i * nv + j % nv;
        let mut t = Vec::new();
        for i in 0..n {
            for j in 0..nv {
                t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        for j in 0..nv {
            t.push([c0, id(0, j + 1), id(0, j)]);
            t.push([c1, id(n, j), id(n, j + 1)]);
        }
        let s = curve_skeleton(&p, &t);
        let off = |q: &Vec3| q.y.hypot(q.z);
        let worst = s.iter().flatten().map(off).fold(0.0, f32::max);
        let mean = s.iter().flatten().map(off).sum::<f32>() / (2 * s.len()) as f32;
        assert!(worst < 0.2 && mean < 0.06, "{worst} {mean}");
        let (lo, hi) = s
            .iter()
            .flatten()
            .fold((f32::MAX, f32::MIN), |(a, b), q| (a.min(q.x), b.max(q.x)));
        assert!(lo > 0.4 && lo < 1.6 && hi > 8.4 && hi < 9.6, "{lo} {hi}");
        // A ball (latitude-longitude sphere of radius 2 around (1, 2, 3)): its centre.
        let c = Vec3::new(1.0, 2.0, 3.0);
        let (nu, nv) = (16u32, 24u32);
        let mut p = vec![c + Vec3::Z * 2.0, c - Vec3::Z * 2.0];
        for i in 1..nu {
            let th = PI * i as f32 / nu as f32;
            for j in 0..nv {
                let ph = TAU * j as f32 / nv as f32;
                p.push(c + 2.0 * Vec3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()));
            }
        }
        let id = |i: u32, j: u32| 2 + (i - 1) * nv + j % nv;
        let mut t = Vec::new();
        for j in 0..nv {
            t.push([0, id(1, j), id(1, j + 1)]);
            t.push([1, id(nu - 1, j + 1), id(nu - 1, j)]);
        }
        for i in 1..nu - 1 {
            for j in 0..nv {
                t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let s = curve_skeleton(&p, &t);
        assert!(s.iter().flatten().all(|q| q.distance(c) < 0.05), "{s:?}");
        // An icosahedron (the two ends of its diagram meet): its centre.
        let phi = (1.0 + 5f32.sqrt()) / 2.0;
        let mut p = Vec::new();
        for (a, b) in [(1.0, phi), (-1.0, phi), (1.0, -phi), (-1.0, -phi)] {
            p.extend([
                Vec3::new(0.0, a, b),
                Vec3::new(a, b, 0.0),
                Vec3::new(b, 0.0, a),
            ]);
        }
        let mut t = Vec::new();
        for i in 0..12u32 {
            for j in i + 1..12 {
                for k in j + 1..12 {
                    let [a, b, d] = [i, j, k].map(|x| p[x as usize]);
                    let edge = |u: Vec3, v: Vec3| (u.distance(v) - 2.0).abs() < 1e-3;
                    if edge(a, b) && edge(b, d) && edge(a, d) {
                        let out = (b - a).cross(d - a).dot(a) > 0.0;
                        t.push(if out { [i, j, k] } else { [i, k, j] });
                    }
                }
            }
        }
        assert_eq!(t.len(), 20);
        let s = curve_skeleton(&p, &t);
        assert!(s.iter().flatten().all(|q| q.length() < 1e-5), "{s:?}");
        // Two separate pieces: each its own skeleton; no triangles: none.
        let (p2, mut t2) = tube(4.0, 1.0, TAU, 24, 8);
        let off = p2.len() as u32;
        let mut p3 = p2.clone();
        p3.extend(p2.iter().map(|q| *q + Vec3::new(20.0, 0.0, 0.0)));
        t2.extend(t2.clone().iter().map(|t| t.map(|v| v + off)));
        let s = curve_skeleton(&p3, &t2);
        assert!(s.iter().flatten().any(|q| q.x > 14.0) && s.iter().flatten().any(|q| q.x < 6.0));
        assert!(curve_skeleton(&p3, &[]).is_empty());
    }

    #[test]
    fn focus_on_a_bracelet_measures_from_its_ring() {
        // Without a skeleton file the focus object's computed skeleton is used: a small triangle
        // in the bracelet's hole is 4 from its core (3 from its surface), one beside the tube
        // 1.5 from it. The principal axis would put the hole's triangle at distance 0.
        use crate::{Doi, DoiContext, Focus};
        let (p, t) = tube(4.0, 1.0, TAU, 32, 10);
        let mut obj = String::new();
        for q in &p {
            obj += &format!("v {} {} {}\n", q.x, q.y, q.z);
        }
        obj += "v -0.2 0 0\nv 0.2 0 0\nv 0 0.2 0\nv 6.3 0 0\nv 6.7 0 0\nv 6.5 0.2 0\ng bracelet\n";
        for f in &t {
            obj += &format!("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1);
        }
        let n = p.len();
        obj += &format!(
            "g hole\nf {} {} {}\ng beside\nf {} {} {}\n",
            n + 1,
            n + 2,
            n + 3,
            n + 4,
            n + 5,
            n + 6
        );
        let m = subdiv_mesh::Mesh::from_soup(&subdiv_mesh::parse_obj(&obj).unwrap()).unwrap();
        let focus = Focus::from_groups(&m, &["bracelet".into()], None, 8.0).unwrap();
        let ctx = DoiContext {
            steps: 8,
            ..Default::default()
        };
        let mut v = Vec::new();
        focus.evaluate(&m, &ctx, &mut v).unwrap();
        let (hole, beside) = (v[v.len() - 2], v[v.len() - 1]);
        // 8 · (1 − d/8) = 8 − d with d the distance to the skeleton: from the core, 3.8 in the
        // hole (the triangle reaches 0.2 towards the ring) and 2.3 beside the tube; the
        // skeleton is within half a tube radius of the core.
        let (d_hole, d_beside) = (8.0 - hole, 8.0 - beside);
        assert!((3.0..4.0).contains(&d_hole), "{d_hole}");
        assert!((1.8..2.8).contains(&d_beside), "{d_beside}");
    }
}
