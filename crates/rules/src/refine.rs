//! Uniform whole-mesh refinement `M^l -> M^(l+1)`.
//!
//! Vertex numbering of the refined mesh: first the children of the parent's vertices (so vertex
//! `i` of every level descends from cage vertex `i`), then for Catmull-Clark one point per face,
//! then one point per edge. Faces: Catmull-Clark splits an n-gon into n quads
//! `(v_k, e_k, f, e_(k-1))`; Loop splits a triangle into four. Child edges inherit decayed
//! sharpness, child faces the hole flag and group of their parent.

use glam::{DVec3, Vec3};
use subdiv_mesh::{
    CreaseMethod, EdgeId, FaceId, HalfedgeId, Mesh, PolygonSoup, TriangleSubdivision, VertexId,
};

use crate::crease::{
    VertexRules, child_whole_vertex_edges, decrement, edge_crease_weight, is_sharp,
};
use crate::{Depth, Point, RulesError, Scheme, catmark, loop_scheme};

/// One uniform refinement step of the whole mesh.
///
/// ```
/// use subdiv_mesh::{parse_obj, Mesh};
/// use subdiv_rules::{refine_uniform, Scheme};
/// let quad = Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")?)?;
/// let level1 = refine_uniform(&quad, Scheme::CatmullClark).unwrap();
/// assert_eq!((level1.num_vertices(), level1.num_faces()), (9, 4));
/// # Ok::<(), subdiv_mesh::MeshError>(())
/// ```
pub fn refine_uniform(mesh: &Mesh, scheme: Scheme) -> Result<Mesh, RulesError> {
    if scheme == Scheme::Loop {
        mesh.check_triangles()?;
        check_doubled_triangles(mesh)?;
    }
    let nv = mesh.num_vertices();
    let fp: Vec<Vec3> = if scheme.splits_to_quads() {
        mesh.faces().map(|f| mesh.face_centroid(f)).collect()
    } else {
        Vec::new()
    };
    let mut kernel = RefineKernel::new(mesh, scheme);
    let positions = kernel.refine_points(&fp);
    let edge_base = (nv + fp.len()) as u32;

    // Child faces.
    let mut soup = PolygonSoup {
        positions,
        options: mesh.options(),
        ..Default::default()
    };
    let mut holes = Vec::new();
    let mut groups = Vec::new();
    let ep = |h: HalfedgeId| (edge_base + h.edge().0) as i64;
    for f in mesh.faces() {
        let h0 = mesh.face_halfedge(f);
        let n = mesh.face_size(f);
        match scheme {
            Scheme::CatmullClark | Scheme::Bilinear => {
                let center = (nv + f.idx()) as i64;
                let mut h = h0;
                let mut hp = mesh.prev(h0);
                for _ in 0..n {
                    soup.push_face([mesh.from(h).0 as i64, ep(h), center, ep(hp)]);
                    hp = h;
                    h = mesh.next(h);
                }
                holes.extend(std::iter::repeat_n(mesh.is_hole(f), n));
                groups.extend(std::iter::repeat_n(mesh.face_group(f), n));
            }
            Scheme::Loop => {
                let (ha, hb, hc) = (h0, mesh.next(h0), mesh.prev(h0));
                let (a, b, c) = (
                    mesh.from(ha).0 as i64,
                    mesh.from(hb).0 as i64,
                    mesh.from(hc).0 as i64,
                );
                soup.push_face([a, ep(ha), ep(hc)]);
                soup.push_face([b, ep(hb), ep(ha)]);
                soup.push_face([c, ep(hc), ep(hb)]);
                soup.push_face([ep(ha), ep(hb), ep(hc)]);
                holes.extend([mesh.is_hole(f); 4]);
                groups.extend([mesh.face_group(f); 4]);
            }
        }
    }
    let child_fv = mesh
        .uv()
        .map(|fv| crate::fvar::refine_face_varying(&mut kernel, fv));
    let mut child = Mesh::from_soup(&soup).map_err(RulesError::Internal)?;
    // Set apart from the soup: the child channel carries its values' dependence.
    child.set_uv(child_fv).map_err(RulesError::Internal)?;
    // A vertex's child has its number.
    child.set_fvar_corners(mesh.fvar_corners());
    child.set_holes(holes);
    child.set_groups(mesh.groups().to_vec(), groups);
    kernel.transfer_sharpness(&mut child, |e| Some(VertexId(edge_base + e.0)), |_| true);
    Ok(child)
}

/// The one refinement kernel: the vertex and edge rules of one subdivision step applied to a
/// mesh, with crease sharpness carried to the child mesh. Uniform refinement
/// ([`refine_uniform`]) applies it to every vertex and edge; adaptive Loop refinement
/// (`subdiv-redgreen`) to the vertices and edges its closure selects. Both therefore produce
/// bit-identical points wherever they refine the same neighbourhood.
///
/// Call [`RefineKernel::vertex_point`] for both ends of an edge before its
/// [`RefineKernel::edge_point`]: the vertex rules decide the child sharpness of the edge at each
/// end (OpenSubdiv's `Sdc::Crease`), which the edge's crease weight needs.
///
/// The kernel is generic over the point type: `RefineKernel::new` refines the mesh's own `f32`
/// positions; [`RefineKernel::with_positions`] refines other positions of the same mesh (the
/// `f64` positions of [`refine_uniform_levels_f64`]) with the same rules.
#[derive(Debug)]
pub struct RefineKernel<'m, P: Point = Vec3> {
    mesh: &'m Mesh,
    pos: &'m [P],
    scheme: Scheme,
    method: CreaseMethod,
    triangles: TriangleSubdivision,
    /// Child sharpness of each edge at the origin of each half-edge.
    child_sharp: Vec<f32>,
    halfedges: Vec<HalfedgeId>,
    edge_ends: Vec<P>,
    face_points: Vec<P>,
    edge_sharpness: Vec<f32>,
    child_edge_sharpness: Vec<f32>,
}

impl<'m> RefineKernel<'m, Vec3> {
    /// A kernel for one step of `scheme` on `mesh` and its positions.
    pub fn new(mesh: &'m Mesh, scheme: Scheme) -> RefineKernel<'m, Vec3> {
        RefineKernel::with_positions(mesh, scheme, mesh.positions())
    }
}

impl<'m, P: Point> RefineKernel<'m, P> {
    /// A kernel for one step of `scheme` on `mesh`'s topology and sharpness with the vertex
    /// positions `pos` (one per vertex of `mesh`).
    pub fn with_positions(mesh: &'m Mesh, scheme: Scheme, pos: &'m [P]) -> RefineKernel<'m, P> {
        debug_assert_eq!(pos.len(), mesh.num_vertices());
        RefineKernel {
            mesh,
            pos,
            scheme,
            method: mesh.options().crease,
            triangles: mesh.options().triangles,
            child_sharp: vec![0.0; mesh.num_halfedges()],
            halfedges: Vec::new(),
            edge_ends: Vec::new(),
            face_points: Vec::new(),
            edge_sharpness: Vec::new(),
            child_edge_sharpness: Vec::new(),
        }
    }

    /// The vertex point of `v` (Catmull-Clark or Loop vertex rule with crease, corner and
    /// boundary rules), recording the child sharpness of each edge at `v`. `face_points` holds
    /// the Catmull-Clark face points by face (unused for Loop). An isolated vertex stays.
    #[inline]
    pub fn vertex_point(&mut self, v: VertexId, face_points: &[P]) -> P {
        self.vertex_point_without(v, face_points, |_| false)
    }

    /// [`RefineKernel::vertex_point`] over the ring of `v` without the edges whose outgoing
    /// half-edge `skip` names: for adaptive Loop, the edges from a corner of a green triangle
    /// to the midpoint of the opposite parent edge, which are not edges of the level the vertex
    /// rule reads (the parent triangle is). Skipped edges must be smooth; their child
    /// sharpness is 0.
    pub fn vertex_point_without(
        &mut self,
        v: VertexId,
        face_points: &[P],
        skip: impl Fn(HalfedgeId) -> bool,
    ) -> P {
        let mesh = self.mesh;
        let pos = self.pos;
        self.vertex_point_over(
            v,
            pos[v.idx()],
            |h| pos[mesh.to(h).idx()],
            |f| face_points[f.idx()],
            skip,
        )
    }

    /// [`RefineKernel::vertex_point`] of other data than the positions (face-varying values
    /// where they are continuous around `v`): `centre` at `v`, `end(h)` at the other end of
    /// each out half-edge `h`, `face_point(f)` the Catmull-Clark face point of face `f`.
    #[inline]
    pub fn vertex_point_with(
        &mut self,
        v: VertexId,
        centre: P,
        end: impl Fn(HalfedgeId) -> P,
        face_point: impl Fn(FaceId) -> P,
    ) -> P {
        self.vertex_point_over(v, centre, end, face_point, |_| false)
    }

    /// The one vertex rule behind [`RefineKernel::vertex_point_without`] and
    /// [`RefineKernel::vertex_point_with`]: other data than the positions (`centre`, `end`,
    /// `face_point` as in [`RefineKernel::vertex_point_with`]) over the ring of `v` without the
    /// out half-edges `skip` names (as in [`RefineKernel::vertex_point_without`]); the
    /// face-varying values of adaptive Loop refinement.
    pub fn vertex_point_over(
        &mut self,
        v: VertexId,
        centre: P,
        end: impl Fn(HalfedgeId) -> P,
        face_point: impl Fn(FaceId) -> P,
        skip: impl Fn(HalfedgeId) -> bool,
    ) -> P {
        let mesh = self.mesh;
        if mesh.is_isolated(v) {
            return centre;
        }
        self.halfedges.clear();
        self.halfedges
            .extend(mesh.outgoing(v).filter(|&h| !skip(h)));
        self.edge_ends.clear();
        self.face_points.clear();
        self.edge_sharpness.clear();
        for &h in &self.halfedges {
            self.edge_ends.push(end(h));
            self.edge_sharpness.push(mesh.edge_sharpness(h.edge()));
            let f = mesh.face(h);
            if f.is_some() && self.scheme.splits_to_quads() {
                self.face_points.push(face_point(f));
            }
        }
        self.child_edge_sharpness.clear();
        self.child_edge_sharpness.resize(self.halfedges.len(), 0.0);
        let vs = mesh.vertex_sharpness(v);
        let rules = match mesh.whole_vertex_edges(v) {
            None => VertexRules::new(
                self.method,
                vs,
                &self.edge_sharpness,
                &mut self.child_edge_sharpness,
            ),
            Some(whole) => {
                let (es, cs) = (&self.edge_sharpness, &mut self.child_edge_sharpness);
                VertexRules::with_whole(self.method, vs, es, whole, cs, &mut Vec::new())
            }
        };
        for (k, &h) in self.halfedges.iter().enumerate() {
            self.child_sharp[h.idx()] = self.child_edge_sharpness[k];
        }
        match self.scheme {
            Scheme::CatmullClark => {
                catmark::vertex_point(centre, &self.edge_ends, &self.face_points, &rules)
            }
            Scheme::Loop => loop_scheme::vertex_point(centre, &self.edge_ends, &rules),
            // OpenSubdiv's bilinear vertex mask: the vertex itself.
            Scheme::Bilinear => centre,
        }
    }

    /// The vertex point of a crease copy `v` ([`Mesh::crease_ends`]): the whole vertex's rules
    /// (its vertex sharpness and whole-vertex values, two infinitely sharp edges) over the far
    /// ends of `ends`, which `v`'s ring lacks; what the copy holding them computes, to the bit.
    pub fn crease_copy_point(&self, v: VertexId, ends: [HalfedgeId; 2]) -> P {
        let mesh = self.mesh;
        let e = ends.map(|h| self.pos[mesh.to(h).idx()]);
        let sharp = [subdiv_mesh::SHARPNESS_INFINITE; 2];
        let whole = mesh.whole_vertex_edges(v).unwrap_or(&[]);
        let vs = mesh.vertex_sharpness(v);
        let rules = VertexRules::with_whole(
            self.method,
            vs,
            &sharp,
            whole,
            &mut [0.0; 2],
            &mut Vec::new(),
        );
        let centre = self.pos[v.idx()];
        match self.scheme {
            Scheme::CatmullClark => catmark::vertex_point(centre, &e, &[], &rules),
            Scheme::Loop => loop_scheme::vertex_point(centre, &e, &rules),
            Scheme::Bilinear => centre,
        }
    }

    /// The child sharpness of `h`'s edge at `h`'s origin (after that vertex's
    /// [`RefineKernel::vertex_point`]).
    #[inline]
    pub fn child_sharpness(&self, h: HalfedgeId) -> f32 {
        self.child_sharp[h.idx()]
    }

    /// The edge point of `e`. `side(h)` gives, for each half-edge of `e` with a face, the point
    /// on that side: the face point (Catmull-Clark) or the vertex opposite the edge (Loop).
    #[inline]
    pub fn edge_point(&self, e: EdgeId, side: impl Fn(HalfedgeId) -> P) -> P {
        let mesh = self.mesh;
        let pos = self.pos;
        let h0 = e.halfedge(0);
        let a = pos[mesh.from(h0).idx()];
        let b = pos[mesh.to(h0).idx()];
        self.edge_point_with(e, a, b, side)
    }

    /// [`RefineKernel::edge_point`] of other data than the positions: `a` and `b` at the
    /// origin and the end of the edge's half-edge 0.
    #[inline]
    pub fn edge_point_with(&self, e: EdgeId, a: P, b: P, side: impl Fn(HalfedgeId) -> P) -> P {
        let mesh = self.mesh;
        let (h0, h1) = (e.halfedge(0), e.halfedge(1));
        let s = mesh.edge_sharpness(e);
        let w = edge_crease_weight(s, [self.child_sharp[h0.idx()], self.child_sharp[h1.idx()]]);
        let mut adj = [a; 2];
        let mut k = 0;
        for h in [h0, h1] {
            if mesh.face(h).is_some() {
                adj[k] = side(h);
                k += 1;
            }
        }
        match self.scheme {
            Scheme::CatmullClark if k == 2 && self.triangles == TriangleSubdivision::Smooth => {
                let sizes = [h0, h1].map(|h| mesh.face_size(mesh.face(h)));
                let fw = catmark::edge_face_weight(self.triangles, sizes);
                catmark::edge_point_weighted(a, b, &adj, w, fw)
            }
            Scheme::CatmullClark => catmark::edge_point(a, b, &adj[..k], w),
            Scheme::Loop => loop_scheme::edge_point(a, b, &adj[..k], w),
            // OpenSubdiv's bilinear edge mask (its crease mask): the midpoint.
            Scheme::Bilinear => a.scale(0.5).add(b.scale(0.5)),
        }
    }

    /// The points of the whole refined mesh in [`refine_uniform`]'s numbering: vertex points,
    /// the face points `fp` (Catmull-Clark; empty for Loop), edge points.
    pub fn refine_points(&mut self, fp: &[P]) -> Vec<P> {
        let mesh = self.mesh;
        let pos = self.pos;
        let scheme = self.scheme;
        let mut points = Vec::with_capacity(mesh.num_vertices() + fp.len() + mesh.num_edges());
        for v in mesh.vertices() {
            points.push(self.vertex_point(v, fp));
        }
        // A copy lacking the crease's edges: the crease rule over them (its own rules gave
        // its edges' child sharpness).
        for (v, ends) in mesh.crease_ends_all() {
            points[v.idx()] = self.crease_copy_point(v, ends);
        }
        points.extend_from_slice(fp);
        for e in mesh.edges() {
            points.push(self.edge_point(e, |h| match scheme {
                Scheme::CatmullClark | Scheme::Bilinear => fp[mesh.face(h).idx()],
                // The vertex of the triangle opposite the edge.
                Scheme::Loop => pos[mesh.to(mesh.next(h)).idx()],
            }));
        }
        points
    }

    /// The mesh this kernel refines.
    #[inline]
    pub fn mesh(&self) -> &'m Mesh {
        self.mesh
    }

    /// The scheme this kernel applies.
    #[inline]
    pub fn scheme(&self) -> Scheme {
        self.scheme
    }

    /// Carries sharpness to `child`, whose vertex `i` descends from the parent's vertex `i`.
    /// `midpoint(e)` is the child vertex of split edge `e` (`None`: the edge is kept whole);
    /// `decays(v)` says whether `v` was refined this step. The halves of a split crease edge get
    /// the child sharpness recorded by the vertex rules; a kept edge keeps its sharpness; a
    /// refined vertex's sharpness decays by one, a kept one's stays; the whole vertex's values
    /// of a copy of a non-manifold vertex decay likewise, and its crease copy stays.
    pub fn transfer_sharpness(
        &self,
        child: &mut Mesh,
        midpoint: impl Fn(EdgeId) -> Option<VertexId>,
        decays: impl Fn(VertexId) -> bool,
    ) {
        let mesh = self.mesh;
        for e in mesh.edges() {
            let s = mesh.edge_sharpness(e);
            if !is_sharp(s) || mesh.is_boundary_edge(e) {
                continue;
            }
            match midpoint(e) {
                Some(m) => {
                    for side in 0..2 {
                        let h = e.halfedge(side);
                        let cs = self.child_sharp[h.idx()];
                        if is_sharp(cs)
                            && let Some(ch) = child.find_halfedge(mesh.from(h), m)
                        {
                            child.set_edge_sharpness(ch.edge(), cs);
                        }
                    }
                }
                None => {
                    let [a, b] = mesh.edge_vertices(e);
                    if let Some(ch) = child.find_halfedge(a, b) {
                        child.set_edge_sharpness(ch.edge(), s);
                    }
                }
            }
        }
        for v in mesh.vertices() {
            let s = mesh.vertex_sharpness(v);
            if is_sharp(s) {
                let s = if decays(v) { decrement(s) } else { s };
                child.set_vertex_sharpness(v, s.max(child.vertex_sharpness(v)));
            }
        }
        for (v, ends) in mesh.crease_ends_all() {
            // The crease's edges one level down: their halves at the vertex's copies.
            let child_ends = ends.map(|h| {
                let to = midpoint(h.edge()).unwrap_or(mesh.to(h));
                child.find_halfedge(mesh.from(h), to)
            });
            if let [Some(a), Some(b)] = child_ends {
                child.set_crease_ends(v, Some([a, b]));
            }
        }
        for (v, whole) in mesh.whole_vertex_edges_all() {
            if decays(v) {
                child.set_whole_vertex_edges(v, &child_whole_vertex_edges(self.method, whole));
            } else {
                child.set_whole_vertex_edges(v, whole);
            }
        }
    }
}

/// Refines `depth` times (refusing cages beyond [`MAX_COORDINATE`]).
pub fn refine_uniform_levels(
    mesh: &Mesh,
    scheme: Scheme,
    depth: Depth,
) -> Result<Mesh, RulesError> {
    check_coordinates(mesh)?;
    check_size(mesh, scheme, depth)?;
    let mut m = mesh.clone();
    for _ in 0..depth {
        m = refine_uniform(&m, scheme)?;
    }
    Ok(m)
}

/// [`refine_uniform_levels`], and the refined mesh's positions computed in `f64` alongside (the
/// same rules through [`RefineKernel::with_positions`], from the cage's positions): the
/// reference path keeps limit normals exact where `f32` rounding of deep levels would turn them
/// (nearly degenerate tangents, e.g. at interior valence-2 vertices).
pub fn refine_uniform_levels_f64(
    mesh: &Mesh,
    scheme: Scheme,
    depth: Depth,
) -> Result<(Mesh, Vec<DVec3>), RulesError> {
    check_coordinates(mesh)?;
    check_size(mesh, scheme, depth)?;
    let mut m = mesh.clone();
    let mut pos: Vec<DVec3> = m.positions().iter().map(|p| p.as_dvec3()).collect();
    let mut corners: Vec<DVec3> = Vec::new();
    for _ in 0..depth {
        let child = refine_uniform(&m, scheme)?;
        let fp: Vec<DVec3> = if scheme.splits_to_quads() {
            m.faces()
                .map(|f| {
                    corners.clear();
                    corners.extend(m.face_vertices(f).iter().map(|v| pos[v.idx()]));
                    catmark::face_point(&corners)
                })
                .collect()
        } else {
            Vec::new()
        };
        pos = RefineKernel::with_positions(&m, scheme, &pos).refine_points(&fp);
        m = child;
    }
    Ok((m, pos))
}

/// Maximum number of faces a uniform refinement may produce.
pub const MAX_REFINED_FACES: u64 = 1 << 26;

/// Number of faces of the uniform level-`depth` refinement.
pub fn refined_face_count(mesh: &Mesh, scheme: Scheme, depth: Depth) -> u64 {
    if depth == 0 {
        return mesh.num_faces() as u64;
    }
    let per = 4u64.saturating_pow(u32::from(depth) - 1);
    match scheme {
        Scheme::CatmullClark | Scheme::Bilinear => {
            let corners: u64 = mesh.faces().map(|f| mesh.face_size(f) as u64).sum();
            corners.saturating_mul(per)
        }
        Scheme::Loop => (mesh.num_faces() as u64).saturating_mul(per.saturating_mul(4)),
    }
}

/// Refuses a refinement beyond this machine's memory (the size it asks for in the error), then
/// one beyond [`MAX_REFINED_FACES`].
fn check_size(mesh: &Mesh, scheme: Scheme, depth: Depth) -> Result<(), RulesError> {
    crate::Budget::machine().check(mesh, crate::Request::Uniform { scheme, depth })?;
    let faces = refined_face_count(mesh, scheme, depth);
    if faces > MAX_REFINED_FACES {
        return Err(RulesError::TooDeep { depth, faces });
    }
    Ok(())
}

mod checks;
pub use checks::{MAX_COORDINATE, check_coordinates, check_doubled_triangles};

#[cfg(test)]
mod tests;
