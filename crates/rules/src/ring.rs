//! Exact limit points and normals from a vertex's local neighbourhood.
//!
//! The limit of a vertex depends only on its *ring*: the vertex, its edge neighbours and the
//! faces around it (for Loop, the triangles are spanned by the neighbours). One subdivision
//! step maps the ring of `v` to the ring of its child, so the ring can be refined on its own,
//! without refining the mesh. [`Ring::limit`] refines it until no semi-sharp feature is left
//! (all sharpness 0 or infinite; for Catmull-Clark also all faces quads), where the rules stop
//! changing and the closed-form limit masks apply. This gives the true limit surface for
//! semi-sharp creases at any level, in `f64`.
//!
//! For the Chaikin crease method a child edge's sharpness depends on the other semi-sharp edges
//! at *both* ends; the ring keeps, for each edge, the (sum, count) of the semi-sharp edges at its
//! far end, which after one step is just the far half of the parent edge.

use glam::{DVec3, Vec3};
use subdiv_mesh::{CreaseMethod, Mesh, TriangleSubdivision, VertexId};

use crate::crease::{Rule, VertexRules, child_edge_sharpness, edge_crease_weight, is_semi_sharp};
use crate::{Scheme, catmark, loop_scheme};

mod load;
mod sided;
mod stencil;
use sided::{Sides, sided_normals};
pub use stencil::QuadRingStencil;

/// The neighbourhood of one vertex, refinable in isolation.
#[derive(Clone, Debug, Default)]
pub struct Ring {
    scheme: Scheme,
    method: CreaseMethod,
    triangles: TriangleSubdivision,
    center: DVec3,
    vertex_sharpness: f32,
    /// The whole vertex's semi-sharp values at a copy of a non-manifold vertex
    /// ([`Mesh::whole_vertex_edges`]); empty elsewhere.
    whole: Vec<f32>,
    /// At a copy of a non-manifold crease vertex that lacks the crease's edges
    /// ([`Mesh::crease_copy_of`]): the ring of the copy that holds them, whose centre this
    /// ring's centre follows at every level and whose limit it takes.
    master: Option<Box<Ring>>,
    /// With a `master` of just the crease's two edges: the normal is this ring's own.
    own_normal: bool,
    boundary: bool,
    edges: Vec<DVec3>,
    sharp: Vec<f32>,
    far: Vec<(f32, u32)>,
    inner: Vec<DVec3>,
    inner_off: Vec<u32>,
    // scratch
    fp: Vec<DVec3>,
    diag_buf: Vec<DVec3>,
    rot_edges: Vec<DVec3>,
    rot_diag: Vec<DVec3>,
    cs: Vec<f32>,
    tmp_edges: Vec<DVec3>,
    tmp_far: Vec<(f32, u32)>,
    tmp_whole: Vec<f32>,
}

impl Ring {
    /// An empty ring; fill it with [`Ring::load`].
    pub fn new() -> Ring {
        Ring::default()
    }

    /// Moves every point of the ring (and of a crease copy's master ring) by `by`. The rules
    /// are affine, so a ring moved to its own centre refines to the same points less `by`,
    /// while keeping its relative precision however deep it is refined.
    pub fn translate(&mut self, by: DVec3) {
        self.center += by;
        for p in self.edges.iter_mut().chain(self.inner.iter_mut()) {
            *p += by;
        }
        if let Some(m) = self.master.as_mut() {
            m.translate(by);
        }
    }

    /// The centre point.
    #[inline]
    pub fn center(&self) -> DVec3 {
        self.center
    }
    /// Edge neighbour `i`.
    #[inline]
    pub fn edge(&self, i: usize) -> DVec3 {
        self.edges[i]
    }
    /// Sharpness of edge `i` (after [`Ring::refine`]: of its child at the centre).
    #[inline]
    pub fn edge_sharpness(&self, i: usize) -> f32 {
        self.sharp[i]
    }
    /// The vertex of quad `i` opposite the centre (Catmull-Clark rings of quads only).
    #[inline]
    pub fn diag(&self, i: usize) -> DVec3 {
        self.face_inner(i)[0]
    }
    /// Number of faces around the vertex.
    #[inline]
    pub fn face_count(&self) -> usize {
        self.num_faces()
    }
    /// `true` for a boundary vertex.
    #[inline]
    pub fn is_boundary(&self) -> bool {
        self.boundary
    }
    /// Vertex sharpness.
    #[inline]
    pub fn vertex_sharpness(&self) -> f32 {
        self.vertex_sharpness
    }
    /// The sharpness of the ring's edges (after [`Ring::refine`]: of their children).
    #[inline]
    pub fn edge_sharpnesses(&self) -> &[f32] {
        &self.sharp
    }
    /// The whole vertex's semi-sharp values at a copy of a non-manifold vertex
    /// ([`Mesh::whole_vertex_edges`]; after [`Ring::refine`]: their children); empty elsewhere.
    #[inline]
    pub fn whole(&self) -> &[f32] {
        &self.whole
    }
    /// `true` at a copy of a non-manifold crease vertex that takes another copy's points
    /// ([`Mesh::crease_copy_of`]).
    #[inline]
    pub fn has_master(&self) -> bool {
        self.master.is_some()
    }
    /// The child sharpness at the centre of every ring edge, as [`Ring::refine`] gives them
    /// (the whole vertex's values included at a copy of a non-manifold vertex).
    pub fn child_edge_sharpness(&self, child: &mut Vec<f32>) {
        child.clear();
        child.resize(self.sharp.len(), 0.0);
        if self.whole.is_empty() {
            crate::crease::child_edge_sharpness_around(self.method, &self.sharp, child);
        } else {
            let (vs, mut cw) = (self.vertex_sharpness, Vec::new());
            VertexRules::with_whole(self.method, vs, &self.sharp, &self.whole, child, &mut cw);
        }
    }
    /// Unit normal of face `i` of the ring (Newell's method relative to a corner,
    /// [`subdiv_mesh::newell_area`], over the whole polygon; for Loop the
    /// triangle spanned by the centre and edges `i`, `i+1`).
    pub fn face_normal(&self, i: usize) -> DVec3 {
        let n = self.edges.len();
        let mut pts: Vec<DVec3> = Vec::with_capacity(4);
        pts.push(self.center);
        pts.push(self.edges[i]);
        if self.scheme == Scheme::CatmullClark {
            pts.extend_from_slice(self.face_inner(i));
        }
        pts.push(self.edges[(i + 1) % n]);
        subdiv_mesh::newell_area(pts).normalize_or_zero()
    }

    /// `true` if all faces are quads.
    pub fn all_quads(&self) -> bool {
        (0..self.num_faces()).all(|i| self.face_inner(i).len() == 1)
    }

    /// Number of edges around the vertex.
    pub fn valence(&self) -> usize {
        self.edges.len()
    }

    fn num_faces(&self) -> usize {
        self.inner_off.len() - 1
    }

    fn face_inner(&self, i: usize) -> &[DVec3] {
        &self.inner[self.inner_off[i] as usize..self.inner_off[i + 1] as usize]
    }

    /// `true` while a further step would change the rules (semi-sharp features left, or
    /// non-quad faces for Catmull-Clark).
    pub fn needs_refinement(&self) -> bool {
        is_semi_sharp(self.vertex_sharpness)
            || !self.whole.is_empty()
            || self.master.as_ref().is_some_and(|m| m.needs_refinement())
            || self.sharp.iter().any(|&s| is_semi_sharp(s))
            || (self.scheme == Scheme::CatmullClark
                && (0..self.num_faces()).any(|i| self.face_inner(i).len() != 1))
    }

    /// One subdivision step: the ring becomes the ring of the vertex's child.
    pub fn refine(&mut self) {
        if self.is_smooth_quads() {
            self.refine_smooth_quads();
            return;
        }
        let n = self.edges.len();
        let nf = self.num_faces();
        self.cs.clear();
        self.cs.resize(n, 0.0);
        let rules = if self.whole.is_empty() {
            VertexRules::new(
                self.method,
                self.vertex_sharpness,
                &self.sharp,
                &mut self.cs,
            )
        } else {
            let (vs, whole) = (self.vertex_sharpness, &self.whole);
            let (sharp, cs) = (&self.sharp, &mut self.cs);
            VertexRules::with_whole(self.method, vs, sharp, whole, cs, &mut self.tmp_whole)
        };
        self.tmp_edges.clear();
        self.tmp_far.clear();
        match self.scheme {
            // A ring is never bilinear (`Ring::load_at` refuses the scheme).
            Scheme::CatmullClark | Scheme::Bilinear => {
                self.fp.clear();
                for i in 0..nf {
                    let inner = self.face_inner(i);
                    let mut s = self.center + self.edges[i] + self.edges[(i + 1) % n];
                    for p in inner {
                        s += *p;
                    }
                    self.fp.push(s / (inner.len() + 3) as f64);
                }
                let new_center = catmark::vertex_point(self.center, &self.edges, &self.fp, &rules);
                for i in 0..n {
                    let (far_child, w) = self.edge_weights(i);
                    let before = if i > 0 {
                        Some(i - 1)
                    } else if !self.boundary {
                        Some(nf - 1)
                    } else {
                        None
                    };
                    let after = if i < nf { Some(i) } else { None };
                    let mut faces = [DVec3::ZERO; 2];
                    let mut sizes = [0usize; 2];
                    let mut k = 0;
                    for f in before.into_iter().chain(after) {
                        faces[k] = self.fp[f];
                        sizes[k] = self.face_inner(f).len() + 3;
                        k += 1;
                    }
                    let fw = catmark::edge_face_weight(self.triangles, sizes);
                    self.tmp_edges.push(catmark::edge_point_weighted(
                        self.center,
                        self.edges[i],
                        &faces[..k],
                        w,
                        fw,
                    ));
                    self.tmp_far.push(if is_semi_sharp(far_child) {
                        (far_child, 1)
                    } else {
                        (0.0, 0)
                    });
                }
                self.center = new_center;
                self.inner.clear();
                self.inner.extend_from_slice(&self.fp);
                self.inner_off.clear();
                self.inner_off.extend(0..=nf as u32);
            }
            Scheme::Loop => {
                let new_center = loop_scheme::vertex_point(self.center, &self.edges, &rules);
                for i in 0..n {
                    let (far_child, w) = self.edge_weights(i);
                    let mut opp = [DVec3::ZERO; 2];
                    let mut k = 0;
                    if i > 0 || !self.boundary {
                        opp[k] = self.edges[(i + n - 1) % n];
                        k += 1;
                    }
                    if i < nf {
                        opp[k] = self.edges[(i + 1) % n];
                        k += 1;
                    }
                    self.tmp_edges.push(loop_scheme::edge_point(
                        self.center,
                        self.edges[i],
                        &opp[..k],
                        w,
                    ));
                    self.tmp_far.push(if is_semi_sharp(far_child) {
                        (far_child, 1)
                    } else {
                        (0.0, 0)
                    });
                }
                self.center = new_center;
                self.inner_off.clear();
                self.inner_off.resize(nf + 1, 0);
            }
        }
        std::mem::swap(&mut self.edges, &mut self.tmp_edges);
        std::mem::swap(&mut self.far, &mut self.tmp_far);
        std::mem::swap(&mut self.sharp, &mut self.cs);
        if !self.whole.is_empty() {
            std::mem::swap(&mut self.whole, &mut self.tmp_whole);
        }
        if let Some(m) = self.master.as_mut() {
            m.refine();
            self.center = m.center;
        }
        self.vertex_sharpness = crate::crease::decrement(self.vertex_sharpness);
    }

    /// `true` for an interior Catmull-Clark ring of quads without any sharpness (no crease copy,
    /// no whole-vertex values): [`Ring::refine`]'s rules there are the smooth ones everywhere.
    #[inline]
    fn is_smooth_quads(&self) -> bool {
        let n = self.edges.len();
        self.scheme == Scheme::CatmullClark
            && !self.boundary
            && self.vertex_sharpness == 0.0
            && self.whole.is_empty()
            && self.master.is_none()
            && self.inner.len() == n
            && self.inner_off.len() == n + 1
            && self
                .inner_off
                .iter()
                .enumerate()
                .all(|(k, &o)| o as usize == k)
            && self.sharp.iter().all(|&s| s == 0.0)
    }

    /// [`Ring::refine`] of a ring that [`Ring::is_smooth_quads`]: the same operations on the same
    /// values as the general path takes there (face points `(c + e_i + e_i+1 + d_i) / 4`, the
    /// smooth vertex rule, edge points `(c + e_i + f_i-1 + f_i) * 1/4`, all child sharpness 0),
    /// without its per-edge rule and weight decisions.
    fn refine_smooth_quads(&mut self) {
        let n = self.edges.len();
        let (c, e) = (self.center, &self.edges[..n]);
        self.fp.clear();
        self.fp.extend(
            e.iter()
                .zip(e.iter().cycle().skip(1))
                .zip(&self.inner[..n])
                .map(|((&a, &b), &d)| (c + a + b + d) / 4.0),
        );
        let smooth = VertexRules {
            parent: Rule::Smooth,
            child: Rule::Smooth,
            parent_weight: 1.0,
        };
        let new_center = catmark::vertex_point(c, e, &self.fp, &smooth);
        self.tmp_edges.clear();
        let before = std::iter::once(self.fp[n - 1]).chain(self.fp[..n - 1].iter().copied());
        self.tmp_edges.extend(
            e.iter()
                .zip(before.zip(&self.fp))
                .map(|(&a, (f0, &f1))| (c + a + f0 + f1) * 0.25),
        );
        std::mem::swap(&mut self.edges, &mut self.tmp_edges);
        std::mem::swap(&mut self.inner, &mut self.fp);
        self.far.fill((0.0, 0));
        self.sharp.fill(0.0);
        self.center = new_center;
        self.vertex_sharpness = crate::crease::decrement(self.vertex_sharpness);
    }

    /// Child sharpness at the far end and crease weight of edge `i`.
    fn edge_weights(&self, i: usize) -> (f32, f32) {
        let s = self.sharp[i];
        let far_child = child_edge_sharpness(self.method, s, self.far[i]);
        (far_child, edge_crease_weight(s, [self.cs[i], far_child]))
    }

    /// The exact limit position and unit limit normal of the ring's vertex. Refines the ring
    /// (in place) as far as needed. The normal is oriented like the faces; it is zero only for a
    /// fully degenerate neighbourhood.
    pub fn limit(&mut self) -> (DVec3, DVec3) {
        if self.own_normal {
            let parts = self.limit_parts();
            let (_, normal) = finish_limit(&parts, self.center, &self.edges, self.num_faces());
            return (self.master_limit(), normal);
        }
        if let Some(m) = self.master.as_mut() {
            return m.limit();
        }
        let parts = self.limit_parts();
        finish_limit(&parts, self.center, &self.edges, self.num_faces())
    }

    /// [`Ring::limit`], and where the limit surface has a crease or a corner at the vertex (an
    /// infinitely sharp or still semi-sharp crease that stays sharp in the limit, a corner with
    /// two or more smooth sectors), the exact one-sided limit normal of each face of the ring
    /// (face `i` between edges `i` and `i + 1`) in `faces`: the crease tangent crossed with that
    /// side's cross tangent. `faces` is left empty where the surface has one tangent plane.
    pub fn limit_sided(&mut self, faces: &mut Vec<DVec3>) -> (DVec3, DVec3) {
        if self.master.is_some() {
            // The crease's sides are the other copies' faces: none of this ring's.
            faces.clear();
            return self.limit();
        }
        let parts = self.limit_parts();
        let nf = self.num_faces();
        sided_normals(&parts, &parts.sides, self.center, &self.edges, nf, faces);
        finish_limit(&parts, self.center, &self.edges, nf)
    }

    /// The exact limit position and the two limit tangents whose cross product, normalised, is
    /// [`Ring::limit`]'s normal (where it is not degenerate), or `None` where the normal is not
    /// that cross product (an interior crease, whose two sides' normals are averaged; a copy of
    /// a non-manifold vertex). All three are linear in the ring's points: the refinement the
    /// masks wait for depends on the sharpness and the faces alone. Refines the ring in place.
    pub fn limit_tangents(&mut self) -> Option<(DVec3, DVec3, DVec3)> {
        if self.own_normal || self.master.is_some() {
            return None;
        }
        let parts = self.limit_parts();
        if parts.other.is_some() {
            return None;
        }
        Some((parts.pos, parts.t1, parts.t2))
    }

    /// The limit position of the master ring (a crease copy's).
    fn master_limit(&mut self) -> DVec3 {
        self.master.as_mut().map_or(self.center, |m| m.limit().0)
    }

    /// Refines as far as [`Ring::limit`] needs, then evaluates the limit masks: the linear part
    /// of the limit (position and tangents), before the normal is formed.
    fn limit_parts(&mut self) -> LimitParts {
        let mut guard = 0;
        while self.needs_refinement() && guard < 64 {
            self.refine();
            guard += 1;
        }
        let rule = Rule::determine(self.vertex_sharpness, &self.sharp);
        let mut diag = std::mem::take(&mut self.diag_buf);
        diag.clear();
        if self.scheme == Scheme::CatmullClark {
            diag.extend((0..self.num_faces()).map(|i| self.face_inner(i)[0]));
        }
        let (pos, t1, t2) = self.eval_masks(&self.edges, &diag, rule);
        let mut other = None;
        if let (Rule::Crease([c0, c1]), false) = (rule, self.boundary) {
            // An interior crease has a tangent plane on each side; the masks give the side
            // between the crease edges in ring order. The other side comes from the ring rotated
            // to start at the second crease edge, so the normal does not depend on where the
            // ring starts (see `finish_limit`).
            let n = self.edges.len();
            let mut edges = std::mem::take(&mut self.rot_edges);
            let mut diag2 = std::mem::take(&mut self.rot_diag);
            edges.clear();
            edges.extend((0..n).map(|k| self.edges[(c1 + k) % n]));
            diag2.clear();
            if !diag.is_empty() {
                diag2.extend((0..n).map(|k| diag[(c1 + k) % n]));
            }
            let (_, u1, u2) = self.eval_masks(&edges, &diag2, Rule::Crease([0, (c0 + n - c1) % n]));
            other = Some((u1, u2));
            self.rot_edges = edges;
            self.rot_diag = diag2;
        }
        self.diag_buf = diag;
        let sides = Sides::new(rule, self.boundary, &self.sharp, self.num_faces());
        LimitParts {
            pos,
            t1,
            t2,
            other,
            sides,
        }
    }

    fn eval_masks(&self, edges: &[DVec3], diag: &[DVec3], rule: Rule) -> (DVec3, DVec3, DVec3) {
        match self.scheme {
            Scheme::CatmullClark | Scheme::Bilinear => {
                catmark::limit(self.center, edges, diag, rule)
            }
            Scheme::Loop => loop_scheme::limit(self.center, edges, rule, self.boundary),
        }
    }
}

/// The linear part of a ring's limit: position, the two tangents, and for an interior crease the
/// tangents of the other side, and the sectors of its faces.
#[derive(Clone, Debug)]
struct LimitParts {
    pos: DVec3,
    t1: DVec3,
    t2: DVec3,
    other: Option<(DVec3, DVec3)>,
    sides: Sides,
}

/// Forms the unit normal from the tangents of [`LimitParts`]: oriented like the faces of the
/// (refined) ring `center`, `edges` with `num_faces` faces, falling back to the ring's area vector
/// when the tangents are degenerate; an interior crease averages the normals of its two sides.
fn finish_limit(
    parts: &LimitParts,
    center: DVec3,
    edges: &[DVec3],
    num_faces: usize,
) -> (DVec3, DVec3) {
    let n_edges = edges.len();
    // Only needed where the tangents are degenerate: computed there.
    let area = || {
        let mut area = DVec3::ZERO;
        for i in 0..num_faces {
            let a = edges[i] - center;
            let b = edges[(i + 1) % n_edges] - center;
            area += a.cross(b);
        }
        area
    };
    let scale = edges
        .iter()
        .map(|e| (*e - center).length_squared())
        .fold(0.0, f64::max);
    // OpenSubdiv's limit normal is the cross product of the limit tangents as the masks give
    // them (du x dv), also where the ring is folded so that it points against the ring's area;
    // the area only stands in when the tangents are degenerate.
    let orient = |n: DVec3| {
        let len = n.length();
        if len > 1e-12 * scale.max(f64::MIN_POSITIVE) && len.is_finite() {
            n / len
        } else {
            area().normalize_or_zero()
        }
    };
    let mut normal = orient(parts.t1.cross(parts.t2));
    if let Some((u1, u2)) = parts.other {
        let sum = normal + orient(u1.cross(u2));
        if sum.length_squared() > 1e-12 {
            normal = sum.normalize();
        }
    }
    (parts.pos, normal)
}

/// The exact limit position and normal of vertex `v` (for an isolated vertex: its position and
/// a zero normal).
///
/// ```
/// use subdiv_mesh::{parse_obj, Mesh, VertexId};
/// use subdiv_rules::{limit_point, Scheme};
/// // A cube: by symmetry each corner's limit lies on the diagonal through the centre.
/// let cube = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
///             f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
/// let mesh = Mesh::from_soup(&parse_obj(cube)?)?;
/// let (p, n) = limit_point(&mesh, VertexId(0), Scheme::CatmullClark);
/// assert!((p.x - p.y).abs() < 1e-6 && (p.y - p.z).abs() < 1e-6 && p.x > 0.0 && p.x < 0.5);
/// assert!(n.x < 0.0 && n.dot(glam::Vec3::splat(-1.0).normalize()) > 0.999);
/// # Ok::<(), subdiv_mesh::MeshError>(())
/// ```
pub fn limit_point(mesh: &Mesh, v: VertexId, scheme: Scheme) -> (Vec3, Vec3) {
    let mut ring = Ring::new();
    limit_point_with(&mut ring, mesh, v, scheme)
}

/// [`limit_point`] reusing a ring's buffers.
pub fn limit_point_with(ring: &mut Ring, mesh: &Mesh, v: VertexId, scheme: Scheme) -> (Vec3, Vec3) {
    if !ring.load(mesh, v, scheme) {
        return (mesh.position(v), Vec3::ZERO);
    }
    let (p, n) = ring.limit();
    (p.as_vec3(), n.as_vec3())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pillow of fixtures/reference/shapes: its ring corners 0, 2, 4, 6 are interior
    /// vertices of valence 2.
    const PILLOW: &str = "v -1 -1 0.1\nv 0 -1 0\nv 1 -1 -0.1\nv 1 0 0.05\nv 1 1 0.1\nv 0 1 0\n\
        v -1 1 -0.05\nv -1 0 0\nv 0.1 0 0.8\nv 0 -0.1 -0.6\nf 1 2 9 8\nf 2 3 4 9\nf 9 4 5 6\n\
        f 8 9 6 7\nf 8 10 2 1\nf 10 4 3 2\nf 6 5 4 10\nf 7 6 10 8\n";

    /// OpenSubdiv gives a smooth valence-2 vertex the corner masks: its limit at any level is its
    /// position at that level, its normal the cross product of its two edges.
    #[test]
    fn valence2_limit_is_the_vertex_at_its_level() {
        let mesh = Mesh::from_soup(&subdiv_mesh::parse_obj(PILLOW).unwrap()).unwrap();
        let mut ring = Ring::new();
        assert!(ring.load(&mesh, VertexId(0), Scheme::CatmullClark));
        assert_eq!(ring.valence(), 2);
        let mut level1 = ring.clone();
        let (p, n) = ring.limit();
        assert_eq!(p, mesh.position(VertexId(0)).as_dvec3());
        let want = (ring.edge(0) - p).cross(ring.edge(1) - p).normalize();
        assert!((n - want).length() < 1e-12, "{n} {want}");
        level1.refine();
        let c = level1.center();
        assert_ne!(c, p);
        assert_eq!(level1.limit().0, c);
        // limit_point, and through it the whole-mesh paths, agree.
        let (lp, _) = limit_point(&mesh, VertexId(0), Scheme::CatmullClark);
        assert_eq!(lp.as_dvec3(), p);
    }
}
