//! Tessellation at any rate: an integer rate per cage edge (1 to [`MAX_RATE`]), triangles of
//! exact limit points with limit normals, watertight to the bit.
//!
//! The faces are cut into *units*: a Catmull-Clark quad, a Loop triangle, or each quad sub-face
//! of another Catmull-Clark face (OpenSubdiv's `Bfr::Tessellation` offers the same three). A
//! cage edge of rate `R` is split into `R` equal parameter steps (`R` is made even next to a
//! face that is not a quad, so that its midpoint, a sub-face corner, is a point of both sides);
//! the two sides of a sub-face inside its face take the face's largest half-edge rate. A unit
//! has an inner grid at its inner rates (a quad: the larger rate of each pair of opposite
//! sides; a triangle: its largest rate), and the ring between the unit's sides and its inner
//! grid is stitched side by side, always taking the next point of whichever polyline is
//! behind (the triangles turn as the face does). A unit too coarse for an inner grid is one or
//! two triangles, or a fan from its centre.
//!
//! Every point has one owner that evaluates it: a cage vertex the first face around it in
//! face order, a point on a cage edge the first of its two faces, everything else its unit.
//! Every unit that uses a point refers to that one point, so the output is watertight to the
//! bit: after welding identical coordinates every inner edge has two triangles. Where a
//! point's side of a crease has its own normal (a sharp edge, or a vertex with sharpness),
//! the other faces' corners there carry their side's one-sided normal
//! ([`LimitMesh::corner_normals`]); on a semi-sharp crease whose band is finer than the
//! tessellation (inside its spans and at its cage vertices), that is the normal just beyond the
//! band on each side (`semi_sharp_offset`).

use glam::{DVec3, Vec3};
use subdiv_mesh::{EdgeId, FaceId, HalfedgeId, Mesh, VertexId};
use subdiv_rules::{LimitMesh, Scheme, VertexParams};

use crate::{Derivatives, Domain, EvalError, Evaluator, Query, Sample};

/// The largest rate of an edge.
pub const MAX_RATE: u32 = 1024;

const NONE: u32 = u32::MAX;

/// A rate for each cage edge (by [`EdgeId`]), clamped to `1..=MAX_RATE`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EdgeRates(Vec<u32>);

impl EdgeRates {
    /// Rate `rate` on every edge of `mesh`.
    pub fn uniform(mesh: &Mesh, rate: u32) -> EdgeRates {
        EdgeRates(vec![rate.clamp(1, MAX_RATE); mesh.num_edges()])
    }

    /// The given rate of each edge (one per [`EdgeId`] of the mesh it is used with).
    pub fn from_rates(rates: Vec<u32>) -> EdgeRates {
        EdgeRates(rates.into_iter().map(|r| r.clamp(1, MAX_RATE)).collect())
    }

    /// The rate of edge `e`.
    #[inline]
    pub fn get(&self, e: EdgeId) -> u32 {
        self.0[e.idx()]
    }

    /// All rates, by edge.
    pub fn as_slice(&self) -> &[u32] {
        &self.0
    }
}

/// A tessellation: its surface (triangles with limit normals, and the cage's UVs at every
/// corner's own parameter point), each vertex's parameter point and the edge rates it used.
#[derive(Clone, Debug)]
pub struct Tessellation {
    /// The triangles, positions and limit normals (one-sided ones at creases).
    pub surface: LimitMesh,
    /// The parameter point each vertex is the limit surface at: `(face, [u, v])`.
    pub params: Vec<(u32, [f64; 2])>,
    /// The rate each cage edge was split at (made even next to a non-quad face).
    pub rates: Vec<u32>,
    /// Every triangle corner whose vertex another face owns (on a shared cage edge or vertex),
    /// by corner: its parameter point in its own face, where face-varying data takes its value
    /// on a seam ([`Tessellation::corner_param`]).
    pub corner_params: Vec<ForeignCorner>,
}

/// Builds the point and triangle lists.
struct Builder<'a> {
    mesh: &'a Mesh,
    scheme: Scheme,
    rate: Vec<u32>,
    /// Owner queries, one per output point.
    points: Vec<Query>,
    vertex_point: Vec<u32>,
    /// The cage vertex of each point that is one (`NONE` for the others).
    point_vertex: Vec<u32>,
    /// First interior point of each edge (in the direction of its half-edge 0).
    edge_first: Vec<u32>,
    tris: Vec<u32>,
    /// (triangle corner, query in the corner's own face) where that side's normal may differ.
    sided: Vec<(u32, Query)>,
}

impl<'a> Builder<'a> {
    fn new(mesh: &'a Mesh, scheme: Scheme, rates: &EdgeRates) -> Builder<'a> {
        let mut rate: Vec<u32> = rates.as_slice().to_vec();
        rate.resize(mesh.num_edges(), 1);
        // Sub-face tiles (Catmull-Clark and bilinear faces that are not quads) meet at the
        // edges' midpoints.
        if scheme != Scheme::Loop {
            for e in mesh.edges() {
                let ngon = [e.halfedge(0), e.halfedge(1)].iter().any(|&h| {
                    let f = mesh.face(h);
                    f.is_some() && mesh.face_size(f) != 4
                });
                if ngon && rate[e.idx()] % 2 == 1 {
                    rate[e.idx()] = (rate[e.idx()] + 1).min(MAX_RATE);
                }
            }
        }
        Builder {
            mesh,
            scheme,
            rate,
            points: Vec::new(),
            vertex_point: vec![NONE; mesh.num_vertices()],
            point_vertex: Vec::new(),
            edge_first: vec![NONE; mesh.num_edges()],
            tris: Vec::new(),
            sided: Vec::new(),
        }
    }

    fn push(&mut self, q: Query) -> u32 {
        self.points.push(q);
        self.point_vertex.push(NONE);
        self.points.len() as u32 - 1
    }

    /// The valence of the cage vertex at point `p` (`usize::MAX` for any other point).
    fn point_valence(&self, p: u32) -> usize {
        match self.point_vertex.get(p as usize) {
            Some(&v) if v != NONE => self.mesh.valence(VertexId(v)),
            _ => usize::MAX,
        }
    }

    /// Registers the owners of face `f`'s corners and edge points.
    fn own(&mut self, f: FaceId, domain: &Domain) {
        let mut h = self.mesh.face_halfedge(f);
        for k in 0..self.mesh.face_size(f) {
            let v = self.mesh.from(h);
            if self.vertex_point[v.idx()] == NONE {
                let [u, w] = domain.corner(k);
                let p = self.push(Query::new(f.0, u, w));
                self.vertex_point[v.idx()] = p;
                self.point_vertex[p as usize] = v.0;
            }
            let e = h.edge();
            if self.edge_first[e.idx()] == NONE {
                let r = self.rate[e.idx()];
                let forward = h == e.halfedge(0);
                self.edge_first[e.idx()] = self.points.len() as u32;
                for m in 1..r {
                    let t = f64::from(m) / f64::from(r);
                    let [u, w] = domain.edge_point(k, if forward { t } else { 1.0 - t });
                    self.push(Query::new(f.0, u, w));
                }
            }
            h = self.mesh.next(h);
        }
    }

    /// The point `m` of `R` along half-edge `h` (0: its origin).
    fn edge_point(&self, h: HalfedgeId, m: u32) -> u32 {
        let e = h.edge();
        let r = self.rate[e.idx()];
        let m = if h == e.halfedge(0) { m } else { r - m };
        let he0 = e.halfedge(0);
        match m {
            0 => self.vertex_point[self.mesh.from(he0).idx()],
            m if m == r => self.vertex_point[self.mesh.to(he0).idx()],
            m => self.edge_first[e.idx()] + m - 1,
        }
    }

    /// Tessellates face `f`.
    fn face(&mut self, f: FaceId) {
        let mesh = self.mesh;
        let n = mesh.face_size(f);
        let domain = Domain::of(self.scheme, n);
        let hs: Vec<HalfedgeId> = mesh.face_halfedges(f).collect();
        match domain {
            Domain::Quad | Domain::Triangle => {
                let sides: Vec<Side> = (0..n)
                    .map(|k| {
                        let r = self.rate[hs[k].edge().idx()];
                        self.edge_side(f, hs[k], k, &domain, (0, r))
                    })
                    .collect();
                let map = |s: f64, t: f64| [s, t];
                self.unit(f, sides, &map);
            }
            Domain::SubFaces { .. } => self.subfaces(f, &hs, &domain),
        }
    }

    /// The sub-faces of an n-gon: their inner sides (midpoint to centre) at the face's largest
    /// half-edge rate, owned by the sub-face they start.
    fn subfaces(&mut self, f: FaceId, hs: &[HalfedgeId], domain: &Domain) {
        let n = hs.len();
        let half: Vec<u32> = hs.iter().map(|h| self.rate[h.edge().idx()] / 2).collect();
        let inner = half.iter().copied().max().unwrap_or(1).max(1);
        let at = |k: usize, s: f64, t: f64| {
            let [x, y] = domain.corner(k);
            [x + 0.5 * s, y + 0.5 * t]
        };
        let [cu, cv] = at(0, 1.0, 1.0);
        let centre = self.push(Query::new(f.0, cu, cv));
        // Inner side k: from the midpoint of edge k to the centre, in sub-face k's frame.
        let mut spokes: Vec<Vec<u32>> = Vec::with_capacity(n);
        for k in 0..n {
            let mut line = vec![self.edge_point(hs[k], half[k])];
            for m in 1..inner {
                let [u, v] = at(k, 1.0, f64::from(m) / f64::from(inner));
                line.push(self.push(Query::new(f.0, u, v)));
            }
            line.push(centre);
            spokes.push(line);
        }
        for k in 0..n {
            let prev = (k + n - 1) % n;
            let first = self.edge_side(f, hs[k], k, domain, (0, half[k]));
            let rp = self.rate[hs[prev].edge().idx()];
            let last = self.edge_side(f, hs[prev], prev, domain, (half[prev], rp));
            let plain = |p: Vec<u32>| Side {
                sided: vec![None; p.len()],
                points: p,
            };
            let back: Vec<u32> = spokes[prev].iter().rev().copied().collect();
            let sides = vec![first, plain(spokes[k].clone()), plain(back), last];
            let map = move |s: f64, t: f64| at(k, s, t);
            self.unit(f, sides, &map);
        }
    }

    /// Tessellates one unit (3 or 4 sides, counter-clockwise in its parameters) whose local
    /// `(s, t)` map to the face's `(u, v)` by `map`.
    fn unit(&mut self, f: FaceId, sides: Vec<Side>, map: &dyn Fn(f64, f64) -> [f64; 2]) {
        let tri = sides.len() == 3;
        let r: Vec<u32> = sides.iter().map(|s| s.points.len() as u32 - 1).collect();
        let (nu, nv) = if tri {
            let n = r.iter().copied().max().unwrap_or(1);
            (n, n)
        } else {
            (r[0].max(r[2]), r[1].max(r[3]))
        };
        let inner_exists = if tri { nu >= 3 } else { nu >= 2 && nv >= 2 };
        if !inner_exists {
            self.small_unit(f, &sides, r.iter().all(|&x| x == 1), map, tri);
            return;
        }
        // The inner grid.
        let mut grid = std::collections::HashMap::new();
        let mut point = |b: &mut Builder, i: u32, j: u32| -> u32 {
            *grid.entry((i, j)).or_insert_with(|| {
                let [u, v] = map(f64::from(i) / f64::from(nu), f64::from(j) / f64::from(nv));
                b.push(Query::new(f.0, u, v))
            })
        };
        let mut inner_sides: Vec<Vec<u32>> = Vec::new();
        if tri {
            let n = nu;
            let lattice: Vec<(u32, u32)> = (1..n)
                .flat_map(|j| (1..n - j).map(move |i| (i, j)))
                .collect();
            for &(i, j) in &lattice {
                point(self, i, j);
            }
            for &(i, j) in &lattice {
                if i + j + 1 < n {
                    let (a, b, c) = (
                        point(self, i, j),
                        point(self, i + 1, j),
                        point(self, i, j + 1),
                    );
                    self.tris.extend([a, b, c]);
                }
                if i + j + 2 < n {
                    let (a, b, c) = (
                        point(self, i + 1, j),
                        point(self, i + 1, j + 1),
                        point(self, i, j + 1),
                    );
                    self.tris.extend([a, b, c]);
                }
            }
            let m = n - 2;
            inner_sides.push((1..=m).map(|i| point(self, i, 1)).collect());
            inner_sides.push((0..m).map(|k| point(self, m - k, 1 + k)).collect());
            inner_sides.push((0..m).map(|k| point(self, 1, m - k)).collect());
        } else {
            for j in 1..nv {
                for i in 1..nu {
                    point(self, i, j);
                }
            }
            for j in 1..nv - 1 {
                for i in 1..nu - 1 {
                    let (a, b) = (point(self, i, j), point(self, i + 1, j));
                    let (c, d) = (point(self, i + 1, j + 1), point(self, i, j + 1));
                    self.tris.extend([a, b, c, a, c, d]);
                }
            }
            inner_sides.push((1..nu).map(|i| point(self, i, 1)).collect());
            inner_sides.push((1..nv).map(|j| point(self, nu - 1, j)).collect());
            inner_sides.push((1..nu).rev().map(|i| point(self, i, nv - 1)).collect());
            inner_sides.push((1..nv).rev().map(|j| point(self, 1, j)).collect());
        }
        for (k, side) in sides.iter().enumerate() {
            let inner = &inner_sides[k];
            let n = if tri || k % 2 == 0 { nu } else { nv };
            // Where the inner points project onto the outer side, as a fraction of it.
            let frac = |j: usize| {
                let j = j as f64;
                match (tri, k) {
                    (true, 1) => (j + 1.5) / f64::from(n),
                    (true, 2) => (j + 2.0) / f64::from(n),
                    _ => (j + 1.0) / f64::from(n),
                }
            };
            self.stitch(side, inner, &frac);
        }
    }

    /// The triangles between the outer polyline of a side and its inner polyline (same
    /// direction, the inner one to the left; `frac(j)`: where inner point `j` projects onto
    /// the side, as a fraction of it), taking the next point of whichever is behind.
    fn stitch(&mut self, side: &Side, inner: &[u32], frac: &dyn Fn(usize) -> f64) {
        let (r, m) = (side.points.len() - 1, inner.len() - 1);
        let (mut i, mut j) = (0usize, 0usize);
        while i < r || j < m {
            let take_outer = j == m || (i < r && (i + 1) as f64 / r as f64 <= frac(j + 1));
            if take_outer {
                self.tri_sided(side, [i, i + 1], inner[j]);
                i += 1;
            } else {
                self.tri_sided(side, [i], inner[j + 1]);
                self.tris.push(inner[j]);
                j += 1;
            }
        }
    }

    /// Pushes the outer points `outer` of a side (recording their one-sided normal queries),
    /// then `inner`.
    fn tri_sided(&mut self, side: &Side, outer: impl IntoIterator<Item = usize>, inner: u32) {
        for i in outer {
            let corner = self.tris.len() as u32;
            self.tris.push(side.points[i]);
            if let Some(q) = side.sided[i] {
                self.sided.push((corner, q));
            }
        }
        self.tris.push(inner);
    }

    /// A unit without an inner grid: two triangles (a quad, or one triangle) when every side
    /// has rate 1, else a fan from its centre.
    fn small_unit(
        &mut self,
        f: FaceId,
        sides: &[Side],
        ones: bool,
        map: &dyn Fn(f64, f64) -> [f64; 2],
        tri: bool,
    ) {
        // The boundary loop, each corner once, with its one-sided queries.
        let mut ring: Vec<(u32, Option<Query>)> = Vec::new();
        for side in sides {
            let n = side.points.len() - 1;
            for i in 0..n {
                ring.push((side.points[i], side.sided[i]));
            }
        }
        let emit = |b: &mut Builder, a: (u32, Option<Query>)| {
            let corner = b.tris.len() as u32;
            b.tris.push(a.0);
            if let Some(q) = a.1 {
                b.sided.push((corner, q));
            }
        };
        if ones {
            // A quad's diagonal avoids a corner of lower valence (two quads sharing two edges at
            // a valence-2 vertex would otherwise both take the diagonal of its neighbours).
            let valence = |i: usize| self.point_valence(ring[i].0);
            let split13 = !tri && valence(1).min(valence(3)) < valence(0).min(valence(2));
            let fan: &[[usize; 3]] = match (tri, split13) {
                (true, _) => &[[0, 1, 2]],
                (false, false) => &[[0, 1, 2], [0, 2, 3]],
                (false, true) => &[[1, 2, 3], [1, 3, 0]],
            };
            for t in fan {
                for &k in t {
                    emit(self, ring[k]);
                }
            }
            return;
        }
        let [u, v] = if tri {
            map(1.0 / 3.0, 1.0 / 3.0)
        } else {
            map(0.5, 0.5)
        };
        let centre = self.push(Query::new(f.0, u, v));
        for k in 0..ring.len() {
            emit(self, ring[k]);
            emit(self, ring[(k + 1) % ring.len()]);
            emit(self, (centre, None));
        }
    }
}

fn unit_normal(s: &Sample) -> DVec3 {
    s.normal()
}

/// Tessellates `eval`'s cage at `rates` ([module docs](self)). Hole faces are left out.
pub fn tessellate_rates(
    eval: &Evaluator<'_>,
    rates: &EdgeRates,
) -> Result<Tessellation, EvalError> {
    let mesh = eval.mesh();
    let mut b = Builder::new(mesh, eval.scheme(), rates);
    let faces: Vec<FaceId> = mesh.faces().filter(|&f| !mesh.is_hole(f)).collect();
    for &f in &faces {
        let domain = Domain::of(eval.scheme(), mesh.face_size(f));
        b.own(f, &domain);
    }
    let mut face_corners = Vec::with_capacity(faces.len() + 1);
    for &f in &faces {
        face_corners.push(b.tris.len() as u32);
        b.face(f);
    }
    face_corners.push(b.tris.len() as u32);
    let corner_params = b.foreign_corners(&faces, &face_corners);
    // Each point's position and unit normal, in `f32` (what the surface keeps).
    let keep = |s: Sample| {
        let n = unit_normal(&s).as_vec3().to_array();
        (s.position.as_vec3().to_array(), n)
    };
    let mut points = vec![([0.0f32; 3], [0.0f32; 3]); b.points.len()];
    eval.evaluate_many_as(&b.points, Derivatives::First, &mut points, keep)?;
    let sided_q: Vec<Query> = b.sided.iter().map(|s| s.1).collect();
    let mut sided_n = vec![DVec3::ZERO; sided_q.len()];
    eval.evaluate_many_as(&sided_q, Derivatives::First, &mut sided_n, |s| {
        unit_normal(&s)
    })?;
    let positions: Vec<[f32; 3]> = points.iter().map(|p| p.0).collect();
    let normals: Vec<[f32; 3]> = points.iter().map(|p| p.1).collect();
    drop(points);
    let mut corner_normals: Vec<(u32, [f32; 3])> = Vec::new();
    for (&(corner, _), &own) in b.sided.iter().zip(&sided_n) {
        let shared = Vec3::from(normals[b.tris[corner as usize] as usize]).as_dvec3();
        if own != DVec3::ZERO && own.angle_between(shared) > 1e-6 {
            corner_normals.push((corner, own.as_vec3().to_array()));
        }
    }
    corner_normals.sort_by_key(|c| c.0);
    corner_normals.dedup_by_key(|c| c.0);
    let params: Vec<(u32, [f64; 2])> = b.points.iter().map(|q| (q.face, [q.u, q.v])).collect();
    let vertex_params = VertexParams {
        face: params.iter().map(|p| p.0).collect(),
        uv: params
            .iter()
            .map(|p| [p.1[0] as f32, p.1[1] as f32])
            .collect(),
    };
    let mut surface = LimitMesh::from_triangles(positions, normals, std::mem::take(&mut b.tris))
        .map_err(|e| EvalError::Internal(e.to_string()))?;
    surface
        .set_corner_normals(corner_normals)
        .map_err(|e| EvalError::Internal(e.to_string()))?;
    surface
        .set_params(vertex_params)
        .map_err(|e| EvalError::Internal(e.to_string()))?;
    let mut t = Tessellation {
        surface,
        params,
        rates: b.rate,
        corner_params,
    };
    corners::write_uvs(eval, &mut t)?;
    Ok(t)
}

mod corners;
mod sides;
pub(crate) use corners::corner_values;
pub use corners::{ForeignCorner, OnCage};
use sides::Side;

#[cfg(test)]
#[path = "tess_tests.rs"]
mod tests;
