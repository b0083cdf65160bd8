//! Loading a [`Ring`]: from a mesh (with the whole vertex's values and the crease copy's ring
//! at a copy of a non-manifold vertex), or from parts (the slates' table points).

use glam::DVec3;
use subdiv_mesh::{CreaseMethod, Mesh, TriangleSubdivision, VertexId};

use super::Ring;
use crate::Scheme;
use crate::crease::far_semi_sharp;

impl Ring {
    /// Loads the ring of vertex `v` of `mesh`. Returns `false` (and leaves the ring empty) for an
    /// isolated vertex, and for the bilinear scheme, whose limit needs no ring (a point is its
    /// own limit: `limit::bilinear`).
    pub fn load(&mut self, mesh: &Mesh, v: VertexId, scheme: Scheme) -> bool {
        self.load_at(mesh, |w| mesh.position(w).as_dvec3(), v, scheme)
    }

    /// [`Ring::load`] with the vertex positions `pos(w)` instead of the mesh's (the `f64`
    /// positions of `refine_uniform_levels_f64`).
    pub fn load_at(
        &mut self,
        mesh: &Mesh,
        pos: impl Fn(VertexId) -> DVec3,
        v: VertexId,
        scheme: Scheme,
    ) -> bool {
        if scheme == Scheme::Bilinear {
            return false;
        }
        self.scheme = scheme;
        self.method = mesh.options().crease;
        self.triangles = mesh.options().triangles;
        self.center = pos(v);
        self.vertex_sharpness = mesh.vertex_sharpness(v);
        self.whole.clear();
        self.whole
            .extend_from_slice(mesh.whole_vertex_edges(v).unwrap_or(&[]));
        self.own_normal = false;
        self.master = match (mesh.crease_ends(v), mesh.crease_copy_of(v)) {
            (Some(_), Some(m)) => {
                let mut ring = self.master.take().unwrap_or_default();
                // Through `dyn`, so that this call instantiates one `load_at` whatever `pos`.
                let pos: &dyn Fn(VertexId) -> DVec3 = &pos;
                ring.load_at(mesh, pos, m, scheme);
                Some(ring)
            }
            (Some(ends), None) => {
                // No copy holds both edges: a ring of just them gives the crease's points.
                let mut ring = self.master.take().unwrap_or_default();
                ring.load_crease(mesh, pos(v), ends.map(|h| pos(mesh.to(h))), v, scheme);
                self.own_normal = true;
                Some(ring)
            }
            _ => None,
        };
        self.boundary = mesh.is_boundary_vertex(v);
        self.edges.clear();
        self.sharp.clear();
        self.far.clear();
        self.inner.clear();
        self.inner_off.clear();
        self.inner_off.push(0);
        if mesh.is_isolated(v) {
            return false;
        }
        let chaikin = self.method == CreaseMethod::Chaikin;
        for h in mesh.outgoing(v) {
            let w = mesh.to(h);
            self.edges.push(pos(w));
            self.sharp.push(mesh.edge_sharpness(h.edge()));
            let far = if chaikin {
                far_semi_sharp(mesh, h)
            } else {
                (0.0, 0)
            };
            self.far.push(far);
            if mesh.face(h).is_some() {
                // Face vertices strictly between this edge's end and the next edge's end.
                let stop = mesh.from(mesh.prev(h));
                let mut g = mesh.next(h);
                while mesh.to(g) != stop {
                    self.inner.push(pos(mesh.to(g)));
                    g = mesh.next(g);
                }
                self.inner_off.push(self.inner.len() as u32);
            }
        }
        true
    }

    /// The ring of a crease copy `v` whose crease edges (ending at `ends`) leave different
    /// copies ([`Mesh::crease_ends`]): the two infinitely sharp edges alone, with `v`'s vertex
    /// sharpness and whole-vertex values, and one face between them that no rule of theirs
    /// reads (the crease and corner rules read only the two ends; edge points on infinitely
    /// sharp edges are midpoints). Its centre and limit position are the crease's; its normal
    /// means nothing.
    fn load_crease(
        &mut self,
        mesh: &Mesh,
        center: DVec3,
        ends: [DVec3; 2],
        v: VertexId,
        scheme: Scheme,
    ) {
        let method = mesh.options().crease;
        let vs = mesh.vertex_sharpness(v);
        let sharp = [subdiv_mesh::SHARPNESS_INFINITE; 2];
        let far = [(0.0, 0); 2];
        match scheme {
            // (Never bilinear: `load_at` refuses it.)
            Scheme::CatmullClark | Scheme::Bilinear => {
                let diag = [ends[0] + ends[1] - center];
                self.load_quads(method, center, vs, true, &ends, &sharp, &far, &diag);
            }
            Scheme::Loop => self.load_triangles(method, center, vs, true, &ends, &sharp, &far),
        }
        self.whole
            .extend_from_slice(mesh.whole_vertex_edges(v).unwrap_or(&[]));
    }

    /// Loads the ring of vertex `v` like [`Ring::load`], and writes the outgoing half-edges in
    /// ring order into `halfedges` (ring edge `i` is `halfedges[i]`).
    pub fn load_with_halfedges(
        &mut self,
        mesh: &Mesh,
        v: VertexId,
        scheme: Scheme,
        halfedges: &mut Vec<subdiv_mesh::HalfedgeId>,
    ) -> bool {
        halfedges.clear();
        halfedges.extend(mesh.outgoing(v));
        self.load(mesh, v, scheme)
    }

    /// Loads a Catmull-Clark ring of quads from parts: edge neighbours `edges` (counter-clockwise;
    /// for a boundary vertex edge 0 and the last edge are the boundary), their sharpness and far-end
    /// semi-sharp (sum, count) for the Chaikin rule, and the vertex of each quad opposite the centre
    /// (`diag[i]` between edges `i` and `i+1`; one fewer than edges on a boundary).
    #[allow(clippy::too_many_arguments)]
    pub fn load_quads(
        &mut self,
        method: CreaseMethod,
        center: DVec3,
        vertex_sharpness: f32,
        boundary: bool,
        edges: &[DVec3],
        sharp: &[f32],
        far: &[(f32, u32)],
        diag: &[DVec3],
    ) {
        // Quads only: the triangle rule never applies.
        let ring = (center, vertex_sharpness, boundary);
        self.load_parts(Scheme::CatmullClark, method, ring, edges, sharp, far);
        self.inner.extend_from_slice(diag);
        self.inner_off.clear();
        self.inner_off.extend(0..=diag.len() as u32);
    }

    /// Loads a Loop ring of triangles from parts: edge neighbours `edges` (counter-clockwise;
    /// for a boundary vertex edge 0 and the last edge are the boundary, and there is one triangle
    /// fewer than edges), their sharpness and far-end semi-sharp (sum, count) for the Chaikin
    /// rule. Triangle `i` is spanned by the centre and edges `i`, `i + 1`.
    #[allow(clippy::too_many_arguments)]
    pub fn load_triangles(
        &mut self,
        method: CreaseMethod,
        center: DVec3,
        vertex_sharpness: f32,
        boundary: bool,
        edges: &[DVec3],
        sharp: &[f32],
        far: &[(f32, u32)],
    ) {
        let ring = (center, vertex_sharpness, boundary);
        self.load_parts(Scheme::Loop, method, ring, edges, sharp, far);
        let faces = if boundary {
            edges.len().saturating_sub(1)
        } else {
            edges.len()
        };
        self.inner_off.resize(faces + 1, 0);
    }

    /// What [`Ring::load_quads`] and [`Ring::load_triangles`] share: `ring` is the centre, its
    /// vertex sharpness and whether it is on the boundary; the faces are left empty.
    fn load_parts(
        &mut self,
        scheme: Scheme,
        method: CreaseMethod,
        ring: (DVec3, f32, bool),
        edges: &[DVec3],
        sharp: &[f32],
        far: &[(f32, u32)],
    ) {
        self.scheme = scheme;
        self.method = method;
        self.triangles = TriangleSubdivision::Catmark;
        (self.center, self.vertex_sharpness, self.boundary) = ring;
        self.whole.clear();
        self.master = None;
        self.own_normal = false;
        self.edges.clear();
        self.edges.extend_from_slice(edges);
        self.sharp.clear();
        self.sharp.extend_from_slice(sharp);
        self.far.clear();
        self.far.extend_from_slice(far);
        self.inner.clear();
        self.inner_off.clear();
    }
}
