//! Gathering a patch: the 1-neighbourhood of a quad of the mesh copied into slate 0 (Settgast et
//! al., Fig. 2), with the sharpness of its edges, the corner arrays of its irregular corners and,
//! for the Chaikin rule, what is known of the creases beyond the table.

use glam::Vec3A;
use subdiv_mesh::{CreaseMethod, FaceId, HalfedgeId, Mesh, VertexId};
use subdiv_rules::Scheme;
use subdiv_rules::crease::{far_semi_sharp, is_infinite};

use crate::table::Table;
use crate::worker::Worker;

/// Table position of the face's corner `k` at level 0.
const CORNER_POS: [(i32, i32); 4] = [(0, 0), (1, 0), (1, 1), (0, 1)];
/// Outward direction of side `k` (as a table offset).
const OUTWARD: [(i32, i32); 4] = [(0, -1), (1, 0), (0, 1), (-1, 0)];
/// Direction index (0 = +i, 1 = +j, 2 = -i, 3 = -j) running along side `k`.
const SIDE_DIR: [usize; 4] = [0, 1, 2, 3];
/// Direction index pointing away from side `k`.
const OUT_DIR: [usize; 4] = [3, 0, 1, 2];

/// Vertex ids of the level-0 table, `[j + 1][i + 1]`.
type TableVertices = [[VertexId; 4]; 4];

/// Table edges and their half-edges, collected while gathering: at most the face's 4 sides,
/// 3 per edge neighbour and 2 per regular corner.
struct TableEdges {
    edges: [((i32, i32), usize, HalfedgeId); 24],
    len: usize,
}

impl TableEdges {
    #[inline]
    fn push(&mut self, at: (i32, i32), dir: usize, h: HalfedgeId) {
        self.edges[self.len] = (at, dir, h);
        self.len += 1;
    }
}

/// A sharp edge of a level-0 table: its lower end `(i, j)`, direction (0 = +i, 1 = +j) and
/// sharpness.
pub(crate) type PlanEdge = (i8, i8, u8, f32);

/// What gathering a patch reads from the mesh besides positions, found once per patch: the
/// vertex of every level-0 table position, the sharp table edges, which corners keep a corner
/// array and whether the regular rules apply. Topology and sharpness never change for a mesh
/// (only its positions may), so a [`PatchLayout`](crate::PatchLayout) keeps one per patch and
/// every tessellation gathers through it ([`Worker::gather_with`]).
#[derive(Clone, Debug)]
pub(crate) struct GatherPlan {
    vid: TableVertices,
    /// Range of this patch's sharp edges in the layout's edge list.
    first_edge: u32,
    num_edges: u8,
    /// Corner `k` keeps a corner array (bit `k`).
    active: u8,
    /// Corner `k` is a boundary vertex (bit `k`).
    boundary: u8,
    regular: bool,
    /// The patch may have one-sided limit normals: a boundary, or an infinitely sharp table edge,
    /// corner array edge or corner vertex (see [`GatherPlan::may_be_sided`]).
    sided: bool,
}

impl GatherPlan {
    /// The plan of quad `f` of `mesh` (whose neighbourhood is all quads); its sharp edges are
    /// appended to `edges`.
    pub(crate) fn new(mesh: &Mesh, f: FaceId, edges: &mut Vec<PlanEdge>) -> GatherPlan {
        let hs = face_halfedges(mesh, f);
        let mut vid = face_and_edge_neighbours(mesh, &hs);
        let mut regular = true;
        // Table edges and their half-edges: the face's sides, the three other sides of each edge
        // neighbour, and the two outer sides of each regular corner's diagonal face.
        let mut table_edges = side_edges(mesh, &hs);
        let (mut active, mut boundary) = (0u8, 0u8);
        let mut sided = false;
        for (k, &h) in hs.iter().enumerate() {
            let v = mesh.from(h);
            let on_boundary = mesh.is_boundary_vertex(v);
            let mut valence = 0usize;
            for _ in mesh.outgoing(v) {
                valence += 1;
                if valence > 4 {
                    break;
                }
            }
            boundary |= u8::from(on_boundary) << k;
            // Sharp edges at an interior valence-4 corner are table edges like any other (the
            // general step's rules handle them); a corner tag has no place in the table.
            // A crease copy's centre follows another copy's ring (`Ring`): never regular.
            let follows = mesh.crease_ends(v).is_some();
            if valence != 4 || on_boundary || mesh.vertex_sharpness(v) > 0.0 || follows {
                active |= 1 << k;
                // The corner array's ring: the vertex and all its edges.
                sided |= on_boundary
                    || is_infinite(mesh.vertex_sharpness(v))
                    || mesh
                        .outgoing(v)
                        .any(|h| is_infinite(mesh.edge_sharpness(h.edge())));
                if on_boundary || mesh.vertex_sharpness(v) > 0.0 || follows {
                    regular = false;
                }
            } else {
                diagonal_corner(mesh, &hs, k, &mut vid, &mut table_edges);
            }
        }
        let first_edge = edges.len() as u32;
        for &((i, j), d, h) in &table_edges.edges[..table_edges.len] {
            let s = mesh.edge_sharpness(h.edge());
            if s > 0.0 {
                regular = false;
                sided |= is_infinite(s);
                edges.push((i as i8, j as i8, d as u8, s));
            }
        }
        // Missing points anywhere except the diagonal spots of irregular corners mean boundary.
        for j in -1..=2i32 {
            for i in -1..=2i32 {
                let diag_spot = (i == -1 || i == 2) && (j == -1 || j == 2);
                if !vid[(j + 1) as usize][(i + 1) as usize].is_some() && !diag_spot {
                    regular = false;
                    sided = true;
                }
            }
        }
        GatherPlan {
            vid,
            first_edge,
            num_edges: (edges.len() - first_edge as usize) as u8,
            active,
            boundary,
            regular: regular && mesh.options().crease != CreaseMethod::Chaikin,
            sided,
        }
    }

    /// `false` where no grid point of the patch can have one-sided normals at any depth, so that
    /// [`Worker::may_be_sided`] would answer `false` everywhere: no point is missing (boundary)
    /// and no table edge, corner array edge or corner vertex is infinitely sharp. Sharpness only
    /// decays under refinement (semi-sharp stays below infinite, under the Chaikin rule too), and
    /// without a boundary the only missing points are the corner arrays' diagonal spots, no grid
    /// point's edge neighbour, so what holds for the level-0 table holds for every level. Debug
    /// builds check it at every point skipped (`run_patch`).
    pub(crate) fn may_be_sided(&self) -> bool {
        self.sided
    }
}

/// The four half-edges of quad `f`, from its first.
#[inline]
fn face_halfedges(mesh: &Mesh, f: FaceId) -> [HalfedgeId; 4] {
    let h0 = mesh.face_halfedge(f);
    [h0, mesh.next(h0), mesh.next(mesh.next(h0)), mesh.prev(h0)]
}

/// An interior valence-4 corner `k` without a corner tag completes the table with its diagonal
/// vertex (and two table edges).
#[inline]
fn diagonal_corner(
    mesh: &Mesh,
    hs: &[HalfedgeId; 4],
    k: usize,
    vid: &mut TableVertices,
    edges: &mut TableEdges,
) {
    let g = mesh.prev(mesh.prev(hs[k]).twin()).twin(); // corner -> behind
    let gn = mesh.next(g);
    let d = mesh.to(gn);
    let (ci, cj) = CORNER_POS[k];
    let (o1i, o1j) = OUTWARD[k];
    let (o2i, o2j) = OUTWARD[(k + 3) % 4];
    vid[(cj + o1j + o2j + 1) as usize][(ci + o1i + o2i + 1) as usize] = d;
    edges.push((ci + o2i, cj + o2j), OUT_DIR[k], gn);
    edges.push(
        (ci + o1i, cj + o1j),
        OUT_DIR[(k + 3) % 4],
        mesh.next(gn).twin(),
    );
}

impl Worker {
    /// Gathers the 1-neighbourhood of quad `f` of `mesh` (whose neighbourhood is all quads) into
    /// slate 0 (paper Fig. 2).
    pub(crate) fn gather(&mut self, mesh: &Mesh, f: FaceId) {
        let mut edges = Vec::new();
        let plan = GatherPlan::new(mesh, f, &mut edges);
        self.gather_with(mesh, f, &plan, &edges);
    }

    /// [`Worker::gather`] through the patch's plan (`edges`: the list its sharp edges are in):
    /// the mesh is read only for positions and the corner arrays' rings.
    pub(crate) fn gather_with(
        &mut self,
        mesh: &Mesh,
        f: FaceId,
        plan: &GatherPlan,
        edges: &[PlanEdge],
    ) {
        self.cur = 0;
        self.method = mesh.options().crease;
        self.origin32 = Vec3A::from(mesh.position(mesh.from(mesh.face_halfedge(f))));
        self.origin = self.origin32.as_dvec3();
        self.regular = plan.regular;
        let t = &mut self.t[0];
        // Clears the sharpness the last patch left, if it left any (its `dirty` flag).
        t.reset(1, false, self.method == CreaseMethod::Chaikin);
        fill_points(t, mesh, &plan.vid, self.origin32);
        let first = plan.first_edge as usize;
        for &(i, j, d, s) in &edges[first..first + plan.num_edges as usize] {
            t.set_edge_sharp(i as i32, j as i32, d as usize, s);
        }
        // Far ends of the crossing edges, for the Chaikin rule.
        if self.method == CreaseMethod::Chaikin {
            gather_far(t, mesh, &plan.vid);
        }
        let hs = face_halfedges(mesh, f);
        for (k, c) in self.corners.iter_mut().enumerate() {
            c.active = plan.active & (1 << k) != 0;
            c.boundary = plan.boundary & (1 << k) != 0;
            if c.active {
                let v = mesh.from(hs[k]);
                c.ring
                    .load_with_halfedges(mesh, v, Scheme::CatmullClark, &mut self.hes);
                c.valence = self.hes.len();
                c.ih = self.hes.iter().position(|&h| h == hs[k]).unwrap_or(0);
                c.keep_sharpness();
            } else {
                c.valence = 4;
            }
        }
    }
}

/// Vertex ids of the face's corners and of the two far vertices of each edge neighbour.
#[inline]
fn face_and_edge_neighbours(mesh: &Mesh, hs: &[HalfedgeId; 4]) -> TableVertices {
    let mut vid = [[VertexId::NONE; 4]; 4];
    for k in 0..4 {
        let (ci, cj) = CORNER_POS[k];
        vid[(cj + 1) as usize][(ci + 1) as usize] = mesh.from(hs[k]);
    }
    for k in 0..4 {
        let tw = hs[k].twin();
        if mesh.face(tw).is_some() {
            let x = mesh.to(mesh.next(tw));
            let y = mesh.to(mesh.next(mesh.next(tw)));
            let (ai, aj) = CORNER_POS[k];
            let (bi, bj) = CORNER_POS[(k + 1) % 4];
            let (oi, oj) = OUTWARD[k];
            vid[(aj + oj + 1) as usize][(ai + oi + 1) as usize] = x;
            vid[(bj + oj + 1) as usize][(bi + oi + 1) as usize] = y;
        }
    }
    vid
}

/// The face's sides and the three other sides of each edge neighbour.
#[inline]
fn side_edges(mesh: &Mesh, hs: &[HalfedgeId; 4]) -> TableEdges {
    let mut edges = TableEdges {
        edges: [((0, 0), 0, HalfedgeId::NONE); 24],
        len: 0,
    };
    for k in 0..4 {
        edges.push(CORNER_POS[k], SIDE_DIR[k], hs[k]);
        let tw = hs[k].twin();
        if mesh.face(tw).is_some() {
            let g1 = mesh.next(tw);
            let g2 = mesh.next(g1);
            let (ai, aj) = CORNER_POS[k];
            let (oi, oj) = OUTWARD[k];
            edges.push(CORNER_POS[k], OUT_DIR[k], g1);
            edges.push((ai + oi, aj + oj), SIDE_DIR[k], g2);
            edges.push(CORNER_POS[(k + 1) % 4], OUT_DIR[k], mesh.next(g2));
        }
    }
    edges
}

/// Positions (relative to `origin32`) and existence flags of the level-0 table.
#[inline]
fn fill_points(t: &mut Table, mesh: &Mesh, vid: &TableVertices, origin32: Vec3A) {
    for j in -1..=2i32 {
        for i in -1..=2i32 {
            let v = vid[(j + 1) as usize][(i + 1) as usize];
            let k = t.at(i, j);
            t.exists[k] = v.is_some();
            t.positions[k] = if v.is_some() {
                Vec3A::from(mesh.position(v)) - origin32
            } else {
                Vec3A::ZERO
            };
        }
    }
}

/// Far ends of the crossing edges (Chaikin rule): for each crossing edge of the level-0 table,
/// the (sum, count) of the semi-sharp edges at its outer end other than itself.
fn gather_far(t: &mut Table, mesh: &Mesh, vid: &TableVertices) {
    for side in 0..4 {
        for s in 0..=1i32 {
            let (ii, jj, oi, oj) = side_crossing(side, s, 1);
            let a = vid[(jj + 1) as usize][(ii + 1) as usize];
            let b = vid[(oj + 1) as usize][(oi + 1) as usize];
            if !(a.is_some() && b.is_some()) {
                continue;
            }
            let Some(h) = mesh.find_halfedge(a, b) else {
                continue;
            };
            t.far_semi_sharp[side][s as usize] = far_semi_sharp(mesh, h);
        }
    }
}

/// Table coordinates of the crossing edge at position `s` along side `side` (grid `n`): the
/// inner end `(i, j)` and the outer end `(oi, oj)`.
#[inline]
fn side_crossing(side: usize, s: i32, n: i32) -> (i32, i32, i32, i32) {
    match side {
        0 => (s, 0, s, -1),
        1 => (n, s, n + 1, s),
        2 => (s, n, s, n + 1),
        _ => (0, s, -1, s),
    }
}
