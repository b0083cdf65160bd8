//! Uniform whole-mesh refinement `M^l -> M^(l+1)`.
//!
//! Vertex numbering of the refined mesh: first the children of the parent's vertices (so vertex
//! `i` of every level descends from cage vertex `i`), then for Catmull-Clark one point per face,
//! then one point per edge. Faces: Catmull-Clark splits an n-gon into n quads
//! `(v_k, e_k, f, e_(k-1))`; Loop splits a triangle into four. Child edges inherit decayed
//! sharpness, child faces the hole flag and group of their parent.

use glam::Vec3;
use subdiv_mesh::{
    CreaseMethod, EdgeId, HalfedgeId, Mesh, PolygonSoup, TriangleSubdivision, VertexId,
};

use crate::crease::{VertexRules, decrement, edge_crease_weight, is_sharp};
use crate::{Depth, RulesError, Scheme, catmark, loop_scheme};

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
    let pos = mesh.positions();
    let fp: Vec<Vec3> = if scheme == Scheme::CatmullClark {
        mesh.faces().map(|f| mesh.face_centroid(f)).collect()
    } else {
        Vec::new()
    };

    let mut kernel = RefineKernel::new(mesh, scheme);
    let mut positions: Vec<Vec3> = Vec::with_capacity(nv + fp.len() + mesh.num_edges());
    for v in mesh.vertices() {
        positions.push(kernel.vertex_point(v, &fp));
    }
    positions.extend_from_slice(&fp);
    let edge_base = positions.len() as u32;
    for e in mesh.edges() {
        positions.push(kernel.edge_point(e, |h| match scheme {
            Scheme::CatmullClark => fp[mesh.face(h).idx()],
            // The vertex of the triangle opposite the edge.
            Scheme::Loop => pos[mesh.to(mesh.next(h)).idx()],
        }));
    }

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
            Scheme::CatmullClark => {
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
    let mut child = Mesh::from_soup(&soup).map_err(RulesError::Internal)?;
    child.set_holes(holes);
    child.set_groups(mesh.groups().to_vec(), groups);
    kernel.transfer_sharpness(&mut child, |e| Some(VertexId(edge_base + e.0)), |_| true);
    Ok(child)
}

/// The one refinement kernel: the vertex and edge rules of one subdivision step applied to a
/// mesh, with crease sharpness carried to the child mesh. Uniform refinement
/// ([`refine_uniform`]) applies it to every vertex and edge; adaptive Loop refinement
/// (`subdiv-loop`) to the vertices and edges its closure selects. Both therefore produce
/// bit-identical points wherever they refine the same neighbourhood.
///
/// Call [`RefineKernel::vertex_point`] for both ends of an edge before its
/// [`RefineKernel::edge_point`]: the vertex rules decide the child sharpness of the edge at each
/// end (OpenSubdiv's `Sdc::Crease`), which the edge's crease weight needs.
#[derive(Debug)]
pub struct RefineKernel<'m> {
    mesh: &'m Mesh,
    scheme: Scheme,
    method: CreaseMethod,
    triangles: TriangleSubdivision,
    /// Child sharpness of each edge at the origin of each half-edge.
    child_sharp: Vec<f32>,
    halfedges: Vec<HalfedgeId>,
    edge_ends: Vec<Vec3>,
    face_points: Vec<Vec3>,
    edge_sharpness: Vec<f32>,
    child_edge_sharpness: Vec<f32>,
}

impl<'m> RefineKernel<'m> {
    /// A kernel for one step of `scheme` on `mesh`.
    pub fn new(mesh: &'m Mesh, scheme: Scheme) -> RefineKernel<'m> {
        RefineKernel {
            mesh,
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
    pub fn vertex_point(&mut self, v: VertexId, face_points: &[Vec3]) -> Vec3 {
        let mesh = self.mesh;
        let pos = mesh.positions();
        if mesh.is_isolated(v) {
            return pos[v.idx()];
        }
        self.halfedges.clear();
        self.halfedges.extend(mesh.outgoing(v));
        self.edge_ends.clear();
        self.face_points.clear();
        self.edge_sharpness.clear();
        for &h in &self.halfedges {
            self.edge_ends.push(pos[mesh.to(h).idx()]);
            self.edge_sharpness.push(mesh.edge_sharpness(h.edge()));
            let f = mesh.face(h);
            if f.is_some() && self.scheme == Scheme::CatmullClark {
                self.face_points.push(face_points[f.idx()]);
            }
        }
        self.child_edge_sharpness.clear();
        self.child_edge_sharpness.resize(self.halfedges.len(), 0.0);
        let rules = VertexRules::new(
            self.method,
            mesh.vertex_sharpness(v),
            &self.edge_sharpness,
            &mut self.child_edge_sharpness,
        );
        for (k, &h) in self.halfedges.iter().enumerate() {
            self.child_sharp[h.idx()] = self.child_edge_sharpness[k];
        }
        match self.scheme {
            Scheme::CatmullClark => {
                catmark::vertex_point(pos[v.idx()], &self.edge_ends, &self.face_points, &rules)
            }
            Scheme::Loop => loop_scheme::vertex_point(pos[v.idx()], &self.edge_ends, &rules),
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
    pub fn edge_point(&self, e: EdgeId, side: impl Fn(HalfedgeId) -> Vec3) -> Vec3 {
        let mesh = self.mesh;
        let pos = mesh.positions();
        let (h0, h1) = (e.halfedge(0), e.halfedge(1));
        let a = pos[mesh.from(h0).idx()];
        let b = pos[mesh.to(h0).idx()];
        let s = mesh.edge_sharpness(e);
        let w = edge_crease_weight(
            self.method,
            s,
            [self.child_sharp[h0.idx()], self.child_sharp[h1.idx()]],
        );
        let mut adj = [Vec3::ZERO; 2];
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
        }
    }

    /// Carries sharpness to `child`, whose vertex `i` descends from the parent's vertex `i`.
    /// `midpoint(e)` is the child vertex of split edge `e` (`None`: the edge is kept whole);
    /// `decays(v)` says whether `v` was refined this step. The halves of a split crease edge get
    /// the child sharpness recorded by the vertex rules; a kept edge keeps its sharpness; a
    /// refined vertex's sharpness decays by one, a kept one's stays.
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
    }
}

/// Refuses two triangles on the same three vertices. Loop refinement connects the edge points
/// of every triangle; for such a pair it would connect the same three edge points twice (parallel
/// edges, which a [`Mesh`] cannot hold). Such triangles always share an edge, so checking each
/// face against its neighbours finds them. Refinement never creates new pairs.
/// Refuses two triangles on the same three vertices ([`RulesError::DoubledTriangle`]): Loop
/// refinement cannot refine such a two-face pillow. Every Loop path calls it before refining.
pub fn check_doubled_triangles(mesh: &Mesh) -> Result<(), RulesError> {
    let sorted = |f| {
        let mut k: Vec<u32> = mesh.face_vertices(f).iter().map(|v| v.0).collect();
        k.sort_unstable();
        k
    };
    for f in mesh.faces() {
        let h0 = mesh.face_halfedge(f);
        for h in [h0, mesh.next(h0), mesh.prev(h0)] {
            let g = mesh.face(h.twin());
            if g.is_some() && g.0 < f.0 && sorted(f) == sorted(g) {
                return Err(RulesError::DoubledTriangle {
                    face: f.0,
                    other: g.0,
                });
            }
        }
    }
    Ok(())
}

/// Largest coordinate magnitude of a mesh to refine or tessellate ([`check_coordinates`]).
/// Subdivision sums weighted points in `f32`: near `f32::MAX` (3.4e38) they overflow to
/// infinity, while below this bound even a sum of a million weighted points stays finite.
pub const MAX_COORDINATE: f32 = 1e30;

/// Refuses the first vertex with a coordinate beyond [`MAX_COORDINATE`]. Checked on the cage by
/// [`refine_uniform_levels`] (and so [`tessellate_uniform`](crate::tessellate_uniform)) and
/// the slate tessellator, not on refined meshes, whose points may exceed a cage at the bound by
/// rounding.
pub fn check_coordinates(mesh: &Mesh) -> Result<(), RulesError> {
    let pos = mesh.positions();
    match pos
        .iter()
        .position(|p| p.abs().max_element() > MAX_COORDINATE)
    {
        Some(v) => Err(RulesError::HugeCoordinate {
            vertex: v as u32,
            x: pos[v].x,
            y: pos[v].y,
            z: pos[v].z,
        }),
        None => Ok(()),
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

/// Maximum number of faces a uniform refinement may produce.
pub const MAX_REFINED_FACES: u64 = 1 << 26;

/// Number of faces of the uniform level-`depth` refinement.
pub fn refined_face_count(mesh: &Mesh, scheme: Scheme, depth: Depth) -> u64 {
    if depth == 0 {
        return mesh.num_faces() as u64;
    }
    let per = 4u64.saturating_pow(u32::from(depth) - 1);
    match scheme {
        Scheme::CatmullClark => {
            let corners: u64 = mesh.faces().map(|f| mesh.face_size(f) as u64).sum();
            corners.saturating_mul(per)
        }
        Scheme::Loop => (mesh.num_faces() as u64).saturating_mul(per.saturating_mul(4)),
    }
}

fn check_size(mesh: &Mesh, scheme: Scheme, depth: Depth) -> Result<(), RulesError> {
    let faces = refined_face_count(mesh, scheme, depth);
    if faces > MAX_REFINED_FACES {
        return Err(RulesError::TooDeep { depth, faces });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::parse_obj;

    /// Found by fuzzing: a pillow (two triangles on one vertex triple) made Loop refinement
    /// build a non-manifold child mesh and report an internal error.
    #[test]
    fn loop_refuses_a_two_triangle_pillow() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 0 0\nv 6 0 0\nv 5 1 0\n\
                    f 4 5 6\nf 1 2 3\nf 3 2 1\n";
        let m = Mesh::from_soup(&parse_obj(text).unwrap()).unwrap();
        let e = refine_uniform(&m, Scheme::Loop).unwrap_err();
        assert!(
            matches!(e, RulesError::DoubledTriangle { face: 2, other: 1 }),
            "{e:?}"
        );
        assert!(
            e.to_string().starts_with("faces 2 and 1 are triangles"),
            "{e}"
        );
        // Catmull-Clark refines the same pillow.
        assert_eq!(
            refine_uniform(&m, Scheme::CatmullClark)
                .unwrap()
                .num_faces(),
            9
        );
        // Triangles sharing one edge are fine.
        let fan = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 3 2 4\n";
        let m = Mesh::from_soup(&parse_obj(fan).unwrap()).unwrap();
        assert_eq!(refine_uniform(&m, Scheme::Loop).unwrap().num_faces(), 8);
    }

    /// Found by fuzzing: finite coordinates near `f32::MAX` overflowed to infinite points (an
    /// internal error from the refined mesh's validation).
    #[test]
    fn huge_coordinates_are_refused_and_the_bound_is_safe() {
        let cube = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
                    f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
        let mut m = Mesh::from_soup(&parse_obj(cube).unwrap()).unwrap();
        m.positions_mut()[6].y = 3.4e38;
        for depth in [0, 1] {
            let e = refine_uniform_levels(&m, Scheme::CatmullClark, depth).unwrap_err();
            assert!(
                matches!(e, RulesError::HugeCoordinate { vertex: 6, .. }),
                "{e:?}"
            );
            assert!(
                e.to_string()
                    .starts_with("vertex 6 has a coordinate beyond"),
                "{e}"
            );
        }
        // At the bound (every vertex, either sign) the refinement and its limit are finite.
        let mut m = Mesh::from_soup(&parse_obj(cube).unwrap()).unwrap();
        for p in m.positions_mut() {
            *p = (*p * 2.0 - glam::Vec3::ONE) * MAX_COORDINATE;
        }
        let t = crate::tessellate_uniform(&m, Scheme::CatmullClark, 3).unwrap();
        assert!(
            t.positions
                .iter()
                .chain(&t.normals)
                .flatten()
                .all(|x| x.is_finite())
        );
    }
}
